//! End-to-end tests of edges an outside user found: an input reached through another name
//! (a hard link, a descriptor) is never written, an input of render or zoo is never an
//! output, no flag is accepted and ignored, no NaN or −0 is printed, and every refusal names
//! the flag and its range.

use std::path::{Path, PathBuf};

#[cfg(unix)]
use crate::common::shell;
use crate::common::{bare, bssrdf, fails_with, ok, text};

/// The walk-angular conformance vector, copied into `dir` as `name`.
fn walk_table(dir: &Path, name: &str) -> PathBuf {
    let source =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/valid/walk-table.bssrdf");
    let path = dir.join(name);
    std::fs::copy(source, &path).unwrap();
    path
}

#[cfg(unix)]
#[test]
fn an_input_is_not_written_through_a_hard_link() {
    let dir = bare();
    let d = dir.path();
    std::fs::hard_link(d.join("t.bssrdf"), d.join("hard")).unwrap();
    let original = std::fs::read(d.join("t.bssrdf")).unwrap();
    let wax = "id = \"my-wax\"\nname = \"My wax\"\neta = 1.45\ncoefficients = \"unreduced\"\nsigma_s = [1.0, 1.1, 1.2]\nsigma_a = [0.01, 0.02, 0.05]\ng = [0.3, 0.3, 0.3]\n";
    std::fs::write(d.join("wax.toml"), wax).unwrap();
    std::fs::hard_link(d.join("wax.toml"), d.join("waxhard")).unwrap();
    for (script, needle) in [
        (
            "$B pack t.bssrdf -o hard",
            "-o hard is the input FILE t.bssrdf",
        ),
        (
            "$B pack t.bssrdf -o /dev/stdout >> hard",
            "-o /dev/stdout is the input FILE t.bssrdf",
        ),
        (
            "$B bake my-wax --materials wax.toml --grid coarse -q -o waxhard",
            "-o waxhard is the input --materials wax.toml",
        ),
        (
            "$B bake my-wax --materials wax.toml --grid coarse -q -o /dev/stdout >> waxhard",
            "-o /dev/stdout is the input --materials wax.toml",
        ),
    ] {
        let out = shell(d, script);
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{script}: {stderr}");
        assert!(stderr.contains(needle), "{script}: {stderr}");
    }
    assert_eq!(std::fs::read(d.join("t.bssrdf")).unwrap(), original);
    assert_eq!(std::fs::read_to_string(d.join("wax.toml")).unwrap(), wax);
    // /dev/null is no input of anything: still written through
    ok(&bssrdf(d, &["pack", "t.bssrdf", "-o", "/dev/null"]));
}

#[test]
fn render_and_zoo_never_write_over_their_walk_table() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let table = walk_table(d, "w.bssrdf");
    let original = std::fs::read(&table).unwrap();
    let render = [
        "render",
        "--preset",
        "figure-10",
        "--model",
        "walk-table",
        "--walk-table",
        "w.bssrdf",
        "--photons",
        "100",
        "--size",
        "4,4",
        "--theta",
        "30",
        "-q",
        "-o",
        "w.bssrdf",
    ];
    fails_with(
        &bssrdf(d, &render),
        2,
        "-o w.bssrdf is the input --walk-table w.bssrdf",
    );
    // zoo: a figure of --plot that is the table, and a figure that cannot be written, are
    // refused before the walks
    std::fs::create_dir(d.join("plots")).unwrap();
    std::fs::copy(&table, d.join("plots/pareto.svg")).unwrap();
    let zoo = |plot: &str| {
        bssrdf(
            d,
            &[
                "zoo",
                "--eta",
                "1.3",
                "--g",
                "0.75",
                "--walk-table",
                "plots/pareto.svg",
                "--models",
                "walk-table",
                "--photons",
                "1000",
                "--cases",
                "0.5:0",
                "-q",
                "--plot",
                plot,
            ],
        )
    };
    fails_with(
        &zoo("plots"),
        2,
        "the --plot figure plots/pareto.svg is the input --walk-table plots/pareto.svg",
    );
    assert_eq!(std::fs::read(d.join("plots/pareto.svg")).unwrap(), original);
    std::fs::create_dir_all(d.join("other/pareto.svg")).unwrap();
    let start = std::time::Instant::now();
    let out = bssrdf(
        d,
        &[
            "zoo",
            "--photons",
            "3000000",
            "--models",
            "dipole",
            "--cases",
            "0.5:0",
            "-q",
            "--plot",
            "other",
        ],
    );
    fails_with(&out, 2, "pareto.svg");
    assert!(
        start.elapsed().as_secs_f64() < 1.0,
        "refused after the walks: {:?}",
        start.elapsed()
    );
}

