//! The C interface from a C program: `crates/capi/tests/c/capi_test.c`, `examples/c/capi_example.c`
//! and `examples/c/separable_step.c`
//! are compiled with the system C compiler (`$CC`, else `cc`) against `include/bssrdf_zoo.h`
//! with `-Wall -Wextra -Werror -pedantic`, linked with `libbssrdf.a`, and run on a
//! library baked here. The test writes the values the Rust API computes into a file; the C
//! program must find the same statuses and the same bits.
//!
//! How the static library is built: `cargo test` compiles the crate's `staticlib` (the crate
//! type is in Cargo.toml) but keeps it in `deps/` under a name another profile may overwrite.
//! So this test asks Cargo for it: `$CARGO build --lib --test capi --profile P
//! --message-format=json` with the profile and target folder of the running test (`test`
//! under `target/debug`, `release` under `target/release`), and takes the `.a` path from
//! Cargo's report. Naming this test target makes the build resolve features exactly as
//! `cargo test` did, so the library unit is the one just built and Cargo finds it fresh: no
//! second compile. Cargo also copies the library to `target/<profile>/libbssrdf.a`.
//! Without a C compiler the tests pass after saying they skipped.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use bssrdf::{
    BSSRDF_ERROR_INVALID_ARGUMENT, BSSRDF_ERROR_NOT_FOUND, BSSRDF_ERROR_NO_SAMPLE,
    BSSRDF_ERROR_OUT_OF_RANGE, BSSRDF_OK,
};
use bssrdf_zoo::embed::{bake_library, ChannelLookup, Library};
use bssrdf_zoo::materials::{self, Rgb};
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{Grid, GridPreset};

fn compiler() -> Option<String> {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_owned());
    if Command::new(&cc).arg("--version").output().is_err() {
        eprintln!(
            "SKIPPED: no C compiler found (tried `{cc}`); the C interface was not tested from C"
        );
        return None;
    }
    Some(cc)
}

/// The target folder and the Cargo profile this test binary was built with, from its path
/// `<target>/[<triple>/]<debug|release|custom>/deps/<test>`.
fn target_and_profile() -> (PathBuf, String) {
    let exe = std::env::current_exe().unwrap();
    let profile_dir = exe.parent().and_then(Path::parent).unwrap();
    let profile = match profile_dir.file_name().and_then(|n| n.to_str()) {
        Some("debug") => "test".to_owned(),
        Some("release") => "release".to_owned(),
        Some(custom) => custom.to_owned(),
        None => "test".to_owned(),
    };
    let mut target = profile_dir.parent().unwrap().to_path_buf();
    // Cross builds put a target triple between the target folder and the profile folder.
    if !target.join("CACHEDIR.TAG").exists()
        && target
            .parent()
            .is_some_and(|p| p.join("CACHEDIR.TAG").exists())
    {
        target = target.parent().unwrap().to_path_buf();
    }
    (target, profile)
}

/// Builds the crate's static library once per test run and returns its path.
fn static_library() -> &'static Path {
    static LIBRARY: OnceLock<PathBuf> = OnceLock::new();
    LIBRARY.get_or_init(|| {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
        let (target, profile) = target_and_profile();
        let out = Command::new(cargo)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .args(["build", "--lib", "--test", env!("CARGO_CRATE_NAME")])
            .args(["--message-format=json-render-diagnostics", "--profile"])
            .arg(&profile)
            .arg("--target-dir")
            .arg(&target)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "cargo build --lib failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let stdout = String::from_utf8(out.stdout).unwrap();
        let mut found = None;
        for line in stdout.lines() {
            let Ok(message) = serde_json::from_str::<serde_json::Value>(line) else {
                continue;
            };
            if message["reason"] == "compiler-artifact" && message["target"]["name"] == "bssrdf" {
                found = message["filenames"]
                    .as_array()
                    .into_iter()
                    .flatten()
                    .filter_map(|f| f.as_str())
                    .find(|f| f.ends_with(".a") || f.ends_with(".lib"))
                    .map(PathBuf::from);
            }
        }
        found.expect("cargo reported no static library for bssrdf")
    })
}

