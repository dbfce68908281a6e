//! What the fuzz targets share: the library file's layout read leniently and laid out again
//! with its CRCs ([`layout`]), and the structure-aware changes of the `structure` target
//! ([`mutate`]).

pub mod layout;
pub mod mutate;

use bssrdf_zoo::format::Library;

/// Reads everything an opened library exposes: nothing it holds may panic on access.
pub fn read_everything(library: &Library) {
    for table in library.tables() {
        let _ = (table.gwc_params().len(), table.radial_cdf().len());
        let _ = (
            table.theta_cdf().map(<[f32]>::len),
            table.dims(),
            table.eta(),
        );
    }
    let _ = (library.materials().len(), library.provenance());
}

#[cfg(test)]
mod tests {
    //! The mutator on the conformance vectors, outside libFuzzer: no panic, and which checks
    //! its files fail (`cargo test --manifest-path fuzz/Cargo.toml -- --nocapture`).

    use std::collections::BTreeMap;

    use bssrdf_zoo::format::{Library, Verify};
    use bssrdf_zoo::rng::{RngCore, SeedableRng, SplitMix64};

    #[test]
    fn mutated_files_meet_the_checks_behind_the_crc() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data");
        let mut seeds = Vec::new();
        for sub in ["valid", "invalid"] {
            for entry in std::fs::read_dir(format!("{dir}/{sub}")).unwrap() {
                seeds.push(std::fs::read(entry.unwrap().path()).unwrap());
            }
        }
        let mut rng = SplitMix64::seed_from_u64(1);
        let mut codes: BTreeMap<&'static str, usize> = BTreeMap::new();
        for k in 0..20_000 {
            let mut file = seeds[k % seeds.len()].clone();
            for _ in 0..1 + rng.next_u64() % 3 {
                crate::mutate::mutate(&mut file, &mut rng);
            }
            crate::layout::repair_crcs(&mut file);
            let code = match Library::from_bytes(&file, Verify::Full) {
                Ok(_) => "ok",
                Err(e) => e.code(),
            };
            *codes.entry(code).or_default() += 1;
        }
        println!("{} codes: {codes:#?}", codes.len());
        assert!(codes.len() > 40, "{codes:?}");
    }

    /// The error codes of the files of a corpus folder (`BSSRDF_CORPUS=corpus/structure cargo
    /// test --release --manifest-path fuzz/Cargo.toml --lib -- --ignored --nocapture`): which
    /// checks a fuzzing run's corpus reaches.
    #[test]
    #[ignore = "needs a corpus folder in BSSRDF_CORPUS"]
    fn corpus_error_codes() {
        let dir = std::env::var("BSSRDF_CORPUS").expect("BSSRDF_CORPUS=folder");
        let mut codes: BTreeMap<&'static str, usize> = BTreeMap::new();
        for entry in std::fs::read_dir(dir).unwrap() {
            let file = std::fs::read(entry.unwrap().path()).unwrap();
            for verify in [Verify::Full, Verify::HeaderOnly] {
                let code = match Library::from_bytes(&file, verify) {
                    Ok(_) => "ok",
                    Err(e) => e.code(),
                };
                *codes.entry(code).or_default() += 1;
            }
        }
        println!("{} codes: {codes:#?}", codes.len());
    }
}
