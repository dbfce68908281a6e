//! The artist's parameters: a diffuse reflectance and a mean free path per channel, turned into
//! coefficients through the table's diffuse reflectance at normal incidence, as pbrt's
//! `SubsurfaceFromDiffuse` turns them through its ρ_eff (pbrt-v3 `core/bssrdf.cpp`, pbrt-v4
//! `BSSRDFTable` and `SubsurfaceFromDiffuse`).
//!
//! | parameter | unit | valid range | meaning |
//! |---|---|---|---|
//! | reflectance | – | [0, 1] per channel | the diffuse colour: the diffuse reflectance A wanted at normal incidence |
//! | mfp | mm | [1e-12, 1e9] per channel ([`MFP_MIN`], [`MFP_MAX`]: σt = 1/mfp in the media's [1e-9, 1e12] mm⁻¹) | the unreduced mean free path 1/σt (pbrt's convention) |
//! | g | – | (−1, 1) | Henyey–Greenstein asymmetry (default 0) |
//!
//! 1. ρ′ from the reflectance: the ρ′ whose diffuse reflectance at θ = 0,
//!    A(ρ′, 0) = (1 − F_r(0; η)) ρ_eff(ρ′, 0), is the reflectance, found by the runtime's one
//!    inversion, [`TableRef::rho_prime_for_reflectance`] (`table::reflectance` defines A), on
//!    the table's own curve. A is what a renderer shows for the material lit from above: the
//!    power leaving after multiple scattering per unit power arriving, the entry Fresnel
//!    transmittance included. pbrt inverts ρ_eff alone (per unit power entering), so what it
//!    renders is 1 − F_r(0) times the colour asked for: 0.980 at η = 1.33, 0.960 at 1.5, 0.816 at
//!    2.5. A is **multiple scattering only** (PBD has no single-scattering term): its largest
//!    value, at ρ′ = 1, is 0.9312 at η = 1.33 on the default grid (ρ_eff(1, 0) = 0.9503 times
//!    1 − F_r = 0.97994; PBD's own ρ_eff is 0.9613, of which the table misses the tail beyond
//!    its last radius, 243 mean free paths, where a non-absorbing profile decays only slowly),
//!    while pbrt's ρ_eff, which adds single scattering, exceeds 1.
//!
//!    A reflectance in [0, 1] above that largest value cannot be reached: it is clamped to the
//!    last albedo row (ρ′ = 1) and reported ([`Inverted::clamped`]) so that the caller warns
//!    (pbrt clamps silently). This is a deliberate choice for materials and scenes, built on the
//!    same inversion (its out-of-range error, taken as "clamp" only above the range): an artist's
//!    white, 1.0, is a common value no multiple scattering reaches, and a bake of many materials
//!    should not stop at it. The strict inverse, which refuses instead, is the runtime's
//!    (`bssrdf invert`, the C library's `bssrdf_library_invert_albedo`). A reflectance outside
//!    [0, 1] is an error.
//! 2. σt = 1/mfp, and σs solves σs(1 − g)/(σs(1 − g) + σa) = ρ′ with σs + σa = σt:
//!    σs = ρ′σt/(1 − g(1 − ρ′)), σa = σt − σs. With g = 0 this is pbrt's σs = ρσt, σa = (1 − ρ)σt.
//!
//! The result depends on the grid the curve comes from (the coarse grid's ρ_eff differs from
//! the default grid's by ~1e-4), so a bake inverts with the curve of the table it bakes.

use crate::error::Number;
use crate::fresnel::Moments;
use crate::medium::{SIGMA_T_MAX, SIGMA_T_MIN};
use crate::table::{
    bake_rows_lobes, AngularTable, Axes, Grid, Lobes, ReflectanceError, SubsetError, TableRef,
};

/// The diffuse reflectance A(ρ′, θ = 0) of a table over its albedo rows: the table's every
/// albedo row at its first two incidence nodes (θ = 0 and the next, which a θ axis needs).
#[derive(Debug, Clone, PartialEq)]
pub struct ReflectanceCurve {
    table: AngularTable,
}