#[test]
fn flags_that_would_change_nothing_are_refused() {
    let dir = bare();
    let d = dir.path();
    walk_table(d, "w.bssrdf");
    for (args, needle) in [
        (
            vec![
                "bake",
                "--reflectance",
                "0.5,0.5,0.5",
                "--mfp",
                "1,1,1",
                "--sigma-a",
                "1,1,1",
                "--grid",
                "coarse",
                "-o",
                "m.bssrdf",
            ],
            "cannot be used with",
        ),
        (
            vec![
                "bake",
                "--source",
                "walk",
                "--eta",
                "1.33",
                "--fresnel-moments",
                "exact",
                "-o",
                "x.bssrdf",
            ],
            "--fresnel-moments sets PBD's boundary",
        ),
        (
            vec![
                "eval",
                "w.bssrdf",
                "--model",
                "walk-table",
                "--fresnel-moments",
                "exact",
                "--rho",
                "0.5",
                "--theta",
                "30",
                "--r",
                "1",
            ],
            "--fresnel-moments exact applies to the diffusion models, not to walk-table",
        ),
        (
            vec!["validate", "t.bssrdf", "--samples", "10", "--channel", "g"],
            "--channel picks a colour channel of --material",
        ),
        (
            vec![
                "validate",
                "t.bssrdf",
                "--samples",
                "10",
                "--materials",
                "t.bssrdf",
            ],
            "--materials adds files to look --material up in",
        ),
    ] {
        fails_with(&bssrdf(d, &args), 2, needle);
    }
    assert!(!d.join("m.bssrdf").exists() && !d.join("x.bssrdf").exists());
    // The same bake with exact moments given is the default's
    ok(&bssrdf(
        d,
        &[
            "bake",
            "--eta",
            "1.33",
            "--grid",
            "coarse",
            "-q",
            "--fresnel-moments",
            "exact",
            "-o",
            "e.bssrdf",
        ],
    ));
    assert_eq!(
        std::fs::read(d.join("e.bssrdf")).unwrap(),
        std::fs::read(d.join("t.bssrdf")).unwrap()
    );
}

#[test]
fn no_nan_and_no_negative_zero_is_printed() {
    let dir = bare();
    let d = dir.path();
    // No light leaves a medium that does not scatter: its centroid is "none", not NaN
    let render = [
        "render",
        "--sigma-s",
        "0,0,0",
        "--sigma-a",
        "1,1,1",
        "--photons",
        "200",
        "--size",
        "8,8",
        "--theta",
        "30",
        "-o",
        "zero.exr",
    ];
    let out = ok(&bssrdf(d, &render));
    assert!(!out.contains("NaN") && out.contains("none"), "{out}");
    let exr = std::fs::read(d.join("zero.exr")).unwrap();
    assert!(
        !exr.windows(3).any(|w| w == b"NaN"),
        "NaN in the EXR's metadata"
    );
    // −0 is 0 when it is echoed
    let o = ok(&bssrdf(
        d,
        &[
            "eval", "t.bssrdf", "--rho", "0.5", "--theta", "-0", "--r", "-0", "--phi", "-0",
            "--json",
        ],
    ));
    let v: serde_json::Value = serde_json::from_str(o.trim()).unwrap();
    for key in ["theta_deg", "r", "phi_deg"] {
        assert!(v[key].as_f64().unwrap().is_sign_positive(), "{key}: {o}");
    }
    let out = bssrdf(
        d,
        &[
            "validate",
            "t.bssrdf",
            "--samples",
            "10",
            "--max-mean-error",
            "-0",
        ],
    );
    assert!(!text(&out.stdout).contains("-0.0"), "{}", text(&out.stdout));
    // and so are the walk's and the zoo's
    let o = ok(&bssrdf(
        d,
        &[
            "walk",
            "--albedo",
            "-0",
            "--g",
            "-0",
            "--theta",
            "-0",
            "--photons",
            "1000",
            "--json",
            "-q",
        ],
    ));
    let v: serde_json::Value = serde_json::from_str(o.trim()).unwrap();
    for key in ["albedo", "g", "theta_deg"] {
        assert!(v[key].as_f64().unwrap().is_sign_positive(), "{key}: {o}");
    }
    let o = ok(&bssrdf(
        d,
        &[
            "zoo",
            "--g",
            "-0",
            "--photons",
            "1000",
            "--cases",
            "0.5:0",
            "--models",
            "mc",
            "--json",
            "-q",
        ],
    ));
    let v: serde_json::Value = serde_json::from_str(o.trim()).unwrap();
    assert!(v["g"].as_f64().unwrap().is_sign_positive(), "{o}");
    // A material file's −0 is listed as 0
    let zz = "id = \"zz\"\nname = \"Z\"\neta = 1.45\ncoefficients = \"unreduced\"\nsigma_s = [1.0, 1.1, 1.2]\nsigma_a = [0.01, -0.0, 0.05]\ng = [0, 0, -0.0]\n";
    std::fs::write(d.join("zz.toml"), zz).unwrap();
    let listed = ok(&bssrdf(
        d,
        &["materials", "--materials", "zz.toml", "--json"],
    ));
    let listed: serde_json::Value = serde_json::from_str(listed.trim()).unwrap();
    let zz = listed
        .as_array()
        .or_else(|| listed["materials"].as_array())
        .unwrap()
        .iter()
        .find(|m| m["id"] == "zz")
        .unwrap();
    for channel in zz["channels"].as_array().unwrap() {
        for key in ["sigma_a", "g"] {
            assert!(channel[key].as_f64().unwrap().is_sign_positive(), "{zz}");
        }
    }
    let text_list = ok(&bssrdf(d, &["materials", "--materials", "zz.toml"]));
    let line = text_list.lines().find(|l| l.contains("zz")).unwrap();
    assert!(!line.contains("-0"), "{line}");
}

