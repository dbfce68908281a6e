//! A floor and two wrapped Cauchy lobes fitted straight to the walk's harmonics: the profile of
//! the walk table's nodes at an incidence where PBD tilted by a few harmonics does not follow
//! the walk's shape (`walk_bake` module docs, "Where the tilt misses the walk").
//!
//! The profile over φ is S(φ) = F/2π + m₁ pdf_WC(φ; κ₁) + m₂ pdf_WC(φ; κ₂), whose harmonics
//! μₙ = ∫ S cos nφ dφ over [−π, π] are F δₙ₀ + m₁ κ₁ⁿ + m₂ κ₂ⁿ. For fixed κ₁ and κ₂ they are
//! linear in (F, m₁, m₂), so the fit is a weighted linear least squares in the masses inside a
//! search over the two concentrations. The masses may have either sign, as the lookups' signed
//! pairs do, with two limits that keep the profile what a stored node gives back: the sharper
//! lobe is positive (the lookups' rebuild refuses a sharper negative lobe), and the profile is
//! not below 0 at [`CHECK_POINTS`] azimuths from 0 to π. κ lies in
//! [[`C_MIN_SECOND_LOBE`], [`C_MAX_TWO_LOBES`]], the concentrations a stored node's lobes can
//! take.

use crate::gwc::{pdf_wc, solve_small, C_MAX_TWO_LOBES, C_MIN_SECOND_LOBE};
use crate::walk::harmonics::HARMONICS;
use std::f64::consts::{PI, TAU};

/// A floor and two wrapped Cauchy lobes (module docs): the sharper lobe first.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Lobes {
    /// The floor's mass F (its density F/2π).
    pub floor: f64,
    /// The lobes' masses m₁ (> 0) and m₂.
    pub mass: [f64; 2],
    /// Their concentrations κ₁ ≥ κ₂.
    pub kappa: [f64; 2],
}

/// Concentrations of the search's grid, spaced more closely towards [`C_MAX_TWO_LOBES`] (a
/// lobe's shape changes fastest there).
const GRID: usize = 40;

/// Azimuths from 0 to π (ends included) at which a fit's profile may not be below 0.
pub(super) const CHECK_POINTS: usize = 65;

/// The least step in κ of the refinement.
const LEAST_STEP: f64 = 1e-7;

impl Lobes {
    /// The harmonics μ₀ … μ_{N−1}.
    pub fn harmonics<const N: usize>(&self) -> [f64; N] {
        std::array::from_fn(|n| {
            let floor = if n == 0 { self.floor } else { 0.0 };
            floor
                + (0..2)
                    .map(|j| self.mass[j] * self.kappa[j].powi(n as i32))
                    .sum::<f64>()
        })
    }

    /// Whether the lobes are within the module's limits: the sharper positive, the profile not
    /// below 0 at [`CHECK_POINTS`] azimuths.
    fn admissible(&self) -> bool {
        self.mass[0] > 0.0
            && (0..CHECK_POINTS)
                .all(|i| self.eval(PI * i as f64 / (CHECK_POINTS - 1) as f64) >= 0.0)
    }

    /// S(φ).
    pub fn eval(&self, phi: f64) -> f64 {
        self.floor / TAU
            + (0..2)
                .map(|j| self.mass[j] * pdf_wc(phi, self.kappa[j]))
                .sum::<f64>()
    }

    /// The lobes whose harmonics are closest to `y` (μ₀ … μ₈) in least squares with weights
    /// `w` (1/σ² for a measurement), within the module's limits: a grid search over
    /// κ₂ < κ₁, then steps of each κ halved until they are below 10⁻⁷. `None` where no pair
    /// of the grid gives an admissible profile.
    pub fn fit(y: &[f64; HARMONICS], w: &[f64; HARMONICS]) -> Option<Lobes> {
        let span = C_MAX_TWO_LOBES - C_MIN_SECOND_LOBE;
        let grid: Vec<f64> = (0..GRID)
            .map(|i| {
                let t = 1.0 - i as f64 / (GRID - 1) as f64;
                C_MIN_SECOND_LOBE + span * (1.0 - t * t)
            })
            .collect();
        let mut best: Option<(f64, Lobes)> = None;
        // (the profile checked only where it would be the best: the check costs most)
        let consider = |best: &mut Option<(f64, Lobes)>, k1: f64, k2: f64| {
            if let Some((cost, lobes)) = masses(y, w, [k1, k2]) {
                if best.is_none_or(|(c, _)| cost < c) && lobes.admissible() {
                    *best = Some((cost, lobes));
                }
            }
        };
        for (i, &k1) in grid.iter().enumerate() {
            for &k2 in &grid[..i] {
                consider(&mut best, k1, k2);
            }
        }
        let (mut cost, mut lobes) = best?;
        let mut step = 0.05;
        while step >= LEAST_STEP {
            let mut moved = false;
            for (d1, d2) in [(step, 0.0), (-step, 0.0), (0.0, step), (0.0, -step)] {
                let k1 = (lobes.kappa[0] + d1).clamp(C_MIN_SECOND_LOBE, C_MAX_TWO_LOBES);
                let k2 = (lobes.kappa[1] + d2).clamp(C_MIN_SECOND_LOBE, C_MAX_TWO_LOBES);
                if k2 >= k1 {
                    continue;
                }
                let mut here = Some((cost, lobes));
                consider(&mut here, k1, k2);
                if let Some((c, l)) = here.filter(|(c, _)| *c < cost) {
                    (cost, lobes, moved) = (c, l, true);
                }
            }
            if !moved {
                step *= 0.5;
            }
        }
        Some(lobes)
    }
}

