//! `bssrdf eval`: evaluate a model at a point (reduced albedo ρ′, θ in degrees, r in reduced
//! mean free paths, φ in degrees) or at every row of a CSV file. With `--material NAME
//! --channel c`, ρ′ and σ′t come from the material and r is in mm (the value in mm⁻²).

use super::CliError;
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::medium::Boundary;
use bssrdf_zoo::pbd::{Pbd, Rule};
use clap::{Args, ValueEnum};
use std::io::{BufRead, Write};
use std::process::ExitCode;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModelName {
    /// Photon beam diffusion, multiple scattering, evaluated by quadrature.
    Pbd,
    /// The angular table of FILE (Ferrier's model).
    Table,
    /// The θ = 0 slice of FILE's table at every θ, uniform in φ (pbrt's assumption).
    Perpendicular,
    /// PBD with the fast quadrature used for baking.
    PbdFast,
    /// Standard dipole (Jensen et al. 2001).
    Dipole,
    /// Directional dipole (Frisvad, Hachisuka, Kjeldsen 2014).
    Dirpole,
    /// Christensen–Burley (2015), searchlight fit.
    Burley,
    /// The Monte Carlo walk, binned (runs a walk of 10⁵ photons per (ρ′, θ)).
    Mc,
}

impl ModelName {
    /// The zoo's model of the same name, for the models built from (ρ′, η) alone.
    fn zoo_kind(self) -> Option<bssrdf_zoo::models::ModelKind> {
        use bssrdf_zoo::models::ModelKind as K;
        match self {
            ModelName::PbdFast => Some(K::PbdFast),
            ModelName::Dipole => Some(K::Dipole),
            ModelName::Dirpole => Some(K::Dirpole),
            ModelName::Burley => Some(K::Burley),
            ModelName::Mc => Some(K::MonteCarlo),
            ModelName::Pbd | ModelName::Table | ModelName::Perpendicular => None,
        }
    }
}

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
    file: Option<std::path::PathBuf>,
    /// Model to evaluate (default: table with FILE, pbd without).
    #[arg(long, value_enum)]
    model: Option<ModelName>,
    /// Relative index of refraction η (medium over outside).
    #[arg(long, default_value_t = 1.33)]
    eta: f64,
    /// Reduced albedo ρ′ = σ′s/σ′t, in [0, 1] (or from --material).
    #[arg(long, required_unless_present_any = ["points", "material"])]
    rho: Option<f64>,
    /// Incidence angle θ before refraction, degrees in [0, 90].
    #[arg(long, required_unless_present = "points")]
    theta: Option<f64>,
    /// Exit distance r in reduced mean free paths (≥ 0); in mm with --material.
    #[arg(long, required_unless_present = "points")]
    r: Option<f64>,
    /// Exit azimuth φ in degrees; 0 is forward, in the plane of incidence.
    #[arg(long, default_value_t = 0.0)]
    phi: f64,
    /// CSV with columns rho,theta_deg,r,phi_deg ('-' for stdin); writes them back with `value`.
    #[arg(long, conflicts_with_all = ["rho", "theta", "r"])]
    points: Option<String>,
    /// Print one JSON object instead of the bare value.
    #[arg(long, conflicts_with = "points")]
    json: bool,
    /// Fresnel moments of the boundary.
    #[arg(long, value_enum, default_value = "exact")]
    fresnel_moments: MomentsArg,
    /// Quadrature of the integral over the beam.
    #[arg(long, value_enum, default_value = "reference")]
    quadrature: QuadratureArg,
    #[command(flatten)]
    choice: super::library::TableChoice,
}

/// What one evaluation needs: the model, and for a material the channel's ρ′ and σ′t.
struct Evaluator<'a> {
    model: ModelName,
    boundary: Boundary,
    rule: Rule,
    table: Option<bssrdf_zoo::table::TableRef<'a>>,
    /// (ρ′, σ′t in mm⁻¹) of the chosen material channel: r is then in mm.
    material: Option<(f64, f64)>,
}

