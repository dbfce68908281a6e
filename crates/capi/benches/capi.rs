//! The cost of the embedding layers: evaluate, pdf, sample and the path-tracing draw through
//! (1) a `TableRef` made once from the mapped file and the crate's `World` conversion (the
//! direct baseline), (2) the Rust handle `embed::ChannelLookup`, (3) the C interface's
//! `extern "C"` functions called from Rust. Same mapped file (default grid, η = 1.33), same
//! random points over 64 media of random ρ′ and σ′t, so the three differ only by their layers.
//! Then the lookups with the medium given per call and the batches (`batch/…`): the same
//! points one call each (`MediumRef`, `bssrdf_table_eval`, …) and as batches of structures of
//! arrays, each point with its own medium (`TableRef::eval_n`, `bssrdf_table_eval_n`, …), for
//! all seven batches: eval, sample, pdf, the separable renderers' sample_radius, pdf_radius and
//! angular_factor, and the path-tracing draw sample_path.
//! Run: `cargo bench -p bssrdf-capi --bench capi` (`-- batch` for the batches alone).
//!
//! After criterion, a paired run prints the times and the ratios C / Rust handle and Rust
//! handle / direct: the 4096 points in blocks of 512, each block timed 31 times per variant
//! with the variants back to back (order alternating), each block's fastest time kept. On a
//! shared machine whose load changes from millisecond to millisecond, these figures are far
//! steadier than criterion's separate estimates, whose spread there exceeds the differences.
//! The batches are timed the same way, a block being one batch call of 512 points against 512
//! single calls, and held to their floors ([`EVAL_FLOOR_NS`], [`SAMPLE_FLOOR_NS`]): the
//! benchmark fails, naming the figure, if a batch costs more per point.
#![allow(unsafe_code)]

use std::ptr::null_mut;
use std::time::Instant;

use bssrdf::{self as capi, bssrdf_channel};
use bssrdf_testkit::lookups::{Columns, Inputs};
use bssrdf_zoo::embed::{ChannelLookup, Library};
use bssrdf_zoo::format::{self, Compression, LibraryBuilder, Verify};
use bssrdf_zoo::fresnel::Moments;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{
    bake, FileTable, Grid, GridPreset, PathSamplesMut, RadialSamplesMut, SamplesMut, TableRef,
    World,
};
use criterion::{black_box, Criterion, Throughput};

const MEDIA: usize = 64;

/// The most a batch evaluation may cost per point, ns, in the paired run.
const EVAL_FLOOR_NS: f64 = 60.0;
/// The most a batch draw of (r, φ) may cost per point, ns, in the paired run.
const SAMPLE_FLOOR_NS: f64 = 250.0;

/// The three ways to one table, and the points to look up.
struct Fixture<'a> {
    direct: Vec<(f64, World<'a>)>,
    handles: Vec<ChannelLookup>,
    channels: Vec<*mut bssrdf_channel>,
    c_library: *mut capi::bssrdf_library,
    /// (medium, [θ, r mm, φ]) where the table holds energy, as a renderer meets them.
    points: Vec<(usize, [f64; 3])>,
    uniforms: Vec<[f64; 4]>,
    /// The Rust library of `handles`, for the lookups with the medium given per call.
    library: Library,
    /// The points as a batch takes them: point i with its medium's ρ′ and σ′t, and the
    /// uniforms of its draw.
    columns: Columns,
}

/// Bakes the default grid for η = 1.33 into `dir`.
fn bench_file(dir: &std::path::Path) -> std::path::PathBuf {
    let path = dir.join("bench.bssrdf");
    let grid = Grid::preset(GridPreset::Default);
    let (table, _) = bake(1.33, Moments::Exact, &grid, true).unwrap();
    let mut builder = LibraryBuilder::new();
    builder.add_table(table.to_table_data()).unwrap();
    builder.write_atomic(&path, Compression::None).unwrap();
    path
}

