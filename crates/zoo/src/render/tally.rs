//! Tallies of a render: the binned image, and per-photon totals and first moments (for the
//! power, the centroid and their standard errors), summed per block of photons in photon order.
//!
//! A block keeps its pixel deposits as a list (pixel channel, weight) in the order they were
//! made, not as a picture: its memory is then independent of the picture's size, and adding
//! the blocks' lists in block order sums every pixel in plain photon order.
//!
//! A photon may leave many exits (the walk) or one exit carrying three channel weights (the
//! sampled models). Its scores are summed per (order, channel) first; only the photon's sums
//! enter the second moments, so the standard errors are those of independent photons. The
//! centroid x̄ = Σ M / Σ X (X a photon's power, M = Σ w x its first moment) is a ratio of means;
//! its standard error is the delta-method one, √(Σ (Mᵢ − x̄ Xᵢ)² / (N (N − 1))) / X̄.

use crate::walk::Estimate;
use serde::Serialize;

/// Scattering orders kept apart in the statistics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Part {
    /// Exits after exactly one scattering vertex (the walk only; the models hold none).
    Single,
    /// Exits after two or more vertices: what the diffusion models describe.
    Multiple,
    /// Both.
    Total,
}

/// Colour channels, and the luminance L = R + G + B (Ferrier's figure 1c).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Band {
    Red,
    Green,
    Blue,
    /// R + G + B.
    Luminance,
}

impl Band {
    /// Red, green, blue, luminance.
    pub const ALL: [Band; 4] = [Band::Red, Band::Green, Band::Blue, Band::Luminance];
    fn index(self) -> usize {
        self as usize
    }
}

impl Part {
    /// Single, multiple, total.
    pub const ALL: [Part; 3] = [Part::Single, Part::Multiple, Part::Total];
    fn index(self) -> usize {
        self as usize
    }
}

/// The pixel grid: `width` × `height` square pixels over `extent_x` mm along the plane of
/// incidence, centred on the entry point; column 0 at x = −extent_x/2, row 0 at the top
/// (y = +extent_y/2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    width: usize,
    height: usize,
    pixel: f64,
}

impl Frame {
    pub(crate) fn new(width: usize, height: usize, extent_x: f64) -> Self {
        Self {
            width,
            height,
            pixel: extent_x / width as f64,
        }
    }
    /// Pixels across (along x).
    pub fn width(&self) -> usize {
        self.width
    }
    /// Pixels down (along −y).
    pub fn height(&self) -> usize {
        self.height
    }
    /// Side of a pixel, mm.
    pub fn pixel_mm(&self) -> f64 {
        self.pixel
    }
    /// Width of the picture, mm.
    pub fn extent_x(&self) -> f64 {
        self.pixel * self.width as f64
    }
    /// Height of the picture, mm.
    pub fn extent_y(&self) -> f64 {
        self.pixel * self.height as f64
    }
    /// The pixel holding (x, y) mm, row-major, if inside.
    pub fn index(&self, x: f64, y: f64) -> Option<usize> {
        let col = (x / self.pixel + 0.5 * self.width as f64).floor();
        let row = (0.5 * self.height as f64 - y / self.pixel).floor();
        let inside =
            col >= 0.0 && row >= 0.0 && col < self.width as f64 && row < self.height as f64;
        inside.then(|| row as usize * self.width + col as usize)
    }
    /// Centre of pixel (col, row), mm.
    pub fn centre(&self, col: usize, row: usize) -> (f64, f64) {
        (
            (col as f64 + 0.5 - 0.5 * self.width as f64) * self.pixel,
            (0.5 * self.height as f64 - row as f64 - 0.5) * self.pixel,
        )
    }
}

/// Sums over photons of one (part, band): X power, M = Σ w x, Y = Σ w y.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Moments {
    x: f64,
    xx: f64,
    m: f64,
    mm: f64,
    xm: f64,
    y: f64,
    yy: f64,
    xy: f64,
}

impl Moments {
    fn add(&mut self, x: f64, m: f64, y: f64) {
        self.x += x;
        self.xx += x * x;
        self.m += m;
        self.mm += m * m;
        self.xm += x * m;
        self.y += y;
        self.yy += y * y;
        self.xy += x * y;
    }
    fn merge(&mut self, o: &Moments) {
        self.x += o.x;
        self.xx += o.xx;
        self.m += o.m;
        self.mm += o.mm;
        self.xm += o.xm;
        self.y += o.y;
        self.yy += o.yy;
        self.xy += o.xy;
    }
}

