//! The library files of the C interface tests: skin1 (η = 1.3) and coke (η = 1.33, whose blue
//! channel scatters nothing: ρ′ = 0), one table per η with θ sampling, or one table without.
//! Baked on the test's grid; under Miri, which runs a bake thousands of times slower, the
//! tables hold made-up smooth values of the same shape instead (a ρ′ = 0 row without energy,
//! θ up to π/2): the C interface's tests depend on the file, not on the physics.

use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};

use bssrdf_zoo::embed::bake_library;
use bssrdf_zoo::format::{self, Compression, FresnelMoments, LibraryBuilder, TableData};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::materials;
use bssrdf_zoo::table::{bake, Grid};

/// skin1 and coke on two tables with θ sampling, in `dir`.
pub fn scene(dir: &Path, grid: &Grid) -> PathBuf {
    let named = materials::Library::builtin();
    let (skin, coke) = (named.get("skin1").unwrap(), named.get("coke").unwrap());
    let path = dir.join("scene.bssrdf");
    if !cfg!(miri) {
        bake_library(&[skin, coke], grid)
            .unwrap()
            .write(&path)
            .unwrap();
        return path;
    }
    let mut builder = LibraryBuilder::new();
    for (t, m) in [skin, coke].into_iter().enumerate() {
        builder.add_table(made_up(m.eta(), true)).unwrap();
        builder
            .add_material(format::Material {
                name: m.id().to_owned(),
                source: String::new(),
                sigma_s: m.sigma_s(),
                sigma_a: m.sigma_a(),
                g: m.g(),
                eta: m.eta(),
                tables: [t as u32; 3],
                albedo_range: None,
            })
            .unwrap();
    }
    std::fs::write(&path, builder.to_bytes(Compression::None).unwrap()).unwrap();
    path
}

/// One table at η = 1.3 without θ sampling and no materials, in `dir`.
pub fn without_theta_sampling(dir: &Path, grid: &Grid) -> PathBuf {
    let path = dir.join("no-theta.bssrdf");
    let table = if cfg!(miri) {
        made_up(1.3, false)
    } else {
        bake(1.3, Moments::Exact, grid, false)
            .unwrap()
            .0
            .to_table_data()
    };
    let mut builder = LibraryBuilder::new();
    builder.add_table(table).unwrap();
    std::fs::write(&path, builder.to_bytes(Compression::None).unwrap()).unwrap();
    path
}

/// A 3 × 3 × 4 table of smooth made-up values: E = ρ′²·r·e^{−r}·(1 + cos θ/10), a lobe of half
/// the energy with c = 0.3 sin θ (a profile ≥ 0), its radial CDF by trapezoids along r and
/// its θ CDF by trapezoids along θ.
fn made_up(eta: f64, theta_sampling: bool) -> TableData {
    let rho = [0.0f32, 0.5, 1.0];
    let theta = [0.0, FRAC_PI_2 / 2.0, FRAC_PI_2].map(|t| t as f32);
    let r = [0.0f32, 0.05, 0.5, 5.0];
    let (mut gwc, mut cdf, mut theta_cdf) = (Vec::new(), Vec::new(), Vec::new());
    for &p in &rho {
        let mut totals = Vec::new();
        for &t in &theta {
            let e = |x: f32| p * p * x * (-x).exp() * (1.0 + 0.1 * t.cos());
            let mut running = 0.0;
            for (k, &x) in r.iter().enumerate() {
                gwc.extend([e(x), 0.5 * e(x), 0.3 * t.sin()]);
                if k > 0 {
                    running += 0.5 * (e(x) + e(r[k - 1])) * (x - r[k - 1]);
                }
                cdf.push(running);
            }
            totals.push(running);
        }
        let mut running = 0.0;
        for j in 0..theta.len() {
            if j > 0 {
                running += 0.5 * (totals[j] + totals[j - 1]) * (theta[j] - theta[j - 1]);
            }
            theta_cdf.push(running);
        }
    }
    TableData {
        model: format::ModelKind::PbdAngular,
        walk: None,
        ridge: bssrdf_zoo::table::RidgeKind::None,
        eta,
        fresnel: FresnelMoments::Exact,
        rho: rho.to_vec(),
        theta: theta.to_vec(),
        r: r.to_vec(),
        gwc,
        cdf,
        theta_cdf: theta_sampling.then_some(theta_cdf),
        harmonics: None,
        rebuild: Default::default(),
    }
}
