//! The renderer API (`bssrdf_zoo::embed`): handles are `Send + Sync + 'static` and cheap to
//! clone; every lookup through a handle equals, bit for bit, the same lookup through a
//! `TableRef` made directly from the file (`FileTable`) and the crate's `World` conversion;
//! handles outlive their library; every failure to open or to make a handle is its own error.
//! Allocation counts are in `tests/embed_alloc.rs` (a binary of its own: it replaces the
//! global allocator).

use std::f64::consts::{FRAC_PI_2, PI};

use bssrdf_zoo::embed::{ChannelLookup, EmbedError, Library, TableLookup};
use bssrdf_zoo::format::{self, Verify};
use bssrdf_zoo::materials::{self, Rgb};
use bssrdf_zoo::rng::SplitMix64;
use bssrdf_zoo::table::{reduced_to_mm, FileTable, Grid, TableRef, World};

/// Two materials on two η (two tables), baked on a small grid and written to a file.
fn baked(dir: &std::path::Path) -> std::path::PathBuf {
    let named = materials::Library::builtin();
    let skin = named.get("skin1").unwrap();
    let espresso = named.get("espresso").unwrap();
    assert_ne!(skin.eta(), espresso.eta(), "the test wants two tables");
    let path = dir.join("two.bssrdf");
    Library::bake(&[skin, espresso], &Grid::ferrier(12, 5, 16))
        .unwrap()
        .write(&path)
        .unwrap();
    path
}

fn assert_send_sync_static<T: Send + Sync + Clone + 'static>() {}

#[test]
fn handles_are_send_sync_static_and_one_arc_to_clone() {
    assert_send_sync_static::<Library>();
    assert_send_sync_static::<TableLookup>();
    assert_send_sync_static::<ChannelLookup>();
    // Library and TableLookup are an `Arc` (and an index); a channel adds ρ′ and σ′t.
    assert!(std::mem::size_of::<Library>() <= 8);
    assert!(std::mem::size_of::<TableLookup>() <= 16);
    assert!(std::mem::size_of::<ChannelLookup>() <= 32);
}

/// Random lookup arguments, with a share of edge cases: θ just outside [0, π/2] and NaN, r
/// negative, zero, beyond the table and NaN, φ beyond ±π and NaN.
struct Points(SplitMix64);

impl Points {
    fn theta(&mut self) -> f64 {
        match self.0.next_u64() % 16 {
            0 => -1e-9,
            1 => FRAC_PI_2 + 1e-6,
            2 => f64::NAN,
            3 => 0.0,
            4 => FRAC_PI_2,
            _ => FRAC_PI_2 * self.0.next_f64(),
        }
    }
    fn r(&mut self, scale: f64) -> f64 {
        match self.0.next_u64() % 16 {
            0 => -0.5,
            1 => 0.0,
            2 => 1e6,
            3 => f64::NAN,
            _ => scale * (-8.0 * self.0.next_f64()).exp() * 20.0,
        }
    }
    fn phi(&mut self) -> f64 {
        match self.0.next_u64() % 16 {
            0 => 7.0,
            1 => f64::NAN,
            2 => -PI,
            _ => PI * (2.0 * self.0.next_f64() - 1.0),
        }
    }
    fn u(&mut self) -> f64 {
        self.0.next_f64()
    }
}

fn bits(x: Option<f64>) -> Option<u64> {
    x.map(f64::to_bits)
}