impl<'a> Fixture<'a> {
    /// `view` is the direct way: table 0 of the file at `path`, opened by the caller.
    fn new(path: &std::path::Path, view: TableRef<'a>) -> Fixture<'a> {
        let library = Library::open_mmap(path).unwrap();
        let c_path = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
        let mut c_library = null_mut();
        // SAFETY: a valid path and output.
        assert_eq!(
            unsafe { capi::bssrdf_library_open(c_path.as_ptr(), 0, &mut c_library) },
            0
        );

        let mut rng = SplitMix64::seed_from_u64(1);
        let (mut direct, mut handles, mut channels) = (Vec::new(), Vec::new(), Vec::new());
        let mut media = Vec::new();
        for _ in 0..MEDIA {
            let (rho, st) = (0.05 + 0.95 * rng.next_f64(), 0.5 + 4.0 * rng.next_f64());
            media.push((rho, st));
            direct.push((rho, World::new(view, st).unwrap()));
            handles.push(library.table(0).unwrap().medium(rho, st).unwrap());
            let mut ch = null_mut();
            // SAFETY: a live library and a valid output.
            let status = unsafe { capi::bssrdf_library_medium(c_library, 0, rho, st, &mut ch) };
            assert_eq!(status, 0);
            channels.push(ch);
        }
        let points: Vec<(usize, [f64; 3])> = (0..4096)
            .map(|k| loop {
                let m = k % MEDIA;
                let theta = 1.5 * rng.next_f64();
                if let Some(s) = handles[m].sample(theta, rng.next_f64(), rng.next_f64()) {
                    break (m, [theta, s.r, s.phi]);
                }
            })
            .collect();
        let uniforms: Vec<[f64; 4]> = (0..4096).map(|_| [0; 4].map(|_| rng.next_f64())).collect();
        let columns = points
            .iter()
            .enumerate()
            .map(|(i, &(m, [theta, r, phi]))| Inputs {
                rho: media[m].0,
                theta,
                r,
                phi,
                u: uniforms[(i + 1) % uniforms.len()],
                sigma_t: media[m].1,
            })
            .collect();
        Fixture {
            direct,
            handles,
            channels,
            c_library,
            points,
            uniforms,
            library,
            columns,
        }
    }

    fn c_eval(&self, m: usize, [theta, r, phi]: [f64; 3]) -> f64 {
        let mut value = 0.0;
        // SAFETY: a live channel and a valid output.
        let status =
            unsafe { capi::bssrdf_channel_eval(self.channels[m], theta, r, phi, &mut value) };
        value + f64::from(status)
    }

    fn c_pdf(&self, m: usize, [theta, r, phi]: [f64; 3]) -> f64 {
        let mut value = 0.0;
        // SAFETY: a live channel and a valid output.
        let status =
            unsafe { capi::bssrdf_channel_pdf(self.channels[m], theta, r, phi, &mut value) };
        value + f64::from(status)
    }

    fn c_sample_path(&self, m: usize, u: [f64; 4]) -> f64 {
        let mut p = capi::bssrdf_path_sample {
            theta: 0.0,
            r: 0.0,
            phi: 0.0,
            phi_prime: 0.0,
            pdf_theta: 0.0,
            pdf: 0.0,
        };
        // SAFETY: a live channel, 4 readable doubles and a valid output.
        let status =
            unsafe { capi::bssrdf_channel_sample_path(self.channels[m], u.as_ptr(), &mut p) };
        p.r + f64::from(status)
    }

    fn c_sample(&self, m: usize, theta: f64, u: [f64; 4]) -> f64 {
        let mut s = capi::bssrdf_sample {
            r: 0.0,
            phi: 0.0,
            pdf: 0.0,
        };
        // SAFETY: a live channel and a valid output.
        let status =
            unsafe { capi::bssrdf_channel_sample(self.channels[m], theta, u[0], u[1], &mut s) };
        s.r + f64::from(status)
    }
}

impl Drop for Fixture<'_> {
    fn drop(&mut self) {
        // SAFETY: handles from `new`, released once.
        unsafe {
            for &ch in &self.channels {
                capi::bssrdf_channel_release(ch);
            }
            capi::bssrdf_library_close(self.c_library);
        }
    }
}

