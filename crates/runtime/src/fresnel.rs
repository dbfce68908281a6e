//! Fresnel reflectance of a smooth dielectric boundary and its hemispherical moments.
//!
//! - [`reflectance`]: the unpolarised reflectance for light arriving at cosine `cos_i` on one
//!   side of a boundary whose *relative* index (far side over near side) is `eta`; total
//!   internal reflection gives 1.
//! - [`moment`]: the n-th hemispherical moment F_n(η) = ∫₀¹ F_r(μ) μⁿ dμ of the reflectance seen
//!   **from inside** a medium of relative index η (so the far side has relative index 1/η).
//!   This is the convention of pbrt's `FresnelMoment1/2` and of d'Eon & Irving's C₁ = F₁ and
//!   C₂ = F₂: F₁(1.33) ≈ 0.2365 is large because of total internal reflection.
//!   The exact moment is integrated numerically (split at the critical cosine, with the square
//!   root singularity there removed by a change of variable) to ~1e-14.
//! - [`pbrt_moment1`], [`pbrt_moment2`]: pbrt-v3's fifth-order polynomial fits (d'Eon & Irving
//!   2011, halved and thirded), with pbrt's f32-rounded coefficients. They are accurate to about
//!   1e-3 and go slightly negative near η = 1; they exist to reproduce pbrt's numbers.
//! - [`deon_irving_moment1`], [`deon_irving_moment2`]: the same fits in double precision, with
//!   the branch choices of the directional dipole authors' sample code (used by
//!   `bssrdf_zoo::models::dirpole` to reproduce that code; not a [`Moments`] choice, since tables
//!   and their files record only the two conventions above).

use crate::quadrature::adaptive;

/// Which Fresnel moments a diffusion model uses.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Moments {
    /// Exact moments, integrated numerically once per η.
    #[default]
    Exact,
    /// pbrt-v3's polynomial fits (f32 coefficients), for comparison with pbrt.
    Pbrt,
}

impl Moments {
    /// The name on the command line and in JSON and provenance (`--fresnel-moments exact`):
    /// the one spelling of these moments everywhere.
    pub fn name(self) -> &'static str {
        match self {
            Moments::Exact => "exact",
            Moments::Pbrt => "pbrt",
        }
    }

    /// (F₁, F₂) for relative index η (> 0).
    pub fn evaluate(self, eta: f64) -> (f64, f64) {
        match self {
            Moments::Exact => (moment(1, eta), moment(2, eta)),
            Moments::Pbrt => (pbrt_moment1(eta), pbrt_moment2(eta)),
        }
    }
}

/// cos θ′ of light refracted into a medium of relative index η at incidence θ (radians, from
/// the normal); `None` where no light enters (θ outside [0, π/2], NaN, or sin θ > η).
///
/// From cos²θ′ = ((η − 1)(η + 1) + cos²θ)/η², not 1 − sin²θ′: near η = 1 and θ = 90° that would
/// round sin θ to 1 and make every θ within 1e-8 of 90° exactly grazing. The f64 nearest π/2
/// stands for 90° exactly (its cosine would be 6e-17).
pub fn refracted_cos(theta: f64, eta: f64) -> Option<f64> {
    if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&theta) {
        return None;
    }
    let cos_i = if theta == std::f64::consts::FRAC_PI_2 {
        0.0
    } else {
        theta.cos()
    };
    let cos2 = ((eta - 1.0) * (eta + 1.0) + cos_i * cos_i) / (eta * eta);
    (cos2 >= 0.0).then(|| cos2.sqrt())
}