/// Sums of a block of photons (and, merged in block order, of the run).
#[derive(Debug, Clone)]
pub(crate) struct Sums {
    pub photons: u64,
    /// Deposits (3 · pixel + channel, weight), in the order made (blocks only).
    pub deposits: Vec<(u32, f64)>,
    moments: [[Moments; 4]; 3],
    reflected: (f64, f64),
    expected: [f64; 3],
    pub events: u64,
    pub lost: u64,
}

impl Sums {
    pub fn new() -> Self {
        Self {
            photons: 0,
            deposits: Vec::new(),
            moments: [[Moments::default(); 4]; 3],
            reflected: (0.0, 0.0),
            expected: [0.0; 3],
            events: 0,
            lost: 0,
        }
    }

    /// Adds the next block's sums (callers merge blocks in index order), its deposits into
    /// `image` (row-major RGB, 3 values per pixel).
    pub fn merge(&mut self, o: &Sums, image: &mut [f64]) {
        self.photons += o.photons;
        for &(i, w) in &o.deposits {
            if let Some(v) = image.get_mut(i as usize) {
                *v += w;
            }
        }
        for (pa, pb) in self.moments.iter_mut().zip(&o.moments) {
            for (a, b) in pa.iter_mut().zip(pb) {
                a.merge(b);
            }
        }
        self.reflected.0 += o.reflected.0;
        self.reflected.1 += o.reflected.1;
        for (a, b) in self.expected.iter_mut().zip(&o.expected) {
            *a += b;
        }
        self.events += o.events;
        self.lost += o.lost;
    }
}

/// The scores of the photon being traced, deposited into a block's sums.
pub(crate) struct Recorder<'a> {
    frame: &'a Frame,
    image_single: bool,
    sums: Sums,
    /// Per (order: single, multiple; channel): (Σ w, Σ w x, Σ w y) of the current photon.
    photon: [[[f64; 3]; 3]; 2],
    reflected: f64,
    expected: [f64; 3],
}

impl<'a> Recorder<'a> {
    /// `image_single`: whether single-scattering exits go into the image.
    pub fn new(frame: &'a Frame, image_single: bool) -> Self {
        Self {
            frame,
            image_single,
            sums: Sums::new(),
            photon: [[[0.0; 3]; 3]; 2],
            reflected: 0.0,
            expected: [0.0; 3],
        }
    }

    /// An exit at (x, y) mm carrying `w[c]` in channel c (per unit incident power).
    #[inline]
    pub fn exit(&mut self, x: f64, y: f64, w: [f64; 3], single: bool) {
        let order = usize::from(!single);
        for (c, &wc) in w.iter().enumerate() {
            let s = &mut self.photon[order][c];
            s[0] += wc;
            s[1] += wc * x;
            s[2] += wc * y;
        }
        if single && !self.image_single {
            return;
        }
        if let Some(p) = self.frame.index(x, y) {
            for (c, wc) in w.into_iter().enumerate() {
                if wc != 0.0 {
                    // 3 · pixel + c < 3 · MAX_SIDE² fits u32.
                    self.sums.deposits.push(((3 * p + c) as u32, wc));
                }
            }
        }
    }

    /// An exit carrying weight `w` in channel `c` only.
    #[inline]
    pub fn exit_channel(&mut self, c: usize, x: f64, y: f64, w: f64, single: bool) {
        let order = usize::from(!single);
        let s = &mut self.photon[order][c];
        s[0] += w;
        s[1] += w * x;
        s[2] += w * y;
        if single && !self.image_single {
            return;
        }
        if let Some(p) = self.frame.index(x, y) {
            if w != 0.0 {
                self.sums.deposits.push(((3 * p + c) as u32, w));
            }
        }
    }

    /// Fresnel reflectance at entry of the current photon (not imaged).
    pub fn reflect(&mut self, r: f64) {
        self.reflected = r;
    }

    /// The model's expected power per channel for the current photon, T(θᵢ) ρ_eff(θᵢ).
    pub fn expect(&mut self, e: [f64; 3]) {
        self.expected = e;
    }

    /// Scattering vertices of the walk.
    pub fn events(&mut self, n: u64) {
        self.sums.events += n;
    }

    /// A photon whose exit could not be sampled (counted, never silently dropped).
    pub fn lost(&mut self) {
        self.sums.lost += 1;
    }

