//! Conformance vectors: hand-made files in `tests/data/`, each invalid one rejected with its
//! own error, each valid one accepted, plus the accept path of the checks that tolerate
//! newer minors, extensions and skipped verification.
//!
//! The files are generated here from the tiny library of `common`. After a deliberate format
//! change, regenerate and review them with
//! `BSSRDF_REGEN_VECTORS=1 cargo test -p bssrdf-zoo --test format conformance`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use bssrdf_testkit::files::{
    kind, synthetic_table, tiny_builder, tiny_two_lobes_sections, Raw, Sec, ENTRY, HEADER,
};
use bssrdf_zoo::format::spec::VERSION_MINOR;
use bssrdf_zoo::format::{
    pack, AxisKind, Compression, Library, LibraryBuilder, SectionKind, Verify,
};
use bssrdf_zoo::table::RidgeKind;

use super::ridge::{ridge_vectors, tiny_ridge};
use super::walk::{tiny_walk, walk_vectors};

fn data_dir(sub: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data")
        .join(sub)
}

fn tiny() -> Raw {
    Raw::new(tiny_builder().to_bytes(Compression::None).unwrap())
}

fn tiny_packed() -> Raw {
    Raw::new(
        tiny_builder()
            .to_bytes(Compression::Zstd { level: 3 })
            .unwrap(),
    )
}

/// Offset of material record `m` in a tiny file.
fn material(raw: &Raw, m: usize) -> usize {
    raw.data(kind::MATERIALS, kind::FILE) + 512 * m
}

fn last_entry(raw: &Raw) -> usize {
    raw.entry(raw.section_count() - 1)
}

/// Byte offset within `gwc-params` of the node the node vectors change: node 5 of the tiny
/// table's 2×2×4, (i, j, k) = (0, 1, 1).
const NODE: usize = 5 * 12;

/// A change that makes the tiny library invalid.
type Mutation = Box<dyn Fn(&mut Raw)>;

