//! The accuracy protocol of Ferrier's table 2, with run time: error against run time in one row.
//!
//! For each (ρ′, θ), draw points (r, φ) with the table's own sampler, evaluate the table and the
//! reference PBD quadrature there, and report the mean, 99th-percentile and max relative error,
//! with the time per evaluation of each (so the speed-up and its price read in one line).

use super::TableRef;
use crate::fresnel::Moments;
use crate::medium::Boundary;
use crate::pbd::{Pbd, Rule};
use crate::rng::{SeedableRng, SplitMix64, UnitF64};
use std::time::Instant;

/// The report's cases: ρ′ ∈ {0.5, 0.9, 0.99} × θ ∈ {0°, 60°, 89°}, with its mean relative errors
/// in per cent (Ferrier 2016, table 2), the ceiling to beat.
pub const REPORT_TABLE_2: [(f64, f64, f64); 9] = [
    (0.5, 0.0, 0.026),
    (0.9, 0.0, 0.026),
    (0.99, 0.0, 0.021),
    (0.5, 60.0, 0.08),
    (0.9, 60.0, 0.26),
    (0.99, 60.0, 0.25),
    (0.5, 89.0, 0.22),
    (0.9, 89.0, 0.53),
    (0.99, 89.0, 0.48),
];

/// One row of the protocol.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ValidationRow {
    /// Reduced albedo.
    pub rho: f64,
    /// Incidence, degrees.
    pub theta_deg: f64,
    /// Points drawn (fewer when the table holds no energy).
    pub samples: usize,
    /// Mean relative error.
    pub mean_rel_error: f64,
    /// Standard error of that mean: the errors' sample standard deviation over √samples
    /// (+∞ below two points).
    pub mean_rel_error_stderr: f64,
    /// 99th percentile of the relative error.
    pub p99_rel_error: f64,
    /// Largest relative error.
    pub max_rel_error: f64,
    /// Fraction of points above 1 % error.
    pub fraction_above_1pct: f64,
    /// Nanoseconds per table evaluation.
    pub table_ns: f64,
    /// Nanoseconds per reference evaluation.
    pub reference_ns: f64,
    /// The report's mean relative error for this case, if it is one of table 2's.
    pub report_mean_rel_error: Option<f64>,
}

/// Runs the protocol for `cases` (ρ′, θ in degrees) with `samples` points each, from `seed`.
/// `moments` must be those the table was baked with.
pub fn validate(
    table: &TableRef<'_>,
    moments: Moments,
    cases: &[(f64, f64)],
    samples: usize,
    seed: u64,
) -> crate::Result<Vec<ValidationRow>> {
    let boundary = Boundary::new(table.eta(), moments)?;
    let mut rows = Vec::with_capacity(cases.len());
    for (index, &(rho, theta_deg)) in cases.iter().enumerate() {
        let pbd = Pbd::new(rho, boundary)?;
        let theta = theta_deg.to_radians();
        let mut rng = SplitMix64::seed_from_u64(seed.wrapping_add(index as u64));
        let points: Vec<(f64, f64)> = (0..samples)
            .filter_map(|_| table.sample(rho, theta, rng.next_f64(), rng.next_f64()))
            .map(|s| (s.r, s.phi))
            .collect();
        let start = Instant::now();
        let values: Vec<f64> = points
            .iter()
            .map(|&(r, phi)| table.eval(rho, theta, r, phi).unwrap_or(0.0))
            .collect();
        let table_ns = per_point_ns(start, points.len());
        let start = Instant::now();
        let reference: Vec<f64> = points
            .iter()
            .map(|&(r, phi)| pbd.eval(theta, r, phi, Rule::Reference))
            .collect();
        let reference_ns = per_point_ns(start, points.len());
        let mut errors: Vec<f64> = values
            .iter()
            .zip(&reference)
            .filter(|(_, r)| **r > 0.0 && r.is_finite())
            .map(|(v, r)| (v / r - 1.0).abs())
            .collect();
        errors.sort_by(f64::total_cmp);
        let n = errors.len().max(1) as f64;
        let mean = errors.iter().sum::<f64>() / n;
        let stderr = if errors.len() < 2 {
            f64::INFINITY
        } else {
            let squares = errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>();
            (squares / (n - 1.0) / n).sqrt()
        };
        let pick = |q: f64| quantile(&errors, q).unwrap_or(0.0);
        rows.push(ValidationRow {
            rho,
            theta_deg,
            samples: errors.len(),
            mean_rel_error: mean,
            mean_rel_error_stderr: stderr,
            p99_rel_error: pick(0.99),
            max_rel_error: errors.last().copied().unwrap_or(0.0),
            fraction_above_1pct: errors.iter().filter(|&&e| e > 0.01).count() as f64 / n,
            table_ns,
            reference_ns,
            report_mean_rel_error: REPORT_TABLE_2
                .iter()
                .find(|c| c.0 == rho && c.1 == theta_deg)
                .map(|c| c.2 / 100.0),
        });
    }
    Ok(rows)
}

/// The nearest-rank quantile q of `sorted` (ascending): the smallest value with a share q of
/// the values at or below it, so that of 3 values the 99th percentile is the largest, not the
/// median. `None` when empty.
pub(crate) fn quantile(sorted: &[f64], q: f64) -> Option<f64> {
    let rank = (q * sorted.len() as f64).ceil() as usize;
    sorted.get(rank.max(1) - 1).copied()
}

fn per_point_ns(start: Instant, n: usize) -> f64 {
    start.elapsed().as_secs_f64() * 1e9 / n.max(1) as f64
}

#[cfg(test)]
mod tests {
    use super::quantile;

    #[test]
    fn quantiles_are_nearest_rank() {
        assert_eq!(quantile(&[], 0.99), None);
        assert_eq!(quantile(&[1.0, 2.0, 3.0], 0.99), Some(3.0));
        assert_eq!(quantile(&[1.0, 2.0, 3.0], 0.5), Some(2.0));
        assert_eq!(quantile(&[1.0, 2.0, 3.0], 0.0), Some(1.0));
        // Of 10⁵ values the 99th percentile is the 99,000th: 99,000 at or below it
        let values: Vec<f64> = (1..=100_000).map(f64::from).collect();
        assert_eq!(quantile(&values, 0.99), Some(99_000.0));
        assert_eq!(quantile(&values[..400], 0.99), Some(396.0));
    }
}
