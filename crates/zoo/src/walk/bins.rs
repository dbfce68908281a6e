//! Exit-point bins on the lit surface, in polar coordinates (r, φ) about the entry point.
//!
//! - Radial: a first bin [0, r_min), then `radial` geometric bins from r_min to r_max, each
//!   wider than the last by (r_max/r_min)^{1/radial}. Exits at r ≥ r_max are not binned (they
//!   still count in every reflectance).
//! - Azimuthal: `phi` uniform bins over [−π, π), φ = 0 forward. Bin k and bin phi − 1 − k are
//!   mirror images about the plane of incidence, so the evenness of R(r, φ) in φ can be
//!   checked bin by bin.
//!
//! Bin (i, j) covers the annular sector r ∈ [r_i, r_{i+1}), φ ∈ [φ_j, φ_{j+1}) of area
//! (r_{i+1}² − r_i²) Δφ / 2, in squared mean free paths.

use crate::error::{finite, in_range, Error, Result};
use std::f64::consts::{PI, TAU};

/// Most geometric radial bins accepted.
pub const MAX_RADIAL: usize = 10_000;
/// Most azimuthal bins accepted.
pub const MAX_PHI: usize = 3_600;
/// Most bins in all, (radial + 1) · phi; a run keeps a few arrays of this size per thread.
pub const MAX_BINS: usize = 1 << 18;

/// The largest r_max, mean free paths: beyond about 1.3e154 a bin's area ½(r₂² − r₁²) was
/// ∞ − ∞ (NaN), and beyond f64's range over r_min the geometric edges were NaN.
pub const MAX_R: f64 = 1e150;

/// The smallest r_min, mean free paths: below about 1e-154 a point's x² + y² underflows to 0
/// and the point fell in the first bin whatever its bin.
pub const MIN_R: f64 = 1e-150;

/// Layout of the (r, φ) exit bins. Built by [`Bins::new`], which checks it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Bins {
    r_min: f64,
    r_max: f64,
    radial: usize,
    phi: usize,
    #[serde(skip)]
    r_edges: Vec<f64>,
    #[serde(skip)]
    phi_edges: Vec<f64>,
    #[serde(skip)]
    ln_ratio: f64,
}

impl Bins {
    /// Bins with first edge `r_min` and last edge `r_max` (mean free paths, [`MIN_R`] ≤ r_min <
    /// r_max ≤ [`MAX_R`]), `radial` geometric bins between them (1 ≤ radial ≤ [`MAX_RADIAL`]) and `phi`
    /// azimuthal bins (1 ≤ phi ≤ [`MAX_PHI`]), at most [`MAX_BINS`] bins in all.
    pub fn new(r_min: f64, r_max: f64, radial: usize, phi: usize) -> Result<Self> {
        finite("r_min", r_min)?;
        if r_min <= 0.0 {
            return Err(Error::NotPositive {
                name: "r_min",
                value: r_min,
            });
        }
        // Squares of radii neither underflow nor overflow: a point's r from x² + y², and the
        // bins' areas ½(r₂² − r₁²)
        in_range("r_min", r_min, MIN_R, MAX_R)?;
        in_range("r_max", r_max, MIN_R, MAX_R)?;
        if r_max <= r_min {
            return Err(Error::EdgesNotIncreasing {
                lo_name: "r_min",
                lo: r_min,
                hi_name: "r_max",
                hi: r_max,
            });
        }
        let count = |name, value: usize, max: usize| {
            if (1..=max).contains(&value) {
                Ok(())
            } else {
                Err(Error::CountOutOfRange {
                    name,
                    value: value as u64,
                    min: 1,
                    max: max as u64,
                })
            }
        };
        count("radial bins", radial, MAX_RADIAL)?;
        count("phi bins", phi, MAX_PHI)?;
        count(
            "bins in all, (radial + 1) * phi",
            (radial + 1) * phi,
            MAX_BINS,
        )?;

        let ln_ratio = (r_max / r_min).ln() / radial as f64;
        if ln_ratio.is_nan() || ln_ratio <= 0.0 {
            // r_max/r_min rounds to 1: the geometric bins would have no width.
            return Err(Error::EdgesNotIncreasing {
                lo_name: "r_min",
                lo: r_min,
                hi_name: "r_max",
                hi: r_max,
            });
        }
        let mut r_edges = Vec::with_capacity(radial + 2);
        r_edges.push(0.0);
        for i in 0..radial {
            r_edges.push(r_min * (ln_ratio * i as f64).exp());
        }
        r_edges.push(r_max);
        let phi_edges = (0..=phi)
            .map(|j| -PI + TAU * j as f64 / phi as f64)
            .collect();
        Ok(Self {
            r_min,
            r_max,
            radial,
            phi,
            r_edges,
            phi_edges,
            ln_ratio,
        })
    }

