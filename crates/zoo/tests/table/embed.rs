//! The renderer API (`bssrdf_zoo::embed`): handles are `Send + Sync + 'static` and cheap to
//! clone; every lookup through a handle equals, bit for bit, the same lookup through a
//! `TableRef` made directly from the file (`FileTable`) and the crate's `World` conversion;
//! handles outlive their library; every failure to open or to make a handle is its own error.
//! Allocation counts are in `crates/capi/tests/embed_alloc.rs` (a binary of its own: it replaces the
//! global allocator).

use std::f64::consts::{FRAC_PI_2, PI};

use bssrdf_zoo::embed::{bake_library, ChannelLookup, EmbedError, Library, TableLookup};
use bssrdf_zoo::format::{self, Verify};
use bssrdf_zoo::materials::{self, Rgb};
use bssrdf_zoo::rng::{RngCore, SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{reduced_to_mm, FileTable, Grid, RidgeKind, TableRef, World};

/// Two materials on two η (two tables), baked on a small grid and written to a file.
fn baked(dir: &std::path::Path) -> std::path::PathBuf {
    let named = materials::Library::builtin();
    let skin = named.get("skin1").unwrap();
    let espresso = named.get("espresso").unwrap();
    assert_ne!(skin.eta(), espresso.eta(), "the test wants two tables");
    let path = dir.join("two.bssrdf");
    bake_library(&[skin, espresso], Grid::ferrier(12, 5, 16))
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
        let mut points = Points(SplitMix64::seed_from_u64(11));
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
                            [w.r, w.phi, w.pdf].map(f64::to_bits)
                        );
                    }
                    let u = [points.u(), points.u(), points.u(), points.u()];
                    let got = handle.sample_path(u);
                    let want = world.sample_path(rho, u);
                    assert_eq!(got.is_some(), want.is_some());
                    if let (Some(g), Some(w)) = (got, want) {
                        compared[2] += 1;
                        assert_eq!(
                            [g.theta, g.r, g.phi, g.phi_prime, g.pdf_theta, g.pdf]
                                .map(f64::to_bits),
                            [w.theta, w.r, w.phi, w.phi_prime, w.pdf_theta, w.pdf]
                                .map(f64::to_bits)
                        );
                        // World units: r scales with 1/σ′t (rounded so that σ′t·r_mm ≤ r),
                        // the area density with σ′t².
                        let reduced = view.sample_path(rho, u).unwrap();
                        assert_eq!(w.r, reduced_to_mm(reduced.r, st));
                        if st * w.r == reduced.r {
                            assert_eq!(w.pdf, reduced.pdf * st * st);
                        }
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
    let mut points = Points(SplitMix64::seed_from_u64(5));
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

/// A table whose record sets `ridge` (format 1.6: 1, or 2 with the fluence part) gives views
/// of that kind, however the library is opened and whichever handle makes them, as a
/// `FileTable` of the record does; a table without it gives views without.
#[test]
fn views_carry_the_ridge_flag_of_the_record() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/valid");
    for (name, ridge) in [
        ("ridge", RidgeKind::Flux),
        ("ridge-fluence", RidgeKind::FluxAndFluence),
        ("tiny", RidgeKind::None),
        ("walk-table", RidgeKind::None),
    ] {
        let path = data.join(format!("{name}.bssrdf"));
        let header_only = format::Library::read(&path, Verify::HeaderOnly).unwrap();
        for library in [
            Library::open_mmap(&path).unwrap(),
            Library::read(&path).unwrap(),
            Library::from_format(header_only).unwrap(),
        ] {
            assert_eq!(library.view(0).unwrap().ridge(), ridge, "{name}");
            let table = library.table(0).unwrap();
            assert_eq!(table.view().ridge(), ridge, "{name}");
            // A medium's lookups go through the view its table makes
            let medium = table.medium(0.5, 1.0).unwrap();
            assert_eq!(medium.table().view().ridge(), ridge, "{name}");
            assert!(library.tables().all(|t| t.view().ridge() == ridge));
            let record = library.format().table(0).unwrap();
            assert_eq!(record.ridge(), ridge, "{name}");
            let direct = FileTable::new(record).unwrap();
            assert_eq!(direct.view().unwrap().ridge(), ridge, "{name}");
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

/// Every lookup of every channel of `library` at `rounds` points drawn from `seed`, as bits
/// (`u64::MAX` for a `None`).
fn every_lookup(library: &Library, seed: u64, rounds: usize) -> Vec<u64> {
    let mut points = Points(SplitMix64::seed_from_u64(seed));
    let mut out = Vec::new();
    let none = u64::MAX;
    for m in library.materials() {
        for rgb in Rgb::ALL {
            let h = library.channel(&m.name, rgb).unwrap();
            for _ in 0..rounds {
                let (theta, r, phi) = (
                    points.theta(),
                    points.r(1.0 / h.sigma_t_prime()),
                    points.phi(),
                );
                let u = [points.u(), points.u(), points.u(), points.u()];
                out.push(bits(h.eval(theta, r, phi)).unwrap_or(none));
                out.push(h.pdf(theta, r, phi).to_bits());
                out.push(h.pdf_theta(theta).to_bits());
                out.push(bits(h.effective_albedo(theta)).unwrap_or(none));
                match h.sample(theta, u[0], u[1]) {
                    Some(s) => out.extend([s.r, s.phi, s.pdf].map(f64::to_bits)),
                    None => out.push(none),
                }
                match h.sample_path(u) {
                    Some(p) => out.extend(
                        [p.theta, p.r, p.phi, p.phi_prime, p.pdf_theta, p.pdf].map(f64::to_bits),
                    ),
                    None => out.push(none),
                }
            }
        }
    }
    out
}

#[test]
fn many_threads_sharing_one_mapped_library_compute_what_one_thread_does() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let library = Library::open_mmap(&path).unwrap();
    let (threads, rounds) = (8, 400);
    // Each thread its own stream of points, first on this thread alone.
    let serial: Vec<Vec<u64>> = (0..threads)
        .map(|t| every_lookup(&library, t, rounds))
        .collect();
    // Then all at once, twice over: threads borrowing the library, and threads owning clones.
    let borrowed: Vec<Vec<u64>> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                let library = &library;
                scope.spawn(move || every_lookup(library, t, rounds))
            })
            .collect();
        workers.into_iter().map(|w| w.join().unwrap()).collect()
    });
    assert!(
        borrowed == serial,
        "borrowed handles differ from one thread's"
    );
    let owned: Vec<Vec<u64>> = (0..threads)
        .map(|t| {
            let library = library.clone();
            std::thread::spawn(move || every_lookup(&library, t, rounds))
        })
        .collect::<Vec<_>>()
        .into_iter()
        .map(|w| w.join().unwrap())
        .collect();
    assert!(owned == serial, "cloned handles differ from one thread's");
}

