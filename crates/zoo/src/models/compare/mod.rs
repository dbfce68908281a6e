//! Every model against the Monte Carlo walk: errors per model and case, evaluation time, and
//! the data for the plots ([`write_svgs`]).
//!
//! # What is compared
//! For each case (ρ′, θ) the walk runs once on the half-space with the unreduced albedo
//! a = ρ′/(1 − g + gρ′) at σt = 1; its lengths are converted to reduced units (×(1 − g a)) and
//! its densities accordingly (see [`super::mc`]); mirror bins (±φ) are averaged. Each model is
//! compared with the part of the transport it models ([`Model::component`]): the diffusion
//! models (dipole, directional dipole, PBD, tables) with the walk's multiple scattering,
//! Christensen–Burley and the Monte Carlo model with the total.
//!
//! A model's value in a bin is its **average over the bin** (3 × 3 Gauss–Legendre points in
//! (ln r, φ), weighted by area), because the walk's value is one; comparing with the value at
//! the bin centre would add the bin's curvature to the error.
//!
//! **Well resolved** bins ([`Resolution`]): walk value > 0, relative standard error below 5 %,
//! and the bin's reduced radial edges within [0.01, 20] mfp. Over those bins a row reports the
//! mean and the maximum of |model − walk|/walk. The total reflectance error compares the model's
//! effective albedo (closed form, or quadrature where it has none) with the walk's reflectance
//! of the same component (all exits, binned or not). Evaluation time is measured single-threaded
//! on the bin centres (the fastest of five rounds sharing [`CompareConfig::timing_seconds`]).
//!
//! The Monte Carlo model is an independent walk (seed + 1, same photons): its error is the noise
//! level of a walk of that size, the floor no model can be judged below.

mod svg;

pub use svg::write_svgs;

use super::mc::{McModel, McOptions};
use super::table::TableSource;
use super::{build, integrate_total, Model, ModelKind, Options, Params};
use crate::bake::BakeGrid;
use crate::error::{in_range, Result};
use crate::fresnel::Moments;
use crate::quadrature::GaussLegendre;
use crate::table::GridPreset;
use crate::walk::{self, Bins, Component};
use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Instant;

/// Which walk bins take part in the error statistics.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Resolution {
    /// Largest relative standard error of the walk's bin value.
    pub max_rel_stderr: f64,
    /// Smallest lower radial edge, reduced mfp.
    pub r_min: f64,
    /// Largest upper radial edge, reduced mfp.
    pub r_max: f64,
}

impl Default for Resolution {
    /// Relative stderr < 5 %, r within [0.01, 20] reduced mfp.
    fn default() -> Self {
        Self {
            max_rel_stderr: 0.05,
            r_min: 0.01,
            r_max: 20.0,
        }
    }
}

/// What to compare.
#[derive(Debug, Clone)]
pub struct CompareConfig {
    /// Relative index η.
    pub eta: f64,
    /// Henyey–Greenstein g of the walk (diffusion models see only ρ′).
    pub g: f64,
    /// Photons per walk.
    pub photons: u64,
    /// Seed of the reference walks (the Monte Carlo model uses seed + 1).
    pub seed: u64,
    /// (ρ′, θ in degrees) per case.
    pub cases: Vec<(f64, f64)>,
    /// Models to compare.
    pub models: Vec<ModelKind>,
    /// Fresnel moments of every model.
    pub moments: Moments,
    /// Walk bins (unreduced mean free paths).
    pub bins: Bins,
    /// Grid of the table bake (one bake per run, shared by `table` and `perpendicular`): a
    /// preset bakes the table `bssrdf bake --eta ETA --grid PRESET` makes.
    pub grid: BakeGrid,
    /// Dipole and Christensen–Burley options (the table and Monte Carlo options are set here).
    pub options: Options,
    /// Which bins count.
    pub resolution: Resolution,
    /// Give Christensen–Burley the walk's own total reflectance as its surface albedo A (the
    /// setting of the memo's fit, where A is the reference's albedo) instead of
    /// `options.burley.albedo`. Its total error is then 0 by construction; only the shape is
    /// tested.
    pub burley_albedo_from_walk: bool,
    /// Wall time of each model's timing (five rounds), seconds.
    pub timing_seconds: f64,
}

