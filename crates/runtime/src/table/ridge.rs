//! The analytic ridge of grazing incidence near index matching (format-spec.md §10, "The
//! ridge").
//!
//! When the refracted beam runs just under the surface (cos θ′ small: η near 1 at grazing θ,
//! or η < 1 near the critical angle), the sources of photon beam diffusion lie at depth
//! t·cos θ′ under the exit points they pass, and their near field puts a forward ridge on
//! φ = 0 whose width is about cos θ′. Its width changes faster over θ than the θ nodes can
//! follow: blending two nodes' profiles gives a mixture of two ridges, not one of the width
//! between. A table that says so (its record's `ridge`) stores at its nodes S less the ridge
//! R below, and every lookup adds R back at its own θ, with its own width.
//!
//! In reduced units (σ′t = 1), with s = sin θ′, c = cos θ′, the table's C_E and the diffusion
//! coefficient of ρ′, σtr = √(3(1 − ρ′)/(2 − ρ′)):
//!
//! ```text
//! R(r, φ; ρ′, θ) = w(c) · m(r) · pdf_WC(φ; κ),   κ = exp(−max(c, 10⁻⁵)),
//! m(r) = ρ′² C_E s · e^{−r(s + k)} (1 − e^{−2rs}) / (2r),   k = σtr c/s   (m(0) = ρ′² C_E s²),
//! w(c) = 1 for c ≤ 0.1, 0 for c ≥ 0.3, x²(3 − 2x) between, x = (0.3 − c)/0.2,
//! ```
//!
//! and R = 0 where no light enters and beyond the table's last radius r_max, as every lookup
//! is. m is the flux term of the beam's sources, attenuated along the beam as e^{−t}, each
//! seen from the exit point above it at t = r/s: a line density ρ′² C_E (1 − e^{−2rs}) e^{−rs}/2
//! along φ = 0 in the limit c → 0 (`Pbd::surface_ridge`), spread over φ as a wrapped Cauchy
//! lobe of width c, and attenuated by diffusion over the source's depth h = r c/s as e^{−σtr h}
//! (which keeps it nearer S off the ridge at low albedo, where S decays as e^{−σtr r}; it can
//! still reach past S there, far out, and a bake then keeps a floor of S at the node). Over the
//! plane it carries w ρ′² C_E (s/2)·G(r_max), G(r) = ∫₀^r (e^{−ax} − e^{−bx}) dx with a = s + k,
//! b = 3s + k (ρ′² C_E/3 for k = 0, r_max = ∞). The radial density of R, r·m(r) over its
//! energy, is (e^{−ar} − e^{−br})/G(r_max), inverted by a safeguarded Newton iteration.
//!
//! That is the ridge of a table whose record says `ridge` = 1 ([`RidgeKind::Flux`]). A record
//! with `ridge` = 2 ([`RidgeKind::FluxAndFluence`]) adds the fluence term's part L of the same
//! near field. Each beam point's fluence C_φ e^{−σtr d}/(4πD d) integrates along the beam to
//! about −ln(φ² + c²) times ρ′² C_φ (1 − e^{−2t}) e^{−t}/(4πD) near φ = 0: a logarithmic cusp of width c
//! that no lobe over the nodes follows either (the nodes' fit missed PBD by up to 6 % at
//! φ = 0.02–0.2 without it, θ = 89°, η = 1). Since −ln(φ² + c²) = ∫_c^∞ 2w/(φ² + w²) dw up to
//! a constant, L is a sum of wrapped Cauchy lobes whose widths w_j run from c to W = 2,
//! spaced evenly in ln w (K = 12 of them, trapezoid weights), each cut off beyond φ ≈ 1/(λr)
//! as the cusp is:
//!
//! ```text
//! L(r, φ) = w(c) ρ′² C_φ/(4πD) · Σ_j ω_j (e^{−α_j r} − e^{−β_j r}) · 2π pdf_WC(φ; e^{−w_j}),
//! w_j = c_w (W/c_w)^{j/(K−1)},  c_w = max(c, 10⁻⁵),  ω_j = h w_j (h/2 · w_j at both ends),
//! h = ln(W/c_w)/(K − 1),  α_j = s + λ w_j,  β_j = α_j + 2s,  λ = σtr + 1/(4 z_b),
//! ```
//!
//! with D = (2 − ρ′)/3 and z_b = 2AD. Each lobe's energy up to r_max is closed-form,
//! 2π w ρ′² C_φ/(4πD) ω_j H_j(r_max) with H_j(r) = ∫₀^r x(e^{−α_j x} − e^{−β_j x}) dx, and so
//! is its radial CDF, inverted by the same Newton iteration: a draw picks the flux part or
//! one lobe by their energies, then r from that part's radial density and φ from its lobe.

use crate::gwc::{inv_cdf_wc, pdf_wc};
use crate::medium::Boundary;
use std::cell::OnceCell;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// cos θ′ up to which the ridge has its full weight.
pub const FULL_WEIGHT_COS: f64 = 0.1;
/// cos θ′ from which the ridge has weight 0.
pub const ZERO_WEIGHT_COS: f64 = 0.3;
/// The least cos θ′ the width takes: at θ′ = 90° the ridge would be a line.
pub const MIN_WIDTH_COS: f64 = 1e-5;

/// The ridge's weight w at cos θ′ = `cos_t`: 1 up to [`FULL_WEIGHT_COS`], 0 from
/// [`ZERO_WEIGHT_COS`], the smooth step x²(3 − 2x) between.
pub fn weight(cos_t: f64) -> f64 {
    if cos_t <= FULL_WEIGHT_COS {
        1.0
    } else if cos_t >= ZERO_WEIGHT_COS {
        0.0
    } else {
        let x = (ZERO_WEIGHT_COS - cos_t) / (ZERO_WEIGHT_COS - FULL_WEIGHT_COS);
        x * x * (3.0 - 2.0 * x)
    }
}