fn bench(c: &mut Criterion, f: &Fixture) {
    let (points, uniforms, worlds, handles, channels) =
        (&f.points, &f.uniforms, &f.direct, &f.handles, &f.channels);
    let mut i = 0usize;
    let mut next = || {
        i = (i + 1) % 4096;
        i
    };
    let mut group = c.benchmark_group("capi");
    group.bench_function("eval/direct", |b| {
        b.iter(|| {
            let (m, [theta, r, phi]) = points[next()];
            let (rho, world) = &worlds[m];
            world.eval(*rho, black_box(theta), black_box(r), black_box(phi))
        })
    });
    group.bench_function("eval/rust_handle", |b| {
        b.iter(|| {
            let (m, [theta, r, phi]) = points[next()];
            handles[m].eval(black_box(theta), black_box(r), black_box(phi))
        })
    });
    group.bench_function("eval/c_api", |b| {
        b.iter(|| {
            let (m, [theta, r, phi]) = points[next()];
            let mut value = 0.0;
            // SAFETY: a live channel and a valid output.
            let status = unsafe {
                capi::bssrdf_channel_eval(channels[m], black_box(theta), r, phi, &mut value)
            };
            (status, value)
        })
    });
    group.bench_function("sample/direct", |b| {
        b.iter(|| {
            let (m, [theta, _, _]) = points[next()];
            let u = uniforms[next()];
            let (rho, world) = &worlds[m];
            world.sample(*rho, black_box(theta), u[0], u[1])
        })
    });
    group.bench_function("sample/rust_handle", |b| {
        b.iter(|| {
            let (m, [theta, _, _]) = points[next()];
            let u = uniforms[next()];
            handles[m].sample(black_box(theta), u[0], u[1])
        })
    });
    group.bench_function("sample/c_api", |b| {
        b.iter(|| {
            let (m, [theta, _, _]) = points[next()];
            let u = uniforms[next()];
            let mut s = capi::bssrdf_sample {
                r: 0.0,
                phi: 0.0,
                pdf: 0.0,
            };
            // SAFETY: a live channel and a valid output.
            let status = unsafe {
                capi::bssrdf_channel_sample(channels[m], black_box(theta), u[0], u[1], &mut s)
            };
            (status, s)
        })
    });
    group.bench_function("pdf/rust_handle", |b| {
        b.iter(|| {
            let (m, [theta, r, phi]) = points[next()];
            handles[m].pdf(black_box(theta), black_box(r), black_box(phi))
        })
    });
    group.bench_function("pdf/c_api", |b| {
        b.iter(|| {
            let (m, [theta, r, phi]) = points[next()];
            let mut value = 0.0;
            // SAFETY: a live channel and a valid output.
            let status = unsafe {
                capi::bssrdf_channel_pdf(channels[m], black_box(theta), r, phi, &mut value)
            };
            (status, value)
        })
    });
    group.bench_function("sample_path/rust_handle", |b| {
        b.iter(|| {
            let (m, _) = points[next()];
            handles[m].sample_path(black_box(uniforms[next()]))
        })
    });
    group.bench_function("sample_path/c_api", |b| {
        b.iter(|| {
            let (m, _) = points[next()];
            let u = black_box(uniforms[next()]);
            let mut p = capi::bssrdf_path_sample {
                theta: 0.0,
                r: 0.0,
                phi: 0.0,
                phi_prime: 0.0,
                pdf_theta: 0.0,
                pdf: 0.0,
            };
            // SAFETY: a live channel, 4 readable doubles and a valid output.
            let status =
                unsafe { capi::bssrdf_channel_sample_path(channels[m], u.as_ptr(), &mut p) };
            (status, p)
        })
    });
    group.finish();
}

/// Lookups per timed block: about 0.1–0.4 ms, short enough that most blocks run without the
/// process being descheduled on a loaded machine.
const BLOCK: usize = 512;

/// Nanoseconds per lookup of each variant: every block of `BLOCK` points is timed `reps`
/// times per variant, the variants back to back in alternating order; each block keeps its
/// fastest time (the runs no other process interrupted), and the blocks are summed.
fn interleaved(reps: usize, variants: &mut [&mut dyn FnMut(usize) -> f64]) -> Vec<f64> {
    let mut blocks: Vec<Box<dyn FnMut(std::ops::Range<usize>) -> f64 + '_>> = variants
        .iter_mut()
        .map(|v| Box::new(move |block: std::ops::Range<usize>| block.map(&mut **v).sum()) as _)
        .collect();
    let mut blocks: Vec<&mut dyn FnMut(std::ops::Range<usize>) -> f64> =
        blocks.iter_mut().map(|b| &mut **b as _).collect();
    interleaved_blocks(reps, &mut blocks)
}

