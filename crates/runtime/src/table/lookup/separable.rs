//! The table for separable renderers (pbrt's `SeparableBSSRDF` and its kin): the exit distance
//! drawn from the table's radial distribution alone, its density per unit r, and the angular
//! factor that turns the radially symmetric part of S back into S.
//!
//! Such a renderer draws r from a radial profile, φ uniform (or by its own rule), finds the exit
//! point with a probe ray and weights the hit by S over the density of the point. On a flat
//! surface, with r drawn with density p_r(r) ([`TableRef::sample_radius`],
//! [`TableRef::pdf_radius`]) and φ uniform, the point has the area density p_r(r)/(2πr), and
//!
//! ```text
//! S(r, φ; θ) = S̄(r; θ) · F(r, φ; θ),   S̄(r; θ) = (1/2π) ∫ S(r, φ; θ) dφ = E(r; θ)/(2πr),
//! ```
//!
//! F = [`TableRef::angular_factor`], with (1/2π) ∫ F dφ = 1 at every r. Two estimators of the
//! power leaving per unit power entering follow:
//!
//! - **separable**: S̄ is the sampler's own radial profile, S̄_p(r) = ρ_eff(θ) p_r(r)/(2πr) (the
//!   samplers' plain spline of E along r over 2πr), so the weight S/(p_r/(2πr)) is
//!   w = ρ_eff(θ) · F(r, φ; θ). Its mean is ρ_eff(θ) ([`TableRef::effective_albedo`]) exactly:
//!   the radial part is sampled perfectly and F averages to 1 over φ at each r.
//! - **full table value**: S from [`TableRef::eval`], w = 2πr S(r, φ; θ)/p_r(r). Its mean is
//!   ∫ E_eval dr, the energy of evaluation's log-energy interpolation along r, which differs
//!   from ρ_eff (the plain spline's) by the interpolation gap described in the module docs
//!   (a median 8e-5 of it), and by up to about 1 % below the first nonzero albedo node, where
//!   evaluation weighs the rows per radius node (`albedo_ends`) and the samplers blend them.
//!
//! F is defined from evaluation: S_eval = S̄_eval · F up to a few ulp, with S̄_eval = E/(2πr)
//! the isotropic part of evaluation's own cell. Its normalised density in φ is evaluation's
//! (the spline of the nodes' lobe shares), which the samplers' φ law approximates (see
//! [`TableRef::cell_from`]); a separable renderer never uses the latter.

use super::world::mm_to_reduced;
use super::*;

/// One draw of the exit distance alone, in the units of the lookup that drew it: reduced units
/// from [`TableRef`] (r in mean free paths, the density per mfp), world units from
/// [`MediumRef`] (mm, mm⁻¹).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadialSample {
    /// Exit distance, > 0.
    pub r: f64,
    /// Density per unit r of the draw, > 0: the pdf of [`TableRef::sample_radius`] at `r`.
    pub pdf: f64,
}