/// Why artist's parameters could not be turned into coefficients.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ArtistError {
    /// A reflectance is NaN or outside [0, 1].
    #[error("reflectance[{channel}] = {value} is outside [0, 1]")]
    Reflectance { channel: &'static str, value: f64 },
    /// A mean free path outside [1e-12, 1e9] mm (σt = 1/mfp outside the media's [1e-9, 1e12]
    /// mm⁻¹), or NaN.
    #[error(
        "mfp[{channel}] = {} mm is outside [{}, {}] mm (sigma_t = 1/mfp within [{}, {}] /mm)",
        Number(*value),
        Number(MFP_MIN),
        Number(MFP_MAX),
        Number(SIGMA_T_MIN),
        Number(SIGMA_T_MAX)
    )]
    Mfp { channel: &'static str, value: f64 },
    /// g is NaN or outside (−1, 1).
    #[error("g[{channel}] = {value} is outside (-1, 1)")]
    Asymmetry { channel: &'static str, value: f64 },
    /// The table has no θ = 0 node.
    #[error("the table cannot invert reflectance: {0}")]
    Curve(&'static str),
    /// The inversion refused a reflectance in [0, 1] other than by being above the range (a
    /// table whose first albedo row is above 0).
    #[error("reflectance[{channel}]: {source}")]
    Invert {
        channel: &'static str,
        source: ReflectanceError,
    },
    /// Baking the curve failed.
    #[error(transparent)]
    Bake(#[from] SubsetError),
    /// The table's first two θ columns do not make a table (its arrays do not fit its axes).
    #[error("the table cannot invert reflectance: {0}")]
    Table(#[from] crate::Error),
}

/// ρ′ for one reflectance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inverted {
    /// Reduced albedo ρ′ ∈ [0, 1].
    pub rho_prime: f64,
    /// Whether the reflectance was above the largest diffuse reflectance and ρ′ was clamped to
    /// the last albedo row.
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

impl ReflectanceCurve {
    /// The curve of `table`, whose θ axis must start at 0 (normal incidence): its θ = 0 column
    /// and the next.
    pub fn from_table(table: &AngularTable) -> Result<Self, ArtistError> {
        let axes = table.axes();
        let (n_rho, n_theta, n_r) = axes.dims();
        let theta = axes.theta().as_slice();
        if theta.first() != Some(&0.0) {
            return Err(ArtistError::Curve("its theta axis does not start at 0"));
        }
        // The first two θ columns of every albedo row, `per` values per node.
        let columns = |values: &[f32], per: usize| -> Vec<f32> {
            let (row, kept) = (n_theta * n_r * per, 2 * n_r * per);
            values
                .chunks_exact(row)
                .flat_map(|r| &r[..kept])
                .copied()
                .collect()
        };
        let narrow = Axes::new(
            axes.rho().as_slice().to_vec(),
            theta[..2].to_vec(),
            axes.r().as_slice().to_vec(),
        )?;
        debug_assert_eq!(narrow.dims(), (n_rho, 2, n_r));
        let mut curve = AngularTable::from_parts(
            table.eta(),
            table.moments(),
            narrow,
            columns(table.params(), crate::table::PARAMS_PER_NODE),
            columns(table.radial_cdf(), 1),
            None,
        )
        .map_err(crate::Error::from)?
        // (no ridge at θ = 0, where the curve looks up, but the nodes are the table's)
        .with_ridge(table.ridge());
        if let Some(harmonics) = table.harmonics() {
            curve = curve
                .with_harmonics_by(
                    columns(harmonics, crate::table::HARMONICS_PER_NODE),
                    table.rebuild(),
                )
                .map_err(crate::Error::from)?;
        }
        Ok(Self { table: curve })
    }

    /// Bakes only what the curve needs: every albedo row of `grid` at its first two incidence
    /// nodes, with `lobes` (rows are independent, so the θ = 0 values equal those of the full
    /// bake with these lobes bit for bit).
    pub fn bake(
        eta: f64,
        moments: Moments,
        grid: &Grid,
        lobes: Lobes,
    ) -> Result<Self, ArtistError> {
        let small = Grid {
            rho: grid.rho.clone(),
            theta: grid.theta.iter().take(2).copied().collect(),
            r: grid.r.clone(),
        };
        let rows = 0..small.rho.len();
        let (table, _) = bake_rows_lobes(eta, moments, &small, rows, false, lobes, &|_| {})?;
        Self::from_table(&table)
    }

    /// The curve's table (every albedo row, θ = 0 and the next node).
    pub fn view(&self) -> TableRef<'_> {
        self.table.view()
    }

    /// η of the table.
    pub fn eta(&self) -> f64 {
        self.table.eta()
    }

    /// The largest diffuse reflectance the table reaches at normal incidence (at its last albedo
    /// row, normally ρ′ = 1).
    pub fn max(&self) -> f64 {
        self.view()
            .reflectance_range(0.0)
            .map_or(0.0, |[_, max]| max)
    }

    /// A(ρ′, 0) at reduced albedo `rho` (interpolated as the table's), `None` outside the axis.
    pub fn at(&self, rho: f64) -> Option<f64> {
        self.view().diffuse_reflectance(rho, 0.0)
    }

    /// ρ′ whose diffuse reflectance at normal incidence is `reflectance` ∈ [0, 1]; above the
    /// largest, the last albedo row, clamped (module docs).
    pub fn invert(&self, reflectance: f64, channel: usize) -> Result<Inverted, ArtistError> {
        let name = CHANNELS.get(channel).copied().unwrap_or("?");
        if !(0.0..=1.0).contains(&reflectance) {
            return Err(ArtistError::Reflectance {
                channel: name,
                value: reflectance,
            });
        }
        let view = self.view();
        match view.rho_prime_for_reflectance(reflectance, 0.0) {
            Ok(rho_prime) => Ok(Inverted {
                rho_prime,
                clamped: false,
            }),
            Err(ReflectanceError::OutOfRange { max, rho_max, .. }) if reflectance > max => {
                Ok(Inverted {
                    rho_prime: rho_max,
                    clamped: true,
                })
            }
            Err(source) => Err(ArtistError::Invert {
                channel: name,
                source,
            }),
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

    /// A made-up curve for tests that bake nothing: ρ_eff(ρ′ᵢ, θ) = `rho_eff[i]` at the nodes
    /// `rho` (strictly increasing) at θ = 0 and 0.1, on four radii, at η.
    #[cfg(test)]
    pub(crate) fn synthetic(eta: f64, rho: Vec<f64>, rho_eff: Vec<f64>) -> Self {
        let n_r = 4;
        let axes = Axes::new(rho, vec![0.0, 0.1], vec![0.0, 1.0, 2.0, 3.0]).unwrap();
        let (n_rho, n_theta, _) = axes.dims();
        let mut cdf = Vec::with_capacity(n_rho * n_theta * n_r);
        for &total in &rho_eff {
            for _ in 0..n_theta {
                cdf.extend((0..n_r).map(|k| (total * k as f64 / (n_r - 1) as f64) as f32));
            }
        }
        let params = vec![0.0; n_rho * n_theta * n_r * crate::table::PARAMS_PER_NODE];
        let table = AngularTable::from_parts(eta, Moments::Exact, axes, params, cdf, None).unwrap();
        Self { table }
    }
}

/// Shortest mean free path, mm: σt = 1/mfp at most [`SIGMA_T_MAX`] (1/[`SIGMA_T_MAX`]).
pub const MFP_MIN: f64 = 1e-12;
/// Longest mean free path, mm: σt = 1/mfp at least [`SIGMA_T_MIN`] (1/[`SIGMA_T_MIN`]).
pub const MFP_MAX: f64 = 1e9;

/// Checks the artist's parameters without a curve: reflectance in [0, 1], mfp in
/// [[`MFP_MIN`], [`MFP_MAX`]] mm, g in (−1, 1), per channel; errors name the channel and the
/// value.
pub fn check(reflectance: [f64; 3], mfp: [f64; 3], g: [f64; 3]) -> Result<(), ArtistError> {
    for (c, channel) in CHANNELS.into_iter().enumerate() {
        if !(0.0..=1.0).contains(&reflectance[c]) {
            return Err(ArtistError::Reflectance {
                channel,
                value: reflectance[c],
            });
        }
        if !(MFP_MIN..=MFP_MAX).contains(&mfp[c]) {
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

    /// ρ_eff = 0.9ρ′² on five nodes at η = 1.33: A = 0.9·T₀·ρ′², max 0.9·T₀.
    fn curve() -> ReflectanceCurve {
        let rho = vec![0.0, 0.25, 0.5, 0.75, 1.0];
        let rho_eff = rho.iter().map(|r| 0.9 * r * r).collect();
        ReflectanceCurve::synthetic(1.33, rho, rho_eff)
    }

    /// 1 − F_r at normal incidence, η = 1.33.
    const T0: f64 = 1.0 - (0.33 / 2.33) * (0.33 / 2.33);

    #[test]
    fn inversion_includes_the_entry_fresnel_round_trips_and_clamps_above_the_maximum() {
        let c = curve();
        assert!((c.max() - 0.9 * T0).abs() < 1e-7, "{}", c.max());
        for rho in [0.1, 0.4, 0.6, 0.95] {
            let y = c.at(rho).unwrap();
            assert!((y - 0.9 * T0 * rho * rho).abs() < 1e-7 * y);
            let back = c.invert(y, 0).unwrap();
            assert!((back.rho_prime - rho).abs() < 1e-6, "{rho}: {back:?}");
            assert!(!back.clamped);
        }
        // Between T₀·0.9 and 1: clamped to the last row, reported.
        let top = c.invert(0.9, 1).unwrap();
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
        assert!(c.invert(-0.1, 0).is_err());
    }

    #[test]
    fn a_curve_whose_first_row_is_above_zero_refuses_what_it_cannot_reach() {
        let rho = vec![0.5, 0.75, 1.0];
        let c = ReflectanceCurve::synthetic(1.33, rho, vec![0.2, 0.5, 0.9]);
        let err = c.invert(0.1, 1).unwrap_err();
        assert!(
            matches!(err, ArtistError::Invert { channel: "g", .. }),
            "{err:?}"
        );
        assert!(err
            .to_string()
            .starts_with("reflectance[g]: reflectance 0.1 is outside [0.19"));
    }

    #[test]
    fn bad_artist_parameters_name_the_channel_and_value() {
        let c = curve();
        let err = c.diffuse([0.5; 3], [1.0, 0.0, 1.0], [0.0; 3]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "mfp[g] = 0 mm is outside [1e-12, 1e9] mm (sigma_t = 1/mfp within [1e-9, 1e12] /mm)"
        );
        // A value whose σt = 1/mfp would overflow names mfp, not the σs it would give
        let err = c
            .diffuse([0.5; 3], [1e-320, 1.0, 1.0], [0.0; 3])
            .unwrap_err();
        assert!(
            err.to_string().starts_with("mfp[r] = 1e-320 mm is outside"),
            "{err}"
        );
        // The ends are the media's σt range
        assert_eq!(MFP_MIN, 1.0 / SIGMA_T_MAX);
        assert!((MFP_MAX * SIGMA_T_MIN - 1.0).abs() < 1e-15);
        let err = c.diffuse([0.5; 3], [1.0; 3], [0.0, 0.0, 1.0]).unwrap_err();
        assert_eq!(err.to_string(), "g[b] = 1 is outside (-1, 1)");
        let err = c.diffuse([0.5, -0.1, 0.5], [1.0; 3], [0.0; 3]).unwrap_err();
        assert_eq!(err.to_string(), "reflectance[g] = -0.1 is outside [0, 1]");
    }
}
