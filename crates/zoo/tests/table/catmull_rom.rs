//! Tests of `catmull_rom`: weights against an independent Hermite formulation, exact
//! integration, sampler ↔ pdf ↔ CDF consistency (chi-square, round trips, analytic inverses),
//! inversion, and edge cases.

use bssrdf_testkit::splines::{
    chi_square, geometric_radii, integrated, radial_profile, simpson, uneven_nodes, SplitMix64,
    EXACT, SOLVED,
};
use bssrdf_zoo::catmull_rom::{End, Nodes};
use bssrdf_zoo::rng::{RngCore, SeedableRng, UnitF64};
use bssrdf_zoo::Error;

#[test]
fn nodes_are_validated() {
    assert!(matches!(
        Nodes::new(vec![1.0]),
        Err(Error::OutOfRange { value, .. }) if value == 1.0
    ));
    assert!(Nodes::new(Vec::new()).is_err());
    assert!(matches!(
        Nodes::new(vec![0.0, f64::NAN, 1.0]),
        Err(Error::NotFinite { .. })
    ));
    assert!(matches!(
        Nodes::new(vec![0.0, f64::INFINITY]),
        Err(Error::NotFinite { .. })
    ));
    assert!(matches!(
        Nodes::new(vec![0.0, 1.0, 1.0]),
        Err(Error::OutOfRange { value, min, .. }) if value == 1.0 && min == 1.0
    ));
    assert!(Nodes::new(vec![0.0, 2.0, 1.0]).is_err());
    assert!(Nodes::new([-1.0, 0.0]).is_ok());
}

#[test]
fn weights_sum_to_one() {
    for grid in [
        uneven_nodes(),
        geometric_radii(),
        vec![0.0, 1.0],
        vec![0.0, 0.1, 5.0],
    ] {
        let nodes = Nodes::new(grid.clone()).unwrap();
        let (a, b) = (grid[0], grid[grid.len() - 1]);
        let mut rng = SplitMix64::seed_from_u64(1);
        for _ in 0..1000 {
            let x = a + (b - a) * rng.next_f64();
            let w = nodes.weights(x).unwrap();
            let sum: f64 = w.as_array().iter().sum();
            assert!((sum - 1.0).abs() < EXACT, "Σw = {sum} at x = {x}");
            assert!((w.iter().map(|(_, wk)| wk).sum::<f64>() - sum).abs() < EXACT);
        }
    }
}

#[test]
fn weights_reproduce_linear_data() {
    let grid = uneven_nodes();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let line = |x: f64| 0.75 - 2.5 * x;
    let mut rng = SplitMix64::seed_from_u64(2);
    for _ in 0..1000 {
        let x = 2.0 * rng.next_f64();
        let s = nodes.evaluate(|i| line(grid[i]), x).unwrap();
        assert!(
            (s - line(x)).abs() < EXACT,
            "s({x}) = {s}, line {}",
            line(x)
        );
    }
}

#[test]
fn weights_interpolate_node_values_exactly() {
    let grid = geometric_radii();
    let nodes = Nodes::new(grid.clone()).unwrap();
    for (i, &x) in grid.iter().enumerate() {
        let pairs: Vec<(usize, f64)> = nodes.weights(x).unwrap().iter().collect();
        assert_eq!(pairs, vec![(i, 1.0)], "at node {i}");
        let value = nodes.evaluate(|j| radial_profile(grid[j]), x).unwrap();
        assert_eq!(value, radial_profile(x));
    }
}

