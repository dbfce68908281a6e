//! The artist's parameters: a diffuse reflectance and a mean free path per channel, turned into
//! coefficients through the table's effective albedo, as pbrt's `SubsurfaceFromDiffuse` does
//! (pbrt-v3 `core/bssrdf.cpp`, pbrt-v4 `BSSRDFTable` and `SubsurfaceFromDiffuse`).
//!
//! | parameter | unit | valid range | meaning |
//! |---|---|---|---|
//! | reflectance | – | [0, 1] per channel | the diffuse colour: the effective albedo ρ_eff wanted |
//! | mfp | mm | > 0, finite, per channel | the unreduced mean free path 1/σt (pbrt's convention) |
//! | g | – | (−1, 1) | Henyey–Greenstein asymmetry (default 0) |
//!
//! 1. ρ′ from the reflectance: invert ρ ↦ ρ_eff(ρ, θ = 0) of the table (as pbrt's
//!    `InvertCatmullRom` inverts its spline), where ρ_eff(ρ′_i, 0) is the last radial-CDF node of
//!    row (i, θ = 0): the table's own total multiply scattered power at normal incidence,
//!    interpolated along ρ′ as the table interpolates it (ρ′² times the spline of ρ_eff/ρ′²,
//!    `table::albedo`), so that the table's ρ_eff at the ρ′ found is the reflectance. It is
//!    **multiple scattering only** (PBD has no single-scattering term): at ρ′ = 1 and η = 1.33
//!    it is 0.9503 on the default grid (0.9513 coarse, 0.9496 fine; PBD's exact value is
//!    0.9613, of which the table misses the tail beyond its last radius, 243 mean free paths,
//!    where a non-absorbing profile decays only slowly), while pbrt's ρ_eff, which adds single
//!    scattering, exceeds 1. A reflectance above the table's largest ρ_eff cannot be
//!    reached: it is clamped to ρ′ = 1 and reported ([`Inverted::clamped`]) so that the caller
//!    warns (pbrt clamps silently); a reflectance outside [0, 1] is an error.
//! 2. σt = 1/mfp, and σs solves σs(1 − g)/(σs(1 − g) + σa) = ρ′ with σs + σa = σt:
//!    σs = ρ′σt/(1 − g(1 − ρ′)), σa = σt − σs. With g = 0 this is pbrt's σs = ρσt, σa = (1 − ρ)σt.
//!
//! The result depends on the grid the curve comes from (the coarse grid's ρ_eff differs from
//! the default grid's by ~1e-4), so a bake inverts with the curve of the grid it bakes.

use crate::catmull_rom::Nodes;
use crate::fresnel::Moments;
use crate::table::{bake_rows, AlbedoAxis, AngularTable, Grid, SubsetError};

/// ρ_eff(ρ′, θ = 0) of a table over its albedo nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct EffectiveAlbedo {
    rho: AlbedoAxis,
    rho_eff: Vec<f64>,
}

