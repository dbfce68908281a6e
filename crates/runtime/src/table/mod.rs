//! The angular table model: photon beam diffusion at any incidence, tabulated over
//! (ρ′, θ, r) with a General Wrapped Cauchy (GWC) profile over φ (Ferrier 2016, §3–4, §7.1).
//!
//! | axis | unit | default nodes (Ferrier §3.1) |
//! |---|---|---|
//! | ρ′ reduced albedo | – | 100: ρ_i = (1 − e^{−8i/99})/(1 − e^{−8}) |
//! | θ incidence before refraction | rad | 10: 0°, 10°, …, 90° |
//! | r exit distance | reduced mean free paths | 64: r₀ = 0, r_i = 0.0025·1.2^i |
//!
//! Axis values are data carried by every table (a scene bake keeps only some albedo rows), not
//! formulas in the reader. Per node the table stores, as f32:
//! - **E** = r ∫ S dφ = (2πα + β) r, the radial energy (Ferrier eq. 1);
//! - **E_β** = β r, the part of E carried by the wrapped-Cauchy lobe. The report stores β itself;
//!   β diverges at r₀ = 0 like the profile does (S ~ ln 1/r), while β r → 0 like E, so the r₀
//!   node holds its true limit and E and E_β interpolate with the same weights;
//! - **c**, the lobe concentration;
//! - the radial CDF ∫₀^r E dr′ of the Catmull-Rom spline through the stored E (for sampling r),
//!   whose last node is the effective albedo ρ_eff(ρ′, θ);
//! - optionally, for path tracing (algorithm 3), the CDF over θ of ρ_eff(ρ′, θ);
//! - for a two-lobe table (`bssrdf_zoo::table::Lobes::Two`, by default below η = 1.33), the profile's third and
//!   fourth harmonics times r, r·μ₃ and r·μ₄, beside (E, E_β, c) of the one lobe with its first
//!   two: lookups interpolate the four harmonics and rebuild two lobes from them
//!   ([`crate::gwc::TwoLobe::from_moments`], `lookup/two_lobe.rs`; docs/accuracy.md).
//!
//! Evaluation (algorithm 1) interpolates (E, E_β, c) with tensor-product Catmull-Rom weights in
//! (ρ′, θ, r), with slope 0 at θ = 90° where PBD's is and at the node before (80° on the
//! default grid) the slope of the quartic even about 90° through the last three nodes (see
//! [`Axes::new`]), forms
//! α = (E − E_β)/(2πr), β = E_β/r and returns α + β pdf_WC(φ; c). The crate's evaluation refines
//! the spline along ρ′ as it does along r, each refinement measured against PBD (docs/table.md):
//! - along ρ′, PBD's explicit factor ρ′² is taken out: the energies (E, E_β, the radial CDF, ρ_eff,
//!   the θ CDF) are ρ′² times the spline of their values over ρ′ᵢ², that is the rows weigh
//!   ωᵢ = wᵢ (ρ′/ρ′ᵢ)², and c is the ωᵢ-weighted mean Σ ωᵢcᵢ / Σ ωᵢ. A node at ρ′ = 0, whose
//!   E = 0 says nothing of E/ρ′², hands its weight to the polynomial through the next nodes up
//!   to four, below ρ′ = ½ (`albedo.rs`). The plain spline of E was 3.2 times PBD at ρ′ = 0.02
//!   and 22 % above it at 0.05; this one is within 0.02 % (mean) there at θ = 0. Below the
//!   first node above 0 and from ρ′ = 0.9999 up, evaluation splines E/(ρ′² f) instead, f the far
//!   field (1 + σ_tr r) e^{−σ_tr r} of diffusion, so that the far tails there stay within a few
//!   per cent of PBD down to 10⁻¹² of the profile's peak (`albedo.rs`, "The ends of the axis");
//! - along r, E is interpolated as exp(Catmull-Rom of ln E) where the segment's energy is
//!   positive, and the first interval [0, r₁] adds PBD's isotropic ln(1/r) growth,
//!   ρ′² C_E cos θ′/π · ln(r₁/r), to the profile at r₁.
//!
//! At a node ρ′ᵢ the weights along ρ′ are 1 there and 0 elsewhere: the refinement along ρ′
//! changes nothing of what the node stores.
//! Sampling (algorithm 2) draws r from the plain spline along r of E interpolated at (ρ′, θ)
//! (with the weights along ρ′ of evaluation), then φ
//! from the GWC profile at that r by Newton–bisection on its analytic CDF; `pdf` is exactly the
//! density of `sample`. Because evaluation refines the spline, S/pdf is ρ_eff only to within
//! a median 8e-5 and a 99th percentile 2e-3 (the first interval, ~1e-4 of the samples, differs
//! most): importance weights are nearly constant, and unbiased regardless.
//!
//! Units: all lookups are in reduced units (σ′t = 1); [`World`] converts (r scales with 1/σ′t,
//! S with σ′t²).
//!
//! The diffuse reflectance A = (1 − F_r(θ)) ρ_eff(ρ′, θ), the power leaving per unit power
//! arriving, and its inverse, the ρ′ that gives an artist's colour, are
//! [`TableRef::diffuse_reflectance`] and [`TableRef::rho_prime_for_reflectance`]
//! (`reflectance.rs`).
//!
//! Where it breaks down: at r = 0 the model returns its continuous limit from the first radius
//! interval (PBD itself diverges there); outside the stored axes a lookup is an error, never an
//! extrapolation; the GWC profile is monotone in |φ| (see [`crate::gwc`]).