#[test]
fn weights_match_the_hermite_form_with_node_slopes() {
    // Independent formulation: slope per node in x-units, central non-uniform differences
    // inside and one-sided differences at the two end nodes, then the cubic Hermite basis.
    let grid = uneven_nodes();
    let n = grid.len();
    let mut rng = SplitMix64::seed_from_u64(3);
    let f: Vec<f64> = (0..n).map(|_| rng.next_f64() - 0.3).collect();
    let slope = |j: usize| match j {
        0 => (f[1] - f[0]) / (grid[1] - grid[0]),
        j if j == n - 1 => (f[j] - f[j - 1]) / (grid[j] - grid[j - 1]),
        j => (f[j + 1] - f[j - 1]) / (grid[j + 1] - grid[j - 1]),
    };
    let nodes = Nodes::new(grid.clone()).unwrap();
    for _ in 0..1000 {
        let x = 2.0 * rng.next_f64();
        let i = grid.partition_point(|&g| g <= x).clamp(1, n - 1) - 1;
        let w = grid[i + 1] - grid[i];
        let t = (x - grid[i]) / w;
        let hermite = (2.0 * t.powi(3) - 3.0 * t * t + 1.0) * f[i]
            + (-2.0 * t.powi(3) + 3.0 * t * t) * f[i + 1]
            + w * (t.powi(3) - 2.0 * t * t + t) * slope(i)
            + w * (t.powi(3) - t * t) * slope(i + 1);
        let weights = nodes.weights(x).unwrap();
        assert_eq!(weights.segment(), i);
        assert!((weights.apply(|j| f[j]) - hermite).abs() < EXACT);
    }
}

#[test]
fn weights_at_the_ends_stay_in_bounds() {
    let grid = uneven_nodes();
    let n = grid.len();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let first = nodes.weights(0.5 * grid[1]).unwrap();
    assert_eq!(first.segment(), 0);
    assert_eq!(first.as_array()[0], 0.0, "node −1 does not exist");
    let last = nodes.weights(0.5 * (grid[n - 2] + grid[n - 1])).unwrap();
    assert_eq!(last.segment(), n - 2);
    assert_eq!(last.as_array()[3], 0.0, "node n does not exist");
    for w in [first, last] {
        assert!(w.iter().all(|(j, _)| j < n));
    }
    assert_eq!(nodes.weights(2.0).unwrap().segment(), n - 2);
}

/// The float next to `x` towards +∞ (x finite).
fn next_up(x: f64) -> f64 {
    if x == 0.0 {
        f64::from_bits(1)
    } else if x > 0.0 {
        f64::from_bits(x.to_bits() + 1)
    } else {
        f64::from_bits(x.to_bits() - 1)
    }
}

#[test]
fn segment_search_matches_a_linear_scan() {
    // The search narrows down with cells over the bit pattern of x (nodes ≥ 0) or bisects
    // (nodes below 0, or spread over too many octaves); both must find the segment a scan does.
    let albedo: Vec<f64> = (0..100)
        .map(|i| (1.0 - (-8.0 * i as f64 / 99.0).exp()) / (1.0 - (-8.0f64).exp()))
        .collect();
    let grids = [
        geometric_radii(),
        albedo,
        (0..10).map(|j| j as f64 * 10f64.to_radians()).collect(),
        uneven_nodes(),
        vec![0.0, 1.0],
        vec![3.0, 3.5, 7.0, 1e6],
        vec![-2.0, -0.5, 0.0, 0.25, 4.0],
        vec![1e-300, 1e-200, 1.0, 1e200, 1e300],
        vec![0.0, 5e-324, 1e-320, 1e-310],
    ];
    let mut rng = SplitMix64::seed_from_u64(17);
    for grid in grids {
        let nodes = Nodes::new(grid.clone()).unwrap();
        let n = grid.len();
        let scan = |x: f64| (0..n - 1).rev().find(|&i| grid[i] <= x).unwrap_or(0);
        let (first, last) = (grid[0], grid[n - 1]);
        let mut points: Vec<f64> = grid.iter().flat_map(|&x| [x, next_up(x)]).collect();
        points.extend((0..2000).map(|_| first + (last - first) * rng.next_f64()));
        // Log-uniform points too, where the grid spans many octaves
        if first >= 0.0 {
            let low = grid.iter().copied().find(|&x| x > 0.0).unwrap();
            points.extend(
                (0..2000).map(|_| (low.ln() + (last.ln() - low.ln()) * rng.next_f64()).exp()),
            );
        }
        if first == 0.0 {
            points.push(-0.0);
        }
        for x in points.into_iter().filter(|x| (first..=last).contains(x)) {
            let got = nodes.weights(x).expect("inside the nodes").segment();
            assert_eq!(got, scan(x), "x = {x:e} on {grid:?}");
        }
    }
}

