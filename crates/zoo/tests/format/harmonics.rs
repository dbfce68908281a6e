//! Every rule of format-spec.md that applies to a `gwc-harmonics` section (kind 0x23, format
//! 1.2), each broken by a file that must be rejected with the error code §14 names, and the
//! accept paths next to them. Errors that other sections already have a conformance vector
//! for are tested here rather than by more vectors (§17 asks for one file per error, not per
//! rule); `harmonics-not-declared` has its vector in `tests/data/invalid/`.
//!
//! The files are the tiny library of the testkit with a harmonics section for its one
//! 2×2×4 table, the last of its ten sections (entry 9), changed in one field and, where the
//! check comes after them, with the CRCs recomputed.

use crate::{assert_accepted, assert_rejected_by};
use bssrdf_testkit::files::{
    kind, synthetic_table, tiny_builder, tiny_two_lobes_sections, Raw, Sec,
};
use bssrdf_zoo::format::spec::required_features::{
    HARMONICS, MERGED_ROOTS, SIGNED_FLOOR, SIGNED_LOBES, ZSTD,
};
use bssrdf_zoo::format::spec::VERSION_MINOR;
use bssrdf_zoo::format::{
    pack, unpack, Compression, Library, LibraryBuilder, SectionKind, TableData, Verify,
};

/// Directory index of the harmonics section in the two-lobe file.
const SECTION: usize = 9;
/// Number of f32 values of the harmonics section: [2, 2, 4, 2].
const VALUES: usize = 32;

/// The two-lobe tiny library, declaring required feature bit 2, at the minor this crate writes
/// (the conformance vector `two-lobes` has the same sections at minor 2).
fn two_lobes() -> Raw {
    build(VERSION_MINOR, HARMONICS, &tiny_two_lobes_sections())
}

fn build(minor: u16, required: u64, secs: &[Sec]) -> Raw {
    Raw::build(minor, required, 0, 256, secs)
}

/// The two-lobe file with its harmonics section changed by `edit` before layout (every CRC
/// right).
fn with_harmonics(edit: impl Fn(&mut Sec)) -> Raw {
    let mut secs = tiny_two_lobes_sections();
    edit(&mut secs[SECTION]);
    build(2, HARMONICS, &secs)
}

/// The two-lobe file with its bytes changed by `edit` and then every CRC recomputed.
fn edited(edit: impl Fn(&mut Raw)) -> Raw {
    let mut raw = two_lobes();
    edit(&mut raw);
    raw.fix_crcs();
    raw
}

/// File offset of the harmonics entry.
fn entry(raw: &Raw) -> usize {
    raw.entry(raw.find(kind::HARMONICS, 0))
}

fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Checks whose failure [`Verify::HeaderOnly`] defers to [`Library::verify`].
const DEFERRED: [&str; 3] = ["section-crc", "non-finite", "negative-lobe"];

/// Asserts that `raw` is rejected with `code` at a full open, and with a header-only open
/// either at open or (for the deferred checks) by `verify`; the message must contain `needle`.
fn assert_rejected(case: &str, raw: &Raw, code: &str, needle: &str) {
    assert_rejected_by(case, raw, Verify::Full, code, needle);
    match Library::from_bytes(&raw.bytes, Verify::HeaderOnly) {
        Err(e) => {
            assert!(!DEFERRED.contains(&code), "{case}: {code} not deferred");
            assert_eq!(e.code(), code, "{case} (header only): {e}");
        }
        Ok(library) => {
            assert!(
                DEFERRED.contains(&code),
                "{case}: header-only open accepted"
            );
            let e = library.verify().unwrap_err();
            assert_eq!(e.code(), code, "{case} (verify): {e}");
        }
    }
}

#[test]
fn the_two_lobe_file_is_valid() {
    let library = assert_accepted("two lobes", &two_lobes());
    assert_eq!(library.version(), (1, VERSION_MINOR));
    assert_eq!(library.required_features(), HARMONICS);
    let harmonics = library.table(0).unwrap().harmonics().unwrap();
    assert_eq!(harmonics.len(), VALUES);
    // The last entry, which the messages below name as "section 9".
    let raw = two_lobes();
    assert_eq!(raw.find(kind::HARMONICS, 0), SECTION);
    assert_eq!(raw.section_count(), SECTION + 1);
    let info = &library.sections()[SECTION];
    assert_eq!(info.known_kind(), Some(SectionKind::Harmonics));
    assert!(info.required);
}