/// Whether the ridge has weight at some incidence θ ∈ [0°, 90°] for this η: below η = 1/√0.91 ≈ 1.0483,
/// where cos θ′ at grazing (or at the critical angle, η < 1) falls below [`ZERO_WEIGHT_COS`].
pub fn reaches(eta: f64) -> bool {
    match crate::fresnel::refracted_cos(FRAC_PI_2, eta) {
        Some(cos_t) => cos_t < ZERO_WEIGHT_COS,
        None => eta > 0.0,
    }
}

/// What a table's nodes hold less, and its lookups add back: its record's `ridge`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum RidgeKind {
    /// `ridge` = 0: the nodes hold the profile itself.
    #[default]
    None,
    /// `ridge` = 1 (format 1.6): the flux part R alone.
    Flux,
    /// `ridge` = 2: R plus the fluence part L (readers that know only 0 and 1 reject it as
    /// `unknown-ridge`).
    FluxAndFluence,
}

impl RidgeKind {
    /// The kind a bake stores.
    pub const NEWEST: RidgeKind = RidgeKind::FluxAndFluence;

    /// The record's code.
    pub fn code(self) -> u32 {
        match self {
            RidgeKind::None => 0,
            RidgeKind::Flux => 1,
            RidgeKind::FluxAndFluence => 2,
        }
    }

    /// The kind of a record's code, `None` for an unknown one.
    pub fn from_code(code: u32) -> Option<Self> {
        match code {
            0 => Some(RidgeKind::None),
            1 => Some(RidgeKind::Flux),
            2 => Some(RidgeKind::FluxAndFluence),
            _ => None,
        }
    }

    /// Whether the nodes hold the profile less a ridge.
    pub fn is_some(self) -> bool {
        self != RidgeKind::None
    }

    /// A short name: "none", "flux", "flux+fluence".
    pub fn name(self) -> &'static str {
        match self {
            RidgeKind::None => "none",
            RidgeKind::Flux => "flux",
            RidgeKind::FluxAndFluence => "flux+fluence",
        }
    }
}

/// The number K of lobes of the fluence part.
pub const FLUENCE_LOBES: usize = 12;
/// The widest lobe W of the fluence part.
pub const FLUENCE_MAX_WIDTH: f64 = 2.0;

/// The ridge at one (ρ′, θ) of a table: the flux part R(r, φ) = scale · m̂(r) · pdf_WC(φ; κ)
/// with m̂ = s e^{−r(s+k)}(1 − e^{−2rs})/(2r), scale = w ρ′² C_E, on r ∈ [0, r_max], and for
/// [`RidgeKind::FluxAndFluence`] the fluence part L (module docs).
#[derive(Debug, Clone)]
pub struct Ridge {
    scale: f64,
    /// C_E: the flux part's scale over its amplitude w ρ′², for the densities, which do not
    /// depend on the amplitude (and must not underflow with it at tiny ρ′).
    c_e: f64,
    s: f64,
    /// The attenuation σtr c/s over the source's depth, per unit r.
    k: f64,
    kappa: f64,
    r_max: f64,
    /// G(r_max): the radial integral up to r_max (`radial_integral`).
    total: f64,
    fluence: Option<Fluence>,
}

/// The fluence part L of a ridge: lobe j carries scale · ω_j (e^{−α_j r} − e^{−β_j r}) ·
/// 2π pdf_WC(φ; κ_j).
#[derive(Debug, Clone)]
struct Fluence {
    scale: f64,
    /// C_φ/(4πD): the scale over the ridge's amplitude w ρ′².
    unit: f64,
    /// The ridge's amplitude w ρ′².
    amp: f64,
    /// sin θ′ and the table's last radius, for the lobes' energies.
    s: f64,
    r_max: f64,
    weight: [f64; FLUENCE_LOBES],
    alpha: [f64; FLUENCE_LOBES],
    kappa: [f64; FLUENCE_LOBES],
    /// 1 − κ_j, without cancellation for the narrow lobes.
    gap: [f64; FLUENCE_LOBES],
    /// Each lobe's energy up to r_max, computed when a draw or a density first needs it (a
    /// value does not).
    energy: OnceCell<[f64; FLUENCE_LOBES]>,
}

impl Fluence {
    /// L at (ρ′, c = cos θ′, s = sin θ′) of a ridge of weight `w` (module docs); `None` where
    /// it carries nothing.
    fn new(boundary: &Boundary, rho: f64, w: f64, c: f64, s: f64, r_max: f64) -> Option<Self> {
        let d = (2.0 - rho) / 3.0;
        let sigma_tr = ((1.0 - rho) / d).max(0.0).sqrt();
        let z_b = 2.0 * boundary.a() * d;
        let lambda = sigma_tr + 0.25 / z_b;
        let unit = boundary.c_phi() / (4.0 * PI * d);
        let amp = w * rho * rho;
        let scale = amp * unit;
        let lo = c.max(MIN_WIDTH_COS);
        let h = (FLUENCE_MAX_WIDTH / lo).ln() / (FLUENCE_LOBES - 1) as f64;
        // w_j = lo·e^{jh} = lo·qʲ
        let q = h.exp();
        let mut out = Self {
            scale,
            unit,
            amp,
            s,
            r_max,
            weight: [0.0; FLUENCE_LOBES],
            alpha: [0.0; FLUENCE_LOBES],
            kappa: [0.0; FLUENCE_LOBES],
            gap: [0.0; FLUENCE_LOBES],
            energy: OnceCell::new(),
        };
        for j in 0..FLUENCE_LOBES {
            let width = lo * q.powi(j as i32);
            let end = if j == 0 || j + 1 == FLUENCE_LOBES {
                0.5
            } else {
                1.0
            };
            out.weight[j] = end * h * width;
            out.alpha[j] = s + lambda * width;
            out.gap[j] = -(-width).exp_m1();
            out.kappa[j] = 1.0 - out.gap[j];
        }
        (unit > 0.0 && unit.is_finite() && lambda.is_finite()).then_some(out)
    }

