//! Round trips of the library format: what is written is read back bit for bit through every
//! reading path; equal content gives equal bytes; pack and unpack are lossless; writes are
//! atomic with respect to readers of the old file.

use bssrdf_testkit::files::{material, synthetic_table, tiny_builder, with_signed_floor, Raw};
use bssrdf_zoo::format::spec::VERSION_MINOR;
use bssrdf_zoo::format::{
    pack, unpack, AxisKind, Codec, Compression, Dtype, ExtraSection, Library, LibraryBuilder,
    SectionKind, TableData, Verify,
};

fn bits(values: &[f32]) -> Vec<u32> {
    values.iter().map(|v| v.to_bits()).collect()
}

/// Checks that `library` holds exactly the tables `expected`.
fn assert_tables(library: &Library, expected: &[TableData]) {
    assert_eq!(library.table_count(), expected.len());
    for (table, data) in library.tables().zip(expected) {
        assert_eq!(table.model(), data.model);
        assert_eq!(table.eta().to_bits(), data.eta.to_bits());
        assert_eq!(table.fresnel(), data.fresnel);
        assert_eq!(
            table.dims(),
            [data.rho.len(), data.theta.len(), data.r.len()]
        );
        assert_eq!(bits(table.axis(AxisKind::Rho)), bits(&data.rho));
        assert_eq!(bits(table.axis(AxisKind::Theta)), bits(&data.theta));
        assert_eq!(bits(table.axis(AxisKind::R)), bits(&data.r));
        assert_eq!(bits(table.gwc_params()), bits(&data.gwc));
        assert_eq!(bits(table.radial_cdf()), bits(&data.cdf));
        assert_eq!(
            table.theta_cdf().map(bits),
            data.theta_cdf.as_deref().map(bits)
        );
        assert_eq!(table.section(SectionKind::Tables), None);
    }
}

fn two_table_builder() -> (LibraryBuilder, Vec<TableData>) {
    let tables = vec![
        synthetic_table(1.33, 5, 3, 64, true),
        synthetic_table(1.5, 2, 4, 7, false),
    ];
    let mut b = LibraryBuilder::new();
    for t in &tables {
        b.add_table(t.clone()).unwrap();
    }
    b.add_material(material("marble", 0)).unwrap();
    let mut m = material("ketchup", 1);
    m.tables = [1, 0, 1];
    b.add_material(m).unwrap();
    (b, tables)
}

#[test]
fn round_trip_is_bit_exact_through_every_reading_path() {
    let dir = tempfile::tempdir().unwrap();
    let (builder, tables) = two_table_builder();
    let plain = dir.path().join("lib.bssrdf");
    let packed = dir.path().join("lib-packed.bssrdf");
    builder.write_atomic(&plain, Compression::None).unwrap();
    builder
        .write_atomic(&packed, Compression::Zstd { level: 3 })
        .unwrap();
    let opened = [
        Library::open_mmap(&plain, Verify::Full).unwrap(),
        Library::open_mmap(&plain, Verify::HeaderOnly).unwrap(),
        Library::read(&plain, Verify::Full).unwrap(),
        Library::read(&plain, Verify::HeaderOnly).unwrap(),
        Library::open_mmap(&packed, Verify::Full).unwrap(),
        Library::read(&packed, Verify::HeaderOnly).unwrap(),
    ];
    for (i, library) in opened.iter().enumerate() {
        assert_tables(library, &tables);
        assert_eq!(library.materials()[0], material("marble", 0), "{i}");
        assert_eq!(library.materials()[1].tables, [1, 0, 1]);
        assert_eq!(library.material("ketchup").unwrap().name, "ketchup");
        assert!(library.provenance().is_none());
        library.verify().unwrap();
    }
    assert!(opened[0].is_mapped() && !opened[2].is_mapped());
    assert!(!opened[0].is_compressed() && opened[4].is_compressed());
    assert_eq!(opened[4].required_features(), 1);
    assert!(std::fs::metadata(&packed).unwrap().len() < std::fs::metadata(&plain).unwrap().len());
}