/// §4, bit 2: "a reader MUST reject a file with such a section when the bit is not set"; §14
/// step 7 checks it per entry, after the codec and before the shape, so it is not deferred.
#[test]
fn a_harmonics_section_needs_required_feature_bit_2() {
    let secs = tiny_two_lobes_sections();
    let needle = "section 9: gwc-harmonics";
    for (case, minor, required) in [
        ("no bit", 2, 0),
        ("other bits only", 2, SIGNED_FLOOR | ZSTD),
        ("a newer minor", 3, 0),
        ("an older minor", 1, SIGNED_FLOOR),
    ] {
        let raw = build(minor, required, &secs);
        assert_rejected(case, &raw, "harmonics-not-declared", needle);
    }
    // Order within the entry: a zstd section without bit 0 fails first, a bad shape after.
    let mut compressed = secs.clone();
    compressed[SECTION] = compressed[SECTION].clone().zstd();
    let raw = build(2, 0, &compressed);
    assert_rejected("zstd, no bits", &raw, "feature-not-declared", "section 9");
    let mut raw = build(2, 0, &secs);
    let e = entry(&raw);
    raw.set_u16(e + 14, 5);
    raw.fix_crcs();
    assert_rejected("ndim 5, no bit", &raw, "harmonics-not-declared", needle);
    // With the bit, the same entry fails its shape.
    let raw = edited(|r| r.set_u16(entry(r) + 14, 5));
    assert_rejected("ndim 5", &raw, "bad-shape", "section 9");
}

/// §5 and §14 step 7: the entry's shape and lengths.
#[test]
fn the_entry_shape_and_lengths_are_checked() {
    type Edit = fn(&mut Raw);
    let cases: [(&str, Edit, &str); 6] = [
        ("ndim 0", |r| r.set_u16(entry(r) + 14, 0), "bad-shape"),
        // ndim 3 leaves dims[3] = 2 in place: an unused dimension that is not 0.
        ("ndim 3", |r| r.set_u16(entry(r) + 14, 3), "bad-shape"),
        (
            "over 1 GiB",
            |r| {
                let e = entry(r);
                r.set_u32(e + 16, 65536);
                r.set_u32(e + 20, 65536);
            },
            "section-too-large",
        ),
        (
            "raw_len",
            |r| {
                let e = entry(r) + 48;
                r.set_u64(e, r.u64(e) + 4);
            },
            "raw-length-mismatch",
        ),
        (
            "stored_len",
            |r| {
                let e = entry(r) + 40;
                r.set_u64(e, r.u64(e) - 4);
            },
            "stored-length-mismatch",
        ),
        (
            "reserved entry byte",
            |r| r.set_u16(entry(r) + 60, 0x0100),
            "reserved-not-zero",
        ),
    ];
    for (case, edit, code) in cases {
        let needle = if code == "reserved-not-zero" {
            "directory entry 9"
        } else {
            "section 9"
        };
        assert_rejected(case, &edited(edit), code, needle);
    }
}

/// §7 and §8: dtype f32, no unknown dtype or codec, the `required` flag set (strict reading)
/// and no reserved flag bit.
#[test]
fn dtype_codec_and_flags_are_the_kinds() {
    type Edit = fn(&mut Raw);
    let cases: [(&str, Edit, &str); 5] = [
        (
            "unknown dtype",
            |r| r.set_u16(entry(r) + 8, 9),
            "unknown-dtype",
        ),
        (
            "unknown codec",
            |r| r.set_u16(entry(r) + 10, 7),
            "unknown-codec",
        ),
        (
            "not required",
            |r| r.set_u16(entry(r) + 12, 0),
            "section-flags",
        ),
        (
            "reserved flag bit",
            |r| r.set_u16(entry(r) + 12, 0x0101),
            "section-flags",
        ),
        (
            // u8 [2, 2, 4, 8]: the same 128 bytes, so only the dtype is wrong.
            "u8",
            |r| {
                let e = entry(r);
                r.set_u16(e + 8, 1);
                r.set_u32(e + 28, 8);
            },
            "wrong-dtype",
        ),
    ];
    for (case, edit, code) in cases {
        assert_rejected(case, &edited(edit), code, "section 9");
    }
}

