//! Tests of [`compare`] on small libraries built from made-up tables, and of the tolerance.

use super::*;
use crate::format::{
    AlbedoRange, Compression, FresnelMoments, LibraryBuilder, Material, ModelKind, Provenance,
    TableData, Verify, WalkComponent, WalkSource,
};

const RHO: [f32; 4] = [0.0, 0.25, 0.5, 1.0];
const THETA: [f32; 3] = [0.0, 0.5, 1.0];
const R: [f32; 5] = [0.0, 0.5, 1.0, 2.0, 4.0];
/// Nodes of a table over all of `RHO`: 4 × 3 × 5.
const NODES: usize = 60;

/// A one-lobe table at `eta` over the albedo nodes `rho` (and all of `THETA`, `R`), with its
/// θ-sampling section. Every value is a function of its node's axis values, so two tables
/// agree wherever they share nodes; every `gwc-params` node is valid (0 ≤ E_β ≤ E, |c| < 1).
fn table(eta: f64, rho: &[f32]) -> TableData {
    let (mut gwc, mut cdf, mut theta_cdf) = (Vec::new(), Vec::new(), Vec::new());
    for &p in rho {
        for &t in &THETA {
            theta_cdf.push(0.5 * p + 0.25 * t);
            for &r in &R {
                gwc.extend([1.0 + p + t, 0.5 * (1.0 + p), 0.25 * t - 0.1]);
                cdf.push(r / 4.0 * (1.0 - 0.5 * p));
            }
        }
    }
    TableData {
        model: ModelKind::PbdAngular,
        walk: None,
        ridge: crate::table::RidgeKind::None,
        eta,
        fresnel: FresnelMoments::Exact,
        rho: rho.to_vec(),
        theta: THETA.to_vec(),
        r: R.to_vec(),
        gwc,
        cdf,
        theta_cdf: Some(theta_cdf),
        harmonics: None,
        rebuild: Default::default(),
    }
}

/// The same table with two lobes: (rμ₃, rμ₄) at every node.
fn two_lobes(mut t: TableData) -> TableData {
    let nodes = t.cdf.len();
    t.harmonics = Some((0..nodes).flat_map(|n| [0.01 * n as f32, -0.02]).collect());
    t
}

/// A library of `tables` and `materials`, made by `tool`, read back from its bytes.
fn library(
    tables: Vec<TableData>,
    materials: Vec<Material>,
    tool: &str,
    compression: Compression,
) -> Library {
    let mut builder = LibraryBuilder::new();
    for t in tables {
        builder.add_table(t).unwrap();
    }
    for m in materials {
        builder.add_material(m).unwrap();
    }
    builder.set_provenance(Provenance::new(tool));
    Library::from_bytes(&builder.to_bytes(compression).unwrap(), Verify::Full).unwrap()
}

/// A library of `tables` only.
fn plain(tables: Vec<TableData>) -> Library {
    library(tables, Vec::new(), "test", Compression::None)
}

fn wax() -> Material {
    Material {
        name: "wax".into(),
        source: "made up".into(),
        sigma_s: [1.0, 2.0, 3.0],
        sigma_a: [0.1; 3],
        g: [0.0; 3],
        eta: 1.3,
        tables: [0; 3],
        albedo_range: None,
    }
}

/// The statistics of `quantity` in the first pair of tables.
fn stats(report: &LibraryDiff, quantity: Quantity) -> &QuantityDiff {
    report.tables()[0]
        .quantities()
        .iter()
        .find(|q| q.quantity() == quantity)
        .unwrap_or_else(|| panic!("{} not compared", quantity.name()))
}

fn names(t: &TableDiff) -> Vec<&'static str> {
    t.quantities().iter().map(|q| q.quantity().name()).collect()
}

/// E at node (ρ′ 2, θ 1, r 3) is 1 + 0.5 + 0.5 = 2: B doubles it.
const CHANGED: [usize; 3] = [2, 1, 3];

fn with_doubled_e() -> (Library, Library) {
    let a = plain(vec![table(1.3, &RHO)]);
    let mut t = table(1.3, &RHO);
    let [i, j, k] = CHANGED;
    let n = (i * THETA.len() + j) * R.len() + k;
    assert_eq!(t.gwc[3 * n], 2.0);
    t.gwc[3 * n] = 4.0;
    (a, plain(vec![t]))
}