    /// Radial edges r_0 = 0, r_1 = r_min, …, r_max (mean free paths); one more than
    /// [`Self::radial_count`].
    pub fn r_edges(&self) -> &[f64] {
        &self.r_edges
    }

    /// Azimuthal edges −π, …, π (radians); one more than [`Self::phi_count`].
    pub fn phi_edges(&self) -> &[f64] {
        &self.phi_edges
    }

    /// Number of radial bins, including the first bin [0, r_min).
    pub fn radial_count(&self) -> usize {
        self.radial + 1
    }

    /// Number of azimuthal bins.
    pub fn phi_count(&self) -> usize {
        self.phi
    }

    /// Number of bins, radial_count · phi_count.
    pub fn len(&self) -> usize {
        self.radial_count() * self.phi
    }

    /// Always false: there is at least one bin.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Upper radial edge of the binned disc (mean free paths).
    pub fn r_max(&self) -> f64 {
        self.r_max
    }

    /// Area of bin (i, j) in squared mean free paths; `None` outside the layout.
    pub fn area(&self, i: usize, j: usize) -> Option<f64> {
        if i >= self.radial_count() || j >= self.phi {
            return None;
        }
        let (lo, hi) = (self.r_edges[i], self.r_edges[i + 1]);
        let dphi = self.phi_edges[j + 1] - self.phi_edges[j];
        Some(0.5 * (hi * hi - lo * lo) * dphi)
    }

    /// Flat index i · phi_count + j of the bin holding the surface point (x, y), or `None`
    /// when r ≥ r_max (or the point is not finite).
    pub fn index(&self, x: f64, y: f64) -> Option<usize> {
        // r ≥ r_max, beyond every bin, also holds for the f64 squares that overflow.
        let r = (x * x + y * y).sqrt();
        if r.is_nan() || r >= self.r_max {
            return None;
        }
        let last = self.radial;
        let mut i = if r < self.r_min {
            0
        } else {
            // About 1 + ⌊ln(r/r_min)/ln q⌋, a logarithm in f32 being close enough for a first
            // guess; then nudged so that the published edges decide.
            // (In f64 where r/r_min passes f32's range: its logarithm would be +∞.)
            let q = r / self.r_min;
            let k = if q < f64::from(f32::MAX) {
                (q as f32).ln() / self.ln_ratio as f32
            } else {
                (q.ln() / self.ln_ratio) as f32
            };
            (k.max(0.0) as usize).saturating_add(1).min(last)
        };
        while i > 1 && r < self.r_edges[i] {
            i -= 1;
        }
        while i < last && r >= self.r_edges[i + 1] {
            i += 1;
        }
        let phi = y.atan2(x);
        let j = (((phi + PI) / TAU) * self.phi as f64) as usize;
        Some(i * self.phi + j.min(self.phi - 1))
    }
}