/// §8: a table kind, so `table` < n_tables (not 0xFFFFFFFF), and at most one per table.
#[test]
fn one_harmonics_section_per_existing_table() {
    for (case, table) in [("table 1 of 1", 1), ("file-level", u32::MAX)] {
        let raw = edited(|r| r.set_u32(entry(r) + 4, table));
        assert_rejected(case, &raw, "section-table-index", "section 9");
    }
    let mut secs = tiny_two_lobes_sections();
    secs.push(secs[SECTION].clone());
    let raw = build(2, HARMONICS, &secs);
    assert_rejected("twice", &raw, "duplicate-section", "section 10: kind 0x23");
    // One per table is fine for two tables.
    let mut b = LibraryBuilder::new();
    for eta in [1.2, 1.3] {
        b.add_table(with_harmonics_of_one_lobe(synthetic_table(
            eta, 2, 3, 4, false,
        )))
        .unwrap();
    }
    let raw = Raw::new(b.to_bytes(Compression::None).unwrap());
    let library = assert_accepted("two tables", &raw);
    assert!(library.tables().all(|t| t.harmonics().is_some()));
}

/// §8 and §10: dims [nρ, nθ, nr, 2] with the table's nρ, nθ, nr, whatever the byte count.
#[test]
fn dims_are_the_tables_axes_then_2() {
    for dims in [
        vec![2, 2, 4, 3],
        vec![2, 2, 4, 1],
        vec![2, 2, 4],
        vec![2, 2, 8],
        vec![32],
        vec![2, 2, 2, 4],
        vec![4, 2, 2, 2],
        vec![1, 2, 4, 2],
        vec![2, 1, 4, 2],
        vec![2, 2, 3, 2],
    ] {
        let count: u32 = dims.iter().product();
        let raw = with_harmonics(|s| {
            s.dims = dims.clone();
            s.data = f32_bytes(&vec![0.0; count as usize]);
            s.raw_len = None;
        });
        let case = format!("dims {dims:?}");
        let needle =
            format!("table 0: section gwc-harmonics has dims {dims:?}, expected [2, 2, 4, 2]");
        assert_rejected(&case, &raw, "section-dims", &needle);
    }
}

/// §9.1: the harmonics do not stand in for a required section.
#[test]
fn a_two_lobe_table_still_needs_its_gwc_params() {
    let raw = edited(|r| {
        let e = r.entry(r.find(kind::GWC, 0));
        r.set_u32(e, 0x7000);
        r.set_u16(e + 12, 0);
    });
    assert_rejected(
        "no gwc-params",
        &raw,
        "missing-section",
        "gwc-params for table 0",
    );
}

/// §10: "Every value of every table section MUST be finite"; the harmonics "need only be
/// finite" (no node rules), and §14 step 10 checks the values in kind order.
#[test]
fn harmonics_values_need_only_be_finite() {
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        for index in [0, 17, VALUES - 1] {
            let raw = edited(|r| {
                let d = r.data(kind::HARMONICS, 0);
                r.set_f32(d + 4 * index, bad);
            });
            let needle = format!("table 0: gwc-harmonics[{index}] = {bad}");
            assert_rejected(&format!("{bad} at {index}"), &raw, "non-finite", &needle);
        }
    }
    // Any finite values pass: negative, huge, subnormal, signed zero.
    let odd = [
        -f32::MAX,
        f32::MAX,
        -1e-45,
        f32::MIN_POSITIVE,
        -0.0,
        1e30,
        -3.5,
    ];
    let values: Vec<f32> = odd.iter().copied().cycle().take(VALUES).collect();
    let raw = with_harmonics(|s| s.data = f32_bytes(&values));
    let library = assert_accepted("odd finite values", &raw);
    let read = library.table(0).unwrap().harmonics().unwrap();
    assert_eq!(
        read.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        values.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
    // Kind order: gwc-params (0x20) and theta-cdf (0x22) come before gwc-harmonics (0x23).
    let nan_harmonics = |r: &mut Raw| {
        let d = r.data(kind::HARMONICS, 0);
        r.set_f32(d, f32::NAN);
    };
    let raw = edited(|r| {
        nan_harmonics(r);
        let d = r.data(kind::GWC, 0);
        r.set_f32(d + 4, -1.0);
    });
    assert_rejected("then a negative lobe", &raw, "negative-lobe", "table 0");
    let raw = edited(|r| {
        nan_harmonics(r);
        let d = r.data(kind::ALBEDO, 0);
        r.set_f32(d, f32::INFINITY);
    });
    assert_rejected("then theta-cdf", &raw, "non-finite", "theta-cdf[0]");
}