#[test]
fn out_of_range_and_nan_give_none() {
    let grid = uneven_nodes();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let values = |i: usize| 1.0 + grid[i];
    let cumulative = integrated(&nodes, &grid.iter().map(|x| 1.0 + x).collect::<Vec<_>>());
    for x in [
        -1e-300,
        2.0000000001,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ] {
        assert!(nodes.weights(x).is_none(), "x = {x}");
        assert!(nodes.evaluate(values, x).is_none());
        assert_eq!(nodes.pdf(values, |k| cumulative[k], x), 0.0);
    }
    assert_eq!(nodes.cdf(values, |k| cumulative[k], -1.0), Some(0.0));
    assert_eq!(nodes.cdf(values, |k| cumulative[k], 3.0), Some(1.0));
    assert_eq!(nodes.cdf(values, |k| cumulative[k], f64::NAN), None);
    for u in [f64::NAN, -1e-300, 1.0000001, f64::INFINITY] {
        assert!(
            nodes.sample(values, |k| cumulative[k], u).is_none(),
            "u = {u}"
        );
    }
    assert!(nodes.invert(values, f64::NAN).is_none());
}

#[test]
fn integrate_linear_data_gives_the_trapezoid_rule() {
    let grid = uneven_nodes();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let values: Vec<f64> = grid.iter().map(|x| 3.0 - x).collect();
    let cumulative = integrated(&nodes, &values);
    let mut trapezoid = 0.0;
    for k in 0..grid.len() {
        if k > 0 {
            trapezoid += 0.5 * (values[k - 1] + values[k]) * (grid[k] - grid[k - 1]);
        }
        assert!((cumulative[k] - trapezoid).abs() < EXACT, "C[{k}]");
    }
    assert_eq!(cumulative[0], 0.0);
    assert!((cumulative[grid.len() - 1] - (6.0 - 2.0)).abs() < EXACT);
}

#[test]
fn integrate_matches_quadrature_of_the_interpolant() {
    for (grid, seed) in [(uneven_nodes(), 4), (geometric_radii(), 5)] {
        let nodes = Nodes::new(grid.clone()).unwrap();
        let mut rng = SplitMix64::seed_from_u64(seed);
        let values: Vec<f64> = grid.iter().map(|_| rng.next_f64() - 0.2).collect();
        let mut cumulative = vec![0.0; grid.len()];
        let total = nodes.integrate(|i| values[i], &mut cumulative).unwrap();
        let spline = |x: f64| nodes.evaluate(|i| values[i], x).unwrap();
        let mut quadrature = 0.0;
        for k in 1..grid.len() {
            // Simpson is exact for the cubic on each segment; 64 panels guard the claim.
            quadrature += simpson(spline, grid[k - 1], grid[k], 64);
            let scale = 1.0 + quadrature.abs();
            assert!((cumulative[k] - quadrature).abs() < 1e-12 * scale, "C[{k}]");
        }
        assert_eq!(total, cumulative[grid.len() - 1]);
    }
    let nodes = Nodes::new(uneven_nodes()).unwrap();
    assert!(nodes.integrate(|_| 1.0, &mut [0.0; 3]).is_none());
}

#[test]
fn sampling_linear_density_matches_the_analytic_inverse() {
    // f(x) = 1 + 3x on [0, 2]: the spline is exactly linear, CDF(x) = (x + 1.5x²)/8,
    // so x(u) = (−1 + √(1 + 48u))/3 and pdf = (1 + 3x)/8.
    let grid = uneven_nodes();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let values: Vec<f64> = grid.iter().map(|x| 1.0 + 3.0 * x).collect();
    let cumulative = integrated(&nodes, &values);
    for k in 0..=1000 {
        let u = k as f64 / 1000.0;
        let s = nodes.sample(|i| values[i], |i| cumulative[i], u).unwrap();
        let x = (-1.0 + (1.0 + 48.0 * u).sqrt()) / 3.0;
        assert!((s.x - x).abs() < SOLVED, "u = {u}: x = {}, exact {x}", s.x);
        assert!((s.pdf - (1.0 + 3.0 * x) / 8.0).abs() < SOLVED);
        assert!((s.value - (1.0 + 3.0 * x)).abs() < SOLVED);
    }
}

