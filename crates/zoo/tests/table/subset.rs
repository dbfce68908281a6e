//! Albedo-row subsets (scene bakes): lookups inside the declared ranges are bit-identical to the
//! full table's, baking only the kept rows gives exactly the full bake's rows, and lookups
//! outside the kept rows are refused. A negative control shows that keeping one neighbour too
//! few does change bits, so the identity checks can fail.

use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{
    bake, bake_rows, kept_rows, rows_for, AngularTable, Grid, GridPreset, RhoInterval, RidgeKind,
};
use std::f64::consts::PI;
use std::sync::OnceLock;

pub(crate) const ETA: f64 = 1.33;

pub(crate) fn grid() -> Grid {
    Grid::preset(GridPreset::Coarse)
}

/// The full coarse table with the θ-sampling CDF, baked once for the file.
pub(crate) fn full() -> &'static AngularTable {
    static TABLE: OnceLock<AngularTable> = OnceLock::new();
    TABLE.get_or_init(|| bake(ETA, Moments::Exact, &grid(), true).unwrap().0)
}

fn bits(t: &AngularTable) -> Vec<u32> {
    t.params()
        .iter()
        .chain(t.radial_cdf())
        .chain(t.theta_cdf().unwrap_or(&[]))
        .map(|v| v.to_bits())
        .collect()
}

fn opt_bits(v: Option<f64>) -> Option<u64> {
    v.map(f64::to_bits)
}

/// Albedos to probe inside `interval`: both ends, every axis node inside, points just inside
/// the ends, and uniform draws.
fn albedos(interval: RhoInterval, axis: &[f64], rng: &mut SplitMix64) -> Vec<f64> {
    let (lo, hi) = (interval.lo(), interval.hi());
    let mut out = vec![lo, hi, lo + (hi - lo) * 1e-9, hi - (hi - lo) * 1e-9];
    out.extend(axis.iter().copied().filter(|x| (lo..=hi).contains(x)));
    out.extend((0..40).map(|_| lo + (hi - lo) * rng.next_f64()));
    out
}

/// Compares every lookup of `sub` with `full` at many points whose albedo lies in `interval`.
fn assert_identical_inside(full: &AngularTable, sub: &AngularTable, interval: RhoInterval) {
    let (f, s) = (full.view(), sub.view());
    let mut rng = SplitMix64::seed_from_u64(11);
    let theta_nodes = full.axes().theta().as_slice().to_vec();
    let r_max = *full.axes().r().as_slice().last().unwrap();
    let mut checked = 0;
    for rho in albedos(interval, full.axes().rho().as_slice(), &mut rng) {
        let mut thetas = theta_nodes.clone();
        thetas.extend((0..6).map(|_| 0.5 * PI * rng.next_f64()));
        for theta in thetas {
            let at = format!("rho {rho}, theta {theta}");
            assert_eq!(
                opt_bits(f.effective_albedo(rho, theta)),
                opt_bits(s.effective_albedo(rho, theta)),
                "effective albedo at {at}"
            );
            assert!(s.effective_albedo(rho, theta).is_some(), "{at} refused");
            for _ in 0..6 {
                let r = r_max * rng.next_f64().powi(4);
                let phi = PI * (2.0 * rng.next_f64() - 1.0);
                assert_eq!(
                    opt_bits(f.eval(rho, theta, r, phi)),
                    opt_bits(s.eval(rho, theta, r, phi)),
                    "eval at {at}, r {r}, phi {phi}"
                );
                assert_eq!(
                    f.pdf(rho, theta, r, phi).to_bits(),
                    s.pdf(rho, theta, r, phi).to_bits(),
                    "pdf at {at}, r {r}, phi {phi}"
                );
                let (u, v) = (rng.next_f64(), rng.next_f64());
                assert_eq!(
                    f.sample(rho, theta, u, v),
                    s.sample(rho, theta, u, v),
                    "sample at {at}"
                );
                checked += 1;
            }
        }
        let u = [0.0; 4].map(|_| rng.next_f64());
        let (a, b) = (f.sample_path(rho, u), s.sample_path(rho, u));
        assert_eq!(a, b, "path sample at rho {rho}");
        if let Some(p) = a {
            assert_eq!(p.pdf.to_bits(), b.unwrap().pdf.to_bits());
        }
        let theta = 0.5 * PI * rng.next_f64();
        assert_eq!(
            f.pdf_theta(rho, theta).to_bits(),
            s.pdf_theta(rho, theta).to_bits(),
            "pdf_theta at rho {rho}, theta {theta}"
        );
        let r = r_max * rng.next_f64().powi(4);
        assert_eq!(
            opt_bits(f.eval_perpendicular(rho, r)),
            opt_bits(s.eval_perpendicular(rho, r)),
            "perpendicular at rho {rho}"
        );
    }
    assert!(checked > 1000, "only {checked} points");
}

