//! The model zoo: every BSSRDF model of the crate behind one trait, selected by name.
//!
//! # The common quantity
//! Every model evaluates the same thing in the same units, so that they can be compared with
//! each other and with the Monte Carlo walk ([`crate::walk`]):
//!
//! R(r, φ; θ) = power leaving the lit surface per unit area at the exit point (r, φ), per unit
//! power **entering** the medium at the origin,
//!
//! in reduced units (σ′t = 1: r in reduced mean free paths, R per reduced mfp²), with θ the
//! incidence angle before refraction and φ = 0 forward (the side the refracted beam travels to).
//! The entry Fresnel transmittance is not included; the exit one is (R is the exitance outside).
//! A model written as a radiance-like S_d with a diffuse exit is converted by integrating
//! S_d T(ω_o) cos θ_o over the outgoing hemisphere; each model file states its factor.
//! [`World`] converts to world units (r in mm, R in mm⁻²): R_world(r) = σ′t² R(σ′t r).
//!
//! | name | file | what it models | compared with the walk's |
//! |---|---|---|---|
//! | `dipole` | [`dipole`] | Jensen et al. 2001 standard dipole | multiple scattering |
//! | `dirpole` | [`dirpole`] | Frisvad, Hachisuka, Kjeldsen 2014 directional dipole | multiple scattering |
//! | `burley` | [`burley`] | Christensen & Burley 2015 empirical profile | total |
//! | `pbd`, `pbd-fast` | [`pbd`] | photon beam diffusion, reference and fast quadratures | multiple scattering |
//! | `table`, `perpendicular` | [`table`] | the angular table, and its θ = 0 slice used at every θ | multiple scattering |
//! | `mc` | [`mc`] | the random walk itself, binned | total (configurable) |
//!
//! Conventions shared by all models: constructors validate ([`Params::new`]); evaluation never
//! panics and returns 0 outside the support, including where no light enters (θ outside
//! [0, π/2], or sin θ > η); R is even in φ.
//!
//! Adding a model is one file, one [`ModelKind`] variant (with its name) and one arm in
//! [`build`] (docs/architecture.md, "How to add a model").

pub mod burley;
pub mod compare;
pub mod dipole;
pub mod dirpole;
pub mod mc;
pub mod pbd;
pub mod table;

use crate::error::{finite, in_range, Error, Result};
use crate::fresnel::Moments;
use crate::medium::Medium;
use crate::quadrature::adaptive;
use crate::walk::Component;
use std::f64::consts::PI;
use std::fmt;
use std::str::FromStr;

/// One draw of an exit point with its density, in reduced units.
pub use crate::table::Sample;

/// A BSSRDF model in reduced units (see the module docs for the quantity).
pub trait Model: Send + Sync {
    /// Which model this is.
    fn kind(&self) -> ModelKind;

    /// Which part of the transport the model represents (what it is compared with).
    fn component(&self) -> Component;

    /// R(r, φ; θ): power leaving per unit area per unit power entering, reduced units
    /// (r in reduced mfp, result per reduced mfp²), θ before refraction (rad), φ = 0 forward.
    /// Never panics; 0 outside the support; +∞ only at the documented singular points.
    fn eval(&self, theta: f64, r: f64, phi: f64) -> f64;

    /// ∫∫ R dA over the whole plane, where known in closed form or by quadrature.
    fn effective_albedo(&self, _theta: f64) -> Option<f64> {
        None
    }

    /// Draws an exit point from two uniforms in [0, 1), where the model has a sampler.
    fn sample(&self, _theta: f64, _u: [f64; 2]) -> Option<Sample> {
        None
    }

    /// Density per unit area of [`Model::sample`] at (r, φ) (0 without a sampler).
    fn pdf(&self, _theta: f64, _r: f64, _phi: f64) -> f64 {
        0.0
    }
}

impl<M: Model + ?Sized> Model for Box<M> {
    fn kind(&self) -> ModelKind {
        (**self).kind()
    }
    fn component(&self) -> Component {
        (**self).component()
    }
    fn eval(&self, theta: f64, r: f64, phi: f64) -> f64 {
        (**self).eval(theta, r, phi)
    }
    fn effective_albedo(&self, theta: f64) -> Option<f64> {
        (**self).effective_albedo(theta)
    }
    fn sample(&self, theta: f64, u: [f64; 2]) -> Option<Sample> {
        (**self).sample(theta, u)
    }
    fn pdf(&self, theta: f64, r: f64, phi: f64) -> f64 {
        (**self).pdf(theta, r, phi)
    }
}

