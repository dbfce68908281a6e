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

/// The reduced distance σ′t·r_mm, negative where r_mm is: a negative r_mm whose product
/// underflows to −0 (−5e-324 mm at σ′t = 0.5) would be read as r = 0, while every lookup
/// refuses a negative distance (the C interface's single calls by name, the batches with 0).
#[inline]
pub(super) fn mm_to_reduced(r_mm: f64, sigma_t_prime: f64) -> f64 {
    let r = sigma_t_prime * r_mm;
    if r == 0.0 && r_mm < 0.0 {
        -f64::from_bits(1)
    } else {
        r
    }
}

/// A table looked up in world units for a medium with reduced extinction σ′t (mm⁻¹):
/// r_reduced = σ′t r_mm and S_world = σ′t² S_reduced (an area density).
#[derive(Debug, Clone, Copy)]
pub struct World<'a> {
    pub(super) table: TableRef<'a>,
    pub(super) sigma_t_prime: f64,
}

impl<'a> World<'a> {
    /// Wraps a table for a medium of reduced extinction σ′t ∈ [1e-9, 1e12] mm⁻¹.
    pub fn new(table: TableRef<'a>, sigma_t_prime: f64) -> crate::Result<Self> {
        let sigma_t_prime = crate::medium::check_sigma_t_prime(sigma_t_prime)?;
        Ok(Self::prevalidated(table, sigma_t_prime))
    }
    /// [`World::new`] for a σ′t already checked by it.
    #[inline]
    pub(crate) fn prevalidated(table: TableRef<'a>, sigma_t_prime: f64) -> Self {
        Self {
            table,
            sigma_t_prime,
        }
    }
    /// S in mm⁻² at r in mm.
    #[inline]
    pub fn eval(&self, rho: f64, theta: f64, r_mm: f64, phi: f64) -> Option<f64> {
        let st = self.sigma_t_prime;
        Some(st * st * self.table.eval(rho, theta, mm_to_reduced(r_mm, st), phi)?)
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
    #[inline]
    pub fn pdf(&self, rho: f64, theta: f64, r_mm: f64, phi: f64) -> f64 {
        let st = self.sigma_t_prime;
        st * st * self.table.pdf(rho, theta, mm_to_reduced(r_mm, st), phi)
    }
}

/// One medium on a table in world units, given per call: reduced albedo ρ′ and reduced
/// extinction σ′t (mm⁻¹) both checked against the table, then the lookups of a
/// [`crate::embed::ChannelLookup`] without a handle: r in mm, S and densities per mm², θ and φ
/// in radians.
///
/// Made by [`TableRef::medium`] in O(1) without allocating, so a renderer can make one per
/// shading point (a textured medium) or per wavelength: one table in reduced units serves every
/// (ρ′, σ′t) of its η. Its lookups give the bits of a handle made for the same medium
/// ([`crate::embed::TableLookup::medium`]), which computes through this type.
///
/// ```
/// # use bssrdf_zoo::fresnel::Moments;
/// # use bssrdf_zoo::table::{bake, Grid};
/// # let (table, _) = bake(1.33, Moments::Exact, &Grid::ferrier(6, 4, 10), true)?;
/// let view = table.view();
/// // Per shading point: ρ′ and σ′t (mm⁻¹) from the textures
/// let medium = view.medium(0.95, 2.5)?;
/// let s = medium.eval(0.3, 0.4, 0.0).expect("θ within the table"); // mm⁻²
/// assert!(s > 0.0);
/// if let Some(hit) = medium.sample(0.3, 0.25, 0.75) {
///     assert!((hit.pdf / medium.pdf(0.3, hit.r, hit.phi) - 1.0).abs() < 1e-12);
/// }
/// // Out-of-domain media are errors naming the value and its range
/// let err = view.medium(1.5, 2.5).unwrap_err();
/// assert!(err.to_string().starts_with("reduced albedo rho' = 1.5 is outside [0, 1]"));
/// assert!(view.medium(0.5, 0.0).is_err()); // σ′t = 0: vacuum
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct MediumRef<'a> {
    pub(super) world: World<'a>,
    pub(super) rho: f64,
}