#[test]
fn mapped_views_point_into_the_map_and_are_aligned() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lib.bssrdf");
    two_table_builder()
        .0
        .write_atomic(&path, Compression::None)
        .unwrap();
    let library = Library::open_mmap(&path, Verify::Full).unwrap();
    for table in library.tables() {
        for info in table.section_infos() {
            assert_eq!(info.offset % 256, 0);
            let kind = info.known_kind().unwrap();
            let view = table.section(kind).unwrap();
            assert_eq!(view.as_ptr() as usize % 256, 0, "{kind}");
            assert_eq!(view.len() * 4, info.raw_len);
        }
    }
}

#[test]
fn tiny_library_round_trips_materials_and_provenance() {
    let bytes = tiny_builder().to_bytes(Compression::None).unwrap();
    assert!(bytes.len() < 8192, "tiny file is {} bytes", bytes.len());
    let library = Library::from_bytes(&bytes, Verify::Full).unwrap();
    let milk = library.material("skimmilk").unwrap();
    assert_eq!(milk.source, "Jensen et al. 2001, table 2");
    assert_eq!(milk.albedo_range.unwrap().max, [0.9, 0.95, 1.0]);
    assert_eq!(milk.g, [0.1, 0.2, 0.3]);
    let p = library.provenance().unwrap();
    assert_eq!(p.tool_version(), "bssrdf-zoo test");
    assert_eq!(p.bake_seconds(), Some(1.5));
    assert_eq!(p.get("accuracy").unwrap()["max_rel_err"], 0.001);
}

#[test]
fn materials_are_found_by_their_name_as_people_type_it() {
    let mut b = LibraryBuilder::new();
    let t = b.add_table(synthetic_table(1.3, 2, 2, 4, true)).unwrap() as u32;
    for name in ["My Jade", "my_jade", "skin1", "Skin1"] {
        b.add_material(material(name, t)).unwrap();
    }
    let bytes = b.to_bytes(Compression::None).unwrap();
    let library = Library::from_bytes(&bytes, Verify::Full).unwrap();
    let names = |query: &str| -> Vec<String> {
        let found = library.materials_named(query);
        found.iter().map(|m| m.name.clone()).collect()
    };
    // An exact name wins over the names that read the same
    assert_eq!(names("Skin1"), ["Skin1"]);
    assert_eq!(names("my_jade"), ["my_jade"]);
    // Otherwise every name that reads the same, in file order
    assert_eq!(names(" SKIN1 "), ["skin1", "Skin1"]);
    assert_eq!(names("MY-JADE"), ["My Jade", "my_jade"]);
    assert!(names("jade").is_empty());
    assert_eq!(
        bssrdf_zoo::format::loose_name(" White Grapefruit_Juice "),
        "white-grapefruit-juice"
    );
}

#[test]
fn same_content_gives_byte_identical_files() {
    for compression in [Compression::None, Compression::Zstd { level: 5 }] {
        let a = tiny_builder().to_bytes(compression).unwrap();
        let b = tiny_builder().to_bytes(compression).unwrap();
        assert_eq!(a, b);
        let (x, _) = two_table_builder();
        assert_eq!(
            x.to_bytes(compression).unwrap(),
            x.to_bytes(compression).unwrap()
        );
    }
}

