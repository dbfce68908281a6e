//! The library-file parser behind its checksums: libFuzzer's inputs are library files, and a
//! custom mutator changes them where the reader decides — a header or directory field, a
//! record field, a table value, the directory itself (`bssrdf_zoo_fuzz::mutate`) — or lets
//! libFuzzer change bytes, then recomputes the CRCs (15 times in 16; the 16th keeps the CRC
//! checks in reach), so that a change meets the check it aims at instead of the header CRC.
//! Every input is parsed as is: a crash is a file with valid CRCs, ready to become a
//! conformance vector. A file that opens is also looked up (no lookup may panic).
//!
//! `mkdir -p corpus/structure && cp ../tests/data/*/*.bssrdf corpus/structure/`, then
//! `cargo +nightly fuzz run structure -- -rss_limit_mb=4096 -max_len=262144`.
#![no_main]

use bssrdf_zoo::embed;
use bssrdf_zoo::format::{Library, Verify};
use bssrdf_zoo::rng::{RngCore, SeedableRng, SplitMix64};
use bssrdf_zoo_fuzz::{layout, mutate, read_everything};
use libfuzzer_sys::{fuzz_mutator, fuzz_target, fuzzer_mutate};

fuzz_target!(|data: &[u8]| {
    for verify in [Verify::Full, Verify::HeaderOnly] {
        let Ok(library) = Library::from_bytes(data, verify) else {
            continue;
        };
        read_everything(&library);
        if library.verify().is_ok() && verify == Verify::Full {
            look_up(library);
        }
    }
});

/// A few lookups in every table of a file that opened: they may return anything, but not
/// panic.
fn look_up(library: Library) {
    let Ok(library) = embed::Library::from_format(library) else {
        return;
    };
    for table in library.tables() {
        let view = table.view();
        for (rho, theta, r, u) in [
            (0.5, 0.3, 0.7, 0.4),
            (0.0, 1.5, 0.0, 0.99),
            (1.0, 0.0, 1e3, 0.0),
        ] {
            let _ = view.eval(rho, theta, r, 0.5);
            let _ = view.pdf(rho, theta, r, 2.0);
            let _ = view.sample(rho, theta, u, 1.0 - u);
            let _ = view.sample_path(rho, [u, 0.5, 0.5, 0.5]);
        }
        if let Ok(channel) = table.medium(0.5, 2.0) {
            let _ = (channel.eval(0.3, 0.2, 0.1), channel.sample(0.3, 0.5, 0.5));
        }
    }
}

fuzz_mutator!(|data: &mut [u8], size: usize, max_size: usize, seed: u32| {
    let mut rng = SplitMix64::seed_from_u64(u64::from(seed));
    let mut file = data[..size].to_vec();
    if rng.next_u64().is_multiple_of(4) {
        let n = fuzzer_mutate(data, size, max_size);
        file = data[..n].to_vec();
    } else {
        mutate::mutate(&mut file, &mut rng);
    }
    if !rng.next_u64().is_multiple_of(16) {
        layout::repair_crcs(&mut file);
    }
    let n = file.len().min(max_size);
    data[..n].copy_from_slice(&file[..n]);
    n
});
