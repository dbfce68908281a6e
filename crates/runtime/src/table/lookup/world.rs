//! Lookups in world units: r in mm, S in mm⁻², for a medium of reduced extinction σ′t.

use super::*;

/// The distance in mm of a reduced distance r for reduced extinction σ′t (r_mm = r/σ′t),
/// rounded down where the quotient rounds up: the lookups in mm convert back by σ′t·r_mm,
/// which so never passes r (a draw on the last radius node stays inside the table).
pub fn reduced_to_mm(r: f64, sigma_t_prime: f64) -> f64 {
    let mut r_mm = r / sigma_t_prime;
    while r_mm > 0.0 && sigma_t_prime * r_mm > r {
        r_mm = crate::float::next_down(r_mm);
    }
    r_mm
}

/// A table looked up in world units for a medium with reduced extinction σ′t (mm⁻¹):
/// r_reduced = σ′t r_mm and S_world = σ′t² S_reduced (an area density).
#[derive(Debug, Clone, Copy)]
pub struct World<'a> {
    table: TableRef<'a>,
    sigma_t_prime: f64,
}

impl<'a> World<'a> {
    /// Wraps a table for a medium of reduced extinction σ′t ∈ [1e-9, 1e12] mm⁻¹.
    pub fn new(table: TableRef<'a>, sigma_t_prime: f64) -> crate::Result<Self> {
        let sigma_t_prime = crate::medium::check_sigma_t_prime(sigma_t_prime)?;
        Ok(Self::prevalidated(table, sigma_t_prime))
    }
    /// [`World::new`] for a σ′t already checked by it.
    pub(crate) fn prevalidated(table: TableRef<'a>, sigma_t_prime: f64) -> Self {
        Self {
            table,
            sigma_t_prime,
        }
    }
    /// S in mm⁻² at r in mm.
    pub fn eval(&self, rho: f64, theta: f64, r_mm: f64, phi: f64) -> Option<f64> {
        let st = self.sigma_t_prime;
        Some(st * st * self.table.eval(rho, theta, st * r_mm, phi)?)
    }
    /// Draws (r in mm, φ) with its density per mm², which is [`World::pdf`] there.
    ///
    /// The radial density jumps at radius nodes by the rounding of the stored CDF (far out in
    /// the tail, where a segment holds less than an f32 ulp of the total, by orders of
    /// magnitude), and a draw with u_r near 1 lands on a node; near φ = π a signed floor's
    /// profile nears 0, where an ulp of r can make it 0. Where σ′t·r_mm does not give back the
    /// drawn distance exactly (about one random pair (r, σ′t) in eleven has no distance in mm
    /// that does), the density returned is [`World::pdf`] at the point returned.
    pub fn sample(&self, rho: f64, theta: f64, u_r: f64, u_phi: f64) -> Option<Sample> {
        let st = self.sigma_t_prime;
        let s = self.table.sample(rho, theta, u_r, u_phi)?;
        let r = reduced_to_mm(s.r, st);
        let pdf = if st * r == s.r {
            s.pdf * st * st
        } else {
            self.pdf(rho, theta, r, s.phi)
        };
        (pdf > 0.0).then_some(Sample { r, phi: s.phi, pdf })
    }
    /// The path-tracing draw ([`TableRef::sample_path`]) with r in mm and the joint density
    /// per mm², which is `pdf_theta` times [`World::pdf`] at (θ, r, φ) over 2π (see
    /// [`World::sample`] for the point on a radius node).
    pub fn sample_path(&self, rho: f64, u: [f64; 4]) -> Option<PathSample> {
        let st = self.sigma_t_prime;
        let p = self.table.sample_path(rho, u)?;
        let r = reduced_to_mm(p.r, st);
        let pdf = if st * r == p.r {
            p.pdf * st * st
        } else {
            p.pdf_theta * self.pdf(rho, p.theta, r, p.phi) / TAU
        };
        (pdf > 0.0).then_some(PathSample { r, pdf, ..p })
    }
    /// Density per mm² of [`World::sample`].
    pub fn pdf(&self, rho: f64, theta: f64, r_mm: f64, phi: f64) -> f64 {
        let st = self.sigma_t_prime;
        st * st * self.table.pdf(rho, theta, st * r_mm, phi)
    }
}