/// The registered models: the one list of names that `bssrdf zoo`, `bssrdf eval --model`,
/// `bssrdf render --model` ([`crate::render::MODELS`]) and [`build`] share. With the `clap`
/// feature it is a `clap::ValueEnum`, its doc comments the command line's help.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum ModelKind {
    /// Standard dipole (Jensen et al. 2001).
    Dipole,
    /// Directional dipole (Frisvad, Hachisuka, Kjeldsen 2014).
    Dirpole,
    /// Christensen–Burley (2015), searchlight fit.
    Burley,
    /// Photon beam diffusion, multiple scattering (render: table samples weighted by PBD).
    Pbd,
    /// PBD with the fast quadrature used for baking.
    PbdFast,
    /// Ferrier's angular table: PBD at any incidence, tabulated (eval: FILE's table).
    Table,
    /// The table's θ = 0 slice at every θ, uniform in φ (pbrt's assumption).
    Perpendicular,
    /// The angular table baked from the walk (`bake --source walk`; zoo: --walk-table FILE).
    WalkTable,
    /// The Monte Carlo random walk, the reference (eval bins 10⁵ photons per (ρ′, θ)).
    #[cfg_attr(feature = "clap", value(name = "mc"))]
    MonteCarlo,
}

impl ModelKind {
    /// All models, in display order.
    pub const ALL: [ModelKind; 9] = [
        ModelKind::Dipole,
        ModelKind::Dirpole,
        ModelKind::Burley,
        ModelKind::Pbd,
        ModelKind::PbdFast,
        ModelKind::Table,
        ModelKind::Perpendicular,
        ModelKind::WalkTable,
        ModelKind::MonteCarlo,
    ];

    /// The models that need nothing but their parameters: all but [`ModelKind::WalkTable`],
    /// whose table is baked for one (η, g) beforehand (minutes of walking) and given to it
    /// ([`Options::walk_table`]).
    pub fn self_contained() -> Vec<ModelKind> {
        Self::ALL
            .into_iter()
            .filter(|&k| k != ModelKind::WalkTable)
            .collect()
    }

    /// Every name [`ModelKind::from_str`] accepts, comma-separated, for messages.
    pub fn names(models: &[ModelKind]) -> String {
        let names: Vec<&str> = models.iter().map(|m| m.name()).collect();
        names.join(", ")
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Dipole => "dipole",
            ModelKind::Dirpole => "dirpole",
            ModelKind::Burley => "burley",
            ModelKind::Pbd => "pbd",
            ModelKind::PbdFast => "pbd-fast",
            ModelKind::Table => "table",
            ModelKind::Perpendicular => "perpendicular",
            ModelKind::WalkTable => "walk-table",
            ModelKind::MonteCarlo => "mc",
        }
    }
}

impl fmt::Display for ModelKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is not one of the registry's models.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown model {name:?}; expected one of {expected}")]
pub struct UnknownModel {
    /// The name given.
    pub name: String,
    /// The registry's names, comma-separated.
    pub expected: String,
}

impl FromStr for ModelKind {
    type Err = UnknownModel;
    fn from_str(s: &str) -> std::result::Result<Self, UnknownModel> {
        ModelKind::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| UnknownModel {
                name: s.to_owned(),
                expected: ModelKind::names(&ModelKind::ALL),
            })
    }
}

impl serde::Serialize for ModelKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for ModelKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}

/// The medium in reduced units, validated: what every model is built from.
///
/// | parameter | unit | valid range |
/// |---|---|---|
/// | ρ′ reduced albedo σ′s/σ′t | – | [0, 1] |
/// | η relative index, inside over outside | – | [0.75, 2.5] ([`crate::medium::validate_eta`]) |
/// | g Henyey–Greenstein asymmetry | – | (−1, 1); only the walk and the directional dipole's back-lit branch see it |
/// | moments | – | Fresnel moments for the boundary constants |
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Params {
    rho_prime: f64,
    eta: f64,
    g: f64,
    moments: Moments,
}

impl Params {
    /// Validated parameters with g = 0.
    pub fn new(rho_prime: f64, eta: f64, moments: Moments) -> Result<Self> {
        in_range("rho'", rho_prime, 0.0, 1.0)?;
        crate::medium::validate_eta(eta)?;
        Ok(Self {
            rho_prime,
            eta,
            g: 0.0,
            moments,
        })
    }

    /// The same parameters with asymmetry g ∈ (−1, 1).
    pub fn with_g(self, g: f64) -> Result<Self> {
        finite("g", g)?;
        if g.abs() >= 1.0 {
            return Err(Error::AsymmetryOutOfRange(g));
        }
        Ok(Self { g, ..self })
    }