mod albedo;
mod io;
mod lookup;
mod reflectance;
pub mod ridge;
pub use ridge::RidgeKind;
mod subset;

pub use crate::error::TableError;
use albedo::FarField;
pub use albedo::{AlbedoAxis, AlbedoPower, AlbedoWeights};
pub use io::FileTable;
pub use lookup::{
    reduced_to_mm, MediumRef, PathSample, PathSamplesMut, RadialSample, RadialSamplesMut, Sample,
    SamplesMut, World, TINY_ALBEDO,
};
pub use reflectance::ReflectanceError;
pub use subset::{check_rows, kept_rows, merge_runs, rows_for, RhoInterval, SubsetError};

use crate::catmull_rom::{End, Nodes};
use crate::fresnel::Moments;
use crate::gwc::Rebuild;
use std::f64::consts::FRAC_PI_2;

/// Number of f32 values per (ρ′, θ, r) node in the parameter array: E, E_β, c.
pub const PARAMS_PER_NODE: usize = 3;

/// How far from π/2 the last θ node may lie and still be grazing incidence, where the θ spline
/// has slope 0 (format-spec.md §10), radians: 8 f32 ulps there. π/2 rounded to f32, the node
/// the bake writes, is 4.4·10⁻⁸ above it.
pub const THETA_GRAZING_TOLERANCE: f64 = 1e-6;

/// The power of ρ′ the spline along ρ′ of a table measured from the walk with `walk` takes
/// out of its energies (`table::albedo`, format-spec.md §10): ρ′ for the total, whose single
/// scattering is linear in ρ′, ρ′² for multiple scattering, as for PBD.
pub fn walk_albedo_power(walk: crate::format::WalkSource) -> AlbedoPower {
    match walk.component {
        crate::format::WalkComponent::Total => AlbedoPower::Linear,
        crate::format::WalkComponent::Multiple => AlbedoPower::Square,
    }
}

/// The three axes of a table.
#[derive(Debug, Clone, PartialEq)]
pub struct Axes {
    rho: AlbedoAxis,
    theta: Nodes,
    r: Nodes,
    /// 1/f of the rows at the ends of the ρ′ axis, for evaluation there (`albedo.rs`).
    far: FarField,
}

