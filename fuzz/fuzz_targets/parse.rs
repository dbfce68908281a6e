//! Feeds arbitrary bytes to the library-file parser: it must return a library or an error,
//! never panic, overflow or read out of bounds. Seed the corpus with the conformance vectors:
//! `mkdir -p corpus/parse && cp ../tests/data/*/*.bssrdf corpus/parse/`, then
//! `cargo +nightly fuzz run parse -- -rss_limit_mb=4096` (one section may decode to 1 GiB).
#![no_main]

use bssrdf_zoo::format::{Library, Verify};
use bssrdf_zoo_fuzz::read_everything;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for verify in [Verify::Full, Verify::HeaderOnly] {
        if let Ok(library) = Library::from_bytes(data, verify) {
            read_everything(&library);
            let _ = library.verify();
        }
    }
});
