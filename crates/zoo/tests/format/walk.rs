//! Every rule of format-spec.md for a walk-angular table (model 3, format 1.5): the record's
//! `component` at byte 28 and `g` at byte 32, its reserved bytes from byte 44 (byte 40 holds
//! the ridge code of format 1.6, tested in `ridge.rs`), required feature
//! bit 5 (`walk-tables`) and its required `gwc-harmonics` section, each broken by a file that
//! must be rejected with the error code §14 names, next to the accept paths. The conformance
//! vectors of the new codes are made here ([`walk_vectors`]); errors that other vectors
//! already cover (`reserved-not-zero`, `missing-section`) are tested here only.
//!
//! The files are the tiny library of the testkit with its one 2×2×4 table made walk-angular
//! (g = 0.75, total), changed in one field and with the CRCs recomputed.

use bssrdf_testkit::files::{
    as_walk_table, kind, synthetic_table, tiny_builder, tiny_builder_of, Raw,
};
use bssrdf_zoo::format::spec::required_features::{HARMONICS, MERGED_ROOTS, WALK_TABLES, ZSTD};
use bssrdf_zoo::format::spec::VERSION_MINOR;
use bssrdf_zoo::format::{
    pack, unpack, Compression, Library, LibraryBuilder, ModelKind, TableData, Verify,
    WalkComponent, WalkSource,
};
use bssrdf_zoo::table::FileTable;

use crate::{assert_accepted, assert_rejected, written_features};

/// The walk of the tiny walk-angular table.
const WALK: WalkSource = WalkSource {
    g: 0.75,
    component: WalkComponent::Total,
};

/// The tiny library's table as a walk-angular table of [`WALK`].
fn walk_table() -> TableData {
    as_walk_table(synthetic_table(1.3, 2, 2, 4, true), WALK.g, WALK.component)
}

/// The tiny library with its table walk-angular, as the writer makes it (the conformance
/// vector `walk-table`): required feature bits 2, 4 and 5.
pub fn tiny_walk() -> Raw {
    Raw::new(
        tiny_builder_of(walk_table())
            .to_bytes(Compression::None)
            .unwrap(),
    )
}

/// File offset of the record of table 0.
pub fn record(raw: &Raw) -> usize {
    raw.data(kind::TABLES, kind::FILE)
}

/// `raw` changed by `edit`, with every CRC recomputed.
pub fn edited(mut raw: Raw, edit: impl Fn(&mut Raw)) -> Raw {
    edit(&mut raw);
    raw.fix_crcs();
    raw
}

/// The invalid conformance vectors of the walk-angular record, one per error code it adds.
pub fn walk_vectors() -> Vec<(&'static str, Raw)> {
    vec![
        (
            "walk-tables-not-declared",
            edited(tiny_walk(), |r| r.set_u64(32, r.u64(32) & !WALK_TABLES)),
        ),
        (
            "unknown-component",
            edited(tiny_walk(), |r| {
                let t = record(r);
                r.set_u32(t + 28, 2);
            }),
        ),
        (
            "table-g",
            edited(tiny_walk(), |r| {
                let t = record(r);
                r.set_f64(t + 32, 1.0);
            }),
        ),
    ]
}

/// `library`, read from `raw`, rewritten by the writer (byte for byte the same), then packed
/// (zstd) and unpacked again (byte for byte the same): the packed file, read back.
pub(crate) fn rewritten_and_packed(library: &Library, raw: &Raw) -> Library {
    let rebuilt = LibraryBuilder::from_library(library).unwrap();
    assert!(rebuilt.to_bytes(Compression::None).unwrap() == raw.bytes);
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.bssrdf"), dir.path().join("b.bssrdf"));
    std::fs::write(&a, &raw.bytes).unwrap();
    pack(&a, &b, 3).unwrap();
    let packed = Library::read(&b, Verify::Full).unwrap();
    let unpacked = dir.path().join("c.bssrdf");
    unpack(&b, &unpacked).unwrap();
    assert!(std::fs::read(&unpacked).unwrap() == raw.bytes);
    packed
}