/// The default cases: ρ′ ∈ {0.5, 0.9, 0.99} × θ ∈ {0°, 60°, 89°}.
pub fn default_cases() -> Vec<(f64, f64)> {
    let mut cases = Vec::new();
    for rho in [0.5, 0.9, 0.99] {
        for theta in [0.0, 60.0, 89.0] {
            cases.push((rho, theta));
        }
    }
    cases
}

impl CompareConfig {
    /// The default comparison for η, g, photons and seed: every model but the walk table
    /// ([`ModelKind::self_contained`]; give it with `options.walk_table`), the default cases, exact
    /// moments, the walk's default bins, the default table grid.
    pub fn new(eta: f64, g: f64, photons: u64, seed: u64) -> Self {
        Self {
            eta,
            g,
            photons,
            seed,
            cases: default_cases(),
            models: ModelKind::self_contained(),
            moments: Moments::Exact,
            bins: Bins::default(),
            grid: BakeGrid::Preset(GridPreset::Default),
            options: Options::default(),
            resolution: Resolution::default(),
            burley_albedo_from_walk: false,
            timing_seconds: 0.05,
        }
    }
}

impl Default for CompareConfig {
    /// The default comparison at η = 1.33, g = 0, 10⁶ photons, seed 1.
    fn default() -> Self {
        Self::new(1.33, 0.0, 1_000_000, 1)
    }
}

/// One model in one case.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Row {
    /// Model name.
    pub model: ModelKind,
    /// ρ′.
    pub rho: f64,
    /// θ, degrees.
    pub theta_deg: f64,
    /// Walk component compared with: "single", "multiple" or "total".
    pub component: &'static str,
    /// Well-resolved bins used.
    pub bins: usize,
    /// Mean |model − walk|/walk over those bins.
    pub mean_rel_err: Option<f64>,
    /// Max of the same.
    pub max_rel_err: Option<f64>,
    /// The model's total ∫∫R dA.
    pub total_model: Option<f64>,
    /// The walk's reflectance of the component.
    pub total_walk: f64,
    /// Its standard error.
    pub total_walk_stderr: f64,
    /// (model − walk)/walk of the totals.
    pub total_rel_err: Option<f64>,
    /// Mean evaluation time on the bin centres, nanoseconds.
    pub ns_per_eval: Option<f64>,
    /// Why the row has no error figures: the model could not be built, or no bin of the
    /// walk was precise enough to compare with.
    pub note: Option<String>,
}

/// One point of a profile: the walk with its standard error and each model.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ProfilePoint {
    /// Bin edges along the profile's axis (reduced mfp, or degrees).
    pub lo: f64,
    /// Upper edge.
    pub hi: f64,
    /// Walk, multiple scattering.
    pub walk_multiple: f64,
    /// Its standard error.
    pub walk_multiple_stderr: f64,
    /// Walk, total.
    pub walk_total: f64,
    /// Its standard error.
    pub walk_total_stderr: f64,
    /// Model bin averages, in the order of [`Case::models`] (NaN where missing).
    pub models: Vec<f64>,
}

/// Per-case data for the plots.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Case {
    /// ρ′.
    pub rho: f64,
    /// θ, degrees.
    pub theta_deg: f64,
    /// Unreduced albedo the walk ran with.
    pub albedo: f64,
    /// Models in [`ProfilePoint::models`] order.
    pub models: Vec<ModelKind>,
    /// Walk reflectances (single, multiple, total) with standard errors.
    pub walk_reflectance: [(f64, f64); 3],
    /// Azimuthal average against r (reduced mfp): one point per radial bin past the first.
    pub radial: Vec<ProfilePoint>,
    /// Reduced radial edges of the azimuthal profile's shell (the bin nearest r = 1).
    pub azimuthal_shell: (f64, f64),
    /// Against φ (degrees, 0 forward) on that shell.
    pub azimuthal: Vec<ProfilePoint>,
}