/// Every invalid vector: its error code (also its file name) and how it is made. Each one
/// changes the tiny library just enough to fail one check and recomputes the CRCs where the
/// check comes after them.
fn invalid_vectors() -> Vec<(&'static str, Raw)> {
    let gwc = |r: &Raw| r.entry(r.find(kind::GWC, 0));
    let mut v: Vec<(&'static str, Mutation)> = vec![
        ("bad-magic", Box::new(|r| r.bytes[1] = b'X')),
        ("too-short", Box::new(|r| r.bytes.truncate(100))),
        ("wrong-byte-order", Box::new(|r| r.set_u32(16, 0x0D0C_0B0A))),
        ("unsupported-major", Box::new(|r| r.set_u16(12, 2))),
        (
            "truncated",
            Box::new(|r| r.bytes.truncate(r.bytes.len() - 8)),
        ),
        ("trailing-bytes", Box::new(|r| r.bytes.extend([0; 4]))),
        (
            "directory-out-of-bounds",
            Box::new(|r| r.set_u32(20, 1_000_000)),
        ),
        // The stored CRC alone: every byte it covers stays valid, so a reader that skips the
        // header CRC accepts the file (`header_crc_vector_differs_only_in_the_stored_crc`).
        ("header-crc", Box::new(|r| r.bytes[124] ^= 1)),
        ("unsupported-features", Box::new(|r| r.set_u64(32, 1 << 7))),
        ("reserved-not-zero", Box::new(|r| r.bytes[60] = 1)),
        ("bad-alignment", Box::new(|r| r.set_u32(48, 100))),
        ("unknown-dtype", Box::new(|r| r.set_u16(r.entry(0) + 8, 9))),
        ("unknown-codec", Box::new(|r| r.set_u16(r.entry(0) + 10, 7))),
        (
            "feature-not-declared",
            Box::new(|r| r.set_u16(r.entry(0) + 10, 1)),
        ),
        ("bad-shape", Box::new(|r| r.set_u16(r.entry(0) + 14, 5))),
        (
            "section-too-large",
            Box::new(move |r| {
                let e = gwc(r);
                r.set_u32(e + 16, 65536);
                r.set_u32(e + 20, 65536);
            }),
        ),
        (
            "raw-length-mismatch",
            Box::new(|r| {
                let e = r.entry(0) + 48;
                r.set_u64(e, r.u64(e) + 4);
            }),
        ),
        (
            "stored-length-mismatch",
            Box::new(|r| {
                let e = r.entry(0) + 40;
                r.set_u64(e, r.u64(e) + 4);
            }),
        ),
        (
            "section-flags",
            Box::new(|r| r.set_u16(r.entry(0) + 12, 0x8001)),
        ),
        (
            "misaligned-section",
            Box::new(|r| {
                let e = last_entry(r) + 32;
                r.set_u64(e, r.u64(e) + 4);
            }),
        ),
        (
            "sections-out-of-order",
            Box::new(|r| {
                let first = r.offset(0) as u64;
                r.set_u64(last_entry(r) + 32, first);
            }),
        ),
        (
            "sections-overlap",
            Box::new(|r| {
                let previous = r.offset(r.section_count() - 2) as u64;
                r.set_u64(last_entry(r) + 32, previous);
            }),
        ),
        (
            "section-gap",
            Box::new(|r| {
                let e = last_entry(r) + 32;
                r.set_u64(e, r.u64(e) + 256);
            }),
        ),
        (
            "section-out-of-bounds",
            Box::new(|r| {
                // theta-cdf [2, 2] -> [2, 66]: 528 bytes, past the end of the file.
                let e = r.entry(r.find(kind::ALBEDO, 0));
                r.set_u32(e + 20, 66);
                r.set_u64(e + 40, 528);
                r.set_u64(e + 48, 528);
            }),
        ),
        (
            "data-after-last-section",
            Box::new(|r| {
                r.bytes.extend([0; 256]);
                r.set_file_size();
            }),
        ),
        (
            "non-zero-padding",
            Box::new(|r| {
                let dir_end = HEADER + ENTRY * r.section_count();
                r.bytes[dir_end] = 1;
            }),
        ),
        (
            "unknown-required-section",
            Box::new(|r| {
                let e = r.entry(r.find(kind::ALBEDO, 0));
                r.set_u32(e, 0x7777);
                r.set_u16(e + 12, 1);
            }),
        ),
        (
            "wrong-dtype",
            Box::new(|r| {
                let e = r.entry(r.find(kind::AXIS_RHO, 0));
                r.set_u16(e + 8, 1);
                r.set_u32(e + 16, 8);
            }),
        ),
        (
            "section-table-index",
            Box::new(move |r| r.set_u32(gwc(r) + 4, 5)),
        ),
        (
            "duplicate-section",
            Box::new(|r| {
                let e = r.entry(r.find(kind::AXIS_THETA, 0));
                r.set_u32(e, kind::AXIS_RHO);
            }),
        ),
        (
            "missing-section",
            Box::new(|r| {
                let e = r.entry(r.find(kind::CDF, 0));
                r.set_u32(e, 0x7000);
                r.set_u16(e + 12, 0);
            }),
        ),
        ("section-crc", Box::new(|_| {})),
        (
            "record-size",
            Box::new(|r| {
                let e = r.entry(r.find(kind::TABLES, kind::FILE));
                r.set_u32(e + 16, 2);
                r.set_u32(e + 20, 32);
            }),
        ),
        (
            "unknown-model",
            Box::new(|r| {
                let t = r.data(kind::TABLES, kind::FILE);
                r.set_u32(t, 9);
            }),
        ),
        (
            "unknown-fresnel",
            Box::new(|r| {
                let t = r.data(kind::TABLES, kind::FILE);
                r.set_u32(t + 4, 5);
            }),
        ),
        (
            "table-eta",
            Box::new(|r| {
                let t = r.data(kind::TABLES, kind::FILE);
                r.set_f64(t + 8, -1.0);
            }),
        ),
        (
            "table-dims",
            Box::new(|r| {
                let t = r.data(kind::TABLES, kind::FILE);
                r.set_u32(t + 16, 0);
            }),
        ),
        (
            "section-dims",
            Box::new(|r| {
                let e = r.entry(r.find(kind::CDF, 0));
                r.set_u32(e + 16, 4);
                r.set_u32(e + 24, 2);
            }),
        ),
        (
            "non-finite",
            Box::new(|r| {
                let d = r.data(kind::GWC, 0);
                r.set_f32(d + 20, f32::NAN);
            }),
        ),
        (
            "negative-lobe",
            Box::new(|r| {
                let d = r.data(kind::GWC, 0);
                r.set_f32(d + NODE + 4, -0.25);
            }),
        ),
        (
            "radial-cdf-decreasing",
            Box::new(|r| {
                // The second radius of the first row below the first (a running integral
                // never decreases)
                let d = r.data(kind::CDF, 0);
                let first = f32::from_bits(r.u32(d));
                r.set_f32(d + 4, 0.5 * first);
            }),
        ),
        (
            "theta-cdf-decreasing",
            Box::new(|r| {
                // The first angle of the first albedo row above the second (the tiny table
                // has two angles; a running integral never decreases)
                let d = r.data(kind::ALBEDO, 0);
                let second = f32::from_bits(r.u32(d + 4));
                r.set_f32(d, 2.0 * second);
            }),
        ),
        (
            "concentration-out-of-range",
            Box::new(|r| {
                let d = r.data(kind::GWC, 0);
                r.set_f32(d + NODE + 8, 1.0);
            }),
        ),
        (
            "negative-profile",
            Box::new(|r| {
                // E_β·2|c| = 0.5 > E·(1 + |c|) = 0.15, with the signed-floor bit set so that only
                // the profile rule fails.
                let d = r.data(kind::GWC, 0);
                r.set_f32(d + NODE, 0.1);
                r.set_f32(d + NODE + 4, 0.5);
                r.set_f32(d + NODE + 8, 0.5);
                r.set_u64(32, 1 << 1);
            }),
        ),
        (
            "signed-floor-not-declared",
            Box::new(|r| {
                // E_β = 1.25 E: a negative floor under a profile that stays ≥ 0 (|c| ≤ 0.25),
                // without required feature bit 1.
                let d = r.data(kind::GWC, 0);
                let e = f32::from_bits(r.u32(d + NODE));
                r.set_f32(d + NODE + 4, 1.25 * e);
            }),
        ),
        (
            "axis-not-increasing",
            Box::new(|r| {
                let d = r.data(kind::AXIS_R, 0);
                let (a, b) = (r.u32(d + 4), r.u32(d + 8));
                r.set_u32(d + 4, b);
                r.set_u32(d + 8, a);
            }),
        ),
        (
            "axis-out-of-range",
            Box::new(|r| {
                let d = r.data(kind::AXIS_RHO, 0);
                r.set_f32(d + 4, 1.5);
            }),
        ),
        (
            "empty-name",
            Box::new(|r| {
                let m = material(r, 0);
                r.set_u32(m, 0);
                r.bytes[m + 192..m + 256].fill(0);
            }),
        ),
        (
            "string-too-long",
            Box::new(|r| r.set_u32(material(r, 0) + 4, 300)),
        ),
        (
            "invalid-utf8",
            Box::new(|r| {
                let m = material(r, 0);
                r.bytes[m + 192] = 0xFF;
            }),
        ),
        (
            "control-character",
            Box::new(|r| {
                let m = material(r, 0);
                r.bytes[m + 192] = 7;
            }),
        ),
        (
            "duplicate-name",
            Box::new(|r| {
                let (a, b) = (material(r, 0), material(r, 1));
                r.set_u32(b, r.u32(a));
                r.bytes.copy_within(a + 192..a + 256, b + 192);
            }),
        ),
        (
            "material-table",
            Box::new(|r| r.set_u32(material(r, 0) + 12, 9)),
        ),
        (
            "material-value",
            Box::new(|r| r.set_f64(material(r, 0) + 48, -1.0)),
        ),
        (
            "provenance-json",
            Box::new(|r| {
                let d = r.data(kind::PROVENANCE, kind::FILE);
                r.bytes[d] = b'[';
            }),
        ),
        (
            "provenance-duplicate-key",
            Box::new(|r| {
                let d = r.data(kind::PROVENANCE, kind::FILE);
                let n = r.stored_len(r.find(kind::PROVENANCE, kind::FILE));
                let text = String::from_utf8(r.bytes[d..d + n].to_vec()).unwrap();
                let at = d + text.find("settings").unwrap();
                r.bytes[at..at + 8].copy_from_slice(b"accuracy");
            }),
        ),
    ];
    // Vectors whose check runs before the header CRC keep the stale CRC (it would not be
    // reached); "header-crc" and "section-crc" must keep theirs; the rest get fixed CRCs.
    let no_fix = [
        "bad-magic",
        "too-short",
        "wrong-byte-order",
        "unsupported-major",
        "truncated",
        "trailing-bytes",
        "directory-out-of-bounds",
        "header-crc",
        "non-zero-padding",
    ];
    let mut out = Vec::new();
    for (code, make) in v.drain(..) {
        let mut raw = tiny();
        make(&mut raw);
        if code == "section-crc" {
            let d = raw.data(kind::GWC, 0);
            raw.bytes[d] ^= 1;
        } else if !no_fix.contains(&code) {
            raw.fix_crcs();
        }
        out.push((code, raw));
    }
    out.extend(packed_vectors());
    out
}