/// [`interleaved`] for variants that take a block of points at once (a batch).
fn interleaved_blocks(
    reps: usize,
    variants: &mut [&mut dyn FnMut(std::ops::Range<usize>) -> f64],
) -> Vec<f64> {
    let blocks = 4096 / BLOCK;
    // best[block][variant], ns for the whole block.
    let mut best = vec![vec![f64::INFINITY; variants.len()]; blocks];
    let mut sink = 0.0;
    for rep in 0..reps {
        for (block, best) in best.iter_mut().enumerate() {
            for k in 0..variants.len() {
                // Alternate the order so that neither variant always runs first.
                let v = if (rep + block) % 2 == 0 {
                    k
                } else {
                    variants.len() - 1 - k
                };
                let start = Instant::now();
                sink += (variants[v])(block * BLOCK..(block + 1) * BLOCK);
                best[v] = best[v].min(start.elapsed().as_nanos() as f64);
            }
        }
    }
    black_box(sink);
    (0..variants.len())
        .map(|v| best.iter().map(|b| b[v]).sum::<f64>() / 4096.0)
        .collect()
}

/// Prints the times and ratios of an interleaved comparison.
fn report(name: &str, labels: &[&str], ns: &[f64]) {
    let times: Vec<String> = labels
        .iter()
        .zip(ns)
        .map(|(l, t)| format!("{l} {t:.0} ns"))
        .collect();
    let mut line = format!("paired {name}: {}", times.join(", "));
    if ns.len() == 3 {
        line += &format!("; handle/direct {:.3}", ns[1] / ns[0]);
    }
    let n = ns.len();
    line += &format!("; C/handle {:.3}", ns[n - 1] / ns[n - 2]);
    println!("{line}");
}

/// The interleaved comparison (see the module docs).
fn paired(f: &Fixture) {
    let reps = 31;
    let n = f.points.len();
    let eval = interleaved(
        reps,
        &mut [
            &mut |i| {
                let (m, [theta, r, phi]) = f.points[i];
                let (rho, world) = &f.direct[m];
                world.eval(*rho, black_box(theta), r, phi).unwrap_or(0.0)
            },
            &mut |i| {
                let (m, [theta, r, phi]) = f.points[i];
                f.handles[m].eval(black_box(theta), r, phi).unwrap_or(0.0)
            },
            &mut |i| {
                let (m, [theta, r, phi]) = f.points[i];
                f.c_eval(m, [black_box(theta), r, phi])
            },
        ],
    );
    report("eval", &["direct", "handle", "C"], &eval);
    let sample = interleaved(
        reps,
        &mut [
            &mut |i| {
                let (m, [theta, _, _]) = f.points[i];
                let u = f.uniforms[(i + 1) % n];
                let (rho, world) = &f.direct[m];
                world
                    .sample(*rho, black_box(theta), u[0], u[1])
                    .map_or(0.0, |s| s.r)
            },
            &mut |i| {
                let (m, [theta, _, _]) = f.points[i];
                let u = f.uniforms[(i + 1) % n];
                f.handles[m]
                    .sample(black_box(theta), u[0], u[1])
                    .map_or(0.0, |s| s.r)
            },
            &mut |i| {
                let (m, [theta, _, _]) = f.points[i];
                f.c_sample(m, black_box(theta), f.uniforms[(i + 1) % n])
            },
        ],
    );
    report("sample", &["direct", "handle", "C"], &sample);
    let pdf = interleaved(
        reps,
        &mut [
            &mut |i| {
                let (m, [theta, r, phi]) = f.points[i];
                f.handles[m].pdf(black_box(theta), r, phi)
            },
            &mut |i| {
                let (m, [theta, r, phi]) = f.points[i];
                f.c_pdf(m, [black_box(theta), r, phi])
            },
        ],
    );
    report("pdf", &["handle", "C"], &pdf);
    let path = interleaved(
        reps,
        &mut [
            &mut |i| {
                let (m, _) = f.points[i];
                f.handles[m]
                    .sample_path(black_box(f.uniforms[i]))
                    .map_or(0.0, |p| p.r)
            },
            &mut |i| {
                let (m, _) = f.points[i];
                f.c_sample_path(m, black_box(f.uniforms[i]))
            },
        ],
    );
    report("sample_path", &["handle", "C"], &path);
}