/// The system libraries Rust's standard library needs in a static link
/// (`rustc --print native-static-libs`).
fn system_libraries() -> &'static [&'static str] {
    if cfg!(target_os = "linux") {
        &[
            "-lgcc_s",
            "-lutil",
            "-lrt",
            "-lpthread",
            "-lm",
            "-ldl",
            "-lc",
        ]
    } else if cfg!(target_os = "macos") {
        &["-lSystem", "-lc", "-lm"]
    } else {
        &["-lpthread", "-lm"]
    }
}

/// The flags that build a C program under AddressSanitizer and UndefinedBehaviorSanitizer,
/// every report fatal (`-fno-sanitize-recover`).
const SANITIZERS: [&str; 4] = [
    "-fsanitize=address,undefined",
    "-fno-sanitize-recover=all",
    "-fno-omit-frame-pointer",
    "-g",
];

/// Whether `cc` builds and runs a program under [`SANITIZERS`] (their runtime libraries are
/// a separate package on some systems).
fn sanitizers_work(cc: &str, dir: &Path) -> bool {
    let source = dir.join("probe.c");
    std::fs::write(&source, "int main(void) { return 0; }\n").unwrap();
    let exe = dir.join("probe");
    let built = Command::new(cc)
        .args(SANITIZERS)
        .arg(&source)
        .arg("-o")
        .arg(&exe)
        .output()
        .is_ok_and(|o| o.status.success());
    built && Command::new(&exe).status().is_ok_and(|s| s.success())
}

/// Compiles one C source file against the header and the static library, with
/// [`SANITIZERS`] if `sanitize`.
fn compile(cc: &str, source: &str, exe: &Path, sanitize: bool) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Command::new(cc)
        .args([
            "-std=c99",
            "-O2",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
        ])
        .args(if sanitize { &SANITIZERS[..] } else { &[] })
        .arg("-I")
        .arg(root.join("../../include"))
        .arg(root.join(source))
        .arg(static_library())
        .args(system_libraries())
        .arg("-o")
        .arg(exe)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{cc} {source} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// skin1 (η = 1.3) and coke (η = 1.33, blue ρ′ = 0) on the coarse grid, written to `dir`.
fn bake(dir: &Path) -> (Library, PathBuf) {
    let named = materials::Library::builtin();
    let (skin, coke) = (named.get("skin1").unwrap(), named.get("coke").unwrap());
    let library = bake_library(&[skin, coke], Grid::preset(GridPreset::Coarse)).unwrap();
    let path = dir.join("scene.bssrdf");
    library.write(&path).unwrap();
    (library, path)
}

fn hex(x: f64) -> String {
    format!("{:016x}", x.to_bits())
}

/// Status and values of an optional lookup, as the C interface reports them.
fn line_values(status_if_none: i32, values: Option<Vec<f64>>, width: usize) -> String {
    match values {
        Some(v) => format!(
            "{BSSRDF_OK} {}",
            v.iter().map(|&x| hex(x)).collect::<Vec<_>>().join(" ")
        ),
        None => format!("{status_if_none} {}", vec![hex(0.0); width].join(" ")),
    }
}