/// The tiny library with a `gwc-harmonics` section for its table, declaring required feature
/// bit 2 or not.
fn two_lobes(declared: bool) -> Raw {
    let required = if declared { 1 << 2 } else { 0 };
    Raw::build(2, required, 0, 256, &tiny_two_lobes_sections())
}

/// The two-lobe tiny library with node (0, 0, 1) a signed pair: r·μₙ of β = (1, −0.5) at
/// c = (0.8, 0.5), so (E_β, c) = (0.587379, 0.936364) for r·μ₁ = 0.55, r·μ₂ = 0.515 and
/// (r·μ₃, r·μ₄) = (0.4495, 0.37835), with E = 1. Format 1.3: bit 2, and bit 3 if `declared`.
fn signed_lobes(declared: bool) -> Raw {
    let mut secs = tiny_two_lobes_sections();
    let put = |data: &mut Vec<u8>, at: usize, values: &[f32]| {
        for (k, v) in values.iter().enumerate() {
            data[4 * (at + k)..4 * (at + k + 1)].copy_from_slice(&v.to_le_bytes());
        }
    };
    let gwc = secs.iter().position(|s| s.kind == kind::GWC).unwrap();
    put(&mut secs[gwc].data, 3, &[1.0, 0.587_379, 0.936_364]);
    let harmonics = secs.iter().position(|s| s.kind == kind::HARMONICS).unwrap();
    put(&mut secs[harmonics].data, 2, &[0.4495, 0.378_35]);
    let required = (1 << 2) | if declared { 1 << 3 } else { 0 };
    Raw::build(3, required, 0, 256, &secs)
}