    /// The reduced parameters of a medium, and its σ′t (mm⁻¹) for [`World`].
    pub fn from_medium(medium: &Medium, moments: Moments) -> Result<(Self, f64)> {
        let params = Self::new(medium.rho_prime().clamp(0.0, 1.0), medium.eta(), moments)?
            .with_g(medium.g())?;
        Ok((params, medium.sigma_t_prime()))
    }

    /// ρ′.
    pub fn rho_prime(&self) -> f64 {
        self.rho_prime
    }
    /// η.
    pub fn eta(&self) -> f64 {
        self.eta
    }
    /// g.
    pub fn g(&self) -> f64 {
        self.g
    }
    /// Fresnel moments.
    pub fn moments(&self) -> Moments {
        self.moments
    }
    /// Unreduced single-scattering albedo a = ρ′/(1 − g + gρ′) (so that σ′s/σ′t = ρ′).
    pub fn albedo(&self) -> f64 {
        let denominator = 1.0 - self.g + self.g * self.rho_prime;
        if denominator > 0.0 {
            (self.rho_prime / denominator).min(1.0)
        } else {
            1.0
        }
    }
    /// σt/σ′t = 1/(1 − g·a): the unreduced extinction in reduced units.
    pub fn sigma_t_over_reduced(&self) -> f64 {
        1.0 / (1.0 - self.g * self.albedo())
    }
}

/// Per-model options for [`build`]; every field has a default.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// Standard dipole.
    pub dipole: dipole::DipoleOptions,
    /// Directional dipole.
    pub dirpole: dirpole::DirpoleOptions,
    /// Christensen–Burley.
    pub burley: burley::BurleyOptions,
    /// Where the table models get their table.
    pub table: table::TableSource,
    /// The walk table of [`ModelKind::WalkTable`] (a walk-angular table, [`crate::table::AngularTable::walk`]),
    /// for the model's η and g.
    pub walk_table: Option<std::sync::Arc<crate::table::AngularTable>>,
    /// The Monte Carlo model.
    pub mc: mc::McOptions,
}

/// Builds a model by kind: the registry.
pub fn build(kind: ModelKind, params: &Params, options: &Options) -> Result<Box<dyn Model>> {
    Ok(match kind {
        ModelKind::Dipole => Box::new(dipole::Dipole::new(*params, options.dipole)),
        ModelKind::Dirpole => Box::new(dirpole::Dirpole::new(*params, options.dirpole)),
        ModelKind::Burley => Box::new(burley::Burley::new(*params, options.burley)?),
        ModelKind::Pbd => Box::new(pbd::PbdModel::new(*params, crate::pbd::Rule::Reference)?),
        ModelKind::PbdFast => Box::new(pbd::PbdModel::new(*params, crate::pbd::Rule::Fast)?),
        ModelKind::Table => Box::new(table::TableModel::new(
            params,
            &options.table,
            table::Mode::Angular,
        )?),
        ModelKind::Perpendicular => Box::new(table::TableModel::new(
            params,
            &options.table,
            table::Mode::Perpendicular,
        )?),
        ModelKind::WalkTable => Box::new(table::TableModel::walk(
            params,
            options.walk_table.as_ref(),
        )?),
        ModelKind::MonteCarlo => Box::new(mc::McModel::run(params, &options.mc)?),
    })
}

/// cos θ′ of the refracted beam, or `None` where no light enters: θ outside [0, π/2] or NaN,
/// or sin θ > η (η < 1 beyond the critical angle).
pub fn entering(theta: f64, eta: f64) -> Option<f64> {
    crate::fresnel::refracted_cos(theta, eta)
}

/// ∫∫ R dA by nested adaptive quadrature: φ over [0, π] (R is even), r over [0, ∞) mapped by
/// r = s·y/(1 − y) with s = 1 reduced mfp. Relative tolerance about 1e-7; for models whose
/// total has no closed form.
pub fn integrate_total(model: &dyn Model, theta: f64) -> f64 {
    let radial = |phi: f64| {
        adaptive(
            |y: f64| {
                let one_minus = 1.0 - y;
                let r = y / one_minus;
                let v = model.eval(theta, r, phi) * r / (one_minus * one_minus);
                if v.is_finite() {
                    v
                } else {
                    0.0
                }
            },
            &[0.0, 0.01, 0.1, 0.5, 0.9, 0.99, 1.0],
            1e-8,
            1e-300,
            400,
        )
        .value
    };
    let total = adaptive(radial, &[0.0, 0.05, 0.25, 0.5 * PI, PI], 1e-7, 1e-300, 200);
    2.0 * total.value
}