/// §6 and §12: the section is placed, padded and checksummed like any other (it is the last).
#[test]
fn placement_and_crc_of_the_harmonics_section() {
    type Edit = fn(&mut Raw);
    let cases: [(&str, Edit, &str, bool); 8] = [
        (
            "misaligned",
            |r| {
                let e = entry(r) + 32;
                r.set_u64(e, r.u64(e) + 4);
            },
            "misaligned-section",
            true,
        ),
        (
            "gap",
            |r| {
                let e = entry(r) + 32;
                r.set_u64(e, r.u64(e) + 256);
            },
            "section-gap",
            true,
        ),
        (
            "overlap",
            |r| r.set_u64(entry(r) + 32, r.offset(SECTION - 1) as u64),
            "sections-overlap",
            true,
        ),
        (
            "out of order",
            |r| r.set_u64(entry(r) + 32, r.offset(0) as u64),
            "sections-out-of-order",
            true,
        ),
        (
            // [2, 2, 4, 66]: 4224 bytes, past the end of the file.
            "past the end",
            |r| {
                let e = entry(r);
                r.set_u32(e + 28, 66);
                r.set_u64(e + 40, 4224);
                r.set_u64(e + 48, 4224);
            },
            "section-out-of-bounds",
            true,
        ),
        (
            "padding before it",
            |r| {
                let d = r.data(kind::HARMONICS, 0);
                r.bytes[d - 1] = 1;
            },
            "non-zero-padding",
            true,
        ),
        (
            "bytes after it",
            |r| {
                r.bytes.extend([0; 256]);
                r.set_file_size();
            },
            "data-after-last-section",
            true,
        ),
        (
            "one data bit",
            |r| {
                let d = r.data(kind::HARMONICS, 0);
                r.bytes[d + 5] ^= 1;
            },
            "section-crc",
            false,
        ),
    ];
    for (case, edit, code, fix) in cases {
        let mut raw = two_lobes();
        edit(&mut raw);
        if fix {
            raw.fix_crcs();
        }
        let needle = match code {
            "data-after-last-section" => "follow the end of the last section",
            "non-zero-padding" => "padding byte",
            _ => "section 9",
        };
        assert_rejected(case, &raw, code, needle);
    }
    // Page alignment is as good as 256.
    let raw = Raw::build(2, HARMONICS, 0, 4096, &tiny_two_lobes_sections());
    let library = assert_accepted("4096", &raw);
    assert_eq!(library.sections()[SECTION].offset % 4096, 0);
}

/// §7: a compressed harmonics section needs bit 0 as well, decodes to exactly its raw length,
/// and `pack` and `unpack` keep it.
#[test]
fn compressed_harmonics() {
    let mut secs = tiny_two_lobes_sections();
    secs[SECTION] = secs[SECTION].clone().zstd();
    let raw = build(2, HARMONICS | ZSTD, &secs);
    let library = assert_accepted("zstd", &raw);
    let plain = Library::from_bytes(&two_lobes().bytes, Verify::Full).unwrap();
    assert_eq!(
        library.table(0).unwrap().harmonics(),
        plain.table(0).unwrap().harmonics()
    );
    let raw = build(2, HARMONICS, &secs);
    assert_rejected(
        "zstd without bit 0",
        &raw,
        "feature-not-declared",
        "section 9",
    );
    // Not a zstd frame.
    let mut garbage = secs.clone();
    garbage[SECTION].data.fill(0xAA);
    let raw = build(2, HARMONICS | ZSTD, &garbage);
    assert_rejected("garbage", &raw, "zstd", "section 9");
    // A frame of 124 bytes where [2, 2, 4, 2] needs 128.
    let mut short = tiny_two_lobes_sections();
    let s = &mut short[SECTION];
    s.data.truncate(124);
    s.data = zstd::bulk::compress(&s.data, 3).unwrap();
    s.codec = 1;
    s.raw_len = Some(128);
    let raw = build(2, HARMONICS | ZSTD, &short);
    assert_rejected("short frame", &raw, "decoded-length", "section 9");
    // A frame of 132 bytes: more than the raw length is a decoded length too, not zstd's
    // "destination buffer is too small"
    let mut long = tiny_two_lobes_sections();
    let s = &mut long[SECTION];
    s.data.extend_from_slice(&[0; 4]);
    s.data = zstd::bulk::compress(&s.data, 3).unwrap();
    s.codec = 1;
    s.raw_len = Some(128);
    let raw = build(2, HARMONICS | ZSTD, &long);
    assert_rejected("long frame", &raw, "decoded-length", "decoded to 132 bytes");
    // No frame at all: a compressed section holds one or more (§7), even one that decodes to
    // nothing (the materials section of a library without materials)
    let mut builder = LibraryBuilder::new();
    builder
        .add_table(synthetic_table(1.3, 2, 2, 4, true))
        .unwrap();
    let mut empty = Raw::new(builder.to_bytes(Compression::None).unwrap()).sections();
    let materials = empty
        .iter_mut()
        .find(|s| s.kind == kind::MATERIALS)
        .unwrap();
    assert!(materials.data.is_empty());
    (materials.codec, materials.raw_len) = (1, Some(0));
    let raw = build(2, ZSTD, &empty);
    assert_rejected("no frame", &raw, "zstd", "no zstd frame");
    // The whole file packed and unpacked: bits 0 and 2, then the same bytes.
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.bssrdf"), dir.path().join("b.bssrdf"));
    std::fs::write(&a, &two_lobes().bytes).unwrap();
    pack(&a, &b, 3).unwrap();
    let packed = Library::read(&b, Verify::Full).unwrap();
    assert_eq!(packed.required_features(), HARMONICS | ZSTD);
    unpack(&b, &b).unwrap();
    assert!(std::fs::read(&b).unwrap() == two_lobes().bytes);
}

