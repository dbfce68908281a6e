//! Lookups never allocate: through the Rust handles (`embed`) and through the C interface,
//! on success and on failure. A counting global allocator counts the allocations of the
//! current thread only, so the test harness's own threads cannot disturb the count; this
//! file is a test binary of its own because it replaces the global allocator.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use bssrdf as capi;
use bssrdf_zoo::embed::bake_library;
use bssrdf_zoo::materials::{self, Rgb};
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{Grid, PathSamplesMut, RadialSamplesMut, SamplesMut};

struct Counting;

thread_local! {
    // Const-initialised and without destructor: usable inside the allocator.
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

// SAFETY: forwards every call to the system allocator unchanged; only counts.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        // SAFETY: the caller's contract is passed on unchanged.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract is passed on unchanged.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        // SAFETY: the caller's contract is passed on unchanged.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by this thread while running `f`.
fn allocations(f: impl FnOnce()) -> u64 {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

#[test]
fn the_counter_counts() {
    assert!(allocations(|| drop(std::hint::black_box(vec![1u8; 64]))) >= 1);
}

#[test]
fn rust_handle_lookups_and_clones_never_allocate() {
    // Every lookup of a handle, the separable renderers' and the diffuse reflectance included
    let skin = materials::Library::builtin().get("skin1").unwrap().clone();
    let library = bake_library(&[&skin], Grid::ferrier(12, 5, 16)).unwrap();
    let handles: Vec<_> = Rgb::ALL
        .map(|c| library.channel("skin1", c).unwrap())
        .into();
    let table = library.table(0).unwrap();
    let mut rng = SplitMix64::seed_from_u64(3);
    let mut sink = 0.0;
    let n = allocations(|| {
        for k in 0..3000 {
            let h = &handles[k % 3];
            // θ up to 1.1 × 90°: a tenth of the lookups fall outside the table.
            let theta = 1.1 * std::f64::consts::FRAC_PI_2 * rng.next_f64();
            let (r, phi) = (3.0 * rng.next_f64(), 6.0 * rng.next_f64() - 3.0);
            let u = [0; 4].map(|_| rng.next_f64());
            sink += h.eval(theta, r, phi).unwrap_or(0.0);
            sink += h.pdf(theta, r, phi);
            sink += h.sample(theta, u[0], u[1]).map_or(0.0, |s| s.r);
            sink += h.sample_path(u).map_or(0.0, |s| s.pdf);
            sink += h.pdf_theta(theta);
            sink += h.effective_albedo(theta).unwrap_or(0.0);
            sink += h.diffuse_reflectance(theta).unwrap_or(0.0);
            sink += h.sample_radius(theta, u[0]).map_or(0.0, |s| s.pdf);
            sink += h.pdf_radius(theta, r) + h.angular_factor(theta, r, phi).unwrap_or(0.0);
            sink += table.view().eval(u[2], theta, r, phi).unwrap_or(0.0);
            let clone = std::hint::black_box(h.clone());
            sink += clone.rho_prime();
        }
    });
    assert!(sink.is_finite() && sink > 0.0);
    assert_eq!(n, 0, "{n} allocations in 3000 rounds of lookups");
}

/// skin1 baked on a small grid into `dir`, and opened by C (the caller closes it).
#[allow(unsafe_code)]
fn skin1(dir: &std::path::Path) -> (bssrdf_zoo::embed::Library, *mut capi::bssrdf_library) {
    let path = dir.join("skin.bssrdf");
    let skin = materials::Library::builtin().get("skin1").unwrap().clone();
    let rust = bake_library(&[&skin], Grid::ferrier(12, 5, 16)).unwrap();
    rust.write(&path).unwrap();
    let c_path = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
    let mut library = std::ptr::null_mut();
    // SAFETY: a valid string and output.
    let status = unsafe { capi::bssrdf_library_open(c_path.as_ptr(), 0, &mut library) };
    assert_eq!(status, 0);
    (rust, library)
}

#[test]
#[allow(unsafe_code)]
fn c_interface_lookups_never_allocate_even_when_they_fail() {
    let dir = tempfile::tempdir().unwrap();
    let (_, library) = skin1(dir.path());
    let mut channel = std::ptr::null_mut();
    // SAFETY: a live library, a valid string and output; the handle is released below, once.
    let status =
        unsafe { capi::bssrdf_library_channel(library, c"skin1".as_ptr(), 1, &mut channel) };
    assert_eq!(status, 0);
    let mut rng = SplitMix64::seed_from_u64(4);
    let mut failures = 0;
    let n = allocations(|| {
        for _ in 0..3000 {
            let theta = 1.1 * std::f64::consts::FRAC_PI_2 * rng.next_f64();
            let (r, phi) = (3.0 * rng.next_f64(), 6.0 * rng.next_f64() - 3.0);
            let u = [0; 4].map(|_| rng.next_f64());
            let mut value = 0.0;
            let mut sample = capi::bssrdf_sample {
                r: 0.0,
                phi: 0.0,
                pdf: 0.0,
            };
            let mut radial = capi::bssrdf_radial_sample::default();
            let mut path_sample = capi::bssrdf_path_sample {
                theta: 0.0,
                r: 0.0,
                phi: 0.0,
                phi_prime: 0.0,
                pdf_theta: 0.0,
                pdf: 0.0,
            };
            // SAFETY: a live channel handle and valid outputs.
            let statuses = unsafe {
                [
                    capi::bssrdf_channel_eval(channel, theta, r, phi, &mut value),
                    capi::bssrdf_channel_pdf(channel, theta, r, phi, &mut value),
                    capi::bssrdf_channel_sample(channel, theta, u[0], u[1], &mut sample),
                    capi::bssrdf_channel_sample_path(channel, u.as_ptr(), &mut path_sample),
                    capi::bssrdf_channel_pdf_theta(channel, theta, &mut value),
                    capi::bssrdf_channel_effective_albedo(channel, theta, &mut value),
                    capi::bssrdf_channel_eval(channel, theta, r, phi, std::ptr::null_mut()),
                    capi::bssrdf_channel_sample_radius(channel, theta, u[0], &mut radial),
                    capi::bssrdf_channel_pdf_radius(channel, theta, r, &mut value),
                    capi::bssrdf_channel_angular_factor(channel, theta, r, phi, &mut value),
                    capi::bssrdf_channel_diffuse_reflectance(channel, theta, &mut value),
                ]
            };
            failures += statuses.iter().filter(|&&s| s != 0).count();
            std::hint::black_box((value, sample, path_sample, radial));
        }
    });
    // SAFETY: handles from above, released once.
    unsafe {
        capi::bssrdf_channel_release(channel);
        capi::bssrdf_library_close(library);
    }
    assert!(
        failures > 3000,
        "the failure paths ran ({failures} failures)"
    );
    assert_eq!(n, 0, "{n} allocations in 3000 rounds of C lookups");
}

/// The diffuse reflectance's inverse and range allocate nothing when they succeed, through the
/// runtime (`TableRef`) and through the C interface (a failure formats its message).
#[test]
#[allow(unsafe_code)]
fn reflectance_inversions_that_succeed_never_allocate() {
    let dir = tempfile::tempdir().unwrap();
    let (rust, library) = skin1(dir.path());
    let table = rust.table(0).unwrap();
    let mut rng = SplitMix64::seed_from_u64(5);
    let mut sink = 0.0;
    let n = allocations(|| {
        for _ in 0..3000 {
            // θ below 89° and A inside the range: every call succeeds.
            let theta = 1.55 * rng.next_f64();
            let view = table.view();
            let [_, max] = view.reflectance_range(theta).unwrap();
            let a = max * rng.next_f64();
            sink += view.rho_prime_for_reflectance(a, theta).unwrap();
            let (mut rho, mut lo, mut hi) = (0.0, 0.0, 0.0);
            // SAFETY: a live library handle and valid outputs.
            let statuses = unsafe {
                [
                    capi::bssrdf_library_reflectance_range(library, 0, theta, &mut lo, &mut hi),
                    capi::bssrdf_library_invert_albedo(library, 0, a, theta, &mut rho),
                ]
            };
            assert_eq!(statuses, [0, 0]);
            sink += rho + hi;
        }
    });
    // SAFETY: the handle from above, closed once.
    unsafe { capi::bssrdf_library_close(library) };
    assert!(sink.is_finite() && sink > 0.0);
    assert_eq!(n, 0, "{n} allocations in 3000 rounds of inversions");
}

/// Lookups with the medium given per call and batches (the separable renderers' and the
/// path-tracing draws' among them), from Rust and through C: none
/// allocates, not even a failing one, whose message names the value (C formats it into a
/// fixed buffer).
#[test]
#[allow(unsafe_code)]
fn per_call_and_batch_lookups_never_allocate_even_when_they_fail() {
    const N: usize = 64;
    let dir = tempfile::tempdir().unwrap();
    let (rust, library) = skin1(dir.path());
    let view = rust.view(0).unwrap();
    let mut rng = SplitMix64::seed_from_u64(5);
    // Per-point media: ρ′ up to 1.1 (a tenth outside the table), σ′t down to 0 (vacuum), θ
    // beyond 90°
    let mut column = |scale: f64| -> [f64; N] { std::array::from_fn(|_| scale * rng.next_f64()) };
    let (rho, sigma_t, theta) = (column(1.1), column(3.0), column(1.7));
    let (r, phi, u_r, u_phi) = (column(3.0), column(3.0), column(1.0), column(1.0));
    let (mut out, mut draw_r, mut draw_phi, mut draw_pdf) =
        ([0.0; N], [0.0; N], [0.0; N], [0.0; N]);
    // The Rust and C batches over the points, and a C batch refused (a NULL array)
    let batches = |library, out: &mut [f64; N], [dr, dphi, dpdf]: [&mut [f64; N]; 3]| {
        view.eval_n(&rho, &sigma_t, &theta, &r, &phi, out).unwrap();
        view.pdf_n(&rho, &sigma_t, &theta, &r, &phi, out).unwrap();
        let draws = SamplesMut {
            r: dr,
            phi: dphi,
            pdf: dpdf,
        };
        view.sample_n(&rho, &sigma_t, &theta, &u_r, &u_phi, draws)
            .unwrap();
        // The separable and path batches write into the same arrays
        view.pdf_radius_n(&rho, &sigma_t, &theta, &r, out).unwrap();
        view.angular_factor_n(&rho, &sigma_t, &theta, &r, &phi, out)
            .unwrap();
        let radial = RadialSamplesMut {
            r: &mut *dr,
            pdf: &mut *dpdf,
        };
        view.sample_radius_n(&rho, &sigma_t, &theta, &u_r, radial)
            .unwrap();
        let mut path = [[0.0; N]; 6];
        let paths = PathSamplesMut::from(path.each_mut().map(|p| &mut p[..]));
        view.sample_path_n(&rho, &sigma_t, [&u_r, &u_phi, &r, &phi], paths)
            .unwrap();
        let pp = path.each_mut().map(|p| p.as_mut_ptr());
        let [rho, sigma_t, theta, r, phi, u_r, u_phi] =
            [&rho, &sigma_t, &theta, &r, &phi, &u_r, &u_phi].map(|a| a.as_ptr());
        let out = out.as_mut_ptr();
        let (dr, dphi, dpdf) = (dr.as_mut_ptr(), dphi.as_mut_ptr(), dpdf.as_mut_ptr());
        // SAFETY: a live library handle, arrays of N doubles (or NULL, refused), outputs apart
        // from the inputs.
        let statuses = unsafe {
            let [eval_n, pdf_n] = [capi::bssrdf_table_eval_n, capi::bssrdf_table_pdf_n]
                .map(|f| f(library, 0, N, rho, sigma_t, theta, r, phi, out));
            let null = std::ptr::null();
            [
                eval_n,
                pdf_n,
                capi::bssrdf_table_sample_n(
                    library, 0, N, rho, sigma_t, theta, u_r, u_phi, dr, dphi, dpdf,
                ),
                capi::bssrdf_table_eval_n(library, 0, N, rho, null, theta, r, phi, out),
                capi::bssrdf_table_sample_radius_n(
                    library, 0, N, rho, sigma_t, theta, u_r, dr, dpdf,
                ),
                capi::bssrdf_table_pdf_radius_n(library, 0, N, rho, sigma_t, theta, r, out),
                capi::bssrdf_table_angular_factor_n(
                    library, 0, N, rho, sigma_t, theta, r, phi, out,
                ),
                capi::bssrdf_table_sample_path_n(
                    library, 0, N, rho, sigma_t, u_r, u_phi, r, phi, pp[0], pp[1], pp[2], pp[3],
                    pp[4], pp[5],
                ),
                capi::bssrdf_table_sample_path_n(
                    library, 0, N, rho, sigma_t, u_r, u_phi, r, phi, pp[0], pp[0], pp[2], pp[3],
                    pp[4], pp[5],
                ),
            ]
        };
        let refused = [capi::BSSRDF_ERROR_NULL_POINTER, 0, 0, 0, 0];
        assert_eq!(statuses[3..8], refused);
        assert_eq!(statuses[..3], [0, 0, 0]);
        assert_eq!(statuses[8], capi::BSSRDF_ERROR_INVALID_ARGUMENT);
    };
    let mut failures = 0;
    let mut sink = 0.0;
    let n = allocations(|| {
        for round in 0..3000 {
            let k = round % N;
            let (rho, sigma_t, theta) = (rho[k], sigma_t[k], theta[k]);
            let u = [u_r[k], u_phi[k], u_r[N - 1 - k], u_phi[N - 1 - k]];
            match view.medium(rho, sigma_t) {
                Ok(m) => {
                    sink += m.eval(theta, r[k], phi[k]).unwrap_or(0.0) + m.pdf(theta, r[k], phi[k]);
                    sink += m.sample(theta, u[0], u[1]).map_or(0.0, |s| s.r);
                    sink += m.sample_path(u).map_or(0.0, |s| s.pdf) + m.pdf_theta(theta);
                    sink += m.effective_albedo(theta).unwrap_or(0.0);
                    // The separable renderers' lookups
                    sink += m.sample_radius(theta, u[0]).map_or(0.0, |s| s.pdf);
                    sink += m.pdf_radius(theta, r[k]);
                    sink += m.angular_factor(theta, r[k], phi[k]).unwrap_or(0.0);
                    sink += m.diffuse_reflectance(theta).unwrap_or(0.0);
                }
                Err(e) => sink += f64::from(u8::from(matches!(e, bssrdf_zoo::Error::Vacuum))),
            }
            let mut value = 0.0;
            let mut sample = capi::bssrdf_sample::default();
            let mut path = capi::bssrdf_path_sample::default();
            let mut radial = capi::bssrdf_radial_sample::default();
            // SAFETY: a live library handle and valid outputs (one NULL, refused).
            let statuses = unsafe {
                [
                    capi::bssrdf_table_eval(
                        library, 0, rho, sigma_t, theta, r[k], phi[k], &mut value,
                    ),
                    capi::bssrdf_table_pdf(
                        library, 0, rho, sigma_t, theta, r[k], phi[k], &mut value,
                    ),
                    capi::bssrdf_table_sample(
                        library,
                        0,
                        rho,
                        sigma_t,
                        theta,
                        u[0],
                        u[1],
                        &mut sample,
                    ),
                    capi::bssrdf_table_sample_path(library, 0, rho, sigma_t, u.as_ptr(), &mut path),
                    capi::bssrdf_table_pdf_theta(library, 0, rho, sigma_t, theta, &mut value),
                    capi::bssrdf_table_effective_albedo(
                        library, 0, rho, sigma_t, theta, &mut value,
                    ),
                    capi::bssrdf_table_sample_radius(
                        library,
                        0,
                        rho,
                        sigma_t,
                        theta,
                        u[0],
                        &mut radial,
                    ),
                    capi::bssrdf_table_pdf_radius(
                        library, 0, rho, sigma_t, theta, r[k], &mut value,
                    ),
                    capi::bssrdf_table_angular_factor(
                        library, 0, rho, sigma_t, theta, r[k], phi[k], &mut value,
                    ),
                    capi::bssrdf_table_diffuse_reflectance(
                        library, 0, rho, sigma_t, theta, &mut value,
                    ),
                    capi::bssrdf_table_eval(
                        library, 3, rho, sigma_t, theta, r[k], phi[k], &mut value,
                    ),
                    capi::bssrdf_table_eval(
                        library,
                        0,
                        rho,
                        sigma_t,
                        theta,
                        r[k],
                        phi[k],
                        std::ptr::null_mut(),
                    ),
                ]
            };
            failures += statuses.iter().filter(|&&s| s != 0).count();
            std::hint::black_box((value, sample, path, radial));
            if k == 0 {
                batches(
                    library,
                    &mut out,
                    [&mut draw_r, &mut draw_phi, &mut draw_pdf],
                );
            }
        }
    });
    std::hint::black_box(sink);
    // SAFETY: opened above, closed once.
    unsafe { capi::bssrdf_library_close(library) };
    assert!(
        failures > 3000,
        "the failure paths ran ({failures} failures)"
    );
    assert_eq!(
        n, 0,
        "{n} allocations in 3000 rounds of per-call and batch lookups"
    );
}