    /// Folds the current photon into the sums and clears it.
    pub fn end_photon(&mut self) {
        let p = &self.photon;
        for part in Part::ALL {
            let per_channel = |c: usize| -> [f64; 3] {
                match part {
                    Part::Single => p[0][c],
                    Part::Multiple => p[1][c],
                    Part::Total => [0, 1, 2].map(|k| p[0][c][k] + p[1][c][k]),
                }
            };
            let rgb = [0, 1, 2].map(per_channel);
            let lum = [0, 1, 2].map(|k| rgb[0][k] + rgb[1][k] + rgb[2][k]);
            let row = &mut self.sums.moments[part.index()];
            for (c, s) in rgb.iter().chain(std::iter::once(&lum)).enumerate() {
                row[c].add(s[0], s[1], s[2]);
            }
        }
        self.sums.reflected.0 += self.reflected;
        self.sums.reflected.1 += self.reflected * self.reflected;
        for (a, b) in self.sums.expected.iter_mut().zip(self.expected) {
            *a += b;
        }
        self.photon = [[[0.0; 3]; 3]; 2];
        self.reflected = 0.0;
        self.expected = [0.0; 3];
        self.sums.photons += 1;
    }

    pub fn into_sums(self) -> Sums {
        self.sums
    }
}

/// Power and centroid of one (part, band), per unit incident power, with standard errors.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BandStats {
    /// Power leaving the surface per unit incident power, everywhere (inside the picture or not).
    pub power: Estimate,
    /// Exitance-weighted mean x (along the plane of incidence, + forward), mm.
    pub centroid_x_mm: Estimate,
    /// Exitance-weighted mean y (across the plane of incidence), mm.
    pub centroid_y_mm: Estimate,
}

/// Statistics of a render, per scattering order and band.
#[derive(Debug, Clone, PartialEq)]
pub struct Stats {
    /// Photons traced.
    pub photons: u64,
    /// Power reflected specularly at entry per unit incident power (Fresnel; not imaged).
    pub reflected: Estimate,
    /// The model's own prediction of the power it places per channel (multiple scattering; a
    /// `total` walk table's total), the mean over photons of T(θᵢ) ρ_eff(θᵢ); `None` where it is not computed per photon (mc, and pbd
    /// with a cone).
    pub expected: Option<[f64; 3]>,
    /// Power inside the picture per unit incident power, R, G, B, luminance.
    pub in_picture: [f64; 4],
    /// Indexed [part][band] as in [`Part::ALL`] and [`Band::ALL`].
    parts: [[BandStats; 4]; 3],
    /// Scattering vertices (the walk).
    pub scattering_events: u64,
    /// Photons whose exit the model could not sample (0 in every case measured).
    pub lost_samples: u64,
    /// Whether the exits are known by order: not for a `total` walk table, whose exits are
    /// single and multiple scattering together ([`Stats::get`] then gives NaN for either alone,
    /// and the JSON leaves them out).
    pub split: bool,
}

impl Stats {
    pub(crate) fn new(sums: &Sums, expected: bool, in_picture: [f64; 4]) -> Self {
        let n = sums.photons;
        let nf = n as f64;
        let parts = sums.moments.map(|row| row.map(|m| band_stats(&m, n)));
        let (mean_r, se_r) = mean_and_stderr(sums.reflected.0, sums.reflected.1, n);
        Self {
            photons: n,
            reflected: Estimate {
                value: mean_r,
                stderr: se_r,
            },
            expected: expected.then(|| sums.expected.map(|e| e / nf)),
            in_picture,
            parts,
            scattering_events: sums.events,
            lost_samples: sums.lost,
            split: true,
        }
    }

    /// These statistics with the exits not known by order ([`Stats::split`]).
    pub(crate) fn unsplit(mut self) -> Self {
        self.split = false;
        self
    }

    /// Power and centroid of one part and band; NaN for single or multiple scattering alone
    /// where the exits are not known by order ([`Stats::split`]).
    pub fn get(&self, part: Part, band: Band) -> BandStats {
        if !self.split && part != Part::Total {
            let nan = Estimate {
                value: f64::NAN,
                stderr: f64::NAN,
            };
            return BandStats {
                power: nan,
                centroid_x_mm: nan,
                centroid_y_mm: nan,
            };
        }
        self.parts[part.index()][band.index()]
    }
}

impl Serialize for Stats {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut map = s.serialize_map(None)?;
        map.serialize_entry("photons", &self.photons)?;
        map.serialize_entry("reflected_at_entry", &self.reflected)?;
        map.serialize_entry("expected", &self.expected)?;
        map.serialize_entry("in_picture", &self.in_picture)?;
        for part in Part::ALL
            .into_iter()
            .filter(|&p| self.split || p == Part::Total)
        {
            let bands: std::collections::BTreeMap<&str, BandStats> = Band::ALL
                .iter()
                .map(|&b| (band_name(b), self.get(part, b)))
                .collect();
            map.serialize_entry(part_name(part), &bands)?;
        }
        map.serialize_entry("scattering_events", &self.scattering_events)?;
        map.serialize_entry("lost_samples", &self.lost_samples)?;
        map.end()
    }
}

