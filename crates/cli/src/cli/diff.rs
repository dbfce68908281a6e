//! `bssrdf diff A B`: compares two library files. Metadata (tables, axes, sections, materials)
//! must match; per paired table, every section is compared value by value on the axis nodes
//! both tables hold (so a scene bake can be checked against a full one), with the max and mean
//! absolute and relative differences and where the max is. Provenance and compression are
//! reported, never compared.
//!
//! Exit status: 0 when the metadata match and every value agrees within tolerance, 1 when not,
//! 2 for a missing or invalid file or a bad option. Values a and b agree when
//! |a − b| ≤ max(abs_tolerance, tolerance·max(|a|, |b|)); both default to 0 (bit-equal values).

use super::CliError;
use bssrdf_zoo::format::{AxisKind, Library, Table};
use clap::Args;
use serde_json::{json, Value};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Args)]
pub struct DiffArgs {
    /// First library file.
    a: PathBuf,
    /// Second library file.
    b: PathBuf,
    /// Relative tolerance: values agree when |a − b| ≤ max(ABS, T·max(|a|, |b|)).
    #[arg(long, value_name = "T", default_value_t = 0.0)]
    tolerance: f64,
    /// Absolute tolerance (see --tolerance).
    #[arg(long, value_name = "ABS", default_value_t = 0.0)]
    abs_tolerance: f64,
    /// One JSON object on stdout instead of the report.
    #[arg(long)]
    json: bool,
    /// Map the files instead of reading them into memory (see `eval --mmap`).
    #[arg(long)]
    mmap: bool,
}

/// One metadata difference: what, and its value in each file (null where absent).
struct Difference {
    item: String,
    field: &'static str,
    a: Value,
    b: Value,
}

impl Difference {
    fn json(&self) -> Value {
        json!({"item": self.item, "field": self.field, "a": self.a, "b": self.b})
    }
}

/// Statistics of one section over the common nodes.
struct SectionStats {
    name: &'static str,
    count: usize,
    sum_abs: f64,
    sum_rel: f64,
    max_abs: (f64, Location),
    max_rel: (f64, Location),
    outside: usize,
}

/// Where an element is: indices in A and in B, and its axis values.
#[derive(Clone, Copy, Default)]
struct Location {
    a: [usize; 3],
    b: [usize; 3],
    values: [f64; 3],
    a_value: f64,
    b_value: f64,
}

impl Location {
    fn json(&self, dims: usize) -> Value {
        let mut at = json!({
            "index_a": &self.a[..dims], "index_b": &self.b[..dims],
            "rho": self.values[0], "theta_deg": self.values[1].to_degrees(),
            "a": self.a_value, "b": self.b_value,
        });
        if dims == 3 {
            at["r"] = json!(self.values[2]);
        }
        at
    }
    fn text(&self, dims: usize) -> String {
        let idx = |i: &[usize]| {
            i[..dims]
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(",")
        };
        let r = if dims == 3 {
            format!(", r {}", self.values[2])
        } else {
            String::new()
        };
        format!(
            "[{}]/[{}] rho {}, theta {:.4} deg{r}: {:e} vs {:e}",
            idx(&self.a),
            idx(&self.b),
            self.values[0],
            self.values[1].to_degrees(),
            self.a_value,
            self.b_value
        )
    }
}

impl SectionStats {
    fn new(name: &'static str) -> Self {
        Self {
            name,
            count: 0,
            sum_abs: 0.0,
            sum_rel: 0.0,
            max_abs: (-1.0, Location::default()),
            max_rel: (-1.0, Location::default()),
            outside: 0,
        }
    }
    fn add(&mut self, a: f32, b: f32, at: Location, tol: (f64, f64)) {
        let (a, b) = (f64::from(a), f64::from(b));
        let abs = (a - b).abs();
        let scale = a.abs().max(b.abs());
        let rel = if abs == 0.0 { 0.0 } else { abs / scale };
        let at = Location {
            a_value: a,
            b_value: b,
            ..at
        };
        self.count += 1;
        self.sum_abs += abs;
        self.sum_rel += rel;
        if abs > self.max_abs.0 {
            self.max_abs = (abs, at);
        }
        if rel > self.max_rel.0 {
            self.max_rel = (rel, at);
        }
        if abs > tol.1.max(tol.0 * scale) {
            self.outside += 1;
        }
    }
    fn mean(&self, sum: f64) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            sum / self.count as f64
        }
    }
    fn dims(&self) -> usize {
        if self.name == "theta-cdf" {
            2
        } else {
            3
        }
    }
    fn json(&self) -> Value {
        json!({
            "section": self.name, "count": self.count,
            "max_abs": self.max_abs.0.max(0.0), "mean_abs": self.mean(self.sum_abs),
            "max_rel": self.max_rel.0.max(0.0), "mean_rel": self.mean(self.sum_rel),
            "max_abs_at": (self.count > 0).then(|| self.max_abs.1.json(self.dims())),
            "max_rel_at": (self.count > 0).then(|| self.max_rel.1.json(self.dims())),
            "outside_tolerance": self.outside,
        })
    }
}

