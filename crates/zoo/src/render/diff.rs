//! The signed luminance difference of two pictures (Ferrier's figure 1c) and its numbers.
//!
//! With L = R + G + B per pixel (the figure's luminance) and D = L_A − L_B:
//! - relative L1 = Σ|D| / Σ|L_B|, relative L2 = √(Σ D²) / √(Σ L_B²): B is the reference;
//! - the exitance centroid along the plane of incidence, x̄ = Σ L x / Σ L over pixel centres
//!   (mm, + forward), of each picture, and the shift x̄_A − x̄_B.
//!
//! Centroids from pictures see only what falls inside them; a render's own statistics
//! ([`super::Stats`]) count every exit.

use super::{Frame, Picture, RenderError, META_PREFIX};

/// The difference of two pictures.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    frame: Frame,
    values: Vec<f32>,
    /// Σ|L_A − L_B| / Σ|L_B|.
    pub relative_l1: f64,
    /// ‖L_A − L_B‖₂ / ‖L_B‖₂.
    pub relative_l2: f64,
    /// Luminance centroid of A along x, mm.
    pub centroid_a_mm: f64,
    /// Luminance centroid of B along x, mm.
    pub centroid_b_mm: f64,
    meta: Vec<(String, String)>,
}

impl Difference {
    /// The pixel grid (that of both pictures).
    pub fn frame(&self) -> &Frame {
        &self.frame
    }
    /// L_A − L_B per pixel, row-major, mm⁻² per unit incident power.
    pub fn values(&self) -> &[f32] {
        &self.values
    }
    /// x̄_A − x̄_B, mm.
    pub fn centroid_shift_mm(&self) -> f64 {
        self.centroid_a_mm - self.centroid_b_mm
    }
    /// Metadata for the difference's file: the numbers, and the pictures' own metadata
    /// prefixed `a:` and `b:`.
    pub fn meta(&self) -> &[(String, String)] {
        &self.meta
    }
}

/// Luminance centroid along x of row-major luminance on `frame`, mm.
pub fn centroid_x(frame: &Frame, luminance: &[f64]) -> Option<f64> {
    let (mut sum, mut moment) = (0.0, 0.0);
    for (i, &l) in luminance.iter().enumerate() {
        let (x, _) = frame.centre(i % frame.width(), i / frame.width());
        sum += l;
        moment += l * x;
    }
    (sum > 0.0).then(|| moment / sum)
}

/// A − B in luminance. The pictures must have the same size and extent.
pub fn difference(a: &Picture, b: &Picture) -> Result<Difference, RenderError> {
    let (fa, fb) = (a.frame(), b.frame());
    if (fa.width(), fa.height()) != (fb.width(), fb.height()) {
        return Err(RenderError::Mismatch {
            what: "size",
            a: format!("{}x{}", fa.width(), fa.height()),
            b: format!("{}x{}", fb.width(), fb.height()),
        });
    }
    let (ea, eb) = (fa.extent_x(), fb.extent_x());
    if (ea - eb).abs() > 1e-9 * ea.abs().max(eb.abs()) {
        return Err(RenderError::Mismatch {
            what: "extent (mm)",
            a: ea.to_string(),
            b: eb.to_string(),
        });
    }
    let (la, lb) = (a.luminance(), b.luminance());
    let empty = |what: &str, l: &[f64]| RenderError::Empty {
        what: what.to_string(),
        sum: l.iter().sum(),
    };
    let centroid_a_mm = centroid_x(fa, &la).ok_or_else(|| empty("the first picture", &la))?;
    let centroid_b_mm = centroid_x(fb, &lb).ok_or_else(|| empty("the second picture", &lb))?;
    let (mut l1, mut l1_ref, mut l2, mut l2_ref) = (0.0, 0.0, 0.0, 0.0);
    let values: Vec<f32> = la
        .iter()
        .zip(&lb)
        .map(|(&x, &y)| {
            let d = x - y;
            l1 += d.abs();
            l1_ref += y.abs();
            l2 += d * d;
            l2_ref += y * y;
            d as f32
        })
        .collect();
    let relative_l1 = l1 / l1_ref;
    let relative_l2 = (l2 / l2_ref).sqrt();
    let shift = centroid_a_mm - centroid_b_mm;
    let mut meta: Vec<(String, String)> = [
        (
            "kind",
            "signed luminance difference A - B (L = R + G + B)".to_string(),
        ),
        ("relative_l1", relative_l1.to_string()),
        ("relative_l2", relative_l2.to_string()),
        ("centroid_a_mm", centroid_a_mm.to_string()),
        ("centroid_b_mm", centroid_b_mm.to_string()),
        ("centroid_shift_mm", shift.to_string()),
        ("extent_mm", ea.to_string()),
    ]
    .into_iter()
    .map(|(k, v)| (format!("{META_PREFIX}{k}"), v))
    .collect();
    for (tag, picture) in [("a", a), ("b", b)] {
        for (k, v) in picture.meta() {
            if let Some(key) = k.strip_prefix(META_PREFIX) {
                if matches!(key, "model" | "material" | "photons" | "theta_deg" | "seed") {
                    meta.push((format!("{META_PREFIX}{tag}:{key}"), v.clone()));
                }
            }
        }
    }
    Ok(Difference {
        frame: *fa,
        values,
        relative_l1,
        relative_l2,
        centroid_a_mm,
        centroid_b_mm,
        meta,
    })
}