/// The whole comparison.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CompareReport {
    /// η.
    pub eta: f64,
    /// g.
    pub g: f64,
    /// Photons per walk.
    pub photons: u64,
    /// Seed.
    pub seed: u64,
    /// Fresnel moments.
    pub moments: Moments,
    /// The well-resolved rule.
    pub resolution: Resolution,
    /// One row per model and case, cases outer.
    pub rows: Vec<Row>,
    /// Plot data per case.
    pub cases: Vec<Case>,
}

/// Name of a walk component.
pub fn component_name(c: Component) -> &'static str {
    match c {
        Component::Unscattered => "unscattered",
        Component::Single => "single",
        Component::Multiple => "multiple",
        Component::Total => "total",
    }
}

/// Runs the comparison (walks in parallel on the current rayon pool; timing on this thread).
pub fn run(config: &CompareConfig) -> Result<CompareReport> {
    run_with_progress(config, &|_| {})
}

/// Steps [`run_with_progress`] reports: per case, its reference walk and each model.
pub fn progress_steps(config: &CompareConfig) -> u64 {
    (config.cases.len() * (1 + config.models.len())) as u64
}

/// [`run`], calling `progress(1)` after each of the [`progress_steps`] steps.
pub fn run_with_progress(config: &CompareConfig, progress: &dyn Fn(u64)) -> Result<CompareReport> {
    let mut options = config.options.clone();
    if config
        .models
        .iter()
        .any(|k| matches!(k, ModelKind::Table | ModelKind::Perpendicular))
    {
        let source = TableSource::Bake(config.grid.clone());
        let params = Params::new(0.5, config.eta, config.moments)?;
        options.table = TableSource::Shared(source.table(&params)?);
    }
    let mut rows = Vec::new();
    let mut cases = Vec::new();
    for &(rho, theta_deg) in &config.cases {
        in_range("theta (degrees)", theta_deg, 0.0, 90.0)?;
        let params = Params::new(rho, config.eta, config.moments)?.with_g(config.g)?;
        let (case, case_rows) = run_case(config, &options, &params, theta_deg, progress)?;
        rows.extend(case_rows);
        cases.push(case);
    }
    Ok(CompareReport {
        eta: config.eta,
        g: config.g,
        photons: config.photons,
        seed: config.seed,
        moments: config.moments,
        resolution: config.resolution,
        rows,
        cases,
    })
}

/// The reference walk of a case in reduced units, both components.
struct Reference {
    multiple: McModel,
    total: McModel,
}

impl Reference {
    fn of(&self, c: Component) -> &McModel {
        match c {
            Component::Total => &self.total,
            _ => &self.multiple,
        }
    }
}

fn run_case(
    config: &CompareConfig,
    options: &Options,
    params: &Params,
    theta_deg: f64,
    progress: &dyn Fn(u64),
) -> Result<(Case, Vec<Row>)> {
    let theta = theta_deg.to_radians();
    let walk_config = walk::Config {
        albedo: params.albedo(),
        g: params.g(),
        eta: params.eta(),
        theta,
        photons: config.photons,
        seed: config.seed,
        bins: config.bins.clone(),
        geometry: walk::Geometry::HalfSpace,
    };
    let result = walk::run(&walk_config)?;
    progress(1);
    let reference = Reference {
        multiple: McModel::from_walk(&result, Component::Multiple, params.moments())?,
        total: McModel::from_walk(&result, Component::Total, params.moments())?,
    };
    let grid = BinGrid::new(&reference.total);

    let mut case_options = options.clone();
    case_options.mc = McOptions {
        theta,
        photons: config.photons,
        seed: config.seed.wrapping_add(1),
        bins: config.bins.clone(),
        component: Component::Total,
    };
    if config.burley_albedo_from_walk {
        let total = result.total_reflectance().value.clamp(0.0, 1.0);
        case_options.burley.albedo = super::burley::SurfaceAlbedo::Given(total);
    }
    let mut rows = Vec::new();
    let mut averages: Vec<Vec<f64>> = Vec::new();
    for &kind in &config.models {
        let (row, avg) = match build(kind, params, &case_options) {
            Ok(model) => evaluate_model(config, &*model, &reference, &grid, params, theta_deg),
            Err(e) => {
                let mut row = empty_row(kind, params, theta_deg, &reference, Component::Multiple);
                row.note = Some(e.to_string());
                (row, vec![f64::NAN; grid.len()])
            }
        };
        rows.push(row);
        averages.push(avg);
        progress(1);
    }
    let case = profiles(
        config, params, theta_deg, &result, &reference, &grid, &averages,
    );
    Ok((case, rows))
}

