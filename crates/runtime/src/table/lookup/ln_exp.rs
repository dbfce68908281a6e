//! ln and exp for the interpolation of ln E along r (`TableRef::cell_from`): E = exp(Σ wₖ ln Eₖ)
//! over the four radius nodes of a segment. Self-contained, inlined, and branch-free on the
//! path of a lookup, so the four logarithms of a window compile to a few packed instructions
//! where four library `logf` calls and an `exp` took a fifth of an evaluation
//! (docs/performance.md). Both run in f64 on every input a lookup gives them.
//!
//! - [`ln_f32`]: ln x of a positive f32 (normal or subnormal), in f64, by the reduction and
//!   polynomial of fdlibm's `e_log.c` (Sun Microsystems, 1993; also musl's `log`): x = 2ᵏ·m with
//!   m ∈ [√2/2, √2), f = m − 1, s = f/(2 + f), ln m = f − f²/2 + s(f²/2 + R(s²)), R the fdlibm
//!   minimax polynomial (|error| < 2⁻⁵⁸·⁴⁵), k·ln 2 in two parts. Within 1 ulp of f64.
//! - [`exp`]: eˣ for x ∈ [−708, 709] (0 below, +∞ above, NaN kept), by x = n·ln 2 + r with
//!   |r| ≤ ln 2/2 (Cody and Waite's two-part ln 2, fdlibm's constants), eʳ by its Taylor series
//!   to r¹³ (truncation below 4·10⁻¹⁸ relative), then the exponent set from n. Within 2 ulp of
//!   f64.
//!
//! `tests` holds both to the library's f64 `ln` and `exp`: every binade of f32 (subnormals
//! included) and its end points, a dense grid of x, and the ends of exp's range.

/// ln 2 split for Cody–Waite reduction (fdlibm): the high part has 32 significant bits, so
/// k·LN2_HI is exact for |k| < 2²¹.
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);

/// fdlibm's `e_log.c` coefficients Lg1 … Lg7 of R(z) = Σ Lgᵢ zⁱ, z = s².
const LG: [f64; 7] = [
    f64::from_bits(0x3fe5_5555_5555_5593),
    f64::from_bits(0x3fd9_9999_9997_fa04),
    f64::from_bits(0x3fd2_4924_9422_9359),
    f64::from_bits(0x3fcc_71c5_1d8e_78af),
    f64::from_bits(0x3fc7_4664_96cb_03de),
    f64::from_bits(0x3fc3_9a09_d078_c69f),
    f64::from_bits(0x3fc2_f112_df3e_5244),
];

/// The bit pattern of √2/2 rounded down to its high 32 bits (fdlibm's 0x3fe6a09e): mantissas
/// from it up are reduced to [√2/2, √2).
const SQRT_HALF_BITS: u64 = 0x3fe6_a09e_0000_0000;

/// ln x in f64 for a positive, finite f32 x (normal or subnormal), within 1 ulp. Other inputs
/// (0, negative, ∞, NaN) give a finite value with no meaning: callers test x > 0 first.
#[inline(always)]
pub(super) fn ln_f32(x: f32) -> f64 {
    // f32 → f64 is exact and makes the subnormals normal: one reduction for all
    let bits = f64::from(x).to_bits();
    // x = 2ᵏ·m, m ∈ [√2/2, √2): shift the pattern so that the exponent field carries k + 1023
    // exactly when m ≥ √2/2 (fdlibm's and musl's trick)
    let shifted = bits.wrapping_add(0x3ff0_0000_0000_0000 - SQRT_HALF_BITS);
    let k = (shifted >> 52) as i64 - 0x3ff;
    let m = f64::from_bits((shifted & 0x000f_ffff_ffff_ffff) + SQRT_HALF_BITS);
    let f = m - 1.0;
    let s = f / (2.0 + f);
    let (z, half_f2) = (s * s, 0.5 * f * f);
    let w = z * z;
    // R(z) = Lg1·z + … + Lg7·z⁷, odd and even powers apart (fdlibm's grouping)
    let t1 = w * (LG[1] + w * (LG[3] + w * LG[5]));
    let t2 = z * (LG[0] + w * (LG[2] + w * (LG[4] + w * LG[6])));
    let dk = k as f64;
    s * (half_f2 + (t1 + t2)) + dk * LN2_LO - half_f2 + f + dk * LN2_HI
}

/// 1/k! for k = 2 … 13, the Taylor coefficients of (eʳ − 1 − r)/r².
const INV_FACTORIAL: [f64; 12] = [
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5_040.0,
    1.0 / 40_320.0,
    1.0 / 362_880.0,
    1.0 / 3_628_800.0,
    1.0 / 39_916_800.0,
    1.0 / 479_001_600.0,
    1.0 / 6_227_020_800.0,
];

