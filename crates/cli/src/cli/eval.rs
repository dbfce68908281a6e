//! `bssrdf eval`: evaluate a model at a point (reduced albedo ρ′, θ in degrees, r in reduced
//! mean free paths, φ in degrees) or at every row of a CSV file. With `--material NAME
//! --channel c`, ρ′ and σ′t come from the material and r is in mm (the value in mm⁻²).
//! The CSV columns are those `bssrdf sample` writes (docs/cli.md), so its output can be fed
//! back: `bssrdf sample FILE --rho 0.9 | bssrdf eval FILE --points -`.

use super::points::Point;
use super::values::{check_kept, check_theta_kept};
use super::{check_range, CliError};
use bssrdf_zoo::format::{WalkComponent, WalkSource};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::models::ModelKind;
use bssrdf_zoo::pbd::{Pbd, Rule};
use bssrdf_zoo::walk::Component;
use clap::{Args, ValueEnum};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MomentsArg {
    /// Exact Fresnel moments, integrated numerically.
    Exact,
    /// pbrt-v3's polynomial fits, to compare with pbrt's numbers.
    Pbrt,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum QuadratureArg {
    /// Adaptive Gauss–Kronrod to 1e-10 relative.
    Reference,
    /// The fixed rule used for baking.
    Fast,
}

/// The Fresnel moments `eval` offers: those of every model, and the directional dipole's
/// authors' fits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum EvalMomentsArg {
    /// Exact Fresnel moments, integrated numerically.
    Exact,
    /// pbrt-v3's polynomial fits, to compare with pbrt's numbers.
    Pbrt,
    /// The dirpole model only: the authors' sample code (d'Eon & Irving's fits), to compare
    /// with their numbers.
    Authors,
}

impl From<MomentsArg> for Moments {
    fn from(m: MomentsArg) -> Self {
        match m {
            MomentsArg::Exact => Moments::Exact,
            MomentsArg::Pbrt => Moments::Pbrt,
        }
    }
}

#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Library file (needed by the table models).
    file: Option<PathBuf>,
    /// Model to evaluate (default: table with FILE, walk-table for a table of FILE baked from
    /// the walk, pbd without FILE).
    #[arg(long, value_enum)]
    model: Option<ModelKind>,
    /// Reduced albedo ρ′ = σ′s/σ′t, in [0, 1] (not with --material, which gives it).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "material",
          required_unless_present_any = ["points", "material"])]
    rho: Option<f64>,
    /// Incidence angle θ before refraction, degrees in [0, 90].
    #[arg(long, allow_hyphen_values = true, required_unless_present = "points")]
    theta: Option<f64>,
    /// Exit distance r in reduced mean free paths, finite and ≥ 0; in mm with --material.
    #[arg(long, allow_hyphen_values = true, required_unless_present = "points")]
    r: Option<f64>,
    /// Exit azimuth φ in degrees, any finite number; 0 is forward, in the plane of incidence.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    phi: f64,
    /// CSV of points ('-' for stdin), columns as `bssrdf sample` writes them: rho, theta_deg,
    /// r (r_mm with --material), phi_deg; other columns are copied through. Writes every row
    /// back with a `value` column (or, with --json, one JSON object per row).
    #[arg(long, value_name = "CSV", conflicts_with_all = ["rho", "theta", "r", "phi"])]
    points: Option<PathBuf>,
    /// Print a JSON object (one per row with --points) instead of the bare value.
    #[arg(long)]
    json: bool,
    /// Fresnel moments of the boundary [default: exact; with FILE, the table's].
    #[arg(long, value_enum)]
    fresnel_moments: Option<EvalMomentsArg>,
    /// Quadrature of the integral over the beam (the pbd model only) [default: reference].
    #[arg(long, value_enum)]
    quadrature: Option<QuadratureArg>,
    #[command(flatten)]
    choice: super::library::TableChoice,
}

