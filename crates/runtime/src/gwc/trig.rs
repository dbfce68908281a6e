//! sin x on the quarter period [0, π/2], the only range the GWC profile asks for (half-angles
//! h = |φ|/2 and their complements, and π·m for tail masses m ≤ 1/2), as one polynomial.
//!
//! The library `sin` reduces any argument to a quarter period first and costs about 14 ns;
//! on [0, π/2] the Taylor series x·Σ (−x²)ᵏ/(2k + 1)! to k = 10 leaves a truncation error
//! below (π/2)²³/23! ≈ 1.3·10⁻¹⁸, under half an ulp of the result, and the terms fall fast
//! enough (the largest after x is x³/6 ≤ 0.65) that, with x added last and exactly, the sum
//! rounds to within 2 ulp. Two evaluations (sin h and cos h = sin(π/2 − h)) then cost less than
//! one library call. sin 0 is exactly 0, so cos h is exactly 0 at h = π/2 computed as
//! (π − |φ|)/2 = 0.
//!
//! The sines sit on the dependency chain of a draw (the sampler's inverse of the lobe's CDF
//! waits for the sines of its iterate), so the sum is grouped for latency: the two largest
//! terms by Horner's rule, the rest by Estrin's scheme (Estrin's all through rounds to 3 ulp
//! near π/2). Against Horner's rule all through, a draw takes 23 ns less and an evaluation
//! 3 ns (`examples/lookup_loop.rs`, min of 7 alternating runs: 401 → 378 ns, 92 → 89.5 ns).
//!
//! [`atan2_quadrant`] is atan2(y, x) for y, x ≥ 0, the only quadrant the profile asks for (the
//! half-angle of the inverse of the lobe's CDF, the lobe's tail mass), with one division to
//! reduce the argument and the rational approximation of Cephes' `atan.c` (S. L. Moshier,
//! 1984–1995: atan x = x + x·z·P(z)/Q(z), z = x², for |x| ≤ 0.66, relative error 2·10⁻¹⁶
//! there). Inlined, it halves the instructions of the inverse of the lobe's CDF
//! (`sample::LobePoint::at`: 525 → 273 per draw, the library's general atan2 taking about 135 a
//! call, 1.6 calls a draw); it is within 2 ulp of the library's over the quadrant (tested).

use std::f64::consts::FRAC_PI_2;

/// 1/(2k + 1)! with alternating signs, k = 0 … 10.
const TAYLOR: [f64; 11] = [
    1.0,
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5_040.0,
    1.0 / 362_880.0,
    -1.0 / 39_916_800.0,
    1.0 / 6_227_020_800.0,
    -1.0 / 1_307_674_368_000.0,
    1.0 / 355_687_428_096_000.0,
    -1.0 / 121_645_100_408_832_000.0,
    1.0 / 51_090_942_171_709_440_000.0,
];

/// sin x for x ∈ [0, π/2] (and, as accurately, for |x| ≤ π/2); outside that range the
/// truncation error grows like x²³/23! and callers must not rely on it.
#[inline(always)]
pub(super) fn sin_quarter(x: f64) -> f64 {
    let y = x * x;
    // Σ_{k=1}^{10} TAYLOR[k]·y^{k−1}: the two largest terms by Horner's rule, the small rest
    // by Estrin's scheme (pairs, then pairs of pairs), so the sum waits on six dependent steps
    // instead of nine; Estrin's rounding all through measured 3 ulp near π/2
    let t = &TAYLOR;
    let (y2, pair) = (y * y, |k: usize| t[k] + t[k + 1] * y);
    let rest = (pair(3) + pair(5) * y2) + (pair(7) + pair(9) * y2) * (y2 * y2);
    let p = t[1] + y * (t[2] + y * rest);
    // x + x³·(…): the leading term exact, the rounding only in a correction ≤ 0.36·x
    x + x * y * p
}

/// Cephes' `atan.c` numerator P(z), highest power first.
const ATAN_P: [f64; 5] = [
    -0.8750608600031904,
    -16.157537187333652,
    -75.00855792314705,
    -122.88666844901361,
    -64.85021904942025,
];

/// Cephes' `atan.c` denominator Q(z) = z⁵ + …, its lower coefficients highest power first.
const ATAN_Q: [f64; 5] = [
    24.858464901423062,
    165.02700983169885,
    432.88106049129027,
    485.3903996359137,
    194.5506571482614,
];

/// π/2 less its f64 rounding `FRAC_PI_2` (Cephes' MOREBITS): added after the small terms.
const PI_2_LOW: f64 = 6.123233995736766e-17;