#[test]
fn chi_square_exponential_profile_on_geometric_grid() {
    let grid = geometric_radii();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let values: Vec<f64> = grid.iter().map(|&r| radial_profile(r)).collect();
    let cumulative = integrated(&nodes, &values);
    let (f, c) = (|i: usize| values[i], |k: usize| cumulative[k]);
    chi_square(
        &grid,
        0x5eed_0001,
        4,
        |u| nodes.sample(f, c, u).map(|s| s.x),
        |x| nodes.pdf(f, c, x),
    );
}

#[test]
fn chi_square_peaked_density() {
    // A Lorentzian of half-width 0.002 at 0.6 on nodes clustered around it; the peak is
    // 10⁵ times the density at x = 0.
    let grid: Vec<f64> = (0..=80)
        .map(|i| {
            let s = -1.0 + 1.7 * i as f64 / 80.0;
            0.6 + 0.6 * s * s * s
        })
        .collect();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let values: Vec<f64> = grid
        .iter()
        .map(|x| 1.0 / (1.0 + ((x - 0.6) / 0.002).powi(2)))
        .collect();
    let cumulative = integrated(&nodes, &values);
    let (f, c) = (|i: usize| values[i], |k: usize| cumulative[k]);
    chi_square(
        &grid,
        0x5eed_0002,
        4,
        |u| nodes.sample(f, c, u).map(|s| s.x),
        |x| nodes.pdf(f, c, x),
    );
}

/// A 2D table over (albedo, r) stored as f32, rows 2πr·ρ·e^{−(1.2 − 0.4ρ)r}, and its CDFs.
/// The decay rates differ little between rows, so interpolated rows stay positive (except
/// beyond r ≈ 50, at 10⁻¹⁹ of the peak).
fn albedo_table() -> (Nodes, Nodes, Vec<f32>, Vec<f32>) {
    let albedo = Nodes::new(vec![0.0, 0.3, 0.6, 0.8, 0.9, 0.95, 1.0]).unwrap();
    let radius = Nodes::new(geometric_radii()).unwrap();
    let (mut profile, mut cdf) = (Vec::new(), Vec::new());
    for &a in albedo.as_slice() {
        let row: Vec<f64> = radius
            .as_slice()
            .iter()
            .map(|&r| 2.0 * std::f64::consts::PI * r * a * (-(1.2 - 0.4 * a) * r).exp())
            .collect();
        profile.extend(row.iter().map(|&v| v as f32));
        cdf.extend(integrated(&radius, &row).iter().map(|&v| v as f32));
    }
    (albedo, radius, profile, cdf)
}

#[test]
fn chi_square_row_interpolated_f32_table() {
    let (albedo, radius, profile, cdf) = albedo_table();
    let n = radius.as_slice().len();
    let w = albedo.weights(0.73).unwrap();
    let row = |j: usize| w.apply(|i| f64::from(profile[i * n + j]));
    let row_cdf = |j: usize| w.apply(|i| f64::from(cdf[i * n + j]));
    chi_square(
        radius.as_slice(),
        0x5eed_0003,
        4,
        |u| radius.sample(row, row_cdf, u).map(|s| s.x),
        |x| radius.pdf(row, row_cdf, x),
    );
}

#[test]
fn row_interpolated_sampling_matches_an_explicit_row() {
    let (albedo, radius, profile, cdf) = albedo_table();
    let n = radius.as_slice().len();
    let w = albedo.weights(0.85).unwrap();
    let row = |j: usize| w.apply(|i| f64::from(profile[i * n + j]));
    let row_cdf = |j: usize| w.apply(|i| f64::from(cdf[i * n + j]));
    // The same row materialized, with its CDF integrated in f64 rather than interpolated.
    let explicit: Vec<f64> = (0..n).map(row).collect();
    let explicit_cdf = integrated(&radius, &explicit);
    let mut rng = SplitMix64::seed_from_u64(6);
    let (mut worst_u, mut worst_pdf) = (0.0_f64, 0.0_f64);
    for _ in 0..10_000 {
        let u = rng.next_f64();
        let a = radius.sample(row, row_cdf, u).unwrap();
        let b = radius
            .sample(|j| explicit[j], |k| explicit_cdf[k], u)
            .unwrap();
        // The two CDFs differ by the f32 rounding of the stored table: compare in u.
        let u_explicit = radius
            .cdf(|j| explicit[j], |k| explicit_cdf[k], a.x)
            .unwrap();
        worst_u = worst_u.max((u_explicit - u).abs());
        worst_pdf = worst_pdf.max((a.pdf - b.pdf).abs() / b.pdf);
    }
    // Measured: 5·10⁻⁸ in u; 4·10⁻³ in the pdf, in tail segments whose mass is comparable to
    // the f32 rounding of C and which are therefore rescaled the most.
    assert!(worst_u < 1e-6, "u differs by {worst_u}");
    assert!(worst_pdf < 1e-2, "pdf differs by {worst_pdf} relative");
}