/// The masses (F, m₁, m₂) of lobes of concentrations `kappa` (κ₁ > κ₂) closest to `y` with
/// weights `w`, and the weighted squared misfit; `None` where the system is singular.
fn masses(y: &[f64; HARMONICS], w: &[f64; HARMONICS], kappa: [f64; 2]) -> Option<(f64, Lobes)> {
    let column = |j: usize, n: usize| match j {
        0 => f64::from(u8::from(n == 0)),
        _ => kappa[j - 1].powi(n as i32),
    };
    let mut normal = [[0.0; 4]; 3];
    for (i, row) in normal.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().take(3).enumerate() {
            *x = (0..HARMONICS)
                .map(|n| w[n] * column(i, n) * column(j, n))
                .sum();
        }
        row[3] = (0..HARMONICS).map(|n| w[n] * column(i, n) * y[n]).sum();
    }
    let [floor, m1, m2] = solve_small(&mut normal, 3)?;
    let lobes = Lobes {
        floor,
        mass: [m1, m2],
        kappa,
    };
    let h = lobes.harmonics::<HARMONICS>();
    let cost = (0..HARMONICS).map(|n| w[n] * (h[n] - y[n]).powi(2)).sum();
    Some((cost, lobes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{SeedableRng, SplitMix64, UnitF64};

    /// Random lobes within the fit's limits: a positive sharp lobe, a broader one of either
    /// sign and a floor, the profile ≥ 0 on 1,001 azimuths (checked here, not by the fit's
    /// own check).
    fn random_lobes(rng: &mut SplitMix64) -> Lobes {
        loop {
            let mut u = || rng.next_f64();
            let k1 = 0.3 + 0.69 * u();
            let k2 = C_MIN_SECOND_LOBE + (k1 - 0.1 - C_MIN_SECOND_LOBE) * u();
            let lobes = Lobes {
                floor: 0.5 * u(),
                mass: [0.2 + u(), u() - 0.4],
                kappa: [k1, k2],
            };
            let positive = (0..=1000).all(|i| lobes.eval(PI * f64::from(i) / 1000.0) >= 0.0);
            if k2 >= C_MIN_SECOND_LOBE && positive {
                return lobes;
            }
        }
    }

    #[test]
    fn the_harmonics_are_the_profiles_by_quadrature() {
        // μₙ against the midpoint rule over φ (exact for these profiles to ~κⁿ of 4,096 points)
        let mut rng = SplitMix64::seed_from_u64(31);
        for _ in 0..50 {
            let lobes = random_lobes(&mut rng);
            let h = lobes.harmonics::<HARMONICS>();
            let points = 4096;
            for (n, hn) in h.iter().enumerate() {
                let q: f64 = (0..points)
                    .map(|i| {
                        let phi = -PI + TAU * (i as f64 + 0.5) / points as f64;
                        lobes.eval(phi) * (n as f64 * phi).cos()
                    })
                    .sum::<f64>()
                    * TAU
                    / points as f64;
                assert!((q - hn).abs() < 1e-9 * h[0], "{n}: {q} against {hn}");
            }
        }
    }

    #[test]
    fn known_lobes_are_recovered_from_their_noisy_harmonics() {
        // 300 random admissible lobes; their harmonics with normal noise of σ = 10⁻³ μ₀ in
        // each: the fit's profile is within a few σ of the lobes' in relative RMS over φ, and
        // its own profile admissible. Without noise the harmonics are matched to 10⁻⁹
        let mut rng = SplitMix64::seed_from_u64(32);
        let mut normal = {
            let mut rng = SplitMix64::seed_from_u64(33);
            move || {
                let (u, v) = (rng.next_f64(), rng.next_f64());
                (-2.0 * (1.0 - u).ln()).sqrt() * (TAU * v).cos()
            }
        };
        let (mut worst, mut signed) = (0.0f64, 0);
        for case in 0..300 {
            let lobes = random_lobes(&mut rng);
            signed += usize::from(lobes.mass[1] < 0.0);
            let h = lobes.harmonics::<HARMONICS>();
            let sigma = if case % 3 == 0 { 0.0 } else { 1e-3 * h[0] };
            let y = std::array::from_fn(|n| h[n] + sigma * normal());
            let w = [1.0 / (sigma.max(1e-6 * h[0])).powi(2); HARMONICS];
            let fit = Lobes::fit(&y, &w).unwrap();
            assert!(fit.mass[0] > 0.0 && fit.kappa[0] > fit.kappa[1], "{fit:?}");
            let got = fit.harmonics::<HARMONICS>();
            if sigma == 0.0 {
                for n in 0..HARMONICS {
                    assert!((got[n] - h[n]).abs() < 1e-6 * h[0], "{lobes:?} {fit:?}");
                }
            }
            // relative RMS over φ of the difference by Parseval, over the measured harmonics
            let rms = ((got[0] - h[0]).powi(2)
                + 2.0 * (1..HARMONICS).map(|n| (got[n] - h[n]).powi(2)).sum::<f64>())
            .sqrt()
                / h[0];
            if sigma > 0.0 {
                worst = worst.max(rms * h[0] / sigma);
            }
            for i in 0..=1000 {
                assert!(
                    fit.eval(PI * f64::from(i) / 1000.0) > -1e-9 * h[0],
                    "{fit:?}"
                );
            }
        }
        // nine harmonics of noise σ: a fit of five numbers to them misses by about √(2·5) σ
        assert!(worst < 6.0, "{worst}");
        assert!(signed > 50, "{signed} signed pairs");
    }

    #[test]
    fn a_profile_no_admissible_pair_holds_gives_none() {
        // Harmonics of a negative profile: no positive sharper lobe above 0 holds them
        let y = std::array::from_fn(|n| -(0.5f64.powi(n as i32)));
        assert_eq!(Lobes::fit(&y, &[1.0; HARMONICS]), None);
    }
}