/// The ranges of the example scene of docs/scenes.md plus the awkward places: the axis ends, an
/// interior node, a tiny interval, the whole axis.
fn intervals() -> Vec<RhoInterval> {
    let node = full().axes().rho().as_slice()[17];
    [
        (0.85, 0.97),
        (0.80, 0.90),
        (0.60, 0.70),
        (0.0, 0.0),
        (1.0, 1.0),
        (0.0, 0.02),
        (0.995, 1.0),
        (node, node),
        (0.5, 0.5 + 1e-12),
        (0.0, 1.0),
    ]
    .iter()
    .map(|&(lo, hi)| RhoInterval::new(lo, hi).unwrap())
    .collect()
}

#[test]
fn lookups_inside_the_declared_ranges_are_bit_identical() {
    let full = full();
    for interval in intervals() {
        let runs = kept_rows(full.axes().rho(), &[interval]).unwrap();
        assert_eq!(runs.len(), 1, "{interval:?}");
        let sub = full.subset_rows(runs[0].clone()).unwrap();
        assert_identical_inside(full, &sub, interval);
    }
}

#[test]
fn a_scene_keeps_few_rows() {
    let axis = full().axes().rho();
    let skin = [(0.85, 0.97), (0.80, 0.90), (0.60, 0.70)]
        .map(|(lo, hi)| RhoInterval::new(lo, hi).unwrap());
    let runs = kept_rows(axis, &skin).unwrap();
    let kept: usize = runs.iter().map(|r| r.len()).sum();
    assert!(kept < axis.as_slice().len() / 2, "{runs:?}");
}

#[test]
fn baking_only_the_kept_rows_equals_the_full_bake() {
    let full = full();
    let n = full.axes().rho().as_slice().len();
    // All rows in blocks: the same table as one bake.
    let (whole, _) = bake_rows(ETA, Moments::Exact, &grid(), 0..n, true, &|_| {}).unwrap();
    assert_eq!(bits(&whole), bits(full));
    assert_eq!(whole.axes(), full.axes());
    for interval in [intervals()[0], intervals()[4], intervals()[7]] {
        let rows = rows_for(full.axes().rho(), interval).unwrap();
        let done = std::sync::Mutex::new(Vec::new());
        let (baked, report) = bake_rows(ETA, Moments::Exact, &grid(), rows.clone(), true, &|k| {
            done.lock().unwrap().push(k)
        })
        .unwrap();
        let sub = full.subset_rows(rows.clone()).unwrap();
        assert_eq!(bits(&baked), bits(&sub), "{interval:?}");
        assert_eq!(baked.axes(), sub.axes());
        assert_eq!(done.into_inner().unwrap().last(), Some(&rows.len()));
        let nodes: usize = report.fit_branches.values().sum();
        let (_, nt, nr) = baked.axes().dims();
        assert_eq!(nodes, rows.len() * nt * nr);
    }
    // Without the θ CDF: the same rows, no theta-cdf.
    let rows = rows_for(full.axes().rho(), intervals()[0]).unwrap();
    let (particle, _) =
        bake_rows(ETA, Moments::Exact, &grid(), rows.clone(), false, &|_| {}).unwrap();
    assert!(particle.theta_cdf().is_none());
    let sub = full
        .subset_rows(rows)
        .unwrap()
        .without_theta_sampling()
        .unwrap();
    assert_eq!(bits(&particle), bits(&sub));
}