/// The expectations file (format in `crates/capi/tests/c/capi_test.c`): what the Rust API computes.
fn expectations(library: &Library) -> String {
    let mut text = String::new();
    let mut rng = SplitMix64::seed_from_u64(2024);
    // Failing channel requests first: an unknown name and an invalid channel.
    writeln!(text, "M skin2 0 {BSSRDF_ERROR_NOT_FOUND}").unwrap();
    writeln!(text, "M skin1 7 {BSSRDF_ERROR_INVALID_ARGUMENT}").unwrap();
    // Media the per-call lookups refuse: ρ′ beyond the rows or NaN, σ′t zero or too large,
    // a table past the end
    for (table, rho, sigma_t, status) in [
        (0, 1.5, 2.0, BSSRDF_ERROR_OUT_OF_RANGE),
        (1, f64::NAN, 2.0, BSSRDF_ERROR_OUT_OF_RANGE),
        (0, 0.5, 0.0, BSSRDF_ERROR_INVALID_ARGUMENT),
        (1, 0.5, 1e300, BSSRDF_ERROR_INVALID_ARGUMENT),
        (2, 0.5, 2.0, BSSRDF_ERROR_NOT_FOUND),
    ] {
        writeln!(text, "X {table} {} {} {status}", hex(rho), hex(sigma_t)).unwrap();
    }
    for m in library.materials() {
        for rgb in Rgb::ALL {
            let h: ChannelLookup = library.channel(&m.name, rgb).unwrap();
            let view = library.view(h.table().index()).unwrap();
            let medium = view.medium(h.rho_prime(), h.sigma_t_prime()).unwrap();
            writeln!(text, "M {} {} {BSSRDF_OK}", m.name, rgb.index()).unwrap();
            let table = h.table().index() as f64;
            let info = [h.rho_prime(), h.sigma_t_prime(), h.table().eta(), table];
            writeln!(text, "I {}", info.map(hex).join(" ")).unwrap();
            for _ in 0..150 {
                // θ to 1.1 × 90°, so that some lookups fall outside the table.
                let theta = 1.1 * std::f64::consts::FRAC_PI_2 * rng.next_f64();
                let r = 5.0 / h.sigma_t_prime() * rng.next_f64().powi(2);
                let phi = 7.0 * rng.next_f64() - 3.5;
                let u = [0; 4].map(|_| rng.next_f64());
                let args = [theta, r, phi].map(hex).join(" ");
                let eval = h.eval(theta, r, phi).map(|v| vec![v]);
                writeln!(
                    text,
                    "E {args} {}",
                    line_values(BSSRDF_ERROR_OUT_OF_RANGE, eval, 1)
                )
                .unwrap();
                // (the densities refuse θ outside the table, as eval)
                let keeps = h.table().view().keeps_theta(theta);
                let pdf = keeps.then(|| vec![h.pdf(theta, r, phi)]);
                let status = line_values(BSSRDF_ERROR_OUT_OF_RANGE, pdf, 1);
                writeln!(text, "P {args} {status}").unwrap();
                let args = [theta, u[0], u[1]].map(hex).join(" ");
                let sample = h.sample(theta, u[0], u[1]).map(|s| vec![s.r, s.phi, s.pdf]);
                writeln!(
                    text,
                    "S {args} {}",
                    line_values(BSSRDF_ERROR_NO_SAMPLE, sample, 3)
                )
                .unwrap();
                let path = h
                    .sample_path(u)
                    .map(|p| vec![p.theta, p.r, p.phi, p.phi_prime, p.pdf_theta, p.pdf]);
                let args = u.map(hex).join(" ");
                writeln!(
                    text,
                    "T {args} {}",
                    line_values(BSSRDF_ERROR_NO_SAMPLE, path, 6)
                )
                .unwrap();
                let pdf_theta = keeps.then(|| vec![h.pdf_theta(theta)]);
                let status = line_values(BSSRDF_ERROR_OUT_OF_RANGE, pdf_theta, 1);
                writeln!(text, "Q {} {status}", hex(theta)).unwrap();
                let albedo = h.effective_albedo(theta).map(|v| vec![v]);
                let status = line_values(BSSRDF_ERROR_OUT_OF_RANGE, albedo, 1);
                writeln!(text, "A {} {status}", hex(theta)).unwrap();
                // The separable renderers' lookups and the diffuse reflectance, at the same
                // points (the handle's; the C program also makes them per call)
                let draw = h.sample_radius(theta, u[0]).map(|d| vec![d.r, d.pdf]);
                let status = line_values(BSSRDF_ERROR_NO_SAMPLE, draw, 2);
                writeln!(text, "D {} {} {status}", hex(theta), hex(u[0])).unwrap();
                let pdf_r = keeps.then(|| vec![h.pdf_radius(theta, r)]);
                let status = line_values(BSSRDF_ERROR_OUT_OF_RANGE, pdf_r, 1);
                let args = [theta, r].map(hex).join(" ");
                writeln!(text, "W {args} {status}").unwrap();
                let factor = h.angular_factor(theta, r, phi).map(|v| vec![v]);
                let status = line_values(BSSRDF_ERROR_OUT_OF_RANGE, factor, 1);
                let args = [theta, r, phi].map(hex).join(" ");
                writeln!(text, "K {args} {status}").unwrap();
                let reflectance = h.diffuse_reflectance(theta).map(|v| vec![v]);
                let status = line_values(BSSRDF_ERROR_OUT_OF_RANGE, reflectance, 1);
                writeln!(text, "F {} {status}", hex(theta)).unwrap();
                // The handle's bits are the per-call medium's (held per point in media.rs)
                assert_eq!(
                    medium.sample_radius(theta, u[0]).map(|d| d.r.to_bits()),
                    h.sample_radius(theta, u[0]).map(|d| d.r.to_bits())
                );
            }
        }
    }
    text
}

