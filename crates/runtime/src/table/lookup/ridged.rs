//! Lookups of a table with the analytic ridge (`table::ridge`, format-spec.md §10 "The
//! ridge"): its nodes hold D = S − R, and every lookup is of S = D + R.
//!
//! - **Value**: the nodes' value plus R at the point.
//! - **Effective albedo**: the nodes' plus R's energy up to the last radius.
//! - **Sampling** draws from the mixture of the two parts by their energies E_D and E_R: the
//!   radial uniform u picks the part (u < E_D/(E_D + E_R): the nodes', with u rescaled to
//!   [0, 1)), which then draws r and φ as on its own; the density is the mixture's,
//!   (E_D p_D + E_R p_R)/(E_D + E_R), at the point whichever part drew it. `sample_radius`
//!   draws r the same way (the same u gives the same r) and `pdf_radius` is the mixture of the
//!   two radial densities; the angular factor is S over its mean over φ, D̄ + R̄. The separable
//!   estimator's mean stays the effective albedo: E_R p_R(r)/(2πr) is R's mean over φ.
//! - **θ for path tracing**: the θ CDF a bake stores is of the nodes' totals plus R's energy
//!   at each θ node, row by row ([`TableRef::node_total`]), and the draws of θ and its
//!   density read the same node totals.
//! - **Inverse**: a point has a preimage through each part; [`TableRef::invert`] gives the
//!   one through the nodes' part.

use super::*;
use crate::table::ridge::{Ridge, RidgeKind};

impl TableRef<'_> {
    /// The ridge at (ρ′, θ) of this table, `None` for a table without (or where it has no
    /// weight). θ as the lookups take it ([`TableRef::snap_theta`], at most π/2).
    #[inline]
    pub(super) fn ridge_at(&self, rho: f64, theta: f64) -> Option<Ridge> {
        if self.ridge == RidgeKind::None {
            return None;
        }
        let r_max = *self.axes.r().as_slice().last()?;
        let theta = self.snap_theta(theta).clamp(0.0, FRAC_PI_2);
        Ridge::at(self.ridge, &self.boundary, rho, theta, r_max)
    }

    /// The total a θ draw reads at node (i, j) of the albedo and θ axes: the row's radial CDF
    /// at its last radius, plus the ridge's energy at (ρ′ᵢ, θⱼ) for a table with the ridge (at
    /// cos θ′ = 0 for a node beyond the critical angle that holds energy, [`Ridge::with_cos`]).
    /// A bake's θ CDF integrates these.
    pub fn node_total(&self, i: usize, j: usize) -> f64 {
        let (_, n_theta, n_r) = self.axes.dims();
        let stored = f64::from(self.radial_cdf[((i * n_theta + j) * n_r) + n_r - 1]);
        if self.ridge == RidgeKind::None {
            return stored;
        }
        let rho = self.axes.rho().as_slice()[i];
        let theta = self.axes.theta().as_slice()[j].clamp(0.0, FRAC_PI_2);
        // Nodes beyond the critical angle (η < 1) that hold energy hold the profile's limit at
        // it, cos θ′ = 0 (the critical node and its copies); the others hold 0
        let cos_t = match crate::fresnel::refracted_cos(theta, self.eta) {
            Some(cos_t) => cos_t,
            None if stored > 0.0 => 0.0,
            None => return stored,
        };
        let r_max = self.axes.r().as_slice()[n_r - 1];
        stored
            + Ridge::with_cos(self.ridge, &self.boundary, rho, cos_t, r_max)
                .map_or(0.0, |r| r.energy())
    }

    /// S at the point: the nodes' value `nodes` plus the ridge.
    #[cold]
    #[inline(never)]
    pub(super) fn with_ridge_value(
        &self,
        nodes: f64,
        rho: f64,
        theta: f64,
        r: f64,
        phi: f64,
    ) -> f64 {
        match self.ridge_at(rho, theta) {
            Some(ridge) if phi.is_finite() => nodes + ridge.eval(r, wrap_phi(phi)),
            _ => nodes,
        }
    }

    /// The two parts' energies (nodes', ridge's) of a slice.
    fn parts(&self, s: &Slice, ridge: &Ridge) -> (f64, f64) {
        (self.total(s), ridge.energy())
    }

    /// [`TableRef::sample_slice`] of the mixture of the nodes' part and `ridge`.
    pub(super) fn sample_mixture(
        &self,
        s: &Slice,
        ridge: &Ridge,
        u_r: f64,
        u_phi: f64,
    ) -> Option<Sample> {
        if !(0.0..=1.0).contains(&u_r) {
            return None;
        }
        let (e_d, e_r) = self.parts(s, ridge);
        let share_d = e_d / (e_d + e_r);
        let (r, phi, pdf_d) = if u_r < share_d {
            let d = self.sample_slice(s, u_r / share_d, u_phi)?;
            (d.r, d.phi, d.pdf)
        } else {
            let u = ((u_r - share_d) / (1.0 - share_d)).min(1.0);
            let (r, phi) = ridge.sample(u, u_phi);
            (r, phi, self.pdf_slice(s, r, phi))
        };
        let pdf = mixture(e_d, pdf_d, e_r, ridge.pdf(r, phi));
        (r > 0.0 && pdf.is_finite() && pdf > 0.0).then_some(Sample { r, phi, pdf })
    }

    /// [`TableRef::pdf_slice`] of the mixture.
    pub(super) fn pdf_mixture(&self, s: &Slice, ridge: &Ridge, r: f64, phi: f64) -> f64 {
        if r <= 0.0 || !r.is_finite() {
            return 0.0;
        }
        let (e_d, e_r) = self.parts(s, ridge);
        mixture(
            e_d,
            self.pdf_slice(s, r, phi),
            e_r,
            ridge.pdf(r, wrap_phi(phi)),
        )
    }

    /// [`TableRef::radius_draw`] of the mixture: (r, density per unit r).
    pub(super) fn radius_draw_mixture(
        &self,
        s: &Slice,
        ridge: &Ridge,
        u: f64,
    ) -> Option<(f64, f64)> {
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let (e_d, e_r) = self.parts(s, ridge);
        let share_d = e_d / (e_d + e_r);
        let (r, pdf_d) = if u < share_d {
            let d = self.radius_draw(s, u / share_d)?;
            (d.x, d.pdf)
        } else {
            let r = ridge.sample_radius(((u - share_d) / (1.0 - share_d)).min(1.0));
            (r, self.radial_pdf(s, r))
        };
        let pdf = mixture(e_d, pdf_d, e_r, ridge.pdf_radius(r));
        (r > 0.0 && pdf.is_finite() && pdf > 0.0).then_some((r, pdf))
    }

    /// [`TableRef::radial_pdf`] of the mixture.
    pub(super) fn radial_pdf_mixture(&self, s: &Slice, ridge: &Ridge, r: f64) -> f64 {
        let (e_d, e_r) = self.parts(s, ridge);
        mixture(e_d, self.radial_pdf(s, r), e_r, ridge.pdf_radius(r))
    }
}

/// The mixture's density: the parts' densities weighted by their energies; 0 where neither
/// holds any (both underflow at ρ′ ≲ 10⁻¹⁶¹).
fn mixture(e_d: f64, pdf_d: f64, e_r: f64, pdf_r: f64) -> f64 {
    let total = e_d + e_r;
    if total > 0.0 {
        (e_d * pdf_d + e_r * pdf_r) / total
    } else {
        0.0
    }
}