/// Unpolarised Fresnel reflectance for incidence cosine `cos_i` ∈ [0, 1] and relative index
/// `eta` = n_far / n_near (> 0). Returns 1 beyond the critical angle. Inputs outside the domain
/// are clamped (cosine to [0, 1]); a non-positive or NaN `eta` gives 1 (nothing transmitted).
pub fn reflectance(cos_i: f64, eta: f64) -> f64 {
    if !eta.is_finite() || eta <= 0.0 {
        return 1.0;
    }
    let cos_i = if cos_i.is_nan() {
        0.0
    } else {
        cos_i.clamp(0.0, 1.0)
    };
    // Snell: sin_t = sin_i / eta.
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular)
}

/// Unpolarised Fresnel transmittance 1 − [`reflectance`].
pub fn transmittance(cos_i: f64, eta: f64) -> f64 {
    1.0 - reflectance(cos_i, eta)
}

/// T(θ) = 1 − F_r: the unpolarised Fresnel transmittance into a medium of relative index η for
/// light arriving from outside at incidence θ (radians from the normal, before refraction). It
/// is 0 at grazing incidence (the f64 nearest π/2 stands for 90° exactly, as in
/// [`refracted_cos`]), beyond the critical angle (η < 1), and for θ outside [0, π/2] or NaN;
/// at index matching (η = 1: no interface) it is 1 at every θ in [0, π/2], grazing included,
/// as its limit there is.
///
/// Computed as the sum of the two polarisations' transmittances, 1 − r² = 4ab/(a + b)² for
/// r = (a − b)/(a + b), rather than 1 − [`reflectance`]: near grazing incidence, where
/// F_r → 1, that difference would lose the digits of T.
pub fn entry_transmittance(theta: f64, eta: f64) -> f64 {
    let Some(cos_t) = refracted_cos(theta, eta) else {
        return 0.0;
    };
    if eta == 1.0 {
        return 1.0;
    }
    let cos_i = if theta == std::f64::consts::FRAC_PI_2 {
        0.0
    } else {
        theta.cos()
    };
    // t_s = 4 cos_i η cos_t / (cos_i + η cos_t)², t_p = 4 η cos_i cos_t / (η cos_i + cos_t)²
    let numerator = 2.0 * eta * cos_i * cos_t;
    let (s, p) = (cos_i + eta * cos_t, eta * cos_i + cos_t);
    if numerator == 0.0 {
        return 0.0;
    }
    numerator / (s * s) + numerator / (p * p)
}

/// The density of the exit direction that pairs with a table's exitance, per steradian:
/// S_ω(θ_o) = (1 − F_r(cos θ_o; η)) / (π η² (1 − 2F₁(η))), a diffuse lobe shaped by the
/// transmittance into the medium at the exit angle θ_o (outside, from the normal), normalised
/// so that ∫ S_ω cos θ_o dω = 1 over the hemisphere. The exitance already holds the exit
/// transmission (PBD's C_φ = (1 − 2F₁)/4), so this lobe only distributes it. The η² comes from
/// reciprocity: the hemispherical transmittance from outside, 2∫(1 − F_r(μ; η))μ dμ, is η²
/// times the one from inside, 1 − 2F₁ (F₁ is [`moment`]`(1, η)`, of the internal reflectance).
/// 0 for `cos_o` outside (0, 1] or NaN, or `eta` outside (0, ∞).
pub fn exit_direction_density(cos_o: f64, eta: f64) -> f64 {
    if !(cos_o > 0.0 && cos_o <= 1.0 && eta > 0.0 && eta.is_finite()) {
        return 0.0;
    }
    let inside = 1.0 - 2.0 * moment(1, eta);
    transmittance(cos_o, eta) / (std::f64::consts::PI * eta * eta * inside)
}