/// `table` with the harmonics of each node's one lobe, rμ₃ = E_β c³ and rμ₄ = E_β c⁴.
fn with_harmonics_of_one_lobe(mut table: TableData) -> TableData {
    let harmonics = table
        .gwc
        .chunks_exact(3)
        .flat_map(|n| [n[1] * n[2].powi(3), n[1] * n[2].powi(4)])
        .collect();
    table.harmonics = Some(harmonics);
    table
}

/// §4, bit 2, the writer's side: "A writer MUST set it if any table has one, and MUST NOT
/// otherwise"; and the builder refuses what the reader would reject, with the same codes.
#[test]
fn the_writer_sets_bit_2_exactly_when_a_table_has_harmonics() {
    let features = |b: &LibraryBuilder, c: Compression| {
        Library::from_bytes(&b.to_bytes(c).unwrap(), Verify::Full)
            .unwrap()
            .required_features()
    };
    assert_eq!(features(&tiny_builder(), Compression::None), 0);
    let mut b = LibraryBuilder::new();
    b.add_table(synthetic_table(1.2, 2, 3, 4, true)).unwrap();
    assert_eq!(features(&b, Compression::None), 0);
    b.add_table(with_harmonics_of_one_lobe(synthetic_table(
        1.3, 2, 3, 4, false,
    )))
    .unwrap();
    // (and bit 4: this crate's two-lobe tables rebuild with merged roots)
    assert_eq!(features(&b, Compression::None), HARMONICS | MERGED_ROOTS);
    assert_eq!(
        features(&b, Compression::Zstd { level: 3 }),
        HARMONICS | MERGED_ROOTS | ZSTD
    );
    // The two-lobe file is canonical: the writer rewrites it byte for byte.
    let library = Library::from_bytes(&two_lobes().bytes, Verify::Full).unwrap();
    let rebuilt = LibraryBuilder::from_library(&library).unwrap();
    assert!(rebuilt.to_bytes(Compression::None).unwrap() == two_lobes().bytes);

    let table = |edit: fn(&mut Vec<f32>)| {
        let mut t = with_harmonics_of_one_lobe(synthetic_table(1.3, 2, 3, 4, false));
        edit(t.harmonics.as_mut().unwrap());
        LibraryBuilder::new().add_table(t).unwrap_err()
    };
    let err = table(|h| h.truncate(2 * 3 * 4));
    assert_eq!(err.code(), "section-dims", "{err}");
    assert!(err.to_string().contains("gwc-harmonics"), "{err}");
    let err = table(|h| h[5] = f32::NAN);
    assert_eq!(err.code(), "non-finite", "{err}");
    assert!(err.to_string().contains("gwc-harmonics[5]"), "{err}");
}

/// §4, bit 2: a reader "MUST read a file that sets it without one": every table one lobe.
#[test]
fn bit_2_without_a_harmonics_section_reads_every_table_as_one_lobe() {
    let one_lobe = Raw::new(tiny_builder().to_bytes(Compression::None).unwrap()).sections();
    assert!(one_lobe.iter().all(|s| s.kind != kind::HARMONICS));
    let library = assert_accepted("bit 2, no harmonics", &build(2, HARMONICS, &one_lobe));
    assert_eq!(library.required_features(), HARMONICS);
    assert!(library.table(0).unwrap().harmonics().is_none());
}

/// §4, bit 4: a reader "MUST read a file that sets it without" a harmonics section: nothing is
/// read differently.
#[test]
fn bit_4_without_a_harmonics_section_is_read() {
    let one_lobe = Raw::new(tiny_builder().to_bytes(Compression::None).unwrap()).sections();
    let library = assert_accepted(
        "bit 4, no harmonics",
        &build(VERSION_MINOR, MERGED_ROOTS, &one_lobe),
    );
    assert_eq!(library.required_features(), MERGED_ROOTS);
    assert!(library.table(0).unwrap().harmonics().is_none());
}