impl Fixture<'_> {
    /// One point per call with its medium (`MediumRef`, `bssrdf_table_*`), and batches over
    /// the points of `range`, each a sum of the outputs (so none is optimised away).
    fn rust_single(&self, what: Lookup, i: usize) -> f64 {
        let c = &self.columns;
        let view = self.library.view(0).unwrap();
        let Ok(m) = view.medium(c.rho[i], c.sigma_t[i]) else {
            return 0.0;
        };
        match what {
            Lookup::Eval => m
                .eval(black_box(c.theta[i]), c.r[i], c.phi[i])
                .unwrap_or(0.0),
            Lookup::Pdf => m.pdf(black_box(c.theta[i]), c.r[i], c.phi[i]),
            Lookup::Sample => m
                .sample(black_box(c.theta[i]), c.u_r[i], c.u_phi[i])
                .map_or(0.0, |s| s.r),
            Lookup::SampleRadius => m
                .sample_radius(black_box(c.theta[i]), c.u_r[i])
                .map_or(0.0, |s| s.r),
            Lookup::PdfRadius => m.pdf_radius(black_box(c.theta[i]), c.r[i]),
            Lookup::AngularFactor => m
                .angular_factor(black_box(c.theta[i]), c.r[i], c.phi[i])
                .unwrap_or(0.0),
            Lookup::SamplePath => m
                .sample_path(black_box([c.u_r[i], c.u_phi[i], c.u2[i], c.u3[i]]))
                .map_or(0.0, |s| s.r),
        }
    }

    fn c_single(&self, what: Lookup, i: usize) -> f64 {
        let (c, lib) = (&self.columns, self.c_library);
        let (rho, st, theta) = (c.rho[i], c.sigma_t[i], black_box(c.theta[i]));
        let mut value = 0.0;
        let mut s = capi::bssrdf_sample::default();
        let mut d = capi::bssrdf_radial_sample::default();
        let mut p = capi::bssrdf_path_sample::default();
        let u = [c.u_r[i], c.u_phi[i], c.u2[i], c.u3[i]];
        // SAFETY: a live library and valid outputs.
        let status = unsafe {
            match what {
                Lookup::Eval => {
                    capi::bssrdf_table_eval(lib, 0, rho, st, theta, c.r[i], c.phi[i], &mut value)
                }
                Lookup::Pdf => {
                    capi::bssrdf_table_pdf(lib, 0, rho, st, theta, c.r[i], c.phi[i], &mut value)
                }
                Lookup::Sample => {
                    capi::bssrdf_table_sample(lib, 0, rho, st, theta, c.u_r[i], c.u_phi[i], &mut s)
                }
                Lookup::SampleRadius => {
                    capi::bssrdf_table_sample_radius(lib, 0, rho, st, theta, c.u_r[i], &mut d)
                }
                Lookup::PdfRadius => {
                    capi::bssrdf_table_pdf_radius(lib, 0, rho, st, theta, c.r[i], &mut value)
                }
                Lookup::AngularFactor => capi::bssrdf_table_angular_factor(
                    lib, 0, rho, st, theta, c.r[i], c.phi[i], &mut value,
                ),
                Lookup::SamplePath => {
                    capi::bssrdf_table_sample_path(lib, 0, rho, st, black_box(u).as_ptr(), &mut p)
                }
            }
        };
        value + s.r + d.r + p.r + f64::from(status)
    }

    fn rust_batch(&self, what: Lookup, range: std::ops::Range<usize>, out: &mut Outputs) -> f64 {
        let c = &self.columns;
        let view = self.library.view(0).unwrap();
        let n = range.len();
        let (rho, st, theta) = (
            &c.rho[range.clone()],
            &c.sigma_t[range.clone()],
            &c.theta[range.clone()],
        );
        let u = [&c.u_r, &c.u_phi, &c.u2, &c.u3].map(|u| &u[range.clone()]);
        let (a, b) = match what {
            Lookup::Sample => (&c.u_r[range.clone()], &c.u_phi[range]),
            _ => (&c.r[range.clone()], &c.phi[range]),
        };
        let [e0, e1, e2] = &mut out.extra;
        match what {
            Lookup::Eval => view.eval_n(rho, st, theta, a, b, &mut out.value[..n]),
            Lookup::Pdf => view.pdf_n(rho, st, theta, a, b, &mut out.value[..n]),
            Lookup::Sample => {
                let draws = SamplesMut {
                    r: &mut out.r[..n],
                    phi: &mut out.phi[..n],
                    pdf: &mut out.value[..n],
                };
                view.sample_n(rho, st, theta, a, b, draws)
            }
            Lookup::SampleRadius => {
                let draws = RadialSamplesMut {
                    r: &mut out.r[..n],
                    pdf: &mut out.value[..n],
                };
                view.sample_radius_n(rho, st, theta, u[0], draws)
            }
            Lookup::PdfRadius => view.pdf_radius_n(rho, st, theta, a, &mut out.value[..n]),
            Lookup::AngularFactor => {
                view.angular_factor_n(rho, st, theta, a, b, &mut out.value[..n])
            }
            Lookup::SamplePath => {
                let fields = [e0, &mut out.r, &mut out.phi, e1, e2, &mut out.value];
                let draws = PathSamplesMut::from(fields.map(|f| &mut f[..n]));
                view.sample_path_n(rho, st, u, draws)
            }
        }
        .unwrap();
        out.value[n - 1] + out.r[n - 1]
    }

    fn c_batch(&self, what: Lookup, range: std::ops::Range<usize>, out: &mut Outputs) -> f64 {
        let (c, lib, n) = (&self.columns, self.c_library, range.len());
        let at = |v: &[f64]| v[range.start..].as_ptr();
        let (rho, st, theta) = (at(&c.rho), at(&c.sigma_t), at(&c.theta));
        let (r, phi, value) = (at(&c.r), at(&c.phi), out.value.as_mut_ptr());
        let (u_r, u_phi, u2, u3) = (at(&c.u_r), at(&c.u_phi), at(&c.u2), at(&c.u3));
        let (draw_r, draw_phi) = (out.r.as_mut_ptr(), out.phi.as_mut_ptr());
        let [e0, e1, e2] = out.extra.each_mut().map(|e| e.as_mut_ptr());
        // SAFETY: a live library; every array holds at least n doubles from its pointer, the
        // outputs apart from the inputs.
        let status = unsafe {
            match what {
                Lookup::Eval => capi::bssrdf_table_eval_n(lib, 0, n, rho, st, theta, r, phi, value),
                Lookup::Pdf => capi::bssrdf_table_pdf_n(lib, 0, n, rho, st, theta, r, phi, value),
                Lookup::Sample => capi::bssrdf_table_sample_n(
                    lib, 0, n, rho, st, theta, u_r, u_phi, draw_r, draw_phi, value,
                ),
                Lookup::SampleRadius => capi::bssrdf_table_sample_radius_n(
                    lib, 0, n, rho, st, theta, u_r, draw_r, value,
                ),
                Lookup::PdfRadius => {
                    capi::bssrdf_table_pdf_radius_n(lib, 0, n, rho, st, theta, r, value)
                }
                Lookup::AngularFactor => {
                    capi::bssrdf_table_angular_factor_n(lib, 0, n, rho, st, theta, r, phi, value)
                }
                Lookup::SamplePath => capi::bssrdf_table_sample_path_n(
                    lib, 0, n, rho, st, u_r, u_phi, u2, u3, e0, draw_r, draw_phi, e1, e2, value,
                ),
            }
        };
        assert_eq!(status, 0);
        out.value[n - 1] + out.r[n - 1]
    }
}