/// Exact n-th hemispherical moment of the internal reflectance, F_n(η) = ∫₀¹ F_r(μ; 1/η) μⁿ dμ.
///
/// For η > 1, light inside is totally reflected for μ < μ_c = √(1 − 1/η²); that part integrates
/// to μ_cⁿ⁺¹/(n+1) exactly. Above μ_c the transmitted cosine behaves like √(μ − μ_c); the
/// substitution μ = μ_c + (1 − μ_c)s² makes the integrand smooth in s.
pub fn moment(n: i32, eta: f64) -> f64 {
    if !eta.is_finite() || eta <= 0.0 {
        return f64::NAN;
    }
    let eta_inside_to_out = 1.0 / eta;
    let mu_c = if eta > 1.0 {
        (1.0 - 1.0 / (eta * eta)).max(0.0).sqrt()
    } else {
        0.0
    };
    let total_internal = mu_c.powi(n + 1) / (n as f64 + 1.0);
    let width = 1.0 - mu_c;
    let partial = adaptive(
        |s| {
            let mu = mu_c + width * s * s;
            reflectance(mu, eta_inside_to_out) * mu.powi(n) * 2.0 * width * s
        },
        &[0.0, 0.5, 1.0],
        1e-14,
        1e-16,
        400,
    );
    total_internal + partial.value
}

/// Evaluates Σ cᵢ xⁱ with coefficients rounded to f32 first, as pbrt's literals are.
fn poly_f32(coefficients: &[f64], x: f64) -> f64 {
    coefficients
        .iter()
        .rev()
        .fold(0.0, |acc, &c| acc * x + (c as f32) as f64)
}

/// pbrt-v3 `FresnelMoment1(η)`: polynomial fit of F₁ (coefficients in notes-pbrt §1.3).
pub fn pbrt_moment1(eta: f64) -> f64 {
    if eta < 1.0 {
        poly_f32(
            &[0.45966, -1.73965, 3.37668, -3.904945, 2.49277, -0.68441],
            eta,
        )
    } else {
        poly_f32(
            &[-4.61686, 11.1136, -10.4646, 5.11455, -1.27198, 0.12746],
            eta,
        )
    }
}

/// pbrt-v3 `FresnelMoment2(η)`: polynomial fit of F₂, with 1/η terms above η = 1.
pub fn pbrt_moment2(eta: f64) -> f64 {
    if eta < 1.0 {
        poly_f32(
            &[0.27614, -0.87350, 1.12077, -0.65095, 0.07883, 0.04860],
            eta,
        )
    } else {
        let inv = 1.0 / eta;
        poly_f32(
            &[-547.033, 404.557, -189.519, 54.9327, -9.00603, 0.63942],
            eta,
        ) + ((458.843f32 as f64) + ((-218.725f32 as f64) + (45.3087f32 as f64) * inv) * inv) * inv
    }
}

/// Σ cᵢ xⁱ in double precision.
fn poly(coefficients: &[f64], x: f64) -> f64 {
    coefficients.iter().rev().fold(0.0, |acc, &c| acc * x + c)
}

/// F₁ = C₁ from d'Eon & Irving's (2011) fit of 2C₁(η), in double precision. The η > 1 branch is
/// taken only for η > 1, as in the directional dipole sample code (Frisvad, Hachisuka, Kjeldsen
/// 2014; at η = 1 the two branches give 2C₁ = 0.000207 and 0.004333).
pub fn deon_irving_moment1(eta: f64) -> f64 {
    let two_c1 = if eta > 1.0 {
        poly(
            &[-9.23372, 22.2272, -20.9292, 10.2291, -2.54396, 0.254913],
            eta,
        )
    } else {
        poly(
            &[0.919317, -3.4793, 6.75335, -7.80989, 4.98554, -1.36881],
            eta,
        )
    };
    0.5 * two_c1
}