/// §4: "a feature bit means the same in a file of any minor": a 1.0 or 1.1 file that sets bit 2
/// is read as a 1.2 file would be, with its harmonics; without the bit its harmonics section
/// is still refused.
#[test]
fn bit_2_means_the_same_in_a_file_of_an_older_minor() {
    for minor in [0, 1] {
        let case = format!("minor {minor} with bit 2");
        let library = assert_accepted(&case, &build(minor, HARMONICS, &tiny_two_lobes_sections()));
        assert_eq!(library.version(), (1, minor));
        let harmonics = library.table(0).unwrap().harmonics().unwrap();
        assert_eq!(harmonics.len(), VALUES, "{case}");
        let undeclared = build(minor, 0, &tiny_two_lobes_sections());
        let case = format!("minor {minor} without bit 2");
        assert_rejected(&case, &undeclared, "harmonics-not-declared", "section 9");
    }
}

/// §4, bit 3, the writer's side: set exactly when a node is a signed pair. The one lobe's own
/// harmonics, rounded to f32, are not one, whatever sign Prony's ill-determined roots take.
#[test]
fn the_writer_sets_bit_3_exactly_when_a_node_is_a_signed_pair() {
    let features = |t: TableData| {
        let mut b = LibraryBuilder::new();
        b.add_table(t).unwrap();
        Library::from_bytes(&b.to_bytes(Compression::None).unwrap(), Verify::Full)
            .unwrap()
            .required_features()
    };
    let one_lobe = with_harmonics_of_one_lobe(synthetic_table(1.3, 2, 3, 4, false));
    assert_eq!(features(one_lobe.clone()), HARMONICS | MERGED_ROOTS);
    // Node 5 made the vector `signed-lobes`' pair: β = (1, −0.5) at c = (0.8, 0.5), E = 1
    let mut signed = one_lobe;
    signed.gwc[15..18].copy_from_slice(&[1.0, 0.587_379, 0.936_364]);
    signed.harmonics.as_mut().unwrap()[10..12].copy_from_slice(&[0.4495, 0.378_35]);
    assert_eq!(features(signed), HARMONICS | SIGNED_LOBES | MERGED_ROOTS);
}

/// `node_is_signed` over random one-lobe nodes in f32 (none is signed) and the same nodes with
/// a broader negative lobe of 5 % of the sharp one's mass added: each is, where its harmonics
/// depart from its one lobe's by more than twice `SIGNED_DEPARTURE` (most do); by either rule of
/// the rebuild (merged roots never count one lobe's rounding as a signed pair).
#[test]
fn node_is_signed_tells_one_lobe_from_a_signed_pair() {
    use bssrdf_zoo::gwc::Rebuild;
    use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
    use bssrdf_zoo::table::SIGNED_DEPARTURE;
    let node_is_signed = |cell: [f32; 5]| {
        let [roots, merged] = [Rebuild::Roots, Rebuild::MergedRoots]
            .map(|r| bssrdf_zoo::table::node_is_signed(cell, r));
        assert_eq!(roots, merged, "{cell:?}");
        roots
    };
    let mut rng = SplitMix64::seed_from_u64(17);
    let mut uniform = move || rng.next_f64();
    let (cases, mut signed) = (10_000, 0);
    for _ in 0..cases {
        let (e, c) = (0.01 + uniform(), 0.05 + 0.94 * uniform());
        let e_beta = e * uniform() * (1.0 + c) / (2.0 * c);
        let cell = [e, e_beta, c, e_beta * c.powi(3), e_beta * c.powi(4)].map(|v| v as f32);
        assert!(!node_is_signed(cell), "one lobe {cell:?}");
        // β₂ = −0.05 β at c₂ = c/2: harmonics Σ βᵢcᵢⁿ, stored as one lobe of μ₁, μ₂ and μ₃, μ₄
        let (b1, b2, c2) = (e_beta, -0.05 * e_beta, 0.5 * c);
        let mu = |n: i32| b1 * c.powi(n) + b2 * c2.powi(n);
        let (m1, m2) = (mu(1), mu(2));
        let (e_beta, c) = (m1 * m1 / m2, m2 / m1);
        let departure = (mu(3) - e_beta * c.powi(3))
            .abs()
            .max((mu(4) - e_beta * c.powi(4)).abs());
        if departure > 2.0 * SIGNED_DEPARTURE * e {
            let cell = [e, e_beta, c, mu(3), mu(4)].map(|v| v as f32);
            assert!(node_is_signed(cell), "signed pair {cell:?}");
            signed += 1;
        }
    }
    assert!(
        signed > cases / 2,
        "{signed} of {cases} signed pairs depart enough"
    );
}