/// Compiles `crates/capi/tests/c/capi_test.c` (with [`SANITIZERS`] if `sanitize`) and runs it on a
/// library baked here against the Rust API's values.
fn run_capi_test(cc: &str, sanitize: bool) {
    let dir = tempfile::tempdir().unwrap();
    let (library, path) = bake(dir.path());
    let expected = dir.path().join("expected.txt");
    std::fs::write(&expected, expectations(&library)).unwrap();
    let reflectance = dir.path().join("reflectance.txt");
    std::fs::write(&reflectance, crate::reflectance::expectations(&library)).unwrap();
    let exe = dir.path().join("capi_test");
    compile(cc, "tests/c/capi_test.c", &exe, sanitize);
    let out = Command::new(&exe)
        .arg(&path)
        .arg(&expected)
        .arg(&reflectance)
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "capi_test failed:\n{stderr}{stdout}");
    // 2 runs × (6 channels × (8 + 150 × 35 checks through the handle, as many per call, and
    // 150 × 15 in the batches) + channel requests and refused media): tens of thousands.
    let checks: u64 = stdout
        .trim()
        .strip_prefix("ok: ")
        .and_then(|s| s.strip_suffix(" checks"))
        .unwrap()
        .parse()
        .unwrap();
    eprintln!("capi_test: {checks} checks");
    assert!(checks > 100_000, "{stdout}");
}

#[test]
#[cfg_attr(miri, ignore = "Miri runs no C compiler")]
fn the_c_interface_gives_the_rust_values_bit_for_bit_from_c() {
    let Some(cc) = compiler() else { return };
    run_capi_test(&cc, false);
}

/// The same C program under AddressSanitizer and UndefinedBehaviorSanitizer: every pointer
/// the C side reads or writes through the interface (outputs, names, messages, handles) is
/// checked, and any report fails the run. The Rust side is not instrumented (Miri checks it,
/// docs/reliability.md).
#[test]
#[cfg_attr(miri, ignore = "Miri runs no C compiler")]
fn the_c_program_is_clean_under_address_and_undefined_behaviour_sanitizers() {
    let Some(cc) = compiler() else { return };
    if !sanitizers_work(&cc, tempfile::tempdir().unwrap().path()) {
        eprintln!("SKIPPED: `{cc}` cannot build with {SANITIZERS:?}");
        return;
    }
    run_capi_test(&cc, true);
}

