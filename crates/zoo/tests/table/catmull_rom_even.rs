//! Tests of the even end condition of `catmull_rom` ([`End::Even`]: slope 0 at the last node,
//! and at the node before the slope of the even quartic through the last three): zero slope,
//! the even quartic's slope and C¹ at x_{n−2}, interpolation, weights that sum to 1, agreement
//! with the chord rule away from the last two segments, better reproduction of data even about
//! the last node, exact integration, and the sampling triad (round trips and chi-square).

use bssrdf_testkit::splines::{chi_square, simpson, uneven_nodes, SplitMix64, EXACT, SOLVED};
use bssrdf_zoo::catmull_rom::{End, Nodes};
use bssrdf_zoo::rng::{SeedableRng, UnitF64};
use std::f64::consts::FRAC_PI_2;

/// The table's default θ axis: 0°, 10°, …, 90°, in radians.
fn theta_nodes() -> Vec<f64> {
    (0..10).map(|j| FRAC_PI_2 * f64::from(j) / 9.0).collect()
}

/// Random values in [0.2, 1.2) at the nodes of `grid`.
fn random_values(grid: &[f64], seed: u64) -> Vec<f64> {
    let mut rng = SplitMix64::seed_from_u64(seed);
    grid.iter().map(|_| 0.2 + rng.next_f64()).collect()
}

/// Both end conditions on the same nodes.
fn both(grid: &[f64]) -> (Nodes, Nodes) {
    let chord = Nodes::new(grid.to_vec()).unwrap();
    let even = chord.clone().with_end(End::Even);
    (chord, even)
}

/// ds/dx just left of x (side −1) or right of it (side 1): the one-sided second-order
/// difference ±(3s(x) − 4s(x ∓ h) + s(x ∓ 2h))/(2h) (upper signs on the left), whose error
/// is s‴h²/3.
fn one_sided_slope(nodes: &Nodes, values: &[f64], x: f64, h: f64, side: f64) -> f64 {
    let s = |x: f64| nodes.evaluate(|i| values[i], x).unwrap();
    side * (-3.0 * s(x) + 4.0 * s(x + side * h) - s(x + 2.0 * side * h)) / (2.0 * h)
}

/// ds/dx at the last node, from the cubic of the last segment.
fn end_slope(nodes: &Nodes, values: &[f64], h: f64) -> f64 {
    one_sided_slope(nodes, values, *nodes.as_slice().last().unwrap(), h, -1.0)
}

#[test]
fn end_is_chord_unless_asked_and_part_of_equality() {
    let (chord, even) = both(&theta_nodes());
    assert_eq!(chord.end(), End::Chord);
    assert_eq!(even.end(), End::Even);
    assert_ne!(chord, even);
    assert_eq!(even, chord.clone().with_end(End::Even));
    assert_eq!(chord, even.with_end(End::Chord));
}

#[test]
fn even_end_has_zero_slope_at_the_last_node() {
    for (grid, seed) in [(theta_nodes(), 1), (uneven_nodes(), 2), (vec![0.0, 0.7], 3)] {
        let values = random_values(&grid, seed);
        let n = grid.len();
        let width = grid[n - 1] - grid[n - 2];
        let h = 1e-4 * width;
        let (chord, even) = both(&grid);
        // The chord rule's slope is the chord's; the even end's is 0, both up to the
        // difference's error s‴h²/3 (|s‴| = 6|c₃|/w³ with |c₃| ≲ 5 for these values, so
        // 10⁻⁷/w) and its rounding (≈ 10⁻¹⁵/h)
        let chord_slope = (values[n - 1] - values[n - 2]) / width;
        let bound = 1e-6 / width;
        assert!(chord_slope.abs() > 1e3 * bound, "{chord_slope}");
        let slope = end_slope(&chord, &values, h);
        assert!(
            (slope - chord_slope).abs() < bound,
            "{slope} vs {chord_slope}"
        );
        let slope = end_slope(&even, &values, h);
        assert!(slope.abs() < bound, "slope {slope} at the even end");
    }
}

#[test]
fn even_end_interpolates_the_nodes_and_its_weights_sum_to_one() {
    let mut rng = SplitMix64::seed_from_u64(4);
    for grid in [theta_nodes(), uneven_nodes(), vec![-1.0, 2.0]] {
        let (_, even) = both(&grid);
        let n = grid.len();
        for (k, &x) in grid.iter().enumerate() {
            let w = even.weights(x).unwrap();
            let unit: Vec<(usize, f64)> = w.iter().collect();
            assert_eq!(unit, vec![(k, 1.0)], "node {k}");
        }
        let (first, last) = (grid[0], grid[n - 1]);
        for _ in 0..10_000 {
            let x = first + (last - first) * rng.next_f64();
            let w = even.weights(x).unwrap();
            assert!(
                (w.as_array().iter().sum::<f64>() - 1.0).abs() < EXACT,
                "x = {x}"
            );
            assert!(w.iter().all(|(node, _)| node < n), "x = {x}");
        }
    }
}

