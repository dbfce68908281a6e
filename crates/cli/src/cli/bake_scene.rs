//! `bssrdf bake --scene SCENE.toml`: bake only what a scene needs (the albedo rows of each
//! channel's range with their Catmull-Rom neighbours, the tables of the materials' η, the
//! θ-sampling section only for path tracing) and report the size saved against the full
//! library of the same materials. The manifest and the row plan live in `bssrdf_zoo::scene`,
//! the bake in `bssrdf_zoo::bake` ([`Baker::bake_scene`]).

use super::bake::{bake_error, table_summary, BakeArgs, Session, Summary};
use super::CliError;
use bssrdf_zoo::bake::{BakeError, Baker};
use bssrdf_zoo::scene::{Integrator, Scene};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

pub fn run(
    args: &BakeArgs,
    baker: &Baker,
    session: &Session,
    path: &Path,
) -> Result<ExitCode, CliError> {
    let output = match &args.output {
        Some(o) => o.clone(),
        // SCENE.toml gives SCENE.bssrdf: only the last extension goes (`shot.v1.toml` is
        // `shot.v1.bssrdf`, never `shot.bssrdf`, which `shot.v2.toml` would overwrite)
        None => {
            let mut name = path.file_stem().unwrap_or_default().to_os_string();
            name.push(".bssrdf");
            PathBuf::from(name)
        }
    };
    super::bake::check_output(args, &output)?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::input(format!("cannot read scene {}: {e}", path.display())))?;
    let library = super::materials::library(args.materials.as_deref())?;
    let scene = Scene::from_toml_str(&text, &library, &mut |eta| session.curve(baker, eta))
        .map_err(|e| CliError::input(format!("{}: {e}", path.display())))?;
    super::bake::check_materials_used(args, scene.materials().iter().map(|m| m.material()))?;
    let baked = session
        .bake(true, |progress| baker.bake_scene(&scene, Some(progress)))?
        .map_err(|e| match e {
            BakeError::Scene(e) => CliError::input(format!("{}: {e}", path.display())),
            e => bake_error(e),
        })?;
    let tables = baked
        .tables()
        .iter()
        .map(|t| table_summary(t.index(), t.table(), t.rows()))
        .collect();
    let materials = scene
        .materials()
        .iter()
        .zip(baked.materials())
        .map(|(m, baked)| {
            let record = baked.record();
            json!({
                "name": record.name, "eta": record.eta, "tables": record.tables,
                "origin": m.origin(), "rho_prime": m.material().rho_prime(),
                "albedo_range": record.albedo_range.map(|r| json!({"min": r.min, "max": r.max})),
            })
        })
        .collect();
    let integrator = match scene.integrator() {
        Integrator::Path => "path",
        Integrator::Particle => "particle",
    };
    let accepted = session.verdict(&baked, args.accept_error)?;
    let bytes = session.write(baked.builder(), &output)?;
    let summary = Summary {
        output: &output,
        bytes,
        full_bytes: baked.full_bytes(),
        integrator: Some(integrator),
        seconds: baked.seconds(),
        tables,
        materials,
        warnings: baked.warnings().iter().cloned().chain(accepted).collect(),
    };
    summary.print(args, session)?;
    Ok(ExitCode::SUCCESS)
}