/// eˣ within 2 ulp for x ∈ [−708, 709]; 0 below (the true value is below the smallest normal
/// f64, 2.2·10⁻³⁰⁸), +∞ above, NaN for NaN.
#[inline(always)]
pub(super) fn exp(x: f64) -> f64 {
    if !(-708.0..=709.0).contains(&x) {
        return if x < 0.0 { 0.0 } else { x * f64::INFINITY };
    }
    // x = n·ln 2 + r, |r| ≤ ln 2/2 (up to rounding of n), r in two parts exactly
    // n = x/ln 2 rounded to nearest by the shifter 1.5·2⁵², which leaves no fraction bits
    // (`f64::round` is a library call without SSE4.1); exact for |x/ln 2| < 2⁵¹
    const SHIFTER: f64 = 6_755_399_441_055_744.0;
    let n = (x * std::f64::consts::LOG2_E + SHIFTER) - SHIFTER;
    let r = (x - n * LN2_HI) - n * LN2_LO;
    // eʳ = 1 + r + r²·q(r), q by Estrin's scheme (pairs, then pairs of pairs): the sum waits on
    // fewer dependent steps; its terms fall fast enough (r²/2 ≤ 0.06) to round within an ulp
    let c = &INV_FACTORIAL;
    let (r2, pair) = (r * r, |k: usize| c[k] + c[k + 1] * r);
    let r4 = r2 * r2;
    let low = pair(0) + pair(2) * r2;
    let mid = pair(4) + pair(6) * r2;
    let high = pair(8) + pair(10) * r2;
    let q = low + r4 * (mid + r4 * high);
    let e_r = 1.0 + (r + r2 * q);
    // × 2ⁿ: x ∈ [−708, 709] gives n ∈ [−1021, 1023], a normal power of two, and
    // eʳ ∈ [0.7, 1.42] keeps the product finite and normal
    e_r * f64::from_bits(((n as i64 + 1023) as u64) << 52)
}

#[cfg(test)]
mod tests {
    use super::{exp, ln_f32};

    /// Distance in ulps of f64 between `got` and `want` (finite, same sign).
    fn ulps(got: f64, want: f64) -> f64 {
        let ulp = f64::from_bits(want.abs().to_bits() + 1) - want.abs();
        (got - want).abs() / ulp
    }

    /// Within 1 ulp of the library's f64 ln at every positive f32 of a strided walk through
    /// all their bit patterns (every binade, subnormals included, 2²⁰ values) and at the ends
    /// of every binade.
    #[test]
    fn ln_f32_matches_the_library_within_one_ulp() {
        let patterns = (1..0x7f80_0000u32).step_by(2039);
        let ends = (0..255u32).flat_map(|e| {
            let low = e << 23;
            [low.max(1), low + 1, low | 0x7f_ffff, (low | 0x7f_ffff) - 1]
        });
        let mut worst: f64 = 0.0;
        for bits in patterns.chain(ends) {
            let x = f32::from_bits(bits);
            let (got, want) = (ln_f32(x), f64::from(x).ln());
            if want == 0.0 {
                assert_eq!(got, 0.0, "ln 1");
                continue;
            }
            let e = ulps(got, want);
            worst = worst.max(e);
            assert!(e <= 1.0, "ln({x:e}) = {want:e}, got {got:e} ({e} ulp)");
        }
        assert!(worst > 0.0);
    }

    /// Within 2 ulp of the library's f64 exp on a dense grid of [−708, 709] (every 10⁻³ and
    /// the neighbourhoods of the reduction's steps, multiples of ln 2/2), 0 and ∞ beyond.
    #[test]
    fn exp_matches_the_library_within_two_ulp() {
        let grid = (-708_000..=709_000).map(|i| f64::from(i) * 1e-3);
        let steps = (-2044..=2046).flat_map(|k| {
            let x = f64::from(k) * 0.5 * std::f64::consts::LN_2;
            [x, crate::float::next_up(x), crate::float::next_down(x)]
        });
        let special = [0.0, -0.0, 1e-300, -1e-300, 1e-10, -708.0, 709.0, 1.0, -1.0];
        for x in grid.chain(steps).chain(special) {
            if !(-708.0..=709.0).contains(&x) {
                continue;
            }
            let (got, want) = (exp(x), x.exp());
            let e = ulps(got, want);
            assert!(e <= 2.0, "exp({x:e}) = {want:e}, got {got:e} ({e} ulp)");
        }
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(exp(-709.0), 0.0);
        assert_eq!(exp(-1e10), 0.0);
        assert_eq!(exp(710.0), f64::INFINITY);
        assert!(exp(f64::NAN).is_nan());
        assert_eq!(exp(f64::NEG_INFINITY), 0.0);
    }
}