impl Axes {
    /// Builds axes from node values (each validated: ≥ 2 finite, strictly increasing nodes).
    ///
    /// This is where every table (baked, read from a file, or a subset) gets its splines, so
    /// all of them interpolate alike: chord slopes at the ends of the ρ′ and r axes and at
    /// θ's first node, and an even end along θ when its last node is π/2 (within
    /// [`THETA_GRAZING_TOLERANCE`]): PBD depends on θ only through sin θ = η sin θ′, which is
    /// even about π/2, so the slope there is 0 and the one at the node before is the even
    /// quartic's through the last three nodes ([`End::Even`], format-spec.md §10).
    pub fn new(rho: Vec<f64>, theta: Vec<f64>, r: Vec<f64>) -> crate::Result<Self> {
        let end = match theta.last() {
            Some(&last) if (last - FRAC_PI_2).abs() <= THETA_GRAZING_TOLERANCE => End::Even,
            _ => End::Chord,
        };
        let (rho, r) = (AlbedoAxis::new(Nodes::new(rho)?), Nodes::new(r)?);
        Ok(Self {
            far: FarField::new(&rho, r.as_slice()),
            rho,
            theta: Nodes::new(theta)?.with_end(end),
            r,
        })
    }
    /// These axes with the spline along ρ′ taking out ρ′ to `power` (`table::albedo`):
    /// [`AlbedoPower::Linear`] for a walk table of the total ([`AngularTable::with_walk`]).
    pub fn with_albedo_power(self, power: AlbedoPower) -> Self {
        if power == self.rho.power() {
            return self;
        }
        let rho = AlbedoAxis::with_power(self.rho.nodes().clone(), power);
        Self {
            far: FarField::new(&rho, self.r.as_slice()),
            rho,
            ..self
        }
    }
    /// The power of ρ′ the spline along ρ′ takes out of the energies.
    pub fn albedo_power(&self) -> AlbedoPower {
        self.rho.power()
    }
    /// Reduced-albedo nodes.
    pub fn rho(&self) -> &Nodes {
        self.rho.nodes()
    }
    /// The reduced albedos the lookups take: the nodes' range with its ends' f32 rounding,
    /// within [0, 1] (`AlbedoAxis::domain`).
    pub fn rho_domain(&self) -> [f64; 2] {
        self.rho.domain()
    }
    /// Whether ρ′ lies in [`Axes::rho_domain`] (false for NaN).
    pub fn keeps_rho(&self, rho: f64) -> bool {
        self.rho.keeps(rho)
    }
    /// Incidence nodes, radians.
    pub fn theta(&self) -> &Nodes {
        &self.theta
    }
    /// Radius nodes, reduced mean free paths.
    pub fn r(&self) -> &Nodes {
        &self.r
    }
    /// (nρ, nθ, nr).
    pub fn dims(&self) -> (usize, usize, usize) {
        (
            self.rho().as_slice().len(),
            self.theta.as_slice().len(),
            self.r.as_slice().len(),
        )
    }
}

/// A baked angular table held in memory (see [`TableRef`] for lookups).
#[derive(Debug, Clone, PartialEq)]
pub struct AngularTable {
    eta: f64,
    boundary: crate::medium::Boundary,
    moments: Moments,
    axes: Axes,
    params: Vec<f32>,
    radial_cdf: Vec<f32>,
    theta_cdf: Option<Vec<f32>>,
    harmonics: Option<Vec<f32>>,
    /// How lookups rebuild the lobes from the harmonics.
    rebuild: Rebuild,
    /// [`harmonic_shares_of`] the params and harmonics, with them (derived, not stored in files).
    shares: Option<Vec<f32>>,
    /// The walk a table measured from the Monte Carlo walk was baked with (`None`: PBD).
    walk: Option<crate::format::WalkSource>,
    /// What the nodes hold less, the analytic ridge that lookups add back ([`ridge`]).
    ridge: RidgeKind,
}

/// A borrowed view of a table's arrays, as owned by [`AngularTable`] or mapped from a file.
#[derive(Debug, Clone, Copy)]
pub struct TableRef<'a> {
    eta: f64,
    /// The boundary's constants: C_E for the ln(1/r) growth in the first radius interval, and
    /// the ridge's ([`ridge`]).
    boundary: crate::medium::Boundary,
    axes: &'a Axes,
    params: &'a [f32],
    radial_cdf: &'a [f32],
    theta_cdf: Option<&'a [f32]>,
    /// the harmonics (rμ₃, rμ₄) per node, `[nρ][nθ][nr][2]`, for tables with a second lobe.
    harmonics: Option<&'a [f32]>,
    /// How lookups rebuild the lobes from the harmonics (format-spec.md §10 step 4).
    rebuild: Rebuild,
    /// [`harmonic_shares_of`] the params and harmonics, where the owner computed them (an
    /// [`AngularTable`], an opened `embed::Library`): lookups then blend them as they are
    /// instead of dividing row by row. `None` in views of raw arrays ([`TableRef::new`]).
    shares: Option<&'a [f32]>,
    /// What the nodes hold less, the analytic ridge that lookups add back ([`ridge`]).
    ridge: RidgeKind,
}

/// Values per node of [`harmonic_shares_of`] that lookups blend.
pub(crate) const SHARES_PER_NODE: usize = 5;

