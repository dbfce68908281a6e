//! Statistics of the sampler tests.

/// Upper-tail standard normal quantile for p = 1e-6: Φ⁻¹(1 − 10⁻⁶) = 4.753424308822899
/// (e.g. `scipy.stats.norm.isf(1e-6)`). Each chi-square test fails falsely with probability
/// 10⁻⁶ over the choice of seed.
pub const Z_ONE_IN_A_MILLION: f64 = 4.753_424_308_822_899;

/// Upper critical value of χ² with `dof` degrees of freedom at upper-tail probability 10⁻⁶, by
/// the Wilson–Hilferty cube-root normal approximation, k·(1 − 2/(9k) + z·√(2/(9k)))³ (accurate
/// to about 1 % here). With a fixed seed each test is deterministic; 10⁻⁶ is its false-failure
/// rate over seeds.
pub fn chi2_critical_1e6(dof: usize) -> f64 {
    let k = dof as f64;
    let h = 2.0 / (9.0 * k);
    k * (1.0 - h + Z_ONE_IN_A_MILLION * h.sqrt()).powi(3)
}
