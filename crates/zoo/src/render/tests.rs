//! Unit tests of the renderer's parts (the physics checks are in `crates/zoo/tests/models/render.rs`).

use super::*;
use crate::table::bake;

fn coarse_table() -> AngularTable {
    bake(
        1.33,
        Moments::Exact,
        &crate::table::Grid::preset(GridPreset::Coarse),
        false,
    )
    .unwrap()
    .0
}

#[test]
fn the_theta_zero_density_is_the_perpendicular_models() {
    // `place` weights perpendicular samples with `pdf(ρ′, 0, r, φ)`: at the θ = 0 node the
    // stored concentration is 0 and the profile is flat, so this must be the density of
    // `sample_perpendicular` at any φ.
    let table = coarse_table();
    let t = table.view();
    for rho in [0.3, 0.9, 0.99] {
        for (u_r, u_phi) in [(0.1, 0.2), (0.5, 0.9), (0.97, 0.4), (0.999, 0.01)] {
            let s = t.sample_perpendicular(rho, u_r, u_phi).unwrap();
            for phi in [s.phi, 0.0, 2.5, -1.0] {
                let p = t.pdf(rho, 0.0, s.r, phi);
                assert!(
                    (p / s.pdf - 1.0).abs() < 1e-6,
                    "rho {rho}, r {}, phi {phi}: {p} vs {}",
                    s.r,
                    s.pdf
                );
            }
        }
    }
}

#[test]
fn configurations_are_checked_and_name_the_value() {
    let ok = Config::new(ModelKind::Table, 1.0);
    assert!(ok.validate().is_ok());
    let bad = |f: &dyn Fn(&mut Config), needle: &str| {
        let mut c = ok.clone();
        f(&mut c);
        let e = c.validate().unwrap_err().to_string();
        assert!(e.contains(needle), "{e}");
    };
    bad(&|c| c.theta = -0.1, "theta = -0.1");
    bad(&|c| c.theta = f64::NAN, "theta = NaN");
    bad(&|c| c.cone = 2.0, "cone = 2");
    bad(&|c| c.theta = 1.56, "below 90 deg");
    bad(&|c| c.photons = 0, "photons = 0");
    bad(&|c| c.width = 0, "0x256");
    bad(&|c| c.height = MAX_SIDE + 1, "256x4097");
    bad(&|c| c.extent = 0.0, "extent = 0");
    bad(&|c| c.extent = f64::INFINITY, "extent = inf");
}

#[test]
fn figure_10_material_has_the_papers_coefficients() {
    let m = figure_10_material();
    assert_eq!(m.sigma_s(), [1.0; 3]);
    assert_eq!(m.sigma_a(), [0.01, 0.1, 1.0]);
    assert_eq!(m.g(), [0.0; 3]);
    assert_eq!(m.eta(), 1.33);
}

fn picture(values: &[f32], width: usize, extent: f64) -> Picture {
    let frame = Frame::new(width, values.len() / 3 / width, extent);
    let meta = vec![(format!("{META_PREFIX}model"), "test".to_string())];
    Picture::new(frame, values.to_vec(), meta).unwrap()
}

#[test]
fn differences_give_signed_luminance_norms_and_centroids() {
    // Two pixels across 2 mm: centres at x = −0.5 and +0.5.
    let a = picture(&[1.0, 1.0, 1.0, 3.0, 0.0, 0.0], 2, 2.0);
    let b = picture(&[2.0, 0.0, 0.0, 1.0, 0.0, 0.0], 2, 2.0);
    let d = difference(&a, &b).unwrap();
    assert_eq!(d.values(), &[1.0, 2.0]);
    assert!((d.relative_l1 - 1.0).abs() < 1e-12);
    assert!((d.relative_l2 - (5.0f64 / 5.0).sqrt()).abs() < 1e-12);
    assert!((d.centroid_a_mm - 0.0).abs() < 1e-12);
    assert!((d.centroid_b_mm - (-1.0 + 0.5) / 3.0).abs() < 1e-12);
    assert!((d.centroid_shift_mm() - 1.0 / 6.0).abs() < 1e-12);
    assert!(d
        .meta()
        .iter()
        .any(|(k, v)| k == "bssrdf:a:model" && v == "test"));
    let same = difference(&a, &a).unwrap();
    assert_eq!(same.relative_l1, 0.0);
    assert_eq!(same.centroid_shift_mm(), 0.0);
}

#[test]
fn differences_refuse_mismatched_or_empty_pictures() {
    let a = picture(&[1.0; 6], 2, 2.0);
    let wide = picture(&[1.0; 6], 2, 3.0);
    let tall = picture(&[1.0; 6], 1, 2.0);
    let dark = picture(&[0.0; 6], 2, 2.0);
    let e = difference(&a, &wide).unwrap_err().to_string();
    assert!(e.contains("extent") && e.contains('3'), "{e}");
    let e = difference(&a, &tall).unwrap_err().to_string();
    assert!(e.contains("2x1") && e.contains("1x2"), "{e}");
    let e = difference(&a, &dark).unwrap_err().to_string();
    assert!(e.contains("no energy"), "{e}");
    assert!(Picture::new(Frame::new(2, 2, 1.0), vec![0.0; 5], Vec::new()).is_err());
}

#[test]
fn every_photon_is_counted_and_blocks_cover_the_run() {
    // A run that is not a whole number of blocks: photons and reflected power add up.
    let config = Config {
        photons: block(ModelKind::Perpendicular) + 7,
        width: 8,
        height: 8,
        grid: GridPreset::Coarse,
        cone: 0.0,
        ..Config::new(ModelKind::Perpendicular, 0.5)
    };
    let r = render(&config, &figure_10_material(), &|_| ()).unwrap();
    assert_eq!(r.stats.photons, block(ModelKind::Perpendicular) + 7);
    assert_eq!(r.stats.lost_samples, 0);
    let expected = crate::fresnel::reflectance(0.5f64.cos(), 1.33);
    assert!((r.stats.reflected.value - expected).abs() < 1e-12);
    assert!(r.stats.reflected.stderr < 1e-12);
    assert_eq!(r.picture.get("bssrdf:theta_deg"), Some("28.647889757"));
}

/// The registry's models outside [`MODELS`] are refused by name, with the ones a render draws.
#[test]
fn a_model_a_render_cannot_draw_is_refused_by_name() {
    for model in ModelKind::ALL {
        let result = Config::new(model, 1.0).validate();
        if MODELS.contains(&model) {
            assert!(result.is_ok(), "{model}: {result:?}");
        } else {
            let message = result.unwrap_err().to_string();
            assert!(message.contains(model.name()), "{message}");
            assert!(
                message.contains("table, perpendicular, pbd, walk-table, mc"),
                "{message}"
            );
        }
    }
}
