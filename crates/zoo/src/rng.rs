//! Random streams. The generators are `rand_xoshiro`'s; what is ours is how a seed becomes a
//! stream ([`mix64`], [`crate::walk::rng::photon_stream`]) and how 64 bits become a number in
//! [0, 1) ([`UnitF64`]).
//!
//! - [`SplitMix64`] (Steele, Lea, Flood 2014, "Fast splittable pseudorandom number
//!   generators"; Vigna's `splitmix64.c`): the tool's own fixed, portable stream for its
//!   sampling (validation, tests, the `sample` command). `SplitMix64::seed_from_u64(seed)`
//!   starts the Weyl sequence at `seed` itself, as `splitmix64.c` does (rand_xoshiro overrides
//!   rand_core's generic seeding here), so any seed is valid and sampler output can be pinned
//!   for a seed on every platform.
//! - [`Xoshiro256PlusPlus`] (Blackman, Vigna 2021, "Scrambled linear pseudorandom number
//!   generators"): period 2²⁵⁶ − 1, the walk's per-photon streams.

pub use rand_core::{RngCore, SeedableRng};
pub use rand_xoshiro::{SplitMix64, Xoshiro256PlusPlus};

/// SplitMix64's increment γ = ⌊2⁶⁴/φ⌋ rounded to odd.
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// SplitMix64's output function at state `z`, a bijection of u64 (the MurmurHash3 finaliser
/// with Stafford's "Mix13" constants): the first output of the generator started at z − γ.
/// Hashes seeds into independent streams.
pub fn mix64(z: u64) -> u64 {
    SplitMix64::seed_from_u64(z.wrapping_sub(GAMMA)).next_u64()
}

/// Uniform doubles from any generator's 64-bit output.
pub trait UnitF64: RngCore {
    /// A uniform number in [0, 1) with 53 random bits: the top 53 bits of the next output,
    /// times 2⁻⁵³.
    #[inline]
    fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

impl<R: RngCore + ?Sized> UnitF64 for R {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_reference_outputs() {
        // Vigna's splitmix64.c (prng.di.unimi.it): from x = 0 its first two outputs, the
        // generator's usual test vector; from x = 1234567 the outputs quoted on Rosetta Code,
        // "Pseudo-random numbers/Splitmix64".
        let vectors: [(u64, &[u64]); 2] = [
            (0, &[0xE220_A839_7B1D_CDAF, 0x6E78_9E6A_A1B9_65F4]),
            (
                1_234_567,
                &[
                    6_457_827_717_110_365_317,
                    3_203_168_211_198_807_973,
                    9_817_491_932_198_370_423,
                    4_593_380_528_125_082_431,
                    16_408_922_859_458_223_821,
                ],
            ),
        ];
        for (seed, expected) in vectors {
            let mut g = SplitMix64::seed_from_u64(seed);
            let got: Vec<u64> = expected.iter().map(|_| g.next_u64()).collect();
            assert_eq!(got, expected, "seed {seed}");
        }
    }

    #[test]
    fn xoshiro256pp_matches_reference_outputs() {
        // Vigna's xoshiro256plusplus.c (prng.di.unimi.it) from s = {1, 2, 3, 4}, the vector of
        // rand_xoshiro's own tests. The first two follow by hand: rotl(1 + 4, 23) + 1 =
        // 5·2²³ + 1 = 41943041.
        let mut seed = [0u8; 32];
        for (k, word) in seed.chunks_exact_mut(8).enumerate() {
            word.copy_from_slice(&(k as u64 + 1).to_le_bytes());
        }
        let mut x = Xoshiro256PlusPlus::from_seed(seed);
        let expected: [u64; 10] = [
            41_943_041,
            58_720_359,
            3_588_806_011_781_223,
            3_591_011_842_654_386,
            9_228_616_714_210_784_205,
            9_973_669_472_204_895_162,
            14_011_001_112_246_962_877,
            12_406_186_145_184_390_807,
            15_849_039_046_786_891_736,
            10_450_023_813_501_588_000,
        ];
        for e in expected {
            assert_eq!(x.next_u64(), e);
        }
    }

    #[test]
    fn mix64_is_the_splitmix64_finaliser() {
        // The finaliser written out, z = 1: (z ^ z>>30)·C1, (· ^ ·>>27)·C2, · ^ ·>>31.
        let mut z: u64 = 1;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        assert_eq!(mix64(1), z ^ (z >> 31));
        assert_eq!(mix64(1), 6_238_072_747_940_578_789);
        assert_eq!(mix64(0), 0);
    }

    #[test]
    fn unit_f64_takes_the_top_53_bits() {
        let mut g = SplitMix64::seed_from_u64(0);
        let x = g.next_f64();
        assert_eq!(
            x,
            (0xE220_A839_7B1D_CDAF_u64 >> 11) as f64 / 9_007_199_254_740_992.0
        );
        assert!((0.0..1.0).contains(&x));
    }
}
