//! The lookups' blend ([`TableRef::blend`] over a [`Slice`], evaluation's
//! [`TableRef::window_at`] and the radial sampler's [`TableRef::radial_near`]) against a plain sum written from the table's layout: for every (ρ′, θ) node pair of the 4 × 4 neighbourhood in order, the
//! product of the two axes' weights (skipped where it is 0 in f32) times the row's value. The
//! slice leaves rows out and pads; the sums must not notice, bit for bit, in f32 (the GWC
//! window) and in f64 (energies and the radial CDF). The values are arbitrary: the blend does
//! not care what they mean.

use super::blend::Lane;
use super::*;
use crate::fresnel::Moments;
use crate::table::{AngularTable, Axes};
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};

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

/// Σ over the neighbourhood of (ρ′, θ) of w_ρ′ · w_θ × `value(row)`, in node order, with
/// the row index i·nθ + j of each node pair inside both axes.
fn plain_sum<A: Lane>(
    view: &TableRef<'_>,
    albedo: &AlbedoWeights,
    theta: &Weights,
    value: impl Fn(usize) -> A,
) -> A {
    let (n_rho, n_theta, _) = view.axes.dims();
    let mut sum = A::ZERO;
    for (a, &wa) in albedo.energy.as_array().iter().enumerate() {
        for (b, &wb) in theta.as_array().iter().enumerate() {
            let (i, j) = (albedo.energy.segment() + a, theta.segment() + b);
            let w = (wa * wb) as f32;
            if (1..=n_rho).contains(&i) && (1..=n_theta).contains(&j) && w != 0.0 {
                sum = sum + A::from(w) * value((i - 1) * n_theta + j - 1);
            }
        }
    }
    sum
}

#[test]
fn the_blend_is_the_plain_sum_over_the_neighbourhood() {
    let mut rng = SplitMix64::seed_from_u64(7);
    for n_r in [2, 3, 4, 9] {
        let table = table(n_r, &mut rng);
        let view = table.view();
        // 0 past the axis (a window of 4 nodes of a table of fewer radii)
        let param = |row: usize, node: usize, p: usize| {
            if node < n_r {
                view.params[(row * n_r + node) * 3 + p]
            } else {
                0.0
            }
        };
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
            let blend = Blend::new(&albedo, rho, theta);
            let slice = view.slice_of(&albedo.energy, &theta_weights, blend);
            let at = format!("n_r {n_r}, (ρ′, θ) = ({rho}, {theta})");
            for first in 0..=n_r.saturating_sub(4) {
                let window = view.window(&slice, first);
                // Evaluation's fast leaf, the same sums without a slice (for tables of at least
                // 4 radii: evaluation takes the others through the slice)
                if n_r >= 4 {
                    let at_point = view.window_at(&albedo.energy, &theta_weights, first);
                    assert_eq!(window.map(f32::to_bits), at_point.map(f32::to_bits), "{at}");
                }
                let plain: [f32; 12] = std::array::from_fn(|lane| {
                    plain_sum(&view, &albedo, &theta_weights, |row| {
                        param(row, first + lane / 3, lane % 3)
                    })
                });
                assert_eq!(
                    window.map(f32::to_bits),
                    plain.map(f32::to_bits),
                    "{at}, first {first}"
                );
            }
            for k in 0..n_r {
                let energy = plain_sum(&view, &albedo, &theta_weights, |row| {
                    f64::from(param(row, k, 0))
                });
                assert_eq!(
                    view.energy(&slice, k).to_bits(),
                    energy.to_bits(),
                    "{at}, E at {k}"
                );
                let cdf = plain_sum(&view, &albedo, &theta_weights, |row| {
                    f64::from(view.radial_cdf[row * n_r + k])
                });
                assert_eq!(
                    view.cdf(&slice, k).to_bits(),
                    cdf.to_bits(),
                    "{at}, CDF at {k}"
                );
            }
            // The radial sampler's four energies of each segment k, node by node
            for k in 0..n_r - 1 {
                for (j, value) in view.energies_around(&slice, k).into_iter().enumerate() {
                    let expected = match (k + j).checked_sub(1) {
                        Some(node) if node < n_r => view.energy(&slice, node),
                        _ => 0.0,
                    };
                    assert_eq!(
                        value.to_bits(),
                        expected.to_bits(),
                        "{at}, node {k} + {j} − 1"
                    );
                }
            }
            // The radial sampler's one pass near each segment: what it holds, the same bits
            for k in 0..n_r - 1 {
                let Some(near) = view.radial_near::<true>(&slice, k) else {
                    assert!(n_r < 4, "{at}: no reads near segment {k}");
                    continue;
                };
                let first = k.saturating_sub(1).min(n_r - 4);
                let window = near.window(first).expect("the hinted segment's window");
                let expected = view.window(&slice, first);
                assert_eq!(
                    window.map(f32::to_bits),
                    expected.map(f32::to_bits),
                    "{at}, {k}"
                );
                let around = near
                    .energies_around(k)
                    .expect("the hinted segment's energies");
                let expected = view.energies_around(&slice, k);
                assert_eq!(
                    around.map(f64::to_bits),
                    expected.map(f64::to_bits),
                    "{at}, {k}"
                );
                let mut held = 0;
                for node in 0..n_r {
                    if let Some(c) = near.cdf(node) {
                        assert_eq!(c.to_bits(), view.cdf(&slice, node).to_bits(), "{at}, {k}");
                        held += 1;
                    }
                }
                // Nodes k − 1 … k + 2 (inside the axis) and the total
                assert!(held >= 4, "{at}: {held} nodes near segment {k}");
                for other in 0..n_r - 1 {
                    if let Some(e) = near.energies_around(other) {
                        let expected = view.energies_around(&slice, other);
                        assert_eq!(e.map(f64::to_bits), expected.map(f64::to_bits), "{at}");
                    }
                }
            }
        }
    }
}

