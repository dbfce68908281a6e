//! [`Nodes::weights`] and [`Nodes::find_segment`] against a straightforward reference (a plain
//! binary search and the weight formula as written before the keyed cells), bit for bit, on
//! the default table's axes and on irregular node sets, with either [`End`], at every node,
//! the floats next to each, random points, the ends, outside, NaN, ±∞ and ±0.

use super::{even_slopes, End, Nodes, Slope, Span, EVEN_SLOPE_RATIOS};
use crate::float::{next_down, next_up};
use bssrdf_zoo::rng::{RngCore, SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{Grid, GridPreset};

/// Segment and weights by the reference: segment i = the number of nodes x₁ … x_{n−2} that are
/// ≤ v, then the formula with its end branches, all factors computed on the spot (the even
/// end's slope at x_{n−2} by [`even_slopes`], which `even_slopes_are_the_even_quartics` checks).
fn reference(x: &[f64], end: End, v: f64) -> Option<(usize, [f64; 4])> {
    let n = x.len();
    if v.is_nan() || v < x[0] || v > x[n - 1] {
        return None;
    }
    let i = x[1..n - 1].partition_point(|&xi| xi <= v);
    let width = x[i + 1] - x[i];
    let t = ((v - x[i]) * (1.0 / width)).clamp(0.0, 1.0);
    let (t2, t3) = (t * t, t * t * t);
    let mut w = [0.0, 2.0 * t3 - 3.0 * t2 + 1.0, -2.0 * t3 + 3.0 * t2, 0.0];
    let (h10, h11) = (t3 - 2.0 * t2 + t, t3 - t2);
    let rho = (n >= 3).then(|| (x[n - 1] - x[n - 2]) / (x[n - 1] - x[n - 3]));
    let even = rho
        .filter(|rho| end == End::Even && EVEN_SLOPE_RATIOS.contains(rho))
        .map(even_slopes);
    if let (Some([_, k]), true) = (even, i + 2 == n) {
        for (w, k) in w[..3].iter_mut().zip(k) {
            *w += h10 * k;
        }
    } else if i > 0 {
        let s0 = width / (x[i + 1] - x[i - 1]);
        w[0] -= h10 * s0;
        w[2] += h10 * s0;
    } else {
        w[1] -= h10;
        w[2] += h10;
    }
    if let (Some([k, _]), true) = (even, i + 3 == n) {
        for (w, k) in w[1..].iter_mut().zip(k) {
            *w += h11 * k;
        }
    } else if i + 2 < n {
        let s1 = width / (x[i + 2] - x[i]);
        w[1] -= h11 * s1;
        w[3] += h11 * s1;
    } else if end == End::Chord {
        w[1] -= h11;
        w[2] += h11;
    }
    Some((i, w))
}

#[test]
fn even_slopes_are_the_even_quartics() {
    // Nodes 0 < δ₁ < δ₂ before a = 0 (x = −δ): the slope at x_{n−2} = −δ₁ of the quadratic in
    // v = x² through (0, f₁), (δ₁², f₂), (δ₂², f₃), solved as a 2×2 system, per unit x, against
    // the weights times the values, divided by each segment's width
    let mut rng = SplitMix64::seed_from_u64(3);
    for _ in 0..10_000 {
        let d1 = 0.01 + rng.next_f64();
        let d2 = d1 / (0.25 + 0.5 * rng.next_f64());
        let f = [rng.next_f64(), rng.next_f64(), rng.next_f64()]; // f_{n−3}, f_{n−2}, f_{n−1}
        let (v1, v2) = (d1 * d1, d2 * d2);
        let (r1, r2) = (f[1] - f[2], f[0] - f[2]);
        let det = v1 * v2 * v2 - v2 * v1 * v1;
        let a = (r1 * v2 * v2 - r2 * v1 * v1) / det;
        let b = (v1 * r2 - v2 * r1) / det;
        // dP/dx = dP/dv · dv/dx, v = x², at x = −δ₁
        let want = (a + 2.0 * b * v1) * (-2.0 * d1);
        let [before, last] = even_slopes(d1 / d2);
        let dot = |k: [f64; 3]| k[0] * f[0] + k[1] * f[1] + k[2] * f[2];
        let scale = f.iter().map(|f| f.abs()).sum::<f64>() / d1 * (d2 / (d2 - d1)).powi(2);
        for (got, width) in [(dot(before), d2 - d1), (dot(last), d1)] {
            assert!(
                (got / width - want).abs() < 1e-11 * scale,
                "δ = ({d1}, {d2}): {} vs {want}",
                got / width
            );
        }
    }
}

/// The default grid's axes (and the coarse and fine ones), f32-rounded as the bake stores them.
fn table_axes() -> Vec<Vec<f64>> {
    let round = |v: &[f64]| v.iter().map(|&x| f64::from(x as f32)).collect::<Vec<_>>();
    [GridPreset::Default, GridPreset::Coarse, GridPreset::Fine]
        .into_iter()
        .flat_map(|preset| {
            let grid = Grid::preset(preset);
            [round(&grid.rho), round(&grid.theta), round(&grid.r)]
        })
        .collect()
}

/// Irregular node sets: random, crowded to adjacent f32 (and f64) values, two nodes,
/// negative, through −0, huge and tiny magnitudes, ranges that overflow.
fn irregular() -> Vec<Vec<f64>> {
    let mut rng = SplitMix64::seed_from_u64(2024);
    let mut sets = vec![
        vec![0.0, 1.0],
        vec![-1.0, 1.0],
        vec![5.0, 5.000_001],
        vec![-10.0, -3.0, -2.5, -0.1],
        vec![-2.0, -0.5, 0.0, 0.25, 4.0],
        vec![-1.0, -0.0, 1.0],
        vec![-3.0, -1.0, -0.0],
        vec![1e-300, 1e-200, 1.0, 1e200, 1e300],
        vec![0.0, 5e-324, 1e-320, 1e-310],
        vec![0.0, 5e-324, 1e-323, 1.5e-323, 1.0],
        vec![-1e308, 0.0, 1e308],
        vec![-f64::MAX, -1.0, 1.0, f64::MAX],
        vec![f64::MAX / 4.0, f64::MAX / 2.0, f64::MAX],
        // Segment 1 is so wide that 1/w is subnormal: t reaches 1.0000000000000002 unclamped
        vec![
            -7e307,
            -6.510_109_008_848_191e307,
            6.031_484_485_984_507e307,
            6.5e307,
            6.9e307,
            7e307,
        ],
        vec![1e6, 1e6 + 0.5, 1e6 + 3.0, 2e6],
        vec![3.0, 3.5, 7.0, 1e6],
        // The even end's ratios ρ = δ₁/δ₂ at the ends of `EVEN_SLOPE_RATIOS`: ¼ and ¾
        vec![0.0, 3.0, 4.0],
        vec![0.0, 1.0, 4.0],
    ];
    // Adjacent f32 values, then gaps, as f32-rounded axes with duplicates merged would give
    let f32_run = |start: f32, len: usize| {
        let mut v = vec![start];
        for _ in 1..len {
            let last = *v.last().expect("nonempty");
            v.push(f32::from_bits(last.to_bits() + 1));
        }
        v.into_iter().map(f64::from).collect::<Vec<_>>()
    };
    sets.push(f32_run(1.0, 12));
    let mut mixed = f32_run(0.25, 5);
    mixed.extend([0.5, 0.75]);
    mixed.extend(f32_run(0.8, 4));
    mixed.extend([1.0, 2.0, 64.0]);
    sets.push(mixed);
    // Adjacent f64 values (no key separates them: the guide or the binary search does)
    sets.push(
        (0..8)
            .map(|k| f64::from_bits(1.0f64.to_bits() + k))
            .collect(),
    );
    // Random increasing sets of many sizes and spreads
    for (size, scale) in [
        (3, 1.0),
        (7, 1e-3),
        (20, 1e3),
        (50, 1.0),
        (200, 10.0),
        (1000, 1.0),
    ] {
        for _ in 0..4 {
            let offset = scale * (rng.next_f64() - 0.5) * 4.0;
            let mut v: Vec<f64> = (0..size)
                .map(|_| offset + scale * rng.next_f64().powi(3))
                .collect();
            v.sort_by(f64::total_cmp);
            v.dedup();
            sets.push(v);
        }
    }
    // Random geometric grids with a 0 in front
    for _ in 0..4 {
        let (start, ratio) = (1e-3 * rng.next_f64() + 1e-6, 1.01 + rng.next_f64());
        sets.push(
            std::iter::once(0.0)
                .chain((0..40).map(|k| start * ratio.powi(k)))
                .filter(|x| x.is_finite())
                .collect(),
        );
    }
    sets
}

/// Points to test on nodes `x`: each node and its neighbours, midpoints, random points
/// (uniform, and log-uniform where the nodes are positive), the ends and beyond, NaN, ±∞, ±0.
fn points(x: &[f64], rng: &mut SplitMix64) -> Vec<f64> {
    let (first, last) = (x[0], x[x.len() - 1]);
    let mut p: Vec<f64> = x
        .iter()
        .flat_map(|&xi| [xi, next_down(xi), next_up(xi), -xi])
        .collect();
    p.extend(x.windows(2).map(|w| w[0] + 0.5 * (w[1] - w[0])));
    let range = last - first;
    p.extend((0..2000).map(|_| {
        let v = first + range * rng.next_f64();
        if v.is_finite() {
            v.clamp(first, last)
        } else {
            first * (1.0 - rng.next_f64()) + last * rng.next_f64()
        }
    }));
    if first >= 0.0 {
        let low = x.iter().copied().find(|&v| v > 0.0).unwrap_or(last);
        p.extend((0..2000).map(|_| (low.ln() + (last.ln() - low.ln()) * rng.next_f64()).exp()));
    }
    p.extend([
        first - 1.0,
        last + 1.0,
        2.0 * first,
        2.0 * last,
        f64::NAN,
        -f64::NAN,
        f64::from_bits(0x7ff0_0000_0000_0001),
        f64::INFINITY,
        f64::NEG_INFINITY,
        0.0,
        -0.0,
        f64::MIN_POSITIVE,
        5e-324,
        -5e-324,
        f64::MAX,
        -f64::MAX,
    ]);
    p
}

/// Bit patterns of a result, so that −0 differs from +0 and NaNs compare (as one NaN: Rust
/// leaves the sign and payload of an operation's NaN unspecified).
fn bits(result: Option<(usize, [f64; 4])>) -> Option<(usize, [u64; 4])> {
    let canonical = |w: f64| if w.is_nan() { f64::NAN } else { w }.to_bits();
    result.map(|(i, w)| (i, w.map(canonical)))
}

#[test]
fn weights_and_segments_match_the_reference_bit_for_bit() {
    let mut rng = SplitMix64::seed_from_u64(7);
    let sets: Vec<Vec<f64>> = table_axes().into_iter().chain(irregular()).collect();
    let (mut with_cells, mut hot_points) = (0, 0);
    for x in &sets {
        let chord = Nodes::new(x.clone()).expect("increasing finite nodes");
        with_cells += usize::from(!chord.cells.is_empty());
        for nodes in [chord.clone(), chord.with_end(End::Even)] {
            let end = nodes.end();
            for v in points(x, &mut rng) {
                let want = reference(x, end, v);
                let got = nodes.weights(v).map(|w| (w.segment(), w.as_array()));
                assert_eq!(
                    bits(got),
                    bits(want),
                    "x = {v:e} ({:#x}) on {x:?}, {end:?}",
                    v.to_bits()
                );
                assert_eq!(nodes.find_segment(v), want.map(|(i, _)| i), "x = {v:e}");
                // The hot cells' weights alone, where there are any: the same bits
                if let Some(hot) = nodes.hot_weights(v) {
                    hot_points += 1;
                    let hot = Some((hot.segment(), hot.as_array()));
                    assert_eq!(bits(hot), bits(want), "hot x = {v:e} on {x:?}, {end:?}");
                }
            }
        }
    }
    // The table's axes all take the keyed cells; some irregular sets do not
    assert!(with_cells >= table_axes().len() && with_cells < sets.len());
    assert!(hot_points > 1000, "{hot_points}");
}

#[test]
fn interior_weights_match_the_general_formula_bit_for_bit() {
    let mut rng = SplitMix64::seed_from_u64(11);
    let special = [
        0.0,
        -0.0,
        5e-324,
        1e-310,
        f64::MIN_POSITIVE,
        1e-160,
        1.5e-154,
        1e-100,
        f64::EPSILON,
        0.5,
        next_down(1.0),
        1.0,
    ];
    let random = (0..200_000).map(|k| match k % 3 {
        0 => rng.next_f64(),
        // Random bit patterns over [0, 1]: every binade, subnormals included
        1 => f64::from_bits(rng.next_u64() % 0x3ff0_0000_0000_0001),
        _ => 1.0 - rng.next_f64() * 1e-6,
    });
    let factors = [
        0.0,
        5e-324,
        1e-300,
        0.25,
        1.0 / 3.0,
        0.5,
        next_down(1.0),
        1.0,
    ];
    for t in special.into_iter().chain(random) {
        let s0 = factors[(t.to_bits() % 8) as usize];
        let s1 = factors[((t.to_bits() >> 3) % 8) as usize];
        for (s0, s1) in [(s0, s1), (0.5, 0.5), (1.0, 0.2)] {
            let span = Span {
                x0: 0.0,
                inv_width: 1.0,
                s0,
                s1,
            };
            let (got, want) = (
                span.interior_weights(t),
                span.weights(t, Slope::Central, Slope::Central),
            );
            assert_eq!(
                got.map(f64::to_bits),
                want.map(f64::to_bits),
                "t = {t:e}, s0 = {s0:e}, s1 = {s1:e}"
            );
        }
    }
}
