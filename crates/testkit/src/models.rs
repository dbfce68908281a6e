//! Helpers shared by the model-zoo tests: building every registered model cheaply (a small
//! shared table per η, a short walk).

use bssrdf_zoo::format::{WalkComponent, WalkSource};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::models::mc::McOptions;
use bssrdf_zoo::models::table::TableSource;
use bssrdf_zoo::models::{build, Model, ModelKind, Options, Params};
use bssrdf_zoo::table::{bake, AngularTable, Grid};
use bssrdf_zoo::walk::{Bins, Component};
use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::{Arc, Mutex, OnceLock};

/// A small table grid (12 albedos × 4 angles × 24 radii, nodes as Ferrier places them): enough
/// for properties and samplers, and fast to bake.
pub fn small_grid() -> Grid {
    Grid::ferrier(12, 4, 24)
}

/// The small table for η, baked once per η for the whole test binary.
pub fn table_for(eta: f64) -> Arc<AngularTable> {
    static TABLES: OnceLock<Mutex<HashMap<u64, Arc<AngularTable>>>> = OnceLock::new();
    let map = TABLES.get_or_init(|| Mutex::new(HashMap::new()));
    let mut map = map.lock().unwrap_or_else(|e| e.into_inner());
    Arc::clone(
        map.entry(eta.to_bits()).or_insert_with(|| {
            Arc::new(bake(eta, Moments::Exact, &small_grid(), false).unwrap().0)
        }),
    )
}

/// The small table for η marked as a walk table of g = 0 (multiple scattering): what the
/// walk-table model looks up, for the properties of its lookups (a walk bake takes minutes;
/// the lookups do not depend on where the numbers came from).
pub fn walk_table_for(eta: f64) -> Arc<AngularTable> {
    let walk = WalkSource {
        g: 0.0,
        component: WalkComponent::Multiple,
    };
    Arc::new(table_for(eta).as_ref().clone().with_walk(walk))
}

/// Options for the tests: the shared small table (also as the walk table, [`walk_table_for`]),
/// a short walk at θ with coarse bins.
pub fn options(eta: f64, theta: f64, photons: u64) -> Options {
    Options {
        table: TableSource::Shared(table_for(eta)),
        walk_table: Some(walk_table_for(eta)),
        mc: McOptions {
            theta,
            photons,
            seed: 7,
            bins: Bins::new(0.01, 100.0, 12, 8).unwrap(),
            component: Component::Total,
        },
        ..Options::default()
    }
}

/// Builds `kind` for (ρ′, η) with g = 0 and exact moments; the Monte Carlo model walks at θ
/// with `photons` photons (walks at ρ′ ≈ 1 are long: keep it small where only properties count).
pub fn model(
    kind: ModelKind,
    rho: f64,
    eta: f64,
    theta: f64,
    photons: u64,
) -> bssrdf_zoo::Result<Box<dyn Model>> {
    let params = Params::new(rho, eta, Moments::Exact)?;
    build(kind, &params, &options(eta, theta, photons))
}

/// Whether +∞ is the documented value: PBD at r = 0, where it diverges like ln(1/r), and when
/// the refracted beam runs along the surface (θ = 90° at η = 1) through the exit point (φ = 0);
/// Christensen–Burley at r = 0.
pub fn documented_infinity(kind: ModelKind, eta: f64, theta: f64, r: f64, phi: f64) -> bool {
    match kind {
        ModelKind::Pbd | ModelKind::PbdFast => {
            r == 0.0 || (eta == 1.0 && theta == 0.5 * PI && phi == 0.0)
        }
        // An integrable 1/r at r = 0, beyond f64's range below r ~ 1e-307.
        ModelKind::Burley => r < 1e-300,
        _ => false,
    }
}

/// (ρ′, η) of the models [`zoo`] builds: both ends of the η domain, index matching, ρ′ from 0
/// to 1.
pub const MEDIA: [(f64, f64); 4] = [(0.0, 1.33), (0.5, 0.75), (0.99, 1.0), (1.0, 2.5)];

/// θ at which the walk of the Monte Carlo models of [`zoo`] runs (its only θ).
pub const WALK_THETA: f64 = 0.5;

/// A model of [`zoo`], with what [`documented_infinity`] needs to know of it.
pub struct Built {
    pub kind: ModelKind,
    pub eta: f64,
    pub model: Box<dyn Model>,
}

/// Every registered model at every medium of [`MEDIA`] (walks of 256 photons at
/// [`WALK_THETA`]).
pub fn zoo() -> Vec<Built> {
    let mut all = Vec::new();
    for kind in ModelKind::ALL {
        for (rho, eta) in MEDIA {
            let model = model(kind, rho, eta, WALK_THETA, 256).unwrap();
            all.push(Built { kind, eta, model });
        }
    }
    all
}