fn empty_row(
    kind: ModelKind,
    params: &Params,
    theta_deg: f64,
    reference: &Reference,
    component: Component,
) -> Row {
    let walk_total = reference.of(component).reflectance();
    Row {
        model: kind,
        rho: params.rho_prime(),
        theta_deg,
        component: component_name(component),
        bins: 0,
        mean_rel_err: None,
        max_rel_err: None,
        total_model: None,
        total_walk: walk_total.value,
        total_walk_stderr: walk_total.stderr,
        total_rel_err: None,
        ns_per_eval: None,
        note: None,
    }
}

/// Radial and azimuthal bin edges of a case, in reduced units.
struct BinGrid {
    r_edges: Vec<f64>,
    n_phi: usize,
}

impl BinGrid {
    fn new(reference: &McModel) -> Self {
        Self {
            r_edges: reference.r_edges().to_vec(),
            n_phi: reference.phi_count(),
        }
    }
    fn n_r(&self) -> usize {
        self.r_edges.len() - 1
    }
    fn len(&self) -> usize {
        self.n_r() * self.n_phi
    }
    fn phi_edges(&self, j: usize) -> (f64, f64) {
        let dphi = 2.0 * PI / self.n_phi as f64;
        (-PI + dphi * j as f64, -PI + dphi * (j + 1) as f64)
    }
    /// Geometric centre in r (arithmetic for the first bin), middle in φ.
    fn centre(&self, i: usize, j: usize) -> (f64, f64) {
        let (r0, r1) = (self.r_edges[i], self.r_edges[i + 1]);
        let r = if r0 > 0.0 { (r0 * r1).sqrt() } else { 0.5 * r1 };
        let (p0, p1) = self.phi_edges(j);
        (r, 0.5 * (p0 + p1))
    }
}

/// Area average of the model over bin (i, j), i ≥ 1: 3 × 3 Gauss–Legendre in (ln r, φ).
fn bin_average(
    model: &dyn Model,
    theta: f64,
    grid: &BinGrid,
    rule: &GaussLegendre,
    i: usize,
    j: usize,
) -> f64 {
    let (r0, r1) = (grid.r_edges[i], grid.r_edges[i + 1]);
    let (p0, p1) = grid.phi_edges(j);
    let (s0, s1) = (r0.ln(), r1.ln());
    let mut sum = 0.0;
    for (&xs, &ws) in rule.nodes().iter().zip(rule.weights()) {
        let s = 0.5 * (s0 + s1) + 0.5 * (s1 - s0) * xs;
        let r = s.exp();
        for (&xp, &wp) in rule.nodes().iter().zip(rule.weights()) {
            let phi = 0.5 * (p0 + p1) + 0.5 * (p1 - p0) * xp;
            // dA = r dr dφ = r² ds dφ.
            sum += ws * wp * model.eval(theta, r, phi) * r * r;
        }
    }
    let area = 0.5 * (r1 * r1 - r0 * r0) * (p1 - p0);
    sum * 0.25 * (s1 - s0) * (p1 - p0) / area
}