#[test]
fn pack_and_unpack_are_lossless() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("a.bssrdf");
    let packed = dir.path().join("b.bssrdf");
    let unpacked = dir.path().join("c.bssrdf");
    let mut builder = tiny_builder();
    builder
        .add_extra_section(ExtraSection {
            kind: 0x4000,
            table: Some(0),
            required: false,
            dtype: Dtype::F32,
            dims: vec![3],
            bytes: [1.0f32, 2.0, 3.0]
                .iter()
                .flat_map(|v| v.to_le_bytes())
                .collect(),
        })
        .unwrap();
    builder.write_atomic(&plain, Compression::None).unwrap();
    let report = pack(&plain, &packed, Compression::DEFAULT_ZSTD_LEVEL).unwrap();
    assert!(report.output_bytes < report.input_bytes);
    unpack(&packed, &unpacked).unwrap();
    assert_eq!(
        std::fs::read(&plain).unwrap(),
        std::fs::read(&unpacked).unwrap()
    );
    // In place, both ways.
    pack(&unpacked, &unpacked, 3).unwrap();
    assert!(Library::read(&unpacked, Verify::Full)
        .unwrap()
        .is_compressed());
    unpack(&unpacked, &unpacked).unwrap();
    assert_eq!(
        std::fs::read(&plain).unwrap(),
        std::fs::read(&unpacked).unwrap()
    );
    let library = Library::open_mmap(&unpacked, Verify::Full).unwrap();
    let extra = library.table(0).unwrap().raw_section(0x4000).unwrap();
    assert_eq!(extra.len(), 12);
    assert!(library.sections().iter().all(|s| s.codec == Codec::None));
}

#[test]
fn atomic_write_replaces_the_file_while_an_old_map_stays_valid() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lib.bssrdf");
    let (first, tables) = two_table_builder();
    first.write_atomic(&path, Compression::None).unwrap();
    let old = Library::open_mmap(&path, Verify::Full).unwrap();
    tiny_builder()
        .write_atomic(&path, Compression::None)
        .unwrap();
    // The old map still sees the old inode, whole.
    assert_tables(&old, &tables);
    old.verify().unwrap();
    let new = Library::open_mmap(&path, Verify::Full).unwrap();
    assert_eq!(new.table_count(), 1);
    // No temporary file is left behind.
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("lib.bssrdf")]);
}

#[test]
fn failed_write_leaves_the_old_file_and_no_litter() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lib.bssrdf");
    tiny_builder()
        .write_atomic(&path, Compression::None)
        .unwrap();
    let before = std::fs::read(&path).unwrap();
    let err = tiny_builder()
        .write_atomic(&path, Compression::Zstd { level: 1000 })
        .unwrap_err();
    assert_eq!(err.code(), "invalid-input", "{err}");
    // Renaming onto a folder fails after the temporary file was written.
    let folder = dir.path().join("folder");
    std::fs::create_dir(&folder).unwrap();
    std::fs::write(folder.join("x"), b"x").unwrap();
    let err = tiny_builder()
        .write_atomic(&folder, Compression::None)
        .unwrap_err();
    assert_eq!(err.code(), "io", "{err}");
    assert_eq!(std::fs::read(&path).unwrap(), before);
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["folder", "lib.bssrdf"]);
}

#[test]
fn builder_rejects_invalid_content_with_the_reader_errors() {
    let mut b = LibraryBuilder::new();
    let mut t = synthetic_table(1.3, 2, 2, 4, false);
    t.gwc[3] = f32::NAN;
    assert_eq!(b.add_table(t).unwrap_err().code(), "non-finite");
    let mut t = synthetic_table(1.3, 2, 2, 4, false);
    t.r.swap(1, 2);
    assert_eq!(b.add_table(t).unwrap_err().code(), "axis-not-increasing");
    let mut t = synthetic_table(1.3, 2, 2, 4, false);
    t.cdf.pop();
    assert_eq!(b.add_table(t).unwrap_err().code(), "section-dims");
    let t = synthetic_table(-1.0, 2, 2, 4, false);
    assert_eq!(b.add_table(t).unwrap_err().code(), "table-eta");
    assert_eq!(
        b.add_material(material("x", 0)).unwrap_err().code(),
        "material-table"
    );
    b.add_table(synthetic_table(1.3, 2, 2, 4, false)).unwrap();
    b.add_material(material("x", 0)).unwrap();
    assert_eq!(
        b.add_material(material("x", 0)).unwrap_err().code(),
        "duplicate-name"
    );
    let mut m = material("y", 0);
    m.g[1] = 1.0;
    assert_eq!(b.add_material(m).unwrap_err().code(), "material-value");
    let mut m = material("z", 0);
    m.name = "a\u{7}".into();
    assert_eq!(b.add_material(m).unwrap_err().code(), "control-character");
    assert_eq!(b.set_alignment(300).unwrap_err().code(), "bad-alignment");
}

