//! The walk's exit events one photon at a time, for pictures (`crate::render`'s Monte Carlo
//! reference): the same transport as [`crate::walk::run`], with every score handed to the caller
//! as a weighted exit point instead of being binned.
//!
//! | parameter | unit | range |
//! |---|---|---|
//! | `albedo` | – | a = σs/σt (unreduced), [0, 1] |
//! | `g` | – | Henyey–Greenstein asymmetry, (−1, 1) |
//! | `eta` | – | η = n_inside/n_outside, in [0.75, 2.5] |
//! | `theta` (per photon) | radians | [0, π/2]; at most asin η when η < 1 |
//!
//! Geometry: the half-space z < 0, distances in mean free paths (σt = 1), the refracted beam
//! travelling toward +x (φ = 0 forward). Each [`Exit`] is one score of the walk's estimator (see
//! the [`crate::walk`] module docs): the expected transmitted weight of one flight, at the point
//! where that flight meets the surface, per unit power entering. A photon gives many exits; the
//! sum of their weights over many photons estimates the reflectance, and any tally of them over
//! regions of the surface (pixels) is unbiased for the exitance there.

use super::rng::Xoshiro256PlusPlus;
use super::tally::{Order, PhotonTally, Surface};
use super::transport::Medium;
use super::Component;
use crate::error::{finite, in_range, Error, Result};
use std::f64::consts::FRAC_PI_2;

/// Where the transport loop sends its scores: the walk's binned tally, or an exit callback.
pub(crate) trait Sink {
    /// Scores `weight` leaving through `surface` at (x, y) after `order` scattering vertices.
    fn exit(&mut self, surface: Surface, x: f64, y: f64, weight: f64, order: Order);
    /// Counts one scattering vertex.
    fn vertex(&mut self);
    /// Records weight dropped at the vertex cap.
    fn truncate(&mut self, weight: f64);
}

impl Sink for PhotonTally<'_> {
    fn exit(&mut self, surface: Surface, x: f64, y: f64, weight: f64, order: Order) {
        PhotonTally::exit(self, surface, x, y, weight, order);
    }
    fn vertex(&mut self) {
        PhotonTally::vertex(self);
    }
    fn truncate(&mut self, weight: f64) {
        PhotonTally::truncate(self, weight);
    }
}

/// One score of the walk's exit estimator on the lit surface z = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exit {
    /// Exit point, mean free paths; +x is forward (in the plane of incidence).
    pub x: f64,
    /// Exit point, mean free paths, across the plane of incidence.
    pub y: f64,
    /// Expected power leaving here, per unit power entering.
    pub weight: f64,
    /// [`Component::Single`] (one scattering vertex before the exit) or
    /// [`Component::Multiple`] (two or more).
    pub component: Component,
}

/// What one traced photon did besides its exits.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PhotonPath {
    /// Scattering vertices.
    pub vertices: u64,
    /// Weight dropped at the vertex cap ([`crate::walk::MAX_VERTICES`]); 0 unless a ≈ 1.
    pub truncated_weight: f64,
}

/// A validated half-space medium whose photons are traced one at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExitWalk {
    albedo: f64,
    g: f64,
    eta: f64,
}

struct Callback<F> {
    on_exit: F,
    path: PhotonPath,
}

impl<F: FnMut(Exit)> Sink for Callback<F> {
    fn exit(&mut self, surface: Surface, x: f64, y: f64, weight: f64, order: Order) {
        // A half-space has no bottom and lets no unscattered light out; a score there
        // would be a bug in the transport, never a picture.
        let component = match (surface, order) {
            (Surface::Top, Order::Single) => Component::Single,
            (Surface::Top, Order::Multiple) => Component::Multiple,
            _ => return,
        };
        (self.on_exit)(Exit {
            x,
            y,
            weight,
            component,
        });
    }
    fn vertex(&mut self) {
        self.path.vertices += 1;
    }
    fn truncate(&mut self, weight: f64) {
        self.path.truncated_weight += weight;
    }
}

impl ExitWalk {
    /// Checks albedo ∈ [0, 1], g ∈ (−1, 1) and η > 0, naming the first bad value.
    pub fn new(albedo: f64, g: f64, eta: f64) -> Result<Self> {
        in_range("albedo", albedo, 0.0, 1.0)?;
        finite("g", g)?;
        if g.abs() >= 1.0 {
            return Err(Error::AsymmetryOutOfRange(g));
        }
        crate::medium::validate_eta(eta)?;
        Ok(Self { albedo, g, eta })
    }

    /// Traces one photon of unit power entering at the origin at incidence `theta` (radians,
    /// before refraction), calling `on_exit` for every score in the order the walk makes them.
    /// An incidence outside [0, π/2], or beyond the critical angle when η < 1, lets no light
    /// in: no exits.
    pub fn trace(
        &self,
        theta: f64,
        rng: &mut Xoshiro256PlusPlus,
        on_exit: impl FnMut(Exit),
    ) -> PhotonPath {
        let enters = (0.0..=FRAC_PI_2).contains(&theta) && theta.sin() <= self.eta;
        let mut sink = Callback {
            on_exit,
            path: PhotonPath::default(),
        };
        if enters {
            Medium::new(self.albedo, self.g, self.eta, theta, None).trace(rng, &mut sink);
        }
        sink.path
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::walk::rng::photon_stream;
    use crate::walk::{run, Config};

    #[test]
    fn exits_sum_to_the_walks_reflectance() {
        // The same photons through both sinks: identical sums, bit for bit.
        let theta = 50f64.to_radians();
        let config = Config {
            photons: 300,
            seed: 9,
            ..Config::new(0.9, 0.3, 1.33, theta)
        };
        let walked = run(&config).unwrap();
        let exits = ExitWalk::new(0.9, 0.3, 1.33).unwrap();
        let (mut single, mut multiple, mut events) = (0.0, 0.0, 0);
        for index in 0..config.photons {
            let mut rng = photon_stream(config.seed, index);
            let (mut s, mut m) = (0.0, 0.0);
            let path = exits.trace(theta, &mut rng, |e| match e.component {
                Component::Single => s += e.weight,
                _ => m += e.weight,
            });
            single += s;
            multiple += m;
            events += path.vertices;
        }
        let n = config.photons as f64;
        assert_eq!(events, walked.scattering_events());
        assert!((single / n - walked.single_reflectance().value).abs() < 1e-12);
        assert!((multiple / n - walked.multiple_reflectance().value).abs() < 1e-12);
    }

    #[test]
    fn no_light_enters_beyond_the_critical_angle() {
        let exits = ExitWalk::new(0.9, 0.0, 0.8).unwrap();
        let mut rng = photon_stream(1, 1);
        let mut count = 0;
        let path = exits.trace(60f64.to_radians(), &mut rng, |_| count += 1);
        assert_eq!((count, path.vertices), (0, 0));
        assert!(ExitWalk::new(1.5, 0.0, 1.0).is_err());
        assert!(ExitWalk::new(0.5, 1.0, 1.0).is_err());
        assert!(ExitWalk::new(0.5, 0.0, 0.0).is_err());
    }
}