impl Evaluator<'_> {
    fn value(&self, rho: f64, theta_deg: f64, r: f64, phi_deg: f64) -> Result<f64, CliError> {
        let (rho, scale) = match self.material {
            Some((rho, st)) => (rho, st),
            None => {
                check_range("rho", rho, 0.0, 1.0)?;
                (rho, 1.0)
            }
        };
        check_range("theta", theta_deg, 0.0, 90.0)?;
        check_range("r", r, 0.0, f64::INFINITY)?;
        check_range("phi", phi_deg, f64::NEG_INFINITY, f64::INFINITY)?;
        let (theta, phi, r_opt) = (theta_deg.to_radians(), phi_deg.to_radians(), r * scale);
        if let Some(kind) = self.model.zoo_kind() {
            let params =
                bssrdf_zoo::models::Params::new(rho, self.boundary.eta(), self.boundary.moments())?;
            let mut options = bssrdf_zoo::models::Options::default();
            options.mc.theta = theta;
            let model = bssrdf_zoo::models::build(kind, &params, &options)?;
            return Ok(model.eval(theta, r_opt, phi) * scale * scale);
        }
        let reduced = match (self.model, &self.table) {
            (ModelName::Pbd, _) => Pbd::new(rho, self.boundary)?.eval(theta, r_opt, phi, self.rule),
            (ModelName::Table, Some(t)) => t
                .eval(rho, theta, r_opt, phi)
                .ok_or_else(|| outside(rho, t))?,
            (ModelName::Perpendicular, Some(t)) => t
                .eval_perpendicular(rho, r_opt)
                .ok_or_else(|| outside(rho, t))?,
            (_, None) => return Err(CliError::input("the table models need a library FILE")),
            (_, Some(_)) => unreachable_model(self.model)?,
        };
        Ok(reduced * scale * scale)
    }
}

/// Every model is handled above; kept as an error rather than a panic.
fn unreachable_model(model: ModelName) -> Result<f64, CliError> {
    Err(CliError::input(format!(
        "model {model:?} cannot be evaluated here"
    )))
}

fn outside(rho: f64, table: &bssrdf_zoo::table::TableRef<'_>) -> CliError {
    let nodes = table.axes().rho().as_slice();
    CliError::input(format!(
        "--rho {rho} is outside the albedo range this table keeps, [{}, {}]: the table is never extrapolated",
        nodes[0],
        nodes[nodes.len() - 1]
    ))
}

pub fn check_range(name: &str, value: f64, min: f64, max: f64) -> Result<(), CliError> {
    if value.is_nan() || value < min || value > max || (value.is_infinite() && name != "r") {
        return Err(CliError::input(format!(
            "--{name} {value} is outside the valid range [{min}, {max}]"
        )));
    }
    if value.is_infinite() {
        return Err(CliError::input(format!("--{name} {value} must be finite")));
    }
    Ok(())
}

