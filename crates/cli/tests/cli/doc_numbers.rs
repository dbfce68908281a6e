//! Numbers the docs quote from the commands, checked against what the commands print now
//! (on the coarse grid, which is quick to bake): a change that moves them fails here until the
//! docs follow.

use std::path::Path;

use crate::common::{bssrdf, ok, text};

/// The text of `docs/NAME`.
fn doc(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../docs")
        .join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// A byte count as the docs write it: 7,680.
fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[test]
fn the_coarse_file_size_in_accuracy_md_is_what_bake_prints() {
    let dir = tempfile::tempdir().unwrap();
    let o = bssrdf(
        dir.path(),
        &[
            "bake", "--eta", "1.33", "--grid", "coarse", "-o", "p.bssrdf",
        ],
    );
    ok(&o);
    let err = text(&o.stderr);
    // "wrote p.bssrdf (1 table(s), 0 material(s), 236664 bytes, 231.1 KiB) in 0.15 s"
    let kib = err
        .split(" bytes, ")
        .nth(1)
        .and_then(|rest| rest.split(')').next())
        .unwrap_or_else(|| panic!("no size in {err}"));
    let row = format!("| coarse | 50 × 7 × 40 | {kib} |");
    assert!(
        doc("accuracy.md").contains(&row),
        "{row} not in accuracy.md"
    );
}

#[test]
fn the_full_library_estimate_in_scenes_md_is_what_bake_gives() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The example of scenes.md limited to its first two materials, and their full library
    std::fs::write(
        d.join("scene.toml"),
        "integrator = \"path\"\n[[material]]\nname = \"white-grapefruit-juice\"\n\
         [[material]]\nname = \"skin1\"\n\
         albedo_range = [[0.85, 0.97], [0.80, 0.90], [0.60, 0.70]]\n",
    )
    .unwrap();
    let s: serde_json::Value = serde_json::from_str(&ok(&bssrdf(
        d,
        &[
            "bake",
            "--scene",
            "scene.toml",
            "--grid",
            "coarse",
            "--json",
            "-q",
        ],
    )))
    .unwrap();
    ok(&bssrdf(
        d,
        &[
            "bake",
            "white-grapefruit-juice",
            "skin1",
            "--grid",
            "coarse",
            "-q",
            "-o",
            "full.bssrdf",
        ],
    ));
    let real = std::fs::metadata(d.join("full.bssrdf")).unwrap().len();
    let computed = s["full_bytes"].as_u64().unwrap();
    let scenes = doc("scenes.md");
    let difference = format!("{} on the coarse", thousands(real.abs_diff(computed)));
    assert!(
        scenes.contains(&difference),
        "{difference} not in scenes.md"
    );
    let row = format!(
        "| {} bytes | {} bytes |",
        thousands(s["bytes"].as_u64().unwrap()),
        thousands(computed)
    );
    assert!(scenes.contains(&row), "{row} not in scenes.md");
}