/// What one evaluation needs: the model, and for a material the channel's ρ′ and σ′t.
struct Evaluator<'a> {
    /// The dirpole with its authors' Fresnel fits (`--fresnel-moments authors`).
    authors: bool,
    model: ModelKind,
    boundary: Boundary,
    rule: Rule,
    table: Option<bssrdf_zoo::table::TableRef<'a>>,
    /// The table's index in FILE, and the file's other tables of its η with the albedo rows
    /// each keeps (for the refusal of a ρ′ the table does not keep).
    index: usize,
    siblings: Vec<(usize, [f64; 2])>,
    /// (ρ′, σ′t in mm⁻¹) of the chosen material channel: r is then in mm.
    material: Option<(f64, f64)>,
    /// The walk of a walk-angular table of FILE: the Monte Carlo model walks with its g and
    /// keeps its component, as the table's η is the model's.
    walk: Option<WalkSource>,
}

impl Evaluator<'_> {
    /// Checks a point against the domains; `names` say how the input calls ρ′, θ, r and φ
    /// (flags or CSV columns).
    fn check(&self, p: &Point, names: [&str; 4]) -> Result<(), CliError> {
        if self.material.is_none() {
            check_range(names[0], p.rho, 0.0..=1.0)?;
        }
        check_range(names[1], p.theta_deg, 0.0..=90.0)?;
        check_r(names[2], p.r)?;
        check_range(names[3], p.phi_deg, ..)?;
        match (self.model, &self.table) {
            (ModelKind::Table | ModelKind::WalkTable, Some(t)) => {
                check_theta_kept(names[1], p.theta_deg, t)?
            }
            // The perpendicular model reads the table's θ = 0 rows, whatever θ is
            (ModelKind::Perpendicular, Some(t)) => {
                check_theta_kept("the perpendicular model's theta", 0.0, t)?
            }
            _ => {}
        }
        match (self.model, &self.table) {
            (ModelKind::Table | ModelKind::Perpendicular | ModelKind::WalkTable, Some(t)) => {
                match self.material {
                    Some((rho, _)) => self.check_kept("the material's rho'", rho, t),
                    None => self.check_kept(names[0], p.rho, t),
                }
            }
            _ => Ok(()),
        }
    }

    /// [`check_kept`] on this evaluator's table of FILE.
    fn check_kept(
        &self,
        name: &str,
        rho: f64,
        table: &bssrdf_zoo::table::TableRef<'_>,
    ) -> Result<(), CliError> {
        check_kept(name, rho, (self.index, table), &self.siblings)
    }

    /// The refusal of a ρ′ that [`Evaluator::check`] let through but the table did not take.
    fn kept_error(&self, rho: f64, table: &bssrdf_zoo::table::TableRef<'_>) -> CliError {
        self.check_kept("rho", rho, table)
            .err()
            .unwrap_or_else(|| CliError::input(format!("rho {}: no value", super::show(rho))))
    }

    fn value(&self, p: &Point) -> Result<f64, CliError> {
        let (rho, scale) = match self.material {
            Some((rho, st)) => (rho, st),
            None => (p.rho, 1.0),
        };
        let (theta, phi, r_opt) = (
            p.theta_deg.to_radians(),
            super::values::azimuth_radians(p.phi_deg),
            p.r * scale,
        );
        // Where no light enters (η < 1 beyond the critical angle) every model gives 0 (the
        // tables would interpolate toward their zero nodes, the walk cannot normalise).
        if bssrdf_zoo::fresnel::refracted_cos(theta, self.boundary.eta()).is_none() {
            return Ok(0.0);
        }
        // The models built from (ρ′, η) alone; PBD and the tables are evaluated below, with the
        // quadrature chosen and the table of FILE.
        let own = matches!(
            self.model,
            ModelKind::Pbd | ModelKind::Table | ModelKind::Perpendicular | ModelKind::WalkTable
        );
        if !own {
            let kind = self.model;
            let mut params =
                bssrdf_zoo::models::Params::new(rho, self.boundary.eta(), self.boundary.moments())?;
            let mut options = bssrdf_zoo::models::Options::default();
            options.mc.theta = theta;
            if let (ModelKind::MonteCarlo, Some(walk)) = (kind, self.walk) {
                params = params.with_g(walk.g)?;
                options.mc.component = match walk.component {
                    WalkComponent::Multiple => Component::Multiple,
                    WalkComponent::Total => Component::Total,
                };
            }
            if self.authors {
                options.dirpole.fresnel = bssrdf_zoo::models::dirpole::DirpoleFresnel::AuthorsFits;
            }
            let model = bssrdf_zoo::models::build(kind, &params, &options)?;
            // σ′t² first, as `World` and the handles multiply, so the values agree bit for bit
            return Ok(scale * scale * model.eval(theta, r_opt, phi));
        }
        let reduced = match (self.model, &self.table) {
            (ModelKind::Pbd, _) => Pbd::new(rho, self.boundary)?.eval(theta, r_opt, phi, self.rule),
            (ModelKind::Table | ModelKind::WalkTable, Some(t)) => t
                .eval(rho, theta, r_opt, phi)
                .ok_or_else(|| self.kept_error(rho, t))?,
            (ModelKind::Perpendicular, Some(t)) => t
                .eval_perpendicular(rho, r_opt)
                .ok_or_else(|| self.kept_error(rho, t))?,
            (_, None) => return Err(CliError::input("the table models need a library FILE")),
            (_, Some(_)) => unreachable_model(self.model)?,
        };
        Ok(scale * scale * reduced)
    }
}