/// Per node of a two-lobe table, what its lookups blend of the harmonics
/// (`TableRef::harmonic_shares`): the shares of E of μ₁, μ₂ (the one lobe's E_β·c and E_β·c²)
/// and of rμ₃, rμ₄, each times 1/E where the node holds energy (E > 0) and 0 elsewhere, then
/// 1 or 0 for whether it does. In f32 with the lookups' own operations, so that blending these
/// gives bit for bit what dividing row by row gives (tested in `lookup/tests.rs`). After these
/// [`SHARES_PER_NODE`] values of every node, one more per node: the largest [`node_sharpness`]
/// of it and the next three along r (the window a lookup from it reads; 0 where none holds
/// energy), then one more: its own, which lookups near a radius node ramp in by the node's
/// weight (`lookup::two_lobe`). `n_r`: the radii per row.
pub(crate) fn harmonic_shares_of(
    params: &[f32],
    harmonics: &[f32],
    n_r: usize,
    rebuild: Rebuild,
) -> Vec<f32> {
    let cells = || {
        params
            .chunks_exact(PARAMS_PER_NODE)
            .zip(harmonics.chunks_exact(HARMONICS_PER_NODE))
    };
    let sharpness: Vec<f32> = cells()
        .map(|(p, h)| {
            if p[0] > 0.0 {
                node_sharpness([p[0], p[1], p[2], h[0], h[1]], rebuild)
            } else {
                0.0
            }
        })
        .collect();
    let shares = cells().flat_map(|(p, h)| {
        let [s1, s2, s3, s4] = node_shares([p[0], p[1], p[2], h[0], h[1]]);
        [s1, s2, s3, s4, if p[0] > 0.0 { 1.0 } else { 0.0 }]
    });
    // Each node's window of four along r (within its row), for the lookups away from nodes
    let n_r = n_r.max(1);
    let window_max: Vec<f32> = (0..sharpness.len())
        .map(|node| {
            let end = (node / n_r + 1) * n_r;
            sharpness[node..(node + 4).min(end)]
                .iter()
                .fold(0.0f32, |m, &x| m.max(x))
        })
        .collect();
    shares.chain(window_max).chain(sharpness).collect()
}

/// How far (relative to E) a node's stored r·μ₃ and r·μ₄ must depart from its one lobe's,
/// E_β·c³ and E_β·c⁴, before [`node_is_signed`] calls it a signed pair. A reader without
/// signed pairs reads such a node as its one lobe, whose third and fourth harmonics then differ
/// by cosines of amplitude 2Δμ/E times the mean, ≤ 0.02 % of it below this; the higher ones,
/// which the pair's two roots set, can differ more (format-spec.md §10, "Signed nodes").
/// Rounding the one lobe's own harmonics to f32 departs by about 10⁻⁷ E, where Prony's roots
/// are noise and may give any sign.
pub const SIGNED_DEPARTURE: f64 = 1e-4;

/// Whether a node of a two-lobe table with stored values (E, E_β, c, rμ₃, rμ₄) is a signed
/// pair, what required feature bit 3, `signed-lobes`, declares: its harmonics depart from its
/// one lobe's by more than [`SIGNED_DEPARTURE`]·E, and format-spec.md §10 step 4 on them by the
/// table's `rebuild` gives a negative broader lobe.
pub fn node_is_signed(cell: [f32; 5], rebuild: Rebuild) -> bool {
    let [e, e_beta, c, h0, h1] = cell.map(f64::from);
    let departure = (h0 - e_beta * c * c * c)
        .abs()
        .max((h1 - e_beta * c * c * c * c).abs());
    e > 0.0
        && departure > SIGNED_DEPARTURE * e
        && crate::gwc::harmonics_are_signed([e_beta * c, e_beta * c * c, h0, h1], e, rebuild)
}

/// The shares of E of the harmonics of a node of a two-lobe table with stored values
/// (E, E_β, c, rμ₃, rμ₄), (E_β·c, E_β·c², rμ₃, rμ₄)/E, 0 where E ≤ 0: what lookups blend, in
/// f32 with their own operations (`lookup::two_lobe`).
pub fn node_shares(cell: [f32; 5]) -> [f32; 4] {
    let [e, e_beta, c, h0, h1] = cell;
    let inv = if e > 0.0 { 1.0 / e } else { 0.0 };
    let share1 = e_beta * c * inv;
    [share1, share1 * c, h0 * inv, h1 * inv]
}

