//! Comparing two library files: what `bssrdf diff` reports, as a typed report a front end can
//! print or test.
//!
//! [`compare`] pairs each table of A with a table of B of the same η and Fresnel moments (one
//! of the same model, walk and ridge kind if there is one, then the same index if possible,
//! else the one sharing the most albedo nodes, so several tables of a scene bake may pair with
//! one full table), and reports
//! - the metadata differences ([`Difference`]): tables without a counterpart, the table count,
//!   per pair its model, the walk's g and component, the ridge kind, Fresnel moments, dims,
//!   each axis, the θ-sampling section and the number of lobes; per material its presence and
//!   every field;
//! - per pair of tables ([`TableDiff`]), for each compared quantity ([`Quantity`]: E, E_β and c
//!   of `gwc-params`, `radial-cdf`, `theta-cdf`, rμ₃ and rμ₄ of `gwc-harmonics`) over the axis
//!   nodes both tables hold (equal f32 values), the count, the max and mean absolute and
//!   relative differences, where each max is ([`Location`]) and how many values lie outside the
//!   [`Tolerance`];
//! - what differs but is never compared: provenance keys and compression.
//!
//! The relative difference of a and b is |a − b| / max(|a|, |b|) (0 when a = b); they agree
//! when |a − b| ≤ max(absolute, relative · max(|a|, |b|)) ([`Tolerance::agrees`]). Values are
//! compared in f64 from the stored f32.
//!
//! ```no_run
//! # use bssrdf_zoo::format::{diff, Library, Verify};
//! # fn demo() -> Result<(), Box<dyn std::error::Error>> {
//! let a = Library::read("scene.bssrdf", Verify::Full)?;
//! let b = Library::read("full.bssrdf", Verify::Full)?;
//! let report = diff::compare(&a, &b, diff::Tolerance::new(1e-6, 0.0)?);
//! for table in report.tables() {
//!     for q in table.quantities() {
//!         println!("{}: max rel {:e}", q.quantity().name(), q.max_rel());
//!     }
//! }
//! # Ok(()) }
//! ```

mod report;
#[cfg(test)]
mod tests;

use std::cmp::Ordering;

use serde_json::Value as Json;

use super::library::{Library, Table};
use super::records::Material;
use super::spec::AxisKind;

pub use report::{
    AxisSummary, Difference, Field, Item, LibraryDiff, Location, MetaValue, Quantity, QuantityDiff,
    Side, TableDiff, Tolerance, ToleranceError,
};

/// Compares library `a` with library `b`, values within `tolerance` (see the module's
/// documentation for what is compared and how tables are paired).
pub fn compare(a: &Library, b: &Library, tolerance: Tolerance) -> LibraryDiff {
    let mut differences = Vec::new();
    let (pairs, only_a, only_b) = pair_tables(a, b);
    for (side, library, list) in [(Side::A, a, &only_a), (Side::B, b, &only_b)] {
        for &table in list {
            let eta = library
                .table(table)
                .map_or(MetaValue::Absent, |t| MetaValue::Number(t.eta()));
            let (in_a, in_b) = match side {
                Side::A => (eta, MetaValue::Absent),
                Side::B => (MetaValue::Absent, eta),
            };
            differences.push(Difference {
                item: Item::Unpaired { side, table },
                field: Field::Counterpart,
                a: in_a,
                b: in_b,
            });
        }
    }
    if a.table_count() != b.table_count() {
        differences.push(Difference {
            item: Item::File,
            field: Field::Tables,
            a: MetaValue::Count(a.table_count()),
            b: MetaValue::Count(b.table_count()),
        });
    }
    let mut tables = Vec::new();
    for (i, j) in pairs {
        if let (Some(ta), Some(tb)) = (a.table(i), b.table(j)) {
            compare_table_fields(&ta, &tb, &mut differences);
            tables.push(compare_table_values(&ta, &tb, tolerance));
        }
    }
    compare_materials(a, b, &mut differences);
    LibraryDiff {
        tolerance,
        differences,
        not_compared: not_compared(a, b),
        tables,
    }
}