#[test]
fn lookups_outside_the_kept_rows_are_refused() {
    let full = full();
    let interval = RhoInterval::new(0.6, 0.7).unwrap();
    let rows = rows_for(full.axes().rho(), interval).unwrap();
    let sub = full.subset_rows(rows).unwrap();
    let axis = sub.axes().rho().as_slice();
    let (first, last) = (axis[0], axis[axis.len() - 1]);
    let v = sub.view();
    for rho in [first - 1e-6, last + 1e-6, 0.0, 1.0, f64::NAN] {
        assert_eq!(v.eval(rho, 0.3, 1.0, 0.0), None, "rho {rho}");
        assert_eq!(v.effective_albedo(rho, 0.3), None, "rho {rho}");
        assert_eq!(v.sample(rho, 0.3, 0.5, 0.5), None, "rho {rho}");
        assert_eq!(v.pdf(rho, 0.3, 1.0, 0.0), 0.0, "rho {rho}");
        assert_eq!(v.sample_path(rho, [0.5; 4]), None, "rho {rho}");
    }
}

/// Negative control: dropping the outer neighbour on the low side changes the first segment's
/// end slope, so the identity check above would catch a subset that keeps too few rows.
#[test]
fn one_neighbour_too_few_changes_the_values() {
    let full = full();
    let interval = RhoInterval::new(0.6, 0.7).unwrap();
    let rows = rows_for(full.axes().rho(), interval).unwrap();
    let short = full.subset_rows(rows.start + 1..rows.end).unwrap();
    let (f, s) = (full.view(), short.view());
    let mut rng = SplitMix64::seed_from_u64(3);
    let differs = (0..200).any(|_| {
        let rho = 0.6 + 0.1 * rng.next_f64();
        let (theta, r) = (1.0 * rng.next_f64(), 0.5 + rng.next_f64());
        opt_bits(f.eval(rho, theta, r, 0.0)) != opt_bits(s.eval(rho, theta, r, 0.0))
    });
    assert!(
        differs,
        "a subset without the outer neighbour gave identical bits"
    );
}

#[test]
fn bad_row_ranges_are_errors_not_panics() {
    let full = full();
    let n = full.axes().rho().as_slice().len();
    #[allow(clippy::reversed_empty_ranges)]
    let reversed = 7..3;
    for rows in [0..1, 5..5, n - 1..n + 1, reversed] {
        let err = full.subset_rows(rows.clone()).unwrap_err();
        assert!(err.to_string().contains("albedo rows"), "{rows:?}: {err}");
        assert!(grid().rho_rows(rows).is_err());
    }
    assert!(AngularTable::concat_rows(&[]).is_err());
    let a = full.subset_rows(0..4).unwrap();
    // Rows that do not increase across the parts.
    assert!(AngularTable::concat_rows(&[a.clone(), a]).is_err());
}

/// A two-lobe table keeps its rule of rebuilding the lobes (format 1.4, bit 4) through every
/// subset, and tables of both rules are not joined: the same harmonics read by the two rules
/// are two profiles.
#[test]
fn subsets_keep_the_rule_of_the_rebuild() {
    use bssrdf_zoo::gwc::Rebuild;
    use bssrdf_zoo::table::Lobes;
    let grid = GridPreset::Coarse.grid(1.2, Lobes::Two);
    let merged = bssrdf_zoo::table::bake_lobes(1.2, Moments::Exact, &grid, true, Lobes::Two)
        .unwrap()
        .0;
    let n = merged.axes().rho().as_slice().len();
    let copy = merged
        .subset_rows(0..n)
        .unwrap()
        .without_theta_sampling()
        .unwrap();
    assert_eq!(copy.rebuild(), Rebuild::MergedRoots);
    // The same table read as a file without bit 4 reads it
    let roots = AngularTable::from_parts(
        copy.eta(),
        copy.moments(),
        copy.axes().clone(),
        copy.params().to_vec(),
        copy.radial_cdf().to_vec(),
        None,
    )
    .unwrap()
    .with_harmonics_by(copy.harmonics().unwrap().to_vec(), Rebuild::Roots)
    .unwrap();
    for part in cut_three_ways(&roots) {
        assert_eq!(part.rebuild(), Rebuild::Roots);
        assert_eq!(part.view().rebuild(), Rebuild::Roots);
    }
    let plain = merged.without_theta_sampling().unwrap();
    let err = AngularTable::concat_rows(&[
        roots.subset_rows(0..n / 2).unwrap(),
        plain.subset_rows(n / 2..n).unwrap(),
    ])
    .unwrap_err();
    assert!(err.to_string().contains("rebuild"), "{err}");
}