/// Required feature bit 1 of format 1.1.
const SIGNED_FLOOR: u64 = 1 << 1;

/// A one-table library of `table`, as bytes.
fn one_table(table: TableData, compression: Compression) -> Vec<u8> {
    let mut b = LibraryBuilder::new();
    b.add_table(table).unwrap();
    b.add_material(material("wax", 0)).unwrap();
    b.to_bytes(compression).unwrap()
}

#[test]
fn writer_sets_the_signed_floor_bit_exactly_when_a_node_needs_it() {
    // No node with E_β > E: no feature bits, readable by every 1.x reader.
    let plain = Library::from_bytes(
        &tiny_builder().to_bytes(Compression::None).unwrap(),
        Verify::Full,
    )
    .unwrap();
    assert_eq!(
        (plain.version(), plain.required_features()),
        ((1, VERSION_MINOR), 0)
    );
    // E_β = E at every node is not a negative floor either.
    let mut table = synthetic_table(1.3, 2, 3, 5, false);
    for node in table.gwc.chunks_exact_mut(3) {
        node[1] = node[0];
    }
    let bytes = one_table(table, Compression::None);
    assert_eq!(
        Library::from_bytes(&bytes, Verify::Full)
            .unwrap()
            .required_features(),
        0
    );
    // One node with E_β one ulp above E is.
    let mut table = synthetic_table(1.3, 2, 3, 5, false);
    table.gwc[3 * 17 + 1] = f32::from_bits(table.gwc[3 * 17].to_bits() + 1);
    let bytes = one_table(table, Compression::None);
    let library = Library::from_bytes(&bytes, Verify::Full).unwrap();
    assert_eq!(library.required_features(), SIGNED_FLOOR);
    // Compressed: both bits.
    let bytes = one_table(
        with_signed_floor(synthetic_table(1.3, 2, 3, 5, true)),
        Compression::Zstd { level: 3 },
    );
    let library = Library::from_bytes(&bytes, Verify::Full).unwrap();
    assert_eq!(library.required_features(), SIGNED_FLOOR | 1);
}

#[test]
fn negative_floors_round_trip_with_the_bit_through_pack_and_unpack() {
    let dir = tempfile::tempdir().unwrap();
    let tables = vec![
        synthetic_table(1.33, 3, 2, 6, true),
        with_signed_floor(synthetic_table(1.5, 2, 4, 7, false)),
    ];
    let mut b = LibraryBuilder::new();
    for t in &tables {
        b.add_table(t.clone()).unwrap();
    }
    let plain = dir.path().join("a.bssrdf");
    let back = dir.path().join("b.bssrdf");
    b.write_atomic(&plain, Compression::None).unwrap();
    for verify in [Verify::Full, Verify::HeaderOnly] {
        let library = Library::open_mmap(&plain, verify).unwrap();
        assert_eq!(library.required_features(), SIGNED_FLOOR);
        assert_tables(&library, &tables);
        library.verify().unwrap();
    }
    pack(&plain, &back, 3).unwrap();
    let packed = Library::read(&back, Verify::Full).unwrap();
    assert_eq!(packed.required_features(), SIGNED_FLOOR | 1);
    assert_tables(&packed, &tables);
    unpack(&back, &back).unwrap();
    assert_eq!(
        std::fs::read(&plain).unwrap(),
        std::fs::read(&back).unwrap()
    );
}

