//! PNG previews (8-bit sRGB-ish, for people without an EXR viewer), with a scale bar.
//!
//! - **Renders**: the luminance L = R + G + B on a log scale over D decades (default
//!   [`DECADES`]) below the brightest pixel, v = 1 + log₁₀(L / L_max) / D clamped to [0, 1],
//!   and the hue kept:
//!   each channel is v · (c / max(R, G, B))^(1/2.2). Exitance falls exponentially with distance
//!   and diverges like ln(1/r) at the entry point; a log scale shows both the core and the tail,
//!   where a linear or Reinhard map shows a dot. Mapping each channel's log separately would
//!   squeeze a tenfold colour ratio into a quarter of the range and turn every hue pale.
//! - **Differences**: red where the first picture is brighter, blue where the second is, black
//!   where they agree; full scale is the 99.5th percentile of |ΔL| (a few noisy pixels at the
//!   entry point would otherwise set it), with gamma 1/2.2 on the magnitude.
//!
//! The scale bar (white, bottom left) is 1, 2 or 5 × 10ᵏ mm, the longest at most a quarter of
//! the width, labelled in a built-in 3 × 5 pixel font.

use super::{Frame, Picture, RenderError};
use std::path::Path;

/// Decades of exitance the render preview shows by default.
pub const DECADES: f64 = 3.0;

/// Writes the log-tone-mapped preview of a render over `decades` (> 0; else [`DECADES`]).
pub fn write_preview(path: &Path, picture: &Picture, decades: f64) -> Result<(), RenderError> {
    let mut rgb = tonemap_log(picture.rgb(), decades);
    scale_bar(&mut rgb, picture.frame());
    encode(path, picture.frame(), &rgb)
}

/// Writes the preview of a signed difference (row-major values).
pub fn write_difference_preview(
    path: &Path,
    frame: &Frame,
    values: &[f32],
) -> Result<(), RenderError> {
    let mut rgb = diverging(values);
    scale_bar(&mut rgb, frame);
    encode(path, frame, &rgb)
}

/// 8-bit RGB of linear RGB values on the log scale described in the module docs, over
/// `decades` (> 0 and finite; else [`DECADES`]).
pub fn tonemap_log(linear: &[f32], decades: f64) -> Vec<u8> {
    let decades = if decades.is_finite() && decades > 0.0 {
        decades
    } else {
        DECADES
    };
    let luminance = |p: &[f32]| p.iter().map(|&v| f64::from(v)).sum::<f64>();
    let max = linear
        .chunks_exact(3)
        .map(luminance)
        .filter(|l| l.is_finite())
        .fold(0.0f64, f64::max);
    let mut out = Vec::with_capacity(linear.len());
    for p in linear.chunks_exact(3) {
        let l = luminance(p);
        let peak = p.iter().copied().fold(0.0f32, f32::max);
        if !(max > 0.0 && l > 0.0 && l.is_finite() && peak > 0.0) {
            out.extend_from_slice(&[0, 0, 0]);
            continue;
        }
        let level = (1.0 + (l / max).log10() / decades).clamp(0.0, 1.0);
        for &c in p {
            let hue = f64::from(c.max(0.0) / peak).powf(1.0 / 2.2);
            out.push((255.0 * level * hue).round() as u8);
        }
    }
    out
}