/// The vector `merged-roots`' sections: its node (0, 0, 1) is the limit of a signed pair whose
/// roots merge at c = 0.7, r·μₙ = cⁿ + 0.1·n·cⁿ⁻¹, E = 1.2, with complex Prony roots.
fn merged_roots_sections() -> Vec<Sec> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/valid/merged-roots.bssrdf");
    Raw::new(std::fs::read(path).unwrap()).sections()
}

/// The node (E, E_β, c, r·μ₃, r·μ₄) of table 0 at index `node`, as `table::node_is_signed` takes it.
fn cell(library: &Library, node: usize) -> [f32; 5] {
    let table = library.table(0).unwrap();
    let (p, h) = (table.gwc_params(), table.harmonics().unwrap());
    [
        p[3 * node],
        p[3 * node + 1],
        p[3 * node + 2],
        h[2 * node],
        h[2 * node + 1],
    ]
}

/// §4, bit 4 (`merged-roots`): a file that sets it is read with step 4b of §10, a file that
/// does not (of any minor) without. The vector's node is a merged pair only with the bit: read
/// so, it is the limit of its signed pair, whose profile is computed here by definition; read
/// without, the one lobe of its first two harmonics. Its signed pair needs bit 3 exactly when
/// the bit is set.
#[test]
fn bit_4_says_how_a_file_rebuilds_merged_roots() {
    use bssrdf_zoo::gwc::{Rebuild, TwoLobe};
    use bssrdf_zoo::table::{node_is_signed, node_shares, node_sharpness};
    use std::f64::consts::{PI, TAU};
    let secs = merged_roots_sections();
    let read = |library: &Library| {
        let rebuild = library.table(0).unwrap().rebuild();
        let cell = cell(library, 1);
        let e = f64::from(cell[0]);
        let m = node_shares(cell).map(|s| f64::from(s) * e);
        let cap = f64::from(node_sharpness(cell, rebuild));
        (
            TwoLobe::from_moments_capped(e, m, cap, rebuild),
            node_is_signed(cell, rebuild),
        )
    };
    // With bit 4: a lobe of mass 1 at c = 0.7 plus 0.1 times its derivative in c, over the
    // floor of the rest of E = 1.2
    let merged = assert_accepted(
        "bit 4",
        &build(
            VERSION_MINOR,
            HARMONICS | SIGNED_LOBES | MERGED_ROOTS,
            &secs,
        ),
    );
    assert_eq!(merged.table(0).unwrap().rebuild(), Rebuild::MergedRoots);
    let (profile, signed) = read(&merged);
    assert!(signed && profile.is_signed(), "{profile:?}");
    let c = 0.7f64;
    for k in 0..=16 {
        let phi = PI * f64::from(k) / 16.0;
        let (x, d) = (phi.cos(), 1.0 + c * c - 2.0 * c * phi.cos());
        let lobe = (1.0 - c * c) / (TAU * d);
        let derivative = (2.0 * x * (1.0 + c * c) - 4.0 * c) / (TAU * d * d);
        let expected = 0.2 / TAU + lobe + 0.1 * derivative;
        let got = profile.eval(phi);
        assert!(
            (got - expected).abs() <= 1e-5 * expected,
            "phi {phi}: {got} against {expected}"
        );
    }
    // Without it, at the minor this crate writes and at 1.3: one lobe, not signed, so bit 3 is
    // not needed either
    for minor in [VERSION_MINOR, 3] {
        let library = assert_accepted("no bit 4", &build(minor, HARMONICS, &secs));
        assert_eq!(library.table(0).unwrap().rebuild(), Rebuild::Roots);
        let (profile, signed) = read(&library);
        assert!(!signed && profile.beta()[1] == 0.0, "{profile:?}");
    }
    // With bit 4 and without bit 3 the signed pair is undeclared
    let undeclared = build(VERSION_MINOR, HARMONICS | MERGED_ROOTS, &secs);
    let err = Library::from_bytes(&undeclared.bytes, Verify::Full).unwrap_err();
    assert_eq!(err.code(), "signed-lobes-not-declared", "{err}");
    assert!(err.to_string().contains("node 1 "), "{err}");
}