/// Index pairs of the nodes two increasing axes share (equal f32 values).
fn common(a: &[f32], b: &[f32]) -> Vec<(usize, usize)> {
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < a.len() && j < b.len() {
        match a[i].total_cmp(&b[j]) {
            Ordering::Equal => {
                out.push((i, j));
                i += 1;
                j += 1;
            }
            Ordering::Less => i += 1,
            Ordering::Greater => j += 1,
        }
    }
    out
}

/// Pairs each table of A with a table of B of the same η and Fresnel moments, among those of
/// the same model, walk (g, component) and ridge kind if there are any: the same index if they
/// share an albedo node, else the one sharing the most albedo nodes (the lowest index among
/// equals).
/// Returns the pairs, the tables of A without a counterpart and the tables of B no table of A
/// paired with.
fn pair_tables(a: &Library, b: &Library) -> (Vec<(usize, usize)>, Vec<usize>, Vec<usize>) {
    let key = |t: &Table<'_>| (t.eta().to_bits(), t.fresnel());
    let source = |t: &Table<'_>| {
        let walk = t.walk().map(|w| (w.g.to_bits(), w.component));
        (t.model(), walk, t.ridge())
    };
    let mut used = vec![false; b.table_count()];
    let (mut pairs, mut only_a) = (Vec::new(), Vec::new());
    for ta in a.tables() {
        let candidates: Vec<Table<'_>> = b.tables().filter(|tb| key(tb) == key(&ta)).collect();
        let shared = |tb: &Table<'_>| common(ta.axis(AxisKind::Rho), tb.axis(AxisKind::Rho)).len();
        let same = |tb: &Table<'_>| source(tb) == source(&ta);
        let best = candidates
            .iter()
            .find(|tb| same(tb) && tb.index() == ta.index() && shared(tb) > 0)
            .or_else(|| {
                candidates
                    .iter()
                    .max_by_key(|tb| (same(tb), shared(tb), usize::MAX - tb.index()))
            });
        match best {
            Some(tb) => {
                used[tb.index()] = true;
                pairs.push((ta.index(), tb.index()));
            }
            None => only_a.push(ta.index()),
        }
    }
    let only_b = (0..b.table_count()).filter(|&i| !used[i]).collect();
    (pairs, only_a, only_b)
}

/// Appends the metadata differences of a pair of tables: model, the walk's g and component,
/// the ridge kind, Fresnel moments, dims, each axis (when its node count, first or last node
/// differ), θ-sampling and lobes.
fn compare_table_fields(ta: &Table<'_>, tb: &Table<'_>, differences: &mut Vec<Difference>) {
    let item = Item::Tables {
        a: ta.index(),
        b: tb.index(),
    };
    let mut differ = |field, a: MetaValue, b: MetaValue| {
        if a != b {
            differences.push(Difference {
                item: item.clone(),
                field,
                a,
                b,
            });
        }
    };
    let model = |t: &Table<'_>| MetaValue::Text(t.model().name().to_owned());
    differ(Field::Model, model(ta), model(tb));
    let walk_g = |t: &Table<'_>| {
        t.walk()
            .map_or(MetaValue::Absent, |w| MetaValue::Number(w.g))
    };
    differ(Field::WalkG, walk_g(ta), walk_g(tb));
    let component = |t: &Table<'_>| {
        t.walk().map_or(MetaValue::Absent, |w| {
            MetaValue::Text(w.component.name().to_owned())
        })
    };
    differ(Field::WalkComponent, component(ta), component(tb));
    differ(
        Field::Ridge,
        MetaValue::Text(ta.ridge().name().to_owned()),
        MetaValue::Text(tb.ridge().name().to_owned()),
    );
    differ(
        Field::FresnelMoments,
        MetaValue::Fresnel(ta.fresnel()),
        MetaValue::Fresnel(tb.fresnel()),
    );
    differ(
        Field::Dims,
        MetaValue::Dims(ta.dims()),
        MetaValue::Dims(tb.dims()),
    );
    for kind in [AxisKind::Rho, AxisKind::Theta, AxisKind::R] {
        let (a, b) = (ta.axis(kind), tb.axis(kind));
        if a != b {
            let summary = |axis| MetaValue::Axis(AxisSummary::of(axis));
            differ(Field::Axis(kind), summary(a), summary(b));
        }
    }
    differ(
        Field::ThetaCdf,
        MetaValue::Bool(ta.theta_cdf().is_some()),
        MetaValue::Bool(tb.theta_cdf().is_some()),
    );
    let lobes = |t: &Table<'_>| MetaValue::Count(if t.harmonics().is_some() { 2 } else { 1 });
    differ(Field::Lobes, lobes(ta), lobes(tb));
    // The same harmonics read by two rules are two profiles (format 1.4, bit 4)
    if ta.harmonics().is_some() && tb.harmonics().is_some() {
        let rebuild = |t: &Table<'_>| MetaValue::Text(t.rebuild().name().to_owned());
        differ(Field::Rebuild, rebuild(ta), rebuild(tb));
    }
}