#[test]
fn identical_libraries_agree_on_every_value() {
    let tables = || vec![table(1.3, &RHO), two_lobes(table(1.5, &RHO))];
    let report = compare(&plain(tables()), &plain(tables()), Tolerance::default());
    assert!(report.within_tolerance());
    assert!(
        report.differences().is_empty(),
        "{:?}",
        report.differences()
    );
    assert!(
        report.not_compared().is_empty(),
        "{:?}",
        report.not_compared()
    );
    assert_eq!(report.outside_tolerance(), 0);
    let pairs: Vec<(usize, usize)> = report.tables().iter().map(|t| (t.a(), t.b())).collect();
    assert_eq!(pairs, [(0, 0), (1, 1)]);
    let one = &report.tables()[0];
    assert_eq!(one.eta(), 1.3);
    assert_eq!(one.common_dims(), [4, 3, 5]);
    assert_eq!(
        names(one),
        [
            "gwc-params E",
            "gwc-params E_beta",
            "gwc-params c",
            "radial-cdf",
            "theta-cdf"
        ]
    );
    // 3-D quantities at every node, theta-cdf at every (ρ′, θ).
    assert_eq!(one.values_compared(), 4 * NODES + 12);
    let two = &report.tables()[1];
    assert_eq!(
        names(two)[5..],
        ["gwc-harmonics r*mu3", "gwc-harmonics r*mu4"]
    );
    assert_eq!(two.values_compared(), 6 * NODES + 12);
    for q in report.tables().iter().flat_map(TableDiff::quantities) {
        let name = q.quantity().name();
        assert_eq!(
            (q.max_abs(), q.mean_abs(), q.max_rel(), q.mean_rel()),
            (0.0, 0.0, 0.0, 0.0),
            "{name}"
        );
        assert_eq!(q.outside_tolerance(), 0, "{name}");
        // All equal: the max is the first value compared.
        let at = q.max_abs_at().unwrap();
        assert_eq!((at.index_a, at.index_b), ([0; 3], [0; 3]), "{name}");
    }
}

#[test]
fn one_changed_value_is_counted_once_with_its_size_and_place() {
    let (a, b) = with_doubled_e();
    let report = compare(&a, &b, Tolerance::default());
    assert!(!report.within_tolerance());
    assert!(
        report.differences().is_empty(),
        "{:?}",
        report.differences()
    );
    assert_eq!(report.outside_tolerance(), 1);
    let e = stats(&report, Quantity::GwcE);
    assert_eq!(e.count(), NODES);
    assert_eq!(e.outside_tolerance(), 1);
    // |2 − 4| = 2, relative 2/4, and the means over the 60 values.
    assert_eq!(e.max_abs(), 2.0);
    assert_eq!(e.max_rel(), 0.5);
    assert_eq!(e.mean_abs(), 2.0 / NODES as f64);
    assert_eq!(e.mean_rel(), 0.5 / NODES as f64);
    for at in [e.max_abs_at().unwrap(), e.max_rel_at().unwrap()] {
        let [i, j, k] = CHANGED;
        let expected = Location {
            index_a: CHANGED,
            index_b: CHANGED,
            rho: f64::from(RHO[i]),
            theta: f64::from(THETA[j]),
            r: f64::from(R[k]),
            a: 2.0,
            b: 4.0,
        };
        assert_eq!(*at, expected);
    }
    for q in report.tables()[0].quantities() {
        if q.quantity() != Quantity::GwcE {
            assert_eq!(q.max_abs(), 0.0, "{}", q.quantity().name());
            assert_eq!(q.outside_tolerance(), 0, "{}", q.quantity().name());
        }
    }
}

#[test]
fn a_difference_equal_to_the_tolerance_is_within_it() {
    let (a, b) = with_doubled_e();
    // |a − b| = 2 and max(|a|, |b|) = 4, both exact: relative 0.5 or absolute 2 just holds it.
    let below = 1.0 - 1e-12;
    for (relative, absolute, outside) in [
        (0.5, 0.0, 0),
        (0.5 * below, 0.0, 1),
        (0.0, 2.0, 0),
        (0.0, 2.0 * below, 1),
        (0.5 * below, 2.0 * below, 1),
        (0.5 * below, 2.0, 0),
    ] {
        let tolerance = Tolerance::new(relative, absolute).unwrap();
        let report = compare(&a, &b, tolerance);
        assert_eq!(report.tolerance(), tolerance);
        assert_eq!(
            report.outside_tolerance(),
            outside,
            "relative {relative}, absolute {absolute}"
        );
        assert_eq!(report.within_tolerance(), outside == 0);
        // The statistics do not depend on the tolerance.
        assert_eq!(stats(&report, Quantity::GwcE).max_abs(), 2.0);
    }
}