/// Which lookup a batch benchmark times.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Lookup {
    Eval,
    Pdf,
    Sample,
    SampleRadius,
    PdfRadius,
    AngularFactor,
    SamplePath,
}

/// Every lookup the batch benchmarks time, with its name; the floors of the paired run.
const LOOKUPS: [(&str, Lookup, Option<f64>); 7] = [
    ("eval", Lookup::Eval, Some(EVAL_FLOOR_NS)),
    ("sample", Lookup::Sample, Some(SAMPLE_FLOOR_NS)),
    ("pdf", Lookup::Pdf, None),
    ("sample_radius", Lookup::SampleRadius, None),
    ("pdf_radius", Lookup::PdfRadius, None),
    ("angular_factor", Lookup::AngularFactor, None),
    ("sample_path", Lookup::SamplePath, None),
];

/// The output arrays of a batch (`value` is the draws' density; `extra` the path draws' θ, φ′
/// and pdf_theta).
struct Outputs {
    value: Vec<f64>,
    r: Vec<f64>,
    phi: Vec<f64>,
    extra: [Vec<f64>; 3],
}

impl Outputs {
    fn new() -> Outputs {
        Outputs {
            value: vec![0.0; 4096],
            r: vec![0.0; 4096],
            phi: vec![0.0; 4096],
            extra: [(); 3].map(|_| vec![0.0; 4096]),
        }
    }
}