/// Index pairs of the nodes two axes share (equal f32 values).
fn common(a: &[f32], b: &[f32]) -> Vec<(usize, usize)> {
    let (mut i, mut j, mut out) = (0, 0, Vec::new());
    while i < a.len() && j < b.len() {
        match a[i].total_cmp(&b[j]) {
            std::cmp::Ordering::Equal => {
                out.push((i, j));
                i += 1;
                j += 1;
            }
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
        }
    }
    out
}

/// Compares one pair of tables: metadata into `diffs`, values into section statistics.
fn compare_tables(
    ta: &Table<'_>,
    tb: &Table<'_>,
    tol: (f64, f64),
    diffs: &mut Vec<Difference>,
) -> Value {
    let item = format!("table {} / {}", ta.index(), tb.index());
    let mut differ = |field, a: Value, b: Value| {
        if a != b {
            diffs.push(Difference {
                item: item.clone(),
                field,
                a,
                b,
            });
        }
    };
    differ(
        "fresnel_moments",
        json!(super::inspect::fresnel_name(ta.fresnel())),
        json!(super::inspect::fresnel_name(tb.fresnel())),
    );
    differ("dims", json!(ta.dims()), json!(tb.dims()));
    for (kind, field) in [
        (AxisKind::Rho, "axis-rho"),
        (AxisKind::Theta, "axis-theta"),
        (AxisKind::R, "axis-r"),
    ] {
        let (a, b) = (ta.axis(kind), tb.axis(kind));
        if a != b {
            let summary =
                |v: &[f32]| json!({"nodes": v.len(), "first": v.first(), "last": v.last()});
            differ(field, summary(a), summary(b));
        }
    }
    differ(
        "theta-cdf",
        json!(ta.theta_cdf().is_some()),
        json!(tb.theta_cdf().is_some()),
    );
    let lobes = |t: &bssrdf_zoo::format::Table| if t.harmonics().is_some() { 2 } else { 1 };
    differ("lobes", json!(lobes(ta)), json!(lobes(tb)));
    let axes = [AxisKind::Rho, AxisKind::Theta, AxisKind::R];
    let [ci, cj, ck] = axes.map(|k| common(ta.axis(k), tb.axis(k)));
    let [_, nta, nra] = ta.dims();
    let [_, ntb, nrb] = tb.dims();
    let value = |k: AxisKind, i: usize| f64::from(ta.axis(k).get(i).copied().unwrap_or(f32::NAN));
    let mut sections = [
        SectionStats::new("gwc-params E"),
        SectionStats::new("gwc-params E_beta"),
        SectionStats::new("gwc-params c"),
        SectionStats::new("radial-cdf"),
    ];
    let mut theta_cdf = SectionStats::new("theta-cdf");
    let mut harmonics = [
        SectionStats::new("gwc-harmonics r*mu3"),
        SectionStats::new("gwc-harmonics r*mu4"),
    ];
    let (ga, gb) = (ta.gwc_params(), tb.gwc_params());
    let (ra, rb) = (ta.radial_cdf(), tb.radial_cdf());
    for &(ia, ib) in &ci {
        for &(ja, jb) in &cj {
            for &(ka, kb) in &ck {
                let na = (ia * nta + ja) * nra + ka;
                let nb = (ib * ntb + jb) * nrb + kb;
                let at = Location {
                    a: [ia, ja, ka],
                    b: [ib, jb, kb],
                    values: [
                        value(AxisKind::Rho, ia),
                        value(AxisKind::Theta, ja),
                        value(AxisKind::R, ka),
                    ],
                    ..Location::default()
                };
                for (p, stats) in sections.iter_mut().take(3).enumerate() {
                    if let (Some(&x), Some(&y)) = (ga.get(3 * na + p), gb.get(3 * nb + p)) {
                        stats.add(x, y, at, tol);
                    }
                }
                if let (Some(&x), Some(&y)) = (ra.get(na), rb.get(nb)) {
                    sections[3].add(x, y, at, tol);
                }
                if let (Some(ha), Some(hb)) = (ta.harmonics(), tb.harmonics()) {
                    for (p, stats) in harmonics.iter_mut().enumerate() {
                        if let (Some(&x), Some(&y)) = (ha.get(2 * na + p), hb.get(2 * nb + p)) {
                            stats.add(x, y, at, tol);
                        }
                    }
                }
            }
            if let (Some(a), Some(b)) = (ta.theta_cdf(), tb.theta_cdf()) {
                if let (Some(&x), Some(&y)) = (a.get(ia * nta + ja), b.get(ib * ntb + jb)) {
                    let at = Location {
                        a: [ia, ja, 0],
                        b: [ib, jb, 0],
                        values: [value(AxisKind::Rho, ia), value(AxisKind::Theta, ja), 0.0],
                        ..Location::default()
                    };
                    theta_cdf.add(x, y, at, tol);
                }
            }
        }
    }
    let mut all: Vec<&SectionStats> = sections.iter().collect();
    if theta_cdf.count > 0 {
        all.push(&theta_cdf);
    }
    all.extend(harmonics.iter().filter(|s| s.count > 0));
    let outside: usize = all.iter().map(|s| s.outside).sum();
    json!({
        "a": ta.index(), "b": tb.index(), "eta": ta.eta(),
        "common_dims": [ci.len(), cj.len(), ck.len()],
        "values_compared": all.iter().map(|s| s.count).sum::<usize>(),
        "outside_tolerance": outside,
        "sections": all.iter().map(|s| s.json()).collect::<Vec<_>>(),
        "text": all.iter().map(|s| section_text(s)).collect::<Vec<_>>(),
    })
}