/// `examples/c/{name}.c` compiled into a temporary folder, with the library file baked there:
/// the folder (kept alive by the caller), the executable and the library file.
fn build_example(cc: &str, name: &str) -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let (_, path) = bake(dir.path());
    let exe = dir.path().join(name);
    compile(cc, &format!("../../examples/c/{name}.c"), &exe, false);
    (dir, exe, path)
}

#[test]
#[cfg_attr(miri, ignore = "Miri runs no C compiler")]
fn the_c_example_builds_and_runs() {
    let Some(cc) = compiler() else { return };
    let (_dir, exe, path) = build_example(&cc, "capi_example");
    let out = Command::new(&exe).arg(&path).arg("skin1").output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}{stdout}",
        String::from_utf8_lossy(&out.stderr)
    );
    for needle in [
        "2 material(s)",
        "  skin1\n",
        "  coke\n",
        "channel g: rho' = ",
        "sample: r = ",
    ] {
        assert!(stdout.contains(needle), "no {needle:?} in:\n{stdout}");
    }
    let out = Command::new(&exe).arg(&path).arg("milk").output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("BSSRDF_ERROR_NOT_FOUND") && stderr.contains("\"milk\""),
        "{stderr}"
    );
}

/// Standard errors allowed between the separable step's mean weight and ρ_eff(θ): |Z| > 4 has
/// probability 6.3e-5 per case for a normal mean (10⁵ draws of a bounded weight), 5e-4 over the
/// 8 checks; the example's seed is fixed, so the test is deterministic.
const STEP_Z: f64 = 4.0;
/// Allowance for the full-table-value weight, whose mean is the integral of the evaluated S:
/// ρ_eff to the gap between evaluation's log-energy interpolation along r and the samplers'
/// spline (about 5e-5 of ρ_eff, crates/zoo/tests/table/separable.rs), about 1 % below the
/// first nonzero albedo node (coke's green channel, ρ′ = 5e-4), where evaluation weighs the
/// table's rows per radius node.
const STEP_EVAL_GAP: [f64; 2] = [5e-4, 2e-2];

#[test]
#[cfg_attr(miri, ignore = "Miri runs no C compiler")]
fn the_separable_step_example_estimates_the_effective_albedo() {
    let Some(cc) = compiler() else { return };
    let (_dir, exe, path) = build_example(&cc, "separable_step");
    // Normal, oblique and grazing incidence, on both tables (skin1 η 1.3, coke η 1.33)
    for (material, theta, gap) in [
        ("skin1", "0", STEP_EVAL_GAP[0]),
        ("skin1", "60", STEP_EVAL_GAP[0]),
        ("skin1", "89", STEP_EVAL_GAP[0]),
        ("coke", "80", STEP_EVAL_GAP[1]),
    ] {
        let out = Command::new(&exe)
            .args([path.to_str().unwrap(), material, theta, "100000"])
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{}{stdout}",
            String::from_utf8_lossy(&out.stderr)
        );
        eprint!("{stdout}");
        let mut results = 0;
        for line in stdout.lines().filter_map(|l| l.strip_prefix("result ")) {
            let fields: Vec<&str> = line.split(' ').collect();
            let [kind, rho_eff, mean, error] = fields[..] else {
                panic!("malformed result line {line:?}");
            };
            let [rho_eff, mean, error] = [rho_eff, mean, error].map(|x| x.parse::<f64>().unwrap());
            let gap = if kind == "full" { gap } else { 0.0 };
            // (at θ = 0 the separable weights are all ρ_eff: the sum's rounding, n·ε)
            let allowed = STEP_Z * error + (gap + 1e5 * f64::EPSILON) * rho_eff;
            assert!(
                rho_eff > 0.0 && (mean - rho_eff).abs() <= allowed,
                "{material} θ {theta}°, {kind}: {mean} against ρ_eff {rho_eff}:\n{stdout}"
            );
            results += 1;
        }
        assert_eq!(results, 2, "{stdout}");
    }
}
