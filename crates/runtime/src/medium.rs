//! A homogeneous scattering medium and the diffusion constants derived from it.
//!
//! | parameter | unit | valid range | meaning |
//! |---|---|---|---|
//! | σs | mm⁻¹ | ≥ 0, finite | scattering coefficient (unreduced) |
//! | σa | mm⁻¹ | ≥ 0, finite | absorption coefficient |
//! | g | – | (−1, 1) | Henyey–Greenstein mean cosine |
//! | η | – | [0.75, 2.5] | relative index of refraction, medium over outside |
//! | σ′t = σs(1−g) + σa | mm⁻¹ | [1e-9, 1e12] | reduced extinction (0 is refused as vacuum) |
//!
//! Derived (Habel et al. 2013; Ferrier 2016, table 4; Grosjean's diffusion coefficient):
//! σ′s = σs(1−g), σ′t = σ′s + σa, ρ′ = σ′s/σ′t, D = (2σa + σ′s)/(3σ′t²), σtr = √(σa/D).
//! Diffusion models depend on (σs, σa, g) only through (σ′s, σa): in reduced optical units
//! (lengths times σ′t) everything is a function of ρ′ alone, with D = (2 − ρ′)/3 and
//! σtr = √(3(1 − ρ′)/(2 − ρ′)). This is what lets one table serve every g.
//!
//! Boundary (from the Fresnel moments F₁, F₂ of the internal reflectance, see [`crate::fresnel`]):
//! A = (1 + 3F₂)/(1 − 2F₁), extrapolation distance z_b = 2AD (positive: the extrapolated
//! boundary lies z_b *above* the surface; pbrt's `ze` is −z_b), C_φ = (1 − 2F₁)/4,
//! C_E = (1 − 3F₂)/2.

use crate::error::{finite, Error, Result};
use crate::fresnel::Moments;

/// Smallest reduced extinction σ′t a medium may have, mm⁻¹ (a mean free path of 1000 km): below
/// it the world-unit scale factor σ′t² of every profile would leave f64's normal range.
pub const SIGMA_T_MIN: f64 = 1e-9;
/// Largest reduced extinction σ′t, mm⁻¹ (a mean free path of 1 fm), see [`SIGMA_T_MIN`].
pub const SIGMA_T_MAX: f64 = 1e12;

/// Refuses a reduced extinction σ′t (mm⁻¹) outside [[`SIGMA_T_MIN`], [`SIGMA_T_MAX`]]: world-unit
/// lookups scale by σ′t², which beyond 1.3e154 is ∞, and ∞ times a profile's 0 is NaN.
pub fn check_sigma_t_range(sigma_t_prime: f64) -> Result<()> {
    if (SIGMA_T_MIN..=SIGMA_T_MAX).contains(&sigma_t_prime) {
        return Ok(());
    }
    Err(Error::OutOfRange {
        name: "sigma_t'",
        value: sigma_t_prime,
        min: SIGMA_T_MIN,
        max: SIGMA_T_MAX,
    })
}

/// Checks a reduced extinction σ′t (mm⁻¹) given on its own, as world-unit lookups take it: not
/// finite, 0 (vacuum), negative, or outside [[`SIGMA_T_MIN`], [`SIGMA_T_MAX`]] is an error
/// naming the value.
pub fn check_sigma_t_prime(sigma_t_prime: f64) -> Result<f64> {
    finite("sigma_t'", sigma_t_prime)?;
    if sigma_t_prime == 0.0 {
        return Err(Error::Vacuum);
    }
    if sigma_t_prime < 0.0 {
        return Err(Error::NotPositive {
            name: "sigma_t'",
            value: sigma_t_prime,
        });
    }
    check_sigma_t_range(sigma_t_prime)?;
    Ok(sigma_t_prime)
}

/// A validated homogeneous medium (see the module table for units and ranges).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Medium {
    sigma_s: f64,
    sigma_a: f64,
    g: f64,
    eta: f64,
}

impl Medium {
    /// Validates and builds a medium. Rejects NaN, infinities, negative coefficients,
    /// |g| ≥ 1, η outside [[`ETA_MIN`], [`ETA_MAX`]], a medium with σ′t = 0 (vacuum), and σ′t
    /// outside [[`SIGMA_T_MIN`], [`SIGMA_T_MAX`]] mm⁻¹ (σ′t = 10³⁰⁸ + 10³⁰⁸ overflows to ∞).
    pub fn new(sigma_s: f64, sigma_a: f64, g: f64, eta: f64) -> Result<Self> {
        for (name, value) in [("sigma_s", sigma_s), ("sigma_a", sigma_a)] {
            finite(name, value)?;
            if value < 0.0 {
                return Err(Error::Negative { name, value });
            }
        }
        finite("g", g)?;
        if g <= -1.0 || g >= 1.0 {
            return Err(Error::AsymmetryOutOfRange(g));
        }
        validate_eta(eta)?;
        let medium = Self {
            sigma_s,
            sigma_a,
            g,
            eta,
        };
        let sigma_t_prime = medium.sigma_t_prime();
        if sigma_t_prime == 0.0 {
            return Err(Error::Vacuum);
        }
        // Not in_range: σ′t = ∞ from finite coefficients is out of range, not "not finite".
        check_sigma_t_range(sigma_t_prime)?;
        Ok(medium)
    }

