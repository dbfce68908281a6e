//! Feeds arbitrary bytes to the library-file parser: it must return a library or an error,
//! never panic, overflow or read out of bounds. Seed the corpus with the conformance vectors:
//! `mkdir -p corpus/parse && cp ../tests/data/*/*.bssrdf corpus/parse/`, then
//! `cargo +nightly fuzz run parse -- -rss_limit_mb=4096` (one section may decode to 1 GiB).
#![no_main]

use bssrdf_zoo::format::{Library, Verify};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for verify in [Verify::Full, Verify::HeaderOnly] {
        if let Ok(library) = Library::from_bytes(data, verify) {
            for table in library.tables() {
                let _ = (table.gwc_params().len(), table.radial_cdf().len());
                let _ = (
                    table.theta_cdf().map(<[f32]>::len),
                    table.dims(),
                    table.eta(),
                );
            }
            let _ = (library.materials().len(), library.provenance());
            let _ = library.verify();
        }
    }
});
