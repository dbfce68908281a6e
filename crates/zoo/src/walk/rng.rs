//! Random streams for the walk: one independent stream per photon, so that a photon's path
//! depends only on (seed, photon index) and never on which thread traced it.
//!
//! A photon's stream is xoshiro256++ (`rand_xoshiro`'s [`Xoshiro256PlusPlus`]) whose state is
//! four consecutive SplitMix64 outputs started from `mix64(mix64(seed) ⊕ index)`, SplitMix64
//! filling the state as Vigna recommends. Distinct photons start from (practically) unrelated
//! points of the 2²⁵⁶ cycle; a photon draws far fewer than 2⁶⁴ numbers, so streams never
//! overlap in practice.

pub use crate::rng::{mix64, RngCore, SeedableRng, UnitF64, Xoshiro256PlusPlus};

/// The stream of photon `index` for run seed `seed`.
pub fn photon_stream(seed: u64, index: u64) -> Xoshiro256PlusPlus {
    // rand_xoshiro seeds from a u64 through SplitMix64: the state is its next four outputs.
    Xoshiro256PlusPlus::seed_from_u64(mix64(mix64(seed) ^ index))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    #[test]
    fn photon_streams_are_pinned() {
        // The first outputs of photons (seed 7, index 3) and (0, 0), from the walk's own
        // xoshiro256++ and SplitMix64 before they came from rand_xoshiro: the walk's random
        // numbers are the same bits.
        let first = |seed, index| {
            let mut x = photon_stream(seed, index);
            [x.next_u64(), x.next_u64(), x.next_u64()]
        };
        assert_eq!(
            first(7, 3),
            [
                3_058_406_973_651_767_468,
                13_501_681_856_782_480_218,
                4_622_983_218_844_396_510
            ]
        );
        assert_eq!(
            first(0, 0),
            [
                5_987_356_902_031_041_503,
                7_051_070_477_665_621_255,
                6_633_766_593_972_829_180
            ]
        );
    }

    #[test]
    fn the_state_is_four_splitmix64_outputs() {
        // What `photon_stream` relies on in `seed_from_u64`, spelled out.
        let start = mix64(mix64(7) ^ 3);
        let mut sm = SplitMix64::seed_from_u64(start);
        let mut seed = [0u8; 32];
        for word in seed.chunks_exact_mut(8) {
            word.copy_from_slice(&sm.next_u64().to_le_bytes());
        }
        let (mut a, mut b) = (Xoshiro256PlusPlus::from_seed(seed), photon_stream(7, 3));
        for _ in 0..8 {
            assert_eq!(a.next_u64(), b.next_u64());
        }
    }

    #[test]
    fn uniform_stays_in_unit_interval_and_has_mean_one_half() {
        let mut x = photon_stream(7, 3);
        let n = 100_000;
        let mut sum = 0.0;
        for _ in 0..n {
            let u = x.next_f64();
            assert!((0.0..1.0).contains(&u));
            sum += u;
        }
        // Standard error of the mean is 1/sqrt(12 n) ≈ 9.1e-4; 5 of them.
        assert!((sum / n as f64 - 0.5).abs() < 5.0 * 9.2e-4);
    }

    #[test]
    fn photon_streams_differ_between_indices_and_seeds() {
        let first = |seed, index| photon_stream(seed, index).next_u64();
        assert_ne!(first(1, 0), first(1, 1));
        assert_ne!(first(1, 0), first(2, 0));
        assert_eq!(first(5, 9), first(5, 9));
    }
}