pub fn run(args: EvalArgs) -> Result<ExitCode, CliError> {
    let moments: Moments = args.fresnel_moments.into();
    let rule = match args.quadrature {
        QuadratureArg::Reference => Rule::Reference,
        QuadratureArg::Fast => Rule::Fast,
    };
    let model = args.model.unwrap_or(if args.file.is_some() {
        ModelName::Table
    } else {
        ModelName::Pbd
    });
    let library = match &args.file {
        Some(path) => Some(super::library::open(path)?),
        None => None,
    };
    let chosen = match (&library, &args.file) {
        (Some(lib), Some(path)) => Some(args.choice.resolve(lib, path)?),
        _ => None,
    };
    // Without a file, --material still works for pbd: ρ′, σ′t and η from the named library.
    let named = match (&chosen, &args.choice.material) {
        (None, Some(name)) => {
            let lib = super::materials::library(args.choice.materials.as_deref())?;
            let m = lib
                .get(name)
                .map_err(|e| CliError::input(e.to_string()))?
                .clone();
            Some(m)
        }
        _ => None,
    };
    let table = match &chosen {
        Some(c) => Some(c.table.view().map_err(|e| CliError::input(e.to_string()))?),
        None => None,
    };
    let (eta, material) = match (&chosen, &named) {
        (Some(c), _) => (
            table.as_ref().map_or(args.eta, |t| t.eta()),
            c.material.as_ref().map(|(_, rho, st)| (*rho, *st)),
        ),
        (None, Some(m)) => {
            let ch = m.channel(args.choice.channel.rgb());
            (m.eta(), Some((ch.rho_prime(), ch.sigma_t_prime())))
        }
        (None, None) => (args.eta, None),
    };
    let moments = chosen.as_ref().map_or(moments, |c| c.table.moments());
    let evaluator = Evaluator {
        model,
        boundary: Boundary::new(eta, moments)?,
        rule,
        table,
        material,
    };
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if let Some(path) = &args.points {
        eval_points(&evaluator, path, &mut out)?;
    } else {
        // clap guarantees these are present without --points (ρ′ may come from --material).
        let (rho, theta, r) = (
            material.map_or(args.rho.unwrap_or_default(), |m| m.0),
            args.theta.unwrap_or_default(),
            args.r.unwrap_or_default(),
        );
        let value = evaluator.value(rho, theta, r, args.phi)?;
        if args.json {
            let json = serde_json::json!({
                "model": format!("{model:?}").to_lowercase(),
                "eta": eta,
                "fresnel_moments": format!("{moments:?}").to_lowercase(),
                "quadrature": format!("{rule:?}").to_lowercase(),
                "rho": rho,
                "theta_deg": theta,
                "r": r,
                "r_unit": if material.is_some() { "mm" } else { "reduced mfp" },
                "phi_deg": args.phi,
                "value": json_number(value),
            });
            writeln!(out, "{json}")?;
        } else {
            writeln!(out, "{value:e}")?;
        }
    }
    out.flush()?;
    Ok(ExitCode::SUCCESS)
}

/// JSON has no infinity: the documented +∞ limits are written as the string "inf".
fn json_number(v: f64) -> serde_json::Value {
    if v.is_finite() {
        serde_json::json!(v)
    } else {
        serde_json::json!(v.to_string())
    }
}

const COLUMNS: [&str; 4] = ["rho", "theta_deg", "r", "phi_deg"];

fn eval_points(evaluator: &Evaluator, path: &str, out: &mut impl Write) -> Result<(), CliError> {
    let reader: Box<dyn BufRead> = if path == "-" {
        Box::new(std::io::BufReader::new(std::io::stdin()))
    } else {
        let file = std::fs::File::open(path)
            .map_err(|e| CliError::input(format!("cannot open points file {path:?}: {e}")))?;
        Box::new(std::io::BufReader::new(file))
    };
    let mut lines = reader.lines().enumerate();
    let header = match lines.next() {
        Some((_, line)) => line?,
        None => return Err(CliError::input(format!("points file {path:?} is empty"))),
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut index = [0usize; 4];
    for (slot, column) in index.iter_mut().zip(COLUMNS) {
        *slot = names.iter().position(|n| *n == column).ok_or_else(|| {
            CliError::input(format!(
                "points file {path:?} has no column {column:?} (header must name rho,theta_deg,r,phi_deg)"
            ))
        })?;
    }
    writeln!(out, "rho,theta_deg,r,phi_deg,value")?;
    for (number, line) in lines {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let mut v = [0.0f64; 4];
        for ((slot, &i), column) in v.iter_mut().zip(&index).zip(COLUMNS) {
            let text = fields.get(i).copied().unwrap_or("");
            *slot = text.parse().map_err(|_| {
                CliError::input(format!(
                    "{path}:{}: column {column} = {text:?} is not a number",
                    number + 1
                ))
            })?;
        }
        let value = evaluator
            .value(v[0], v[1], v[2], v[3])
            .map_err(|e| CliError::input(format!("{path}:{}: {e}", number + 1)))?;
        writeln!(out, "{},{},{},{},{value:e}", v[0], v[1], v[2], v[3])?;
    }
    Ok(())
}