/// §4, bit 4, the writer's side: set on a file whose two-lobe tables rebuild with merged roots
/// (every table this crate bakes), not on one without two-lobe tables; a table read from a
/// file without the bit keeps its rule through a rewrite (`pack`, `unpack`), and two-lobe
/// tables of both rules cannot share a file.
#[test]
fn the_writer_sets_bit_4_for_tables_rebuilt_with_merged_roots() {
    use bssrdf_zoo::gwc::Rebuild;
    let features = |tables: Vec<TableData>| {
        let mut b = LibraryBuilder::new();
        for t in tables {
            b.add_table(t)?;
        }
        let bytes = b.to_bytes(Compression::None)?;
        Ok::<_, bssrdf_zoo::format::FormatError>(
            Library::from_bytes(&bytes, Verify::Full)?.required_features(),
        )
    };
    let one_lobe = synthetic_table(1.3, 2, 3, 4, false);
    let two_lobes = with_harmonics_of_one_lobe(one_lobe.clone());
    assert_eq!(features(vec![one_lobe.clone()]).unwrap(), 0);
    assert_eq!(
        features(vec![two_lobes.clone()]).unwrap(),
        HARMONICS | MERGED_ROOTS
    );
    let roots = TableData {
        rebuild: Rebuild::Roots,
        ..two_lobes.clone()
    };
    assert_eq!(features(vec![roots.clone(), one_lobe]).unwrap(), HARMONICS);
    let err = features(vec![two_lobes, roots]).unwrap_err();
    assert!(err.to_string().contains("one rule"), "{err}");
    // A 1.3 file's rule survives a rewrite
    let dir = tempfile::tempdir().unwrap();
    let (old, packed) = (
        dir.path().join("old.bssrdf"),
        dir.path().join("packed.bssrdf"),
    );
    std::fs::write(&old, &build(3, HARMONICS, &merged_roots_sections()).bytes).unwrap();
    pack(&old, &packed, 3).unwrap();
    unpack(&packed, &packed).unwrap();
    let library = Library::read(&packed, Verify::Full).unwrap();
    assert_eq!(library.required_features(), HARMONICS);
    assert_eq!(library.table(0).unwrap().rebuild(), Rebuild::Roots);
}

/// §4, bit 4, through the lookups renderers use: a table of a file that sets the bit and of one
/// that does not (the vector `merged-roots` and the same sections without the bit) reads the same
/// through `FileTable` (shares blended row by row) and `embed::Library` (shares computed at
/// open, by the file's rule), bit for bit; and the two files read differently at the merged
/// node and next to it.
#[test]
fn lookups_through_every_path_take_the_files_rule() {
    use bssrdf_zoo::format::AxisKind;
    use bssrdf_zoo::gwc::Rebuild;
    use bssrdf_zoo::table::FileTable;
    let secs = merged_roots_sections();
    let files = [
        (
            HARMONICS | SIGNED_LOBES | MERGED_ROOTS,
            Rebuild::MergedRoots,
        ),
        (HARMONICS, Rebuild::Roots),
    ];
    let mut read = Vec::new();
    for (bits, rule) in files {
        let bytes = build(VERSION_MINOR, bits, &secs).bytes;
        let file = Library::from_bytes(&bytes, Verify::Full).unwrap();
        let table = file.table(0).unwrap();
        let (rho, theta, r) = (
            table.axis(AxisKind::Rho),
            table.axis(AxisKind::Theta),
            table.axis(AxisKind::R),
        );
        let points: Vec<[f64; 4]> = [0.0, 0.3, 1.0, 2.0, 3.0]
            .iter()
            .flat_map(|&phi| {
                [
                    [rho[0], theta[0], r[1]],
                    [rho[0], theta[0], 0.5 * (r[1] + r[2])],
                ]
                .map(|[a, b, c]| [f64::from(a), f64::from(b), f64::from(c), phi])
            })
            .collect();
        let file_table = FileTable::new(table).unwrap();
        let by_file = file_table.view().unwrap();
        assert_eq!(by_file.rebuild(), rule);
        let embedded = bssrdf_zoo::embed::Library::from_format(
            Library::from_bytes(&bytes, Verify::Full).unwrap(),
        )
        .unwrap();
        let by_embed = embedded.view(0).unwrap();
        assert_eq!(by_embed.rebuild(), rule);
        let values: Vec<f64> = points
            .iter()
            .map(|&[x, t, k, phi]| {
                let (a, b) = (by_file.eval(x, t, k, phi), by_embed.eval(x, t, k, phi));
                assert_eq!(
                    a.map(f64::to_bits),
                    b.map(f64::to_bits),
                    "{rule:?} at {x} {t} {k} {phi}"
                );
                a.unwrap()
            })
            .collect();
        read.push(values);
    }
    // At the node, φ = 0: the merged pair against the one lobe
    assert!(
        (read[0][0] / read[1][0] - 1.0).abs() > 1e-3,
        "{} against {}",
        read[0][0],
        read[1][0]
    );
}
