//! Every rule of format-spec.md for a table record's `ridge` (format 1.6): the u32 at byte 28
//! of a pbd-angular record and at byte 40 of a walk-angular one, 0, 1 (the flux ridge) or 2
//! (the ridge with its fluence part), and required feature bit 6 (`ridge`) for a table that
//! sets it, each broken by a file that must be rejected with the error code §14 names, next to
//! the accept paths. The conformance vectors of the new codes, and the valid `ridge` and
//! `ridge-fluence` vectors, are made here ([`ridge_vectors`], [`tiny_ridge`]).
//!
//! The files are the tiny library of the testkit with its one 2×2×4 table at η = 1 (where the
//! ridge has weight, below η ≈ 1.048) marked as holding the profile less a ridge of either
//! kind, changed in one field and with the CRCs recomputed.

use bssrdf_testkit::files::{as_walk_table, synthetic_table, tiny_builder, tiny_builder_of, Raw};
use bssrdf_zoo::format::spec::required_features::{
    HARMONICS, MERGED_ROOTS, RIDGE, WALK_TABLES, ZSTD,
};
use bssrdf_zoo::format::spec::VERSION_MINOR;
use bssrdf_zoo::format::{Compression, Library, ModelKind, TableData, Verify, WalkComponent};
use bssrdf_zoo::table::{FileTable, RidgeKind};

use super::walk::{edited, record, rewritten_and_packed, with_record_byte};
use crate::{assert_accepted, assert_rejected, written_features};

/// The kinds of ridge a record can set: `ridge` = 1 and 2.
const KINDS: [RidgeKind; 2] = [RidgeKind::Flux, RidgeKind::FluxAndFluence];

/// The tiny library's table at η = 1, marked as holding the profile less a ridge of `kind`.
fn ridge_table(kind: RidgeKind) -> TableData {
    TableData {
        ridge: kind,
        ..synthetic_table(1.0, 2, 2, 4, true)
    }
}

/// [`ridge_table`] as a walk-angular table (g = 0.75, total): its `ridge` at byte 40.
fn walk_ridge_table(kind: RidgeKind) -> TableData {
    as_walk_table(ridge_table(kind), 0.75, WalkComponent::Total)
}

/// The tiny library with [`ridge_table`] of `kind`, as the writer makes it (the conformance
/// vectors `ridge`, of [`RidgeKind::Flux`], and `ridge-fluence`, of
/// [`RidgeKind::FluxAndFluence`]): required feature bit 6 alone.
pub fn tiny_ridge(kind: RidgeKind) -> Raw {
    Raw::new(
        tiny_builder_of(ridge_table(kind))
            .to_bytes(Compression::None)
            .unwrap(),
    )
}

/// The tiny library with [`walk_ridge_table`] of `kind`: required feature bits 2, 4, 5 and 6.
fn tiny_walk_ridge(kind: RidgeKind) -> Raw {
    Raw::new(
        tiny_builder_of(walk_ridge_table(kind))
            .to_bytes(Compression::None)
            .unwrap(),
    )
}

/// The invalid conformance vectors of the ridge field, one per error code it adds: the
/// `ridge` vector without bit 6, and with `ridge` = 3, the least code no reader knows.
pub fn ridge_vectors() -> Vec<(&'static str, Raw)> {
    vec![
        (
            "ridge-not-declared",
            edited(tiny_ridge(RidgeKind::Flux), |r| {
                r.set_u64(32, r.u64(32) & !RIDGE)
            }),
        ),
        (
            "unknown-ridge",
            edited(tiny_ridge(RidgeKind::Flux), |r| {
                let t = record(r);
                r.set_u32(t + 28, 3);
            }),
        ),
    ]
}