fn evaluate_model(
    config: &CompareConfig,
    model: &dyn Model,
    reference: &Reference,
    grid: &BinGrid,
    params: &Params,
    theta_deg: f64,
) -> (Row, Vec<f64>) {
    let component = model.component();
    let theta = theta_deg.to_radians();
    let mut row = empty_row(model.kind(), params, theta_deg, reference, component);
    let rule = GaussLegendre::new(3);
    // Bin averages for i ≥ 1 (the first bin, [0, r_min), has no area-weighted log rule and is
    // never well resolved by the rule's r_min); mirror bins share the value.
    let mut avg = vec![f64::NAN; grid.len()];
    for i in 1..grid.n_r() {
        for j in 0..grid.n_phi {
            let m = grid.n_phi - 1 - j;
            if m < j {
                avg[i * grid.n_phi + j] = avg[i * grid.n_phi + m];
                continue;
            }
            avg[i * grid.n_phi + j] = bin_average(model, theta, grid, &rule, i, j);
        }
    }
    let walk = reference.of(component);
    let res = &config.resolution;
    let (mut sum, mut max, mut count) = (0.0, 0.0f64, 0usize);
    for i in 1..grid.n_r() {
        if grid.r_edges[i] < res.r_min || grid.r_edges[i + 1] > res.r_max {
            continue;
        }
        for j in 0..grid.n_phi {
            let (Some(w), Some(s)) = (walk.bin_value(i, j), walk.bin_stderr(i, j)) else {
                continue;
            };
            if !(w > 0.0 && s < res.max_rel_stderr * w) {
                continue;
            }
            let rel = (avg[i * grid.n_phi + j] - w).abs() / w;
            sum += rel;
            max = max.max(rel);
            count += 1;
        }
    }
    row.bins = count;
    if count > 0 {
        row.mean_rel_err = Some(sum / count as f64);
        row.max_rel_err = Some(max);
    } else {
        row.note = Some(format!(
            "no bin of the walk was known to {} % (relative standard error) to compare with: raise --photons",
            100.0 * res.max_rel_stderr
        ));
    }
    let total = model
        .effective_albedo(theta)
        .unwrap_or_else(|| integrate_total(model, theta));
    row.total_model = Some(total);
    if row.total_walk > 0.0 {
        row.total_rel_err = Some((total - row.total_walk) / row.total_walk);
    }
    row.ns_per_eval = Some(time_eval(model, theta, grid, config.timing_seconds));
    (row, avg)
}

/// Nanoseconds per `eval` over the bin centres (i ≥ 1): the fastest of five rounds, each
/// repeating the sweep for at least `seconds`/5 (the minimum discards interference from other
/// work on the machine).
fn time_eval(model: &dyn Model, theta: f64, grid: &BinGrid, seconds: f64) -> f64 {
    let points: Vec<(f64, f64)> = (1..grid.n_r())
        .flat_map(|i| (0..grid.n_phi).map(move |j| (i, j)))
        .map(|(i, j)| grid.centre(i, j))
        .collect();
    if points.is_empty() {
        return f64::NAN;
    }
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let start = Instant::now();
        let mut evaluations = 0u64;
        loop {
            for &(r, phi) in &points {
                black_box(model.eval(black_box(theta), black_box(r), black_box(phi)));
            }
            evaluations += points.len() as u64;
            let elapsed = start.elapsed().as_secs_f64();
            if elapsed >= seconds / 5.0 {
                best = best.min(1e9 * elapsed / evaluations as f64);
                break;
            }
        }
    }
    best
}