#[test]
fn a_table_of_fewer_than_four_radii_evaluates_its_last_row() {
    // At a node of every axis the weights are 1 and 0, and evaluation returns the stored
    // profile; the last (ρ′, θ) row is where a window of 4 radius nodes runs past the arrays
    let mut rng = SplitMix64::seed_from_u64(11);
    for n_r in [2, 3] {
        let table = table(n_r, &mut rng);
        let view = table.view();
        let (n_rho, n_theta, _) = view.axes.dims();
        let rho = view.axes.rho().as_slice()[n_rho - 1];
        let theta = view.axes.theta().as_slice()[n_theta - 1];
        let r = view.axes.r().as_slice()[1];
        let at = ((n_rho * n_theta - 1) * n_r + 1) * PARAMS_PER_NODE;
        let [e, e_beta, c] = [0, 1, 2].map(|k| f64::from(view.params[at + k]));
        for phi in [0.0, 1.0, 3.0] {
            let expected = table_value(e / r, cap_lobe(e_beta / r, e / r, c), c, phi);
            let value = view.eval(rho, theta, r, phi).unwrap();
            assert!(
                (value - expected).abs() <= 1e-6 * expected,
                "n_r {n_r}, φ {phi}: {value} against {expected}"
            );
        }
    }
}

#[test]
fn two_lobe_lookups_give_the_same_bits_with_and_without_the_precomputed_shares() {
    // An owned table's view blends the shares `harmonic_shares_of` computed once; a view of
    // the raw arrays divides row by row. Arbitrary values, a fifth of the nodes without energy
    // (E = 0, which the shares mark), on axes of 2, 3, 4 and 9 radii.
    let mut rng = SplitMix64::seed_from_u64(11);
    for n_r in [2, 3, 4, 9] {
        let base = table(n_r, &mut rng);
        let mut params = base.params().to_vec();
        for node in params.chunks_exact_mut(PARAMS_PER_NODE) {
            if rng.next_f64() < 0.2 {
                node[0] = 0.0;
            }
            // c in (−1, 1), lobes anywhere
            node[2] = (2.0 * rng.next_f64() - 1.0) as f32;
        }
        let harmonics: Vec<f32> = (0..params.len() / PARAMS_PER_NODE * HARMONICS_PER_NODE)
            .map(|_| (rng.next_f64() - 0.3) as f32)
            .collect();
        let owned = AngularTable::from_parts(
            base.eta(),
            base.moments(),
            base.axes().clone(),
            params,
            base.radial_cdf().to_vec(),
            None,
        )
        .unwrap()
        .with_harmonics(harmonics)
        .unwrap();
        let with = owned.view();
        assert!(with.shares.is_some());
        let raw = TableRef::new(
            owned.eta(),
            owned.moments(),
            owned.axes(),
            owned.params(),
            owned.radial_cdf(),
            None,
        )
        .unwrap()
        .with_harmonics(owned.harmonics().unwrap())
        .unwrap();
        assert!(raw.shares.is_none());
        let r_max = *owned.axes().r().as_slice().last().unwrap();
        for _ in 0..4_000 {
            let rho = rng.next_f64();
            let theta = rng.next_f64() * FRAC_PI_2;
            let (r, phi) = (rng.next_f64() * r_max, (2.0 * rng.next_f64() - 1.0) * PI);
            let bits = |v: Option<f64>| v.map(f64::to_bits);
            assert_eq!(
                bits(with.eval(rho, theta, r, phi)),
                bits(raw.eval(rho, theta, r, phi)),
                "{n_r} {rho} {theta} {r} {phi}"
            );
            assert_eq!(
                with.pdf(rho, theta, r, phi).to_bits(),
                raw.pdf(rho, theta, r, phi).to_bits(),
            );
            let (u1, u2) = (rng.next_f64(), rng.next_f64());
            assert_eq!(
                with.sample(rho, theta, u1, u2)
                    .map(|s| [s.r, s.phi, s.pdf].map(f64::to_bits)),
                raw.sample(rho, theta, u1, u2)
                    .map(|s| [s.r, s.phi, s.pdf].map(f64::to_bits)),
            );
        }
    }
}

