//! Every registered model at arbitrary inputs — θ, r, φ and the random numbers anywhere in f64,
//! NaN, ±∞, subnormals and ±0 included — for albedos and η at the ends of their domains: no
//! panic, `eval` ≥ 0 and never NaN (+∞ only where documented), `pdf` finite and ≥ 0, and a
//! draw either `None` or a valid point whose density is `pdf`'s (`lookup_common`, the rules the
//! fuzz target `fuzz/fuzz_targets/lookups.rs` holds too).

use std::f64::consts::FRAC_PI_2;
use std::sync::OnceLock;

use bssrdf_zoo::models::{Model, ModelKind};
use proptest::prelude::*;

use crate::lookup_common::{check_model, inputs_near, Inputs};
use crate::models_common::model;
use crate::properties::documented_infinity;

/// (ρ′, η) of the models: both ends of the η domain, index matching, ρ′ from 0 to 1.
const MEDIA: [(f64, f64); 4] = [(0.0, 1.33), (0.5, 0.75), (0.99, 1.0), (1.0, 2.5)];

/// θ at which the walk of the Monte Carlo model runs (its only θ).
const WALK_THETA: f64 = 0.5;

struct Built {
    kind: ModelKind,
    eta: f64,
    model: Box<dyn Model>,
}

fn models() -> &'static [Built] {
    static MODELS: OnceLock<Vec<Built>> = OnceLock::new();
    MODELS.get_or_init(|| {
        let mut all = Vec::new();
        for kind in ModelKind::ALL {
            for (rho, eta) in MEDIA {
                let model = model(kind, rho, eta, WALK_THETA, 256).unwrap();
                all.push(Built { kind, eta, model });
            }
        }
        all
    })
}

fn check(built: &Built, x: &Inputs) {
    let infinite_ok = documented_infinity(built.kind, built.eta, x.theta, x.r, x.phi);
    check_model(built.model.as_ref(), x, infinite_ok);
}

/// Inputs near θ = 0, the walk's θ and 90°, r = 0 and 1, inside θ ∈ [0, π/2] and r ∈ [0, 11]
/// otherwise (ρ′ and σ′t are not used).
fn model_inputs(selectors: [u8; 9], bits: [u64; 9]) -> Inputs {
    let nodes: [&[f64]; 3] = [
        &[0.0, 1.0],
        &[0.0, WALK_THETA, FRAC_PI_2],
        &[0.0, 1.0, 10.0],
    ];
    inputs_near(nodes, selectors, bits)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn model_lookups_at_arbitrary_inputs_are_valid(
        m in 0..ModelKind::ALL.len() * MEDIA.len(),
        selectors in any::<[u8; 9]>(),
        bits in any::<[u64; 9]>(),
    ) {
        check(&models()[m], &model_inputs(selectors, bits));
    }
}

/// Regressions: the dipole gave NaN at r = f64::MAX (e^{−σtr d} = 0 times 1 + σtr d = ∞),
/// Christensen–Burley −∞ at r = −0 (the point r = 0, where it is +∞), and both a NaN azimuth
/// for a NaN random number (now read as 0, as every azimuth sampler reads it).
#[test]
fn extreme_radii_and_nan_random_numbers() {
    let dipole = model(ModelKind::Dipole, 0.5, 1.33, WALK_THETA, 0).unwrap();
    assert_eq!(dipole.eval(0.3, f64::MAX, 0.0), 0.0);
    let burley = model(ModelKind::Burley, 0.5, 1.33, WALK_THETA, 0).unwrap();
    assert_eq!(burley.eval(0.3, -0.0, 0.0), f64::INFINITY);
    assert_eq!(burley.pdf(0.3, -0.0, 0.0), f64::INFINITY);
    for m in [dipole, burley] {
        let s = m.sample(0.3, [0.5, f64::NAN]).unwrap();
        assert_eq!(s.phi, -std::f64::consts::PI, "{}", m.kind());
    }
}