/// The two-lobe tiny library with node (0, 0, 1) the limit of a signed pair whose roots merge
/// at c = 0.7 (format-spec.md §10 step 4b): r·μₙ = cⁿ + γncⁿ⁻¹ with γ = 0.1 (a lobe of mass 1
/// plus γ times its derivative in c), with r·μ₄ lowered by 10⁻³ so that Prony's roots are
/// complex, stored as (E, E_β, c) = (1.2, μ₁²/μ₂, μ₂/μ₁) and (r·μ₃, r·μ₄). Read with merged roots,
/// a signed pair; without, one lobe. Format 1.4, required feature bits `required`.
fn merged_roots(required: u64) -> Raw {
    let mut secs = tiny_two_lobes_sections();
    let mu = |n: i32| 0.7f64.powi(n) + 0.1 * f64::from(n) * 0.7f64.powi(n - 1);
    let put = |data: &mut Vec<u8>, at: usize, values: &[f64]| {
        for (k, &v) in values.iter().enumerate() {
            data[4 * (at + k)..4 * (at + k + 1)].copy_from_slice(&(v as f32).to_le_bytes());
        }
    };
    let gwc = secs.iter().position(|s| s.kind == kind::GWC).unwrap();
    put(
        &mut secs[gwc].data,
        3,
        &[1.2, mu(1) * mu(1) / mu(2), mu(2) / mu(1)],
    );
    let harmonics = secs.iter().position(|s| s.kind == kind::HARMONICS).unwrap();
    put(&mut secs[harmonics].data, 2, &[mu(3), mu(4) * 0.999]);
    Raw::build(4, required, 0, 256, &secs)
}

