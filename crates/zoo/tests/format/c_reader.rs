//! The independent C reader in `examples/c/`, written from `format-spec.md` alone, agrees
//! with the Rust reader: it is compiled with the system C compiler (`$CC`, else `cc`), run on
//! files the Rust writer made, and must print the same value bits and reject damaged files.
//! Without a C compiler the tests pass after saying they skipped.

use std::path::{Path, PathBuf};
use std::process::Command;

use bssrdf_testkit::files::{material, synthetic_table, with_signed_floor};
use bssrdf_zoo::format::{Compression, Library, LibraryBuilder, SectionKind, Verify};

/// Compiles the C reader into `dir`, or `None` (with a message) if no compiler works.
fn compile(dir: &Path) -> Option<PathBuf> {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_owned());
    if Command::new(&cc).arg("--version").output().is_err() {
        eprintln!("SKIPPED: no C compiler found (tried `{cc}`); the C reader was not tested");
        return None;
    }
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/c/bssrdf_read.c");
    let exe = dir.join("bssrdf_read");
    let out = Command::new(&cc)
        .args([
            "-std=c99",
            "-O2",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
            "-o",
        ])
        .arg(&exe)
        .arg(&source)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{cc} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    Some(exe)
}

/// Runs the C reader; returns its exit code and standard output.
fn run(exe: &Path, file: &Path, table: i64, kind: u32, index: usize) -> (i32, String) {
    let out = Command::new(exe)
        .arg(file)
        .arg(table.to_string())
        .arg(format!("{kind:#x}"))
        .arg(index.to_string())
        .output()
        .unwrap();
    let code = out.status.code().unwrap_or(-1);
    (code, String::from_utf8_lossy(&out.stdout).into_owned())
}

/// The C reader prints value `index` of section `kind` of table 0 of `file` with the bits of
/// `expected`, the value the Rust reader reads there.
fn prints_bits(exe: &Path, file: &Path, kind: u32, index: usize, expected: f32) {
    let (code, stdout) = run(exe, file, 0, kind, index);
    assert_eq!(code, 0, "{}: {stdout}", file.display());
    let bits = stdout.split_whitespace().next().unwrap();
    assert_eq!(
        u32::from_str_radix(bits, 16).unwrap(),
        expected.to_bits(),
        "{}",
        file.display()
    );
}

