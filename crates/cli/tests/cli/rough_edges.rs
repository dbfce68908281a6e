//! End-to-end tests of the minor promises of the command line (issue 18, "rough edges"):
//! messages that name what went wrong, flags that are used or refused, JSON in one shape.

use std::path::Path;
use std::process::Output;

use crate::common::{bare, bssrdf, fails_with, ok, text};

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_str(&ok(o)).expect("stdout is JSON")
}

#[test]
fn messages_name_the_file_and_the_stream() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // One "cannot open", naming the file once.
    let o = bssrdf(
        d,
        &[
            "eval",
            "missing.bssrdf",
            "--rho",
            "0.5",
            "--theta",
            "0",
            "--r",
            "1",
        ],
    );
    fails_with(&o, 2, "cannot open missing.bssrdf: No such file");
    assert_eq!(
        text(&o.stderr).matches("missing.bssrdf").count(),
        1,
        "{}",
        text(&o.stderr)
    );
    // A full stdout is named as the output.
    if Path::new("/dev/full").exists() {
        let out = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_bssrdf"))
            .args(["materials"])
            .stdout(out)
            .output()
            .unwrap();
        fails_with(
            &o,
            2,
            "cannot write the output (stdout or stderr): No space left on device",
        );
    }
    // Huge values in exponent notation, not 309 digits.
    fails_with(
        &bssrdf(d, &["eval", "--rho", "1e308", "--theta", "0", "--r", "1"]),
        2,
        "--rho 1e308 is outside the valid range: [0, 1]",
    );
}

#[cfg(unix)]
#[test]
fn points_paths_need_not_be_utf8() {
    use std::os::unix::ffi::OsStrExt;
    let dir = tempfile::tempdir().unwrap();
    let name = std::ffi::OsStr::from_bytes(b"pts-\xff.csv");
    std::fs::write(
        dir.path().join(name),
        "rho,theta_deg,r,phi_deg\n0.9,0,1,0\n",
    )
    .unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_bssrdf"))
        .current_dir(dir.path())
        .arg("eval")
        .arg("--points")
        .arg(name)
        .args(["--quadrature", "fast"])
        .output()
        .unwrap();
    assert!(ok(&o).starts_with("rho,theta_deg,r,phi_deg,value\n0.9,0,1,0,"));
}

#[test]
fn names_and_sources_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    fails_with(
        &bssrdf(
            d,
            &[
                "bake",
                "--sigma-s",
                "1,1,1",
                "--sigma-a",
                "0.1,0.1,0.1",
                "--name",
                "skin1",
                "-q",
            ],
        ),
        2,
        "--name skin1 is a material of the library",
    );
    let long = "x".repeat(300);
    let scene = format!(
        "integrator = \"path\"\n[[material]]\nname = \"wax\"\nsigma_s = [1, 1, 1]\nsigma_a = [0.1, 0.1, 0.1]\nsource = \"{long}\"\n"
    );
    std::fs::write(d.join("long.toml"), scene).unwrap();
    fails_with(
        &bssrdf(
            d,
            &["bake", "--scene", "long.toml", "--grid", "coarse", "-q"],
        ),
        2,
        "source is 300 bytes; a library file keeps at most 256",
    );
}