/// Vectors that need compressed sections.
fn packed_vectors() -> Vec<(&'static str, Raw)> {
    let mut out = Vec::new();
    // zstd: the stored bytes of a compressed section are not a zstd frame.
    let mut raw = tiny_packed();
    let i = raw.find(kind::GWC, 0);
    let (o, n) = (raw.offset(i), raw.stored_len(i));
    raw.bytes[o..o + n].fill(0xAA);
    raw.fix_crcs();
    out.push(("zstd", raw));
    // decoded-length: a valid frame of 60 bytes where the table records need 64.
    let mut secs = tiny().sections();
    let tables = &mut secs[0];
    tables.data.truncate(60);
    tables.data = zstd::bulk::compress(&tables.data, 3).unwrap();
    tables.codec = 1;
    tables.raw_len = Some(64);
    out.push(("decoded-length", Raw::build(0, 1, 0, 256, &secs)));
    // too-many-records: 65536 table records (4 MiB of zeros, a few hundred bytes packed).
    let mut secs = tiny().sections();
    secs[0].dims = vec![65536, 64];
    secs[0].data = vec![0; 65536 * 64];
    secs[0] = secs[0].clone().zstd();
    out.push(("too-many-records", Raw::build(0, 1, 0, 256, &secs)));
    // harmonics-not-declared: a gwc-harmonics section without required feature bit 2.
    out.push(("harmonics-not-declared", two_lobes(false)));
    // signed-lobes-not-declared: a node that is a signed pair without required feature bit 3.
    out.push(("signed-lobes-not-declared", signed_lobes(false)));
    // The walk-angular record's: bit 5 not set, an unknown component, g outside (-1, 1).
    out.extend(walk_vectors());
    // The ridge field's: bit 6 not set, a value other than 0, 1 and 2.
    out.extend(ridge_vectors());
    out
}

/// Valid files beyond the writer's defaults: each exercises the accept path of a check.
fn valid_vectors() -> Vec<(&'static str, Vec<u8>)> {
    let mut out = vec![("tiny", tiny().bytes), ("tiny-packed", tiny_packed().bytes)];
    // A newer minor: unknown optional feature bit, non-zero reserved bytes, unknown flag bits,
    // longer table records and an unknown optional section; all ignored.
    let mut secs = tiny().sections();
    secs[0].dims = vec![1, 96];
    secs[0].raw_len = None;
    secs[0].data.extend([0x5A; 32]);
    secs[0].data[40] = 1; // reserved byte of the record
    secs[1].flags |= 0x10;
    secs.push(Sec {
        kind: 0x7001,
        table: 0,
        dtype: 2,
        codec: 0,
        flags: 0,
        dims: vec![2],
        data: [7.0f32, 8.0].iter().flat_map(|v| v.to_le_bytes()).collect(),
        raw_len: None,
    });
    let mut raw = Raw::build(VERSION_MINOR + 1, 0, 1 << 9, 256, &secs);
    raw.bytes[100] = 0x42;
    raw.fix_crcs();
    out.push(("newer-minor", raw.bytes));
    // An older minor: the tiny library as format 1.0 wrote it (no negative floor), read strictly.
    out.push((
        "older-minor",
        Raw::build(0, 0, 0, 256, &tiny().sections()).bytes,
    ));
    // Two lobes: the tiny library with a gwc-harmonics section, required feature bit 2.
    out.push(("two-lobes", two_lobes(true).bytes));
    // A signed pair at one node, required feature bits 2 and 3.
    out.push(("signed-lobes", signed_lobes(true).bytes));
    // A merged pair at one node, required feature bits 2, 3 and 4.
    out.push((
        "merged-roots",
        merged_roots((1 << 2) | (1 << 3) | (1 << 4)).bytes,
    ));
    // A walk-angular table (g = 0.75, total), required feature bits 2, 4 and 5.
    out.push(("walk-table", tiny_walk().bytes));
    // A table at eta = 1 whose nodes hold the profile less the ridge (`ridge` = 1), required
    // feature bit 6; and the same less the ridge with its fluence part (`ridge` = 2).
    out.push(("ridge", tiny_ridge(RidgeKind::Flux).bytes));
    out.push(("ridge-fluence", tiny_ridge(RidgeKind::FluxAndFluence).bytes));
    // Page alignment, one albedo row, no materials, no provenance, no θ CDF.
    let mut b = LibraryBuilder::new();
    b.set_alignment(4096).unwrap();
    b.add_table(synthetic_table(1.0, 1, 3, 5, false)).unwrap();
    out.push(("aligned-4096", b.to_bytes(Compression::None).unwrap()));
    // No tables at all, and no materials: an empty library.
    out.push((
        "empty",
        LibraryBuilder::new().to_bytes(Compression::None).unwrap(),
    ));
    out
}

