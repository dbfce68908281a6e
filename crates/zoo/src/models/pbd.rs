//! Photon beam diffusion as a model of the zoo: a thin wrapper of [`crate::pbd::Pbd`] with its
//! reference (`pbd`) or fast (`pbd-fast`) quadrature.
//!
//! | parameter | unit | valid range |
//! |---|---|---|
//! | ρ′ reduced albedo | – | [0, 1] |
//! | η relative index | – | [0.75, 2.5] |
//! | θ incidence before refraction | rad | [0, π/2]; 0 beyond the critical angle |
//! | r, φ | reduced mfp, rad (0 forward) | r ≥ 0 |
//! | result | per reduced mfp², per unit power entering | ≥ 0; +∞ at the singular points below |
//!
//! Sources: Habel, Christensen, Jarosz 2013 (photon beam diffusion); Ferrier 2016, appendix A
//! (any incidence); the derivation and its corrections are in [`crate::pbd`].
//!
//! No conversion: PBD's exitance C_φ φ + C_E E·n is already the power leaving per unit area per
//! unit power entering (the C_φ, C_E weights carry the exit Fresnel transmittance). Multiple
//! scattering only. Grosjean's D and the exact (or chosen) Fresnel moments.
//!
//! Where it breaks down (documented, never NaN): r = 0 gives +∞ (ln(1/r) growth); a refracted
//! beam running along the surface (θ = 90° at η = 1) gives +∞ at φ = 0 only. Diffusion
//! underestimates the profile near the source at low albedo, where single scattering (not
//! modelled here) dominates. The effective albedo is computed independently of `eval`
//! (swapped integration order, relative tolerance 1e-9).

use super::{Model, ModelKind, Params};
use crate::error::Result;
use crate::medium::Boundary;
use crate::pbd::{Pbd, Rule};
use crate::walk::Component;

/// PBD with one quadrature rule.
#[derive(Debug, Clone, PartialEq)]
pub struct PbdModel {
    pbd: Pbd,
    rule: Rule,
}

impl PbdModel {
    /// PBD for validated parameters and a quadrature rule.
    pub fn new(params: Params, rule: Rule) -> Result<Self> {
        let boundary = Boundary::new(params.eta(), params.moments())?;
        Ok(Self {
            pbd: Pbd::new(params.rho_prime(), boundary)?,
            rule,
        })
    }

    /// The wrapped evaluator.
    pub fn pbd(&self) -> &Pbd {
        &self.pbd
    }
}

impl Model for PbdModel {
    fn kind(&self) -> ModelKind {
        match self.rule {
            Rule::Reference => ModelKind::Pbd,
            Rule::Fast => ModelKind::PbdFast,
        }
    }

    fn component(&self) -> Component {
        Component::Multiple
    }

    fn eval(&self, theta: f64, r: f64, phi: f64) -> f64 {
        self.pbd.eval(theta, r, phi, self.rule)
    }

    fn effective_albedo(&self, theta: f64) -> Option<f64> {
        Some(self.pbd.effective_albedo(theta))
    }
}
