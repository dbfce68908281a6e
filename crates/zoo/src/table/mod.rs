//! The angular table: its lookups are the runtime's ([`bssrdf_runtime::table`], re-exported
//! here); the bake from photon beam diffusion, its self-check and the report's validation
//! protocol are here.

mod bake;
mod check;
mod validate;
mod walk_bake;
mod walk_lobes;
mod walk_single;

pub use bake::{
    bake, bake_lobes, bake_rows, bake_rows_lobes, beam_in_surface, critical_node, node_cell,
    two_lobe_azimuths, BakeReport, Grid, GridPreset, Lobes, NodeCell, GRAZING_NODES_BELOW_ETA,
    ONE_LOBE_ABOVE_COS, REFINE_PHI_DEG, REFINE_THETA_MIN_DEG, RESCALE_BELOW_COS, SURFACE_BEAM_COS,
    TWO_LOBES_BELOW_ETA,
};
pub use bssrdf_runtime::table::*;
pub use check::{
    check, CheckBounds, RegionCheck, TableCheck, BOUNDS as CHECK_BOUNDS, CHECK_SEED,
    COARSE_BOUNDS as CHECK_COARSE_BOUNDS, COVERAGE_POINTS, PEAK_FRACTION, RHO_BANDS,
    THETA_BANDS_DEG, WEIGHTED_POINTS,
};
pub use validate::{validate, ValidationRow, REPORT_TABLE_2};
pub use walk_bake::{
    bake_walk, max_ridge_widening, walk_bake_photons, FitBand, NodeFit, WalkBake, WalkBakeReport,
    WalkMiss, WalkProfile, MAX_RIDGE_SHARE, MAX_RIDGE_WIDENING, MIN_HARMONICS_PHOTONS,
    NODE_FIT_SPLIT_R, NODE_FIT_WARNING, WALK_GROUP_EDGES, WALK_LAST_GROUP_SHARE, WALK_MISS_CHI2,
    WALK_MISS_R, WALK_MISS_WARNING,
};