/// Compares every section of a pair of tables value by value on the nodes both hold.
fn compare_table_values(ta: &Table<'_>, tb: &Table<'_>, tolerance: Tolerance) -> TableDiff {
    let [ci, cj, ck] =
        [AxisKind::Rho, AxisKind::Theta, AxisKind::R].map(|k| common(ta.axis(k), tb.axis(k)));
    let [_, nta, nra] = ta.dims();
    let [_, ntb, nrb] = tb.dims();
    let value = |k: AxisKind, i: usize| f64::from(ta.axis(k).get(i).copied().unwrap_or(f32::NAN));
    let mut params = [Quantity::GwcE, Quantity::GwcEBeta, Quantity::GwcC].map(QuantityDiff::new);
    let mut radial = QuantityDiff::new(Quantity::RadialCdf);
    let mut theta_cdf = QuantityDiff::new(Quantity::ThetaCdf);
    let mut harmonics = [Quantity::HarmonicMu3, Quantity::HarmonicMu4].map(QuantityDiff::new);
    let (ga, gb) = (ta.gwc_params(), tb.gwc_params());
    let (ra, rb) = (ta.radial_cdf(), tb.radial_cdf());
    for &(ia, ib) in &ci {
        for &(ja, jb) in &cj {
            for &(ka, kb) in &ck {
                // Flat node indices, row-major (ρ′, θ, r).
                let na = (ia * nta + ja) * nra + ka;
                let nb = (ib * ntb + jb) * nrb + kb;
                let at = Location {
                    index_a: [ia, ja, ka],
                    index_b: [ib, jb, kb],
                    rho: value(AxisKind::Rho, ia),
                    theta: value(AxisKind::Theta, ja),
                    r: value(AxisKind::R, ka),
                    ..Location::default()
                };
                for (p, stats) in params.iter_mut().enumerate() {
                    if let (Some(&x), Some(&y)) = (ga.get(3 * na + p), gb.get(3 * nb + p)) {
                        stats.add(x, y, at, tolerance);
                    }
                }
                if let (Some(&x), Some(&y)) = (ra.get(na), rb.get(nb)) {
                    radial.add(x, y, at, tolerance);
                }
                if let (Some(ha), Some(hb)) = (ta.harmonics(), tb.harmonics()) {
                    for (p, stats) in harmonics.iter_mut().enumerate() {
                        if let (Some(&x), Some(&y)) = (ha.get(2 * na + p), hb.get(2 * nb + p)) {
                            stats.add(x, y, at, tolerance);
                        }
                    }
                }
            }
            if let (Some(a), Some(b)) = (ta.theta_cdf(), tb.theta_cdf()) {
                if let (Some(&x), Some(&y)) = (a.get(ia * nta + ja), b.get(ib * ntb + jb)) {
                    let at = Location {
                        index_a: [ia, ja, 0],
                        index_b: [ib, jb, 0],
                        rho: value(AxisKind::Rho, ia),
                        theta: value(AxisKind::Theta, ja),
                        ..Location::default()
                    };
                    theta_cdf.add(x, y, at, tolerance);
                }
            }
        }
    }
    let mut quantities: Vec<QuantityDiff> = params.into_iter().collect();
    quantities.push(radial);
    quantities.extend(
        [theta_cdf]
            .into_iter()
            .chain(harmonics)
            .filter(|q| q.count() > 0),
    );
    TableDiff {
        a: ta.index(),
        b: tb.index(),
        eta: ta.eta(),
        common_dims: [ci.len(), cj.len(), ck.len()],
        quantities,
    }
}

