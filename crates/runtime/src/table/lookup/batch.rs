//! Lookups of N points at once, as structures of arrays, in world units, each point with its
//! own medium (ρ′, σ′t): what a wavefront renderer holds, a queue of shading points of
//! different (textured) media. Every point gives the bits of the single lookup of
//! [`MediumRef`] at the same arguments; a point outside the domain gives 0 (a failed draw
//! (0, 0, 0)) instead of an error, and the rest of the batch goes on.
//!
//! Each point runs the single lookup, so its bits are the single lookup's by construction. A
//! batch saves what a call adds to a lookup (the C boundary, finding the table's arrays), not
//! arithmetic: a point costs what a lookup through a `TableRef` made once costs
//! (docs/performance.md, "Media per call and batches", with what was measured to go further).

use super::*;

/// The outputs of [`TableRef::sample_n`], one entry per point: the exit distance r (mm), its
/// azimuth φ (radians, 0 forward) and the density per mm², as [`MediumRef::sample`] draws
/// them. A point with no draw (its medium outside the table, θ outside it, nothing to sample
/// there) gets r = φ = pdf = 0; every draw has pdf > 0, so pdf = 0 marks the failed ones.
#[derive(Debug)]
pub struct SamplesMut<'o> {
    /// Exit distances, mm.
    pub r: &'o mut [f64],
    /// Exit azimuths, radians in [−π, π].
    pub phi: &'o mut [f64],
    /// Densities per mm² of the exit plane; 0 for a failed draw.
    pub pdf: &'o mut [f64],
}

/// The outputs of [`TableRef::sample_radius_n`], one entry per point: the exit distance r
/// (mm) and its density per mm, as [`MediumRef::sample_radius`] draws them; r = pdf = 0 for a
/// point with no draw (every draw has pdf > 0).
#[derive(Debug)]
pub struct RadialSamplesMut<'o> {
    /// Exit distances, mm.
    pub r: &'o mut [f64],
    /// Densities per mm of the distance; 0 for a failed draw.
    pub pdf: &'o mut [f64],
}

/// The outputs of [`TableRef::sample_path_n`], one entry per point, as
/// [`MediumRef::sample_path`] draws them ([`PathSample`]'s fields); every field 0 for a point
/// with no draw (every draw has pdf > 0).
#[derive(Debug)]
pub struct PathSamplesMut<'o> {
    /// Incidences before refraction, radians.
    pub theta: &'o mut [f64],
    /// Exit distances, mm.
    pub r: &'o mut [f64],
    /// Exit azimuths relative to the plane of incidence, radians.
    pub phi: &'o mut [f64],
    /// Azimuths of the entry point seen from the exit point, radians.
    pub phi_prime: &'o mut [f64],
    /// Densities of θ, per radian.
    pub pdf_theta: &'o mut [f64],
    /// Joint densities per radian of θ, per mm² and per radian of φ′; 0 for a failed draw.
    pub pdf: &'o mut [f64],
}

impl<'o> From<[&'o mut [f64]; 6]> for PathSamplesMut<'o> {
    /// The six output arrays in the order of [`PathSample`]'s fields: θ, r, φ, φ′, pdf_theta,
    /// pdf.
    fn from([theta, r, phi, phi_prime, pdf_theta, pdf]: [&'o mut [f64]; 6]) -> Self {
        PathSamplesMut {
            theta,
            r,
            phi,
            phi_prime,
            pdf_theta,
            pdf,
        }
    }
}