/// The child half of the truncation test below: opens the file named by
/// `BSSRDF_TRUNCATION_CHILD` (mapped, or read if `BSSRDF_TRUNCATION_READ` is set), says
/// "open", waits for a line on its standard input, then reads every byte of the library
/// again and says "survived".
#[test]
#[ignore = "the child process of a_file_truncated_under_a_map_kills_the_reader_with_sigbus"]
fn truncation_child() {
    use std::io::{BufRead, Write};
    let Ok(path) = std::env::var("BSSRDF_TRUNCATION_CHILD") else {
        return;
    };
    let library = match std::env::var_os("BSSRDF_TRUNCATION_READ") {
        Some(_) => Library::read(&path),
        None => Library::open_mmap(&path),
    }
    .unwrap();
    println!("open");
    std::io::stdout().flush().unwrap();
    let mut line = String::new();
    std::io::stdin().lock().read_line(&mut line).unwrap();
    // Every section again: the CRCs read every byte of the file.
    library.format().verify().unwrap();
    println!("survived");
}

/// What the documentation says of a map (`embed::Library::open_mmap`, docs/reliability.md):
/// another process truncating the file kills the reader with SIGBUS at its next touch of a
/// lost page; a library read into memory (`Library::read`) does not notice.
#[cfg(target_os = "linux")]
#[test]
#[cfg_attr(miri, ignore = "Miri runs no child processes")]
fn a_file_truncated_under_a_map_kills_the_reader_with_sigbus() {
    use std::io::{BufRead, BufReader, Write};
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};
    /// SIGBUS on Linux.
    const SIGBUS: i32 = 7;
    let dir = tempfile::tempdir().unwrap();
    for read in [false, true] {
        let path = baked(dir.path());
        let mut child = Command::new(std::env::current_exe().unwrap())
            .args([
                "--ignored",
                "--exact",
                "embed::truncation_child",
                "--nocapture",
            ])
            .env("BSSRDF_TRUNCATION_CHILD", &path)
            .envs(read.then_some(("BSSRDF_TRUNCATION_READ", "1")))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut stdout = BufReader::new(child.stdout.take().unwrap());
        let mut line = String::new();
        while line.trim() != "open" {
            line.clear();
            assert!(
                stdout.read_line(&mut line).unwrap() > 0,
                "the child never opened"
            );
        }
        // Another process (this one) truncates the file the child holds.
        std::fs::OpenOptions::new()
            .write(true)
            .open(&path)
            .unwrap()
            .set_len(0)
            .unwrap();
        writeln!(child.stdin.take().unwrap()).unwrap();
        let mut rest = String::new();
        std::io::Read::read_to_string(&mut stdout, &mut rest).unwrap();
        let status = child.wait().unwrap();
        if read {
            assert!(
                status.success() && rest.contains("survived"),
                "{status:?} {rest}"
            );
        } else {
            assert_eq!(status.signal(), Some(SIGBUS), "{status:?} {rest}");
        }
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

    let err = bake_library(&[], Grid::ferrier(6, 4, 10)).map(|l| l.table_count());
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
    let library = bake_library(&[&skin], &grid).unwrap();
    // skin1's red channel has ρ′ = 0.96, its blue one 0.68.
    assert!(library.channel("skin1", Rgb::Red).is_ok());
    let err = library.channel("skin1", Rgb::Blue).unwrap_err();
    let EmbedError::AlbedoOutsideTable { rho, min, max, .. } = &err else {
        panic!("{err}");
    };
    // The albedos the lookups take: the rows, widened by f32 rounding
    let (first, last) = (f64::from(0.9f32), f64::from(0.99f32));
    assert!(*rho < *min && *min < first && first - *min < 1e-7, "{min}");
    assert!(*max > last && *max - last < 1e-7, "{max}");
    assert!(err.to_string().contains("channel blue"), "{err}");
}

#[test]
fn every_lookup_outside_the_theta_axis_is_none_and_densities_are_zero() {
    let skin = materials::Library::builtin().get("skin1").unwrap().clone();
    let library = bake_library(&[&skin], Grid::ferrier(6, 4, 10)).unwrap();
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
