//! `bssrdf bake --source walk`: a walk-angular table for one (η, g), and the refusals of what a
//! walk bake cannot take.

use crate::common::{bssrdf, fails_with, ok};

#[test]
fn a_walk_bake_refuses_what_it_would_not_use() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let walk = ["bake", "--source", "walk", "-o", "w.bssrdf", "-q"];
    let refused = |extra: &[&str], needle: &str| {
        fails_with(&bssrdf(d, &[&walk[..], extra].concat()), 2, needle);
    };
    refused(&["--eta", "1.33", "skin1"], "without materials");
    refused(
        &["--eta", "1.33", "--sigma-s", "1,1,1", "--sigma-a", "0,0,0"],
        "without materials",
    );
    refused(&["--scene", "s.toml"], "without materials");
    refused(
        &["--eta", "1.33", "--fresnel-moments", "pbrt"],
        "exact Fresnel",
    );
    refused(&["--eta", "1.33", "--lobes", "1"], "two lobes");
    refused(&["--eta", "1.33", "--accept-error"], "no such check");
    refused(&[], "--source walk needs --eta");
    refused(
        &["--eta", "3"],
        "--eta 3 is outside the valid range: [0.75, 2.5]",
    );
    refused(&["--eta", "1.33", "--g", "0.1,0.2,0.3"], "one g");
    refused(&["--eta", "1.33", "--g", "1"], "g = 1");
    refused(
        &["--eta", "1.33", "--photons", "100"],
        "--photons 100 is outside the valid range: at least 16384",
    );
    assert!(!d.join("w.bssrdf").exists());
    // And a PBD bake refuses the walk's flags
    for flag in ["--photons", "--seed"] {
        fails_with(
            &bssrdf(d, &["bake", "--eta", "1.33", flag, "5", "-o", "p.bssrdf"]),
            2,
            "a PBD bake has no walk",
        );
    }
    let _ = ok;
}