#[test]
fn sample_pdf_and_cdf_round_trip() {
    let grid = geometric_radii();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let values: Vec<f64> = grid.iter().map(|&r| radial_profile(r)).collect();
    let f = |i: usize| values[i];
    let signed = integrated(&nodes, &values);
    let mut positive = vec![0.0; grid.len()];
    let total = nodes.integrate_positive(f, &mut positive).unwrap();
    for cumulative in [&signed, &positive] {
        let c = |k: usize| cumulative[k];
        let mut rng = SplitMix64::seed_from_u64(7);
        let edges = [1e-12, 0.5, 1.0 - f64::EPSILON, 1.0 - 1e-12];
        for u in (0..10_000).map(|_| rng.next_f64()).chain(edges) {
            let s = nodes.sample(f, c, u).unwrap();
            assert!(s.x >= 0.0 && s.x <= grid[63]);
            assert!(
                (nodes.cdf(f, c, s.x).unwrap() - u).abs() < SOLVED,
                "u = {u}"
            );
            assert!(
                (nodes.pdf(f, c, s.x) - s.pdf).abs() < 1e-9 * s.pdf,
                "u = {u}"
            );
        }
        // The density is 0 at r = 0, so u = 0 has nothing to return.
        assert!(nodes.sample(f, c, 0.0).is_none());
    }
    // With the positive-part CDF the density is exactly max(s, 0)/T.
    let mut rng = SplitMix64::seed_from_u64(8);
    for _ in 0..10_000 {
        let s = nodes.sample(f, |k| positive[k], rng.next_f64()).unwrap();
        assert!((s.pdf - s.value / total).abs() < 1e-9 * s.pdf);
    }
}

#[test]
fn integrate_positive_integrates_the_positive_part() {
    let grid = geometric_radii();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let values: Vec<f64> = grid.iter().map(|&r| radial_profile(r)).collect();
    let f = |i: usize| values[i];
    let signed = integrated(&nodes, &values);
    let mut positive = vec![0.0; grid.len()];
    nodes.integrate_positive(f, &mut positive).unwrap();
    let clamped = |x: f64| nodes.evaluate(f, x).unwrap().max(0.0);
    let mut undershoots = 0;
    for k in 1..grid.len() {
        let (a, b) = (grid[k - 1], grid[k]);
        let exact = positive[k] - positive[k - 1];
        // A kink where the spline crosses 0 limits Simpson to O(h²): use many panels.
        let quadrature = simpson(clamped, a, b, 20_000);
        assert!(exact >= 0.0);
        assert!(
            (exact - quadrature).abs() <= 1e-9 * positive[63],
            "segment {k}"
        );
        let net = signed[k] - signed[k - 1];
        if net < exact {
            undershoots += 1;
        } else {
            assert!((net - exact).abs() <= EXACT * positive[63], "segment {k}");
        }
    }
    assert!(
        undershoots > 0,
        "the profile's tail undershoots on this grid"
    );
}

