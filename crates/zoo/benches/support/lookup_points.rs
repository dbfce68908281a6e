//! The lookup points of the table benchmark (`crates/zoo/benches/table.rs`) and of the A/B timing loop
//! (`examples/lookup_loop.rs`), so that both time the same traffic.

use bssrdf_zoo::rng::{SplitMix64, UnitF64};
use bssrdf_zoo::table::TableRef;

/// 4,096 points (ρ′, θ, r, φ) over the whole table, so caches and branches see realistic
/// traffic: ρ′ ∈ [0.05, 1), θ ∈ [0, 1.5) rad, and (r, φ) drawn by the table's own sampler
/// (pairs it cannot draw for are redrawn).
pub fn lookup_points(view: &TableRef<'_>, rng: &mut SplitMix64) -> Vec<[f64; 4]> {
    (0..4096)
        .map(|_| loop {
            let (rho, theta) = (0.05 + 0.95 * rng.next_f64(), 1.5 * rng.next_f64());
            if let Some(s) = view.sample(rho, theta, rng.next_f64(), rng.next_f64()) {
                break [rho, theta, s.r, s.phi];
            }
        })
        .collect()
}