    /// The lobes' masses over φ at r: ω_j (e^{−α_j r} − e^{−β_j r}) times `scale` (the
    /// part's, or its `unit`).
    fn masses(&self, r: f64, scale: f64) -> [f64; FLUENCE_LOBES] {
        let front = scale * -(-2.0 * self.s * r).exp_m1();
        std::array::from_fn(|j| front * self.weight[j] * (-self.alpha[j] * r).exp())
    }

    /// Each lobe's energy up to r_max over the amplitude: 2π unit ω_j H_j(r_max).
    fn unit_energy(&self) -> &[f64; FLUENCE_LOBES] {
        self.energy.get_or_init(|| {
            std::array::from_fn(|j| {
                let a = self.alpha[j];
                TAU * self.unit * self.weight[j] * radial_moment(a, a + 2.0 * self.s, self.r_max)
            })
        })
    }

    fn unit_total(&self) -> f64 {
        self.unit_energy().iter().sum()
    }
}

impl Ridge {
    /// The ridge of `kind` at (ρ′, θ) of a table of boundary `boundary` and last radius
    /// `r_max`; `None` where it has no weight or no energy (no ridge, w = 0, ρ′ = 0, no light
    /// enters, θ outside [0, π/2], r_max not positive).
    pub fn at(
        kind: RidgeKind,
        boundary: &Boundary,
        rho: f64,
        theta: f64,
        r_max: f64,
    ) -> Option<Self> {
        let cos_t = crate::fresnel::refracted_cos(theta, boundary.eta())?;
        Self::with_cos(kind, boundary, rho, cos_t, r_max)
    }

    /// The ridge at cos θ′ = `cos_t` ∈ [0, 1] ([`Ridge::at`] of the θ refracted to it). θ nodes
    /// beyond the critical angle of an η < 1 hold the limit θ′ → 90° of the profile, so their
    /// ridge is this at cos θ′ = 0.
    pub fn with_cos(
        kind: RidgeKind,
        boundary: &Boundary,
        rho: f64,
        cos_t: f64,
        r_max: f64,
    ) -> Option<Self> {
        if kind == RidgeKind::None {
            return None;
        }
        let w = weight(cos_t);
        // The amplitude w ρ′² may be subnormal and the values with it: the densities, of the
        // shape alone, are not
        let amp = w * rho * rho;
        let scale = amp * boundary.c_e();
        let s = (1.0 - cos_t * cos_t).sqrt();
        if !(amp > 0.0 && s > 0.0 && r_max > 0.0) {
            return None;
        }
        let sigma_tr = (3.0 * (1.0 - rho) / (2.0 - rho)).max(0.0).sqrt();
        let k = sigma_tr * cos_t / s;
        let total = radial_integral(s + k, 3.0 * s + k, r_max);
        let fluence = match kind {
            RidgeKind::FluxAndFluence => Fluence::new(boundary, rho, w, cos_t, s, r_max),
            _ => None,
        };
        (total > 0.0).then_some(Self {
            scale,
            c_e: boundary.c_e(),
            s,
            k,
            kappa: (-cos_t.max(MIN_WIDTH_COS)).exp(),
            r_max,
            total,
            fluence,
        })
    }

    /// This ridge convolved over φ with a wrapped Cauchy lobe of concentration e^{−w}, w ≥ 0:
    /// every lobe's concentration κ becomes κ e^{−w} (its width grows by w), its harmonics
    /// ∫ R cos nφ dφ are multiplied by e^{−nw}, and its energy and its mean over φ stay; w = 0
    /// (or a w that is not a positive number) gives the ridge itself. The walk bake's model of a
    /// forward ridge wider than PBD's (`table::walk_bake` in bssrdf-zoo).
    pub fn widened(&self, w: f64) -> Self {
        let mut out = self.clone();
        if w.is_nan() || w <= 0.0 {
            return out;
        }
        let b = (-w).exp();
        // 1 − κ e^{−w} = (1 − e^{−w}) + e^{−w}(1 − κ), without cancellation
        let widen_gap = |gap: f64| -(-w).exp_m1() + b * gap;
        out.kappa = self.kappa * b;
        if let Some(f) = &mut out.fluence {
            for j in 0..FLUENCE_LOBES {
                f.gap[j] = widen_gap(f.gap[j]);
                f.kappa[j] = 1.0 - f.gap[j];
            }
        }
        out
    }

    /// Its energy up to r_max: ∫∫ R r dr dφ = w ρ′² C_E (s/2) G(r_max), plus the fluence
    /// lobes'.
    pub fn energy(&self) -> f64 {
        self.flux_energy()
            + self
                .fluence
                .as_ref()
                .map_or(0.0, |f| f.amp * f.unit_total())
    }

    fn flux_energy(&self) -> f64 {
        self.scale * 0.5 * self.s * self.total
    }

    /// The flux part's energy over the amplitude w ρ′².
    fn flux_unit_energy(&self) -> f64 {
        self.c_e * 0.5 * self.s * self.total
    }

    /// Its mean over φ, (1/2π) ∫ R dφ, per unit area; 0 outside [0, r_max].
    pub fn mean(&self, r: f64) -> f64 {
        if !(0.0..=self.r_max).contains(&r) {
            return 0.0;
        }
        let fluence = self
            .fluence
            .as_ref()
            .map_or(0.0, |f| f.masses(r, f.scale).iter().sum());
        self.scale * self.radial(r) / TAU + fluence
    }

