//! The in-memory bake (`embed::bake_library`) is the pipeline `bssrdf bake` runs
//! (`bake::Baker`): the same tables, material records, check and provenance. The only field
//! that can differ is the one measured at run time, `bake_seconds`, written only when asked
//! for (`--record-bake-time`); the thread count is never written (the tables are bit-identical
//! on any count) and stays in each table's `BakeReport`.

use std::sync::Mutex;

use bssrdf_zoo::bake::{BakeGrid, Baker, MaterialSpec, Progress};
use bssrdf_zoo::embed::bake_library;
use bssrdf_zoo::format::{self, Compression, LibraryBuilder, Verify};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::materials;
use bssrdf_zoo::table::{Grid, GridPreset, Lobes};

/// A table's decoded sections: kind code and bytes, in kind order.
type Sections = Vec<(u32, Vec<u8>)>;

/// Each table's η and its decoded sections, in file order.
fn table_sections(file: &format::Library) -> Vec<(f64, Sections)> {
    file.tables()
        .map(|t| {
            let sections = t
                .section_infos()
                .map(|s| (s.kind, t.raw_section(s.kind).unwrap_or_default().to_vec()))
                .collect();
            (t.eta(), sections)
        })
        .collect()
}

#[test]
fn bake_library_is_the_command_lines_pipeline_with_the_same_provenance() {
    let skin = materials::Library::builtin().get("skin1").unwrap().clone();
    let grid = Grid::ferrier(12, 5, 16);
    let in_memory = bake_library(&[&skin], grid.clone()).unwrap();

    // The pipeline as `bssrdf bake skin1 --threads 1 --record-bake-time` sets it up: the
    // command's defaults spelled out, one thread, a progress callback.
    let baker = Baker::new(grid)
        .with_moments(Moments::Exact)
        .with_lobes(None)
        .with_theta_sampling(true)
        .with_bake_time(true);
    let seen = Mutex::new(Vec::new());
    let progress = |p: &Progress| seen.lock().unwrap().push(p.clone());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let spec = MaterialSpec::named(&skin).unwrap();
    let baked = pool
        .install(|| baker.bake(&[spec], &[], Some(&progress)))
        .unwrap();
    let bytes = baked.to_bytes(Compression::None).unwrap();
    let file = format::Library::from_bytes(&bytes, Verify::Full).unwrap();

    // The same tables and material records (with the file's citation as source).
    assert_eq!(table_sections(in_memory.format()), table_sections(&file));
    assert_eq!(file.table_count(), 1);
    assert_eq!(in_memory.materials(), file.materials());
    assert!(file.materials()[0].source.contains("Jensen"));

    // The same provenance apart from bake_seconds, which only the second asked for.
    let (a, b) = (
        in_memory.format().provenance().unwrap(),
        file.provenance().unwrap(),
    );
    let without_time = |p: &format::Provenance| {
        p.fields()
            .filter(|(key, _)| *key != "bake_seconds")
            .map(|(key, value)| (key.to_string(), value.clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(without_time(a), without_time(b));
    assert_eq!(a.bake_seconds(), None);
    assert_eq!(b.bake_seconds(), Some(baked.seconds()));
    let keys: Vec<&str> = a.fields().map(|(key, _)| key).collect();
    assert_eq!(keys, ["accuracy", "quadrature", "settings", "tool_version"]);
    // The check's result is what the provenance holds; the thread count is in the report only.
    let check = serde_json::to_value(baked.tables()[0].check()).unwrap();
    assert_eq!(a.get("accuracy").unwrap()["tables"][0], check);
    assert_eq!(baked.tables()[0].report().threads, 1);
    assert_eq!(a.get("settings").unwrap()["grid"], "custom");

    // With the in-memory bake's provenance, the file is the same byte for byte.
    let mut builder = baked.into_builder();
    builder.set_provenance(a.clone());
    let in_memory_bytes = LibraryBuilder::from_library(in_memory.format())
        .unwrap()
        .to_bytes(Compression::None)
        .unwrap();
    assert!(builder.to_bytes(Compression::None).unwrap() == in_memory_bytes);

    // Progress: a start per table, then the rows as they are baked, up to all 12.
    let seen = seen.into_inner().unwrap();
    assert_eq!(seen.first().map(|p| p.rows_done), Some(0));
    assert_eq!(seen.last().map(|p| p.rows_done), Some(12));
    assert!(seen.windows(2).all(|w| w[0].rows_done <= w[1].rows_done));
    assert!(seen.iter().all(|p| p.rows_total == 12 && p.tables == 1));
}

#[test]
fn a_preset_gives_each_table_the_grid_of_its_lobes_and_bare_etas_their_own_table() {
    let baker = Baker::new(GridPreset::Default);
    assert_eq!(baker.grid(), &BakeGrid::Preset(GridPreset::Default));
    // η = 1.2 takes two lobes and 42 radii, η = 1.4 one lobe and 64, on the same albedo rows.
    assert_eq!(baker.lobes_at(1.2), Lobes::Two);
    assert_eq!(baker.grid_at(1.2).r.len(), 42);
    assert_eq!(baker.grid_at(1.4).r.len(), 64);
    assert_eq!(baker.grid_at(1.2).rho, baker.albedo_grid().rho);
    // A custom grid is every table's, whatever its lobes.
    let custom = Baker::new(Grid::ferrier(6, 4, 10)).with_lobes(Some(Lobes::One));
    assert_eq!(custom.grid_at(1.2), Grid::ferrier(6, 4, 10));
    assert_eq!(custom.lobes_at(1.2), Lobes::One);
    assert_eq!(custom.check_bounds(), bssrdf_zoo::table::CHECK_BOUNDS);
    assert_eq!(
        Baker::new(GridPreset::Coarse).check_bounds(),
        bssrdf_zoo::table::CHECK_COARSE_BOUNDS
    );

    // One table per distinct η, in increasing η, a material on the table of its η (skin1's η
    // given again as a bare one adds no table).
    let skin = materials::Library::builtin().get("skin1").unwrap().clone();
    assert_eq!(skin.eta(), 1.3);
    let baked = custom
        .with_theta_sampling(false)
        .bake(
            &[MaterialSpec::named(&skin).unwrap()],
            &[1.6, 1.2, 1.3],
            None,
        )
        .unwrap();
    let etas: Vec<f64> = baked.tables().iter().map(|t| t.eta()).collect();
    assert_eq!(etas, [1.2, 1.3, 1.6]);
    assert_eq!(baked.materials()[0].record().tables, [1; 3]);
    assert!(baked
        .tables()
        .iter()
        .all(|t| t.table().theta_cdf().is_none()));
    assert_eq!(
        baked.provenance().get("settings").unwrap()["theta_sampling"],
        false
    );
    assert!(baked.warnings().is_empty());
}

#[test]
fn a_diffuse_material_is_inverted_through_the_table_of_its_eta() {
    // A reflectance of 0.99 is above the largest effective albedo of the table: clamped, with a
    // warning naming the channel.
    let spec = MaterialSpec::diffuse(
        "wax",
        [0.5, 0.99, 0.3],
        [1.0, 2.0, 3.0],
        [0.0; 3],
        1.4,
        "test",
    )
    .unwrap();
    let baked = Baker::new(Grid::ferrier(12, 5, 16))
        .bake(&[spec], &[], None)
        .unwrap();
    let m = &baked.materials()[0];
    assert_eq!(m.record().source, "test");
    assert_eq!(m.material().id(), "wax");
    assert!(m.material().rho_prime()[1] > 0.999);
    assert_eq!(baked.warnings().len(), 1, "{:?}", baked.warnings());
    assert!(baked.warnings()[0].contains("channel g"));

    // Its parameters and id are checked before any bake.
    let bad = MaterialSpec::diffuse("wax", [1.5, 0.5, 0.5], [1.0; 3], [0.0; 3], 1.4, "");
    assert!(bad.unwrap_err().to_string().contains("wax"));
    let bad = MaterialSpec::diffuse("Not An Id", [0.5; 3], [1.0; 3], [0.0; 3], 1.4, "");
    assert!(bad.is_err());
}

#[test]
fn the_provenance_records_the_rules_of_two_lobes_and_of_grazing_nodes_only_where_a_table_took_them()
{
    let keys = |baked: &bssrdf_zoo::bake::BakedLibrary| {
        let settings = &baked.provenance().get("settings").unwrap();
        ["two_lobe_fit", "theta_nodes_near_eta_1", "beam_in_surface"]
            .map(|k| settings.get(k).is_some())
    };
    // One lobe at η = 1.33: none of them
    let coarse = Baker::new(GridPreset::Coarse).with_theta_sampling(false);
    let baked = coarse.bake(&[], &[1.33], None).unwrap();
    assert_eq!(keys(&baked), [false; 3]);
    // (each table's dims are in its record, not the settings)
    assert!(baked
        .provenance()
        .get("settings")
        .unwrap()
        .get("two_lobe_dims")
        .is_none());
    // Two lobes at η = 1.2: the two-lobe rules only
    let small = Baker::new(Grid::ferrier(6, 4, 10)).with_theta_sampling(false);
    assert_eq!(
        keys(&small.bake(&[], &[1.2], None).unwrap()),
        [true, false, false]
    );
    // η = 1 on a preset: also its θ nodes near η = 1 and the node at 90°, where the beam runs
    // in the surface (a custom grid records no preset nodes)
    let baked = coarse.bake(&[], &[1.0], None).unwrap();
    assert_eq!(keys(&baked), [true; 3]);
    assert_eq!(
        keys(&small.bake(&[], &[1.0], None).unwrap()),
        [true, false, true]
    );
}

#[test]
fn records_the_file_would_refuse_are_refused_before_any_table() {
    // A grid whose bake fails at once: the records' refusal comes first, so no table was baked
    let unbakeable = Grid {
        rho: vec![0.5, 0.2],
        theta: vec![0.0, 0.5],
        r: vec![0.0, 0.5, 1.0, 2.0],
    };
    let baker = Baker::new(unbakeable);
    let wax =
        materials::Material::from_coefficients("wax", [2.0; 3], [0.01; 3], [0.0; 3], 1.4).unwrap();
    let spec = |source: &str| MaterialSpec::new(wax.clone(), source);
    for (specs, needle) in [
        (vec![spec(""), spec("")], "material \"wax\" is listed twice"),
        (vec![spec(&"x".repeat(257))], "source is 257 bytes"),
        (vec![spec("a\nb")], "control character"),
    ] {
        let err = baker.bake(&specs, &[], None).unwrap_err();
        assert!(
            matches!(err, bssrdf_zoo::bake::BakeError::Scene(_))
                && err.to_string().contains(needle),
            "{err}"
        );
    }
    // The same grid's own refusal, with records the file keeps
    let err = baker.bake(&[spec("")], &[], None).unwrap_err();
    assert!(err.to_string().contains("cannot bake the table"), "{err}");
}

#[test]
fn a_check_whose_rows_lie_below_its_regions_says_nothing_was_checked() {
    let grid = Grid {
        rho: vec![0.0, 0.0005],
        theta: vec![0.0, 0.5, 1.0, 1.5],
        r: vec![0.0, 0.5, 1.0, 2.0, 4.0],
    };
    let baked = Baker::new(grid).bake(&[], &[1.33], None).unwrap();
    let check = baked.tables()[0].check();
    assert!(check.regions.is_empty() && !check.passes());
    let note = check.nothing_checked().unwrap();
    assert!(note.contains("nothing was checked"), "{note}");
    // A check that saw regions has no such note
    let seen = Baker::new(Grid::ferrier(6, 4, 10))
        .bake(&[], &[1.33], None)
        .unwrap();
    assert_eq!(seen.tables()[0].check().nothing_checked(), None);
}
