//! The single scattering a `total` walk table adds to the walk's multiple scattering at each
//! node: exact, by quadrature along the refracted beam ([`crate::walk::single`]), in each row's
//! reduced units.
//!
//! At a node (ρ′, θ, r > 0) it gives the harmonics μ₀ … μ₄ and the values at the two-lobe
//! azimuths ([`two_lobe_azimuths`]) of a · S₁(r/k, φ)/k², a the row's unreduced albedo
//! and k = 1 − g a; for a beam in the surface ([`super::beam_in_surface`]) the limit, a ridge
//! on φ = 0 of energy a·e^{−r/k}·K/k per unit reduced r ([`surface_ridge_weight`]), whose every
//! harmonic is its mass. With g = 0 every row is the albedo times one profile (k = 1), computed
//! once per θ node; with g ≠ 0 each row has its own radii and is integrated on its own:
//! 1.2–2 ms per node at θ ≥ 30° on one core (`cost_of_a_node`, on two cores shared with a walk),
//! about a minute of one core for the 42,000 nodes of the default grid, against the tens of
//! minutes its walks take at g = 0.9.

use super::two_lobe_azimuths;
use super::walk_bake::{check_azimuths, CHECK_AZIMUTHS};
use crate::error::Result;
use crate::walk::single::{surface_ridge_weight, SingleScattering, SINGLE_HARMONICS};
use rayon::prelude::*;

/// Azimuths of a two-lobe node ([`two_lobe_azimuths`]): a total node is fitted at the same
/// eight as a multiple one (25 changed its error by under half a point of L1 except at
/// (η, θ) = (1.33, 90°), 14 → 11 %: docs/walk-table.md).
const AZIMUTHS: usize = 8;

/// The single scattering at one node, per unit power entering, reduced units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SingleNode {
    /// μ₀ … μ₄ (μₙ = ∫ S₁ cos nφ dφ over [−π, π]).
    pub harmonics: [f64; SINGLE_HARMONICS],
    /// S₁ at [`two_lobe_azimuths`]; 0 for a beam in the surface (all of it on the ridge).
    pub at_azimuths: [f64; AZIMUTHS],
    /// S₁ at [`check_azimuths`], where the bake compares its stored node with the profile;
    /// 0 for a beam in the surface.
    pub at_check: [f64; CHECK_AZIMUTHS],
}

impl SingleNode {
    pub(super) const ZERO: SingleNode = SingleNode {
        harmonics: [0.0; SINGLE_HARMONICS],
        at_azimuths: [0.0; AZIMUTHS],
        at_check: [0.0; CHECK_AZIMUTHS],
    };

    fn scaled(&self, factor: f64) -> SingleNode {
        SingleNode {
            harmonics: self.harmonics.map(|m| m * factor),
            at_azimuths: self.at_azimuths.map(|v| v * factor),
            at_check: self.at_check.map(|v| v * factor),
        }
    }
}

/// Single scattering at one θ node of a walk bake.
pub(super) struct SinglePart {
    g: f64,
    exact: SingleScattering,
    /// K of a beam in the surface, `None` where the beam is refracted into the medium.
    ridge: Option<f64>,
    /// With g = 0, the profile per unit albedo at every radius node.
    per_albedo: Option<Vec<SingleNode>>,
}

impl SinglePart {
    /// The single scattering of the beam at `theta` (radians, within the walk's domain) into
    /// (η, g), at the radius nodes `r`; `in_surface` for a node baked as the limit of a beam in
    /// the surface.
    pub(super) fn new(g: f64, eta: f64, theta: f64, in_surface: bool, r: &[f64]) -> Result<Self> {
        let exact = SingleScattering::new(g, eta, theta)?;
        let mut part = SinglePart {
            g,
            exact,
            ridge: in_surface.then(|| surface_ridge_weight(g, eta)),
            per_albedo: None,
        };
        if g == 0.0 {
            let nodes = r.par_iter().map(|&x| part.compute(1.0, x)).collect();
            part.per_albedo = Some(nodes);
        }
        Ok(part)
    }

    /// The single scattering of the row of unreduced albedo `albedo` at its radius node
    /// `node` (reduced radius `r`).
    pub(super) fn node(&self, albedo: f64, node: usize, r: f64) -> SingleNode {
        match &self.per_albedo {
            Some(nodes) => nodes
                .get(node)
                .map_or(SingleNode::ZERO, |n| n.scaled(albedo)),
            None => self.compute(albedo, r),
        }
    }

    fn compute(&self, albedo: f64, r: f64) -> SingleNode {
        if r <= 0.0 || albedo <= 0.0 {
            return SingleNode::ZERO;
        }
        let k = 1.0 - self.g * albedo;
        match self.ridge {
            Some(weight) => {
                // Energy a e^{−r/k} K/k per unit reduced r: every harmonic is it over r
                let m = albedo * (-r / k).exp() * weight / (k * r);
                SingleNode {
                    harmonics: [m; SINGLE_HARMONICS],
                    ..SingleNode::ZERO
                }
            }
            None => SingleNode {
                harmonics: self.exact.reduced_harmonics(albedo, r),
                at_azimuths: two_lobe_azimuths().map(|phi| self.exact.reduced(albedo, r, phi)),
                at_check: check_azimuths().map(|phi| self.exact.reduced(albedo, r, phi)),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[ignore = "timing, not a check: prints the cost of a node"]
    fn cost_of_a_node() {
        let r: Vec<f64> = crate::table::GridPreset::Default
            .grid(1.33, crate::table::Lobes::Two)
            .r;
        for theta_deg in [0.0f64, 30.0, 60.0, 89.0] {
            let part = SinglePart::new(0.5, 1.33, theta_deg.to_radians(), false, &r).unwrap();
            let start = std::time::Instant::now();
            let mut sum = 0.0;
            for (k, &x) in r.iter().enumerate() {
                sum += part.node(0.7, k, x).harmonics[0];
            }
            let each = start.elapsed().as_secs_f64() / r.len() as f64;
            println!("{theta_deg}°: {:.3} ms per node ({sum})", 1e3 * each);
        }
    }
}
