//! The lookups' blends agree with each other bit for bit: evaluation's [`TableRef::window_at`]
//! with the samplers' [`TableRef::window_params`] over the slice, and the samplers' four
//! energies of a segment at once ([`TableRef::blend_e_around`]) with [`TableRef::blend`] node by
//! node. The
//! lookups rely on it (an evaluation and a density at a node see the same profile); the values
//! are arbitrary, the blends do not care what they mean.

use super::*;
use crate::fresnel::Moments;
use crate::table::{AngularTable, Axes};
use bssrdf_zoo::rng::SplitMix64;

/// A table of arbitrary positive values on uneven axes from ρ′ = 0 (whose node folds into its
/// neighbours) to 1, θ to 90° (the even end) and r from 0.
fn table(n_r: usize, rng: &mut SplitMix64) -> AngularTable {
    let rho = vec![0.0, 0.05, 0.2, 0.45, 0.7, 0.9, 0.99, 1.0];
    let theta: Vec<f64> = [0.0, 20.0, 45.0, 70.0, 80.0, 90.0]
        .iter()
        .map(|d: &f64| f64::from(d.to_radians() as f32))
        .collect();
    let r: Vec<f64> = (0..n_r)
        .map(|k| 0.01 * k as f64 * (1.0 + k as f64))
        .collect();
    let cells = rho.len() * theta.len() * n_r;
    let axes = Axes::new(rho, theta, r).unwrap();
    let params = (0..cells * PARAMS_PER_NODE)
        .map(|_| (0.01 + rng.next_f64()) as f32)
        .collect();
    let radial_cdf = (0..cells).map(|_| rng.next_f64() as f32).collect();
    AngularTable::from_parts(1.33, Moments::Exact, axes, params, radial_cdf, None).unwrap()
}

#[test]
fn evaluation_and_sampling_blend_the_same_window() {
    let mut rng = SplitMix64::new(7);
    for n_r in [4, 9] {
        let table = table(n_r, &mut rng);
        let view = table.view();
        for _ in 0..4000 {
            // Points anywhere on the axes, a quarter of them on a node of one axis
            let on_node = |rng: &mut SplitMix64, nodes: &[f64]| {
                if rng.next_f64() < 0.25 {
                    nodes[(rng.next_f64() * nodes.len() as f64) as usize]
                } else {
                    nodes[0] + rng.next_f64() * (nodes[nodes.len() - 1] - nodes[0])
                }
            };
            let rho = on_node(&mut rng, view.axes.rho().as_slice());
            let theta = on_node(&mut rng, view.axes.theta().as_slice());
            let Some(albedo) = view.axes.rho.weights(rho) else {
                continue;
            };
            let theta_weights = view.theta_weights(theta).unwrap();
            let slice = view.slice_of(&albedo, &theta_weights, rho, theta);
            for first in 0..=n_r - 4 {
                let at = view.window_at(&albedo.energy, &theta_weights, first);
                let params = view.window_params(&slice, first);
                assert_eq!(
                    at.map(f32::to_bits),
                    params.map(f32::to_bits),
                    "(ρ′, θ) = ({rho}, {theta}), first {first}"
                );
            }
            // Every segment k of the radius axis, as the samplers ask
            for k in 0..n_r - 1 {
                let around = view.blend_e_around(&slice, k);
                for (j, value) in around.into_iter().enumerate() {
                    let expected = match (k + j).checked_sub(1) {
                        Some(node) if node < n_r => {
                            TableRef::blend(&slice, view.params, node, PARAMS_PER_NODE)
                        }
                        _ => 0.0,
                    };
                    assert_eq!(value.to_bits(), expected.to_bits(), "node {k} + {j} − 1");
                }
            }
        }
    }
}