#[test]
fn refusals_name_the_flag_and_its_range() {
    let dir = bare();
    let d = dir.path();
    for (args, needle) in [
        (
            vec!["bake", "--eta", "nan", "-o", "x.bssrdf"],
            "--eta NaN is outside the valid range: [0.75, 2.5]",
        ),
        (
            vec!["walk", "--albedo", "0.5", "--g", "1"],
            "--g 1 is outside the valid range: (-1, 1)",
        ),
        (
            vec!["zoo", "--g", "nan"],
            "--g NaN is outside the valid range: (-1, 1)",
        ),
        (
            vec!["zoo", "--eta", "3"],
            "--eta 3 is outside the valid range: [0.75, 2.5]",
        ),
        (
            vec!["walk", "--albedo", "1.5"],
            "--albedo 1.5 is outside the valid range: [0, 1]",
        ),
        (
            vec!["walk", "--albedo", "0.5", "--slab", "0"],
            "--slab 0 is outside the valid range: a finite number > 0",
        ),
        (
            vec!["walk", "--albedo", "0.5", "--bins", "1,0.1,10,10", "--json"],
            "--bins: r_min = 1 must be below r_max = 0.1",
        ),
        (
            vec!["walk", "--albedo", "--g", "0.5"],
            "the value of --albedo is missing: --g is the next option, not a value",
        ),
        (
            vec!["sample", "t.bssrdf", "--rho", "0.5", "-n", "--seed", "1"],
            "the value of -n is missing: --seed is the next option, not a value",
        ),
        (
            vec![
                "sample",
                "t.bssrdf",
                "--rho",
                "0.5",
                "--seed",
                "18446744073709551616",
            ],
            "18446744073709551616 is too large: a whole number in [0, 18446744073709551615]",
        ),
    ] {
        fails_with(&bssrdf(d, &args), 2, needle);
    }
    assert!(!d.join("x.bssrdf").exists());
}

/// invert's range is the table's ρ_eff times the entry transmittance: multiple scattering for a
/// PBD table, single scattering too for a walk table of the total, and the refusal and --json
/// say which.
#[test]
fn invert_says_what_the_tables_reflectance_holds() {
    let dir = bare();
    let d = dir.path();
    walk_table(d, "w.bssrdf");
    fails_with(
        &bssrdf(d, &["invert", "w.bssrdf", "--reflectance", "0.999"]),
        2,
        "this table reaches at --theta 0 (single and multiple scattering, the walk's total; rho' from 0.25 to 0.75)",
    );
    fails_with(
        &bssrdf(d, &["invert", "t.bssrdf", "--reflectance", "0.999"]),
        2,
        "this table reaches at --theta 0 (multiple scattering only; rho' from 0 to 1)",
    );
    let walk: serde_json::Value = serde_json::from_str(&ok(&bssrdf(
        d,
        &["invert", "w.bssrdf", "--reflectance", "0.93", "--json"],
    )))
    .unwrap();
    assert_eq!(walk["walk_component"], "total", "{walk}");
    let pbd: serde_json::Value = serde_json::from_str(&ok(&bssrdf(
        d,
        &["invert", "t.bssrdf", "--reflectance", "0.5", "--json"],
    )))
    .unwrap();
    assert!(pbd["walk_component"].is_null(), "{pbd}");
}

#[test]
fn a_material_of_the_file_is_found_as_the_library_finds_its_own() {
    let dir = bare();
    let d = dir.path();
    let wax = "id = \"my-wax\"\nname = \"My wax\"\neta = 1.45\ncoefficients = \"unreduced\"\nsigma_s = [1.0, 1.1, 1.2]\nsigma_a = [0.01, 0.02, 0.05]\ng = [0.3, 0.3, 0.3]\n";
    std::fs::write(d.join("wax.toml"), wax).unwrap();
    let bake = [
        "bake",
        "my-wax",
        "--materials",
        "wax.toml",
        "--grid",
        "coarse",
    ];
    ok(&bssrdf(
        d,
        &[&bake[..], &["-q", "-o", "wax.bssrdf"]].concat(),
    ));
    // The file's record is "my-wax"; the built-in names are found in any case, and so is it
    let eval = |name: &str| {
        let args = [
            "eval",
            "wax.bssrdf",
            "--material",
            name,
            "--theta",
            "30",
            "--r",
            "1",
        ];
        bssrdf(d, &args)
    };
    let exact = ok(&eval("my-wax"));
    for name in ["MY-WAX", " my_wax", "My Wax"] {
        assert_eq!(ok(&eval(name)), exact, "{name}");
    }
    // A name found nowhere lists the file's materials beside the library's suggestions
    fails_with(&eval("my-wa"), 2, "no material named \"my-wa\"");
    fails_with(
        &eval("my-wa"),
        2,
        "nor in wax.bssrdf, whose materials are \"my-wax\"",
    );
}
