//! The mapping (`crates/runtime/src/format/map.rs`, with the C interface the crate's only `unsafe` code) and
//! the zero-copy views over it, on the committed conformance vectors: each valid file opens
//! alike mapped and read, with the same bytes behind every view and every `&[f32]` view
//! aligned; each invalid file fails alike with the error its name gives; views into a mapped
//! file stay valid for as long as the library lives. No bake and no file written, so that it
//! runs under Miri: `MIRIFLAGS=-Zmiri-disable-isolation cargo +nightly miri test -p bssrdf-zoo --test format
//! mapping` (docs/reliability.md). Miri cannot run the mmap system call, so there
//! `open_mmap` reads the file into an owned aligned buffer (`Backing::map` under `cfg(miri)`)
//! and Miri checks the code after the map: the casts to `&[f32]`, the bounds of every view,
//! their lifetimes. Files with zstd sections are skipped under Miri (zstd is C code).

use std::path::{Path, PathBuf};

use bssrdf_zoo::format::{Library, SectionKind, Verify};

fn vectors(sub: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data")
        .join(sub);
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "bssrdf"))
        .collect();
    files.sort();
    files
}

/// Whether the file declares zstd sections (required feature bit 0), which Miri cannot decode.
fn skipped_under_miri(bytes: &[u8]) -> bool {
    cfg!(miri) && bytes.get(32).is_some_and(|b| b & 1 != 0)
}

/// Every byte a library exposes, section by section in directory order, with each table's
/// `&[f32]` views checked for alignment.
fn exposed(library: &Library) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for table in library.tables() {
        for kind in SectionKind::ALL.into_iter().filter(|k| k.per_table()) {
            if let Some(view) = table.section(kind) {
                assert_eq!(view.as_ptr().align_offset(4), 0, "{kind:?} view misaligned");
                out.push(view.iter().flat_map(|v| v.to_le_bytes()).collect());
            }
        }
        for info in table.section_infos() {
            out.push(table.raw_section(info.kind).unwrap().to_vec());
        }
    }
    for info in library.sections().iter().filter(|s| s.table.is_none()) {
        out.push(library.file_section(info.kind).unwrap().to_vec());
    }
    out
}

#[test]
fn every_valid_vector_opens_alike_mapped_and_read() {
    for path in vectors("valid") {
        let bytes = std::fs::read(&path).unwrap();
        if skipped_under_miri(&bytes) {
            continue;
        }
        let mapped = Library::open_mmap(&path, Verify::Full).unwrap();
        let read = Library::read(&path, Verify::Full).unwrap();
        let copied = Library::from_bytes(&bytes, Verify::HeaderOnly).unwrap();
        copied.verify().unwrap();
        assert_eq!(mapped.is_mapped(), !cfg!(miri));
        assert!(!read.is_mapped());
        let expected = exposed(&read);
        assert_eq!(exposed(&mapped), expected, "{path:?}");
        assert_eq!(exposed(&copied), expected, "{path:?}");
        assert_eq!(mapped.materials(), read.materials());
    }
}

#[test]
fn every_invalid_vector_fails_alike_mapped_and_read() {
    for path in vectors("invalid") {
        let bytes = std::fs::read(&path).unwrap();
        if skipped_under_miri(&bytes) {
            continue;
        }
        let code = path.file_stem().unwrap().to_str().unwrap();
        for opened in [
            Library::open_mmap(&path, Verify::Full),
            Library::read(&path, Verify::Full),
            Library::from_bytes(&bytes, Verify::Full),
        ] {
            assert_eq!(opened.unwrap_err().code(), code, "{path:?}");
        }
    }
}

/// What is not a regular file fails alike mapped and read, with the system's own reason: a
/// folder is "Is a directory" (mapping it failed with "No such device"), /dev/null a file too
/// short to be a library.
#[test]
#[cfg_attr(miri, ignore = "opens folders and devices")]
fn a_folder_or_device_fails_alike_mapped_and_read() {
    let dir = std::env::temp_dir();
    for opened in [
        Library::open_mmap(&dir, Verify::Full),
        Library::read(&dir, Verify::Full),
    ] {
        let message = opened.unwrap_err().to_string();
        assert!(message.contains("Is a directory"), "{message}");
    }
    if Path::new("/dev/null").exists() {
        let mapped = Library::open_mmap("/dev/null", Verify::Full).unwrap_err();
        let read = Library::read("/dev/null", Verify::Full).unwrap_err();
        assert_eq!(mapped.to_string(), read.to_string());
    }
}

#[test]
fn views_into_a_map_live_as_long_as_the_library() {
    let path = vectors("valid")
        .into_iter()
        .find(|p| p.ends_with("tiny.bssrdf"))
        .unwrap();
    let library = Library::open_mmap(&path, Verify::Full).unwrap();
    let table = library.table(0).unwrap();
    let (gwc, cdf) = (table.gwc_params(), table.radial_cdf());
    let names: Vec<&str> = library
        .materials()
        .iter()
        .map(|m| m.name.as_str())
        .collect();
    // The views borrow the library: reading them after other opens and drops of the same file.
    drop(Library::open_mmap(&path, Verify::Full).unwrap());
    let sum: f32 = gwc.iter().chain(cdf).sum();
    assert!(sum.is_finite() && !names.is_empty());
}