#[test]
fn negative_floor_without_the_bit_is_rejected_naming_the_node() {
    let bytes = one_table(
        with_signed_floor(synthetic_table(1.3, 2, 3, 5, false)),
        Compression::None,
    );
    let mut raw = Raw::new(bytes);
    raw.set_u64(32, 0);
    raw.fix_header_crc();
    let err = Library::from_bytes(&raw.bytes, Verify::Full).unwrap_err();
    assert_eq!(err.code(), "signed-floor-not-declared", "{err}");
    let message = err.to_string();
    assert!(
        message.contains("table 0") && message.contains("(0, 0, 0)"),
        "{message}"
    );
    assert!(message.contains("signed-floor"), "{message}");
    // Header-only opening defers the check to `verify`, like the CRCs and NaN scans.
    let library = Library::from_bytes(&raw.bytes, Verify::HeaderOnly).unwrap();
    assert_eq!(
        library.verify().unwrap_err().code(),
        "signed-floor-not-declared"
    );
    // Packed, the same.
    let bytes = one_table(
        with_signed_floor(synthetic_table(1.3, 2, 3, 5, false)),
        Compression::Zstd { level: 3 },
    );
    let mut raw = Raw::new(bytes);
    raw.set_u64(32, 1);
    raw.fix_header_crc();
    let err = Library::from_bytes(&raw.bytes, Verify::Full).unwrap_err();
    assert_eq!(err.code(), "signed-floor-not-declared", "{err}");
}

/// Sets node (i, j, k) = (1, 2, 3) of a 2×3×5 table's `gwc-params` in a file and fixes the CRCs.
fn set_node(raw: &mut Raw, node: [f32; 3]) {
    let d = raw.data(bssrdf_testkit::files::kind::GWC, 0) + ((3 + 2) * 5 + 3) * 12;
    for (p, v) in node.into_iter().enumerate() {
        raw.set_f32(d + 4 * p, v);
    }
    raw.fix_crcs();
}

#[test]
fn negative_profiles_and_lobes_are_rejected_with_or_without_the_bit() {
    let cases = [
        // E_β·2|c| = 0.9 > E·(1 + |c|) = 0.6 (c of either sign).
        ("negative-profile", [0.4, 1.0, 0.45]),
        ("negative-profile", [0.4, 1.0, -0.45]),
        // E < 0 is a negative profile even without a lobe.
        ("negative-profile", [-0.5, 0.0, 0.0]),
        ("negative-lobe", [0.4, -0.1, 0.2]),
        ("negative-lobe", [0.4, -1e-30, 0.0]),
        ("concentration-out-of-range", [0.4, 0.2, 1.0]),
        ("concentration-out-of-range", [0.4, 0.2, -1.5]),
    ];
    for table in [
        synthetic_table(1.3, 2, 3, 5, false),
        with_signed_floor(synthetic_table(1.3, 2, 3, 5, false)),
    ] {
        let bytes = one_table(table.clone(), Compression::None);
        for (code, node) in cases {
            let mut raw = Raw::new(bytes.clone());
            set_node(&mut raw, node);
            for verify in [Verify::Full, Verify::HeaderOnly] {
                let result = Library::from_bytes(&raw.bytes, verify).and_then(|l| l.verify());
                let err = result.unwrap_err();
                assert_eq!(err.code(), code, "{node:?}: {err}");
                assert!(err.to_string().contains("(1, 2, 3)"), "{err}");
            }
            // The builder refuses the same node with the same error.
            let mut bad = table.clone();
            bad.gwc[((3 + 2) * 5 + 3) * 3..][..3].copy_from_slice(&node);
            let err = LibraryBuilder::new().add_table(bad).unwrap_err();
            assert_eq!(err.code(), code, "{node:?}: {err}");
        }
    }
}