    /// The ridge at (r, φ) per unit area; 0 outside [0, r_max] or for φ outside [−π, π]
    /// (wrapped by the caller) or NaN.
    pub fn eval(&self, r: f64, phi: f64) -> f64 {
        self.value(
            r,
            phi,
            self.scale,
            self.fluence.as_ref().map_or(0.0, |f| f.scale),
        )
    }

    /// [`Ridge::eval`] with the flux part's scale `flux_scale` and the fluence part's
    /// `fluence_scale` (theirs, or their units).
    fn value(&self, r: f64, phi: f64, flux_scale: f64, fluence_scale: f64) -> f64 {
        if !(0.0..=self.r_max).contains(&r) {
            return 0.0;
        }
        let flux = flux_scale * self.radial(r) * pdf_wc(phi, self.kappa);
        match &self.fluence {
            Some(f) if (-PI..=PI).contains(&phi) => {
                // 2π pdf_WC(φ; κ) = (1 − κ²)/((1 − κ)² + 4κ sin²(φ/2)), one sine for all lobes
                let half = (0.5 * phi).sin();
                let q = 4.0 * half * half;
                let masses = f.masses(r, fluence_scale);
                flux + (0..FLUENCE_LOBES)
                    .map(|j| {
                        let (k, gap) = (f.kappa[j], f.gap[j]);
                        masses[j] * gap * (2.0 - gap) / (gap * gap + k * q)
                    })
                    .sum::<f64>()
            }
            _ => flux,
        }
    }

    /// Its harmonics ∫ R cos nφ dφ over [−π, π] at r, n = 0 … N − 1 (each wrapped Cauchy
    /// lobe's are its mass times κⁿ); 0 outside [0, r_max].
    pub fn harmonics<const N: usize>(&self, r: f64) -> [f64; N] {
        if !(0.0..=self.r_max).contains(&r) {
            return [0.0; N];
        }
        let flux = self.scale * self.radial(r);
        let masses = self.fluence.as_ref().map(|f| f.masses(r, f.scale));
        std::array::from_fn(|n| {
            let fluence = match (&self.fluence, &masses) {
                (Some(f), Some(m)) => (0..FLUENCE_LOBES)
                    .map(|j| TAU * m[j] * f.kappa[j].powi(n as i32))
                    .sum(),
                _ => 0.0,
            };
            flux * self.kappa.powi(n as i32) + fluence
        })
    }

    /// m̂(r) = s e^{−r(s+k)}(1 − e^{−2rs})/(2r), s² at r = 0.
    fn radial(&self, r: f64) -> f64 {
        let q = 2.0 * r * self.s;
        let front = if q == 0.0 { 1.0 } else { -(-q).exp_m1() / q };
        self.s * self.s * (-r * (self.s + self.k)).exp() * front
    }

    /// Density per unit area of [`Ridge::sample`] at (r, φ): the ridge over its energy, both
    /// over the amplitude w ρ′² (for the flux part alone, its radial density times its
    /// density in φ, over r).
    pub fn pdf(&self, r: f64, phi: f64) -> f64 {
        if r <= 0.0 {
            return 0.0;
        }
        match &self.fluence {
            Some(f) => {
                self.value(r, phi, self.c_e, f.unit) / (self.flux_unit_energy() + f.unit_total())
            }
            None => self.pdf_radius(r) * pdf_wc(phi, self.kappa) / r,
        }
    }

    /// Density per unit r of [`Ridge::sample_radius`]: 2πr times the mean over φ, over the
    /// energy, on [0, r_max], 0 elsewhere.
    pub fn pdf_radius(&self, r: f64) -> f64 {
        if !(0.0..=self.r_max).contains(&r) {
            return 0.0;
        }
        let Some(f) = &self.fluence else {
            // e^{−ar} − e^{−br} = e^{−ar}(1 − e^{−2sr}), exact near 0
            return (-r * (self.s + self.k)).exp() * -(-2.0 * r * self.s).exp_m1() / self.total;
        };
        let flux = self.c_e
            * 0.5
            * self.s
            * (-r * (self.s + self.k)).exp()
            * -(-2.0 * r * self.s).exp_m1();
        let fluence = TAU * r * f.masses(r, f.unit).iter().sum::<f64>();
        (flux + fluence) / (self.flux_unit_energy() + f.unit_total())
    }

    /// The part a radial uniform u ∈ [0, 1] picks, by the parts' energies, and u rescaled
    /// within it: `None` for the flux part, `Some(j)` for fluence lobe j.
    fn pick(&self, u: f64) -> (Option<usize>, f64) {
        let u = u.clamp(0.0, 1.0);
        let Some(f) = &self.fluence else {
            return (None, u);
        };
        let flux = self.flux_unit_energy();
        let total = flux + f.unit_total();
        let mut target = u * total;
        if target < flux {
            return (None, target / flux);
        }
        target -= flux;
        for (j, &e) in f.unit_energy().iter().enumerate() {
            if target < e || j + 1 == FLUENCE_LOBES {
                return (Some(j), (target / e).clamp(0.0, 1.0));
            }
            target -= e;
        }
        (Some(FLUENCE_LOBES - 1), 1.0)
    }

    /// The r ∈ [0, r_max] a radial uniform u ∈ [0, 1] gives (clamped into it): u picks the
    /// flux part or a fluence lobe by their energies, then, rescaled, the r whose share of that
    /// part's energy it is (a safeguarded Newton inversion of its closed-form CDF).
    pub fn sample_radius(&self, u: f64) -> f64 {
        let (part, u) = self.pick(u);
        self.radius_of(part, u)
    }