#[test]
fn invert_round_trip() {
    // Effective albedo ρ_eff against albedo ρ, pbrt's g = 0, η = 1.33 table at selected nodes.
    let rho = vec![
        0.0, 0.0777, 0.5545, 0.8016, 0.9118, 0.9609, 0.98274, 0.99249, 0.99878, 0.99964, 0.99994,
        1.0,
    ];
    let rho_eff = [
        0.0, 0.00608, 0.0795, 0.1869, 0.3167, 0.4572, 0.5925, 0.7108, 0.8849, 0.9491, 0.9968,
        1.0193,
    ];
    let nodes = Nodes::new(rho.clone()).unwrap();
    let f = |i: usize| rho_eff[i];
    let mut previous = f64::NEG_INFINITY;
    let mut rng = SplitMix64::seed_from_u64(8);
    let mut xs: Vec<f64> = (0..2000).map(|_| rng.next_f64()).collect();
    xs.sort_by(f64::total_cmp);
    for x in xs {
        let y = nodes.evaluate(f, x).unwrap();
        assert!(
            y > previous,
            "the spline must increase for the test to hold"
        );
        previous = y;
        let back = nodes.invert(f, y).unwrap();
        // Compare in y: the spline is steep near ρ = 1, where x is poorly conditioned.
        let y_back = nodes.evaluate(f, back).unwrap();
        assert!((y_back - y).abs() < SOLVED, "x = {x}, back {back}");
    }
    for (i, &r) in rho.iter().enumerate() {
        assert_eq!(nodes.invert(f, rho_eff[i]).unwrap(), r, "node {i}");
    }
    assert_eq!(nodes.invert(f, -0.5).unwrap(), 0.0);
    assert_eq!(nodes.invert(f, 7.0).unwrap(), 1.0);
}

#[test]
fn all_zero_values_neither_sample_nor_panic() {
    let grid = uneven_nodes();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let zero = |_: usize| 0.0;
    let mut cumulative = vec![0.0; grid.len()];
    assert_eq!(nodes.integrate(zero, &mut cumulative), Some(0.0));
    let c = |k: usize| cumulative[k];
    for u in [0.0, 0.5, 1.0 - f64::EPSILON, 1.0] {
        assert!(nodes.sample(zero, c, u).is_none());
    }
    assert_eq!(nodes.pdf(zero, c, 1.0), 0.0);
    assert_eq!(nodes.cdf(zero, c, 1.0), None);
    assert_eq!(nodes.evaluate(zero, 1.0), Some(0.0));
    assert_eq!(nodes.invert(zero, 0.0), Some(0.0));
    assert_eq!(nodes.invert(zero, 1.0), Some(2.0));
}

#[test]
fn two_nodes_give_a_linear_spline() {
    let nodes = Nodes::new(vec![1.0, 3.0]).unwrap();
    let values = [2.0, 0.5];
    let f = |i: usize| values[i];
    assert_eq!(nodes.weights(2.0).unwrap().as_array(), [0.0, 0.5, 0.5, 0.0]);
    assert!((nodes.evaluate(f, 1.5).unwrap() - 1.625).abs() < EXACT);
    let mut cumulative = [0.0; 2];
    assert!((nodes.integrate(f, &mut cumulative).unwrap() - 2.5).abs() < EXACT);
    // Density (2 − 0.75(x − 1))/2.5: CDF = (2y − 0.375y²)/2.5 with y = x − 1.
    for u in [0.0, 0.25, 0.5, 0.999_999, 1.0] {
        let s = nodes.sample(f, |k| cumulative[k], u).unwrap();
        let y = (2.0 - (4.0 - 3.75 * u).sqrt()) / 0.75;
        assert!((s.x - (1.0 + y)).abs() < SOLVED, "u = {u}");
    }
    assert_eq!(nodes.sample(f, |k| cumulative[k], 0.0).unwrap().x, 1.0);
    assert_eq!(nodes.sample(f, |k| cumulative[k], 1.0).unwrap().x, 3.0);
    let increasing = |i: usize| [0.5, 2.0][i];
    assert!((nodes.invert(increasing, 1.0).unwrap() - (1.0 + 2.0 / 3.0)).abs() < SOLVED);
}

/// Values 10⁻³ with a spike of 1 at node 10 of `uneven_nodes`: the spline dips below zero
/// on both sides of the spike.
fn spike() -> (Vec<f64>, Vec<f64>) {
    let grid = uneven_nodes();
    let values = (0..grid.len())
        .map(|i| if i == 10 { 1.0 } else { 1e-3 })
        .collect();
    (grid, values)
}