#[test]
fn tolerances_are_finite_and_not_negative() {
    let t = Tolerance::default();
    assert_eq!((t.relative(), t.absolute()), (0.0, 0.0));
    assert!(t.agrees(1.5, 1.5) && t.agrees(0.0, -0.0));
    assert!(!t.agrees(1.0, f64::from(1f32 + f32::EPSILON)));
    assert!(!t.agrees(f64::NAN, f64::NAN) && !t.agrees(1.0, f64::NAN));
    let relative = Tolerance::new(0.01, 0.0).unwrap();
    // |100 − 101| = 1 ≤ 0.01 · 101.
    assert!(relative.agrees(100.0, 101.0) && relative.agrees(-101.0, -100.0));
    assert!(!Tolerance::new(0.0099, 0.0).unwrap().agrees(100.0, 101.0));
    // An absolute tolerance covers values near 0, where a relative one does not.
    assert!(!relative.agrees(0.0, 1e-9));
    assert!(Tolerance::new(0.01, 1e-9).unwrap().agrees(0.0, 1e-9));
    for (relative, absolute, which, value) in [
        (-1.0, 0.0, "relative", "-1"),
        (f64::NAN, 0.0, "relative", "NaN"),
        (0.0, f64::INFINITY, "absolute", "inf"),
        (0.0, -1e-9, "absolute", "-1e-9"),
    ] {
        let err = Tolerance::new(relative, absolute).unwrap_err();
        assert_eq!(err.which, which);
        assert_eq!(
            err.to_string(),
            format!("{which} tolerance {value} is outside its domain: a finite number >= 0")
        );
    }
}

#[test]
fn tables_without_a_counterpart_and_the_table_count_are_differences() {
    let one = plain(vec![table(1.3, &RHO)]);
    let two = plain(vec![table(1.3, &RHO), table(1.5, &RHO)]);
    let report = compare(&one, &two, Tolerance::default());
    assert!(!report.within_tolerance());
    assert_eq!(report.outside_tolerance(), 0);
    assert_eq!(
        report.differences(),
        [
            Difference {
                item: Item::Unpaired {
                    side: Side::B,
                    table: 1
                },
                field: Field::Counterpart,
                a: MetaValue::Absent,
                b: MetaValue::Number(1.5),
            },
            Difference {
                item: Item::File,
                field: Field::Tables,
                a: MetaValue::Count(1),
                b: MetaValue::Count(2),
            },
        ]
    );
    assert_eq!(report.differences()[0].item.to_string(), "table 1 of B");
    assert_eq!(report.tables().len(), 1);
    // The other way round, the unpaired table is A's.
    let report = compare(&two, &one, Tolerance::default());
    let first = &report.differences()[0];
    assert_eq!(first.item.to_string(), "table 1 of A");
    assert_eq!(
        (&first.a, &first.b),
        (&MetaValue::Number(1.5), &MetaValue::Absent)
    );
    // A table of another η or other Fresnel moments never pairs.
    let mut pbrt = table(1.3, &RHO);
    pbrt.fresnel = FresnelMoments::PbrtPolynomial;
    let report = compare(&one, &plain(vec![pbrt]), Tolerance::default());
    assert!(report.tables().is_empty());
    let items: Vec<String> = report
        .differences()
        .iter()
        .map(|d| format!("{} {}", d.item, d.field.name()))
        .collect();
    assert_eq!(
        items,
        ["table 0 of A counterpart", "table 0 of B counterpart"]
    );
}

