//! The per-medium lookup handle: S_p, sampling and densities in world units.

use super::TableLookup;
use crate::table::{MediumRef, RadialSample};

/// The draws of a handle, in world units (mm, mm⁻²).
pub use crate::table::{PathSample, Sample};

/// Lookups for one medium (one colour channel of a material, or any ρ′ and σ′t) on one table,
/// in world units: r in mm, S and densities per mm², θ and φ in radians.
///
/// A lookup at (θ, r, φ) is the table's at (ρ′, θ, σ′t r, φ), times σ′t² for S and the
/// densities (bit for bit what [`crate::table::World`] computes). ρ′ was checked against the
/// table's albedo rows when the handle was made, so evaluation returns `None` only for θ outside
/// the table's θ axis ([0, π/2] for baked tables) or NaN. Cheap to clone (one `Arc`),
/// `Send + Sync`, keeps the library alive; lookups never allocate.
///
/// ```
/// # use bssrdf_zoo::embed::Library;
/// use bssrdf_zoo::materials::Rgb;
/// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
/// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
/// let blue = library.channel("skin1", Rgb::Blue)?;
/// let workers: Vec<_> = (0..2)
///     .map(|k| {
///         let blue = blue.clone();
///         std::thread::spawn(move || blue.eval(0.3 * k as f64, 0.25, 0.0).unwrap())
///     })
///     .collect();
/// for w in workers {
///     assert!(w.join().unwrap() > 0.0);
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct ChannelLookup {
    table: TableLookup,
    rho: f64,
    sigma_t_prime: f64,
}

impl ChannelLookup {
    /// `rho` inside the table's albedo rows and `sigma_t_prime` in [1e-9, 1e12] (checked by the
    /// makers in `library.rs`).
    pub(super) fn new(table: TableLookup, rho: f64, sigma_t_prime: f64) -> Self {
        Self {
            table,
            rho,
            sigma_t_prime,
        }
    }