/// Why artist's parameters could not be turned into coefficients.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ArtistError {
    /// A reflectance is NaN or outside [0, 1].
    #[error("reflectance[{channel}] = {value} is outside [0, 1]")]
    Reflectance { channel: &'static str, value: f64 },
    /// A mean free path is not a finite number > 0.
    #[error("mfp[{channel}] = {value} mm must be a finite number > 0")]
    Mfp { channel: &'static str, value: f64 },
    /// g is NaN or outside (−1, 1).
    #[error("g[{channel}] = {value} is outside (-1, 1)")]
    Asymmetry { channel: &'static str, value: f64 },
    /// The table has no θ = 0 node, or its ρ_eff does not increase with ρ′.
    #[error("the table cannot invert reflectance: {0}")]
    Curve(&'static str),
    /// Baking the curve failed.
    #[error(transparent)]
    Bake(#[from] SubsetError),
}

/// ρ′ for one reflectance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inverted {
    /// Reduced albedo ρ′ ∈ [0, 1].
    pub rho_prime: f64,
    /// Whether the reflectance was above the largest ρ_eff and ρ′ was clamped to the last node.
    pub clamped: bool,
}

/// Coefficients of one material from the artist's parameters, per channel R, G, B.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Diffuse {
    /// σs, mm⁻¹.
    pub sigma_s: [f64; 3],
    /// σa, mm⁻¹.
    pub sigma_a: [f64; 3],
    /// The inverted reduced albedo and whether it was clamped.
    pub inverted: [Inverted; 3],
}

const CHANNELS: [&str; 3] = ["r", "g", "b"];

impl EffectiveAlbedo {
    /// A curve from its nodes ρ′ᵢ (strictly increasing, at least 2) and the values
    /// ρ_eff(ρ′ᵢ, θ = 0), which must not decrease. Between the nodes it is ρ′² times the spline
    /// of ρ_eff/ρ′², as a table's (see the module docs): for values that vanish like ρ′² (multiple
    /// scattering only; pbrt's `rhoEff`, which adds single scattering, does not).
    pub fn new(rho: Vec<f64>, rho_eff: Vec<f64>) -> Result<Self, ArtistError> {
        let rho = Nodes::new(rho).map_err(|_| ArtistError::Curve("its nodes do not increase"))?;
        let rho = AlbedoAxis::new(rho);
        if rho_eff.len() != rho.nodes().as_slice().len() {
            return Err(ArtistError::Curve("it has not one value per node"));
        }
        if rho_eff.iter().any(|v| !v.is_finite()) {
            return Err(ArtistError::Curve("a value is not finite"));
        }
        if rho_eff.windows(2).any(|w| w[1] < w[0]) {
            return Err(ArtistError::Curve("its rho_eff decreases somewhere"));
        }
        Ok(Self { rho, rho_eff })
    }

    /// The curve of `table`, whose θ axis must start at 0 (normal incidence).
    pub fn from_table(table: &AngularTable) -> Result<Self, ArtistError> {
        let (n_rho, n_theta, n_r) = table.axes().dims();
        if table.axes().theta().as_slice().first() != Some(&0.0) {
            return Err(ArtistError::Curve("its theta axis does not start at 0"));
        }
        let cdf = table.radial_cdf();
        let rho_eff: Vec<f64> = (0..n_rho)
            .map(|i| f64::from(cdf[i * n_theta * n_r + n_r - 1]))
            .collect();
        Self::new(table.axes().rho().as_slice().to_vec(), rho_eff)
    }

    /// Bakes only what the curve needs: every albedo row of `grid` at its first two incidence
    /// nodes (rows are independent, so the θ = 0 values equal the full bake's bit for bit).
    pub fn bake(eta: f64, moments: Moments, grid: &Grid) -> Result<Self, ArtistError> {
        let small = Grid {
            rho: grid.rho.clone(),
            theta: grid.theta.iter().take(2).copied().collect(),
            r: grid.r.clone(),
        };
        let (table, _) = bake_rows(eta, moments, &small, 0..small.rho.len(), false, &|_| {})?;
        Self::from_table(&table)
    }

    /// The largest effective albedo the table reaches (at its last albedo node, normally ρ′ = 1).
    pub fn max(&self) -> f64 {
        self.rho_eff.last().copied().unwrap_or(0.0)
    }

    /// ρ_eff at reduced albedo `rho` (interpolated as the table's), `None` outside the axis.
    pub fn at(&self, rho: f64) -> Option<f64> {
        Some(self.rho.weights(rho)?.apply(|i| self.rho_eff[i]))
    }

    /// ρ′ whose ρ_eff is `reflectance` ∈ [0, 1]; above the largest ρ_eff, the last node, clamped.
    pub fn invert(&self, reflectance: f64, channel: usize) -> Result<Inverted, ArtistError> {
        let name = CHANNELS.get(channel).copied().unwrap_or("?");
        if !(0.0..=1.0).contains(&reflectance) {
            return Err(ArtistError::Reflectance {
                channel: name,
                value: reflectance,
            });
        }
        let rho_prime = self.solve(reflectance);
        Ok(Inverted {
            rho_prime: rho_prime.clamp(0.0, 1.0),
            clamped: reflectance > self.max(),
        })
    }

    /// ρ′ with ρ_eff(ρ′) = y (not NaN): the first node at or below the curve's first value, the
    /// last at or above its last, else bisected on the segment whose nodes bracket y, to the
    /// last bit (ρ_eff is continuous and its nodes do not decrease).
    fn solve(&self, y: f64) -> f64 {
        let (x, v) = (self.rho.nodes().as_slice(), &self.rho_eff);
        let n = x.len();
        if y <= v[0] {
            return x[0];
        }
        if y >= v[n - 1] {
            return x[n - 1];
        }
        // Segment i: v[i] ≤ y < v[i + 1]
        let i = v.partition_point(|&vi| vi <= y) - 1;
        let (mut lo, mut hi) = (x[i], x[i + 1]);
        loop {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                return if y - self.at(lo).unwrap_or(y) <= self.at(hi).unwrap_or(y) - y {
                    lo
                } else {
                    hi
                };
            }
            if self.at(mid).is_some_and(|v| v <= y) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    }

    /// σs and σa per channel from reflectance, mfp (mm) and g (see the module docs).
    pub fn diffuse(
        &self,
        reflectance: [f64; 3],
        mfp: [f64; 3],
        g: [f64; 3],
    ) -> Result<Diffuse, ArtistError> {
        let mut out = Diffuse {
            sigma_s: [0.0; 3],
            sigma_a: [0.0; 3],
            inverted: [Inverted {
                rho_prime: 0.0,
                clamped: false,
            }; 3],
        };
        check(reflectance, mfp, g)?;
        for c in 0..3 {
            let inverted = self.invert(reflectance[c], c)?;
            let (sigma_s, sigma_a) = coefficients(inverted.rho_prime, mfp[c], g[c]);
            out.sigma_s[c] = sigma_s;
            out.sigma_a[c] = sigma_a;
            out.inverted[c] = inverted;
        }
        Ok(out)
    }
}

/// Checks the artist's parameters without a curve: reflectance in [0, 1], mfp finite and > 0,
/// g in (−1, 1), per channel; errors name the channel and the value.
pub fn check(reflectance: [f64; 3], mfp: [f64; 3], g: [f64; 3]) -> Result<(), ArtistError> {
    for (c, channel) in CHANNELS.into_iter().enumerate() {
        if !(0.0..=1.0).contains(&reflectance[c]) {
            return Err(ArtistError::Reflectance {
                channel,
                value: reflectance[c],
            });
        }
        if !(mfp[c].is_finite() && mfp[c] > 0.0) {
            return Err(ArtistError::Mfp {
                channel,
                value: mfp[c],
            });
        }
        if !(g[c] > -1.0 && g[c] < 1.0) {
            return Err(ArtistError::Asymmetry {
                channel,
                value: g[c],
            });
        }
    }
    Ok(())
}

/// (σs, σa) in mm⁻¹ with σs + σa = 1/mfp and reduced albedo ρ′ for asymmetry g:
/// σs = ρ′σt/(1 − g(1 − ρ′)), σa = σt − σs (≥ 0 for ρ′ ∈ [0, 1], g ∈ (−1, 1)).
pub fn coefficients(rho_prime: f64, mfp: f64, g: f64) -> (f64, f64) {
    let sigma_t = 1.0 / mfp;
    let sigma_s = rho_prime * sigma_t / (1.0 - g * (1.0 - rho_prime));
    (sigma_s, (sigma_t - sigma_s).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficients_give_back_the_reduced_albedo_and_extinction() {
        for &(rho, mfp, g) in &[
            (0.0, 1.0, 0.0),
            (0.9, 0.5, 0.0),
            (0.7, 2.0, 0.8),
            (1.0, 1.0, -0.5),
        ] {
            let (s, a) = coefficients(rho, mfp, g);
            assert!((s + a - 1.0 / mfp).abs() < 1e-12);
            let reduced = s * (1.0 - g) / (s * (1.0 - g) + a);
            assert!((reduced - rho).abs() < 1e-12, "{rho} {g}: {reduced}");
        }
        // pbrt's g = 0 form: σs = ρσt.
        assert_eq!(coefficients(0.25, 0.5, 0.0), (0.5, 1.5));
    }

    fn curve() -> EffectiveAlbedo {
        // ρ_eff = ρ²·0.9 on five nodes: increasing, max 0.9.
        let rho = vec![0.0, 0.25, 0.5, 0.75, 1.0];
        let rho_eff = rho.iter().map(|r| 0.9 * r * r).collect();
        EffectiveAlbedo::new(rho, rho_eff).unwrap()
    }

    #[test]
    fn inversion_round_trips_and_clamps_above_the_maximum() {
        let c = curve();
        for rho in [0.1, 0.4, 0.6, 0.95] {
            let y = c.at(rho).unwrap();
            let back = c.invert(y, 0).unwrap();
            assert!((back.rho_prime - rho).abs() < 1e-9, "{rho}: {back:?}");
            assert!(!back.clamped);
        }
        let top = c.invert(0.95, 1).unwrap();
        assert_eq!(top.rho_prime, 1.0);
        assert!(top.clamped);
        assert_eq!(
            c.invert(1.2, 2),
            Err(ArtistError::Reflectance {
                channel: "b",
                value: 1.2
            })
        );
        assert!(c.invert(f64::NAN, 0).is_err());
    }

    #[test]
    fn bad_artist_parameters_name_the_channel_and_value() {
        let c = curve();
        let err = c.diffuse([0.5; 3], [1.0, 0.0, 1.0], [0.0; 3]).unwrap_err();
        assert_eq!(err.to_string(), "mfp[g] = 0 mm must be a finite number > 0");
        let err = c.diffuse([0.5; 3], [1.0; 3], [0.0, 0.0, 1.0]).unwrap_err();
        assert_eq!(err.to_string(), "g[b] = 1 is outside (-1, 1)");
        let err = c.diffuse([0.5, -0.1, 0.5], [1.0; 3], [0.0; 3]).unwrap_err();
        assert_eq!(err.to_string(), "reflectance[g] = -0.1 is outside [0, 1]");
    }
}