#[test]
fn a_subset_of_the_rows_is_compared_on_the_shared_nodes() {
    let rows = plain(vec![table(1.3, &RHO[1..3])]);
    let full = plain(vec![table(1.3, &RHO)]);
    let report = compare(&rows, &full, Tolerance::default());
    let item = Item::Tables { a: 0, b: 0 };
    assert_eq!(item.to_string(), "table 0 / 0");
    assert_eq!(
        report.differences(),
        [
            Difference {
                item: item.clone(),
                field: Field::Dims,
                a: MetaValue::Dims([2, 3, 5]),
                b: MetaValue::Dims([4, 3, 5]),
            },
            Difference {
                item,
                field: Field::Axis(AxisKind::Rho),
                a: MetaValue::Axis(AxisSummary {
                    nodes: 2,
                    first: Some(0.25),
                    last: Some(0.5)
                }),
                b: MetaValue::Axis(AxisSummary {
                    nodes: 4,
                    first: Some(0.0),
                    last: Some(1.0)
                }),
            },
        ]
    );
    assert_eq!(report.differences()[1].field.name(), "axis-rho");
    // Every shared value is equal: only the metadata differ.
    assert_eq!(report.outside_tolerance(), 0);
    assert!(!report.within_tolerance());
    let t = &report.tables()[0];
    assert_eq!(t.common_dims(), [2, 3, 5]);
    assert_eq!(t.values_compared(), 4 * 30 + 6);
    let at = stats(&report, Quantity::GwcC).max_abs_at().unwrap();
    assert_eq!((at.index_a, at.index_b), ([0, 0, 0], [1, 0, 0]));
    assert_eq!(at.rho, 0.25);
    let theta = stats(&report, Quantity::ThetaCdf).max_abs_at().unwrap();
    assert_eq!((theta.index_a, theta.index_b), ([0, 0, 0], [1, 0, 0]));
}

#[test]
fn tables_pair_at_the_same_index_else_by_shared_albedo_nodes() {
    // A's table 0 shares no ρ′ node with B's table 0, so it pairs with B's table 1; A's
    // table 1 shares none with B's table 1 and one with B's table 0.
    let a = plain(vec![table(1.3, &[0.5]), table(1.3, &[0.0])]);
    let b = plain(vec![table(1.3, &[0.0, 0.25]), table(1.3, &[0.5, 1.0])]);
    let report = compare(&a, &b, Tolerance::default());
    let pairs: Vec<(usize, usize)> = report.tables().iter().map(|t| (t.a(), t.b())).collect();
    assert_eq!(pairs, [(0, 1), (1, 0)]);
    assert!(report.tables().iter().all(|t| t.common_dims() == [1, 3, 5]));
    assert_eq!(report.outside_tolerance(), 0);
    // Only dims and ρ′ axes differ, per pair; no table lacks a counterpart.
    let fields: Vec<String> = report
        .differences()
        .iter()
        .map(|d| format!("{} {}", d.item, d.field.name()))
        .collect();
    assert_eq!(
        fields,
        [
            "table 0 / 1 dims",
            "table 0 / 1 axis-rho",
            "table 1 / 0 dims",
            "table 1 / 0 axis-rho"
        ]
    );
    // A table of no shared node still pairs (there is nothing better), with nothing compared.
    let report = compare(
        &plain(vec![table(1.3, &[0.5])]),
        &plain(vec![table(1.3, &[0.25])]),
        Tolerance::default(),
    );
    let t = &report.tables()[0];
    assert_eq!((t.common_dims(), t.values_compared()), ([0, 3, 5], 0));
    assert_eq!(
        names(t),
        [
            "gwc-params E",
            "gwc-params E_beta",
            "gwc-params c",
            "radial-cdf"
        ]
    );
    let e = &t.quantities()[0];
    assert_eq!(
        (e.max_abs(), e.mean_abs(), e.max_abs_at()),
        (0.0, 0.0, None)
    );
}

/// The report's metadata differences as (field, A's value, B's value).
fn fields(report: &LibraryDiff) -> Vec<(Field, &MetaValue, &MetaValue)> {
    report
        .differences()
        .iter()
        .map(|d| (d.field, &d.a, &d.b))
        .collect()
}

#[test]
fn sections_only_one_table_has_are_differences_not_values() {
    let mut bare = table(1.3, &RHO);
    bare.theta_cdf = None;
    let report = compare(
        &plain(vec![bare]),
        &plain(vec![two_lobes(table(1.3, &RHO))]),
        Tolerance::default(),
    );
    let fields = fields(&report);
    assert_eq!(
        fields,
        [
            (
                Field::ThetaCdf,
                &MetaValue::Bool(false),
                &MetaValue::Bool(true)
            ),
            (Field::Lobes, &MetaValue::Count(1), &MetaValue::Count(2)),
        ]
    );
    assert_eq!(
        names(&report.tables()[0]),
        [
            "gwc-params E",
            "gwc-params E_beta",
            "gwc-params c",
            "radial-cdf"
        ]
    );
    assert_eq!(report.tables()[0].values_compared(), 4 * NODES);
}