/// A walk-angular table goes through the writer and back unchanged: model, g, component and
/// every array, in the format's view, in an owned table and through pack and unpack.
#[test]
fn a_walk_table_round_trips() {
    let raw = tiny_walk();
    let library = assert_accepted("walk table", &raw);
    assert_eq!(library.version(), (1, VERSION_MINOR));
    assert_eq!(
        library.required_features(),
        HARMONICS | MERGED_ROOTS | WALK_TABLES
    );
    let table = library.table(0).unwrap();
    assert_eq!(table.model(), ModelKind::WalkAngular);
    assert_eq!(table.walk(), Some(WALK));
    assert_eq!(table.header().walk, Some(WALK));
    // Every array, and the rest of the record, as written: the owned table gives back the
    // table data bit for bit.
    let owned = FileTable::new(table).unwrap().to_owned_table().unwrap();
    assert_eq!(owned.walk(), Some(WALK));
    assert_eq!(owned.to_table_data(), walk_table());
    // The writer rewrites the file byte for byte; pack and unpack keep the walk.
    let packed = rewritten_and_packed(&library, &raw);
    assert_eq!(packed.table(0).unwrap().walk(), Some(WALK));
    assert_eq!(packed.required_features() & WALK_TABLES, WALK_TABLES);
    assert_eq!(packed.required_features() & ZSTD, ZSTD);
    // The other component, and a negative g, in a second table of the same file.
    let multiple = WalkSource {
        g: -0.3,
        component: WalkComponent::Multiple,
    };
    let mut builder = tiny_builder_of(walk_table());
    let second = as_walk_table(
        synthetic_table(1.5, 3, 2, 5, false),
        -0.3,
        multiple.component,
    );
    builder.add_table(second.clone()).unwrap();
    let library =
        Library::from_bytes(&builder.to_bytes(Compression::None).unwrap(), Verify::Full).unwrap();
    assert_eq!(library.table(1).unwrap().walk(), Some(multiple));
    let owned = FileTable::new(library.table(1).unwrap())
        .unwrap()
        .to_owned_table()
        .unwrap();
    assert_eq!(owned.to_table_data(), second);
}

/// §9.1: `component` is the u32 at byte 28 of the record, `g` the f64 at byte 32, the ridge
/// flag (0 here) at byte 40 and zeros from byte 44; a pbd-angular record without the ridge is
/// zero from byte 28.
#[test]
fn the_record_holds_component_at_28_and_g_at_32() {
    let raw = tiny_walk();
    let t = record(&raw);
    assert_eq!(raw.u32(t), 3);
    assert_eq!(raw.u32(t + 28), 1);
    assert_eq!(raw.bytes[t + 32..t + 40], 0.75f64.to_le_bytes());
    assert!(raw.bytes[t + 40..t + 64].iter().all(|&b| b == 0));
    let pbd = Raw::new(tiny_builder().to_bytes(Compression::None).unwrap());
    let t = record(&pbd);
    assert_eq!(pbd.u32(t), 1);
    assert!(pbd.bytes[t + 28..t + 64].iter().all(|&b| b == 0));
}

/// §4, bit 5, the writer's side: set exactly when some table is walk-angular.
#[test]
fn the_writer_sets_bit_5_exactly_when_a_table_is_walk_angular() {
    assert_eq!(written_features(&tiny_builder()) & WALK_TABLES, 0);
    // A two-lobe pbd-angular table does not set it.
    let mut two_lobes = walk_table();
    two_lobes.model = ModelKind::PbdAngular;
    two_lobes.walk = None;
    let mut b = tiny_builder_of(two_lobes);
    assert_eq!(written_features(&b), HARMONICS | MERGED_ROOTS);
    // One walk-angular table among others does.
    b.add_table(walk_table()).unwrap();
    assert_eq!(written_features(&b), HARMONICS | MERGED_ROOTS | WALK_TABLES);
}