impl Default for Bins {
    /// r_min = 0.01, r_max = 100 mean free paths, 40 geometric radial bins (ratio 10^0.1),
    /// 36 azimuthal bins of 10°.
    fn default() -> Self {
        match Self::new(0.01, 100.0, 40, 36) {
            Ok(b) => b,
            Err(_) => unreachable!("the default bin layout is valid"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_are_geometric_and_end_exactly() {
        let b = Bins::new(0.01, 100.0, 4, 6).unwrap();
        let e = b.r_edges();
        assert_eq!(e.len(), 6);
        assert_eq!((e[0], e[1], e[5]), (0.0, 0.01, 100.0));
        for k in 1..5 {
            assert!((e[k + 1] / e[k] - 10.0).abs() < 1e-12);
        }
        assert_eq!(b.phi_edges().len(), 7);
        assert_eq!(b.phi_edges()[0], -PI);
        assert_eq!(b.phi_edges()[6], PI);
    }

    #[test]
    fn points_land_in_the_bin_whose_edges_hold_them() {
        let b = Bins::new(0.05, 20.0, 17, 12).unwrap();
        for k in 0..2000 {
            let r = 25.0 * (k as f64 / 2000.0).powi(3);
            let phi = -PI + TAU * ((k * 37) % 2000) as f64 / 2000.0;
            let (x, y) = (r * phi.cos(), r * phi.sin());
            match b.index(x, y) {
                None => assert!((x * x + y * y).sqrt() >= 20.0),
                Some(idx) => {
                    let (i, j) = (idx / 12, idx % 12);
                    let rr = (x * x + y * y).sqrt();
                    assert!(b.r_edges()[i] <= rr && rr < b.r_edges()[i + 1], "r = {rr}");
                    let p = y.atan2(x);
                    assert!(b.phi_edges()[j] - 1e-12 <= p && p <= b.phi_edges()[j + 1] + 1e-12);
                }
            }
        }
        // Exactly on an edge: the upper bin.
        let edge = b.r_edges()[5];
        assert_eq!(b.index(edge, 0.0).map(|i| i / 12), Some(5));
        // φ = π (negative zero y) and φ = −π both land in a valid bin.
        assert!(b.index(-1.0, 0.0).is_some());
        assert!(b.index(-1.0, -0.0).is_some());
        assert_eq!(b.index(f64::NAN, 0.0), None);
        assert_eq!(b.index(0.0, 0.0), Some(6));
    }

    /// At the ends of the domain: r/r_min beyond f32's range still finds its bin (it
    /// overflowed to a panic), every edge and area is finite, and beyond the domain the layout
    /// is refused naming the value (r_max = 1e308 gave NaN edges, r_min = 1e-300 radii that
    /// underflowed into the first bin).
    #[test]
    fn extreme_layouts_have_finite_bins_or_are_refused() {
        let b = Bins::new(MIN_R, MAX_R, 3, 2).unwrap();
        for r in [MIN_R, 1e-100, 0.5, 1e100, 0.999 * MAX_R] {
            let i = b.index(r, 0.0).unwrap() / 2;
            assert!(b.r_edges()[i] <= r && r < b.r_edges()[i + 1], "{r}");
        }
        assert!(b.r_edges().iter().all(|e| e.is_finite()));
        assert!((0..b.radial_count()).all(|i| b.area(i, 0).unwrap().is_finite()));
        for (r_min, r_max, name) in [(0.1, 1e308, "r_max"), (1e-300, 1.0, "r_min")] {
            match Bins::new(r_min, r_max, 3, 2) {
                Err(Error::OutOfRange { name: n, .. }) => assert_eq!(n, name),
                other => panic!("{r_min}, {r_max}: {other:?}"),
            }
        }
    }

    #[test]
    fn areas_sum_to_the_disc() {
        let b = Bins::new(0.1, 3.0, 5, 7).unwrap();
        let mut total = 0.0;
        for i in 0..b.radial_count() {
            for j in 0..b.phi_count() {
                total += b.area(i, j).unwrap();
            }
        }
        assert!((total - PI * 9.0).abs() < 1e-12);
        assert_eq!(b.area(6, 0), None);
    }

    #[test]
    fn invalid_layouts_are_rejected() {
        assert!(matches!(
            Bins::new(0.0, 1.0, 3, 3),
            Err(Error::NotPositive { name: "r_min", .. })
        ));
        assert!(matches!(
            Bins::new(f64::NAN, 1.0, 3, 3),
            Err(Error::NotFinite { name: "r_min", .. })
        ));
        assert!(matches!(
            Bins::new(0.1, f64::INFINITY, 3, 3),
            Err(Error::NotFinite { name: "r_max", .. })
        ));
        assert!(matches!(
            Bins::new(1.0, 1.0, 3, 3),
            Err(Error::EdgesNotIncreasing { .. })
        ));
        assert!(matches!(
            Bins::new(0.1, 1.0, 0, 3),
            Err(Error::CountOutOfRange {
                name: "radial bins",
                value: 0,
                ..
            })
        ));
        assert!(matches!(
            Bins::new(0.1, 1.0, 3, 0),
            Err(Error::CountOutOfRange {
                name: "phi bins",
                value: 0,
                ..
            })
        ));
        assert!(matches!(
            Bins::new(0.1, 1.0, 5000, 3000),
            Err(Error::CountOutOfRange { .. })
        ));
    }
}