impl TableRef<'_> {
    /// Draws the exit distance r (reduced mfp) for (ρ′, θ) from one uniform u ∈ [0, 1): the
    /// radial step of [`TableRef::sample`] (the same u gives the same r), with its density per
    /// unit r, [`TableRef::pdf_radius`] at r up to rounding. `None` where `sample` is: no energy
    /// (ρ′ = 0, light beyond the critical angle) or (ρ′, θ) outside the axes.
    pub fn sample_radius(&self, rho: f64, theta: f64, u: f64) -> Option<RadialSample> {
        let rho = self.read_albedo(rho);
        if !self.light_enters(theta) {
            return None;
        }
        if let Some(ridge) = self.ridge_at(rho, theta) {
            let (r, pdf) =
                self.with_slice(rho, theta, |s| self.radius_draw_mixture(s, &ridge, u))??;
            return Some(RadialSample { r, pdf });
        }
        let radial = self.with_slice(rho, theta, |s| self.radius_draw(s, u))??;
        (radial.pdf.is_finite() && radial.pdf > 0.0).then_some(RadialSample {
            r: radial.x,
            pdf: radial.pdf,
        })
    }

    /// Density per unit r (reduced mfp⁻¹) of [`TableRef::sample_radius`] at r: the radial factor
    /// of [`TableRef::pdf`], which is `pdf_radius · p(φ | r) / r`. 0 outside (0, r_max], beyond
    /// the critical angle and outside the axes.
    pub fn pdf_radius(&self, rho: f64, theta: f64, r: f64) -> f64 {
        let rho = self.read_albedo(rho);
        if !self.light_enters(theta) || r <= 0.0 || !r.is_finite() {
            return 0.0;
        }
        if let Some(ridge) = self.ridge_at(rho, theta) {
            return self
                .with_slice(rho, theta, |s| self.radial_pdf_mixture(s, &ridge, r))
                .unwrap_or(0.0);
        }
        self.with_slice(rho, theta, |s| self.radial_pdf(s, r))
            .unwrap_or(0.0)
    }

    /// The angular factor F(r, φ; θ) = S(r, φ; θ)/S̄(r; θ), dimensionless, ≥ 0, with
    /// S̄ = (1/2π) ∫ S dφ = E/(2πr) of [`TableRef::eval`]'s cell at (ρ′, θ, r): eval = S̄·F up to
    /// a few ulp, and F averages to 1 over φ. 0 where eval is 0 for every φ (r outside the
    /// radial support, no energy, beyond the critical angle) and for NaN φ; `None` for (ρ′, θ)
    /// outside the axes, as eval. See the module docs for the estimators it serves.
    pub fn angular_factor(&self, rho: f64, theta: f64, r: f64, phi: f64) -> Option<f64> {
        let rho = self.read_albedo(rho);
        let cell = self.cell_at_point(rho, theta, r)?;
        if let Some(ridge) = self.ridge_at(rho, theta) {
            // S over its mean over φ, the nodes' part's E/(2πr) and the ridge's
            let e_per_r = match cell {
                Cell::Profile([e_per_r, ..]) => e_per_r,
                Cell::OutsideRadius => 0.0,
            };
            let mean = e_per_r / TAU + ridge.mean(r);
            if mean <= 0.0 || !phi.is_finite() {
                return Some(0.0);
            }
            return Some(self.eval(rho, theta, r, phi)? / mean);
        }
        let Cell::Profile([e_per_r, beta, c]) = cell else {
            return Some(0.0);
        };
        if e_per_r <= 0.0 || !phi.is_finite() || !self.light_enters(theta) {
            return Some(0.0);
        }
        // S as eval gives it: from the same cell for one lobe, through the harmonics for two
        let s = match self.harmonics {
            Some(_) => self.eval(rho, theta, r, phi)?,
            None => table_value(e_per_r, beta, c, wrap_phi(phi)),
        };
        Some(s * TAU / e_per_r)
    }
}

impl MediumRef<'_> {
    /// Draws the exit distance in mm for incidence θ from one uniform u ∈ [0, 1), with its
    /// density per mm (> 0, [`MediumRef::pdf_radius`] at the distance returned; see
    /// [`World::sample`] for a distance that σ′t·r_mm does not give back exactly). `None` where
    /// [`MediumRef::sample`] is.
    pub fn sample_radius(&self, theta: f64, u: f64) -> Option<RadialSample> {
        let st = self.sigma_t_prime();
        let s = self.world.table.sample_radius(self.rho, theta, u)?;
        let r = reduced_to_mm(s.r, st);
        let pdf = if st * r == s.r {
            s.pdf * st
        } else {
            self.pdf_radius(theta, r)
        };
        (pdf > 0.0).then_some(RadialSample { r, pdf })
    }

    /// Density per mm of [`MediumRef::sample_radius`] at `r_mm`: 0 where it cannot sample.
    pub fn pdf_radius(&self, theta: f64, r_mm: f64) -> f64 {
        let st = self.sigma_t_prime();
        st * self
            .world
            .table
            .pdf_radius(self.rho, theta, mm_to_reduced(r_mm, st))
    }

    /// The angular factor S/S̄ at (θ, r in mm, φ), dimensionless ([`TableRef::angular_factor`]
    /// at σ′t·r_mm): [`MediumRef::eval`] = S̄·F with S̄ = (1/2π) ∫ eval dφ in mm⁻². `None` for θ
    /// outside the table.
    pub fn angular_factor(&self, theta: f64, r_mm: f64, phi: f64) -> Option<f64> {
        let st = self.sigma_t_prime();
        self.world
            .table
            .angular_factor(self.rho, theta, mm_to_reduced(r_mm, st), phi)
    }
}
