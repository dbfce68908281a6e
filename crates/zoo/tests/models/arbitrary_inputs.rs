//! Every registered model at arbitrary inputs — θ, r, φ and the random numbers anywhere in f64,
//! NaN, ±∞, subnormals and ±0 included — for albedos and η at the ends of their domains
//! (`bssrdf_testkit::models::zoo`): no panic, `eval` and `pdf` ≥ 0 and never NaN (+∞ only where
//! documented), and a draw either `None` or a valid point whose density is `pdf`'s
//! (`bssrdf_testkit::lookups`, the rules the fuzz target `fuzz/fuzz_targets/lookups.rs` holds too).

use std::sync::OnceLock;

use bssrdf_zoo::models::ModelKind;
use proptest::prelude::*;

use bssrdf_testkit::lookups::{check_model, model_inputs};
use bssrdf_testkit::models::{documented_infinity, model, zoo, Built, MEDIA, WALK_THETA};

fn models() -> &'static [Built] {
    static MODELS: OnceLock<Vec<Built>> = OnceLock::new();
    MODELS.get_or_init(zoo)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn model_lookups_at_arbitrary_inputs_are_valid(
        m in 0..ModelKind::ALL.len() * MEDIA.len(),
        selectors in any::<[u8; 9]>(),
        bits in any::<[u64; 9]>(),
    ) {
        let built = &models()[m];
        let x = model_inputs(WALK_THETA, selectors, bits);
        let infinite_ok = documented_infinity(built.kind, built.eta, x.theta, x.r, x.phi);
        check_model(built.model.as_ref(), &x, infinite_ok);
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
