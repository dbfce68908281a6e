//! Speed of the library file format: opening a ~1 MiB library (one default 100×10×64 table)
//! with and without section verification, and table lookups through the map against an
//! in-memory copy. Run with `cargo bench -p bssrdf-zoo --bench format`.
//!
//! Targets (issue 4): open with full CRC verification ≤ 1 ms, without section verification
//! ≤ 50 µs.

use std::hint::black_box;

use bssrdf_zoo::format::{
    Compression, FresnelMoments, Library, LibraryBuilder, ModelKind, TableData, Verify,
};
use criterion::{criterion_group, criterion_main, Criterion};

/// A table of the default size with smooth made-up values.
fn default_table() -> TableData {
    let (n_rho, n_theta, n_r) = (100, 10, 64);
    let rho: Vec<f32> = (0..n_rho)
        .map(|i| (i as f32 + 0.5) / n_rho as f32)
        .collect();
    let theta: Vec<f32> = (0..n_theta)
        .map(|i| 1.5 * i as f32 / n_theta as f32)
        .collect();
    let r: Vec<f32> = (0..n_r).map(|i| 0.01 * 1.08f32.powi(i)).collect();
    let n = n_rho * n_theta * n_r as usize;
    TableData {
        model: ModelKind::PbdAngular,
        walk: None,
        ridge: bssrdf_zoo::table::RidgeKind::None,
        eta: 1.33,
        fresnel: FresnelMoments::Exact,
        gwc: (0..n).flat_map(gwc_node).collect(),
        cdf: (0..n).map(|i| (i % 64) as f32 / 63.0).collect(),
        theta_cdf: Some(rho.iter().flat_map(|&p| [p; 10]).collect()),
        harmonics: None,
        rebuild: Default::default(),
        rho,
        theta,
        r,
    }
}

/// Node `n`'s (E, E_β, c): smooth made-up values that the format accepts (a profile ≥ 0),
/// some with a negative floor (E_β up to 1.2 E, with |c| ≤ 0.4), as format 1.1 allows.
fn gwc_node(n: usize) -> [f32; 3] {
    let x = n as f32;
    let e = 0.5 + 0.4 * (x * 1e-3).sin();
    [
        e,
        e * (0.7 + 0.5 * (x * 7e-4).sin()),
        0.4 * (x * 3e-4).sin(),
    ]
}

/// Pseudo-random element indices of the GWC table (fixed LCG: the same every run).
fn indices(count: usize, len: usize) -> Vec<usize> {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    (0..count)
        .map(|_| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as usize % len
        })
        .collect()
}

fn bench_format(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("default.bssrdf");
    let mut builder = LibraryBuilder::new();
    builder.add_table(default_table()).unwrap();
    builder.write_atomic(&path, Compression::None).unwrap();
    let size = std::fs::metadata(&path).unwrap().len();
    eprintln!("library file: {size} bytes");

    let mut group = c.benchmark_group("open");
    group.bench_function("mmap_full_verify", |b| {
        b.iter(|| Library::open_mmap(black_box(&path), Verify::Full).unwrap())
    });
    group.bench_function("mmap_header_only", |b| {
        b.iter(|| Library::open_mmap(black_box(&path), Verify::HeaderOnly).unwrap())
    });
    group.bench_function("read_full_verify", |b| {
        b.iter(|| Library::read(black_box(&path), Verify::Full).unwrap())
    });
    group.finish();

    let mapped = Library::open_mmap(&path, Verify::Full).unwrap();
    let table = mapped.table(0).unwrap();
    let copy: Vec<f32> = table.gwc_params().to_vec();
    let at = indices(4096, copy.len());
    let mut group = c.benchmark_group("lookup_4096_random");
    group.bench_function("mapped", |b| {
        b.iter(|| {
            let gwc = table.gwc_params();
            at.iter().map(|&i| gwc[i]).sum::<f32>()
        })
    });
    group.bench_function("in_memory_copy", |b| {
        b.iter(|| at.iter().map(|&i| copy[i]).sum::<f32>())
    });
    group.finish();
}

criterion_group!(benches, bench_format);
criterion_main!(benches);