/// Every model is handled above; kept as an error rather than a panic.
fn unreachable_model(model: ModelKind) -> Result<f64, CliError> {
    Err(CliError::input(format!(
        "model {model} cannot be evaluated here"
    )))
}

/// r is a finite number ≥ 0; every positive r, subnormals included, has a finite value, but
/// burley's at subnormal r, whose 1/r growth passes f64's largest number, and pbd's on φ = 0
/// when the refracted beam runs in the surface (θ = 90° at η = 1), +∞ there (docs/cli.md). At
/// r = 0 each model gives its limit: +∞ where it diverges (pbd like ln(1/r), burley like 1/r;
/// in JSON `"value": null, "limit": "inf"`), and the table models the value at which they cap that growth, 10⁻⁹
/// times the first radial node (finite, documented in `TableRef::eval`).
fn check_r(name: &str, r: f64) -> Result<(), CliError> {
    check_range(name, r, 0.0..)
}

pub fn run(args: EvalArgs) -> Result<ExitCode, CliError> {
    let mut model = args.model.unwrap_or(if args.file.is_some() {
        ModelKind::Table
    } else {
        ModelKind::Pbd
    });
    if args.quadrature.is_some() && model != ModelKind::Pbd {
        return Err(CliError::input(format!(
            "--quadrature applies to the pbd model only, not to {}",
            model.name()
        )));
    }
    let rule = match args.quadrature {
        Some(QuadratureArg::Fast) => Rule::Fast,
        Some(QuadratureArg::Reference) | None => Rule::Reference,
    };
    if args.file.is_none() {
        // What only a file gives meaning to.
        let given = [
            ("--table", args.choice.table.is_some()),
            ("--mmap", args.choice.mmap),
        ];
        if let Some((flag, _)) = given.iter().find(|(_, on)| *on) {
            return Err(CliError::input(format!(
                "{flag} chooses how to read a library FILE; give one, or drop {flag}"
            )));
        }
    }
    if let (Some(file), Some(points)) = (&args.file, &args.points) {
        if points.as_os_str() == "-" && super::output::is_stream_of(file, "/dev/stdin") {
            return Err(CliError::input(format!(
                "FILE {} and --points - both read standard input: give one of them as a file",
                file.display()
            )));
        }
    }
    let library = match &args.file {
        Some(path) => Some(super::library::open(path, args.choice.mmap)?),
        None => None,
    };
    let chosen = match (&library, &args.file) {
        (Some(lib), Some(path)) => Some(args.choice.resolve(lib, path)?),
        _ => None,
    };
    // Without a file, --material still works for the analytic models: ρ′, σ′t and η from
    // the named library.
    let named = match &chosen {
        None => args.choice.named_material()?,
        Some(_) => None,
    };
    // A walk-angular table is the walk-table model's, a PBD table the table models'
    if let Some(c) = &chosen {
        let walk = c.table.record().walk().is_some();
        match (args.model, walk) {
            (None, true) => model = ModelKind::WalkTable,
            (Some(ModelKind::Table | ModelKind::Perpendicular), true) => {
                return Err(CliError::input(format!(
                    "table {} of the file is walk-angular (`bake --source walk`): --model walk-table (the default for it) evaluates it",
                    c.index
                )))
            }
            (Some(ModelKind::WalkTable), false) => {
                return Err(CliError::input(format!(
                    "--model walk-table evaluates a walk-angular table; table {} of the file is a PBD table (--model table)",
                    c.index
                )))
            }
            _ => {}
        }
    }
    let table = match &chosen {
        Some(c) => Some(c.table.view().map_err(|e| CliError::input(e.to_string()))?),
        None => None,
    };
    let (eta, material) = match (&chosen, &named, &table) {
        (Some(c), _, Some(t)) => (t.eta(), c.material.as_ref().map(|(_, rho, st)| (*rho, *st))),
        (_, Some(m), _) => {
            let ch = m.channel(args.choice.channel());
            (m.eta(), Some((ch.rho_prime(), ch.sigma_t_prime())))
        }
        _ => (args.choice.eta.unwrap_or(1.33), None),
    };
    if let (ModelKind::MonteCarlo | ModelKind::WalkTable, Some(m)) = (model, args.fresnel_moments) {
        return Err(CliError::input(format!(
            "--fresnel-moments {} applies to the diffusion models, not to {}: the walk takes the exact Fresnel reflectance at every crossing",
            m.to_possible_value()
                .map_or(String::new(), |v| v.get_name().to_owned()),
            model.name()
        )));
    }
    let authors = args.fresnel_moments == Some(EvalMomentsArg::Authors);
    if authors && model != ModelKind::Dirpole {
        return Err(CliError::input(format!(
            "--fresnel-moments authors is the dirpole model's only, not {}'s",
            model.name()
        )));
    }
    let given = match args.fresnel_moments {
        Some(EvalMomentsArg::Exact) => Some(Moments::Exact),
        Some(EvalMomentsArg::Pbrt) => Some(Moments::Pbrt),
        Some(EvalMomentsArg::Authors) | None => None,
    };
    let moments = match (&chosen, given) {
        // (The authors' fits are neither moments a table is baked with)
        (Some(c), Some(m)) if m != c.table.moments() => {
            return Err(CliError::input(format!(
                "--fresnel-moments {} conflicts with the table, baked with {} moments",
                m.name(),
                c.table.moments().name()
            )))
        }
        (Some(c), None) if authors => {
            return Err(CliError::input(format!(
                "--fresnel-moments authors conflicts with the table, baked with {} moments",
                c.table.moments().name()
            )))
        }
        (Some(c), _) => c.table.moments(),
        (None, m) => m.unwrap_or(Moments::Exact),
    };
    let walk = chosen.as_ref().and_then(|c| c.table.record().walk());
    let (index, siblings) = chosen
        .as_ref()
        .map_or((0, Vec::new()), |c| (c.index, c.siblings.clone()));
    let evaluator = Evaluator {
        index,
        siblings,
        authors,
        model,
        boundary: Boundary::new(eta, moments)?,
        rule,
        table,
        material,
        walk,
    };
    let describe = |p: &Point, value: f64| {
        serde_json::json!({
            "model": model.name(),
            "eta": eta,
            "fresnel_moments": match (model, authors) {
                (ModelKind::MonteCarlo | ModelKind::WalkTable, _) => None,
                (_, true) => Some("authors"),
                _ => Some(moments.name()),
            },
            "quadrature": (model == ModelKind::Pbd).then_some(rule_name(rule)),
            "g": (model == ModelKind::MonteCarlo).then(|| walk.map_or(0.0, |w| w.g)),
            "component": matches!(model, ModelKind::MonteCarlo | ModelKind::WalkTable).then(|| {
                walk.map_or(WalkComponent::Total, |w| w.component).name()
            }),
            "rho": p.rho,
            "theta_deg": p.theta_deg,
            "r": p.r,
            "r_unit": if material.is_some() { "mm" } else { "reduced-mfp" },
            "phi_deg": p.phi_deg,
            "value": json_number(value),
            "limit": json_limit(value),
        })
    };
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if let Some(path) = &args.points {
        let rows = super::points::read(path, material.map(|m| m.0))?;
        let mut values = Vec::with_capacity(rows.points.len());
        // Every row is checked and evaluated before anything is printed.
        for (point, line) in rows.points.iter().zip(&rows.lines) {
            let at = |e: CliError| CliError::input(format!("{}:{line}: {e}", rows.name));
            evaluator.check(point, rows.column_names()).map_err(at)?;
            values.push(evaluator.value(point).map_err(at)?);
        }
        if args.json {
            for (p, &v) in rows.points.iter().zip(&values) {
                writeln!(out, "{}", describe(p, v))?;
            }
        } else {
            rows.write_with_values(&mut out, &values)?;
        }
    } else {
        // clap guarantees these are present without --points (ρ′ may come from --material).
        let point = Point {
            rho: material.map_or(args.rho.unwrap_or_default(), |m| m.0),
            theta_deg: args.theta.unwrap_or_default(),
            r: args.r.unwrap_or_default(),
            phi_deg: args.phi,
        }
        .unsigned_zeros();
        evaluator.check(&point, ["--rho", "--theta", "--r", "--phi"])?;
        let value = evaluator.value(&point)?;
        if args.json {
            writeln!(out, "{}", describe(&point, value))?;
        } else {
            writeln!(out, "{value:e}")?;
        }
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// The quadrature as `--quadrature` names it.
fn rule_name(rule: Rule) -> &'static str {
    match rule {
        Rule::Reference => "reference",
        Rule::Fast => "fast",
    }
}

/// A value in JSON, always a number or null: JSON has no infinity, so the documented +∞
/// limits (r = 0 on the diverging models) are null, with `limit` saying which.
fn json_number(v: f64) -> serde_json::Value {
    if v.is_finite() {
        serde_json::json!(v)
    } else {
        serde_json::Value::Null
    }
}

/// `"inf"` (or `"-inf"`) where [`json_number`] wrote null for an infinite value; null otherwise.
fn json_limit(v: f64) -> serde_json::Value {
    if v.is_infinite() {
        serde_json::json!(v.to_string())
    } else {
        serde_json::Value::Null
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flags_spell_the_moments_as_moments_name() {
        for (arg, moments) in [
            (MomentsArg::Exact, Moments::Exact),
            (MomentsArg::Pbrt, Moments::Pbrt),
        ] {
            let flag = arg.to_possible_value().map(|v| v.get_name().to_string());
            assert_eq!(flag.as_deref(), Some(moments.name()));
            assert_eq!(Moments::from(arg), moments);
        }
        for (arg, moments) in [
            (EvalMomentsArg::Exact, Moments::Exact),
            (EvalMomentsArg::Pbrt, Moments::Pbrt),
        ] {
            let flag = arg.to_possible_value().map(|v| v.get_name().to_string());
            assert_eq!(flag.as_deref(), Some(moments.name()));
        }
        for (arg, rule) in [
            (QuadratureArg::Reference, Rule::Reference),
            (QuadratureArg::Fast, Rule::Fast),
        ] {
            let flag = arg.to_possible_value().map(|v| v.get_name().to_string());
            assert_eq!(flag.as_deref(), Some(rule_name(rule)));
        }
    }

    /// The command line's names of the models are the registry's, for every model.
    #[test]
    fn the_flags_spell_every_model_as_the_registry_names_it() {
        assert_eq!(ModelKind::value_variants(), ModelKind::ALL);
        for model in ModelKind::ALL {
            let flag = model.to_possible_value().map(|v| v.get_name().to_string());
            assert_eq!(flag.as_deref(), Some(model.name()));
            assert_eq!(model.name().parse::<ModelKind>().ok(), Some(model));
        }
    }
}