/// A table with a ridge of either kind goes through the writer and back with its kind: in the
/// format's view, in a lookup view and an owned table, through a rewrite and through pack and
/// unpack; a walk-angular one too.
#[test]
fn a_ridge_table_round_trips() {
    for kind in KINDS {
        let raw = tiny_ridge(kind);
        let library = assert_accepted(&format!("{kind:?} table"), &raw);
        assert_eq!(library.version(), (1, VERSION_MINOR));
        assert_eq!(library.required_features(), RIDGE);
        let table = library.table(0).unwrap();
        assert_eq!(table.model(), ModelKind::PbdAngular);
        assert_eq!((table.ridge(), table.header().ridge), (kind, kind));
        let file_table = FileTable::new(table).unwrap();
        assert_eq!(file_table.view().unwrap().ridge(), kind);
        let owned = file_table.to_owned_table().unwrap();
        assert_eq!((owned.ridge(), owned.view().ridge()), (kind, kind));
        // The writer takes the kind from the table: the owned table gives back the data bit
        // for bit
        assert_eq!(owned.to_table_data(), ridge_table(kind));
        for other in [RidgeKind::None, RidgeKind::Flux, RidgeKind::FluxAndFluence] {
            let data = owned.clone().with_ridge(other).to_table_data();
            assert_eq!(data.ridge, other);
        }
        // The writer rewrites the file byte for byte; pack and unpack keep the kind.
        let packed = rewritten_and_packed(&library, &raw);
        assert_eq!(packed.table(0).unwrap().ridge(), kind);
        assert_eq!(packed.required_features(), RIDGE | ZSTD);
        // A walk-angular table with the ridge, beside a pbd-angular one without
        let mut builder = tiny_builder_of(walk_ridge_table(kind));
        builder
            .add_table(synthetic_table(1.5, 3, 2, 5, false))
            .unwrap();
        let library =
            Library::from_bytes(&builder.to_bytes(Compression::None).unwrap(), Verify::Full)
                .unwrap();
        assert_eq!(
            library.required_features(),
            HARMONICS | MERGED_ROOTS | WALK_TABLES | RIDGE
        );
        let (walk, pbd) = (library.table(0).unwrap(), library.table(1).unwrap());
        assert_eq!((walk.ridge(), pbd.ridge()), (kind, RidgeKind::None));
        assert!(walk.walk().is_some());
        let owned = FileTable::new(walk).unwrap().to_owned_table().unwrap();
        assert_eq!(owned.to_table_data(), walk_ridge_table(kind));
    }
}

/// §9.1: `ridge` is the u32 at byte 28 of a pbd-angular record, zeros from byte 32, and the
/// u32 at byte 40 of a walk-angular one, zeros from byte 44; 1 for the flux ridge, 2 for the
/// ridge with its fluence part.
#[test]
fn the_record_holds_ridge_at_28_or_40_by_model() {
    for (kind, code) in [(RidgeKind::Flux, 1), (RidgeKind::FluxAndFluence, 2)] {
        assert_eq!(kind.code(), code);
        let raw = tiny_ridge(kind);
        let t = record(&raw);
        assert_eq!((raw.u32(t), raw.u32(t + 28)), (1, code));
        assert!(raw.bytes[t + 32..t + 64].iter().all(|&b| b == 0));
        let raw = tiny_walk_ridge(kind);
        let t = record(&raw);
        assert_eq!((raw.u32(t), raw.u32(t + 28), raw.u32(t + 40)), (3, 1, code));
        assert_eq!(raw.bytes[t + 32..t + 40], 0.75f64.to_le_bytes());
        assert!(raw.bytes[t + 44..t + 64].iter().all(|&b| b == 0));
    }
}