    /// The table the medium is looked up in (its reduced-unit [`TableLookup::view`], η, index).
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let red = library.channel("skin1", Rgb::Red)?;
    /// assert_eq!(red.table().eta(), 1.3);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn table(&self) -> &TableLookup {
        &self.table
    }

    /// Reduced albedo ρ′ = σ′s/σ′t of the medium.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let red = library.channel("skin1", Rgb::Red)?;
    /// assert_eq!(red.rho_prime(), 0.74 / (0.74 + 0.032));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn rho_prime(&self) -> f64 {
        self.rho
    }

    /// Reduced extinction σ′t = σs(1 − g) + σa of the medium, mm⁻¹.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let red = library.channel("skin1", Rgb::Red)?;
    /// assert_eq!(red.sigma_t_prime(), 0.74 + 0.032);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn sigma_t_prime(&self) -> f64 {
        self.sigma_t_prime
    }

    /// S_p(r, φ; θ) in mm⁻² at distance `r_mm` (mm) and azimuth `phi` from the entry point,
    /// for light entering at incidence `theta` (radians, before refraction). Multiple
    /// scattering per unit area per unit power entering the medium (no entry Fresnel factor).
    /// 0 outside the radial support (r < 0, beyond the last radius node, NaN r or φ); `None`
    /// for θ outside the table's θ axis.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let red = library.channel("skin1", Rgb::Red)?;
    /// let theta = 60f64.to_radians();
    /// let forward = red.eval(theta, 1.0, 0.0).unwrap();
    /// let backward = red.eval(theta, 1.0, std::f64::consts::PI).unwrap();
    /// assert!(forward > backward); // oblique light exits ahead of the entry point
    /// assert_eq!(red.eval(2.0, 1.0, 0.0), None); // θ > 90°
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn eval(&self, theta: f64, r_mm: f64, phi: f64) -> Option<f64> {
        self.lookup(false).eval(theta, r_mm, phi)
    }

    /// Density per mm² of [`ChannelLookup::sample`] at (r, φ): 0 where it cannot sample.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let red = library.channel("skin1", Rgb::Red)?;
    /// assert!(red.pdf(0.5, 1.0, 0.3) > 0.0);
    /// assert_eq!(red.pdf(0.5, -1.0, 0.3), 0.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn pdf(&self, theta: f64, r_mm: f64, phi: f64) -> f64 {
        self.lookup(false).pdf(theta, r_mm, phi)
    }

    /// Draws the exit point (r in mm, φ) for incidence θ from two uniforms in [0, 1), with its
    /// density per mm² (equal to [`ChannelLookup::pdf`] there). `None` where the table holds no
    /// energy (ρ′ = 0, light beyond the critical angle) or θ is outside the table.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let red = library.channel("skin1", Rgb::Red)?;
    /// let s = red.sample(0.5, 0.25, 0.75).unwrap();
    /// let weight = red.eval(0.5, s.r, s.phi).unwrap() / s.pdf; // ≈ ρ_eff(θ)
    /// assert!((weight / red.effective_albedo(0.5).unwrap() - 1.0).abs() < 0.05);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn sample(&self, theta: f64, u_r: f64, u_phi: f64) -> Option<Sample> {
        self.lookup(false).sample(theta, u_r, u_phi)
    }

    /// The path-tracing draw from four uniforms: θ from ρ_eff(ρ′, ·), then (r, φ) given θ, then
    /// φ′ uniform (Ferrier's algorithm 3). `None` if the table was baked without θ sampling or
    /// holds no energy for this medium.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let green = library.channel("skin1", Rgb::Green)?;
    /// let p = green.sample_path([0.1, 0.2, 0.3, 0.4]).unwrap();
    /// let given_theta = green.pdf(p.theta, p.r, p.phi);
    /// assert!((p.pdf - p.pdf_theta * given_theta / std::f64::consts::TAU).abs() <= 1e-12 * p.pdf);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn sample_path(&self, u: [f64; 4]) -> Option<PathSample> {
        self.lookup(true).sample_path(u)
    }

    /// Density of θ in [`ChannelLookup::sample_path`], per radian (0 without θ sampling).
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let green = library.channel("skin1", Rgb::Green)?;
    /// assert!(green.pdf_theta(0.2) > 0.0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn pdf_theta(&self, theta: f64) -> f64 {
        self.lookup(true).pdf_theta(theta)
    }

    /// Effective albedo ρ_eff(θ) = ∫∫ S dA: the multiply scattered power leaving the surface per
    /// unit power entering at incidence θ (dimensionless, the same in every unit system).
    /// `None` for θ outside the table.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let [r, b] = [Rgb::Red, Rgb::Blue].map(|c| library.channel("skin1", c).unwrap());
    /// assert!(r.effective_albedo(0.0).unwrap() > b.effective_albedo(0.0).unwrap());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn effective_albedo(&self, theta: f64) -> Option<f64> {
        self.lookup(false).effective_albedo(theta)
    }

    /// The diffuse reflectance A = (1 − F_r(cos θ; η)) ρ_eff(θ) for light arriving at incidence
    /// θ: the multiply scattered power leaving per unit power *arriving*, the entry Fresnel
    /// transmittance included, which is what an artist's colour gives
    /// ([`crate::table::TableRef::rho_prime_for_reflectance`] inverts it). `None` for θ outside
    /// the table.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let red = library.channel("skin1", Rgb::Red)?;
    /// let a = red.diffuse_reflectance(0.0).unwrap();
    /// assert!(a < red.effective_albedo(0.0).unwrap()); // the boundary reflects some at entry
    /// let rho = red.table().view().rho_prime_for_reflectance(a, 0.0)?;
    /// assert!((rho - red.rho_prime()).abs() < 1e-6);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn diffuse_reflectance(&self, theta: f64) -> Option<f64> {
        self.lookup(false).diffuse_reflectance(theta)
    }

    /// For separable renderers: the exit distance in mm for incidence θ drawn from one uniform
    /// u ∈ [0, 1), with its density per mm ([`MediumRef::sample_radius`]: the radial step of
    /// [`ChannelLookup::sample`], the same u giving the same r). `None` where `sample` is.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let red = library.channel("skin1", Rgb::Red)?;
    /// let d = red.sample_radius(0.5, 0.25).unwrap();
    /// assert_eq!(d.r, red.sample(0.5, 0.25, 0.75).unwrap().r);
    /// assert!((d.pdf / red.pdf_radius(0.5, d.r) - 1.0).abs() < 1e-12);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn sample_radius(&self, theta: f64, u: f64) -> Option<RadialSample> {
        self.lookup(false).sample_radius(theta, u)
    }

    /// Density per mm of [`ChannelLookup::sample_radius`] at `r_mm`: 0 where it cannot sample
    /// ([`MediumRef::pdf_radius`]).
    #[inline]
    pub fn pdf_radius(&self, theta: f64, r_mm: f64) -> f64 {
        self.lookup(false).pdf_radius(theta, r_mm)
    }

    /// The angular factor F = S/S̄ at (θ, r in mm, φ), dimensionless
    /// ([`MediumRef::angular_factor`]): [`ChannelLookup::eval`] = S̄·F with
    /// S̄ = (1/2π) ∫ eval dφ, and F averages to 1 over φ. `None` for θ outside the table.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let red = library.channel("skin1", Rgb::Red)?;
    /// let theta = 60f64.to_radians();
    /// let forward = red.angular_factor(theta, 1.0, 0.0).unwrap();
    /// assert!(forward > 1.0); // oblique light exits ahead of the entry point
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn angular_factor(&self, theta: f64, r_mm: f64, phi: f64) -> Option<f64> {
        self.lookup(false).angular_factor(theta, r_mm, phi)
    }

    /// The medium's lookups on its table's view, with or without the θ-sampling CDF (only
    /// `sample_path` and `pdf_theta` read it): every lookup of the handle goes through
    /// [`MediumRef`], so a handle and a per-call medium give the same bits.
    #[inline]
    fn lookup(&self, theta_cdf: bool) -> MediumRef<'_> {
        MediumRef::prevalidated(
            self.table.view_with(theta_cdf),
            self.rho,
            self.sigma_t_prime,
        )
    }
}