impl<'a> TableRef<'a> {
    /// The lookups in world units of the medium of reduced albedo ρ′ = σ′s/σ′t and reduced
    /// extinction σ′t (mm⁻¹) on this table (η is the table's). Fails, naming the value and its
    /// range, for σ′t not finite and in [1e-9, 1e12] mm⁻¹ (the range of
    /// [`crate::medium::Medium`]) and, with [`crate::Error::AlbedoOutsideTable`], for ρ′ NaN or
    /// outside the table's albedo rows (a scene bake keeps only some): a table is never
    /// extrapolated. O(1); allocates nothing, failing or not.
    #[inline]
    pub fn medium(&self, rho_prime: f64, sigma_t_prime: f64) -> crate::Result<MediumRef<'a>> {
        let sigma_t_prime = crate::medium::check_sigma_t_prime(sigma_t_prime)?;
        if !self.keeps_rho(rho_prime) {
            // (The albedos the lookups take, as θ's errors name theta_domain)
            let [min, max] = self.rho_domain();
            return Err(crate::Error::AlbedoOutsideTable {
                rho: rho_prime,
                min,
                max,
            });
        }
        Ok(MediumRef::prevalidated(*self, rho_prime, sigma_t_prime))
    }
}

impl<'a> MediumRef<'a> {
    /// [`TableRef::medium`] for a ρ′ and σ′t it has already accepted on this table's axes.
    #[inline]
    pub(crate) fn prevalidated(table: TableRef<'a>, rho: f64, sigma_t_prime: f64) -> Self {
        Self {
            world: World::prevalidated(table, sigma_t_prime),
            rho,
        }
    }

    /// Reduced albedo ρ′ = σ′s/σ′t.
    pub fn rho_prime(&self) -> f64 {
        self.rho
    }

    /// Reduced extinction σ′t, mm⁻¹.
    pub fn sigma_t_prime(&self) -> f64 {
        self.world.sigma_t_prime
    }

    /// The table the medium is looked up on, in reduced units.
    pub fn table(&self) -> TableRef<'a> {
        self.world.table
    }

    /// S_p(r, φ; θ) in mm⁻² at distance `r_mm` (mm) and azimuth `phi` from the entry point,
    /// for light entering at incidence `theta` (radians, before refraction): 0 outside the
    /// radial support (r < 0, beyond the last radius node, NaN r or φ); `None` for θ outside
    /// the table's θ axis.
    #[inline]
    pub fn eval(&self, theta: f64, r_mm: f64, phi: f64) -> Option<f64> {
        self.world.eval(self.rho, theta, r_mm, phi)
    }

    /// Density per mm² of [`MediumRef::sample`] at (r, φ): 0 where it cannot sample.
    #[inline]
    pub fn pdf(&self, theta: f64, r_mm: f64, phi: f64) -> f64 {
        self.world.pdf(self.rho, theta, r_mm, phi)
    }

    /// Draws the exit point (r in mm, φ) for incidence θ from two uniforms in [0, 1), with its
    /// density per mm² (> 0, [`MediumRef::pdf`] there). `None` where the table holds no energy
    /// (ρ′ = 0, light beyond the critical angle) or θ is outside the table.
    #[inline]
    pub fn sample(&self, theta: f64, u_r: f64, u_phi: f64) -> Option<Sample> {
        self.world.sample(self.rho, theta, u_r, u_phi)
    }

    /// The path-tracing draw from four uniforms: θ from ρ_eff(ρ′, ·), then (r, φ) given θ, then
    /// φ′ uniform (Ferrier's algorithm 3). `None` if the table was baked without θ sampling or
    /// holds no energy for this medium.
    #[inline]
    pub fn sample_path(&self, u: [f64; 4]) -> Option<PathSample> {
        self.world.sample_path(self.rho, u)
    }

    /// Density of θ in [`MediumRef::sample_path`], per radian (0 without θ sampling). σ′t does
    /// not enter it.
    #[inline]
    pub fn pdf_theta(&self, theta: f64) -> f64 {
        self.world.table.pdf_theta(self.rho, theta)
    }

    /// Effective albedo ρ_eff(θ), dimensionless: `None` for θ outside the table. σ′t does not
    /// enter it.
    #[inline]
    pub fn effective_albedo(&self, theta: f64) -> Option<f64> {
        self.world.table.effective_albedo(self.rho, theta)
    }

    /// The diffuse reflectance A = (1 − F_r(cos θ; η)) ρ_eff(θ) for light arriving at incidence
    /// θ (radians, before refraction), dimensionless: what an artist's colour gives
    /// ([`TableRef::diffuse_reflectance`], inverted by [`TableRef::rho_prime_for_reflectance`]).
    /// `None` for θ outside the table. σ′t does not enter it.
    #[inline]
    pub fn diffuse_reflectance(&self, theta: f64) -> Option<f64> {
        self.world.table.diffuse_reflectance(self.rho, theta)
    }
}
