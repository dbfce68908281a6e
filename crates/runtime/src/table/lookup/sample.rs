//! Sampling (algorithm 2 of the report): r from the slice's radial distribution, φ from the
//! profile at r; the density of each draw, the path-tracing draw over θ, and the inverse map.

use super::*;

impl TableRef<'_> {
    /// Draws (r, φ) for (ρ′, θ) from two uniforms (algorithm 2). `None` when the table holds no
    /// energy there (ρ′ = 0, light beyond the critical angle), (ρ′, θ) is outside the axes,
    /// u_r is outside [0, 1) or draws the entry point (u_r = 0 on every baked table, where the
    /// density is infinite), or u_φ is outside [0, 1) (NaN and ±∞ included): a broken random
    /// stream draws nothing rather than a plausible point.
    pub fn sample(&self, rho: f64, theta: f64, u_r: f64, u_phi: f64) -> Option<Sample> {
        let rho = self.read_albedo(rho);
        // (A uniform outside [0, 1) is a broken random stream: no plausible point)
        if !self.light_enters(theta) || !(0.0..1.0).contains(&u_phi) {
            return None;
        }
        if let Some(ridge) = self.ridge_at(rho, theta) {
            return self.with_slice(rho, theta, |s| self.sample_mixture(s, &ridge, u_r, u_phi))?;
        }
        self.with_slice(rho, theta, |s| self.sample_slice(s, u_r, u_phi))?
    }

    pub(super) fn sample_slice(&self, s: &Slice, u_r: f64, u_phi: f64) -> Option<Sample> {
        let (radial, near) = self.radius_draw_near::<true>(s, u_r)?;
        let g = self.profile_at(s, radial.x, near.as_ref())?;
        let (phi, pdf_phi) = g.sample_with_pdf(u_phi);
        let pdf = radial.pdf * pdf_phi / radial.x;
        (pdf.is_finite() && pdf > 0.0).then_some(Sample {
            r: radial.x,
            phi,
            pdf,
        })
    }

    /// Draws r from the spline of E interpolated over the slice, by inverting its radial CDF
    /// (the rows' CDFs blended with the same weights).
    ///
    /// The segment search starts from the segment of the row with the largest weight, found in
    /// that row's own CDF (one contiguous f32 row instead of 16 scattered ones): the blended
    /// CDF is a mixture of rows of nearby (ρ′, θ), so the guess is usually exact or one segment
    /// off, and the search reads the blended CDF at two or three nodes instead of bisecting 64.
    pub(super) fn radius_draw(&self, s: &Slice, u: f64) -> Option<crate::catmull_rom::Sample> {
        Some(self.radius_draw_near::<false>(s, u)?.0)
    }

    /// [`TableRef::radius_draw`] with the reads it blended near the drawn segment
    /// ([`TableRef::radial_near`], with the (E, E_β, c) window if `WINDOW`), for the profile at
    /// the drawn r.
    #[inline(always)]
    fn radius_draw_near<const WINDOW: bool>(
        &self,
        s: &Slice,
        u: f64,
    ) -> Option<(crate::catmull_rom::Sample, Option<RadialNear>)> {
        let (_, _, n_r) = self.axes.dims();
        let n = s.len.min(16);
        let mut heaviest = 0;
        for k in 1..n {
            if s.weights[k] > s.weights[heaviest] {
                heaviest = k;
            }
        }
        let hint = s.offsets.get(heaviest).and_then(|&offset| {
            let row = self
                .radial_cdf
                .get(offset as usize..offset as usize + n_r)?;
            let (&total, inner) = row.split_last()?;
            let goal = (u * f64::from(total)) as f32;
            // Nodes 1 … n − 2 at most goal: segment of the first node above it, minus one (the
            // row's CDF never decreases). Counted, not bisected: the loads are independent and
            // the comparisons vectorise, where a bisection waits for each load in turn. Summed
            // as 0s and 1s, which compiles to packed compares (a filter's count did not).
            let below = inner
                .get(1..)?
                .iter()
                .map(|&c| u32::from(c <= goal))
                .sum::<u32>();
            Some(below as usize)
        });
        // The reads near the hint in one pass; the others (a walk of more than a segment, a
        // segment whose nodes leave the window) blend on their own, to the same bits
        let near = hint.and_then(|k| self.radial_near::<WINDOW>(s, k));
        let e = |k: usize| self.energies_near(s, near, k);
        let cdf = |k: usize| self.cdf_near(s, near, k);
        Some((self.axes.r().sample_with(e, cdf, u, hint)?, near))
    }

    /// Density per unit area of [`TableRef::sample`] at (r, φ), reduced mfp⁻².
    pub fn pdf(&self, rho: f64, theta: f64, r: f64, phi: f64) -> f64 {
        let rho = self.read_albedo(rho);
        if !self.light_enters(theta) {
            return 0.0;
        }
        if let Some(ridge) = self.ridge_at(rho, theta) {
            return self
                .with_slice(rho, theta, |s| self.pdf_mixture(s, &ridge, r, phi))
                .unwrap_or(0.0);
        }
        self.with_slice(rho, theta, |s| self.pdf_slice(s, r, phi))
            .unwrap_or(0.0)
    }

    pub(super) fn pdf_slice(&self, s: &Slice, r: f64, phi: f64) -> f64 {
        if r <= 0.0 || !r.is_finite() {
            return 0.0;
        }
        let (pdf_r, near) = self.radial_pdf_near::<true>(s, r);
        match self.profile_at(s, r, near.as_ref()) {
            Some(g) if pdf_r > 0.0 => pdf_r * g.pdf(wrap_phi(phi)) / r,
            _ => 0.0,
        }
    }

    /// Density per unit r of [`TableRef::radius_draw`] at r > 0: the radial factor of
    /// [`TableRef::pdf_slice`].
    #[inline(always)]
    pub(super) fn radial_pdf(&self, s: &Slice, r: f64) -> f64 {
        self.radial_pdf_near::<false>(s, r).0
    }

    /// [`TableRef::radial_pdf`] with its reads, as in [`TableRef::radius_draw_near`].
    #[inline(always)]
    fn radial_pdf_near<const WINDOW: bool>(&self, s: &Slice, r: f64) -> (f64, Option<RadialNear>) {
        // Every read of the density in r's segment in one pass, as in `radius_draw`
        let near = self
            .axes
            .r()
            .find_segment(r)
            .and_then(|k| self.radial_near::<WINDOW>(s, k));
        let e = |k: usize| self.energies_near(s, near, k);
        let cdf = |k: usize| self.cdf_near(s, near, k);
        (self.axes.r().pdf_with(e, cdf, r), near)
    }

    /// The energies around node k ([`TableRef::energies_around`]) from `near`'s one pass where
    /// it holds them, else blended on their own (the same bits).
    #[inline(always)]
    fn energies_near(&self, s: &Slice, near: Option<RadialNear>, k: usize) -> [f64; 4] {
        near.and_then(|w| w.energies_around(k))
            .unwrap_or_else(|| self.energies_around(s, k))
    }

    /// The radial CDF at node k ([`TableRef::cdf`]) from `near`'s one pass where it holds it,
    /// else blended on its own (the same bits).
    #[inline(always)]
    fn cdf_near(&self, s: &Slice, near: Option<RadialNear>, k: usize) -> f64 {
        near.and_then(|w| w.cdf(k))
            .unwrap_or_else(|| self.cdf(s, k))
    }

    /// Perpendicular model's sampler: r from the θ = 0 slice, φ uniform. `None` as
    /// [`TableRef::sample`] (a uniform outside [0, 1) included).
    pub fn sample_perpendicular(&self, rho: f64, u_r: f64, u_phi: f64) -> Option<Sample> {
        let rho = self.read_albedo(rho);
        if !(0.0..1.0).contains(&u_phi) {
            return None;
        }
        let radial = self.with_slice(rho, 0.0, |s| self.radius_draw(s, u_r))??;
        let phi = uniform_azimuth(u_phi);
        Some(Sample {
            r: radial.x,
            phi,
            pdf: radial.pdf / (TAU * radial.x),
        })
    }

    /// Path-tracing draw (algorithm 3): θ from ρ_eff(ρ′, ·), then (r, φ), then φ′ uniform.
    /// `None` without the θ-sampling table, where no energy is stored or for a uniform outside
    /// [0, 1) (NaN and ±∞ included).
    pub fn sample_path(&self, rho: f64, u: [f64; 4]) -> Option<PathSample> {
        let rho = self.read_albedo(rho);
        if u.iter().any(|u| !(0.0..1.0).contains(u)) {
            return None;
        }
        let theta_cdf = self.theta_cdf?;
        let w_rho = self.axes.rho.weights(rho)?;
        let (_, n_theta, _) = self.axes.dims();
        let rho_eff = |j: usize| w_rho.apply_rows(|i| self.node_total(i, j));
        let cdf = |j: usize| w_rho.apply_rows(|i| f64::from(theta_cdf[i * n_theta + j]));
        let mut t = self.axes.theta().sample(rho_eff, cdf, u[0])?;
        if !self.light_enters(t.x) {
            // Below η = 1 the last lit node is the critical angle rounded to f32, a little
            // above asin η where light stops entering: a θ drawn between the two (u[0] within
            // about 10⁻⁷ of 1) is the critical angle itself, with its density
            let lit = self.critical_below(t.x)?;
            t.pdf = self.axes.theta().pdf(rho_eff, cdf, lit);
            t.x = lit;
        }
        let w_theta = self.axes.theta().weights(t.x)?;
        let s = self.slice_of(&w_rho.energy, &w_theta, Blend::new(&w_rho, rho, t.x));
        let rphi = match self.ridge_at(rho, t.x) {
            Some(ridge) => self.sample_mixture(&s, &ridge, u[1], u[2])?,
            None => self.sample_slice(&s, u[1], u[2])?,
        };
        let phi_prime = uniform_azimuth(u[3]);
        Some(PathSample {
            theta: t.x,
            r: rphi.r,
            phi: rphi.phi,
            phi_prime,
            pdf_theta: t.pdf,
            pdf: t.pdf * rphi.pdf / TAU,
        })
    }

    /// The largest angle at most `theta` where light enters, if one lies within f32 rounding
    /// (2⁻²³ of it) below: the critical angle of an η < 1 as the lookups see it.
    fn critical_below(&self, theta: f64) -> Option<f64> {
        let floor = theta * (1.0 - 1.0 / f64::from(1u32 << 23));
        let critical = self.eta.asin();
        (critical >= floor && critical <= theta)
            .then(|| {
                // asin η's sine can round above η: step down to the first angle that enters
                let mut x = critical;
                while !self.light_enters(x) && x > floor {
                    x = crate::float::next_down(x);
                }
                x
            })
            .filter(|&x| self.light_enters(x))
    }

    /// Density of θ in [`TableRef::sample_path`], per radian: 0 where no light enters (beyond
    /// the critical angle of an η < 1, where the θ CDF is constant).
    pub fn pdf_theta(&self, rho: f64, theta: f64) -> f64 {
        let rho = self.read_albedo(rho);
        let (Some(theta_cdf), Some(w_rho)) = (self.theta_cdf, self.axes.rho.weights(rho)) else {
            return 0.0;
        };
        if !self.light_enters(theta) {
            return 0.0;
        }
        let (_, n_theta, _) = self.axes.dims();
        let rho_eff = |j: usize| w_rho.apply_rows(|i| self.node_total(i, j));
        let cdf = |j: usize| w_rho.apply_rows(|i| f64::from(theta_cdf[i * n_theta + j]));
        self.axes.theta().pdf(rho_eff, cdf, self.snap_theta(theta))
    }

    /// The inverse of [`TableRef::sample`]: the uniforms (u_r, u_φ) that `sample` maps to
    /// (r, φ), from the radial CDF of the interpolated spline and the GWC profile's analytic CDF.
    /// `None` outside the axes or where the table holds no energy. For a table with the ridge,
    /// the preimage through the nodes' part (`lookup::ridged`).
    pub fn invert(&self, rho: f64, theta: f64, r: f64, phi: f64) -> Option<(f64, f64)> {
        let rho = self.read_albedo(rho);
        if !self.light_enters(theta) {
            return None;
        }
        let ridge = self.ridge_at(rho, theta);
        self.with_slice(rho, theta, |s| {
            let e = |k: usize| self.energy(s, k);
            let cdf = |k: usize| self.cdf(s, k);
            let u_r = self.axes.r().cdf(e, cdf, r)?;
            let g = self.profile_at(s, r, None)?;
            // The nodes' part takes the radial uniforms below E_D/(E_D + E_R)
            let share = ridge.as_ref().map_or(1.0, |ridge| {
                let e_d = self.total(s);
                e_d / (e_d + ridge.energy())
            });
            Some((u_r * share, g.cdf(wrap_phi(phi))))
        })?
    }
}