/// §4, bit 6, the writer's side: set exactly when some table's record has `ridge` = 1 or 2.
#[test]
fn the_writer_sets_bit_6_exactly_when_a_table_has_the_ridge() {
    assert_eq!(written_features(&tiny_builder()) & RIDGE, 0);
    for kind in KINDS {
        let mut b = tiny_builder_of(synthetic_table(1.0, 2, 2, 4, true));
        assert_eq!(written_features(&b), 0);
        // One table with the ridge among others does.
        b.add_table(ridge_table(kind)).unwrap();
        assert_eq!(written_features(&b), RIDGE, "{kind:?}");
    }
    // and so do tables of both kinds together
    let mut b = tiny_builder_of(ridge_table(RidgeKind::Flux));
    b.add_table(ridge_table(RidgeKind::FluxAndFluence)).unwrap();
    assert_eq!(written_features(&b), RIDGE);
}

/// §4, bit 6: a reader "MUST reject a table with `ridge` = 1 or 2 when the bit is not set",
/// in a file of any minor and in a record of either model, and reads a file of any minor that
/// sets it.
#[test]
fn a_ridge_table_needs_required_feature_bit_6() {
    for kind in KINDS {
        let needle = format!(
            "table 0: ridge = {} in a file without required feature bit 6",
            kind.code()
        );
        for (model, raw, bits) in [
            ("pbd", tiny_ridge(kind), 0),
            (
                "walk",
                tiny_walk_ridge(kind),
                HARMONICS | MERGED_ROOTS | WALK_TABLES,
            ),
        ] {
            let secs = raw.sections();
            for minor in [0, 5, VERSION_MINOR] {
                let case = format!("{model}, {kind:?}, minor {minor}");
                let undeclared = Raw::build(minor, bits, 0, 256, &secs);
                assert_rejected(&case, &undeclared, "ridge-not-declared", &needle);
                let declared = Raw::build(minor, bits | RIDGE, 0, 256, &secs);
                let library = assert_accepted(&format!("{case} with bit 6"), &declared);
                assert_eq!(library.table(0).unwrap().ridge(), kind, "{case}");
            }
        }
    }
}

/// §4, bit 6: a reader reads a file that sets it without a table with the ridge; nothing is
/// read differently.
#[test]
fn bit_6_without_a_ridge_table_is_read() {
    let pbd = Raw::new(tiny_builder().to_bytes(Compression::None).unwrap());
    let raw = Raw::build(VERSION_MINOR, RIDGE, 0, 256, &pbd.sections());
    let library = assert_accepted("bit 6, no ridge table", &raw);
    assert_eq!(library.required_features(), RIDGE);
    let table = library.table(0).unwrap();
    assert_eq!(table.ridge(), RidgeKind::None);
    let file_table = FileTable::new(table).unwrap();
    assert_eq!(file_table.view().unwrap().ridge(), RidgeKind::None);
    let plain = Library::from_bytes(&pbd.bytes, Verify::Full).unwrap();
    assert_eq!(table.gwc_params(), plain.table(0).unwrap().gwc_params());
}

/// §9.1: `ridge` is 0, 1 or 2; other values are rejected, with the bit set or not, at byte 28
/// of a pbd-angular record and byte 40 of a walk-angular one. Each known code is read as its
/// kind.
#[test]
fn an_unknown_ridge_is_rejected() {
    let flux = RidgeKind::Flux;
    for (model, raw, at) in [
        ("pbd", tiny_ridge(flux), 28),
        ("walk", tiny_walk_ridge(flux), 40),
    ] {
        for code in [3, 7, 0x100, u32::MAX] {
            for bit in [RIDGE, 0] {
                let broken = edited(raw.clone(), |r| {
                    let t = record(r);
                    r.set_u32(t + at, code);
                    r.set_u64(32, (r.u64(32) & !RIDGE) | bit);
                });
                let needle = format!("table 0: unknown ridge code {code}");
                let case = format!("{model}, ridge {code}, bits {bit:#x}");
                assert_rejected(&case, &broken, "unknown-ridge", &needle);
            }
        }
        for kind in [RidgeKind::None, RidgeKind::Flux, RidgeKind::FluxAndFluence] {
            let code = kind.code();
            let known = edited(raw.clone(), |r| {
                let t = record(r);
                r.set_u32(t + at, code);
            });
            let library = assert_accepted(&format!("{model}, ridge {code}"), &known);
            assert_eq!(library.table(0).unwrap().ridge(), kind, "{model}");
        }
    }
}