#[test]
fn json_uses_command_line_names_and_one_shape() {
    let dir = bare();
    let d = dir.path();
    let inspect = json(&bssrdf(d, &["inspect", "t.bssrdf", "--json"]));
    assert_eq!(inspect["tables"][0]["model"], "pbd-angular");
    assert_eq!(inspect["tables"][0]["fresnel_moments"], "exact");
    for s in inspect["sections"].as_array().unwrap() {
        assert!(["u8", "f32"].contains(&s["dtype"].as_str().unwrap()), "{s}");
        assert_eq!(s["codec"], "none");
    }
    let text_inspect = ok(&bssrdf(d, &["inspect", "t.bssrdf"]));
    for debug in ["PbdAngular", "Exact", " None ", "F32"] {
        assert!(!text_inspect.contains(debug), "{debug} in {text_inspect}");
    }
    // The provenance pretty-printed: one key per line; the bake's check as a table.
    assert!(
        text_inspect
            .lines()
            .any(|l| l.trim() == "\"points_per_panel\": 8,"),
        "{text_inspect}"
    );
    assert!(
        text_inspect.contains("accuracy: the bake's check, per table and region"),
        "{text_inspect}"
    );
    let eval = json(&bssrdf(
        d,
        &[
            "eval", "--model", "pbd-fast", "--rho", "0.5", "--theta", "0", "--r", "1", "--json",
        ],
    ));
    assert_eq!(eval["model"], "pbd-fast");
    // walk: geometry always an object, θ as given.
    let walk = |extra: &[&str]| {
        json(&bssrdf(
            d,
            &[
                &[
                    "walk",
                    "--albedo",
                    "0.9",
                    "--theta",
                    "60",
                    "--photons",
                    "100",
                    "--json",
                ][..],
                extra,
            ]
            .concat(),
        ))
    };
    let half = walk(&[]);
    assert_eq!(half["geometry"], serde_json::json!({"kind": "half-space"}));
    assert_eq!(half["theta_deg"], 60.0);
    let slab = walk(&["--slab", "2"]);
    assert_eq!(
        slab["geometry"],
        serde_json::json!({"kind": "slab", "thickness": 2.0})
    );
    // render: numbers as numbers.
    let render = json(&bssrdf(
        d,
        &[
            "render",
            "--preset",
            "figure-10",
            "--theta",
            "60",
            "--photons",
            "200",
            "--size",
            "4,4",
            "-q",
            "--json",
            "-o",
            "r.exr",
        ],
    ));
    let meta = &render["render"]["meta"];
    assert_eq!(meta["photons"], 200);
    // Each key has one type: whole numbers stay u64, the angles are numbers (60, not
    // 59.99999999999999), text stays text.
    assert_eq!(meta["theta_deg"].as_f64(), Some(60.0), "{meta}");
    assert!(meta["seed"].is_u64(), "{meta}");
    assert!(meta["eta"].is_f64(), "{meta}");
    assert!(meta["model"].is_string());
}

#[test]
fn materials_align_and_show_small_coefficients() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let id = "a-material-with-a-very-long-identifier-indeed";
    std::fs::write(
        d.join("long.toml"),
        format!("id = \"{id}\"\nname = \"Long\"\neta = 1.4\ncoefficients = \"unreduced\"\nsigma_s = [0.00002, 1.0, 1.0]\nsigma_a = [0.1, 0.1, 0.1]\ng = [0.0, 0.0, 0.0]\n"),
    )
    .unwrap();
    let out = ok(&bssrdf(d, &["materials", "--materials", "long.toml"]));
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[0].contains("sigma_s is"), "{}", lines[0]);
    // The eta column ends at the same place on every line.
    let eta_end = lines[0].find("eta").unwrap() + 3;
    for line in &lines[1..] {
        assert_eq!(line.as_bytes()[eta_end], b' ', "{line}");
        assert_ne!(line.as_bytes()[eta_end - 1], b' ', "{line}");
    }
    let long = lines.iter().find(|l| l.starts_with(id)).unwrap();
    assert!(
        long.contains("unreduced") && long.contains("2.000e-5"),
        "{long}"
    );
    assert!(lines.iter().any(|l| l.contains(" reduced ")));
}