/// 8-bit RGB of signed values: red positive, blue negative.
pub fn diverging(values: &[f32]) -> Vec<u8> {
    let mut magnitudes: Vec<f32> = values
        .iter()
        .map(|v| v.abs())
        .filter(|v| v.is_finite() && *v > 0.0)
        .collect();
    magnitudes.sort_by(f32::total_cmp);
    let full = match magnitudes.len() {
        0 => 1.0,
        n => magnitudes[((n - 1) as f64 * 0.995).round() as usize],
    };
    let mut out = Vec::with_capacity(3 * values.len());
    for &v in values {
        let t = if v.is_finite() {
            (f64::from(v) / f64::from(full)).clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let level = (255.0 * t.abs().powf(1.0 / 2.2)).round() as u8;
        out.extend_from_slice(&if t > 0.0 {
            [level, 0, 0]
        } else {
            [0, 0, level]
        });
    }
    out
}

/// The scale bar's length, mm: 1, 2 or 5 × 10ᵏ, at most a quarter of `width_mm`.
pub fn scale_bar_mm(width_mm: f64) -> f64 {
    let limit = 0.25 * width_mm;
    let decade = 10f64.powf(limit.log10().floor());
    [5.0, 2.0, 1.0]
        .iter()
        .map(|m| m * decade)
        .find(|&l| l <= limit)
        .unwrap_or(decade)
}

/// Draws the scale bar and its label into row-major 8-bit RGB.
fn scale_bar(rgb: &mut [u8], frame: &Frame) {
    let (w, h) = (frame.width(), frame.height());
    let length_mm = scale_bar_mm(frame.extent_x());
    let length_px = (length_mm / frame.pixel_mm()).round() as usize;
    let unit = (w.min(h) / 128).max(1);
    let (margin, thick) = (4 * unit, 2 * unit);
    if length_px == 0 || w < 2 * margin + length_px || h < 2 * margin + thick + 8 * unit {
        return;
    }
    let mut put = |x: usize, y: usize| {
        if x < w && y < h {
            rgb[3 * (y * w + x)..3 * (y * w + x) + 3].fill(255);
        }
    };
    let bar_top = h - margin - thick;
    for y in bar_top..bar_top + thick {
        for x in margin..margin + length_px {
            put(x, y);
        }
    }
    let label = format!("{} mm", trim_number(length_mm));
    let mut x0 = margin;
    let y0 = bar_top - 7 * unit;
    for ch in label.chars() {
        let glyph = glyph(ch);
        let width = glyph.first().map_or(3, |row| row.len());
        for (gy, row) in glyph.iter().enumerate() {
            for (gx, bit) in row.bytes().enumerate() {
                if bit == b'#' {
                    for dy in 0..unit {
                        for dx in 0..unit {
                            put(x0 + gx * unit + dx, y0 + gy * unit + dy);
                        }
                    }
                }
            }
        }
        x0 += (width + 1) * unit;
    }
}

fn trim_number(v: f64) -> String {
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Five rows of a glyph of the 3 × 5 font ('m' is 5 wide); unknown characters are blank.
fn glyph(c: char) -> [&'static str; 5] {
    match c {
        '0' => ["###", "#.#", "#.#", "#.#", "###"],
        '1' => [".#.", "##.", ".#.", ".#.", "###"],
        '2' => ["###", "..#", "###", "#..", "###"],
        '3' => ["###", "..#", "###", "..#", "###"],
        '4' => ["#.#", "#.#", "###", "..#", "..#"],
        '5' => ["###", "#..", "###", "..#", "###"],
        '6' => ["###", "#..", "###", "#.#", "###"],
        '7' => ["###", "..#", "..#", "..#", "..#"],
        '8' => ["###", "#.#", "###", "#.#", "###"],
        '9' => ["###", "#.#", "###", "..#", "###"],
        '.' => ["...", "...", "...", "...", ".#."],
        'm' => [".....", ".....", "####.", "#.#.#", "#.#.#"],
        _ => ["...", "...", "...", "...", "..."],
    }
}

fn encode(path: &Path, frame: &Frame, rgb: &[u8]) -> Result<(), RenderError> {
    let fail = |message: String| RenderError::WritePng {
        path: path.to_path_buf(),
        message,
    };
    let (w, h) = (frame.width(), frame.height());
    let (Ok(w32), Ok(h32)) = (u32::try_from(w), u32::try_from(h)) else {
        return Err(fail(format!("{w}x{h} pixels is too large for PNG")));
    };
    let mut bytes = Vec::new();
    {
        let mut encoder = ::png::Encoder::new(&mut bytes, w32, h32);
        encoder.set_color(::png::ColorType::Rgb);
        encoder.set_depth(::png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(|e| fail(e.to_string()))?;
        writer
            .write_image_data(rgb)
            .map_err(|e| fail(e.to_string()))?;
        writer.finish().map_err(|e| fail(e.to_string()))?;
    }
    crate::format::write_file_atomic(path, &bytes).map_err(|e| fail(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_bar_lengths_are_round_numbers() {
        assert_eq!(scale_bar_mm(10.0), 2.0);
        assert_eq!(scale_bar_mm(8.0), 2.0);
        assert_eq!(scale_bar_mm(20.0), 5.0);
        assert_eq!(scale_bar_mm(4.0), 1.0);
        assert!((scale_bar_mm(1.0) - 0.2).abs() < 1e-12);
        assert_eq!(trim_number(0.2), "0.2");
        assert_eq!(trim_number(5.0), "5");
    }

    #[test]
    fn log_map_spans_the_decades_and_keeps_hues() {
        let v = [
            1.0f32,
            1.0,
            1.0, // the brightest: white
            0.3,
            0.0,
            0.0, // one decade down: red at 3/4
            1e-5,
            0.0,
            0.0, // beyond four decades: black
            0.0,
            0.0,
            0.0,
            f32::NAN,
            1.0,
            0.0,
        ];
        let m = tonemap_log(&v, 4.0);
        assert_eq!(&m[..3], &[255, 255, 255]);
        assert_eq!(&m[3..6], &[(255.0f64 * 0.75).round() as u8, 0, 0]);
        assert_eq!(&m[6..], &[0; 9]);
    }

    #[test]
    fn diverging_colours_follow_the_sign() {
        let m = diverging(&[1.0, -1.0, 0.0]);
        assert_eq!(&m[..3], &[255, 0, 0]);
        assert_eq!(&m[3..6], &[0, 0, 255]);
        assert_eq!(&m[6..], &[0, 0, 0]);
    }
}
