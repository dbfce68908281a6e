//! Tallies: per-photon scores folded into sums and sums of squares, per block of photons.
//!
//! Every score is a weight (power, per unit power entering) deposited at an exit point. A
//! photon may score many times; its scores are first summed per quantity (and per bin), and
//! only the photon's total enters the second moment. The standard error of a mean over N
//! photons is then √[(Q − S²/N) / (N (N − 1))] with S = Σ x and Q = Σ x²: the per-photon
//! estimator, exact for independent photons (it is NaN for N = 1).

use super::Bins;

/// How many scattering vertices preceded an exit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Order {
    /// No vertex: the collimated beam itself (only a slab lets it out).
    Unscattered = 0,
    /// Exactly one vertex.
    Single = 1,
    /// Two or more vertices.
    Multiple = 2,
}

impl Order {
    pub(crate) fn from_vertices(n: u32) -> Self {
        match n {
            0 => Order::Unscattered,
            1 => Order::Single,
            _ => Order::Multiple,
        }
    }
}

/// The boundary an exit crosses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Surface {
    /// z = 0, the lit side: reflectance.
    Top,
    /// z = −τ, the far side of a slab: transmittance.
    Bottom,
}

/// Indices of the per-photon scalar tallies.
pub(crate) mod scalar {
    /// Reflectance by order: unscattered, single, multiple, and their sum.
    pub const R: [usize; 4] = [0, 1, 2, 3];
    /// Reflectance exiting inside the binned disc r < r_max.
    pub const R_BINNED: usize = 4;
    /// Transmittance by order: unscattered, single, multiple, and their sum.
    pub const T: [usize; 4] = [5, 6, 7, 8];
    /// Weight dropped at the vertex cap.
    pub const TRUNCATED: usize = 9;
    /// Number of scalar tallies.
    pub const COUNT: usize = 10;
}

/// Number of tallied components per bin: unscattered, single, multiple, total.
pub(crate) const COMPONENTS: usize = 4;

/// Sums over photons: the part of a run that blocks reduce.
#[derive(Debug, Clone)]
pub(crate) struct Sums {
    pub photons: u64,
    pub events: u64,
    /// Σ x and Σ x² of each scalar.
    pub scalar_sum: [f64; scalar::COUNT],
    pub scalar_sq: [f64; scalar::COUNT],
    /// Σ x and Σ x² per (component, bin), component-major: index c · bins + b.
    pub bin_sum: Vec<f64>,
    pub bin_sq: Vec<f64>,
    /// The power of two the scores are multiplied by before squaring ([`square_scale`]): the
    /// sums of squares hold Σ (scale·x)².
    pub scale: f64,
}

/// The power of two the walk's scores are multiplied by before they are squared, for a walk of
/// single-scattering albedo `albedo`: about 1/albedo, at most 2⁴⁸⁰ (1 for albedo ≥ 1/2 and 0).
/// Scores of scattered light carry the albedo, and their squares underflowed to 0 below an
/// albedo of about 1e-157, which gave a standard error of 0, "exact". A score is at most about
/// 1, so Σ (scale·x)² stays below 2⁹⁶⁰ · 10¹² photons, far from overflow; scaling by a power of
/// two is exact, so the sums are the same bits as unscaled ones wherever those did not
/// underflow.
pub(crate) fn square_scale(albedo: f64) -> f64 {
    if albedo.is_nan() || albedo <= 0.0 || albedo >= 0.5 {
        return 1.0;
    }
    let exponent = (-albedo.log2()).floor().clamp(0.0, 480.0) as i32;
    2f64.powi(exponent)
}

impl Sums {
    pub(crate) fn new(bins: usize, scale: f64) -> Self {
        Self {
            photons: 0,
            events: 0,
            scalar_sum: [0.0; scalar::COUNT],
            scalar_sq: [0.0; scalar::COUNT],
            bin_sum: vec![0.0; COMPONENTS * bins],
            bin_sq: vec![0.0; COMPONENTS * bins],
            scale,
        }
    }

    /// Adds another block's sums (callers add blocks in index order).
    pub(crate) fn merge(&mut self, other: &Sums) {
        debug_assert_eq!(self.scale, other.scale);
        self.photons += other.photons;
        self.events += other.events;
        for k in 0..scalar::COUNT {
            self.scalar_sum[k] += other.scalar_sum[k];
            self.scalar_sq[k] += other.scalar_sq[k];
        }
        for (a, b) in self.bin_sum.iter_mut().zip(&other.bin_sum) {
            *a += b;
        }
        for (a, b) in self.bin_sq.iter_mut().zip(&other.bin_sq) {
            *a += b;
        }
    }
}

/// Mean and standard error of the mean from a sum, a sum of squares of the scores times
/// `scale` (a power of two, [`square_scale`]) and a count.
pub(crate) fn mean_and_stderr(sum: f64, sq: f64, n: u64, scale: f64) -> (f64, f64) {
    let nf = n as f64;
    if n == 0 {
        return (0.0, f64::NAN);
    }
    let mean = sum / nf;
    let stderr = if n > 1 {
        ((sq - (scale * sum) * (scale * mean)).max(0.0) / (nf * (nf - 1.0))).sqrt() / scale
    } else {
        f64::NAN
    };
    (mean, stderr)
}

/// The scores of the photon being traced, plus the block's running sums.
#[derive(Debug)]
pub(crate) struct PhotonTally<'a> {
    bins: &'a Bins,
    sums: Sums,
    scalars: [f64; scalar::COUNT],
    /// Per (bin, order) score of the current photon, bin-major: index 3 · b + order.
    scratch: Vec<f64>,
    /// Bins the current photon has scored in.
    touched: Vec<usize>,
}