#[test]
fn dirpole_authors_fits_are_reachable() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let at = ["--rho", "0.9", "--theta", "30", "--r", "1", "--json"];
    let run = |moments: &str| {
        json(&bssrdf(
            d,
            &[
                &["eval", "--model", "dirpole", "--fresnel-moments", moments][..],
                &at,
            ]
            .concat(),
        ))
    };
    let (exact, authors) = (run("exact"), run("authors"));
    assert_eq!(authors["fresnel_moments"], "authors");
    let (a, b) = (
        exact["value"].as_f64().unwrap(),
        authors["value"].as_f64().unwrap(),
    );
    assert!(a != b && (a / b - 1.0).abs() < 0.01, "{a} vs {b}");
    fails_with(
        &bssrdf(
            d,
            &[&["eval", "--fresnel-moments", "authors"][..], &at].concat(),
        ),
        2,
        "--fresnel-moments authors is the dirpole model's only",
    );
    // The walk takes no moments: any is refused, and --json says null
    for moments in ["exact", "pbrt"] {
        fails_with(
            &bssrdf(
                d,
                &[
                    &["eval", "--model", "mc", "--fresnel-moments", moments][..],
                    &at,
                ]
                .concat(),
            ),
            2,
            &format!("--fresnel-moments {moments} applies to the diffusion models, not to mc"),
        );
    }
    let walk = json(&bssrdf(d, &[&["eval", "--model", "mc"][..], &at].concat()));
    assert!(walk["fresnel_moments"].is_null(), "{walk}");
    // without a walk table's g, the walk's defaults: isotropic, every exit
    assert_eq!(
        (walk["g"].as_f64(), walk["component"].as_str()),
        (Some(0.0), Some("total")),
        "{walk}"
    );
}

#[test]
fn r_zero_is_each_models_limit_and_tiny_r_is_finite() {
    let dir = bare();
    let d = dir.path();
    let at = |model: &str, r: &str| {
        bssrdf(
            d,
            &[
                "eval", "t.bssrdf", "--model", model, "--rho", "0.9", "--theta", "0", "--r", r,
            ],
        )
    };
    // PBD diverges like ln(1/r): +inf at 0; the table gives its value at 1e-9 r_1 (finite).
    assert_eq!(ok(&at("pbd", "0")).trim(), "inf");
    let table0: f64 = ok(&at("table", "0")).trim().parse().unwrap();
    assert!(table0.is_finite() && table0 > 0.0);
    // Below 1e-9 r_1 the table keeps that value; PBD follows its ln(1/r) down to subnormals.
    for r in ["1e-100", "5e-324"] {
        let tiny: f64 = ok(&at("table", r)).trim().parse().unwrap();
        assert_eq!(tiny, table0, "{r}");
    }
    let pbd_tiny: f64 = ok(&at("pbd", "5e-324")).trim().parse().unwrap();
    let pbd_small: f64 = ok(&at("pbd", "1e-100")).trim().parse().unwrap();
    assert!(pbd_tiny.is_finite() && pbd_tiny > pbd_small);
    fails_with(&at("pbd", "-1e-300"), 2, "--r");
}

/// The README's quick start, line by line as printed (`> FILE` redirects stdout), in a fresh
/// folder: every command succeeds.
#[test]
fn readme_quick_start_runs_as_printed() {
    let readme = include_str!("../../../../README.md");
    let start = readme
        .find("`cargo install --locked --path crates/cli`")
        .expect("the README says how to install");
    let block = &readme[start..];
    let block = &block[block.find("```sh\n").unwrap() + 6..];
    let block = &block[..block.find("```").unwrap()];
    let dir = tempfile::tempdir().unwrap();
    let mut ran = 0;
    for line in block.lines() {
        let command = line.split(" #").next().unwrap().trim();
        let (command, redirect) = match command.split_once(" > ") {
            Some((c, file)) => (c, Some(file.trim())),
            None => (command, None),
        };
        let words: Vec<&str> = command.split_whitespace().collect();
        assert_eq!(words[0], "bssrdf", "{line}");
        let o = bssrdf(dir.path(), &words[1..]);
        assert!(o.status.success(), "{line}: {}", text(&o.stderr));
        if let Some(file) = redirect {
            std::fs::write(dir.path().join(file), &o.stdout).unwrap();
        }
        ran += 1;
    }
    assert!(ran >= 8, "{block}");
    // No command of the README writes into the tracked docs/ folder.
    for line in readme
        .lines()
        .filter(|l| l.trim_start().starts_with("bssrdf "))
    {
        for flag in ["-o docs/", "--plot docs/", "--dir docs/", "--profile docs/"] {
            assert!(!line.contains(flag), "{line}");
        }
    }
}