#[test]
fn c_reader_reads_the_same_values_as_the_rust_reader() {
    let dir = tempfile::tempdir().unwrap();
    let Some(exe) = compile(dir.path()) else {
        return;
    };
    let mut builder = LibraryBuilder::new();
    builder
        .add_table(synthetic_table(1.33, 4, 3, 64, true))
        .unwrap();
    // Negative floors: the file sets required feature bit 1, which the C reader implements.
    builder
        .add_table(with_signed_floor(synthetic_table(1.5, 2, 5, 7, false)))
        .unwrap();
    builder.add_material(material("jade", 1)).unwrap();
    let path = dir.path().join("lib.bssrdf");
    builder.write_atomic(&path, Compression::None).unwrap();
    let library = Library::open_mmap(&path, Verify::Full).unwrap();
    assert_eq!(library.required_features(), 1 << 1);
    let mut checked = 0;
    for table in library.tables() {
        for kind in SectionKind::ALL.into_iter().filter(|k| k.per_table()) {
            let Some(values) = table.section(kind) else {
                continue;
            };
            for index in [0, values.len() / 2, values.len() - 1] {
                let (code, stdout) = run(&exe, &path, table.index() as i64, kind.code(), index);
                assert_eq!(code, 0, "{kind} {index}: {stdout}");
                let bits = stdout.split_whitespace().next().unwrap();
                let bits = u32::from_str_radix(bits, 16).unwrap();
                assert_eq!(
                    bits,
                    values[index].to_bits(),
                    "table {} {kind}[{index}]",
                    table.index()
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 30);
}

#[test]
fn c_reader_reads_the_spec_example_and_rejects_damaged_files() {
    let dir = tempfile::tempdir().unwrap();
    let Some(exe) = compile(dir.path()) else {
        return;
    };
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data");
    let gwc = SectionKind::GwcParams.code();
    // Required feature bit 1 (signed-floor): E_β = 2 > E = 0.5 at node 1.
    let (code, stdout) = run(&exe, &data.join("valid/spec-example.bssrdf"), 0, gwc, 4);
    assert_eq!((code, stdout.as_str()), (0, "40000000 2\n"));
    // A newer minor with extensions is read too, and so is an older one.
    for file in ["valid/newer-minor", "valid/older-minor"] {
        let (code, _) = run(&exe, &data.join(format!("{file}.bssrdf")), 0, gwc, 0);
        assert_eq!(code, 0, "{file}");
    }
    // The C reader prints harmonic `index` of a two-lobe vector as the Rust reader reads it
    let harmonics = SectionKind::Harmonics.code();
    let same_harmonic = |file: &str, index: usize| {
        let path = data.join(format!("valid/{file}.bssrdf"));
        let library = Library::read(&path, Verify::Full).unwrap();
        let expected = library.table(0).unwrap().harmonics().unwrap()[index];
        prints_bits(&exe, &path, harmonics, index, expected);
    };
    // Format 1.2 with required feature bit 2: the harmonics of a two-lobe table.
    same_harmonic("two-lobes", 3);
    // Format 1.3 with required feature bit 3: a signed pair's stored r·μ₃ at node (0, 0, 1).
    let signed = data.join("valid/signed-lobes.bssrdf");
    let (code, stdout) = run(&exe, &signed, 0, harmonics, 2);
    assert_eq!((code, stdout.as_str()), (0, "3ee624dd 0.449499995\n"));
    // Format 1.4 with required feature bit 4: a merged pair's stored r·μ₃ at node (0, 0, 1).
    same_harmonic("merged-roots", 2);
    // Format 1.5 with required feature bit 5: a walk-angular table's arrays, stored alike.
    same_harmonic("walk-table", 1);
    for (file, why) in [
        ("invalid/bad-magic", "magic"),
        ("invalid/unsupported-major", "version"),
        ("invalid/truncated", "file size"),
        ("invalid/trailing-bytes", "file size"),
        ("invalid/header-crc", "header crc"),
        ("invalid/section-crc", "section crc"),
        ("valid/tiny-packed", "compressed"),
        ("invalid/unsupported-features", "unknown required bit 7"),
        (
            "invalid/harmonics-not-declared",
            "gwc-harmonics without bit 2",
        ),
        (
            "invalid/feature-not-declared",
            "a compressed section without bit 0",
        ),
        (
            "invalid/walk-tables-not-declared",
            "a walk-angular table without bit 5",
        ),
        ("invalid/ridge-not-declared", "ridge = 1 without bit 6"),
        ("invalid/unknown-ridge", "ridge = 3"),
    ] {
        let (code, _) = run(&exe, &data.join(format!("{file}.bssrdf")), 0, gwc, 0);
        assert_eq!(code, 3, "{file} should be rejected ({why})");
    }
    // The undeclared harmonics are rejected whichever section is asked for, themselves too.
    let undeclared = data.join("invalid/harmonics-not-declared.bssrdf");
    let (code, _) = run(&exe, &undeclared, 0, harmonics, 3);
    assert_eq!(code, 3, "harmonics-not-declared: its harmonics were read");
}

/// Format 1.6: the C reader reads a table whose record sets `ridge` (1 or 2) where the file
/// sets bit 6, at byte 28 of a pbd-angular record and byte 40 of a walk-angular one (whose
/// byte 28 is the walk's component), and rejects it without the bit or with a `ridge` other
/// than 0, 1 and 2.
#[test]
fn c_reader_reads_the_ridge_field_by_model() {
    use bssrdf_testkit::files::{as_walk_table, kind, Raw};
    use bssrdf_zoo::format::spec::required_features::RIDGE;
    use bssrdf_zoo::format::{TableData, WalkComponent};
    use bssrdf_zoo::table::RidgeKind;
    let dir = tempfile::tempdir().unwrap();
    let Some(exe) = compile(dir.path()) else {
        return;
    };
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data");
    let gwc = SectionKind::GwcParams.code();
    // The ridge vectors, `ridge` = 1 and 2: the values the Rust reader reads
    for file in ["ridge", "ridge-fluence"] {
        let path = data.join(format!("valid/{file}.bssrdf"));
        let library = Library::read(&path, Verify::Full).unwrap();
        let expected = library.table(0).unwrap().gwc_params()[7];
        prints_bits(&exe, &path, gwc, 7, expected);
    }
    // A walk-angular table with the ridge (component total = 1 at byte 28, ridge at byte 40)
    let table = TableData {
        ridge: RidgeKind::Flux,
        ..synthetic_table(1.0, 2, 2, 4, true)
    };
    let mut builder = LibraryBuilder::new();
    builder
        .add_table(as_walk_table(table, 0.75, WalkComponent::Total))
        .unwrap();
    let raw = Raw::new(builder.to_bytes(Compression::None).unwrap());
    let edited = |name: &str, edit: &dyn Fn(&mut Raw)| {
        let mut raw = raw.clone();
        edit(&mut raw);
        raw.fix_crcs();
        let path = dir.path().join(name);
        std::fs::write(&path, &raw.bytes).unwrap();
        run(&exe, &path, 0, gwc, 0).0
    };
    let record = raw.data(kind::TABLES, kind::FILE);
    assert_eq!(edited("walk-ridge.bssrdf", &|_| {}), 0);
    let no_bit = |r: &mut Raw| r.set_u64(32, r.u64(32) & !RIDGE);
    assert_eq!(
        edited("no-bit.bssrdf", &no_bit),
        3,
        "ridge = 1 without bit 6"
    );
    let two = |r: &mut Raw| r.set_u32(record + 40, 2);
    assert_eq!(edited("two.bssrdf", &two), 0, "ridge = 2");
    let two_no_bit = |r: &mut Raw| {
        two(r);
        no_bit(r);
    };
    assert_eq!(
        edited("two-no-bit.bssrdf", &two_no_bit),
        3,
        "ridge = 2 without bit 6"
    );
    let three = |r: &mut Raw| r.set_u32(record + 40, 3);
    assert_eq!(edited("three.bssrdf", &three), 3, "ridge = 3");
    // Without the ridge and without the bit: the component at byte 28 is no ridge code
    let without = |r: &mut Raw| {
        no_bit(r);
        r.set_u32(record + 40, 0);
    };
    assert_eq!(edited("without.bssrdf", &without), 0);
}