#[test]
fn undershooting_spline_yields_only_valid_samples() {
    let (grid, values) = spike();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let f = |i: usize| values[i];
    assert!(nodes.evaluate(f, 0.5 * (grid[8] + grid[9])).unwrap() < 0.0);
    let cumulative = integrated(&nodes, &values);
    let c = |k: usize| cumulative[k];
    let mut rng = SplitMix64::seed_from_u64(9);
    for _ in 0..10_000 {
        let u = rng.next_f64();
        let s = nodes.sample(f, c, u).unwrap();
        assert!(s.pdf > 0.0 && s.pdf.is_finite() && s.value > 0.0);
        assert!((nodes.cdf(f, c, s.x).unwrap() - u).abs() < SOLVED);
    }
    for k in 0..=2000 {
        let x = 2.0 * k as f64 / 2000.0;
        let p = nodes.pdf(f, c, x);
        assert!(p >= 0.0 && p.is_finite());
        let u = nodes.cdf(f, c, x).unwrap();
        assert!((0.0..=1.0).contains(&u));
    }
}

#[test]
fn chi_square_undershooting_spike() {
    let (grid, values) = spike();
    let nodes = Nodes::new(grid.clone()).unwrap();
    let mut cumulative = vec![0.0; grid.len()];
    nodes
        .integrate_positive(|i| values[i], &mut cumulative)
        .unwrap();
    let (f, c) = (|i: usize| values[i], |k: usize| cumulative[k]);
    chi_square(
        &grid,
        0x5eed_0004,
        8,
        |u| nodes.sample(f, c, u).map(|s| s.x),
        |x| nodes.pdf(f, c, x),
    );
}

#[test]
fn arbitrary_inputs_neither_panic_nor_return_nan() {
    let mut rng = SplitMix64::seed_from_u64(10);
    let specials = [
        0.0,
        -0.0,
        1e-300,
        -1e-300,
        1e300,
        -1e300,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    let pick = |rng: &mut SplitMix64, scale: f64| match rng.next_u64() % 4 {
        0 => specials[(rng.next_u64() % specials.len() as u64) as usize],
        _ => scale * (rng.next_f64() - 0.3),
    };
    for _ in 0..200_000 {
        let n = 2 + (rng.next_u64() % 8) as usize;
        let mut grid = vec![rng.next_f64() - 0.5];
        for _ in 1..n {
            let gap = 10f64.powf(12.0 * rng.next_f64() - 6.0);
            grid.push(grid[grid.len() - 1] + gap);
        }
        let end = [End::Chord, End::Even][(rng.next_u64() % 2) as usize];
        let nodes = Nodes::new(grid.clone()).unwrap().with_end(end);
        let (first, last) = (grid[0], grid[n - 1]);
        let values: Vec<f64> = (0..n).map(|_| pick(&mut rng, 10.0)).collect();
        let f = |i: usize| values[i];
        let mut cumulative = vec![0.0; n];
        let _ = nodes.integrate_positive(f, &mut cumulative);
        let c = |k: usize| cumulative[k];
        let span = last - first;
        let x = first + span * pick(&mut rng, 1.5);
        if let Some(w) = nodes.weights(x) {
            assert!(w.iter().all(|(j, wk)| j < n && wk.is_finite()));
            assert!((w.as_array().iter().sum::<f64>() - 1.0).abs() < 1e-9);
        }
        let p = nodes.pdf(f, c, x);
        assert!(p >= 0.0 && p.is_finite(), "pdf {p}");
        if let Some(u) = nodes.cdf(f, c, x) {
            assert!((0.0..=1.0).contains(&u), "cdf {u}");
        }
        if let Some(s) = nodes.sample(f, c, pick(&mut rng, 1.5)) {
            assert!(s.x >= first && s.x <= last, "x {} outside", s.x);
            assert!(s.pdf > 0.0 && s.pdf.is_finite() && s.value > 0.0, "{s:?}");
        }
        if let Some(x) = nodes.invert(f, pick(&mut rng, 10.0)) {
            assert!(x >= first && x <= last, "inverted to {x}");
        }
    }
}