#[test]
fn file_flags_without_a_file_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let at = ["eval", "--rho", "0.5", "--theta", "0", "--r", "1"];
    for flag in [&["--table", "1"][..], &["--mmap"]] {
        fails_with(
            &bssrdf(d, &[&at[..], flag].concat()),
            2,
            &format!("{} chooses how to read a library FILE", flag[0]),
        );
    }
    fails_with(
        &bssrdf(d, &[&at[..], &["--materials", "m.toml"]].concat()),
        2,
        "--material",
    );
}

/// Issue 16's list: inputs that printed NaN, a negative value or stored ∞ with exit 0 now give
/// the finite value or a refusal naming the value and its range (exit 2).
#[test]
fn no_nan_and_no_negative_value_from_any_model() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let eval = |model: &str, extra: &[&str]| {
        let mut args = vec!["eval", "--model", model, "--rho", "0.5", "--theta", "10"];
        args.extend_from_slice(extra);
        bssrdf(d, &args)
    };
    for model in ["pbd", "pbd-fast", "burley", "dipole", "dirpole"] {
        for eta in ["1e6", "100", "2.51", "0.74"] {
            fails_with(
                &eval(model, &["--eta", eta, "--r", "1"]),
                2,
                &format!("--eta {eta} is outside the valid range: [0.75, 2.5]"),
            );
        }
    }
    for model in ["pbd", "pbd-fast"] {
        for r in ["5e-324", "1e-310", "1e-200"] {
            let v: f64 = ok(&eval(model, &["--r", r])).trim().parse().unwrap();
            assert!(v.is_finite() && v > 0.0, "{model} r {r}: {v}");
        }
    }
    fails_with(
        &bssrdf(
            d,
            &[
                "bake",
                "--sigma-s",
                "1e308,1e308,1e308",
                "--sigma-a",
                "1e308,1e308,1e308",
                "-o",
                "x.bssrdf",
            ],
        ),
        2,
        "sigma_t' = inf is outside [1e-9, 1e12]",
    );
    assert!(!d.join("x.bssrdf").exists());
}

/// Found by trying the tool as a new user: whole turns of φ give the same value, every model
/// gives 0 where no light enters, and a beam a hair below grazing is finite.
#[test]
fn azimuths_turn_whole_and_no_light_means_zero() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let eval = |args: &[&str]| -> f64 { ok(&bssrdf(d, args)).trim().parse().unwrap() };
    let point = [
        "eval", "--model", "pbd", "--eta", "1.3", "--rho", "0.9", "--theta", "60", "--r", "0.5",
    ];
    let at = |phi: &str| eval(&[&point[..], &["--phi", phi]].concat());
    let forward = at("0");
    for phi in [
        "360",
        "-360",
        "720",
        "405323966463344640",
        "1e300",
        "-1e-20",
    ] {
        assert_eq!(at(phi), forward, "--phi {phi}");
    }
    ok(&bssrdf(
        d,
        &[
            "bake",
            "--eta",
            "0.75",
            "--grid",
            "coarse",
            "-q",
            "-o",
            "d.bssrdf",
            "--accept-error",
        ],
    ));
    for model in ["table", "perpendicular", "pbd", "dipole", "mc"] {
        let v = eval(&[
            "eval", "d.bssrdf", "--model", model, "--rho", "0.9", "--theta", "60", "--r", "1",
        ]);
        assert_eq!(v, 0.0, "{model}");
    }
    let grazing = eval(&[
        "eval",
        "--model",
        "pbd",
        "--eta",
        "1",
        "--rho",
        "0.9",
        "--theta",
        "89.9999999",
        "--r",
        "0.5",
    ]);
    assert!(grazing.is_finite() && grazing > 1e6, "{grazing}");
}

