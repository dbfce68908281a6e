//! The bake of a walk-angular library (`bssrdf bake --source walk`): one table for one (η, g),
//! measured from the Monte Carlo walk ([`table::bake_walk`]), with its provenance.
//!
//! # The provenance
//!
//! `tool_version`; `settings`: `source` (`"walk"`), `component` (`"multiple"`: the walk's
//! multiple scattering, the part PBD models; `"total"`: with single scattering added by
//! quadrature, and then `single_scattering`, how, and the exit directions it assumes), `g`, the grid's name and dims, θ sampling, the
//! photons per θ node, the row groups and the last group's share of them, the seed, and the
//! method in words; `quadrature`: PBD's fast rule (the model the walk's tilt is fitted to);
//! `accuracy`: `walk`, the photons walked, the scattering events and the median and 90th
//! percentile of the relative standard error of the nodes' measured μ₀ (ρ′ ≥ 0.1, r in
//! [0.01, 20] reduced mfp), the noise the table carries before smoothing. As for PBD bakes,
//! `bake_seconds` only when asked for; the rest depends on the inputs only (the walk is
//! bit-identical for a seed on any thread count).

use serde_json::json;

use super::{BakeError, BakeGrid};
use crate::format::{FormatError, LibraryBuilder, Provenance, WalkComponent, WalkSource};
use crate::table::{
    self, bake_walk, AngularTable, Grid, Lobes, WalkBake, WalkBakeReport, WALK_GROUP_EDGES,
    WALK_LAST_GROUP_SHARE,
};

/// What a walk bake is asked for.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkSettings {
    /// The grid: a preset's two-lobe grid at η, or one given node by node.
    pub grid: BakeGrid,
    /// Relative index η.
    pub eta: f64,
    /// Henyey–Greenstein asymmetry g of the walk.
    pub g: f64,
    /// Photons per θ node and group of rows ([`WalkBake::photons`]).
    pub photons: u64,
    /// Seed of the walks.
    pub seed: u64,
    /// Whether to keep the CDF over θ (path tracing).
    pub theta_sampling: bool,
    /// Whether the provenance records the bake's wall-clock time.
    pub bake_time: bool,
    /// What the table holds ([`WalkBake::component`]).
    pub component: WalkComponent,
}

impl WalkSettings {
    /// The table bake these settings ask for.
    pub fn config(&self) -> WalkBake {
        WalkBake {
            eta: self.eta,
            g: self.g,
            grid: match &self.grid {
                BakeGrid::Preset(preset) => preset.grid(self.eta, Lobes::Two),
                BakeGrid::Custom(grid) => grid.clone(),
            },
            photons: self.photons,
            seed: self.seed,
            theta_sampling: self.theta_sampling,
            component: self.component,
        }
    }
}

/// A baked walk library: the builder (one table, its provenance), the table and what the bake
/// did.
#[derive(Debug, Clone)]
pub struct WalkLibrary {
    builder: LibraryBuilder,
    table: AngularTable,
    report: WalkBakeReport,
}

impl WalkLibrary {
    /// The library's builder, ready to write.
    pub fn builder(&self) -> &LibraryBuilder {
        &self.builder
    }
    /// The table (marked with its walk, [`AngularTable::walk`]).
    pub fn table(&self) -> &AngularTable {
        &self.table
    }
    /// What the bake did: time, photons, noise.
    pub fn report(&self) -> &WalkBakeReport {
        &self.report
    }
}