    /// σs, mm⁻¹.
    pub fn sigma_s(&self) -> f64 {
        self.sigma_s
    }
    /// σa, mm⁻¹.
    pub fn sigma_a(&self) -> f64 {
        self.sigma_a
    }
    /// Henyey–Greenstein g.
    pub fn g(&self) -> f64 {
        self.g
    }
    /// Relative index of refraction η.
    pub fn eta(&self) -> f64 {
        self.eta
    }
    /// Reduced scattering coefficient σ′s = σs(1 − g), mm⁻¹.
    pub fn sigma_s_prime(&self) -> f64 {
        self.sigma_s * (1.0 - self.g)
    }
    /// Reduced extinction σ′t = σ′s + σa, mm⁻¹ (> 0 by construction).
    pub fn sigma_t_prime(&self) -> f64 {
        self.sigma_s_prime() + self.sigma_a
    }
    /// Reduced albedo ρ′ = σ′s/σ′t ∈ [0, 1].
    pub fn rho_prime(&self) -> f64 {
        self.sigma_s_prime() / self.sigma_t_prime()
    }
    /// Grosjean's diffusion coefficient D = (2σa + σ′s)/(3σ′t²), mm.
    pub fn diffusion_coefficient(&self) -> f64 {
        let st = self.sigma_t_prime();
        (2.0 * self.sigma_a + self.sigma_s_prime()) / (3.0 * st * st)
    }
    /// Effective transport coefficient σtr = √(σa/D), mm⁻¹.
    pub fn sigma_tr(&self) -> f64 {
        (self.sigma_a / self.diffusion_coefficient()).sqrt()
    }
    /// The boundary constants for this medium's η.
    pub fn boundary(&self, moments: Moments) -> Boundary {
        Boundary::new_unchecked(self.eta, moments)
    }
    /// Extrapolation distance z_b = 2AD in mm (positive, above the surface).
    pub fn extrapolation_distance(&self, moments: Moments) -> f64 {
        2.0 * self.boundary(moments).a() * self.diffusion_coefficient()
    }
}

/// The relative index of refraction every model, table and walk accepts: [`ETA_MIN`, `ETA_MAX`].
/// Below 0.75 light enters only near normal incidence; above 2.5 no common medium lies (diamond
/// is 2.42). Every model is verified over this range (PBD by the independent quadrature of
/// `crates/zoo/tests/physics/pbd/mod.rs`).
pub const ETA_MIN: f64 = 0.75;
/// Upper end of the η domain, see [`ETA_MIN`].
pub const ETA_MAX: f64 = 2.5;

/// Checks η ∈ [[`ETA_MIN`], [`ETA_MAX`]], naming it otherwise.
pub fn validate_eta(eta: f64) -> Result<f64> {
    crate::error::in_range("eta", eta, ETA_MIN, ETA_MAX)
}

/// Diffusion constants in reduced optical units (σ′t = 1) for reduced albedo ρ′ ∈ [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReducedDiffusion {
    /// ρ′.
    pub rho_prime: f64,
    /// D = (2 − ρ′)/3, in reduced mean free paths.
    pub d: f64,
    /// σtr = √(3(1 − ρ′)/(2 − ρ′)), per reduced mean free path.
    pub sigma_tr: f64,
}

impl ReducedDiffusion {
    /// Constants for ρ′ (validated to lie in [0, 1]).
    pub fn new(rho_prime: f64) -> Result<Self> {
        crate::error::in_range("rho", rho_prime, 0.0, 1.0)?;
        let d = (2.0 - rho_prime) / 3.0;
        let sigma_tr = ((1.0 - rho_prime) / d).sqrt();
        Ok(Self {
            rho_prime,
            d,
            sigma_tr,
        })
    }
}

/// Boundary constants of a dielectric interface of relative index η for diffusion models.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Boundary {
    eta: f64,
    moments: Moments,
    f1: f64,
    f2: f64,
}

impl Boundary {
    /// Computes F₁, F₂ for η (validated: finite and > 0).
    pub fn new(eta: f64, moments: Moments) -> Result<Self> {
        validate_eta(eta)?;
        Ok(Self::new_unchecked(eta, moments))
    }