#[test]
fn channel_lookups_equal_direct_table_ref_and_world_lookups_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let file = format::Library::open_mmap(&path, Verify::Full).unwrap();
    for library in [
        Library::open_mmap(&path).unwrap(),
        Library::read(&path).unwrap(),
    ] {
        let mut points = Points(SplitMix64::new(11));
        let mut compared = [0usize; 3]; // values, samples, path samples that were Some
        for m in library.materials() {
            for rgb in Rgb::ALL {
                let handle = library.channel(&m.name, rgb).unwrap();
                let c = rgb.index();
                let medium =
                    bssrdf_zoo::medium::Medium::new(m.sigma_s[c], m.sigma_a[c], m.g[c], m.eta)
                        .unwrap();
                let (rho, st) = (medium.rho_prime(), medium.sigma_t_prime());
                assert_eq!(handle.rho_prime().to_bits(), rho.to_bits());
                assert_eq!(handle.sigma_t_prime().to_bits(), st.to_bits());
                let direct = FileTable::new(file.table(m.tables[c] as usize).unwrap()).unwrap();
                let view: TableRef<'_> = direct.view().unwrap();
                let world = World::new(view, st).unwrap();
                for _ in 0..400 {
                    let (theta, r, phi) = (points.theta(), points.r(1.0 / st), points.phi());
                    compared[0] += usize::from(handle.eval(theta, r, phi).is_some_and(|v| v > 0.0));
                    assert_eq!(
                        bits(handle.eval(theta, r, phi)),
                        bits(world.eval(rho, theta, r, phi)),
                        "eval {theta} {r} {phi}"
                    );
                    assert_eq!(
                        handle.pdf(theta, r, phi).to_bits(),
                        world.pdf(rho, theta, r, phi).to_bits()
                    );
                    let (u_r, u_phi) = (points.u(), points.u());
                    let got = handle.sample(theta, u_r, u_phi);
                    let want = world.sample(rho, theta, u_r, u_phi);
                    assert_eq!(got.is_some(), want.is_some(), "sample at θ = {theta}");
                    if let (Some(g), Some(w)) = (got, want) {
                        compared[1] += 1;
                        assert_eq!(
                            [g.r, g.phi, g.pdf].map(f64::to_bits),
                            [w.r, w.phi, w.pdf_area].map(f64::to_bits)
                        );
                    }
                    let u = [points.u(), points.u(), points.u(), points.u()];
                    let got = handle.sample_path(u);
                    let want = view.sample_path(rho, u);
                    assert_eq!(got.is_some(), want.is_some());
                    if let (Some(g), Some(w)) = (got, want) {
                        compared[2] += 1;
                        // World units: r scales with 1/σ′t (rounded so that σ′t·r_mm ≤ r),
                        // the area density with σ′t².
                        assert_eq!(
                            [g.theta, g.r, g.phi, g.phi_prime, g.pdf_theta, g.pdf]
                                .map(f64::to_bits),
                            [
                                w.theta,
                                reduced_to_mm(w.r, st),
                                w.phi,
                                w.phi_prime,
                                w.pdf_theta,
                                w.pdf * st * st
                            ]
                            .map(f64::to_bits)
                        );
                    }
                    assert_eq!(
                        handle.pdf_theta(theta).to_bits(),
                        view.pdf_theta(rho, theta).to_bits()
                    );
                    assert_eq!(
                        bits(handle.effective_albedo(theta)),
                        bits(view.effective_albedo(rho, theta))
                    );
                }
            }
        }
        // 2 materials × 3 channels × 400 points: most lookups are inside the table and positive.
        assert!(compared.iter().all(|&n| n > 1000), "{compared:?}");
    }
}

#[test]
fn table_views_equal_file_table_views_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let file = format::Library::open_mmap(&path, Verify::Full).unwrap();
    let library = Library::open_mmap(&path).unwrap();
    assert_eq!(library.table_count(), 2);
    let mut points = Points(SplitMix64::new(5));
    for (table, record) in library.tables().zip(file.tables()) {
        let direct = FileTable::new(record).unwrap();
        let (a, b) = (table.view(), direct.view().unwrap());
        assert_eq!(a.eta().to_bits(), b.eta().to_bits());
        assert_eq!(a.axes(), b.axes());
        for _ in 0..2000 {
            let rho = match points.0.next_u64() % 8 {
                0 => 1.0 + 1e-9,
                1 => f64::NAN,
                _ => points.u(),
            };
            let (theta, r, phi) = (points.theta(), points.r(1.0), points.phi());
            assert_eq!(
                bits(a.eval(rho, theta, r, phi)),
                bits(b.eval(rho, theta, r, phi))
            );
            assert_eq!(
                bits(a.eval_perpendicular(rho, r)),
                bits(b.eval_perpendicular(rho, r))
            );
            let (u_r, u_phi) = (points.u(), points.u());
            assert_eq!(
                a.sample(rho, theta, u_r, u_phi),
                b.sample(rho, theta, u_r, u_phi)
            );
            assert_eq!(
                a.pdf(rho, theta, r, phi).to_bits(),
                b.pdf(rho, theta, r, phi).to_bits()
            );
        }
    }
}