/// §4, bit 5: a reader "MUST reject a walk-angular table when the bit is not set", in a file
/// of any minor, and reads a file of any minor that sets it.
#[test]
fn a_walk_table_needs_required_feature_bit_5() {
    let secs = tiny_walk().sections();
    for minor in [0, 4, VERSION_MINOR] {
        let case = format!("minor {minor} without bit 5");
        let undeclared = Raw::build(minor, HARMONICS | MERGED_ROOTS, 0, 256, &secs);
        let needle = "table 0: walk-angular (model 3) in a file without required feature bit 5";
        assert_rejected(&case, &undeclared, "walk-tables-not-declared", needle);
        let declared = Raw::build(minor, HARMONICS | WALK_TABLES, 0, 256, &secs);
        let library = assert_accepted(&format!("minor {minor} with bit 5"), &declared);
        assert_eq!(library.table(0).unwrap().walk(), Some(WALK));
    }
}

/// §4, bit 5: a reader reads a file that sets it without a walk-angular table; nothing is read
/// differently.
#[test]
fn bit_5_without_a_walk_table_is_read() {
    let pbd = Raw::new(tiny_builder().to_bytes(Compression::None).unwrap());
    let raw = Raw::build(VERSION_MINOR, WALK_TABLES, 0, 256, &pbd.sections());
    let library = assert_accepted("bit 5, no walk table", &raw);
    assert_eq!(library.required_features(), WALK_TABLES);
    let table = library.table(0).unwrap();
    assert_eq!((table.model(), table.walk()), (ModelKind::PbdAngular, None));
    let plain = Library::from_bytes(&pbd.bytes, Verify::Full).unwrap();
    assert_eq!(table.gwc_params(), plain.table(0).unwrap().gwc_params());
}

/// §9.1: component 0 (multiple) or 1 (total); other values are rejected.
#[test]
fn an_unknown_component_is_rejected() {
    for code in [2, 7, u32::MAX] {
        let raw = edited(tiny_walk(), |r| {
            let t = record(r);
            r.set_u32(t + 28, code);
        });
        let needle = format!("table 0: unknown walk component code {code}");
        assert_rejected(
            &format!("component {code}"),
            &raw,
            "unknown-component",
            &needle,
        );
    }
    let multiple = edited(tiny_walk(), |r| {
        let t = record(r);
        r.set_u32(t + 28, 0);
    });
    let library = assert_accepted("component 0", &multiple);
    let walk = library.table(0).unwrap().walk().unwrap();
    assert_eq!(walk.component, WalkComponent::Multiple);
}

/// §9.1: g is finite and in (−1, 1), on the writer's side too.
#[test]
fn g_is_finite_and_inside_minus_one_to_one() {
    let with_g = |g: f64| {
        edited(tiny_walk(), |r| {
            let t = record(r);
            r.set_f64(t + 32, g);
        })
    };
    for g in [
        1.0,
        -1.0,
        1.5,
        -3.0,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ] {
        let needle = "table 0: the walk's g = ";
        assert_rejected(&format!("g = {g}"), &with_g(g), "table-g", needle);
        let mut table = walk_table();
        table.walk = Some(WalkSource { g, ..WALK });
        let err = LibraryBuilder::new().add_table(table).unwrap_err();
        assert_eq!(err.code(), "table-g", "g = {g}: {err}");
    }
    for g in [0.0, -0.999, 0.999, f64::from(f32::MIN_POSITIVE)] {
        let library = assert_accepted(&format!("g = {g}"), &with_g(g));
        assert_eq!(
            library.table(0).unwrap().walk().unwrap().g.to_bits(),
            g.to_bits()
        );
    }
}

/// §9.1: a walk-angular table has a `gwc-harmonics` section; without it, the error of any
/// missing section (§14 step 10), in reading and in writing.
#[test]
fn a_walk_table_without_gwc_harmonics_is_missing_a_section() {
    let raw = edited(tiny_walk(), |r| {
        // The harmonics entry becomes an optional extension section
        let e = r.entry(r.find(kind::HARMONICS, 0));
        r.set_u32(e, 0x7000);
        r.set_u16(e + 12, 0);
    });
    let needle = "missing required section gwc-harmonics for table 0";
    assert_rejected("no harmonics", &raw, "missing-section", needle);
    let mut table = walk_table();
    table.harmonics = None;
    let err = LibraryBuilder::new().add_table(table).unwrap_err();
    assert_eq!(err.code(), "missing-section", "{err}");
    assert!(err.to_string().contains(needle), "{err}");
}