/// Bakes the walk library of `settings` on the current rayon pool; `progress(n)` receives the
/// photons as they are walked ([`table::walk_bake_photons`] in all).
pub fn bake_walk_library(
    settings: &WalkSettings,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<WalkLibrary, BakeError> {
    let config = settings.config();
    let (table, report) = bake_walk(&config, progress).map_err(|source| BakeError::Walk {
        eta: settings.eta,
        g: settings.g,
        source,
    })?;
    let walk = WalkSource {
        g: settings.g,
        component: settings.component,
    };
    let table = table.with_walk(walk);
    let provenance = provenance(settings, &config.grid, &report)?;
    let mut builder = LibraryBuilder::new();
    builder.add_table(table.to_table_data())?;
    builder.set_provenance(provenance);
    Ok(WalkLibrary {
        builder,
        table,
        report,
    })
}

/// The provenance of a walk bake (module docs).
fn provenance(
    settings: &WalkSettings,
    grid: &Grid,
    report: &WalkBakeReport,
) -> Result<Provenance, FormatError> {
    let name = match &settings.grid {
        BakeGrid::Preset(preset) => format!("{preset:?}").to_lowercase(),
        BakeGrid::Custom(_) => "custom".to_string(),
    };
    let mut settings_json = json!({
        "source": "walk",
        "component": settings.component.name(),
        "g": settings.g,
        "grid": name,
        "dims": [grid.rho.len(), grid.theta.len(), grid.r.len()],
        "theta_sampling": settings.theta_sampling,
        "photons_per_theta_node": settings.photons,
        "row_groups_rho_above": WALK_GROUP_EDGES,
        "last_group_photons_divided_by": WALK_LAST_GROUP_SHARE,
        "seed": settings.seed,
        "method": "per theta node, one walk per group of albedo rows (every row from the walk at the group's largest albedo), harmonics mu_0..mu_8 of multiple scattering on hat kernels in ln r; at each node measured within 30 % (mu_0), the tilt k P (1 + a1 cos phi + a2 cos 2 phi + a3 cos 3 phi + a4 cos 4 phi) of PBD's profile P whose kernel averages match mu_0..mu_4 (where PBD's ridge has weight, a3 = a4 = 0 and mu_0..mu_2 matched: ridge_share); ln k, a1..a4 smoothed along ln r (local quadratic over 6 measured nodes each side, weighted by 1/sigma^2 and a tricube); other nodes take the nearest measured tilt, ln k beyond the last one along the line in r through the last 5; stored as two lobes fitted to the tilted PBD at the two-lobe azimuths, scaled to its energy",
        "two_lobe_fit": {
            "azimuths_deg": table::two_lobe_azimuths().map(f64::to_degrees),
            "stored": "E, E_beta, c of the one lobe with the first two harmonics; r*mu3, r*mu4",
        },
    });
    if crate::table::ridge::reaches(settings.eta) {
        settings_json["ridge_share"] = json!({
            "method": "where PBD's analytic ridge has weight (cos theta' < 0.3, below eta 1.0483; not the beam in the surface), the tilted profile is P - R + s R_w, R the flux part of the ridge (format-spec.md section 10, The ridge; its fluence lobes stay in P) and R_w that part with its lobe's concentration times e^-w (convolved over phi with a wrapped Cauchy lobe of concentration e^-w): s in [0, largest_share] and w in [0, largest_widening] (0 for a total table, whose single scattering has its own narrow ridge) whose two-term tilt matches mu_3..mu_8 best (chi-square with their standard errors) once mu_0..mu_2 are matched; s and w smoothed with a1, a2 and the walk's energy over PBD's, ln(mu_0/P_0), from which k follows",
            "largest_share": table::MAX_RIDGE_SHARE,
            "largest_widening": table::max_ridge_widening(settings.component),
        });
    }
    if settings.component == WalkComponent::Total {
        settings_json["single_scattering"] = json!({
            "method": "exact, by quadrature along the refracted beam (adaptive Gauss-Kronrod in s = b + h sinh u, 1e-9 relative; harmonics by 8-point Gauss-Legendre panels in phi doubling from cos(theta')/2), in each row's reduced units; added to the tilted PBD at every node before the two lobes are fitted, and to its energy and harmonics",
            "exit_directions": "integrated over the exit hemisphere, as the multiple scattering: a lookup carries no exit direction, and a renderer that spreads the total over exit directions by a diffuse (Fresnel-weighted cosine) law does so for single scattering too, whose true exits leave along the line from their vertex on the beam",
            "beam_in_surface": "the limit, a ridge on phi = 0 of energy a e^(-r/k) K/k per unit reduced r",
            "r0_node": "0 (single scattering's r mu_0 tends to a constant as r -> 0; the first interval holds about r_1 times it)",
        });
    }
    let mut provenance = Provenance::new(concat!("bssrdf-zoo ", env!("CARGO_PKG_VERSION")))
        .with_settings(settings_json)?
        .with_quadrature(json!({
            "rule": "fast",
            "description": crate::pbd::fast_rule_description(),
            "points_per_panel": crate::pbd::FAST_POINTS_PER_PANEL,
            "used_for": "PBD, the profile the walk's tilt is fitted to",
        }))?
        .with_accuracy(json!({
            "walk": {
                "photons": report.photons,
                "scattering_events": report.scattering_events,
                "median_rel_stderr": report.median_rel_stderr,
                "p90_rel_stderr": report.p90_rel_stderr,
                "rows_from_pbd": report.rows_from_pbd,
                "of": "the measured mu_0 of the nodes with rho' >= 0.1 and r in [0.01, 20] reduced mfp, before smoothing",
            },
            "walk_miss": {
                "by_theta": report.walk_miss,
                "of": format!("the profile each node was fitted to (profile \"tilt\": PBD with the walk's share of its ridge, tilted; profile \"lobes\": at a theta node where that tilt misses the walk by more than {warn} % RMS with chi2 above {chi2}, a floor and two wrapped Cauchy lobes fitted straight to the walk's smoothed harmonics, where they miss it less, tilt_rms and tilt_chi2 then the replaced tilt's figures; for a total table before its exact single scattering) against the walk's own measured harmonics mu_1 ... mu_8 at the node (kernel averages against kernel averages), at every theta node where light enters, over the nodes with rho' >= 0.1 and r in [{lo}, {hi}] reduced mfp that the walk measured well enough to tilt: rms, the relative root mean square over phi of the difference beyond the walk's noise (by Parseval, 2 sum_n (d mu_n^2 - se_n^2) / mu_0^2 per node, averaged with weights 1/its variance under noise alone, then the square root; 0 within the noise), and chi2, the mean over the nodes of sum_n (d mu_n / se_n)^2 / 8 (about 1 where the profile is the walk's within its noise). The part of the table's error that is the model of the walk's shape and not the stored two lobes'", lo = table::WALK_MISS_R[0], hi = table::WALK_MISS_R[1], warn = 100.0 * table::WALK_MISS_WARNING, chi2 = table::WALK_MISS_CHI2),
            },
            "node_fit": {
                "by_theta": report.node_fit,
                "of": format!("the stored two-lobe nodes against the profile each was fitted to (the tilted PBD or the lobes of walk_miss, plus single scattering for a total table), at every theta node above 0 where light enters (not the limit of a beam in the surface), over the nodes with rho' >= 0.1 in two bands of radius: near, r in [0.01, {split}) reduced mfp (where single scattering is most of a total's profile near grazing incidence, and where a multiple table's tilt follows the walk's noise in mu_3, mu_4, which the lobes smooth away), and far, r in [{split}, 20]; per node the relative L1 error sum |stored - profile| / sum profile over 36 azimuths, the midpoints of equal intervals of [0, 180] deg (the share of the node's energy the lobes put elsewhere); mean and 90th percentile over the nodes (fractions). The part of the table's error that is the two lobes' and not the walk's", split = table::NODE_FIT_SPLIT_R),
            }
        }))?;
    if settings.bake_time {
        provenance = provenance.with_bake_seconds(report.seconds)?;
    }
    Ok(provenance)
}