/// Lowercase name of a band.
pub fn band_name(b: Band) -> &'static str {
    match b {
        Band::Red => "red",
        Band::Green => "green",
        Band::Blue => "blue",
        Band::Luminance => "luminance",
    }
}

/// Lowercase name of a part.
pub fn part_name(p: Part) -> &'static str {
    match p {
        Part::Single => "single",
        Part::Multiple => "multiple",
        Part::Total => "total",
    }
}

fn mean_and_stderr(sum: f64, sq: f64, n: u64) -> (f64, f64) {
    let nf = n as f64;
    if n == 0 {
        return (0.0, f64::NAN);
    }
    let mean = sum / nf;
    let se = if n > 1 {
        ((sq - sum * mean).max(0.0) / (nf * (nf - 1.0))).sqrt()
    } else {
        f64::NAN
    };
    (mean, se)
}

fn band_stats(m: &Moments, n: u64) -> BandStats {
    let (power, se) = mean_and_stderr(m.x, m.xx, n);
    let nf = n as f64;
    // Ratio of means and its delta-method standard error; NaN without power or photons.
    let ratio = |num: f64, num_sq: f64, cross: f64| -> Estimate {
        if m.x <= 0.0 || n < 2 {
            return Estimate {
                value: f64::NAN,
                stderr: f64::NAN,
            };
        }
        let c = num / m.x;
        let resid = (num_sq - 2.0 * c * cross + c * c * m.xx).max(0.0);
        Estimate {
            value: c,
            stderr: (resid / (nf * (nf - 1.0))).sqrt() / (m.x / nf),
        }
    };
    BandStats {
        power: Estimate {
            value: power,
            stderr: se,
        },
        centroid_x_mm: ratio(m.m, m.mm, m.xm),
        centroid_y_mm: ratio(m.y, m.yy, m.xy),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_maps_points_to_pixels_and_back() {
        let f = Frame::new(4, 2, 8.0);
        assert_eq!(f.pixel_mm(), 2.0);
        assert_eq!(f.extent_y(), 4.0);
        assert_eq!(f.index(-3.9, 1.9), Some(0));
        assert_eq!(f.index(3.9, -1.9), Some(7));
        assert_eq!(f.index(4.1, 0.0), None);
        assert_eq!(f.index(0.0, 2.1), None);
        assert_eq!(f.index(f64::NAN, 0.0), None);
        assert_eq!(f.centre(0, 0), (-3.0, 1.0));
        assert_eq!(f.index(f.centre(2, 1).0, f.centre(2, 1).1), Some(6));
    }

    #[test]
    fn centroid_and_its_error_from_known_photons() {
        // Photons of unit power at x = 1, 2, 3, 4: x̄ = 2.5; the residuals xᵢ − x̄ give the
        // standard error √(5/12), as for a plain mean.
        let frame = Frame::new(2, 2, 20.0);
        let mut r = Recorder::new(&frame, true);
        for x in [1.0, 2.0, 3.0, 4.0] {
            r.exit(x, 0.0, [1.0, 0.0, 0.0], false);
            r.end_photon();
        }
        let s = Stats::new(&r.into_sums(), false, [0.0; 4]);
        let red = s.get(Part::Multiple, Band::Red);
        assert_eq!(red.power.value, 1.0);
        assert_eq!(red.power.stderr, 0.0);
        assert!((red.centroid_x_mm.value - 2.5).abs() < 1e-15);
        assert!((red.centroid_x_mm.stderr - (5.0f64 / 12.0).sqrt()).abs() < 1e-12);
        assert_eq!(s.get(Part::Total, Band::Luminance).power.value, 1.0);
        assert!(s.get(Part::Single, Band::Red).centroid_x_mm.value.is_nan());
    }

    #[test]
    fn single_scattering_is_kept_out_of_the_image_on_request() {
        let frame = Frame::new(2, 2, 2.0);
        let mut r = Recorder::new(&frame, false);
        r.exit_channel(1, 0.5, 0.5, 2.0, true);
        r.exit_channel(1, 0.5, 0.5, 3.0, false);
        r.end_photon();
        let sums = r.into_sums();
        assert_eq!(sums.deposits, [(3 + 1, 3.0)]);
        let s = Stats::new(&sums, false, [0.0; 4]);
        assert_eq!(s.get(Part::Total, Band::Green).power.value, 5.0);
    }
}