fn profiles(
    config: &CompareConfig,
    params: &Params,
    theta_deg: f64,
    result: &walk::WalkResult,
    reference: &Reference,
    grid: &BinGrid,
    averages: &[Vec<f64>],
) -> Case {
    let n_phi = grid.n_phi;
    // Azimuthal average of the raw walk bins (stderrs combined as independent).
    let raw = result.bins();
    let walk_ring = |c: Component, i: usize| {
        let (mut v, mut s2) = (0.0, 0.0);
        for j in 0..n_phi {
            v += raw.value(c, i, j).unwrap_or(0.0);
            s2 += raw.stderr(c, i, j).unwrap_or(0.0).powi(2);
        }
        let k = 1.0 - params.g() * params.albedo();
        let per_area = 1.0 / (k * k);
        (
            v / n_phi as f64 * per_area,
            s2.sqrt() / n_phi as f64 * per_area,
        )
    };
    let radial = (1..grid.n_r())
        .map(|i| {
            let (wm, sm) = walk_ring(Component::Multiple, i);
            let (wt, st) = walk_ring(Component::Total, i);
            ProfilePoint {
                lo: grid.r_edges[i],
                hi: grid.r_edges[i + 1],
                walk_multiple: wm,
                walk_multiple_stderr: sm,
                walk_total: wt,
                walk_total_stderr: st,
                models: averages
                    .iter()
                    .map(|a| a[i * n_phi..(i + 1) * n_phi].iter().sum::<f64>() / n_phi as f64)
                    .collect(),
            }
        })
        .collect();
    // The shell nearest r = 1 reduced mfp (geometric centre).
    let shell = (1..grid.n_r())
        .min_by(|&a, &b| {
            let d = |i: usize| grid.centre(i, 0).0.ln().abs();
            d(a).total_cmp(&d(b))
        })
        .unwrap_or(1);
    let azimuthal = (0..n_phi)
        .map(|j| {
            let (p0, p1) = grid.phi_edges(j);
            let m = &reference.multiple;
            let t = &reference.total;
            ProfilePoint {
                lo: p0.to_degrees(),
                hi: p1.to_degrees(),
                walk_multiple: m.bin_value(shell, j).unwrap_or(f64::NAN),
                walk_multiple_stderr: m.bin_stderr(shell, j).unwrap_or(f64::NAN),
                walk_total: t.bin_value(shell, j).unwrap_or(f64::NAN),
                walk_total_stderr: t.bin_stderr(shell, j).unwrap_or(f64::NAN),
                models: averages.iter().map(|a| a[shell * n_phi + j]).collect(),
            }
        })
        .collect();
    let est = |c: Component| {
        let e = result.reflectance(c);
        (e.value, e.stderr)
    };
    Case {
        rho: params.rho_prime(),
        theta_deg,
        albedo: params.albedo(),
        models: config.models.clone(),
        walk_reflectance: [
            est(Component::Single),
            est(Component::Multiple),
            est(Component::Total),
        ],
        radial,
        azimuthal_shell: (grid.r_edges[shell], grid.r_edges[shell + 1]),
        azimuthal,
    }
}

impl CompareReport {
    /// The rows as a Markdown table (errors in %, times in ns).
    pub fn markdown(&self) -> String {
        let pct = |v: Option<f64>| v.map_or("–".to_owned(), |x| format!("{:.1}", 100.0 * x));
        let mut out = String::from(
            "| ρ′ | θ | model | vs | bins | mean err % | max err % | total (model) | total (walk) | total err % | ns/eval |\n\
             |---|---|---|---|---|---|---|---|---|---|---|\n",
        );
        for r in &self.rows {
            out.push_str(&format!(
                "| {} | {}° | {} | {} | {} | {} | {} | {} | {:.4} ± {:.4} | {} | {} |\n",
                crate::error::Number(r.rho),
                crate::error::Number(r.theta_deg),
                r.model,
                r.component,
                r.bins,
                pct(r.mean_rel_err),
                pct(r.max_rel_err),
                r.total_model.map_or("–".to_owned(), |t| format!("{t:.4}")),
                r.total_walk,
                r.total_walk_stderr,
                r.total_rel_err
                    .map_or("–".to_owned(), |t| format!("{:+.1}", 100.0 * t)),
                r.ns_per_eval.map_or("–".to_owned(), |t| format!("{t:.0}")),
            ));
        }
        // Why a row has no figures, under the table
        for r in self.rows.iter().filter(|r| r.note.is_some()) {
            let note = r.note.as_deref().unwrap_or_default();
            out.push_str(&format!(
                "\n{} at ρ′ {}, θ {}°: {note}\n",
                r.model,
                crate::error::Number(r.rho),
                crate::error::Number(r.theta_deg)
            ));
        }
        out
    }
}