#[test]
fn profile_rule_allows_f32_rounding_at_the_boundary_and_no_more() {
    // The deepest negative floor with c = 0.3 puts the profile's minimum at 0: E_β = E(1 + |c|)
    // / (2|c|), computed in f64, then rounded to f32.
    let c = 0.3f32;
    let (e, abs_c) = (0.7f32, f64::from(c));
    let e_beta = (f64::from(e) * (1.0 + abs_c) / (2.0 * abs_c)) as f32;
    let bytes = one_table(
        with_signed_floor(synthetic_table(1.3, 2, 3, 5, false)),
        Compression::None,
    );
    // The node rounded to f32 is 3.7e-8 relative over the boundary; each ulp of E_β adds
    // 7.9e-8, so the slack of 2^-20 = 9.5e-7 ends between 11 and 12 ulps.
    for (step, accepted) in [
        (-1i32, true),
        (0, true),
        (1, true),
        (11, true),
        (12, false),
        (40, false),
    ] {
        let beta = f32::from_bits((e_beta.to_bits() as i32 + step) as u32);
        let mut raw = Raw::new(bytes.clone());
        set_node(&mut raw, [e, beta, c]);
        let result = Library::from_bytes(&raw.bytes, Verify::Full);
        match (accepted, result) {
            (true, Ok(_)) => {}
            (false, Err(err)) => assert_eq!(err.code(), "negative-profile", "{err}"),
            (_, result) => panic!("E_beta {step} ulp from the boundary: {:?}", result.err()),
        }
    }
    // Zero energy with any lobe at c = 0 is the zero profile (as at r = 0).
    let mut raw = Raw::new(bytes);
    set_node(&mut raw, [0.0, 0.0, 0.9]);
    Library::from_bytes(&raw.bytes, Verify::Full).unwrap();
}

#[test]
fn libraries_can_be_shared_between_threads() {
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<Library>();
    assert_send_sync::<bssrdf_zoo::format::Table<'static>>();
}

/// In the child process: rewrite the library at `path` forever, alternating two contents.
fn rewrite_forever(path: &std::path::Path) -> ! {
    let a = tiny_builder();
    let (b, _) = two_table_builder();
    loop {
        a.write_atomic(path, Compression::None).unwrap();
        b.write_atomic(path, Compression::None).unwrap();
    }
}

#[test]
fn killed_writer_leaves_the_old_or_the_new_file() {
    const CHILD: &str = "BSSRDF_TEST_WRITER_CHILD";
    if let Some(path) = std::env::var_os(CHILD) {
        rewrite_forever(std::path::Path::new(&path));
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lib.bssrdf");
    let a = tiny_builder().to_bytes(Compression::None).unwrap();
    let b = two_table_builder().0.to_bytes(Compression::None).unwrap();
    let mut seen = 0;
    for delay_ms in [5u64, 13, 29, 41, 67, 150] {
        let mut child = std::process::Command::new(std::env::current_exe().unwrap())
            .args([
                "--exact",
                "roundtrip::killed_writer_leaves_the_old_or_the_new_file",
            ])
            .env(CHILD, &path)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        child.kill().unwrap(); // SIGKILL: no destructor, no cleanup runs
        child.wait().unwrap();
        if let Ok(bytes) = std::fs::read(&path) {
            assert!(
                bytes == a || bytes == b,
                "torn file after kill at {delay_ms} ms"
            );
            Library::from_bytes(&bytes, Verify::Full).unwrap();
            seen += 1;
        }
        // Only stray temporary files may remain beside it, never a partial target.
        for entry in std::fs::read_dir(dir.path()).unwrap() {
            let name = entry.unwrap().file_name().into_string().unwrap();
            assert!(name == "lib.bssrdf" || name.ends_with(".tmp"), "{name}");
        }
    }
    assert!(seen > 0, "the child never wrote a file");
}