/// `raw` with byte `at` of table record 0 set to `value` and the header's minor to `minor`.
pub fn with_record_byte(mut raw: Raw, at: usize, value: u8, minor: u16) -> Raw {
    let t = record(&raw);
    raw.bytes[t + at] = value;
    raw.set_u16(14, minor);
    raw.fix_crcs();
    raw
}

/// §9.1 and §4: in strict reading the reserved bytes of a walk-angular record, 44 to 63, are
/// zero; a file of a newer minor may use them, and is read with its walk.
#[test]
fn a_walk_record_is_reserved_from_byte_44() {
    for at in [44, 51, 63] {
        let set = |minor: u16| with_record_byte(tiny_walk(), at, 0x5A, minor);
        let needle = format!("reserved byte {at} of the table record 0 is 0x5a");
        assert_rejected(
            &format!("byte {at}"),
            &set(VERSION_MINOR),
            "reserved-not-zero",
            &needle,
        );
        let newer = assert_accepted(&format!("byte {at}, newer minor"), &set(VERSION_MINOR + 1));
        assert_eq!(newer.table(0).unwrap().walk(), Some(WALK));
    }
}

/// §9.1: in a pbd-angular record bytes 32 to 63 stay reserved (byte 28 is its ridge code),
/// those of a walk's fields too.
#[test]
fn a_pbd_record_is_reserved_from_byte_32() {
    for at in [32, 39, 40, 44, 63] {
        let set = |minor: u16| {
            let pbd = Raw::new(tiny_builder().to_bytes(Compression::None).unwrap());
            with_record_byte(pbd, at, 0x01, minor)
        };
        let needle = format!("reserved byte {at} of the table record 0 is 0x01");
        assert_rejected(
            &format!("byte {at}"),
            &set(VERSION_MINOR),
            "reserved-not-zero",
            &needle,
        );
        let newer = assert_accepted(&format!("byte {at}, newer minor"), &set(VERSION_MINOR + 1));
        assert_eq!(newer.table(0).unwrap().walk(), None);
    }
}

/// §14 step 10: the record's checks in order: reserved bytes, model, bit 5, component,
/// fresnel, g, η.
#[test]
fn the_record_is_checked_in_the_order_of_section_14() {
    let broken = |edits: &[(usize, u64)]| {
        let mut raw = tiny_walk();
        let t = record(&raw);
        for &(at, value) in edits {
            match at {
                0 => raw.set_u64(32, raw.u64(32) & !WALK_TABLES),
                28 | 4 => raw.set_u32(t + at, value as u32),
                _ => raw.set_f64(t + at, f64::from_bits(value)),
            }
        }
        raw.fix_crcs();
        Library::from_bytes(&raw.bytes, Verify::Full)
            .unwrap_err()
            .code()
    };
    let reserved = (48, 1.0f64.to_bits());
    let no_bit = (0, 0);
    let component = (28, 9);
    let fresnel = (4, 9);
    let g = (32, 2.0f64.to_bits());
    let eta = (8, (-1.0f64).to_bits());
    assert_eq!(broken(&[reserved, no_bit]), "reserved-not-zero");
    assert_eq!(broken(&[no_bit, component]), "walk-tables-not-declared");
    assert_eq!(broken(&[component, fresnel]), "unknown-component");
    assert_eq!(broken(&[fresnel, g]), "unknown-fresnel");
    assert_eq!(broken(&[g, eta]), "table-g");
}

/// The builder takes a walk exactly with the walk-angular model.
#[test]
fn the_walk_goes_with_the_model() {
    let mut without = walk_table();
    without.walk = None;
    let mut pbd_with = synthetic_table(1.3, 2, 2, 4, true);
    pbd_with.walk = Some(WALK);
    for (case, table) in [("walk-angular without", without), ("pbd with", pbd_with)] {
        let err = LibraryBuilder::new().add_table(table).unwrap_err();
        assert_eq!(err.code(), "invalid-input", "{case}: {err}");
        assert!(err.to_string().contains("table 0"), "{case}: {err}");
    }
}