/// Nodes whose last two widths differ by more than a factor 3 (ρ = 0.8/0.9, outside
/// `EVEN_SLOPE_RATIOS`): x_{n−2} keeps the central difference.
fn lopsided_nodes() -> Vec<f64> {
    vec![0.0, 0.1, 0.2, 1.0]
}

#[test]
fn even_end_changes_only_the_last_two_segments() {
    let mut rng = SplitMix64::seed_from_u64(5);
    for (grid, changed) in [
        (theta_nodes(), 2),
        (uneven_nodes(), 2),
        (lopsided_nodes(), 1),
    ] {
        let (chord, even) = both(&grid);
        let n = grid.len();
        let from = grid[n - 1 - changed];
        for _ in 0..10_000 {
            let x = grid[0] + (grid[n - 1] - grid[0]) * rng.next_f64();
            let (a, b) = (chord.weights(x).unwrap(), even.weights(x).unwrap());
            if x < from {
                assert_eq!(a, b, "x = {x}");
            } else if x > from && !grid.contains(&x) {
                assert_ne!(a, b, "x = {x}");
            }
        }
    }
}

#[test]
fn even_end_takes_the_even_quartics_slope_at_the_node_before_and_stays_c1() {
    // f = 1 + b(x − a)² + c(x − a)⁴ is an even quartic about the last node a: the spline's slope
    // at x_{n−2} is its exact slope from both sides (C¹), on equal widths and on uneven ones.
    // With the widths of `lopsided_nodes` it is the central difference instead.
    for grid in [theta_nodes(), uneven_nodes(), lopsided_nodes()] {
        let n = grid.len();
        let a = grid[n - 1];
        let (b, c) = (0.7, -2.3);
        let f = |x: f64| 1.0 + b * (x - a).powi(2) + c * (x - a).powi(4);
        let slope = |x: f64| 2.0 * b * (x - a) + 4.0 * c * (x - a).powi(3);
        let values: Vec<f64> = grid.iter().map(|&x| f(x)).collect();
        let (_, even) = both(&grid);
        let x = grid[n - 2];
        let h = 1e-5 * (grid[n - 1] - grid[n - 2]).min(grid[n - 2] - grid[n - 3]);
        let (left, right) = (
            one_sided_slope(&even, &values, x, h, -1.0),
            one_sided_slope(&even, &values, x, h, 1.0),
        );
        let want = if grid == lopsided_nodes() {
            (values[n - 1] - values[n - 3]) / (grid[n - 1] - grid[n - 3])
        } else {
            slope(x)
        };
        for got in [left, right] {
            assert!((got - want).abs() < 1e-6, "{got} vs {want} on {grid:?}");
        }
        assert!((want - slope(x)).abs() > 1e-3 || grid != lopsided_nodes());
    }
}

#[test]
fn even_end_reproduces_data_even_about_the_last_node_better_than_the_chord() {
    // sin θ on the table's θ nodes, even about 90° like PBD, and cos(x − 2) on uneven nodes
    // ending at 2. Largest error on the last segment: the chord's d₁ error
    // (f_{n−1} − f_{n−2})·max|h₁₁| against the central difference's O(w³) at x_{n−2}.
    type Case = (Vec<f64>, fn(f64) -> f64);
    let cases: [Case; 2] = [
        (theta_nodes(), f64::sin),
        (uneven_nodes(), |x| (x - 2.0).cos()),
    ];
    for (grid, f) in cases {
        let n = grid.len();
        assert_eq!(f(grid[n - 1]), 1.0);
        let values: Vec<f64> = grid.iter().map(|&x| f(x)).collect();
        let (chord, even) = both(&grid);
        let error = |nodes: &Nodes| {
            (0..=1000)
                .map(|k| grid[n - 2] + (grid[n - 1] - grid[n - 2]) * f64::from(k) / 1000.0)
                .map(|x| (nodes.evaluate(|i| values[i], x).unwrap() - f(x)).abs())
                .fold(0.0, f64::max)
        };
        let (chord_error, even_error) = (error(&chord), error(&even));
        assert!(
            even_error < chord_error / 5.0,
            "even {even_error:e} vs chord {chord_error:e}"
        );
    }
}

#[test]
fn even_end_integrates_exactly() {
    // Three nodes: segment 0 has the chord slope at x₀ and the even quartic's at x₁
    let three = vec![0.0, 0.6, 1.0];
    let grids = [
        (theta_nodes(), 6),
        (uneven_nodes(), 7),
        (vec![0.0, 0.7], 8),
        (three, 11),
    ];
    for (grid, seed) in grids {
        let values = random_values(&grid, seed);
        let (chord, even) = both(&grid);
        let n = grid.len();
        let mut cumulative = vec![0.0; n];
        let total = even.integrate(|i| values[i], &mut cumulative).unwrap();
        let spline = |x: f64| even.evaluate(|i| values[i], x).unwrap();
        let mut quadrature = 0.0;
        for k in 1..n {
            quadrature += simpson(spline, grid[k - 1], grid[k], 64);
            assert!((cumulative[k] - quadrature).abs() < 1e-12 * (1.0 + quadrature));
        }
        assert_eq!(total, cumulative[n - 1]);
        // Against the chord rule: the same up to the first segment that changed
        let mut chord_cumulative = vec![0.0; n];
        chord
            .integrate(|i| values[i], &mut chord_cumulative)
            .unwrap();
        let same = if n >= 3 { n - 2 } else { n - 1 };
        assert_eq!(cumulative[..same], chord_cumulative[..same]);
    }
}