/// A sample run that cannot draw writes nothing on stdout (not a header alone).
#[test]
fn a_sample_that_cannot_draw_writes_nothing() {
    let dir = bare();
    let d = dir.path();
    for extra in [&[][..], &["--path-tracing"][..]] {
        let args = [&["sample", "t.bssrdf", "--rho", "0", "-n", "3"][..], extra].concat();
        let o = bssrdf(d, &args);
        fails_with(&o, 2, "no light leaves at rho 0");
        assert!(o.stdout.is_empty(), "{}", text(&o.stdout));
    }
}

/// A material file that is not text says so, and a library file given as one is named as
/// such (not "stream did not contain valid UTF-8").
#[test]
fn a_material_file_that_is_not_text_says_what_it_is() {
    let dir = bare();
    let d = dir.path();
    fails_with(
        &bssrdf(d, &["materials", "--materials", "t.bssrdf"]),
        2,
        "t.bssrdf: not a material file: material files are TOML text, and this is not UTF-8; it is a library file",
    );
    std::fs::write(d.join("bytes.toml"), [0xff, 0xfe, 0x00, 0x80]).unwrap();
    let o = bssrdf(d, &["materials", "--materials", "bytes.toml"]);
    fails_with(&o, 2, "bytes.toml: not a material file");
    assert!(
        !text(&o.stderr).contains("library file"),
        "{}",
        text(&o.stderr)
    );
}

/// `eval FILE --points -` with FILE itself standard input: one stream cannot be both, and the
/// refusal says so (it said the points were empty).
#[cfg(unix)]
#[test]
fn a_file_and_points_both_on_stdin_are_refused_naming_both() {
    let dir = bare();
    let o = crate::common::shell(
        dir.path(),
        r#"cat t.bssrdf | "$B" eval /dev/stdin --points -"#,
    );
    fails_with(
        &o,
        2,
        "FILE /dev/stdin and --points - both read standard input",
    );
    let o = crate::common::shell(
        dir.path(),
        r#"printf 'rho,theta_deg,r,phi_deg\n0.5,30,1,0\n' | "$B" eval t.bssrdf --points -"#,
    );
    assert!(ok(&o).starts_with("rho,theta_deg,r,phi_deg,value"));
}

/// Messages name the flags given and the ranges that hold: --name alone is named alone; walk
/// --bins names its radii's domain; a render beam wholly beyond the critical angle of an
/// η < 1 is refused as walk and zoo refuse it (it wrote a black picture).
#[test]
fn refusals_name_what_was_given_and_the_range_that_holds() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = bssrdf(d, &["bake", "skin1", "--name", "foo", "-o", "x.bssrdf"]);
    fails_with(&o, 2, "--name describes a material given by --sigma-s");
    assert!(!text(&o.stderr).contains("--g"), "{}", text(&o.stderr));
    for (bins, needle) in [
        ("9e-151,1,1,1", "r_min = 9e-151 is outside [1e-150, 1e150]"),
        (
            "0.1,1.1e150,1,1",
            "r_max = 1.1e150 is outside [1e-150, 1e150]",
        ),
    ] {
        let args = [
            "walk",
            "--albedo",
            "0.5",
            "--photons",
            "100",
            "--json",
            "--bins",
            bins,
        ];
        fails_with(&bssrdf(d, &args), 2, needle);
    }
    let render = |theta: &str, cone: &str| {
        let mut args = vec!["render", "--sigma-s", "1,1,1", "--sigma-a", "0.1,0.1,0.1"];
        args.extend([
            "--eta",
            "0.8",
            "--theta",
            theta,
            "--cone",
            cone,
            "--photons",
            "100",
        ]);
        args.extend(["--size", "8,8", "--grid", "coarse", "-q", "-o", "x.exr"]);
        bssrdf(d, &args)
    };
    fails_with(
        &render("60", "1"),
        2,
        "--theta 60 with --cone 1 lies beyond the critical angle of eta 0.8",
    );
    assert!(!d.join("x.exr").exists());
    // Part of the cone enters: a picture
    ok(&render("54", "2"));
}
