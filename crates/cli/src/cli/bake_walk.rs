//! `bssrdf bake --source walk`: one walk-angular table for one (η, g), measured from the Monte
//! Carlo walk (`bssrdf_zoo::bake::bake_walk_library`), written atomically with its provenance:
//! `--component total` (the default) adds single scattering by quadrature to the walk's
//! multiple scattering, `--component multiple` keeps the latter alone.

use super::bake::{table_summary, BakeArgs, ComponentArg, LobesArg, Summary};
use super::values::show_whole;
use super::CliError;
use bssrdf_zoo::bake::{bake_walk_library, BakeError, BakeGrid, WalkSettings};
use bssrdf_zoo::format::Compression;
use bssrdf_zoo::table::{
    walk_bake_photons, GridPreset, MIN_HARMONICS_PHOTONS, WALK_LAST_GROUP_SHARE,
};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde_json::json;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

/// Photons per θ node (and group of albedo rows) of a walk bake without --photons.
pub const DEFAULT_WALK_PHOTONS: u64 = 250_000;

/// Seed of a walk bake without --seed.
pub const DEFAULT_WALK_SEED: u64 = 1;

/// The fewest --photons: the last group of rows takes 1/8 of them and needs 16 blocks.
const MIN_WALK_PHOTONS: u64 = MIN_HARMONICS_PHOTONS * WALK_LAST_GROUP_SHARE;

/// Refuses what a walk bake cannot take: materials and scenes (a walk table is one (η, g)),
/// and the flags of PBD bakes that would change nothing here.
fn refuse_other_flags(args: &BakeArgs) -> Result<(), CliError> {
    let material = !args.materials_named.is_empty()
        || args.scene.is_some()
        || args.sigma_s.is_some()
        || args.reflectance.is_some()
        || args.name.is_some()
        || args.materials.is_some();
    if material {
        return Err(CliError::input(
            "--source walk bakes one table for --eta and --g, without materials: drop the materials, --scene, --sigma-s/--sigma-a, --reflectance/--mfp, --name and --materials",
        ));
    }
    if args.fresnel_moments.is_some() {
        return Err(CliError::input(
            "--fresnel-moments sets PBD's boundary; the walk refracts and reflects by the exact Fresnel equations: drop it with --source walk",
        ));
    }
    if args.lobes == LobesArg::One {
        return Err(CliError::input(
            "a walk table has two lobes at every eta: drop --lobes 1 with --source walk",
        ));
    }
    if args.accept_error {
        return Err(CliError::input(
            "--accept-error writes a PBD table above the bound of the bake's check; a walk bake has no such check (its noise is in the provenance): drop it with --source walk",
        ));
    }
    Ok(())
}

pub fn run(args: &BakeArgs) -> Result<ExitCode, CliError> {
    refuse_other_flags(args)?;
    let Some(eta) = args.eta else {
        return Err(CliError::input(
            "--source walk needs --eta: the relative index of the table, in [0.75, 2.5]",
        ));
    };
    super::check_range(
        "--eta",
        eta,
        bssrdf_zoo::medium::ETA_MIN..=bssrdf_zoo::medium::ETA_MAX,
    )?;
    let g = match args.g {
        None => 0.0,
        Some(g) if !g.listed => g.rgb[0],
        Some(g) => {
            let [r, gg, b] = g.rgb.map(super::show);
            return Err(CliError::input(format!(
                "--g {r},{gg},{b}: a walk table holds one g, given as one value; bake one table per g"
            )));
        }
    };
    super::check_g(g)?;
    // −0 is 0: in the file's record, the default file name and the summary
    let g = g + 0.0;
    let photons = args.photons.unwrap_or(DEFAULT_WALK_PHOTONS);
    // (at most what every walk takes, per θ node and group here: days of walking already)
    if !(MIN_WALK_PHOTONS..=super::MAX_PHOTONS).contains(&photons) {
        return Err(CliError::input(format!(
            "--photons {} is outside the valid range: [{}, {}] (the rows above rho' = 0.999 walk 1/{WALK_LAST_GROUP_SHARE} of them, and their standard errors need 16 blocks of {} photons)",
            show_whole(photons),
            show_whole(MIN_WALK_PHOTONS),
            show_whole(super::MAX_PHOTONS),
            bssrdf_zoo::walk::BLOCK
        )));
    }
    let preset = GridPreset::from(args.grid);
    let component = args.component.unwrap_or(ComponentArg::Total).component();
    let settings = WalkSettings {
        grid: BakeGrid::Preset(preset),
        eta,
        g,
        photons,
        seed: args.seed.unwrap_or(DEFAULT_WALK_SEED),
        theta_sampling: !args.no_theta_sampling,
        bake_time: args.record_bake_time,
        component,
    };
    let output = args.output.clone().unwrap_or_else(|| {
        PathBuf::from(format!(
            "walk-eta{}-g{}.bssrdf",
            super::show(eta),
            super::show(g)
        ))
    });
    super::bake::check_output(args, &output)?;

    let total = walk_bake_photons(&settings.config());
    let bar = if args.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "walking [{bar:32}] {human_pos}/{human_len} photons ({elapsed}, ~{eta} left)",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar
    };
    let progress = |n: u64| bar.inc(n);
    let baked = super::with_threads(args.threads, || bake_walk_library(&settings, &progress))?
        .map_err(|e| match e {
            BakeError::Walk { source, .. } => CliError::Library(source),
            other => super::bake::bake_error(other),
        })?;
    bar.finish_and_clear();
    let compression = if args.compress {
        Compression::Zstd {
            level: Compression::DEFAULT_ZSTD_LEVEL,
        }
    } else {
        Compression::None
    };
    let bytes = baked
        .builder()
        .write_atomic(&output, compression)
        .map_err(|e| {
            let message = e.to_string();
            if message.contains(&output.display().to_string()) {
                CliError::input(message)
            } else {
                CliError::input(format!("cannot write {}: {message}", output.display()))
            }
        })?;
    let report = baked.report();
    let table = baked.table();
    let mut summary = table_summary(0, table, 0..table.axes().dims().0);
    summary["source"] = json!("walk");
    summary["g"] = json!(g);
    summary["component"] = json!(component.name());
    summary["photons"] = json!(report.photons);
    summary["median_rel_stderr"] = json!(report.median_rel_stderr);
    summary["p90_rel_stderr"] = json!(report.p90_rel_stderr);
    summary["rows_from_pbd"] = json!(report.rows_from_pbd);
    summary["node_fit"] = json!(report.node_fit);
    summary["walk_miss"] = json!(report.walk_miss);
    let mut warnings = Vec::new();
    if report.rows_from_pbd > 0 {
        warnings.push(format!(
            "{} (albedo, incidence) row(s) had no radius the walk measured within 30 %: they hold PBD's profile; more --photons measure them",
            report.rows_from_pbd
        ));
    }
    warnings.extend(report.walk_miss_warnings());
    warnings.extend(report.node_fit_warnings(component));
    Summary {
        output: &output,
        bytes,
        full_bytes: None,
        integrator: None,
        seconds: report.seconds,
        tables: vec![summary],
        materials: Vec::new(),
        warnings,
    }
    .print_with(args, compression != Compression::None)?;
    Ok(ExitCode::SUCCESS)
}