/// The same harmonics read by the two rules of format 1.4 (bit 4) are two profiles: a
/// difference, though every stored value is equal.
#[test]
fn two_lobe_tables_read_by_different_rules_differ() {
    let merged = two_lobes(table(1.3, &RHO));
    let roots = TableData {
        rebuild: crate::gwc::Rebuild::Roots,
        ..merged.clone()
    };
    let report = compare(
        &plain(vec![roots]),
        &plain(vec![merged]),
        Tolerance::default(),
    );
    let fields = fields(&report);
    let text = |s: &str| MetaValue::Text(s.into());
    assert_eq!(
        fields,
        [(Field::Rebuild, &text("roots"), &text("merged-roots"))]
    );
    assert_eq!(report.outside_tolerance(), 0);
}

/// `t` with two lobes, as a table of the walk at `g` for `component` (format 1.5).
fn walk(t: TableData, g: f64, component: WalkComponent) -> TableData {
    TableData {
        model: ModelKind::WalkAngular,
        walk: Some(WalkSource { g, component }),
        ..two_lobes(t)
    }
}

/// Tables of PBD and of the walk, or of two walks, at the same η pair and differ in their
/// model, the walk's g and its component; a table of the same model and walk pairs first.
#[test]
fn the_model_and_the_walk_are_differences() {
    let pbd = two_lobes(table(1.3, &RHO));
    let multiple = walk(table(1.3, &RHO), 0.5, WalkComponent::Multiple);
    let total = walk(table(1.3, &RHO), 0.75, WalkComponent::Total);
    let text = |s: &str| MetaValue::Text(s.into());
    let report = compare(
        &plain(vec![pbd.clone()]),
        &plain(vec![multiple.clone()]),
        Tolerance::default(),
    );
    assert_eq!(
        fields(&report),
        [
            (Field::Model, &text("pbd-angular"), &text("walk-angular")),
            (Field::WalkG, &MetaValue::Absent, &MetaValue::Number(0.5)),
            (Field::WalkComponent, &MetaValue::Absent, &text("multiple")),
        ]
    );
    // Every value is compared, and equal
    assert_eq!(report.outside_tolerance(), 0);
    assert!(report.tables()[0].values_compared() > 0);
    let report = compare(
        &plain(vec![multiple.clone()]),
        &plain(vec![total]),
        Tolerance::default(),
    );
    assert_eq!(
        fields(&report),
        [
            (
                Field::WalkG,
                &MetaValue::Number(0.5),
                &MetaValue::Number(0.75)
            ),
            (Field::WalkComponent, &text("multiple"), &text("total")),
        ]
    );
    // B's table 1 is of the same walk as A's table 0: they pair, and B's table 0 of PBD has
    // no counterpart.
    let report = compare(
        &plain(vec![multiple.clone()]),
        &plain(vec![pbd, multiple]),
        Tolerance::default(),
    );
    let pairs: Vec<(usize, usize)> = report.tables().iter().map(|t| (t.a(), t.b())).collect();
    assert_eq!(pairs, [(0, 1)]);
    let differences: Vec<String> = report
        .differences()
        .iter()
        .map(|d| format!("{} {}", d.item, d.field.name()))
        .collect();
    assert_eq!(differences, ["table 0 of B counterpart", "file tables"]);
}

/// Tables that differ only in their ridge kind (format 1.6) are told apart: their values are
/// the same numbers, which mean different profiles. A table pairs first with one of its flag.
#[test]
fn the_ridge_flag_is_a_difference() {
    let plain_table = table(1.3, &RHO);
    let ridge = TableData {
        ridge: crate::table::RidgeKind::Flux,
        ..plain_table.clone()
    };
    let report = compare(
        &plain(vec![plain_table.clone()]),
        &plain(vec![ridge.clone()]),
        Tolerance::default(),
    );
    assert_eq!(
        fields(&report),
        [(
            Field::Ridge,
            &MetaValue::Text("none".into()),
            &MetaValue::Text("flux".into())
        )]
    );
    assert!(!report.within_tolerance());
    assert_eq!(report.outside_tolerance(), 0);
    assert!(report.tables()[0].values_compared() > 0);
    assert_eq!(report.differences()[0].field.name(), "ridge");
    // Two tables of each flag at one η: each pairs with its own, nothing differs.
    let report = compare(
        &plain(vec![plain_table.clone(), ridge.clone()]),
        &plain(vec![ridge, plain_table]),
        Tolerance::default(),
    );
    let pairs: Vec<(usize, usize)> = report.tables().iter().map(|t| (t.a(), t.b())).collect();
    assert_eq!(pairs, [(0, 1), (1, 0)]);
    assert!(report.within_tolerance(), "{:?}", report.differences());
}