fn section_text(s: &SectionStats) -> String {
    if s.count == 0 {
        return format!("  {:<18} no common nodes", s.name);
    }
    let mut text = format!(
        "  {:<18} max abs {:<10.3e} mean abs {:<10.3e} max rel {:<10.3e} mean rel {:<10.3e} {} outside",
        s.name,
        s.max_abs.0,
        s.mean(s.sum_abs),
        s.max_rel.0,
        s.mean(s.sum_rel),
        s.outside,
    );
    if s.max_abs.0 > 0.0 {
        text += &format!("\n      max abs at {}", s.max_abs.1.text(s.dims()));
        text += &format!("\n      max rel at {}", s.max_rel.1.text(s.dims()));
    }
    text
}

/// Pairs each table of A with a table of B of the same model, η and Fresnel moments: the
/// same index if possible, else the one sharing the most albedo nodes (several tables of a
/// scene bake may pair with one full table). Returns the pairs, the tables of A without a
/// counterpart and the tables of B no table of A paired with.
fn pair_tables(a: &Library, b: &Library) -> (Vec<(usize, usize)>, Vec<usize>, Vec<usize>) {
    let key = |t: &Table<'_>| (t.model(), t.eta().to_bits(), t.fresnel());
    let mut used = vec![false; b.table_count()];
    let (mut pairs, mut only_a) = (Vec::new(), Vec::new());
    for ta in a.tables() {
        let candidates: Vec<Table<'_>> = b.tables().filter(|tb| key(tb) == key(&ta)).collect();
        let shared = |tb: &Table<'_>| common(ta.axis(AxisKind::Rho), tb.axis(AxisKind::Rho)).len();
        let best = candidates
            .iter()
            .find(|tb| tb.index() == ta.index() && shared(tb) > 0)
            .or_else(|| {
                candidates
                    .iter()
                    .max_by_key(|tb| (shared(tb), usize::MAX - tb.index()))
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

fn compare_materials(a: &Library, b: &Library, diffs: &mut Vec<Difference>) {
    for ma in a.materials() {
        let Some(mb) = b.material(&ma.name) else {
            diffs.push(Difference {
                item: format!("material {}", ma.name),
                field: "present",
                a: json!(true),
                b: json!(false),
            });
            continue;
        };
        let range = |m: &bssrdf_zoo::format::Material| {
            m.albedo_range.map(|r| json!({"min": r.min, "max": r.max}))
        };
        let fields = [
            ("source", json!(ma.source), json!(mb.source)),
            ("sigma_s", json!(ma.sigma_s), json!(mb.sigma_s)),
            ("sigma_a", json!(ma.sigma_a), json!(mb.sigma_a)),
            ("g", json!(ma.g), json!(mb.g)),
            ("eta", json!(ma.eta), json!(mb.eta)),
            ("tables", json!(ma.tables), json!(mb.tables)),
            ("albedo_range", json!(range(ma)), json!(range(mb))),
        ];
        for (field, x, y) in fields {
            if x != y {
                diffs.push(Difference {
                    item: format!("material {}", ma.name),
                    field,
                    a: x,
                    b: y,
                });
            }
        }
    }
    for mb in b.materials() {
        if a.material(&mb.name).is_none() {
            diffs.push(Difference {
                item: format!("material {}", mb.name),
                field: "present",
                a: json!(false),
                b: json!(true),
            });
        }
    }
}

/// Provenance keys that differ (reported, not compared), and the compression flag.
fn information(a: &Library, b: &Library) -> Vec<Difference> {
    let mut out = Vec::new();
    let fields = |l: &Library| -> serde_json::Map<String, Value> {
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
    for key in keys {
        let (x, y) = (pa.get(key), pb.get(key));
        if x != y {
            out.push(Difference {
                item: format!("provenance {key}"),
                field: "value",
                a: x.cloned().unwrap_or(Value::Null),
                b: y.cloned().unwrap_or(Value::Null),
            });
        }
    }
    if a.is_compressed() != b.is_compressed() {
        out.push(Difference {
            item: "file".into(),
            field: "compressed",
            a: json!(a.is_compressed()),
            b: json!(b.is_compressed()),
        });
    }
    out
}

pub fn run(args: DiffArgs) -> Result<ExitCode, CliError> {
    for (name, value) in [
        ("tolerance", args.tolerance),
        ("abs-tolerance", args.abs_tolerance),
    ] {
        super::check_range(&format!("--{name}"), value, 0.0..)?;
    }
    let a = super::library::open(&args.a, args.mmap)?;
    let b = super::library::open(&args.b, args.mmap)?;
    let tol = (args.tolerance, args.abs_tolerance);
    let mut diffs = Vec::new();
    let (pairs, only_a, only_b) = pair_tables(&a, &b);
    for (list, side) in [(&only_a, "a"), (&only_b, "b")] {
        for &i in list.iter() {
            let t = if side == "a" { a.table(i) } else { b.table(i) };
            let eta = t.map(|t| t.eta());
            diffs.push(Difference {
                item: format!("table {i} of {}", side.to_uppercase()),
                field: "counterpart",
                a: if side == "a" { json!(eta) } else { Value::Null },
                b: if side == "b" { json!(eta) } else { Value::Null },
            });
        }
    }
    if a.table_count() != b.table_count() {
        diffs.push(Difference {
            item: "file".into(),
            field: "tables",
            a: json!(a.table_count()),
            b: json!(b.table_count()),
        });
    }
    let mut tables = Vec::new();
    for (i, j) in pairs {
        if let (Some(ta), Some(tb)) = (a.table(i), b.table(j)) {
            tables.push(compare_tables(&ta, &tb, tol, &mut diffs));
        }
    }
    compare_materials(&a, &b, &mut diffs);
    let info = information(&a, &b);
    let outside: u64 = tables
        .iter()
        .filter_map(|t| t["outside_tolerance"].as_u64())
        .sum();
    let within = diffs.is_empty() && outside == 0;
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if args.json {
        let tables: Vec<Value> = tables
            .into_iter()
            .map(|mut t| {
                if let Some(map) = t.as_object_mut() {
                    map.remove("text");
                }
                t
            })
            .collect();
        let json = json!({
            "a": args.a.display().to_string(), "b": args.b.display().to_string(),
            "tolerance": args.tolerance, "abs_tolerance": args.abs_tolerance,
            "within_tolerance": within,
            "differences": diffs.iter().map(Difference::json).collect::<Vec<_>>(),
            "not_compared": info.iter().map(Difference::json).collect::<Vec<_>>(),
            "tables": tables,
        });
        writeln!(out, "{json}")?;
    } else {
        writeln!(
            out,
            "A: {} ({} table(s), {} material(s))\nB: {} ({} table(s), {} material(s))",
            args.a.display(),
            a.table_count(),
            a.materials().len(),
            args.b.display(),
            b.table_count(),
            b.materials().len()
        )?;
        if diffs.is_empty() {
            writeln!(out, "metadata: identical")?;
        } else {
            writeln!(out, "metadata: {} difference(s)", diffs.len())?;
            for d in &diffs {
                writeln!(out, "  {} {}: {} vs {}", d.item, d.field, d.a, d.b)?;
            }
        }
        if !info.is_empty() {
            let items: Vec<String> = info
                .iter()
                .map(|d| format!("{} {}", d.item, d.field))
                .collect();
            writeln!(out, "not compared, differ: {}", items.join(", "))?;
        }
        for t in &tables {
            writeln!(
                out,
                "table {} (A) vs {} (B), eta {}: {} values on {} common nodes",
                t["a"], t["b"], t["eta"], t["values_compared"], t["common_dims"]
            )?;
            for line in t["text"].as_array().into_iter().flatten() {
                writeln!(out, "{}", line.as_str().unwrap_or_default())?;
            }
        }
        writeln!(
            out,
            "{} (tolerance {} relative, {} absolute; {} value(s) outside)",
            if within {
                "within tolerance"
            } else {
                "DIFFERENT"
            },
            args.tolerance,
            args.abs_tolerance,
            outside
        )?;
    }
    out.flush()?;
    Ok(if within {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