/// atan2(y, x) ∈ [0, π/2] for y, x ≥ 0 (not both 0; (0, 0) gives 0, as the library's does),
/// within 2 ulp of the library's atan2. Reduced by one division to a = t − k·π/4 with
/// |tan a| ≤ 0.66 (k = 0 for y/x ≤ 0.66, 1 for y/x up to 1/0.66, 2 above), then Cephes'
/// rational approximation of atan on [−0.66, 0.66].
#[inline(always)]
pub(super) fn atan2_quadrant(y: f64, x: f64) -> f64 {
    const SPLIT: f64 = 0.66;
    // tan(t − kπ/4): y/x, (y − x)/(y + x) = (y/x − 1)/(y/x + 1), −x/y
    let (num, den, k) = if y <= SPLIT * x {
        (y, x, 0.0)
    } else if SPLIT * y < x {
        (y - x, y + x, 1.0)
    } else {
        (-x, y, 2.0)
    };
    let a = num / den.max(f64::MIN_POSITIVE);
    let z = a * a;
    let [p0, p1, p2, p3, p4] = ATAN_P;
    let [q0, q1, q2, q3, q4] = ATAN_Q;
    let p = (((p0 * z + p1) * z + p2) * z + p3) * z + p4;
    let q = ((((z + q0) * z + q1) * z + q2) * z + q3) * z + q4;
    let atan_a = a + a * (z * p / q);
    // k·π/4 in two parts, its low part added to the small terms first
    (k * 0.5) * FRAC_PI_2 + ((k * 0.5) * PI_2_LOW + atan_a)
}

#[cfg(test)]
mod tests {
    use super::{atan2_quadrant, sin_quarter};
    use std::f64::consts::FRAC_PI_2;

    /// Within 2 ulp of the library's atan2 over the quadrant: a dense grid of angles (as
    /// (sin, cos) pairs and as ratios of 1), the splits of the reduction and their neighbours,
    /// and the axes.
    #[test]
    fn atan2_quadrant_matches_the_library_to_two_ulp() {
        let n = 200_000;
        let angles = (0..=n).map(|i| FRAC_PI_2 * f64::from(i) / f64::from(n));
        let by_angle = angles.map(|t| (t.sin(), t.cos()));
        let ratios = (0..=n).flat_map(|i| {
            let r = f64::from(i) / f64::from(n) * 3.0;
            [(r, 1.0), (1.0, r), (1e-300 * r, 1e-300), (1e300, 1e300 * r)]
        });
        let splits = [0.66, 1.0 / 0.66, 1.0].into_iter().flat_map(|r: f64| {
            let (down, up) = (crate::float::next_down(r), crate::float::next_up(r));
            [
                (r, 1.0),
                (down, 1.0),
                (up, 1.0),
                (1.0, r),
                (1.0, down),
                (1.0, up),
            ]
        });
        let special = [
            (0.0, 1.0),
            (1.0, 0.0),
            (1e-300, 1.0),
            (1.0, 1e-300),
            (0.0, 0.0),
        ];
        for (y, x) in by_angle.chain(ratios).chain(splits).chain(special) {
            let (got, want) = (atan2_quadrant(y, x), y.atan2(x));
            let ulp = f64::from_bits(want.to_bits() + 1) - want;
            assert!(
                (got - want).abs() <= 2.0 * ulp,
                "atan2({y:e}, {x:e}) = {want:e}, got {got:e}"
            );
        }
    }

    /// Within 2 ulp of the library sin over the quarter period, including both ends, a dense
    /// grid and the neighbours of its end points; exact at 0.
    #[test]
    fn matches_the_library_sine_to_two_ulp() {
        assert_eq!(sin_quarter(0.0), 0.0);
        let n = 200_000;
        let grid = (0..=n).map(|i| FRAC_PI_2 * f64::from(i) / f64::from(n));
        let special = [
            1e-300,
            f64::MIN_POSITIVE,
            1e-8,
            FRAC_PI_2,
            f64::from_bits(FRAC_PI_2.to_bits() - 1),
            0.5 * std::f64::consts::PI * 0.5,
        ];
        for x in grid.chain(special) {
            let (got, want) = (sin_quarter(x), x.sin());
            let ulp = f64::from_bits(want.to_bits() + 1) - want;
            assert!(
                (got - want).abs() <= 2.0 * ulp,
                "sin({x:e}) = {want:e}, got {got:e}"
            );
        }
    }

    /// Odd: sin(−x) = −sin(x) exactly (the polynomial is odd).
    #[test]
    fn is_odd() {
        for i in 0..1000 {
            let x = 1.5 * f64::from(i) / 1000.0;
            assert_eq!(sin_quarter(-x), -sin_quarter(x));
        }
    }
}