/// Values on the θ nodes that rise to the last node and end flat there, with a dip near 0 so
/// that the positive part and a decreasing signed CDF are exercised too.
fn grazing_values() -> (Vec<f64>, Vec<f64>) {
    let grid = theta_nodes();
    let values = grid
        .iter()
        .enumerate()
        .map(|(k, &x)| if k == 1 { 1e-4 } else { 0.05 + x.sin() })
        .collect();
    (grid, values)
}

#[test]
fn even_end_sample_pdf_and_cdf_round_trip() {
    let (grid, values) = grazing_values();
    let (_, even) = both(&grid);
    let f = |i: usize| values[i];
    let n = grid.len();
    let mut signed = vec![0.0; n];
    even.integrate(f, &mut signed).unwrap();
    let mut positive = vec![0.0; n];
    let total = even.integrate_positive(f, &mut positive).unwrap();
    for cumulative in [&signed, &positive] {
        let c = |k: usize| cumulative[k];
        let mut rng = SplitMix64::seed_from_u64(9);
        let edges = [0.0, 1e-12, 0.5, 1.0 - f64::EPSILON, 1.0];
        for u in (0..10_000).map(|_| rng.next_f64()).chain(edges) {
            let s = even.sample(f, c, u).unwrap();
            assert!(s.x >= grid[0] && s.x <= grid[n - 1]);
            assert!((even.cdf(f, c, s.x).unwrap() - u).abs() < SOLVED, "u = {u}");
            assert!(
                (even.pdf(f, c, s.x) - s.pdf).abs() < 1e-9 * s.pdf,
                "u = {u}"
            );
            // The sampled value is the even-end spline's
            let spline = even.evaluate(f, s.x).unwrap();
            assert!((s.value - spline).abs() < EXACT, "u = {u}");
        }
    }
    // With the positive-part CDF the density is exactly max(s, 0)/T of the even-end spline
    let mut rng = SplitMix64::seed_from_u64(10);
    for _ in 0..10_000 {
        let s = even.sample(f, |k| positive[k], rng.next_f64()).unwrap();
        assert!((s.pdf - s.value / total).abs() < 1e-9 * s.pdf);
    }
}

/// The even-end spline's density through `values` on `grid` (positive-part CDF): round trips
/// of sample against cdf and pdf, then a chi-square test of sample against pdf.
fn check_even_density(grid: &[f64], values: &[f64], seed: u64) {
    let (_, even) = both(grid);
    let mut cumulative = vec![0.0; grid.len()];
    even.integrate_positive(|i| values[i], &mut cumulative)
        .unwrap();
    let (f, c) = (|i: usize| values[i], |k: usize| cumulative[k]);
    let mut rng = SplitMix64::seed_from_u64(seed);
    for u in (0..10_000).map(|_| rng.next_f64()) {
        let s = even.sample(f, c, u).unwrap();
        assert!((even.cdf(f, c, s.x).unwrap() - u).abs() < SOLVED, "u = {u}");
        assert!(
            (even.pdf(f, c, s.x) - s.pdf).abs() < 1e-9 * s.pdf,
            "u = {u}"
        );
    }
    chi_square(
        grid,
        seed,
        16,
        |u| even.sample(f, c, u).map(|s| s.x),
        |x| even.pdf(f, c, x),
    );
}

#[test]
fn chi_square_even_end() {
    let (grid, values) = grazing_values();
    check_even_density(&grid, &values, 0x5eed_00e0);
}

#[test]
fn chi_square_even_end_on_three_nodes() {
    // Segment 0 is both the first (chord slope at x₀) and the one before the last (the even
    // quartic's slope at x₁, ρ = 0.4)
    check_even_density(&[0.0, 0.6, 1.0], &[0.2, 0.9, 1.0], 0x5eed_00e3);
}

#[test]
fn even_end_invert_round_trip() {
    // sin θ increases on [0, π/2], and so does its even-end spline (d₀ ≤ 3(f₁ − f₀) there)
    let grid = theta_nodes();
    let values: Vec<f64> = grid.iter().map(|x| x.sin()).collect();
    let (_, even) = both(&grid);
    let f = |i: usize| values[i];
    for k in 0..=1000 {
        let x = FRAC_PI_2 * f64::from(k) / 1000.0;
        let y = even.evaluate(f, x).unwrap();
        let back = even.invert(f, y).unwrap();
        // Near the flat end s(x) − s(x_{n−1}) ~ (x_{n−1} − x)², so x is resolved to √ε
        let tolerance = if x > 1.5 { 1e-7 } else { SOLVED };
        assert!((back - x).abs() < tolerance, "x = {x}: {back}");
    }
}