/// Writes the vectors when regenerating; otherwise checks the committed files are the same.
fn sync(dir: &Path, name: &str, bytes: &[u8]) {
    let path = dir.join(format!("{name}.bssrdf"));
    if std::env::var_os("BSSRDF_REGEN_VECTORS").is_some() {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(&path, bytes).unwrap();
    } else {
        let committed = std::fs::read(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (regenerate the vectors)", path.display()));
        assert!(
            committed == bytes,
            "{} is stale: regenerate",
            path.display()
        );
    }
}

#[test]
fn raw_editor_rebuilds_the_writer_output_exactly() {
    let raw = tiny();
    let rebuilt = Raw::build(VERSION_MINOR, 0, 0, 256, &raw.sections());
    assert!(rebuilt.bytes == raw.bytes);
}

#[test]
fn every_invalid_vector_is_rejected_with_its_own_error() {
    let vectors = invalid_vectors();
    let dir = data_dir("invalid");
    let mut codes = BTreeSet::new();
    for (code, raw) in &vectors {
        assert!(codes.insert(*code), "two vectors for {code}");
        sync(&dir, code, &raw.bytes);
        for (how, result) in [
            ("bytes", Library::from_bytes(&raw.bytes, Verify::Full)),
            (
                "mmap",
                Library::open_mmap(dir.join(format!("{code}.bssrdf")), Verify::Full),
            ),
            (
                "read",
                Library::read(dir.join(format!("{code}.bssrdf")), Verify::Full),
            ),
        ] {
            match result {
                Ok(_) => panic!("{code} ({how}) was accepted"),
                Err(e) => assert_eq!(e.code(), *code, "{code} ({how}): {e}"),
            }
        }
    }
    // Every committed invalid file is one of the vectors (no orphans).
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        let code = name.strip_suffix(".bssrdf").unwrap();
        assert!(codes.contains(code), "orphan vector {name}");
    }
}

/// The `header-crc` vector isolates the header CRC check: it is the valid tiny library with
/// one bit of the stored CRC flipped, so no other rule rejects it: with the CRC recomputed it
/// is the tiny library again, which every reader accepts.
#[test]
fn header_crc_vector_differs_only_in_the_stored_crc() {
    let (_, vector) = invalid_vectors()
        .into_iter()
        .find(|(code, _)| *code == "header-crc")
        .unwrap();
    let valid = tiny();
    let differing: Vec<usize> = (0..valid.bytes.len())
        .filter(|&i| vector.bytes[i] != valid.bytes[i])
        .collect();
    assert_eq!(
        (vector.bytes.len(), differing),
        (valid.bytes.len(), vec![124])
    );
    let mut fixed = vector.clone();
    fixed.fix_header_crc();
    assert!(fixed.bytes == valid.bytes);
    assert!(Library::from_bytes(&fixed.bytes, Verify::Full).is_ok());
}

#[test]
fn every_error_a_file_can_cause_has_a_vector() {
    let codes: BTreeSet<&str> = invalid_vectors().iter().map(|(c, _)| *c).collect();
    // Errors no file content can cause: I/O, the host, builder input, rewriting.
    let not_from_files = [
        "io",
        "big-endian-host",
        "invalid-input",
        "rewrite-newer-minor",
    ];
    let source = include_str!("../../../runtime/src/format/error.rs");
    let mut seen = 0;
    for line in source.lines() {
        let Some(rest) = line.trim().strip_prefix("FormatError::") else {
            continue;
        };
        let Some((_, code)) = rest.split_once("=> \"") else {
            continue;
        };
        let code = code.trim_end_matches("\",");
        seen += 1;
        assert!(
            codes.contains(code) || not_from_files.contains(&code),
            "no conformance vector for {code}"
        );
    }
    assert_eq!(
        seen,
        codes.len() + not_from_files.len(),
        "error codes not parsed"
    );
}

#[test]
fn every_valid_vector_is_accepted() {
    let dir = data_dir("valid");
    for (name, bytes) in valid_vectors() {
        sync(&dir, name, &bytes);
        let path = dir.join(format!("{name}.bssrdf"));
        for library in [
            Library::open_mmap(&path, Verify::Full),
            Library::read(&path, Verify::HeaderOnly),
        ] {
            let library = library.unwrap_or_else(|e| panic!("{name}: {e}"));
            library.verify().unwrap();
        }
    }
}