/// Files of older minors read `ridge` as 0: their bytes there were reserved zero. Every valid
/// conformance vector but `ridge` (1) and `ridge-fluence` (2) has no table with the ridge.
#[test]
fn older_files_read_without_the_ridge() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/valid");
    let mut seen = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let library = Library::read(&path, Verify::Full).unwrap();
        let name = path.file_stem().unwrap().to_str().unwrap().to_owned();
        let ridge: Vec<RidgeKind> = library.tables().map(|t| t.ridge()).collect();
        let want = match name.as_str() {
            "ridge" => RidgeKind::Flux,
            "ridge-fluence" => RidgeKind::FluxAndFluence,
            _ => RidgeKind::None,
        };
        assert!(ridge.iter().all(|&r| r == want), "{name}: {ridge:?}");
        let declared = library.required_features() & RIDGE != 0;
        assert_eq!(declared, want.is_some(), "{name}");
        seen += 1;
    }
    assert!(seen >= 12, "{seen} vectors");
}

/// §9.1 and §4: in strict reading bytes 32 to 63 of a pbd-angular record with the ridge are
/// zero, and 44 to 63 of a walk-angular one; a file of a newer minor may use them, and is read
/// with its ridge.
#[test]
fn a_ridge_record_is_reserved_after_the_flag() {
    let kind = RidgeKind::FluxAndFluence;
    for (model, raw, bytes) in [
        ("pbd", tiny_ridge(kind), [32, 40, 63]),
        ("walk", tiny_walk_ridge(kind), [44, 48, 63]),
    ] {
        for at in bytes {
            let set = |minor: u16| with_record_byte(raw.clone(), at, 0x5A, minor);
            let needle = format!("reserved byte {at} of the table record 0 is 0x5a");
            let case = format!("{model}, byte {at}");
            assert_rejected(&case, &set(VERSION_MINOR), "reserved-not-zero", &needle);
            let newer = assert_accepted(&format!("{case}, newer minor"), &set(VERSION_MINOR + 1));
            assert_eq!(newer.table(0).unwrap().ridge(), kind, "{case}");
        }
    }
}

/// §14 step 10: the record's checks in order: reserved bytes, model, bit 5, component,
/// `ridge`, bit 6, fresnel, g, η.
#[test]
fn the_record_is_checked_in_the_order_of_section_14() {
    let broken = |edits: &[(usize, u64)]| {
        let mut raw = tiny_walk_ridge(RidgeKind::FluxAndFluence);
        let t = record(&raw);
        for &(at, value) in edits {
            match at {
                0 => raw.set_u64(32, raw.u64(32) & !value),
                4 | 28 | 40 => raw.set_u32(t + at, value as u32),
                _ => raw.set_f64(t + at, f64::from_bits(value)),
            }
        }
        raw.fix_crcs();
        Library::from_bytes(&raw.bytes, Verify::Full)
            .unwrap_err()
            .code()
    };
    let reserved = (48, 1.0f64.to_bits());
    let no_bit_5 = (0, WALK_TABLES);
    let component = (28, 9);
    let ridge = (40, 9);
    let no_bit_6 = (0, RIDGE);
    let fresnel = (4, 9);
    let g = (32, 2.0f64.to_bits());
    assert_eq!(broken(&[reserved, no_bit_5]), "reserved-not-zero");
    assert_eq!(broken(&[no_bit_5, component]), "walk-tables-not-declared");
    assert_eq!(broken(&[component, ridge]), "unknown-component");
    assert_eq!(broken(&[ridge, no_bit_6]), "unknown-ridge");
    assert_eq!(broken(&[no_bit_6, fresnel]), "ridge-not-declared");
    assert_eq!(broken(&[fresnel, g]), "unknown-fresnel");
}