    fn radius_of(&self, part: Option<usize>, u: f64) -> f64 {
        match (part, &self.fluence) {
            (Some(j), Some(f)) => {
                let a = f.alpha[j];
                invert_radial(1, a, a + 2.0 * self.s, self.s, self.r_max, u)
            }
            _ => {
                let (a, b) = (self.s + self.k, 3.0 * self.s + self.k);
                invert_radial(0, a, b, self.s, self.r_max, u)
            }
        }
    }

    /// (r, φ) from the uniforms (u_r, u_φ): r as [`Ridge::sample_radius`], φ from the wrapped
    /// Cauchy lobe of the part that drew it.
    pub fn sample(&self, u_r: f64, u_phi: f64) -> (f64, f64) {
        let (part, u) = self.pick(u_r);
        let r = self.radius_of(part, u);
        let kappa = match (part, &self.fluence) {
            (Some(j), Some(f)) => f.kappa[j],
            _ => self.kappa,
        };
        (r, inv_cdf_wc(u_phi.clamp(0.0, 1.0), kappa))
    }
}

/// The r ∈ [0, r_max] with ∫₀^r x^p (e^{−ax} − e^{−bx}) dx = u times that integral up to r_max
/// (p = 0 or 1, b = a + 2s, s > 0; u clamped into [0, 1]), by Newton's method kept inside a
/// shrinking bracket (the integral increases; its slope is 0 only at r = 0).
fn invert_radial(p: i32, a: f64, b: f64, s: f64, r_max: f64, u: f64) -> f64 {
    let integral = |r: f64| {
        if p == 0 {
            radial_integral(a, b, r)
        } else {
            radial_moment(a, b, r)
        }
    };
    let total = integral(r_max);
    let target = u.clamp(0.0, 1.0) * total;
    if target <= 0.0 {
        return 0.0;
    }
    if target >= total {
        return r_max;
    }
    let (mut lo, mut hi) = (0.0, r_max);
    // Near 0 the integral is 2s r^{p+2}/(p + 2)
    let start = if p == 0 {
        (target / s).sqrt()
    } else {
        (1.5 * target / s).cbrt()
    };
    let mut r = start.min(0.5 * r_max);
    for _ in 0..200 {
        let f = integral(r) - target;
        if f == 0.0 {
            return r;
        }
        if f > 0.0 {
            hi = r;
        } else {
            lo = r;
        }
        let slope = r.powi(p) * (-a * r).exp() * -(-2.0 * s * r).exp_m1();
        let newton = r - f / slope;
        let next = if slope > 0.0 && (lo..=hi).contains(&newton) {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - r).abs() <= 4.0 * f64::EPSILON * r || hi - lo <= f64::EPSILON * hi {
            return next;
        }
        r = next;
    }
    r
}

/// H(r) = ∫₀^r x (e^{−ax} − e^{−bx}) dx for 0 < a < b: Γ(a) − Γ(b) with
/// Γ(c) = (1 − e^{−cr}(1 + cr))/c², by its Taylor series where br is small.
fn radial_moment(a: f64, b: f64, r: f64) -> f64 {
    if b * r < 0.1 {
        // Σ_{n≥1} (−1)^{n+1} (bⁿ − aⁿ) r^{n+2}/(n! (n + 2)); terms fall by br/n at least
        let (mut an, mut bn, mut rn, mut fact) = (1.0, 1.0, r * r, 1.0);
        let mut sum = 0.0;
        for n in 1..30 {
            an *= a;
            bn *= b;
            rn *= r;
            fact *= f64::from(n);
            let term = (bn - an) * rn / (fact * f64::from(n + 2));
            sum += if n % 2 == 1 { term } else { -term };
            if term.abs() <= 1e-17 * sum.abs() {
                break;
            }
        }
        return sum;
    }
    let gamma = |c: f64| {
        let x = c * r;
        // 1 − e^{−x}(1 + x) = −expm1(−x) − x e^{−x}
        (-(-x).exp_m1() - x * (-x).exp()) / (c * c)
    };
    gamma(a) - gamma(b)
}