/// The concentration of the sharper lobe a node of a two-lobe table rebuilds into
/// ([`crate::gwc::sharp_concentration`] of its [`node_shares`], which at the node are what a
/// lookup rebuilds from, by the table's `rebuild`), rounded to f32 and raised by one f32 step.
/// Lookups rebuild no lobe sharper than the sharpest node they blend: where the harmonics they
/// blend are nearly those of one lobe, Prony's second root is ill-determined, and a sharp lobe
/// of little mass put a spike at φ = 0: at η = 1.01, ρ′ = 0.5, θ = 75°, the largest error of 50,000 points drawn by
/// the table's sampler was 14.9 % without the cap, 4.8 % with it (`examples/worst_points`).
/// The step up keeps a node's own root from being clamped by rounding, which would refuse a
/// signed pair there and read one lobe (it did at 10 % of the signed nodes of the default
/// bakes at η = 1.05 and 1.2, when the cap came from the f64 harmonics rounded to nearest).
pub fn node_sharpness(cell: [f32; 5], rebuild: Rebuild) -> f32 {
    let shares = node_shares(cell).map(f64::from);
    next_f32_up(crate::gwc::sharp_concentration(shares, rebuild) as f32)
}

/// The least f32 above the finite `x` (`f32::next_up`, which is newer than the crate's minimum
/// Rust).
fn next_f32_up(x: f32) -> f32 {
    if x == 0.0 {
        f32::from_bits(1)
    } else if x > 0.0 {
        f32::from_bits(x.to_bits() + 1)
    } else {
        f32::from_bits(x.to_bits() - 1)
    }
}

/// Number of f32 values per node of the second lobe: E_β₂, c₂.
pub const HARMONICS_PER_NODE: usize = 2;

impl<'a> TableRef<'a> {
    /// Checks the array lengths against the axes and that every value is finite.
    pub fn new(
        eta: f64,
        moments: Moments,
        axes: &'a Axes,
        params: &'a [f32],
        radial_cdf: &'a [f32],
        theta_cdf: Option<&'a [f32]>,
    ) -> Result<Self, TableError> {
        let (nrho, ntheta, nr) = axes.dims();
        let cells = nrho * ntheta * nr;
        let check = |name, data: &[f32], expected| {
            if data.len() != expected {
                return Err(TableError::Length {
                    name,
                    len: data.len(),
                    expected,
                    nrho,
                    ntheta,
                    nr,
                });
            }
            match data.iter().position(|v| !v.is_finite()) {
                Some(index) => Err(TableError::NotFinite {
                    name,
                    index,
                    value: data[index],
                }),
                None => Ok(()),
            }
        };
        check("params", params, cells * PARAMS_PER_NODE)?;
        check("radial_cdf", radial_cdf, cells)?;
        if let Some(t) = theta_cdf {
            check("theta_cdf", t, nrho * ntheta)?;
        }
        let boundary = crate::medium::Boundary::new(eta, moments).map_err(|_| TableError::Eta {
            value: eta,
            min: crate::medium::ETA_MIN,
            max: crate::medium::ETA_MAX,
        })?;
        Ok(Self {
            eta,
            boundary,
            axes,
            params,
            radial_cdf,
            theta_cdf,
            harmonics: None,
            rebuild: Rebuild::default(),
            shares: None,
            ridge: RidgeKind::None,
        })
    }

    /// This view with a second lobe, the harmonics (rμ₃, rμ₄) per node, `[nρ][nθ][nr][2]`: its length
    /// checked against the axes and every value finite. Its lobes are rebuilt as this crate
    /// bakes them ([`Rebuild::MergedRoots`]; [`TableRef::with_rebuild`] for another rule).
    pub fn with_harmonics(self, harmonics: &'a [f32]) -> Result<Self, TableError> {
        let (nrho, ntheta, nr) = self.axes.dims();
        let expected = nrho * ntheta * nr * HARMONICS_PER_NODE;
        if harmonics.len() != expected {
            return Err(TableError::Length {
                name: "harmonics",
                len: harmonics.len(),
                expected,
                nrho,
                ntheta,
                nr,
            });
        }
        if let Some(index) = harmonics.iter().position(|v| !v.is_finite()) {
            return Err(TableError::NotFinite {
                name: "harmonics",
                index,
                value: harmonics[index],
            });
        }
        Ok(Self {
            harmonics: Some(harmonics),
            shares: None,
            ..self
        })
    }