/// Criterion: one point per call with its medium, and batches of all 4096 points.
fn bench_batches(c: &mut Criterion, f: &Fixture) {
    let mut group = c.benchmark_group("batch");
    let mut out = Outputs::new();
    for (name, what, _) in LOOKUPS {
        let mut i = 0usize;
        let mut next = || {
            i = (i + 1) % 4096;
            i
        };
        group.throughput(Throughput::Elements(1));
        group.bench_function(format!("{name}/single_rust"), |b| {
            b.iter(|| f.rust_single(what, next()))
        });
        group.bench_function(format!("{name}/single_c"), |b| {
            b.iter(|| f.c_single(what, next()))
        });
        group.throughput(Throughput::Elements(4096));
        group.bench_function(format!("{name}/batch_rust_4096"), |b| {
            b.iter(|| f.rust_batch(what, 0..4096, &mut out))
        });
        group.bench_function(format!("{name}/batch_c_4096"), |b| {
            b.iter(|| f.c_batch(what, 0..4096, &mut out))
        });
    }
    group.finish();
}

/// The paired run of the batches against single calls: ns per point of one C call per point,
/// a C batch per block and a Rust batch per block, and the verdicts on the floors.
fn paired_batches(f: &Fixture) -> Vec<String> {
    let mut over = Vec::new();
    for (name, what, floor) in LOOKUPS {
        let (mut out_c, mut out_rust) = (Outputs::new(), Outputs::new());
        let ns = interleaved_blocks(
            31,
            &mut [
                &mut |block: std::ops::Range<usize>| block.map(|i| f.c_single(what, i)).sum(),
                &mut |block| f.c_batch(what, block, &mut out_c),
                &mut |block| f.rust_batch(what, block, &mut out_rust),
            ],
        );
        let [single, c_batch, rust_batch] = [ns[0], ns[1], ns[2]];
        let figures = format!(
            "C batch {c_batch:.1} ns ({:.2}x), Rust batch {rust_batch:.1} ns ({:.2}x) per point",
            c_batch / single,
            rust_batch / single
        );
        let verdict = match floor {
            Some(floor) if c_batch.max(rust_batch) > floor => {
                over.push(format!(
                    "batch {name}: {figures}, over the floor of {floor} ns"
                ));
                format!("OVER the floor of {floor} ns")
            }
            Some(floor) => format!("within the floor of {floor} ns"),
            None => "no floor".to_owned(),
        };
        println!("paired batch {name}: single C call {single:.1} ns, {figures}; {verdict}");
    }
    over
}

fn main() {
    let dir = tempfile::tempdir().unwrap();
    let path = bench_file(dir.path());
    let file = format::Library::open_mmap(&path, Verify::Full).unwrap();
    let table = FileTable::new(file.table(0).unwrap()).unwrap();
    let fixture = Fixture::new(&path, table.view().unwrap());
    let mut criterion = Criterion::default().configure_from_args();
    bench(&mut criterion, &fixture);
    bench_batches(&mut criterion, &fixture);
    paired(&fixture);
    let over = paired_batches(&fixture);
    criterion.final_summary();
    // The floors are a gate under `cargo bench` (`cargo test --benches` runs this once, as a
    // smoke test, on whatever load the machine has)
    if std::env::args().any(|a| a == "--bench") {
        assert!(over.is_empty(), "batch floors missed:\n{}", over.join("\n"));
    }
}