/// G(r) = ∫₀^r (e^{−ax} − e^{−bx}) dx for 0 < a < b: (1 − e^{−ar})/a − (1 − e^{−br})/b, by its
/// Taylor series where br is small (the two terms cancel to (b − a) r²/2 there).
fn radial_integral(a: f64, b: f64, r: f64) -> f64 {
    if b * r < 1e-3 {
        // Σ_{n≥2} (−1)ⁿ rⁿ (bⁿ⁻¹ − aⁿ⁻¹)/n!, four terms: the fifth is below 1e-15 of the first
        let (a2, b2) = (a * a, b * b);
        let (a3, b3) = (a2 * a, b2 * b);
        let (a4, b4) = (a3 * a, b3 * b);
        let r2 = r * r;
        return r2
            * ((b - a) / 2.0 - r * (b2 - a2) / 6.0 + r2 * (b3 - a3) / 24.0
                - r2 * r * (b4 - a4) / 120.0);
    }
    -(-a * r).exp_m1() / a + (-b * r).exp_m1() / b
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Composite Simpson on n (even) intervals.
    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let mut sum = f(a) + f(b);
        for k in 1..n {
            sum += f(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        sum * h / 3.0
    }

    #[test]
    fn the_weight_is_one_then_a_smooth_step_then_zero() {
        assert_eq!(weight(0.0), 1.0);
        assert_eq!(weight(0.1), 1.0);
        assert_eq!(weight(0.3), 0.0);
        assert_eq!(weight(0.9), 0.0);
        assert!((weight(0.2) - 0.5).abs() < 1e-15);
        let mut last = 1.0;
        for k in 0..=200 {
            let w = weight(0.1 + 0.2 * k as f64 / 200.0);
            assert!(w <= last && (0.0..=1.0).contains(&w));
            last = w;
        }
        assert!(reaches(1.0) && reaches(0.8) && reaches(1.04));
        assert!(!reaches(1.05) && !reaches(1.33));
        // the edge: cos θ′ at 90° is 0.3 at η = 1/√0.91
        assert!(reaches(1.0482) && !reaches(1.0484));
    }

    use crate::fresnel::Moments;

    fn ridge(kind: RidgeKind, eta: f64, rho: f64, theta_deg: f64, r_max: f64) -> Option<Ridge> {
        let boundary = Boundary::new(eta, Moments::Exact).unwrap();
        Ridge::at(kind, &boundary, rho, theta_deg.to_radians(), r_max)
    }

    const KINDS: [RidgeKind; 2] = [RidgeKind::Flux, RidgeKind::FluxAndFluence];

    #[test]
    fn kinds_round_trip_through_their_codes() {
        for kind in [RidgeKind::None, RidgeKind::Flux, RidgeKind::FluxAndFluence] {
            assert_eq!(RidgeKind::from_code(kind.code()), Some(kind));
        }
        assert_eq!(RidgeKind::from_code(3), None);
        assert!(!RidgeKind::None.is_some() && RidgeKind::NEWEST.is_some());
        assert!(ridge(RidgeKind::None, 1.0, 0.9, 89.0, 50.0).is_none());
    }

    #[test]
    fn without_attenuation_the_flux_part_carries_a_third_of_rho_squared_c_e() {
        // ρ′ = 1: σtr = 0, k = 0, and over the whole plane ρ′² C_E/3
        let r = ridge(RidgeKind::Flux, 1.0, 1.0, 85.0, 1e4).unwrap();
        assert_eq!(r.k, 0.0);
        let c_e = Boundary::new(1.0, Moments::Exact).unwrap().c_e();
        assert!((r.energy() / (c_e / 3.0) - 1.0).abs() < 1e-14);
        // and the fluence part adds its lobes' energies
        let both = ridge(RidgeKind::FluxAndFluence, 1.0, 1.0, 85.0, 1e4).unwrap();
        let f = both.fluence.as_ref().unwrap();
        let lobes = f.amp * f.unit_total();
        assert!(lobes > 0.0 && (both.energy() - r.energy() - lobes).abs() < 1e-15);
    }

    #[test]
    fn its_energy_is_the_integral_of_its_values() {
        // ∫₀^{r_max} ∫ R r dφ dr by Simpson over r and φ against its energy, and the mean
        // over φ and the harmonics against R's
        for kind in KINDS {
            for (eta, rho, theta_deg, r_max) in [
                (1.0, 0.8, 89.0, 50.0),
                (1.0, 0.3, 80.0, 3.0),
                (0.9, 0.95, 60.0, 20.0),
            ] {
                let ridge = ridge(kind, eta, rho, theta_deg, r_max).unwrap();
                // φ on a grid that resolves the narrowest width (κ up to e^{−0.0175})
                let over_phi =
                    |r: f64, n: f64| simpson(|p| ridge.eval(r, p) * (n * p).cos(), -PI, PI, 20_000);
                let radial = |r: f64| r * over_phi(r, 0.0);
                let total: f64 = (0..40)
                    .map(|k| {
                        let (a, b) = (r_max * k as f64 / 40.0, r_max * (k + 1) as f64 / 40.0);
                        simpson(radial, a, b, 40)
                    })
                    .sum();
                let want = ridge.energy();
                assert!(
                    (total / want - 1.0).abs() < 1e-6,
                    "{kind:?}: {total} vs {want}"
                );
                for r in [0.0, 0.01, 1.0, r_max] {
                    let mean = over_phi(r, 0.0) / TAU;
                    assert!((mean - ridge.mean(r)).abs() <= 1e-7 * ridge.mean(r) + 1e-300);
                    let h = ridge.harmonics::<4>(r);
                    for (n, hn) in h.iter().enumerate() {
                        let want = over_phi(r, n as f64);
                        assert!(
                            (hn - want).abs() <= 1e-7 * h[0] + 1e-300,
                            "{n}: {hn} {want}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn a_widened_ridge_keeps_its_energy_and_damps_its_harmonics() {
        for kind in KINDS {
            for (eta, rho, theta_deg) in [(1.0, 0.8, 89.0), (1.0, 0.3, 80.0), (0.9, 0.95, 60.0)] {
                let ridge = ridge(kind, eta, rho, theta_deg, 20.0).unwrap();
                for w in [0.0, -1.0, f64::NAN] {
                    let same = ridge.widened(w);
                    assert_eq!(
                        same.eval(0.7, 0.1).to_bits(),
                        ridge.eval(0.7, 0.1).to_bits()
                    );
                }
                for w in [1e-3, 0.1, 0.5] {
                    let wide = ridge.widened(w);
                    assert_eq!(wide.energy(), ridge.energy());
                    for r in [0.01, 1.0, 7.0] {
                        // its harmonics by Simpson over φ: the ridge's times e^{−nw}
                        let h = ridge.harmonics::<5>(r);
                        for (n, hn) in h.iter().enumerate() {
                            let got = simpson(
                                |p| wide.eval(r, p) * (n as f64 * p).cos(),
                                -PI,
                                PI,
                                20_000,
                            );
                            let want = hn * (-w * n as f64).exp();
                            assert!((got - want).abs() <= 1e-7 * h[0], "{n}: {got} {want}");
                        }
                        assert!((wide.mean(r) - ridge.mean(r)).abs() <= 1e-15 * ridge.mean(r));
                    }
                }
            }
        }
    }

    #[test]
    fn the_radial_sampler_inverts_its_distribution() {
        for kind in KINDS {
            for (rho, theta_deg) in [(0.9, 88.0), (0.05, 75.0), (1.0, 89.9)] {
                let ridge = ridge(kind, 1.0, rho, theta_deg, 30.0).unwrap();
                // the CDF of pdf_radius, on panels that resolve its decay near 0
                let cdf = |r: f64| {
                    let edges: [f64; 8] = [0.0, 1e-3, 1e-2, 0.1, 1.0, 3.0, 10.0, 30.0];
                    edges
                        .windows(2)
                        .map(|w| {
                            let (a, b) = (w[0].min(r), w[1].min(r));
                            simpson(|x| ridge.pdf_radius(x), a, b, 4_000)
                        })
                        .sum::<f64>()
                };
                assert!(
                    (cdf(30.0) - 1.0).abs() < 1e-9,
                    "{rho} {theta_deg}: {}",
                    cdf(30.0)
                );
                // stratified uniforms pushed through the sampler fill each bin as the
                // density does (a mixture's draw need not be its CDF's inverse)
                let n = 200_000;
                let edges: Vec<f64> = std::iter::once(0.0)
                    .chain((0..=24).map(|k| 30.0 * 10f64.powf(-6.0 + 0.25 * k as f64)))
                    .collect();
                let mut counts = vec![0usize; edges.len() - 1];
                for k in 0..n {
                    let r = ridge.sample_radius((k as f64 + 0.5) / n as f64);
                    let bin = edges.partition_point(|&e| e <= r).clamp(1, edges.len() - 1);
                    counts[bin - 1] += 1;
                }
                for (b, &count) in counts.iter().enumerate() {
                    let want = cdf(edges[b + 1]) - cdf(edges[b]);
                    let got = count as f64 / n as f64;
                    assert!(
                        (got - want).abs() < 2e-5 + 2e-3 * want,
                        "{kind:?} bin {b}: {got} vs {want}"
                    );
                }
                assert_eq!(ridge.sample_radius(0.0), 0.0);
                assert!(ridge.sample_radius(5e-324) < 1e-100);
                assert!(ridge.sample_radius(1.0) <= 30.0);
                // and each part's own inversion to rounding, down to the least uniforms
                for u in [1e-300, 1e-200, 1e-15, 1e-12, 1e-6, 0.3, 0.999999] {
                    for (p, a, b) in [(0, 1.1, 3.1), (1, 1.3, 3.3)] {
                        let r = invert_radial(p, a, b, 0.5 * (b - a), 30.0, u);
                        let f = |r| {
                            if p == 0 {
                                radial_integral(a, b, r)
                            } else {
                                radial_moment(a, b, r)
                            }
                        };
                        let got = f(r) / f(30.0);
                        assert!(
                            (got - u).abs() <= 1e-12 * u.max(1e-3) && (got - u).abs() <= 1e-9 * u,
                            "{p} u {u}: {got}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_radial_integrals_are_continuous_where_they_switch_to_their_series() {
        for (a, b) in [(1.0, 3.0), (1.7, 3.7), (0.02, 0.06)] {
            let r = 1e-3 / b;
            let below = radial_integral(a, b, r * (1.0 - 1e-12));
            let above = radial_integral(a, b, r * (1.0 + 1e-12));
            assert!(
                (above / below - 1.0).abs() < 1e-9,
                "{a} {b}: {below} {above}"
            );
            // and the series against the closed form in f64 where both are accurate
            let r = 0.9e-3 / b;
            let closed = -(-a * r).exp_m1() / a + (-b * r).exp_m1() / b;
            assert!((radial_integral(a, b, r) / closed - 1.0).abs() < 1e-9);
            // the first moment likewise, at its switch br = 0.1, and against Simpson
            let r = 0.1 / b;
            let below = radial_moment(a, b, r * (1.0 - 1e-12));
            let above = radial_moment(a, b, r * (1.0 + 1e-12));
            assert!(
                (above / below - 1.0).abs() < 1e-10,
                "{a} {b}: {below} {above}"
            );
            for r in [1e-6 / b, 0.05 / b, 0.5 / b, 5.0 / b] {
                let want = simpson(|x| x * ((-a * x).exp() - (-b * x).exp()), 0.0, r, 2_000);
                assert!((radial_moment(a, b, r) / want - 1.0).abs() < 1e-11, "{r}");
            }
        }
    }

    #[test]
    fn the_fluence_lobes_are_wrapped_cauchy_densities() {
        // eval's one-sine form of each lobe against the gwc module's density, over φ and
        // widths down to the floor (θ′ = 90°)
        for theta_deg in [75.0, 89.0, 90.0] {
            let both = ridge(RidgeKind::FluxAndFluence, 1.0, 0.7, theta_deg, 30.0).unwrap();
            let flux = ridge(RidgeKind::Flux, 1.0, 0.7, theta_deg, 30.0).unwrap();
            let f = both.fluence.as_ref().unwrap();
            for r in [1e-3, 0.5, 7.0] {
                let m = f.masses(r, f.scale);
                for phi in [-PI, -2.0, -1e-3, 0.0, 1e-6, 1e-4, 0.02, 0.3, 3.0, PI] {
                    let want = flux.eval(r, phi)
                        + (0..FLUENCE_LOBES)
                            .map(|j| m[j] * TAU * pdf_wc(phi, f.kappa[j]))
                            .sum::<f64>();
                    let got = both.eval(r, phi);
                    assert!(
                        (got / want - 1.0).abs() < 1e-12,
                        "{theta_deg} {r} {phi}: {got} {want}"
                    );
                }
                assert_eq!(both.eval(r, 3.2), flux.eval(r, 3.2));
            }
        }
    }

    #[test]
    fn the_fluence_part_is_the_spec_s() {
        // format-spec.md §10 "The fluence part", written out afresh: L at a few points of
        // η = 1 and 0.9 against what eval adds to the flux part
        for (eta, rho, theta_deg) in [
            (1.0f64, 0.8f64, 89.0f64),
            (1.0, 0.3, 80.0),
            (0.9, 0.95, 63.0),
        ] {
            let boundary = Boundary::new(eta, Moments::Exact).unwrap();
            let theta = f64::to_radians(theta_deg);
            let c = crate::fresnel::refracted_cos(theta, eta).unwrap();
            let s = (1.0 - c * c).sqrt();
            let d = (2.0 - rho) / 3.0;
            let sigma_tr = (3.0 * (1.0 - rho) / (2.0 - rho)).sqrt();
            let lambda = sigma_tr + 1.0 / (4.0 * 2.0 * boundary.a() * d);
            let c_w = c.max(1e-5);
            let h = (2.0 / c_w).ln() / 11.0;
            let spec = |r: f64, phi: f64| -> f64 {
                (0..12)
                    .map(|j| {
                        let w_j = c_w * (j as f64 * h).exp();
                        let omega = h * w_j * if j == 0 || j == 11 { 0.5 } else { 1.0 };
                        let alpha = s + lambda * w_j;
                        let beta = alpha + 2.0 * s;
                        let k = (-w_j).exp();
                        let wc = (1.0 - k * k) / (1.0 + k * k - 2.0 * k * phi.cos());
                        omega * ((-alpha * r).exp() - (-beta * r).exp()) * wc
                    })
                    .sum::<f64>()
                    * weight(c)
                    * rho
                    * rho
                    * boundary.c_phi()
                    / (4.0 * PI * d)
            };
            let both = Ridge::at(RidgeKind::FluxAndFluence, &boundary, rho, theta, 40.0).unwrap();
            let flux = Ridge::at(RidgeKind::Flux, &boundary, rho, theta, 40.0).unwrap();
            for r in [0.01, 0.3, 2.0, 15.0] {
                for phi in [0.0, 0.01, 0.2, 1.0, 3.0] {
                    let got = both.eval(r, phi) - flux.eval(r, phi);
                    let want = spec(r, phi);
                    // the spec's 1 − κ² and 1 + κ² − 2κ cos φ cancel where κ → 1
                    assert!(
                        (got / want - 1.0).abs() < 1e-9,
                        "{eta} {rho} {theta_deg} {r} {phi}: {got} {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn densities_stay_exact_where_the_amplitude_underflows() {
        // ρ′² ~ 1e-323: the ridge's values underflow, its densities do not (they are of the
        // shape alone, the same at every ρ′ of the same σtr, here ≈ √(3/2))
        let kind = RidgeKind::FluxAndFluence;
        let tiny = ridge(kind, 1.0, 3.3e-162, 89.0, 30.0).unwrap();
        let small = ridge(kind, 1.0, 1e-12, 89.0, 30.0).unwrap();
        for (r, phi) in [(0.1, 0.0), (1.0, 0.01), (5.0, 2.0)] {
            let (a, b) = (tiny.pdf(r, phi), small.pdf(r, phi));
            assert!(
                a.is_finite() && (a / b - 1.0).abs() < 1e-6,
                "{r} {phi}: {a} {b}"
            );
            let (a, b) = (tiny.pdf_radius(r), small.pdf_radius(r));
            assert!(a.is_finite() && (a / b - 1.0).abs() < 1e-9, "{r}: {a} {b}");
        }
        for u in [0.01, 0.5, 0.99] {
            let (a, b) = (tiny.sample(u, 0.3), small.sample(u, 0.3));
            assert!(
                (a.0 / b.0 - 1.0).abs() < 1e-9 && (a.1 / b.1 - 1.0).abs() < 1e-9,
                "{u}: {a:?} {b:?}"
            );
        }
    }

    #[test]
    fn draws_come_from_the_part_their_uniform_picks() {
        let ridge = ridge(RidgeKind::FluxAndFluence, 1.0, 0.9, 89.0, 30.0).unwrap();
        let f = ridge.fluence.as_ref().unwrap();
        let total = ridge.flux_unit_energy() + f.unit_total();
        // the uniforms at the middle of each part's share of the energy
        let mut start = 0.0;
        let shares = std::iter::once(ridge.flux_unit_energy()).chain(*f.unit_energy());
        for (part, e) in shares.enumerate() {
            let u = (start + 0.5 * e) / total;
            let (picked, rescaled) = ridge.pick(u);
            assert_eq!(picked, part.checked_sub(1), "{part}");
            assert!((rescaled - 0.5).abs() < 1e-9);
            // φ at u_φ = 3/4 is its lobe's quartile: the wider the lobe, the wider the quartile
            let (_, phi) = ridge.sample(u, 0.75);
            let kappa = picked.map_or(ridge.kappa, |j| f.kappa[j]);
            assert_eq!(phi, inv_cdf_wc(0.75, kappa));
            start += e;
        }
    }

    #[test]
    fn no_ridge_where_it_has_no_weight_or_no_light_enters() {
        for kind in KINDS {
            assert!(ridge(kind, 1.33, 0.9, 89.0, 50.0).is_none());
            assert!(ridge(kind, 1.0, 0.9, 0.0, 50.0).is_none());
            assert!(ridge(kind, 1.0, 0.0, 89.0, 50.0).is_none());
            assert!(ridge(kind, 0.9, 0.9, 70.0, 50.0).is_none());
            assert!(ridge(kind, 1.0, 0.9, 89.0, 50.0).is_some());
            // At θ′ = 90° the width stops at 10⁻⁵: finite everywhere
            let at_90 = ridge(kind, 1.0, 0.9, 90.0, 50.0).unwrap();
            assert!(at_90.eval(1.0, 0.0).is_finite() && at_90.eval(0.0, 0.0) > 0.0);
            assert!(at_90.energy().is_finite() && at_90.pdf(1.0, 0.0).is_finite());
        }
    }
}