    fn new_unchecked(eta: f64, moments: Moments) -> Self {
        let (f1, f2) = moments.evaluate(eta);
        Self {
            eta,
            moments,
            f1,
            f2,
        }
    }

    /// η.
    pub fn eta(&self) -> f64 {
        self.eta
    }
    /// Which moments were used.
    pub fn moments(&self) -> Moments {
        self.moments
    }
    /// First moment F₁ of the internal reflectance.
    pub fn f1(&self) -> f64 {
        self.f1
    }
    /// Second moment F₂ of the internal reflectance.
    pub fn f2(&self) -> f64 {
        self.f2
    }
    /// A = (1 + 3F₂)/(1 − 2F₁).
    pub fn a(&self) -> f64 {
        (1.0 + 3.0 * self.f2) / (1.0 - 2.0 * self.f1)
    }
    /// Fluence weight of the exitance, C_φ = (1 − 2F₁)/4.
    pub fn c_phi(&self) -> f64 {
        0.25 * (1.0 - 2.0 * self.f1)
    }
    /// Vector-irradiance weight of the exitance, C_E = (1 − 3F₂)/2.
    pub fn c_e(&self) -> f64 {
        0.5 * (1.0 - 3.0 * self.f2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One check of σ′t for every world-unit wrapper: each failure its own error, naming the
    /// value (a negative σ′t is not called vacuum).
    #[test]
    fn sigma_t_prime_alone_is_checked_with_its_own_errors() {
        assert_eq!(check_sigma_t_prime(2.5), Ok(2.5));
        assert_eq!(check_sigma_t_prime(0.0), Err(Error::Vacuum));
        assert_eq!(check_sigma_t_prime(-0.0), Err(Error::Vacuum));
        let negative = check_sigma_t_prime(-1.5).unwrap_err();
        assert!(matches!(negative, Error::NotPositive { value, .. } if value == -1.5));
        assert!(negative.to_string().contains("-1.5"), "{negative}");
        assert!(matches!(
            check_sigma_t_prime(f64::NAN),
            Err(Error::NotFinite { .. })
        ));
        for x in [SIGMA_T_MAX * 2.0, SIGMA_T_MIN / 2.0] {
            assert!(matches!(
                check_sigma_t_prime(x),
                Err(Error::OutOfRange { value, .. }) if value == x
            ));
        }
    }

    #[test]
    fn construction_rejects_bad_values_and_names_them() {
        let cases = [
            (f64::NAN, 1.0, 0.0, 1.3, "sigma_s"),
            (1.0, -0.1, 0.0, 1.3, "sigma_a"),
            (f64::INFINITY, 1.0, 0.0, 1.3, "sigma_s"),
            (1.0, 1.0, 1.0, 1.3, "g = 1"),
            (1.0, 1.0, -1.0, 1.3, "g = -1"),
            (1.0, 1.0, 0.0, 0.0, "eta = 0"),
            (1.0, 1.0, 0.0, -2.0, "eta = -2"),
            (1.0, 1.0, f64::NAN, 1.3, "g = NaN"),
            (0.0, 0.0, 0.0, 1.3, "vacuum"),
        ];
        for (s, a, g, eta, needle) in cases {
            let err = Medium::new(s, a, g, eta).unwrap_err().to_string();
            assert!(err.contains(needle), "{err:?} should name {needle:?}");
        }
    }

    #[test]
    fn reduced_quantities_follow_their_definitions() {
        let m = Medium::new(2.0, 0.5, 0.5, 1.33).unwrap();
        assert_eq!(m.sigma_s_prime(), 1.0);
        assert_eq!(m.sigma_t_prime(), 1.5);
        assert!((m.rho_prime() - 2.0 / 3.0).abs() < 1e-15);
        assert!((m.diffusion_coefficient() - 2.0 / (3.0 * 2.25)).abs() < 1e-15);
        // In reduced units D and σtr depend on ρ′ alone.
        let r = ReducedDiffusion::new(m.rho_prime()).unwrap();
        assert!((r.d / m.sigma_t_prime() - m.diffusion_coefficient()).abs() < 1e-15);
        assert!((r.sigma_tr * m.sigma_t_prime() - m.sigma_tr()).abs() < 1e-14);
    }

    #[test]
    fn boundary_constants_match_pbrt_at_eta_1_33() {
        // notes-pbrt §1.3: A = 2.5153, C_φ = 0.13176, C_E = 0.33717 with pbrt's fits.
        let b = Boundary::new(1.33, Moments::Pbrt).unwrap();
        assert!((b.a() - 2.5153).abs() < 2e-4);
        assert!((b.c_phi() - 0.13176).abs() < 1e-5);
        assert!((b.c_e() - 0.33717).abs() < 1e-4);
        let exact = Boundary::new(1.0, Moments::Exact).unwrap();
        assert!((exact.a() - 1.0).abs() < 1e-14);
    }
}