    /// This view with its lobes rebuilt by `rebuild` (a file's rule: required feature bit 4).
    pub fn with_rebuild(self, rebuild: Rebuild) -> Self {
        Self {
            rebuild,
            shares: None,
            ..self
        }
    }

    /// How lookups rebuild the lobes of a two-lobe table from its harmonics.
    pub fn rebuild(&self) -> Rebuild {
        self.rebuild
    }

    /// This view with the analytic ridge added back to what its nodes hold, or not (a file's
    /// table record, format-spec.md §10 "The ridge"; [`ridge`]).
    pub fn with_ridge(self, ridge: RidgeKind) -> Self {
        Self { ridge, ..self }
    }

    /// What the nodes hold less, the analytic ridge that lookups add back.
    pub fn ridge(&self) -> RidgeKind {
        self.ridge
    }

    /// A view of arrays that [`TableRef::new`] has already accepted with these axes, with
    /// `boundary = Boundary::new(eta, moments)?` as `new` computes it: O(1), no checks and no
    /// Fresnel integration, for handles that rebuild their view on every lookup
    /// (`crate::embed`). Arrays of other lengths make lookups panic; they are never unsound.
    pub(crate) fn prevalidated(
        eta: f64,
        boundary: crate::medium::Boundary,
        axes: &'a Axes,
        params: &'a [f32],
        radial_cdf: &'a [f32],
        theta_cdf: Option<&'a [f32]>,
    ) -> Self {
        Self {
            eta,
            boundary,
            axes,
            params,
            radial_cdf,
            theta_cdf,
            harmonics: None,
            rebuild: Rebuild::default(),
            shares: None,
            ridge: RidgeKind::None,
        }
    }

    /// [`TableRef::prevalidated`]'s view with a second lobe [`TableRef::with_harmonics`]
    /// has already accepted with these axes, rebuilt by `rebuild`, and its
    /// [`harmonic_shares_of`] by that rule if computed.
    pub(crate) fn prevalidated_harmonics(
        self,
        harmonics: Option<&'a [f32]>,
        rebuild: Rebuild,
        shares: Option<&'a [f32]>,
    ) -> Self {
        Self {
            harmonics,
            rebuild,
            shares: harmonics.and(shares),
            ..self
        }
    }

    /// Relative index of refraction the table was baked for.
    pub fn eta(&self) -> f64 {
        self.eta
    }
    /// The axes.
    pub fn axes(&self) -> &'a Axes {
        self.axes
    }
    /// Whether the θ-sampling table (path tracing) is present.
    pub fn has_theta_sampling(&self) -> bool {
        self.theta_cdf.is_some()
    }
    /// The second lobe (rμ₃, rμ₄) per node, if the table has one.
    pub fn harmonics(&self) -> Option<&'a [f32]> {
        self.harmonics
    }
}

impl AngularTable {
    /// Assembles a table from its parts (validated as in [`TableRef::new`]).
    pub fn from_parts(
        eta: f64,
        moments: Moments,
        axes: Axes,
        params: Vec<f32>,
        radial_cdf: Vec<f32>,
        theta_cdf: Option<Vec<f32>>,
    ) -> Result<Self, TableError> {
        let boundary = TableRef::new(
            eta,
            moments,
            &axes,
            &params,
            &radial_cdf,
            theta_cdf.as_deref(),
        )?
        .boundary;
        Ok(Self {
            eta,
            boundary,
            moments,
            axes,
            params,
            radial_cdf,
            theta_cdf,
            harmonics: None,
            rebuild: Rebuild::default(),
            shares: None,
            walk: None,
            ridge: RidgeKind::None,
        })
    }

    /// This table marked as measured from the Monte Carlo walk with `walk` (a walk-angular
    /// table in a file; format-spec.md §9.1). Lookups are unchanged but for a table of the total,
    /// whose spline along ρ′ takes out ρ′ instead of ρ′² ([`walk_albedo_power`]).
    pub fn with_walk(mut self, walk: crate::format::WalkSource) -> Self {
        self.walk = Some(walk);
        self.axes = self.axes.with_albedo_power(walk_albedo_power(walk));
        self
    }

