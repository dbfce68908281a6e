//! `bssrdf bake` and the Rust API's in-memory bake (`bssrdf_zoo::embed::bake_library`) are one
//! pipeline (`bssrdf_zoo::bake`): the command's file holds the same tables, material records and
//! provenance; only `bake_seconds`, written with --record-bake-time, is the command's own.

use bssrdf_zoo::embed::bake_library;
use bssrdf_zoo::format::{self, Compression, LibraryBuilder, Verify};
use bssrdf_zoo::materials;
use bssrdf_zoo::table::GridPreset;

use crate::common::{bssrdf, ok};

#[test]
fn bake_writes_the_file_bake_library_makes_in_memory() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = ["bake", "skin1", "--grid", "coarse", "--threads", "1", "-q"];
    ok(&bssrdf(
        d,
        &[&args[..], &["--record-bake-time", "-o", "timed.bssrdf"]].concat(),
    ));
    let timed = format::Library::read(d.join("timed.bssrdf"), Verify::Full).unwrap();

    let skin = materials::Library::builtin().get("skin1").unwrap().clone();
    let in_memory = bake_library(&[&skin], GridPreset::Coarse).unwrap();
    let in_memory = in_memory.format();

    // The same tables and materials, section by section.
    assert_eq!(timed.table_count(), in_memory.table_count());
    for (a, b) in timed.tables().zip(in_memory.tables()) {
        assert_eq!(a.header(), b.header());
        for info in a.section_infos() {
            assert_eq!(a.raw_section(info.kind), b.raw_section(info.kind));
        }
        assert_eq!(a.section_infos().count(), b.section_infos().count());
    }
    assert_eq!(timed.materials(), in_memory.materials());

    // The same provenance apart from the bake time the command was asked to record.
    let (a, b) = (timed.provenance().unwrap(), in_memory.provenance().unwrap());
    assert!(a.bake_seconds().is_some() && b.bake_seconds().is_none());
    let fields = |p: &format::Provenance| {
        p.fields()
            .filter(|(key, _)| *key != "bake_seconds")
            .map(|(key, value)| (key.to_string(), value.clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(fields(a), fields(b));
    assert_eq!(b.get("settings").unwrap()["grid"], "coarse");

    // Without --record-bake-time, the command writes the in-memory library byte for byte.
    ok(&bssrdf(d, &[&args[..], &["-o", "plain.bssrdf"]].concat()));
    let bytes = LibraryBuilder::from_library(in_memory)
        .unwrap()
        .to_bytes(Compression::None)
        .unwrap();
    assert!(std::fs::read(d.join("plain.bssrdf")).unwrap() == bytes);
}