#[test]
fn newer_minor_is_read_and_its_extensions_skipped_but_not_rewritten() {
    let path = data_dir("valid").join("newer-minor.bssrdf");
    let library = Library::open_mmap(&path, Verify::Full).unwrap();
    assert_eq!(library.version(), (1, VERSION_MINOR + 1));
    assert_eq!(library.optional_features(), 1 << 9);
    let table = library.table(0).unwrap();
    assert_eq!(table.dims(), [2, 2, 4]);
    let extra = table.raw_section(0x7001).unwrap();
    assert_eq!(extra, [7.0f32, 8.0].map(f32::to_le_bytes).concat());
    assert_eq!(library.materials().len(), 2);
    let out = tempfile::tempdir().unwrap();
    let err = pack(&path, out.path().join("x"), 3).unwrap_err();
    assert_eq!(err.code(), "rewrite-newer-minor", "{err}");
}

#[test]
fn older_minor_is_read_strictly_and_under_the_same_node_rules() {
    let path = data_dir("valid").join("older-minor.bssrdf");
    let library = Library::open_mmap(&path, Verify::Full).unwrap();
    assert_eq!(library.version(), (1, 0));
    assert_eq!(library.required_features(), 0);
    let tiny = Library::from_bytes(&tiny().bytes, Verify::Full).unwrap();
    let (old, new) = (library.table(0).unwrap(), tiny.table(0).unwrap());
    assert_eq!(old.gwc_params(), new.gwc_params());
    // Strict: a reserved header byte is an error in a file of an older minor.
    let mut raw = Raw::new(std::fs::read(&path).unwrap());
    raw.bytes[100] = 0x42;
    raw.fix_crcs();
    let err = Library::from_bytes(&raw.bytes, Verify::Full).unwrap_err();
    assert_eq!(err.code(), "reserved-not-zero", "{err}");
    // A 1.0 file with E_β > E is ambiguous (the 1.0 reader clamped E_β to E): rejected too.
    let mut raw = Raw::new(std::fs::read(&path).unwrap());
    let d = raw.data(kind::GWC, 0);
    let e = f32::from_bits(raw.u32(d + NODE));
    raw.set_f32(d + NODE + 4, 1.25 * e);
    raw.fix_crcs();
    let err = Library::from_bytes(&raw.bytes, Verify::Full).unwrap_err();
    assert_eq!(err.code(), "signed-floor-not-declared", "{err}");
    assert!(err.to_string().contains("(0, 1, 1)"), "{err}");
}

#[test]
fn strict_checks_accept_what_they_should() {
    let valid = |name: &str| {
        valid_vectors()
            .into_iter()
            .find(|(n, _)| *n == name)
            .unwrap()
            .1
    };
    let library = Library::from_bytes(&valid("aligned-4096"), Verify::Full).unwrap();
    assert_eq!(library.alignment(), 4096);
    assert!(library.sections().iter().all(|s| s.offset % 4096 == 0));
    let table = library.table(0).unwrap();
    assert_eq!(table.axis(AxisKind::Rho).len(), 1);
    assert!(table.theta_cdf().is_none());
    assert!(library.materials().is_empty() && library.provenance().is_none());
    let empty = Library::from_bytes(&valid("empty"), Verify::Full).unwrap();
    assert_eq!(empty.table_count(), 0);
    assert!(empty.sections().iter().all(|s| s.raw_len == 0));
    // Zero-length sections share the first aligned offset after the directory.
    assert!(empty.sections().iter().all(|s| s.offset == 256));
}

#[test]
fn header_only_skips_section_crcs_and_value_checks_until_verify() {
    let vectors = invalid_vectors();
    for code in [
        "section-crc",
        "non-finite",
        "negative-lobe",
        "concentration-out-of-range",
        "negative-profile",
        "signed-floor-not-declared",
        "radial-cdf-decreasing",
        "theta-cdf-decreasing",
    ] {
        let raw = &vectors.iter().find(|(c, _)| *c == code).unwrap().1;
        let library = Library::from_bytes(&raw.bytes, Verify::HeaderOnly)
            .unwrap_or_else(|e| panic!("{code}: {e}"));
        assert_eq!(library.verify().unwrap_err().code(), code);
        assert!(library
            .table(0)
            .unwrap()
            .section(SectionKind::GwcParams)
            .is_some());
    }
}