impl<'a> PhotonTally<'a> {
    pub(crate) fn new(bins: &'a Bins, scale: f64) -> Self {
        let n = bins.len();
        Self {
            bins,
            sums: Sums::new(n, scale),
            scalars: [0.0; scalar::COUNT],
            scratch: vec![0.0; 3 * n],
            touched: Vec::new(),
        }
    }

    /// Scores `weight` leaving through `surface` at (x, y).
    pub(crate) fn exit(&mut self, surface: Surface, x: f64, y: f64, weight: f64, order: Order) {
        let o = order as usize;
        match surface {
            Surface::Top => {
                self.scalars[scalar::R[o]] += weight;
                if let Some(b) = self.bins.index(x, y) {
                    self.scalars[scalar::R_BINNED] += weight;
                    let cell = &mut self.scratch[3 * b..3 * b + 3];
                    if cell.iter().all(|&v| v == 0.0) {
                        self.touched.push(b);
                    }
                    cell[o] += weight;
                }
            }
            Surface::Bottom => self.scalars[scalar::T[o]] += weight,
        }
    }

    /// Counts one scattering vertex.
    pub(crate) fn vertex(&mut self) {
        self.sums.events += 1;
    }

    /// Records weight dropped by the vertex cap.
    pub(crate) fn truncate(&mut self, weight: f64) {
        self.scalars[scalar::TRUNCATED] += weight;
    }

    /// Folds the current photon into the sums and clears it.
    pub(crate) fn end_photon(&mut self) {
        let s = &mut self.scalars;
        s[scalar::R[3]] = s[scalar::R[0]] + s[scalar::R[1]] + s[scalar::R[2]];
        s[scalar::T[3]] = s[scalar::T[0]] + s[scalar::T[1]] + s[scalar::T[2]];
        let scale = self.sums.scale;
        let (sum, sq) = (&mut self.sums.scalar_sum, &mut self.sums.scalar_sq);
        for ((x, sum), sq) in s.iter_mut().zip(sum.iter_mut()).zip(sq.iter_mut()) {
            *sum += *x;
            let y = scale * *x;
            *sq += y * y;
            *x = 0.0;
        }
        let n = self.bins.len();
        for &b in &self.touched {
            let cell = &mut self.scratch[3 * b..3 * b + 3];
            let values = [cell[0], cell[1], cell[2], cell[0] + cell[1] + cell[2]];
            for (c, v) in values.into_iter().enumerate() {
                self.sums.bin_sum[c * n + b] += v;
                let y = scale * v;
                self.sums.bin_sq[c * n + b] += y * y;
            }
            cell.fill(0.0);
        }
        self.touched.clear();
        self.sums.photons += 1;
    }

    /// The block's sums.
    pub(crate) fn into_sums(self) -> Sums {
        self.sums
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stderr_of_known_sample() {
        // x = 1, 2, 3, 4: mean 2.5, sample variance 5/3, stderr √(5/12).
        let (m, s) = mean_and_stderr(10.0, 30.0, 4, 1.0);
        assert_eq!(m, 2.5);
        assert!((s - (5.0_f64 / 12.0).sqrt()).abs() < 1e-15);
        assert!(mean_and_stderr(1.0, 1.0, 1, 1.0).1.is_nan());
        // The same sample scaled by 1e-300, its squares (1e-600) below f64's range: summed
        // as (2^k x)², the standard error is the same multiple of 1e-300 and not 0
        let tiny = 1e-300;
        let scale = square_scale(tiny);
        let sq: f64 = [1.0, 2.0, 3.0, 4.0]
            .iter()
            .map(|x| (scale * x * tiny).powi(2))
            .sum();
        let (m, s) = mean_and_stderr(10.0 * tiny, sq, 4, scale);
        assert_eq!(m, 2.5 * tiny);
        assert!((s / tiny - (5.0_f64 / 12.0).sqrt()).abs() < 1e-12, "{s}");
        // Powers of two, 1 from albedo 1/2 up and for 0
        assert_eq!(square_scale(1.0), 1.0);
        assert_eq!(square_scale(0.5), 1.0);
        assert_eq!(square_scale(0.0), 1.0);
        assert_eq!(square_scale(0.3), 2.0);
        assert_eq!(square_scale(1e-300), 2f64.powi(480));
    }

    #[test]
    fn photon_scores_are_summed_before_squaring() {
        let bins = Bins::new(0.1, 10.0, 4, 4).unwrap();
        let mut t = PhotonTally::new(&bins, 1.0);
        // One photon exits twice in the same bin, once single and once multiple.
        t.exit(Surface::Top, 1.0, 0.01, 0.25, Order::Single);
        t.exit(Surface::Top, 1.0, 0.02, 0.5, Order::Multiple);
        t.exit(Surface::Top, 50.0, 0.0, 0.125, Order::Multiple);
        t.exit(Surface::Bottom, 0.0, 0.0, 0.0625, Order::Unscattered);
        t.end_photon();
        let s = t.into_sums();
        assert_eq!(s.photons, 1);
        assert_eq!(s.scalar_sum[scalar::R[3]], 0.875);
        assert_eq!(s.scalar_sq[scalar::R[3]], 0.875 * 0.875);
        assert_eq!(s.scalar_sum[scalar::R_BINNED], 0.75);
        assert_eq!(s.scalar_sum[scalar::T[3]], 0.0625);
        let b = bins.index(1.0, 0.01).unwrap();
        let n = bins.len();
        assert_eq!(s.bin_sum[3 * n + b], 0.75);
        assert_eq!(s.bin_sq[3 * n + b], 0.5625);
        assert_eq!(s.bin_sq[n + b], 0.0625);
    }
}