/// A table of the walk (a walk-angular table in a file, format 1.5) keeps its walk through
/// every subset, and tables of different walks, or of the walk and of PBD, are not joined.
#[test]
fn subsets_keep_the_walk() {
    use bssrdf_zoo::format::{ModelKind, WalkComponent, WalkSource};
    let walk = WalkSource {
        g: 0.5,
        component: WalkComponent::Multiple,
    };
    let n = full().axes().rho().as_slice().len();
    let marked = full().clone().with_walk(walk);
    for part in cut_three_ways(&marked) {
        assert_eq!(part.walk(), Some(walk));
        let data = part.to_table_data();
        assert_eq!(
            (data.model, data.walk),
            (ModelKind::WalkAngular, Some(walk))
        );
    }
    let other = full().clone().with_walk(WalkSource { g: 0.25, ..walk });
    for high in [other, full().clone()] {
        let err = AngularTable::concat_rows(&[
            marked.subset_rows(0..n / 2).unwrap(),
            high.subset_rows(n / 2..n).unwrap(),
        ])
        .unwrap_err();
        assert!(err.to_string().contains("walk"), "{err}");
    }
}

/// A table whose nodes hold the profile less the ridge keeps its flag through every subset, in
/// its views and in the file it is written to; tables with and without it are not joined.
#[test]
fn subsets_keep_the_ridge() {
    use bssrdf_zoo::format::{
        Compression, Library, LibraryBuilder, Verify, WalkComponent, WalkSource,
    };
    use bssrdf_zoo::table::FileTable;
    let n = full().axes().rho().as_slice().len();
    let walk = WalkSource {
        g: 0.5,
        component: WalkComponent::Total,
    };
    for marked in [
        full().clone().with_ridge(RidgeKind::Flux),
        full().clone().with_ridge(RidgeKind::NEWEST).with_walk(walk),
    ] {
        for part in cut_three_ways(&marked) {
            assert_eq!(
                (part.ridge(), part.view().ridge()),
                (marked.ridge(), marked.ridge())
            );
            assert_eq!(part.walk(), marked.walk());
            let data = part.to_table_data();
            assert_eq!(data.ridge, marked.ridge());
            // A walk-angular table needs two lobes to be written; this one has one
            if part.walk().is_some() {
                continue;
            }
            let mut builder = LibraryBuilder::new();
            builder.add_table(data).unwrap();
            let bytes = builder.to_bytes(Compression::None).unwrap();
            let library = Library::from_bytes(&bytes, Verify::Full).unwrap();
            let read = FileTable::new(library.table(0).unwrap()).unwrap();
            assert_eq!(read.view().unwrap().ridge(), marked.ridge());
            assert_eq!(read.to_owned_table().unwrap(), part);
        }
    }
    // Parts of different kinds do not join: not with and without, nor the flux part with the
    // ridge with its fluence part
    for (a, b) in [
        (RidgeKind::NEWEST, RidgeKind::None),
        (RidgeKind::Flux, RidgeKind::FluxAndFluence),
    ] {
        let err = AngularTable::concat_rows(&[
            full().clone().with_ridge(a).subset_rows(0..n / 2).unwrap(),
            full().clone().with_ridge(b).subset_rows(n / 2..n).unwrap(),
        ])
        .unwrap_err();
        assert!(err.to_string().contains("ridge kind"), "{err}");
    }
}

/// The tables cut from `table` by each subset operation: its first half of the albedo rows,
/// itself without θ sampling, and its two halves joined again.
fn cut_three_ways(table: &AngularTable) -> [AngularTable; 3] {
    let n = table.axes().dims().0;
    [
        table.subset_rows(0..n / 2).unwrap(),
        table.without_theta_sampling().unwrap(),
        AngularTable::concat_rows(&[
            table.subset_rows(0..n / 2).unwrap(),
            table.subset_rows(n / 2..n).unwrap(),
        ])
        .unwrap(),
    ]
}
