//! `bssrdf bake --scene SCENE.toml`: bake only what a scene needs (the albedo rows of each
//! channel's range with their Catmull-Rom neighbours, the tables of the materials' η, the
//! θ-sampling section only for path tracing) and report the size saved against the full
//! library of the same materials. The manifest and the row plan live in `bssrdf_zoo::scene`.

use super::bake::{format_error, table_summary, BakeArgs, Baker, Summary};
use super::CliError;
use bssrdf_zoo::format::{Compression, LibraryBuilder, ModelKind, Provenance, TableData};
use bssrdf_zoo::scene::{Integrator, Scene};
use bssrdf_zoo::table::{Lobes, HARMONICS_PER_NODE};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

pub fn run(args: &BakeArgs, baker: &mut Baker, path: &Path) -> Result<ExitCode, CliError> {
    let output = match &args.output {
        Some(o) => o.clone(),
        None => PathBuf::from(path.file_stem().unwrap_or_default()).with_extension("bssrdf"),
    };
    super::bake::check_output(args, &output)?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::input(format!("cannot read scene {}: {e}", path.display())))?;
    let library = super::materials::library(args.materials.as_deref())?;
    let scene = {
        let baker: &Baker = baker;
        Scene::from_toml_str(&text, &library, &mut |eta| baker.curve(eta))
    }
    .map_err(|e| CliError::input(format!("{}: {e}", path.display())))?;
    let axis = baker.grid.rho_axis()?;
    let plan = scene
        .plan(&axis)
        .map_err(|e| CliError::input(format!("{}: {e}", path.display())))?;
    let theta_sampling = scene.integrator().needs_theta_sampling();

    baker.plan_rows(plan.tables.iter().map(|t| t.rows.len()).sum());
    let mut builder = LibraryBuilder::new();
    let (mut accuracy, mut tables) = (Vec::new(), Vec::new());
    for (k, planned) in plan.tables.iter().enumerate() {
        let label = format!(
            "table {}/{} (eta {}, rows {}..{})",
            k + 1,
            plan.tables.len(),
            planned.eta,
            planned.rows.start,
            planned.rows.end
        );
        let table = baker.bake(planned.eta, planned.rows.clone(), theta_sampling, label)?;
        accuracy.push(baker.check(&table)?);
        let index = builder
            .add_table(table.to_table_data())
            .map_err(format_error)?;
        tables.push(table_summary(index, &table, planned.rows.clone()));
    }
    let mut materials = Vec::new();
    for (m, channel_tables) in scene.materials().iter().zip(&plan.channel_tables) {
        let record = m.record(channel_tables.map(|i| i as u32));
        builder.add_material(record.clone()).map_err(format_error)?;
        materials.push(json!({
            "name": record.name, "eta": record.eta, "tables": record.tables,
            "origin": m.origin(), "rho_prime": m.material().rho_prime(),
            "albedo_range": record.albedo_range.map(|r| json!({"min": r.min, "max": r.max})),
        }));
    }
    let integrator = match scene.integrator() {
        Integrator::Path => "path",
        Integrator::Particle => "particle",
    };
    let plan_json: Vec<Value> = plan
        .tables
        .iter()
        .map(|t| json!({"eta": t.eta, "rows": [t.rows.start, t.rows.end]}))
        .collect();
    let provenance = baker.provenance(
        theta_sampling,
        Some(json!({
            "integrator": integrator,
            "full_rho_rows": baker.grid.rho.len(),
            "tables": plan_json,
        })),
        accuracy,
    )?;
    builder.set_provenance(provenance.clone());
    baker.verdict(args.accept_error, args.quiet)?;
    let bytes = baker.write(&builder, &output)?;
    let full_bytes = full_library_bytes(&scene, baker, provenance)?;
    let summary = Summary {
        output: &output,
        bytes,
        full_bytes: Some(full_bytes),
        integrator: Some(integrator),
        tables,
        materials,
        warnings: scene.warnings(),
    };
    summary.print(args, baker)?;
    Ok(ExitCode::SUCCESS)
}

/// Size of the library `bake MATERIAL...` would write for the scene's materials: one full table
/// per η with the θ-sampling section, uncompressed, the same provenance. Laid out with zero
/// values, which take exactly the bytes of the real ones.
fn full_library_bytes(
    scene: &Scene,
    baker: &Baker,
    provenance: Provenance,
) -> Result<u64, CliError> {
    let mut etas: Vec<f64> = scene
        .materials()
        .iter()
        .map(|m| m.material().eta())
        .collect();
    etas.sort_by(f64::total_cmp);
    etas.dedup();
    let axis = |v: &[f64]| v.iter().map(|&x| x as f32).collect::<Vec<f32>>();
    let mut builder = LibraryBuilder::new();
    for &eta in &etas {
        let grid = &baker.grid_at(eta);
        let (n_rho, n_theta, n_r) = (grid.rho.len(), grid.theta.len(), grid.r.len());
        builder
            .add_table(TableData {
                model: ModelKind::PbdAngular,
                eta,
                fresnel: baker.moments.into(),
                rho: axis(&grid.rho),
                theta: axis(&grid.theta),
                r: axis(&grid.r),
                gwc: vec![0.0; n_rho * n_theta * n_r * 3],
                cdf: vec![0.0; n_rho * n_theta * n_r],
                theta_cdf: Some(vec![0.0; n_rho * n_theta]),
                harmonics: (baker.lobes_at(eta) == Lobes::Two)
                    .then(|| vec![0.0; n_rho * n_theta * n_r * HARMONICS_PER_NODE]),
            })
            .map_err(format_error)?;
    }
    for m in scene.materials() {
        let index = etas
            .iter()
            .position(|&e| e.to_bits() == m.material().eta().to_bits())
            .unwrap_or(0) as u32;
        let mut record = m.record([index; 3]);
        record.albedo_range = None;
        builder.add_material(record).map_err(format_error)?;
    }
    builder.set_provenance(provenance);
    let bytes = builder.to_bytes(Compression::None).map_err(format_error)?;
    Ok(bytes.len() as u64)
}