/// F₂ = C₂ from d'Eon & Irving's fit of 3C₂(η), in double precision; the η ≥ 1 branch has
/// 1/η terms. The directional dipole sample code has no η < 1 branch for it; the η < 1 fit is
/// used there.
pub fn deon_irving_moment2(eta: f64) -> f64 {
    let three_c2 = if eta < 1.0 {
        poly(
            &[0.828421, -2.62051, 3.36231, -1.95284, 0.236494, 0.145787],
            eta,
        )
    } else {
        let inv = 1.0 / eta;
        poly(
            &[-1641.1, 1213.67, -568.556, 164.798, -27.0181, 1.91826],
            eta,
        ) + (1376.53 + (-656.175 + 135.926 * inv) * inv) * inv
    };
    three_c2 / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_reflectance_matches_the_closed_form() {
        for eta in [0.5f64, 1.0, 1.33, 2.5] {
            let want = ((eta - 1.0) / (eta + 1.0)).powi(2);
            assert!((reflectance(1.0, eta) - want).abs() < 1e-15);
        }
    }

    #[test]
    fn reflectance_is_one_beyond_the_critical_angle_and_at_grazing() {
        let eta: f64 = 1.0 / 1.33;
        let cos_c = (1.0 - eta * eta).sqrt();
        assert_eq!(reflectance(cos_c * 0.999, eta), 1.0);
        assert!(reflectance(cos_c * 1.001, eta) < 1.0);
        assert!((reflectance(0.0, 1.5) - 1.0).abs() < 1e-12);
        assert!(reflectance(0.3, 1.0) < 1e-30);
    }

    #[test]
    fn reflectance_is_the_same_from_both_sides_of_a_refraction() {
        // Stokes reciprocity: R(θi, η) = R(θt, 1/η).
        let eta = 1.4;
        for cos_i in [0.1, 0.4, 0.9] {
            let sin_t = (1.0f64 - cos_i * cos_i).sqrt() / eta;
            let cos_t = (1.0 - sin_t * sin_t).sqrt();
            assert!((reflectance(cos_i, eta) - reflectance(cos_t, 1.0 / eta)).abs() < 1e-14);
        }
    }

    #[test]
    fn moments_vanish_at_index_match_and_agree_with_pbrt_fits() {
        assert!(moment(1, 1.0).abs() < 1e-15);
        assert!(moment(2, 1.0).abs() < 1e-15);
        // pbrt's fits are accurate to about 1e-3 (notes-pbrt §1.3 table: 0.236478, 0.1085).
        for eta in [1.1, 1.33, 1.5, 2.0] {
            assert!(
                (moment(1, eta) - pbrt_moment1(eta)).abs() < 2e-3,
                "eta {eta}"
            );
            assert!(
                (moment(2, eta) - pbrt_moment2(eta)).abs() < 2e-3,
                "eta {eta}"
            );
        }
        assert!((pbrt_moment1(1.33) - 0.236478).abs() < 2e-6);
        assert!((pbrt_moment2(1.33) - 0.108534).abs() < 2e-6);
    }

    #[test]
    fn deon_irving_fits_match_the_tabulated_constants() {
        // notes-models §1.2, computed with the sample code's branches: (η, 2C₁, 3C₂).
        for (eta, two_c1, three_c2) in [
            (1.0, 0.000207, -0.006840),
            (1.3, 0.445295, 0.297448),
            (1.5, 0.596541, 0.462609),
        ] {
            assert!(
                (2.0 * deon_irving_moment1(eta) - two_c1).abs() < 1e-6,
                "eta {eta}"
            );
            assert!(
                (3.0 * deon_irving_moment2(eta) - three_c2).abs() < 1e-6,
                "eta {eta}"
            );
        }
        // pbrt rounds the same polynomials to fewer digits (and to f32).
        for eta in [0.8, 1.33, 2.0] {
            assert!((deon_irving_moment1(eta) - pbrt_moment1(eta)).abs() < 2e-4);
            assert!((deon_irving_moment2(eta) - pbrt_moment2(eta)).abs() < 2e-4);
        }
    }

    /// T(θ) against the textbook form in angles, R_s = sin²(θi − θt)/sin²(θi + θt) and
    /// R_p = tan²(θi − θt)/tan²(θi + θt) (θ > 0), and ((η − 1)/(η + 1))² at θ = 0; and against
    /// 1 − [`reflectance`] where that difference keeps its digits.
    #[test]
    fn entry_transmittance_matches_the_fresnel_equations_in_angles() {
        use std::f64::consts::FRAC_PI_2;
        for eta in [0.75f64, 0.9, 1.0, 1.0001, 1.33, 1.5, 2.5] {
            let normal = 1.0 - ((eta - 1.0) / (eta + 1.0)).powi(2);
            assert!(
                (entry_transmittance(0.0, eta) - normal).abs() < 1e-15,
                "{eta}"
            );
            for k in 1..90 {
                let ti = f64::from(k).to_radians();
                let sin_t = ti.sin() / eta;
                if sin_t >= 1.0 {
                    assert_eq!(entry_transmittance(ti, eta), 0.0, "{eta} {k}");
                    continue;
                }
                let tt = sin_t.asin();
                let r_s = ((ti - tt).sin() / (ti + tt).sin()).powi(2);
                let r_p = ((ti - tt).tan() / (ti + tt).tan()).powi(2);
                let closed = 1.0 - 0.5 * (r_s + r_p);
                let got = entry_transmittance(ti, eta);
                assert!((got - closed).abs() < 1e-12, "{eta} {k}: {got} {closed}");
                assert!((got - transmittance(ti.cos(), eta)).abs() < 1e-14);
            }
            // Grazing: no light enters, but at index matching, where nothing reflects
            let grazing = if eta == 1.0 { 1.0 } else { 0.0 };
            assert_eq!(entry_transmittance(FRAC_PI_2, eta), grazing);
            for bad in [-1e-9, FRAC_PI_2 + 1e-9, f64::NAN] {
                assert_eq!(entry_transmittance(bad, eta), 0.0);
            }
        }
        // Near grazing the transmittance keeps its digits: to first order in cos θ,
        // T = 2 cos θ (1/(η cos θ′) + η/cos θ′), the s and p halves.
        let eta = 1.33f64;
        let theta = FRAC_PI_2 - 1e-12;
        let cos_t = (1.0 - 1.0 / (eta * eta)).sqrt();
        let first_order = 2.0 * theta.cos() * (1.0 / (eta * cos_t) + eta / cos_t);
        let got = entry_transmittance(theta, eta);
        assert!(
            (got / first_order - 1.0).abs() < 1e-9,
            "{got} {first_order}"
        );
    }

    #[test]
    fn the_exit_direction_density_integrates_to_one_over_the_projected_hemisphere() {
        // ∫ S_ω cos θ dω = 2π ∫₀¹ S_ω(μ) μ dμ, by a midpoint sum over μ of the Fresnel
        // equations themselves (not the moment's substituted quadrature)
        let n = 100_000;
        for eta in [0.75, 0.9, 1.0, 1.2, 1.33, 1.5, 2.0, 2.5] {
            let integral: f64 = (0..n)
                .map(|i| {
                    let mu = (i as f64 + 0.5) / n as f64;
                    exit_direction_density(mu, eta) * mu
                })
                .sum::<f64>()
                * std::f64::consts::TAU
                / n as f64;
            assert!((integral - 1.0).abs() < 1e-6, "eta {eta}: {integral}");
        }
        for bad in [0.0, -0.5, 1.5, f64::NAN] {
            assert_eq!(exit_direction_density(bad, 1.33), 0.0);
        }
        assert_eq!(exit_direction_density(0.5, f64::NAN), 0.0);
    }

    #[test]
    fn moments_match_a_brute_force_midpoint_sum() {
        let n = 2_000_000;
        for eta in [0.75, 1.33, 2.5] {
            let brute: f64 = (0..n)
                .map(|i| {
                    let mu = (i as f64 + 0.5) / n as f64;
                    reflectance(mu, 1.0 / eta) * mu
                })
                .sum::<f64>()
                / n as f64;
            assert!((brute - moment(1, eta)).abs() < 1e-8, "eta {eta}");
        }
    }
}