/// Appends the material differences: per material of A, its absence from B or each field
/// that differs; then the materials only B has.
fn compare_materials(a: &Library, b: &Library, differences: &mut Vec<Difference>) {
    let present = |name: &str, in_a: bool| Difference {
        item: Item::Material(name.to_string()),
        field: Field::Present,
        a: MetaValue::Bool(in_a),
        b: MetaValue::Bool(!in_a),
    };
    for ma in a.materials() {
        let Some(mb) = b.material(&ma.name) else {
            differences.push(present(&ma.name, true));
            continue;
        };
        let fields = |m: &Material| {
            [
                (Field::Source, MetaValue::Text(m.source.clone())),
                (Field::SigmaS, MetaValue::PerChannel(m.sigma_s)),
                (Field::SigmaA, MetaValue::PerChannel(m.sigma_a)),
                (Field::G, MetaValue::PerChannel(m.g)),
                (Field::Eta, MetaValue::Number(m.eta)),
                (Field::Tables, MetaValue::TableIndices(m.tables)),
                (Field::AlbedoRange, MetaValue::AlbedoRange(m.albedo_range)),
            ]
        };
        for ((field, x), (_, y)) in fields(ma).into_iter().zip(fields(mb)) {
            if x != y {
                differences.push(Difference {
                    item: Item::Material(ma.name.clone()),
                    field,
                    a: x,
                    b: y,
                });
            }
        }
    }
    for mb in b.materials() {
        if a.material(&mb.name).is_none() {
            differences.push(present(&mb.name, false));
        }
    }
}

/// The provenance keys whose values differ (in key order), and the compression flag.
fn not_compared(a: &Library, b: &Library) -> Vec<Difference> {
    let fields = |l: &Library| -> serde_json::Map<String, Json> {
        l.provenance()
            .map(|p| {
                p.fields()
                    .map(|(k, v)| (k.to_string(), v.clone()))
                    .collect()
            })
            .unwrap_or_default()
    };
    let (pa, pb) = (fields(a), fields(b));
    let mut keys: Vec<&String> = pa.keys().chain(pb.keys()).collect();
    keys.sort();
    keys.dedup();
    let value = |v: Option<&Json>| v.map_or(MetaValue::Absent, |v| MetaValue::Json(v.clone()));
    let mut out: Vec<Difference> = keys
        .into_iter()
        .filter(|key| pa.get(*key) != pb.get(*key))
        .map(|key| Difference {
            item: Item::Provenance(key.clone()),
            field: Field::Value,
            a: value(pa.get(key)),
            b: value(pb.get(key)),
        })
        .collect();
    if a.is_compressed() != b.is_compressed() {
        out.push(Difference {
            item: Item::File,
            field: Field::Compressed,
            a: MetaValue::Bool(a.is_compressed()),
            b: MetaValue::Bool(b.is_compressed()),
        });
    }
    out
}
