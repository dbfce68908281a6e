//! The generated shell completions and man pages.

use std::process::Output;

use crate::common::{bssrdf, text};

fn code(o: &Output) -> Option<i32> {
    assert!(!text(&o.stderr).contains("panicked"), "{}", text(&o.stderr));
    o.status.code()
}

#[test]
fn completions_generate_for_each_shell() {
    let dir = tempfile::tempdir().unwrap();
    for (shell, needle) in [
        ("bash", "_bssrdf()"),
        ("zsh", "#compdef bssrdf"),
        ("fish", "complete -c bssrdf"),
    ] {
        let o = bssrdf(dir.path(), &["completions", shell]);
        assert_eq!(code(&o), Some(0), "{shell}");
        let script = text(&o.stdout);
        assert!(script.contains(needle), "{shell}: {needle} missing");
        assert!(
            script.contains("scene") && script.contains("tolerance"),
            "{shell}"
        );
    }
    let o = bssrdf(dir.path(), &["completions", "tcsh"]);
    assert_eq!(code(&o), Some(2));
}

#[test]
fn man_pages_generate() {
    let dir = tempfile::tempdir().unwrap();
    let o = bssrdf(dir.path(), &["man"]);
    assert_eq!(code(&o), Some(0));
    let page = text(&o.stdout);
    for needle in [
        ".TH bssrdf 1",
        ".SH SYNOPSIS",
        ".SH SUBCOMMANDS",
        "EXIT STATUS",
        "bssrdf\\-diff(1)",
    ] {
        assert!(page.contains(needle), "{needle} missing");
    }
    let o = bssrdf(dir.path(), &["man", "--dir", "pages"]);
    assert_eq!(code(&o), Some(0));
    for page in [
        "bssrdf.1",
        "bssrdf-bake.1",
        "bssrdf-diff.1",
        "bssrdf-completions.1",
    ] {
        let text = std::fs::read_to_string(dir.path().join("pages").join(page)).unwrap();
        assert!(text.contains(".TH"), "{page}");
    }
    let bake = std::fs::read_to_string(dir.path().join("pages/bssrdf-bake.1")).unwrap();
    assert!(bake.contains("scene"));
    let top = std::fs::read_to_string(dir.path().join("pages/bssrdf.1")).unwrap();
    assert!(top.contains("EXIT STATUS"));
    // Exit 1 from validate is not only a case above its bound (docs/cli.md, "Exit status")
    let top = top.replace("\\-", "-");
    assert!(
        top.contains("too few points: inconclusive) or nothing to check"),
        "{top}"
    );
}