/// A model in world units for a medium of reduced extinction σ′t (mm⁻¹):
/// r_reduced = σ′t r_mm, R_world = σ′t² R_reduced (mm⁻²), densities likewise.
#[derive(Debug, Clone)]
pub struct World<M> {
    model: M,
    sigma_t_prime: f64,
}

impl<M: Model> World<M> {
    /// Wraps a model for σ′t ∈ [1e-9, 1e12] mm⁻¹.
    pub fn new(model: M, sigma_t_prime: f64) -> Result<Self> {
        crate::medium::check_sigma_t_prime(sigma_t_prime)?;
        Ok(Self {
            model,
            sigma_t_prime,
        })
    }
    /// The wrapped model.
    pub fn model(&self) -> &M {
        &self.model
    }
    /// σ′t, mm⁻¹.
    pub fn sigma_t_prime(&self) -> f64 {
        self.sigma_t_prime
    }
    /// R in mm⁻² at r in mm.
    pub fn eval(&self, theta: f64, r_mm: f64, phi: f64) -> f64 {
        let st = self.sigma_t_prime;
        st * st * self.model.eval(theta, st * r_mm, phi)
    }
    /// ∫∫ R dA (dimensionless, the same in any units).
    pub fn effective_albedo(&self, theta: f64) -> Option<f64> {
        self.model.effective_albedo(theta)
    }
    /// Draws (r in mm, φ) with its density per mm², which is [`World::pdf`] there (computed
    /// there where σ′t·r_mm does not give back the drawn distance exactly, see
    /// [`crate::table::World::sample`]).
    pub fn sample(&self, theta: f64, u: [f64; 2]) -> Option<Sample> {
        let st = self.sigma_t_prime;
        let s = self.model.sample(theta, u)?;
        let r = crate::table::reduced_to_mm(s.r, st);
        let pdf = if st * r == s.r {
            s.pdf * st * st
        } else {
            self.pdf(theta, r, s.phi)
        };
        (pdf > 0.0).then_some(Sample { r, phi: s.phi, pdf })
    }
    /// Density per mm² of [`World::sample`].
    pub fn pdf(&self, theta: f64, r_mm: f64, phi: f64) -> f64 {
        let st = self.sigma_t_prime;
        st * st * self.model.pdf(theta, st * r_mm, phi)
    }
}

impl World<Box<dyn Model>> {
    /// Builds a registered model for a medium given in world units.
    pub fn for_medium(
        kind: ModelKind,
        medium: &Medium,
        moments: Moments,
        options: &Options,
    ) -> Result<Self> {
        let (params, sigma_t_prime) = Params::from_medium(medium, moments)?;
        Self::new(build(kind, &params, options)?, sigma_t_prime)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_rejected_with_the_list() {
        for k in ModelKind::ALL {
            assert_eq!(k.name().parse::<ModelKind>().unwrap(), k);
            assert_eq!(k.to_string(), k.name());
        }
        let err = "dipol".parse::<ModelKind>().unwrap_err().to_string();
        assert!(
            err.contains("\"dipol\"") && err.contains("pbd-fast"),
            "{err}"
        );
    }

    #[test]
    fn params_reject_bad_values_by_name() {
        let e = |r: Result<Params>| r.unwrap_err().to_string();
        assert!(e(Params::new(1.5, 1.3, Moments::Exact)).contains("rho'"));
        assert!(e(Params::new(f64::NAN, 1.3, Moments::Exact)).contains("rho'"));
        assert!(e(Params::new(0.5, 0.0, Moments::Exact)).contains("eta = 0"));
        let p = Params::new(0.5, 1.3, Moments::Exact).unwrap();
        assert!(e(p.with_g(1.0)).contains("g = 1"));
    }

    #[test]
    fn unreduced_albedo_reproduces_the_reduced_one() {
        for g in [-0.5, 0.0, 0.3, 0.9] {
            for rho in [0.0, 0.3, 0.9, 1.0] {
                let p = Params::new(rho, 1.3, Moments::Exact)
                    .unwrap()
                    .with_g(g)
                    .unwrap();
                let a = p.albedo();
                // σt = 1: σ′s = a(1 − g), σ′t = a(1 − g) + 1 − a.
                let back = a * (1.0 - g) / (a * (1.0 - g) + 1.0 - a);
                assert!((back - rho).abs() < 1e-14, "g {g} rho {rho}");
                assert!((p.sigma_t_over_reduced() * (1.0 - g * a) - 1.0).abs() < 1e-14);
            }
        }
    }
}
