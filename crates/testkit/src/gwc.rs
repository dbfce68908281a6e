//! Helpers shared by the GWC integration tests: the seeded RNG and adaptive quadrature.

/// The crate's own generator (SplitMix64), seeded per test.
pub use bssrdf_zoo::rng::SplitMix64;
use bssrdf_zoo::rng::UnitF64;

/// Uniform draws in a range from the crate's generator.
pub trait UniformRange {
    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f64, hi: f64) -> f64;
}

impl UniformRange for SplitMix64 {
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

/// Adaptive Simpson quadrature of `f` over [a, b] to absolute tolerance `tol`.
pub fn simpson(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let m = 0.5 * (a + b);
    let (fa, fm, fb) = (f(a), f(m), f(b));
    let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    simpson_step(f, a, b, fa, fm, fb, whole, tol, 60)
}

#[allow(clippy::too_many_arguments)]
fn simpson_step(
    f: &dyn Fn(f64) -> f64,
    a: f64,
    b: f64,
    fa: f64,
    fm: f64,
    fb: f64,
    whole: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let m = 0.5 * (a + b);
    let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
    let (flm, frm) = (f(lm), f(rm));
    let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    let delta = left + right - whole;
    if depth == 0 || delta.abs() <= 15.0 * tol {
        return left + right + delta / 15.0;
    }
    simpson_step(f, a, m, fa, flm, fm, left, 0.5 * tol, depth - 1)
        + simpson_step(f, m, b, fm, frm, fb, right, 0.5 * tol, depth - 1)
}

/// ∫_a^b f with the interval split at 0 and ±π/2, where GWC lobes peak or bend.
pub fn integrate(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    let mut cuts = vec![a];
    for x in [
        -std::f64::consts::FRAC_PI_2,
        0.0,
        std::f64::consts::FRAC_PI_2,
    ] {
        if x > a && x < b {
            cuts.push(x);
        }
    }
    cuts.push(b);
    let n = (cuts.len() - 1) as f64;
    cuts.windows(2)
        .map(|w| simpson(f, w[0], w[1], tol / n))
        .sum()
}

/// χ² statistic and its degrees of freedom for 200,000 draws of `draw` against `pdf` (a density
/// in φ over [−π, π]). Bins are equiprobable under the wrapped Cauchy lobe of concentration
/// `c` (edges cdf_WC⁻¹(i/64; c)), so a narrow peak there is resolved; expected counts come from
/// quadrature of the pdf, and bins expecting fewer than 5 are pooled.
pub fn chi_square(c: f64, pdf: &dyn Fn(f64) -> f64, draw: &mut dyn FnMut() -> f64) -> (f64, usize) {
    const SAMPLES: usize = 200_000;
    const BINS: usize = 64;
    let edges: Vec<f64> = (0..=BINS)
        .map(|i| bssrdf_zoo::gwc::inv_cdf_wc(i as f64 / BINS as f64, c))
        .collect();
    let mut counts = [0usize; BINS];
    for _ in 0..SAMPLES {
        let phi = draw();
        let bin = edges.partition_point(|&e| e <= phi).clamp(1, BINS) - 1;
        counts[bin] += 1;
    }
    let (mut chi2, mut cells) = (0.0, 0);
    let (mut pooled_obs, mut pooled_exp) = (0.0, 0.0);
    for (i, &n) in counts.iter().enumerate() {
        let expected = SAMPLES as f64 * integrate(pdf, edges[i], edges[i + 1], 1e-12);
        if expected < 5.0 {
            pooled_obs += n as f64;
            pooled_exp += expected;
        } else {
            chi2 += (n as f64 - expected).powi(2) / expected;
            cells += 1;
        }
    }
    if pooled_exp > 0.0 {
        chi2 += (pooled_obs - pooled_exp).powi(2) / pooled_exp;
        cells += 1;
    }
    (chi2, cells - 1)
}