#[test]
fn materials_are_compared_and_provenance_and_compression_only_listed() {
    let tables = || vec![table(1.3, &RHO)];
    let same = |tool, compression| library(tables(), vec![wax()], tool, compression);
    // Provenance and compression differ: listed, yet the files agree.
    let zstd = Compression::Zstd { level: 1 };
    let report = compare(
        &same("tool a", Compression::None),
        &same("tool b", zstd),
        Tolerance::default(),
    );
    assert!(report.within_tolerance());
    assert_eq!(
        report.not_compared(),
        [
            Difference {
                item: Item::Provenance("tool_version".into()),
                field: Field::Value,
                a: MetaValue::Json("tool a".into()),
                b: MetaValue::Json("tool b".into()),
            },
            Difference {
                item: Item::File,
                field: Field::Compressed,
                a: MetaValue::Bool(false),
                b: MetaValue::Bool(true),
            },
        ]
    );
    assert_eq!(
        report.not_compared()[0].item.to_string(),
        "provenance tool_version"
    );
    // A material's fields, and materials on one side only.
    let range = AlbedoRange {
        min: [0.6; 3],
        max: [0.7; 3],
    };
    let changed = Material {
        sigma_s: [1.0, 2.0, 4.0],
        albedo_range: Some(range),
        ..wax()
    };
    let milk = Material {
        name: "milk".into(),
        ..wax()
    };
    let b = library(tables(), vec![changed, milk], "tool a", Compression::None);
    let report = compare(&same("tool a", Compression::None), &b, Tolerance::default());
    assert!(!report.within_tolerance());
    assert!(report.not_compared().is_empty());
    let wax_item = Item::Material("wax".into());
    assert_eq!(
        report.differences(),
        [
            Difference {
                item: wax_item.clone(),
                field: Field::SigmaS,
                a: MetaValue::PerChannel([1.0, 2.0, 3.0]),
                b: MetaValue::PerChannel([1.0, 2.0, 4.0]),
            },
            Difference {
                item: wax_item,
                field: Field::AlbedoRange,
                a: MetaValue::AlbedoRange(None),
                b: MetaValue::AlbedoRange(Some(range)),
            },
            Difference {
                item: Item::Material("milk".into()),
                field: Field::Present,
                a: MetaValue::Bool(false),
                b: MetaValue::Bool(true),
            },
        ]
    );
    assert_eq!(report.differences()[2].item.to_string(), "material milk");
}

#[test]
fn names_are_the_reports_spellings() {
    let fields = [
        (Field::Counterpart, "counterpart"),
        (Field::Tables, "tables"),
        (Field::Compressed, "compressed"),
        (Field::Model, "model"),
        (Field::WalkG, "walk_g"),
        (Field::WalkComponent, "walk_component"),
        (Field::Ridge, "ridge"),
        (Field::FresnelMoments, "fresnel_moments"),
        (Field::Dims, "dims"),
        (Field::Axis(AxisKind::Rho), "axis-rho"),
        (Field::Axis(AxisKind::Theta), "axis-theta"),
        (Field::Axis(AxisKind::R), "axis-r"),
        (Field::ThetaCdf, "theta-cdf"),
        (Field::Lobes, "lobes"),
        (Field::Rebuild, "rebuild"),
        (Field::Present, "present"),
        (Field::Source, "source"),
        (Field::SigmaS, "sigma_s"),
        (Field::SigmaA, "sigma_a"),
        (Field::G, "g"),
        (Field::Eta, "eta"),
        (Field::AlbedoRange, "albedo_range"),
        (Field::Value, "value"),
    ];
    for (field, name) in fields {
        assert_eq!(field.name(), name);
    }
    assert_eq!(Item::File.to_string(), "file");
    assert_eq!(Quantity::ThetaCdf.dims(), 2);
    assert_eq!(Quantity::HarmonicMu4.dims(), 3);
}