/// A one-lobe table on the albedo and θ axes given, six radii 0.5 apart, random valid nodes.
fn random_table(rng: &mut SplitMix64, rho: Vec<f64>, theta: Vec<f64>) -> AngularTable {
    let r: Vec<f64> = (0..6).map(|k| 0.5 * k as f64).collect();
    let cells = rho.len() * theta.len() * r.len();
    let axes = Axes::new(rho, theta, r).unwrap();
    let params = (0..cells * PARAMS_PER_NODE)
        .map(|_| (0.01 + rng.next_f64()) as f32)
        .collect();
    let radial_cdf = (0..cells).map(|k| (k % 6) as f32).collect();
    AngularTable::from_parts(1.33, Moments::Exact, axes, params, radial_cdf, None).unwrap()
}

/// An angle given in f64 at an end node of a θ axis stored in f32 is the node: 45° lies just
/// below f32(π/4), the first node of a table kept from 45°, and is looked up there; an angle a
/// millionth of a radian below is outside.
#[test]
fn an_end_node_given_in_f64_is_the_node() {
    let mut rng = SplitMix64::seed_from_u64(11);
    let theta: Vec<f64> = [45.0f64, 70.0, 90.0]
        .iter()
        .map(|d| f64::from(d.to_radians() as f32))
        .collect();
    let table = random_table(&mut rng, vec![0.0, 0.3, 0.6, 1.0], theta.clone());
    let view = table.view();
    let given = 45f64.to_radians();
    assert!(given < theta[0], "45° in f64 lies below its f32 node");
    assert!(view.keeps_theta(given));
    assert_eq!(view.snap_theta(given), theta[0]);
    assert_eq!(
        view.eval(0.5, given, 1.0, 0.3).map(f64::to_bits),
        view.eval(0.5, theta[0], 1.0, 0.3).map(f64::to_bits)
    );
    let last = 90f64.to_radians();
    assert!(view.keeps_theta(last) && view.eval(0.5, last, 1.0, 0.3).is_some());
    assert!(!view.keeps_theta(given - 1e-6));
    assert_eq!(view.eval(0.5, given - 1e-6, 1.0, 0.3), None);
}

/// The same along ρ′: an albedo given in f64 at an end row stored in f32 is the row. A table
/// kept from 0.3 to 0.9 holds the f32 nodes 0.30000001 and 0.89999998; 0.3 and 0.9 as given,
/// and those nodes' shortest f32 forms as `inspect` prints them, are looked up at the rows, bit
/// for bit, by every lookup and by the medium's check; an albedo beyond f32 rounding is refused.
#[test]
fn an_end_albedo_given_in_f64_is_the_row() {
    let mut rng = SplitMix64::seed_from_u64(12);
    let rho: Vec<f64> = [0.3f32, 0.5, 0.7, 0.9].map(f64::from).to_vec();
    let table = random_table(&mut rng, rho.clone(), vec![0.0, 0.5, 1.0, FRAC_PI_2]);
    let view = table.view();
    let (first, last) = (rho[0], rho[3]);
    // (0.3 lies below its f32 node, 0.9 above; the shortest f32 forms on the other sides)
    let printed = |x: f64| format!("{:?}", x as f32).parse::<f64>().unwrap();
    assert!(0.3 < first && 0.9 > last);
    for (given, node) in [
        (0.3, first),
        (printed(first), first),
        (0.9, last),
        (printed(last), last),
    ] {
        assert!(view.keeps_rho(given), "{given}");
        assert!(view.medium(given, 1.0).is_ok(), "{given}");
        let at = |rho| {
            [
                view.eval(rho, 0.7, 1.0, 0.3),
                Some(view.pdf(rho, 0.7, 1.0, 0.3)),
                view.effective_albedo(rho, 0.7),
            ]
            .map(|v| v.map(f64::to_bits))
        };
        assert_eq!(at(given), at(node), "{given} against {node}");
        let draw = |rho| {
            view.sample(rho, 0.7, 0.4, 0.6)
                .map(|s| [s.r, s.phi].map(f64::to_bits))
        };
        assert_eq!(draw(given), draw(node), "{given}");
    }
    let [lo, hi] = view.rho_domain();
    assert!(lo < first && hi > last && hi - last < 1e-7 && first - lo < 1e-7);
    for outside in [first - 1e-7, last + 1e-7, f64::NAN] {
        assert!(!view.keeps_rho(outside), "{outside}");
        assert!(view.medium(outside, 1.0).is_err(), "{outside}");
        assert_eq!(view.eval(outside, 0.7, 1.0, 0.3), None, "{outside}");
        assert!(view.sample(outside, 0.7, 0.4, 0.6).is_none(), "{outside}");
    }
}