#[test]
fn handles_outlive_their_library_and_work_from_many_threads() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let library = Library::open_mmap(&path).unwrap();
    let green = library.channel("skin1", Rgb::Green).unwrap();
    let thetas: Vec<f64> = (0..64).map(|k| FRAC_PI_2 * k as f64 / 63.0).collect();
    let serial: Vec<u64> = thetas
        .iter()
        .map(|&t| green.eval(t, 0.7, 0.4).unwrap().to_bits())
        .collect();
    drop(library);
    let workers: Vec<_> = (0..4)
        .map(|_| {
            let (green, thetas) = (green.clone(), thetas.clone());
            std::thread::spawn(move || {
                thetas
                    .iter()
                    .map(|&t| green.eval(t, 0.7, 0.4).unwrap().to_bits())
                    .collect::<Vec<u64>>()
            })
        })
        .collect();
    for w in workers {
        assert_eq!(w.join().unwrap(), serial);
    }
}

#[test]
fn each_failure_is_its_own_error_naming_the_value() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let library = Library::open_mmap(&path).unwrap();

    let err = library.channel("skin2", Rgb::Red).unwrap_err();
    assert!(matches!(err, EmbedError::NoMaterial { .. }), "{err}");
    assert!(err.to_string().contains("\"skin1\", \"espresso\""), "{err}");

    let err = library.table(2).unwrap_err();
    assert!(
        matches!(err, EmbedError::NoTable { index: 2, count: 2 }),
        "{err}"
    );

    let table = library.table(0).unwrap();
    // Beyond 1e12 mm⁻¹ the world-unit factor σ′t² heads for ∞ (∞·0 = NaN), below 1e-9 for 0.
    for st in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-10, 1.1e12, 1e300] {
        let err = table.medium(0.5, st).unwrap_err();
        assert!(matches!(err, EmbedError::Medium { .. }), "{err}");
    }
    for rho in [-0.1, 1.0 + 1e-12, f64::NAN] {
        let err = table.medium(rho, 1.0).unwrap_err();
        assert!(
            matches!(err, EmbedError::AlbedoOutsideTable { .. }),
            "{err}"
        );
    }

    let missing = dir.path().join("missing.bssrdf");
    let err = Library::open_mmap(&missing).unwrap_err();
    assert!(matches!(
        err,
        EmbedError::Format(format::FormatError::Io { .. })
    ));
    let junk = dir.path().join("junk.bssrdf");
    std::fs::write(&junk, vec![7u8; 4096]).unwrap();
    let err = Library::read(&junk).unwrap_err();
    assert!(
        matches!(
            err,
            EmbedError::Format(format::FormatError::BadMagic { .. })
        ),
        "{err}"
    );

    let err = Library::bake(&[], &Grid::ferrier(6, 4, 10)).map(|l| l.table_count());
    assert_eq!(
        err.unwrap(),
        0,
        "no materials, no tables: an empty library is valid"
    );
}

#[test]
fn a_scene_bake_keeping_some_albedo_rows_rejects_media_outside_them() {
    let skin = materials::Library::builtin().get("skin1").unwrap().clone();
    let grid = Grid {
        rho: vec![0.9, 0.93, 0.96, 0.99],
        ..Grid::ferrier(6, 4, 10)
    };
    let library = Library::bake(&[&skin], &grid).unwrap();
    // skin1's red channel has ρ′ = 0.96, its blue one 0.68.
    assert!(library.channel("skin1", Rgb::Red).is_ok());
    let err = library.channel("skin1", Rgb::Blue).unwrap_err();
    let EmbedError::AlbedoOutsideTable { rho, min, max, .. } = &err else {
        panic!("{err}");
    };
    assert!(*rho < *min && *min == f64::from(0.9f32) && *max == f64::from(0.99f32));
    assert!(err.to_string().contains("channel blue"), "{err}");
}

#[test]
fn every_lookup_outside_the_theta_axis_is_none_and_densities_are_zero() {
    let skin = materials::Library::builtin().get("skin1").unwrap().clone();
    let library = Library::bake(&[&skin], &Grid::ferrier(6, 4, 10)).unwrap();
    let red = library.channel("skin1", Rgb::Red).unwrap();
    for theta in [-0.1, 1.6, f64::NAN, f64::INFINITY] {
        assert_eq!(red.eval(theta, 1.0, 0.0), None);
        assert_eq!(red.sample(theta, 0.5, 0.5), None);
        assert_eq!(red.effective_albedo(theta), None);
        assert_eq!(red.pdf(theta, 1.0, 0.0), 0.0);
        assert_eq!(red.pdf_theta(theta), 0.0);
    }
    assert!(red.eval(FRAC_PI_2, 1.0, 0.0).is_some());
}