impl TableRef<'_> {
    /// S_p in mm⁻² at N points: point i is [`MediumRef::eval`] at (θᵢ, r_mmᵢ, φᵢ) of the medium
    /// (ρ′ᵢ, σ′tᵢ in mm⁻¹) on this table, into `out[i]`, or 0 where [`TableRef::medium`] refuses
    /// the medium or θᵢ lies outside the table (and where S is 0). Every input must have the
    /// length of `out`, else [`crate::Error::BatchLength`] and nothing is written. Allocates
    /// nothing.
    ///
    /// ```
    /// # use bssrdf_zoo::fresnel::Moments;
    /// # use bssrdf_zoo::table::{bake, Grid};
    /// # let (table, _) = bake(1.33, Moments::Exact, &Grid::ferrier(6, 4, 10), true)?;
    /// let view = table.view();
    /// // Three shading points of a textured medium; the third one's ρ′ is out of range
    /// let (rho, sigma_t) = ([0.9, 0.95, 1.5], [2.0, 1.5, 2.0]);
    /// let (theta, r_mm, phi) = ([0.1, 0.7, 0.1], [0.3, 0.5, 0.3], [0.0, 1.0, 0.0]);
    /// let mut s = [0.0; 3];
    /// view.eval_n(&rho, &sigma_t, &theta, &r_mm, &phi, &mut s)?;
    /// let single = view.medium(0.95, 1.5)?.eval(0.7, 0.5, 1.0).unwrap();
    /// assert_eq!(s[1].to_bits(), single.to_bits());
    /// assert_eq!(s[2], 0.0);
    /// assert!(view.eval_n(&rho, &sigma_t, &theta, &r_mm, &phi[..2], &mut s).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn eval_n(
        &self,
        rho_prime: &[f64],
        sigma_t_prime: &[f64],
        theta: &[f64],
        r_mm: &[f64],
        phi: &[f64],
        out: &mut [f64],
    ) -> crate::Result<()> {
        let inputs = [rho_prime, sigma_t_prime, theta, r_mm, phi];
        self.values_n(inputs, out, |m, theta, r_mm, phi| {
            m.eval(theta, r_mm, phi).unwrap_or(0.0)
        })
    }

    /// The density per mm² of [`TableRef::sample_n`] at N points: point i is
    /// [`MediumRef::pdf`] at (θᵢ, r_mmᵢ, φᵢ) of the medium (ρ′ᵢ, σ′tᵢ), into `out[i]`, or 0
    /// where [`TableRef::medium`] refuses the medium (and where the density is 0). Lengths as
    /// in [`TableRef::eval_n`]. Allocates nothing.
    pub fn pdf_n(
        &self,
        rho_prime: &[f64],
        sigma_t_prime: &[f64],
        theta: &[f64],
        r_mm: &[f64],
        phi: &[f64],
        out: &mut [f64],
    ) -> crate::Result<()> {
        let inputs = [rho_prime, sigma_t_prime, theta, r_mm, phi];
        self.values_n(inputs, out, |m, theta, r_mm, phi| m.pdf(theta, r_mm, phi))
    }

    /// The loop of [`TableRef::eval_n`] and [`TableRef::pdf_n`]: `value` of each point's
    /// medium at its (θ, r_mm, φ), or 0 where the medium is refused.
    #[inline(always)]
    fn values_n(
        &self,
        inputs: [&[f64]; 5],
        out: &mut [f64],
        value: impl Fn(MediumRef<'_>, f64, f64, f64) -> f64,
    ) -> crate::Result<()> {
        self.points_n(
            (INPUTS_EVAL, inputs),
            ([], [out]),
            |m, [_, _, theta, r_mm, phi]| [m.map_or(0.0, |m| value(m, theta, r_mm, phi))],
        )
    }

    /// The loop of every batch: the lengths checked (the last output's is the batch's; the
    /// other outputs, named by `out_names`, then the inputs must have it), then for each point
    /// `lookup` of its medium (from its first two inputs, ρ′ and σ′t; `None` where
    /// [`TableRef::medium`] refuses it) and of all its inputs, into its entry of each output.
    #[inline(always)]
    fn points_n<const K: usize, const O: usize, const P: usize>(
        &self,
        (names, inputs): ([&'static str; K], [&[f64]; K]),
        (out_names, outputs): ([&'static str; P], [&mut [f64]; O]),
        lookup: impl Fn(Option<MediumRef<'_>>, [f64; K]) -> [f64; O],
    ) -> crate::Result<()> {
        let n = outputs[O - 1].len();
        lengths(out_names, std::array::from_fn(|k| &*outputs[k]), n)?;
        // Every slice cut to n values, so that the loop's indexing needs no bounds checks
        let inputs = lengths(names, inputs, n)?.map(|input| &input[..n]);
        let mut outputs = outputs.map(|output| &mut output[..n]);
        for i in 0..n {
            let x = inputs.map(|input| input[i]);
            let values = lookup(self.medium(x[0], x[1]).ok(), x);
            for (output, value) in outputs.iter_mut().zip(values) {
                output[i] = value;
            }
        }
        Ok(())
    }

    /// N draws of the exit point: point i is [`MediumRef::sample`] for incidence θᵢ from the
    /// uniforms (u_rᵢ, u_φᵢ) in the medium (ρ′ᵢ, σ′tᵢ), into entry i of `out`, or the failed
    /// draw (0, 0, 0) where [`TableRef::medium`] refuses the medium or the single draw is
    /// `None`. Every input and output must have the length of `out.pdf`, else
    /// [`crate::Error::BatchLength`] and nothing is written. Allocates nothing.
    ///
    /// ```
    /// # use bssrdf_zoo::fresnel::Moments;
    /// # use bssrdf_zoo::table::{bake, Grid, SamplesMut};
    /// # let (table, _) = bake(1.33, Moments::Exact, &Grid::ferrier(6, 4, 10), true)?;
    /// let view = table.view();
    /// let (rho, sigma_t, theta) = ([0.9, 0.0], [2.0, 2.0], [0.3, 0.3]);
    /// let (u_r, u_phi) = ([0.25, 0.25], [0.75, 0.75]);
    /// let (mut r, mut phi, mut pdf) = ([0.0; 2], [0.0; 2], [0.0; 2]);
    /// let out = SamplesMut { r: &mut r, phi: &mut phi, pdf: &mut pdf };
    /// view.sample_n(&rho, &sigma_t, &theta, &u_r, &u_phi, out)?;
    /// let single = view.medium(0.9, 2.0)?.sample(0.3, 0.25, 0.75).unwrap();
    /// assert_eq!([r[0], phi[0], pdf[0]], [single.r, single.phi, single.pdf]);
    /// assert_eq!(pdf[1], 0.0); // ρ′ = 0 scatters nothing: a failed draw
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn sample_n(
        &self,
        rho_prime: &[f64],
        sigma_t_prime: &[f64],
        theta: &[f64],
        u_r: &[f64],
        u_phi: &[f64],
        out: SamplesMut<'_>,
    ) -> crate::Result<()> {
        let inputs = [rho_prime, sigma_t_prime, theta, u_r, u_phi];
        let outputs = [out.r, out.phi, out.pdf];
        self.points_n((INPUTS_SAMPLE, inputs), (["r", "phi"], outputs), |m, x| {
            let [_, _, theta, u_r, u_phi] = x;
            let s = m.and_then(|m| m.sample(theta, u_r, u_phi));
            s.map_or([0.0; 3], |s| [s.r, s.phi, s.pdf])
        })
    }

    /// N draws of the exit distance alone, for separable renderers: point i is
    /// [`MediumRef::sample_radius`] for incidence θᵢ from the uniform uᵢ in the medium
    /// (ρ′ᵢ, σ′tᵢ), into entry i of `out` (r in mm, density per mm), or the failed draw
    /// r = pdf = 0 where [`TableRef::medium`] refuses the medium or the single draw is `None`.
    /// Every input and output must have the length of `out.pdf`, else
    /// [`crate::Error::BatchLength`] and nothing is written. Allocates nothing.
    ///
    /// ```
    /// # use bssrdf_zoo::fresnel::Moments;
    /// # use bssrdf_zoo::table::{bake, Grid, RadialSamplesMut};
    /// # let (table, _) = bake(1.33, Moments::Exact, &Grid::ferrier(6, 4, 10), true)?;
    /// let view = table.view();
    /// let (rho, sigma_t, theta, u) = ([0.9, 0.0], [2.0, 2.0], [0.3, 0.3], [0.25, 0.25]);
    /// let (mut r, mut pdf) = ([0.0; 2], [0.0; 2]);
    /// let out = RadialSamplesMut { r: &mut r, pdf: &mut pdf };
    /// view.sample_radius_n(&rho, &sigma_t, &theta, &u, out)?;
    /// let single = view.medium(0.9, 2.0)?.sample_radius(0.3, 0.25).unwrap();
    /// assert_eq!([r[0], pdf[0]], [single.r, single.pdf]);
    /// assert_eq!(pdf[1], 0.0); // ρ′ = 0 scatters nothing: a failed draw
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn sample_radius_n(
        &self,
        rho_prime: &[f64],
        sigma_t_prime: &[f64],
        theta: &[f64],
        u: &[f64],
        out: RadialSamplesMut<'_>,
    ) -> crate::Result<()> {
        let inputs = [rho_prime, sigma_t_prime, theta, u];
        let names = ["rho_prime", "sigma_t_prime", "theta", "u"];
        self.points_n((names, inputs), (["r"], [out.r, out.pdf]), |m, x| {
            let [_, _, theta, u] = x;
            let s = m.and_then(|m| m.sample_radius(theta, u));
            s.map_or([0.0; 2], |s| [s.r, s.pdf])
        })
    }

    /// The density per mm of [`TableRef::sample_radius_n`] at N points: point i is
    /// [`MediumRef::pdf_radius`] at (θᵢ, r_mmᵢ) of the medium (ρ′ᵢ, σ′tᵢ), into `out[i]`, or 0
    /// where [`TableRef::medium`] refuses the medium. Every input must have the length of
    /// `out`, else [`crate::Error::BatchLength`] and nothing is written. Allocates nothing.
    pub fn pdf_radius_n(
        &self,
        rho_prime: &[f64],
        sigma_t_prime: &[f64],
        theta: &[f64],
        r_mm: &[f64],
        out: &mut [f64],
    ) -> crate::Result<()> {
        let inputs = [rho_prime, sigma_t_prime, theta, r_mm];
        let names = ["rho_prime", "sigma_t_prime", "theta", "r_mm"];
        self.points_n((names, inputs), ([], [out]), |m, [_, _, theta, r_mm]| {
            [m.map_or(0.0, |m| m.pdf_radius(theta, r_mm))]
        })
    }

    /// The angular factor S/S̄ (dimensionless) at N points: point i is
    /// [`MediumRef::angular_factor`] at (θᵢ, r_mmᵢ, φᵢ) of the medium (ρ′ᵢ, σ′tᵢ), into
    /// `out[i]`, or 0 where [`TableRef::medium`] refuses the medium or θᵢ lies outside the
    /// table. Lengths as in [`TableRef::eval_n`]. Allocates nothing.
    pub fn angular_factor_n(
        &self,
        rho_prime: &[f64],
        sigma_t_prime: &[f64],
        theta: &[f64],
        r_mm: &[f64],
        phi: &[f64],
        out: &mut [f64],
    ) -> crate::Result<()> {
        let inputs = [rho_prime, sigma_t_prime, theta, r_mm, phi];
        self.values_n(inputs, out, |m, theta, r_mm, phi| {
            m.angular_factor(theta, r_mm, phi).unwrap_or(0.0)
        })
    }

    /// N path-tracing draws (θ, r, φ, φ′): point i is [`MediumRef::sample_path`] of the medium
    /// (ρ′ᵢ, σ′tᵢ) from the uniforms (u0ᵢ, u1ᵢ, u2ᵢ, u3ᵢ) (the single call's `u`), into entry
    /// i of `out`, or the failed draw, every field 0, where [`TableRef::medium`] refuses the
    /// medium or the single draw is `None` (among others on a view without the θ-sampling
    /// table). Every input and output must have the length of `out.pdf`, else
    /// [`crate::Error::BatchLength`] and nothing is written. Allocates nothing.
    ///
    /// ```
    /// # use bssrdf_zoo::fresnel::Moments;
    /// # use bssrdf_zoo::table::{bake, Grid, PathSamplesMut};
    /// # let (table, _) = bake(1.33, Moments::Exact, &Grid::ferrier(6, 4, 10), true)?;
    /// let view = table.view();
    /// let (rho, sigma_t) = ([0.9, 1.5], [2.0, 2.0]);
    /// let u = [[0.1, 0.1], [0.2, 0.2], [0.3, 0.3], [0.4, 0.4]];
    /// let mut out = [[0.0; 2]; 6]; // θ, r, φ, φ′, pdf_theta, pdf
    /// let draws = PathSamplesMut::from(out.each_mut().map(|o| &mut o[..]));
    /// view.sample_path_n(&rho, &sigma_t, [&u[0], &u[1], &u[2], &u[3]], draws)?;
    /// let single = view.medium(0.9, 2.0)?.sample_path([0.1, 0.2, 0.3, 0.4]).unwrap();
    /// assert_eq!([out[0][0], out[1][0], out[5][0]], [single.theta, single.r, single.pdf]);
    /// assert_eq!(out[5][1], 0.0); // ρ′ = 1.5 is outside the table: a failed draw
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn sample_path_n(
        &self,
        rho_prime: &[f64],
        sigma_t_prime: &[f64],
        [u0, u1, u2, u3]: [&[f64]; 4],
        out: PathSamplesMut<'_>,
    ) -> crate::Result<()> {
        let inputs = [rho_prime, sigma_t_prime, u0, u1, u2, u3];
        let names = ["rho_prime", "sigma_t_prime", "u0", "u1", "u2", "u3"];
        let out_names = ["theta", "r", "phi", "phi_prime", "pdf_theta"];
        let PathSamplesMut {
            theta,
            r,
            phi,
            phi_prime,
            pdf_theta,
            pdf,
        } = out;
        let outputs = [theta, r, phi, phi_prime, pdf_theta, pdf];
        self.points_n((names, inputs), (out_names, outputs), |m, x| {
            let [_, _, u @ ..] = x;
            let p = m.and_then(|m| m.sample_path(u));
            p.map_or([0.0; 6], |p| {
                [p.theta, p.r, p.phi, p.phi_prime, p.pdf_theta, p.pdf]
            })
        })
    }
}

/// The names of the inputs of [`TableRef::eval_n`] and [`TableRef::pdf_n`], as the errors
/// give them.
const INPUTS_EVAL: [&str; 5] = ["rho_prime", "sigma_t_prime", "theta", "r_mm", "phi"];

/// The names of the inputs of [`TableRef::sample_n`].
const INPUTS_SAMPLE: [&str; 5] = ["rho_prime", "sigma_t_prime", "theta", "u_r", "u_phi"];

/// The arrays, each checked to hold `n` values, or the first that does not, named.
fn lengths<'p, const K: usize>(
    names: [&'static str; K],
    arrays: [&'p [f64]; K],
    n: usize,
) -> crate::Result<[&'p [f64]; K]> {
    for (name, array) in names.into_iter().zip(arrays) {
        if array.len() != n {
            return Err(crate::Error::BatchLength {
                name,
                len: array.len(),
                expected: n,
            });
        }
    }
    Ok(arrays)
}