    /// The walk the table was measured with, if it was (`None`: photon beam diffusion).
    pub fn walk(&self) -> Option<crate::format::WalkSource> {
        self.walk
    }

    /// This table with the θ-sampling CDF `theta_cdf`, `[nρ][nθ]` (validated as in
    /// [`TableRef::new`]).
    pub fn with_theta_cdf(self, theta_cdf: Vec<f32>) -> Result<Self, TableError> {
        TableRef::new(
            self.eta,
            self.moments,
            &self.axes,
            &self.params,
            &self.radial_cdf,
            Some(&theta_cdf),
        )?;
        Ok(Self {
            theta_cdf: Some(theta_cdf),
            ..self
        })
    }

    /// This table with the analytic ridge added back to what its nodes hold, or not
    /// ([`TableRef::with_ridge`]).
    pub fn with_ridge(mut self, ridge: RidgeKind) -> Self {
        self.ridge = ridge;
        self
    }

    /// What the nodes hold less, the analytic ridge that lookups add back.
    pub fn ridge(&self) -> RidgeKind {
        self.ridge
    }

    /// Whether this is a table of the walk at exactly `eta` and `g`: the values a file stores
    /// are the ones the bake was given, so a medium of that (η, g) compares equal.
    pub fn is_walk_at(&self, eta: f64, g: f64) -> bool {
        self.walk.is_some_and(|w| w.g == g) && self.eta == eta
    }

    /// This table with a second lobe (validated as in [`TableRef::with_harmonics`]), rebuilt as
    /// this crate bakes ([`Rebuild::MergedRoots`]).
    pub fn with_harmonics(self, harmonics: Vec<f32>) -> Result<Self, TableError> {
        self.with_harmonics_by(harmonics, Rebuild::default())
    }

    /// This table with a second lobe (validated as in [`TableRef::with_harmonics`]), rebuilt by
    /// `rebuild` (a file's rule: required feature bit 4).
    pub fn with_harmonics_by(
        self,
        harmonics: Vec<f32>,
        rebuild: Rebuild,
    ) -> Result<Self, TableError> {
        self.view().with_harmonics(&harmonics)?;
        Ok(Self {
            shares: Some(harmonic_shares_of(
                &self.params,
                &harmonics,
                self.axes.dims().2,
                rebuild,
            )),
            harmonics: Some(harmonics),
            rebuild,
            ..self
        })
    }

    /// How lookups rebuild the lobes of a two-lobe table from its harmonics.
    pub fn rebuild(&self) -> Rebuild {
        self.rebuild
    }

    /// A lookup view.
    pub fn view(&self) -> TableRef<'_> {
        TableRef {
            eta: self.eta,
            boundary: self.boundary,
            axes: &self.axes,
            params: &self.params,
            radial_cdf: &self.radial_cdf,
            theta_cdf: self.theta_cdf.as_deref(),
            harmonics: self.harmonics.as_deref(),
            rebuild: self.rebuild,
            shares: self.shares.as_deref(),
            ridge: self.ridge,
        }
    }
    /// η.
    pub fn eta(&self) -> f64 {
        self.eta
    }
    /// Fresnel moments used at bake.
    pub fn moments(&self) -> Moments {
        self.moments
    }
    /// The axes.
    pub fn axes(&self) -> &Axes {
        &self.axes
    }
    /// (E, E_β, c) per node, `[nρ][nθ][nr][3]`.
    pub fn params(&self) -> &[f32] {
        &self.params
    }
    /// Radial CDF, `[nρ][nθ][nr]`.
    pub fn radial_cdf(&self) -> &[f32] {
        &self.radial_cdf
    }
    /// θ-sampling CDF over θ of ρ_eff, `[nρ][nθ]`, if kept.
    pub fn theta_cdf(&self) -> Option<&[f32]> {
        self.theta_cdf.as_deref()
    }
    /// (rμ₃, rμ₄) per node of the second lobe, `[nρ][nθ][nr][2]`, if the table has one.
    pub fn harmonics(&self) -> Option<&[f32]> {
        self.harmonics.as_deref()
    }
    /// Size of the arrays in bytes.
    pub fn size_bytes(&self) -> usize {
        4 * (self.params.len()
            + self.radial_cdf.len()
            + self.theta_cdf.as_ref().map_or(0, Vec::len)
            + self.harmonics.as_ref().map_or(0, Vec::len))
    }
}
