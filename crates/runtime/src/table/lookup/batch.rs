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
        let [rho_prime, sigma_t_prime, theta, r_mm, phi] = lengths(INPUTS_EVAL, inputs, out.len())?;
        for (i, out) in out.iter_mut().enumerate() {
            *out = self
                .medium(rho_prime[i], sigma_t_prime[i])
                .map_or(0.0, |m| value(m, theta[i], r_mm[i], phi[i]));
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
        let n = out.pdf.len();
        lengths(["r", "phi"], [&*out.r, &*out.phi], n)?;
        let inputs = [rho_prime, sigma_t_prime, theta, u_r, u_phi];
        let [rho_prime, sigma_t_prime, theta, u_r, u_phi] = lengths(INPUTS_SAMPLE, inputs, n)?;
        for i in 0..n {
            let s = self
                .medium(rho_prime[i], sigma_t_prime[i])
                .ok()
                .and_then(|m| m.sample(theta[i], u_r[i], u_phi[i]))
                .unwrap_or(FAILED_SAMPLE);
            (out.r[i], out.phi[i], out.pdf[i]) = (s.r, s.phi, s.pdf);
        }
        Ok(())
    }
}

/// What [`TableRef::sample_n`] writes for a point without a draw.
const FAILED_SAMPLE: Sample = Sample {
    r: 0.0,
    phi: 0.0,
    pdf: 0.0,
};

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
