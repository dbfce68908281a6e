//! Lookups with the medium given per call and batches, from Rust (`TableRef::medium`,
//! `TableRef::eval_n` …) and through the C interface (`bssrdf_table_*`): every per-call lookup
//! gives the channel handle's status and bits for the same medium, every point of a batch the
//! single call's bits (0 and the failed draw where the single call fails), and every misuse
//! its own status and a message naming the value. The same rules at arbitrary inputs are held
//! by `bssrdf_testkit::lookups::check_capi` (`arbitrary_inputs.rs`).
#![allow(unsafe_code)]

use std::ffi::{c_int, CStr, CString};
use std::ptr::{null, null_mut};

use bssrdf::*;
use bssrdf_testkit::lookups::{check_capi, Columns, Inputs, UNTOUCHED_PATH, UNTOUCHED_SAMPLE};
use bssrdf_zoo::embed::Library;
use bssrdf_zoo::rng::{RngCore, SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::{Grid, PathSamplesMut, RadialSamplesMut, SamplesMut, TableRef};

/// Random points per medium in the comparisons (Miri runs them a thousandfold slower).
const ROUNDS: usize = if cfg!(miri) { 3 } else { 400 };

/// skin1 (η 1.3, table 0) and coke (η 1.33, table 1), mapped by Rust and by C.
fn open(dir: &std::path::Path, flags: u32) -> (Library, *mut bssrdf_library) {
    let path = crate::fixture::scene(dir, &Grid::ferrier(10, 5, 14));
    let c_path = CString::new(path.to_str().unwrap()).unwrap();
    let mut c = null_mut();
    // SAFETY: a valid string and output.
    let status = unsafe { bssrdf_library_open(c_path.as_ptr(), flags, &mut c) };
    assert_eq!(status, BSSRDF_OK);
    (Library::open_mmap(&path).unwrap(), c)
}

fn last_error() -> String {
    // SAFETY: never NULL, NUL-terminated, valid until the next failing call on this thread.
    unsafe { CStr::from_ptr(bssrdf_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

/// Asserts a failure's status and that its message contains each needle.
#[track_caller]
fn fails(status: c_int, code: c_int, needles: &[&str]) {
    assert_eq!(status, code, "{}", last_error());
    for needle in needles {
        assert!(
            last_error().contains(needle),
            "{:?} lacks {needle:?}",
            last_error()
        );
    }
}

/// A medium and a point, mostly inside the domain: ρ′ over the table's rows, now and then just
/// outside them or NaN; σ′t over four decades, now and then 0 or huge; θ a little beyond 90°.
fn point(rng: &mut SplitMix64) -> Inputs {
    let rho = match rng.next_u64() % 20 {
        0 => 1.0 + 1e-9,
        1 => f64::NAN,
        2 => 0.0,
        _ => rng.next_f64(),
    };
    let sigma_t = match rng.next_u64() % 20 {
        0 => 0.0,
        1 => 1e300,
        _ => 10f64.powf(4.0 * rng.next_f64() - 2.0),
    };
    Inputs {
        rho,
        theta: 1.05 * std::f64::consts::FRAC_PI_2 * rng.next_f64(),
        r: 4.0 / sigma_t * rng.next_f64(),
        phi: 7.0 * rng.next_f64() - 3.5,
        u: [0; 4].map(|_| rng.next_f64()),
        sigma_t,
    }
}

#[test]
fn per_call_lookups_equal_the_channel_handles_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    for flags in [BSSRDF_OPEN_MAP, BSSRDF_OPEN_READ] {
        let (rust, c) = open(dir.path(), flags);
        let mut rng = SplitMix64::seed_from_u64(77);
        for table in rust.tables() {
            let view = rust.view(table.index()).unwrap();
            for _ in 0..ROUNDS {
                let x = point(&mut rng);
                let handle = table.medium(x.rho, x.sigma_t).ok();
                let medium = view.medium(x.rho, x.sigma_t);
                assert_eq!(handle.is_some(), medium.is_ok(), "{x:?}");
                if let (Some(h), Ok(m)) = (&handle, medium) {
                    let (theta, r, phi, u) = (x.theta, x.r, x.phi, x.u);
                    let bits = |v: Option<f64>| v.map(f64::to_bits);
                    assert_eq!(bits(m.eval(theta, r, phi)), bits(h.eval(theta, r, phi)));
                    assert_eq!(
                        m.pdf(theta, r, phi).to_bits(),
                        h.pdf(theta, r, phi).to_bits()
                    );
                    assert_eq!(m.sample(theta, u[0], u[1]), h.sample(theta, u[0], u[1]));
                    assert_eq!(m.sample_path(u), h.sample_path(u));
                    assert_eq!(m.pdf_theta(theta).to_bits(), h.pdf_theta(theta).to_bits());
                    assert_eq!(
                        bits(m.effective_albedo(theta)),
                        bits(h.effective_albedo(theta))
                    );
                    assert_eq!((m.rho_prime(), m.sigma_t_prime()), (x.rho, x.sigma_t));
                }
                // SAFETY: the open C handle of the same file.
                unsafe { check_capi(c, table.index(), handle.as_ref(), &x) };
            }
        }
        // SAFETY: closed once.
        unsafe { bssrdf_library_close(c) };
    }
}

/// A batch of `n` points of [`point`], some outside the domain.
fn batch(n: usize, rng: &mut SplitMix64) -> Columns {
    (0..n).map(|_| point(rng)).collect()
}

/// Each point of the Rust batches of `view`, and of the C batches on table `table` of `c`,
/// against the single calls.
fn check_batches(view: &TableRef, c: *const bssrdf_library, table: usize, b: &Columns) {
    let n = b.rho.len();
    let mut value = vec![-7.0; n];
    let mut pdf = vec![-7.0; n];
    let (mut r, mut phi, mut s_pdf) = (vec![-7.0; n], vec![-7.0; n], vec![-7.0; n]);
    let media = (&b.rho[..], &b.sigma_t[..]);
    let check = |value: &[f64], pdf: &[f64], draws: [&[f64]; 3]| {
        for i in 0..n {
            let m = view.medium(b.rho[i], b.sigma_t[i]).ok();
            let (theta, r_mm, phi) = (b.theta[i], b.r[i], b.phi[i]);
            let eval = m.and_then(|m| m.eval(theta, r_mm, phi)).unwrap_or(0.0);
            assert_eq!(value[i].to_bits(), eval.to_bits(), "eval of point {i}");
            let density = m.map_or(0.0, |m| m.pdf(theta, r_mm, phi));
            assert_eq!(pdf[i].to_bits(), density.to_bits(), "pdf of point {i}");
            let draw = m
                .and_then(|m| m.sample(theta, b.u_r[i], b.u_phi[i]))
                .map_or([0.0; 3], |s| [s.r, s.phi, s.pdf]);
            let got = [draws[0][i], draws[1][i], draws[2][i]];
            assert_eq!(got.map(f64::to_bits), draw.map(f64::to_bits), "draw {i}");
        }
    };
    view.eval_n(media.0, media.1, &b.theta, &b.r, &b.phi, &mut value)
        .unwrap();
    view.pdf_n(media.0, media.1, &b.theta, &b.r, &b.phi, &mut pdf)
        .unwrap();
    let out = SamplesMut {
        r: &mut r,
        phi: &mut phi,
        pdf: &mut s_pdf,
    };
    view.sample_n(media.0, media.1, &b.theta, &b.u_r, &b.u_phi, out)
        .unwrap();
    check(&value, &pdf, [&r, &phi, &s_pdf]);
    for v in [&mut value, &mut pdf, &mut r, &mut phi, &mut s_pdf] {
        v.fill(-7.0);
    }
    let [rho, sigma_t, theta, r_mm, phi_in, u_r, u_phi] =
        [&b.rho, &b.sigma_t, &b.theta, &b.r, &b.phi, &b.u_r, &b.u_phi].map(|v| v.as_ptr());
    // SAFETY: a live library handle; every array holds n doubles, the outputs writable and
    // apart from the inputs.
    unsafe {
        for (batch, out) in [
            (bssrdf_table_eval_n as BatchFn, value.as_mut_ptr()),
            (bssrdf_table_pdf_n, pdf.as_mut_ptr()),
        ] {
            let status = batch(c, table, n, rho, sigma_t, theta, r_mm, phi_in, out);
            assert_eq!(status, BSSRDF_OK);
        }
        let (r, phi, s_pdf) = (r.as_mut_ptr(), phi.as_mut_ptr(), s_pdf.as_mut_ptr());
        let status =
            bssrdf_table_sample_n(c, table, n, rho, sigma_t, theta, u_r, u_phi, r, phi, s_pdf);
        assert_eq!(status, BSSRDF_OK);
    }
    check(&value, &pdf, [&r, &phi, &s_pdf]);
    check_separable_and_path_batches(view, c, table, b);
}

/// The separable renderers' batches (`sample_radius_n`, `pdf_radius_n`, `angular_factor_n`)
/// and the path-tracing draws (`sample_path_n`), Rust and C, against the single calls: each
/// point the single call's bits, 0 (every field of a draw) where it fails.
fn check_separable_and_path_batches(
    view: &TableRef,
    c: *const bssrdf_library,
    table: usize,
    b: &Columns,
) {
    let n = b.rho.len();
    let media = (&b.rho[..], &b.sigma_t[..]);
    let u = [&b.u_r[..], &b.u_phi[..], &b.u2[..], &b.u3[..]];
    // Outputs: radial r, radial pdf, pdf_radius, angular factor, then the six path fields
    let mut out = vec![vec![-7.0; n]; 10];
    let check = |out: &[Vec<f64>]| {
        for (i, &rho) in b.rho.iter().enumerate() {
            let m = view.medium(rho, b.sigma_t[i]).ok();
            let (theta, r_mm, phi) = (b.theta[i], b.r[i], b.phi[i]);
            let radial = m.and_then(|m| m.sample_radius(theta, b.u_r[i]));
            let ui = [b.u_r[i], b.u_phi[i], b.u2[i], b.u3[i]];
            let path = m.and_then(|m| m.sample_path(ui));
            let want = [
                radial.map_or(0.0, |d| d.r),
                radial.map_or(0.0, |d| d.pdf),
                m.map_or(0.0, |m| m.pdf_radius(theta, r_mm)),
                m.and_then(|m| m.angular_factor(theta, r_mm, phi))
                    .unwrap_or(0.0),
            ]
            .into_iter()
            .chain(path.map_or([0.0; 6], |p| {
                [p.theta, p.r, p.phi, p.phi_prime, p.pdf_theta, p.pdf]
            }));
            for (k, want) in want.enumerate() {
                assert_eq!(
                    out[k][i].to_bits(),
                    want.to_bits(),
                    "output {k} of point {i}"
                );
            }
        }
    };
    {
        let [d_r, d_pdf, pdf_r, factor, path @ ..] = &mut out[..] else {
            unreachable!()
        };
        let draws = RadialSamplesMut { r: d_r, pdf: d_pdf };
        view.sample_radius_n(media.0, media.1, &b.theta, &b.u_r, draws)
            .unwrap();
        view.pdf_radius_n(media.0, media.1, &b.theta, &b.r, pdf_r)
            .unwrap();
        view.angular_factor_n(media.0, media.1, &b.theta, &b.r, &b.phi, factor)
            .unwrap();
        let path: &mut [Vec<f64>; 6] = path.try_into().unwrap();
        let paths = PathSamplesMut::from(path.each_mut().map(|v| &mut v[..]));
        view.sample_path_n(media.0, media.1, u, paths).unwrap();
    }
    check(&out);
    out.iter_mut().for_each(|v| v.fill(-7.0));
    let [rho, sigma_t, theta, r_mm, phi, u0, u1, u2, u3] = [
        &b.rho, &b.sigma_t, &b.theta, &b.r, &b.phi, &b.u_r, &b.u_phi, &b.u2, &b.u3,
    ]
    .map(|v| v.as_ptr());
    let o: Vec<*mut f64> = out.iter_mut().map(|v| v.as_mut_ptr()).collect();
    // SAFETY: a live library handle; every array holds n doubles, the outputs writable and
    // apart from each other and the inputs.
    let statuses = unsafe {
        [
            bssrdf_table_sample_radius_n(c, table, n, rho, sigma_t, theta, u0, o[0], o[1]),
            bssrdf_table_pdf_radius_n(c, table, n, rho, sigma_t, theta, r_mm, o[2]),
            bssrdf_table_angular_factor_n(c, table, n, rho, sigma_t, theta, r_mm, phi, o[3]),
            bssrdf_table_sample_path_n(
                c, table, n, rho, sigma_t, u0, u1, u2, u3, o[4], o[5], o[6], o[7], o[8], o[9],
            ),
        ]
    };
    assert_eq!(statuses, [BSSRDF_OK; 4]);
    check(&out);
}

/// `bssrdf_table_eval_n` and `bssrdf_table_pdf_n`.
type BatchFn = unsafe extern "C" fn(
    *const bssrdf_library,
    usize,
    usize,
    *const f64,
    *const f64,
    *const f64,
    *const f64,
    *const f64,
    *mut f64,
) -> c_int;

#[test]
fn every_point_of_a_batch_is_the_single_call_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let (rust, c) = open(dir.path(), BSSRDF_OPEN_MAP);
    let mut rng = SplitMix64::seed_from_u64(78);
    for table in 0..rust.table_count() {
        let view = rust.view(table).unwrap();
        // Lengths around the batch code's groups of points, and a long batch
        for n in [0, 1, 2, 3, 4, 5, 7, 8, 9, 63, 64, 65, 2 * ROUNDS] {
            check_batches(&view, c, table, &batch(n, &mut rng));
        }
    }
    // SAFETY: closed once.
    unsafe { bssrdf_library_close(c) };
}

/// A negative distance, even one whose product with σ′t underflows to −0, is refused by the
/// single call and gives 0 in every batch (it gave the value at r = 0), as in Rust.
#[test]
fn a_negative_distance_is_refused_by_the_single_call_and_0_in_a_batch() {
    let dir = tempfile::tempdir().unwrap();
    let (rust, c) = open(dir.path(), BSSRDF_OPEN_MAP);
    let view = rust.view(0).unwrap();
    let m = view.medium(0.5, 0.5).unwrap();
    for r in [-5e-324, -1e-300, -1.0] {
        let (rho, sigma_t, theta, r_mm, phi) = ([0.5], [0.5], [0.3], [r], [0.0]);
        let [rho, sigma_t, theta, r_mm, phi] =
            [&rho, &sigma_t, &theta, &r_mm, &phi].map(|v| v.as_ptr());
        // SAFETY: a live library handle; one-point arrays and a writable output.
        unsafe {
            let mut value = -7.0;
            fails(
                bssrdf_table_eval(c, 0, 0.5, 0.5, 0.3, r, 0.0, &mut value),
                BSSRDF_ERROR_OUT_OF_RANGE,
                &["mm is outside [0, inf): a distance"],
            );
            for batch in [
                bssrdf_table_eval_n as BatchFn,
                bssrdf_table_pdf_n,
                bssrdf_table_angular_factor_n,
            ] {
                let mut out = [-7.0];
                let status = batch(c, 0, 1, rho, sigma_t, theta, r_mm, phi, out.as_mut_ptr());
                assert_eq!((status, out[0]), (BSSRDF_OK, 0.0), "r = {r}");
            }
            let mut out = [-7.0];
            let status =
                bssrdf_table_pdf_radius_n(c, 0, 1, rho, sigma_t, theta, r_mm, out.as_mut_ptr());
            assert_eq!((status, out[0]), (BSSRDF_OK, 0.0), "r = {r}");
        }
        assert_eq!(m.eval(0.3, r, 0.0).unwrap_or(0.0), 0.0, "r = {r}");
        assert_eq!(m.pdf(0.3, r, 0.0), 0.0, "r = {r}");
    }
    // SAFETY: closed once.
    unsafe { bssrdf_library_close(c) };
}

#[test]
fn a_batch_with_arrays_of_other_lengths_is_an_error_naming_the_array() {
    let dir = tempfile::tempdir().unwrap();
    let (rust, c) = open(dir.path(), BSSRDF_OPEN_MAP);
    // SAFETY: closed once; the Rust library is another handle.
    unsafe { bssrdf_library_close(c) };
    let view = rust.view(0).unwrap();
    let (two, three) = ([0.5; 2], [0.5; 3]);
    let mut out = [-7.0; 2];
    let err = view
        .eval_n(&two, &two, &three, &two, &two, &mut out)
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "theta holds 3 values; the batch has 2 points (the output's length)"
    );
    let err = view.pdf_n(&two, &two, &two, &two, &three, &mut out);
    assert!(err.unwrap_err().to_string().starts_with("phi holds 3"));
    let (mut r, mut phi, mut pdf) = ([-7.0; 2], [-7.0; 3], [-7.0; 2]);
    let out_draws = SamplesMut {
        r: &mut r,
        phi: &mut phi,
        pdf: &mut pdf,
    };
    let err = view.sample_n(&two, &two, &two, &two, &two, out_draws);
    assert!(err.unwrap_err().to_string().starts_with("phi holds 3"));
    assert_eq!(
        (out, r, pdf),
        ([-7.0; 2], [-7.0; 2], [-7.0; 2]),
        "nothing written"
    );
    let err = view.pdf_radius_n(&two, &two, &three, &two, &mut out);
    assert!(err.unwrap_err().to_string().starts_with("theta holds 3"));
    let err = view.angular_factor_n(&two, &two, &two, &two, &three, &mut out);
    assert!(err.unwrap_err().to_string().starts_with("phi holds 3"));
    let (mut radial_r, mut radial_pdf) = ([-7.0; 3], [-7.0; 2]);
    let draws = RadialSamplesMut {
        r: &mut radial_r,
        pdf: &mut radial_pdf,
    };
    let err = view.sample_radius_n(&two, &two, &two, &two, draws);
    assert!(err.unwrap_err().to_string().starts_with("r holds 3"));
    let mut fields = [[-7.0; 2]; 6];
    let paths = PathSamplesMut::from(fields.each_mut().map(|f| &mut f[..]));
    let err = view.sample_path_n(&two, &two, [&two, &two, &two, &three], paths);
    assert_eq!(
        err.unwrap_err().to_string(),
        "u3 holds 3 values; the batch has 2 points (the output's length)"
    );
    assert_eq!(
        (out, radial_pdf, fields),
        ([-7.0; 2], [-7.0; 2], [[-7.0; 2]; 6])
    );
}

#[test]
fn per_call_failures_name_the_value_and_leave_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let (_, c) = open(dir.path(), BSSRDF_OPEN_MAP);
    let mut value = -7.0;
    let mut sample = UNTOUCHED_SAMPLE;
    let u = [0.5; 4];
    // SAFETY: a live library handle (or NULL where the test says so) and valid outputs.
    unsafe {
        let out = &mut value as *mut f64;
        fails(
            bssrdf_table_eval(c, 0, 1.5, 2.0, 0.3, 0.5, 0.0, out),
            BSSRDF_ERROR_OUT_OF_RANGE,
            &["medium on table 0", "rho' = 1.5 is outside [0, 1]"],
        );
        fails(
            bssrdf_table_pdf(c, 1, f64::NAN, 2.0, 0.3, 0.5, 0.0, out),
            BSSRDF_ERROR_OUT_OF_RANGE,
            &["medium on table 1", "rho' = NaN"],
        );
        fails(
            bssrdf_table_pdf_theta(c, 0, 0.5, 0.0, 0.3, out),
            BSSRDF_ERROR_INVALID_ARGUMENT,
            &["vacuum"],
        );
        fails(
            bssrdf_table_effective_albedo(c, 0, 0.5, 1e300, 0.3, out),
            BSSRDF_ERROR_INVALID_ARGUMENT,
            &["sigma_t' = 1e300 is outside [1e-9, 1e12]"],
        );
        fails(
            bssrdf_table_effective_albedo(c, 0, 0.5, -2.0, 0.3, out),
            BSSRDF_ERROR_INVALID_ARGUMENT,
            &["sigma_t' = -2"],
        );
        fails(
            bssrdf_table_sample(c, 2, 0.5, 2.0, 0.3, 0.5, 0.5, &mut sample),
            BSSRDF_ERROR_NOT_FOUND,
            &["no table 2: the library holds 2 table(s)"],
        );
        fails(
            bssrdf_table_eval(c, 0, 0.5, 2.0, 1.7, 0.5, 0.0, out),
            BSSRDF_ERROR_OUT_OF_RANGE,
            &["theta = 1.7 rad is outside the table's theta axis [0, 1.5707964"],
        );
        fails(
            bssrdf_table_effective_albedo(c, 0, 0.5, 2.0, f64::NAN, out),
            BSSRDF_ERROR_OUT_OF_RANGE,
            &["theta = NaN rad is outside the table's theta axis [0, 1.5707964"],
        );
        // coke's blue channel: ρ′ = 0 scatters nothing
        fails(
            bssrdf_table_sample(c, 1, 0.0, 2.0, 0.3, 0.5, 0.5, &mut sample),
            BSSRDF_ERROR_NO_SAMPLE,
            &["no sample: the table stores no energy for rho' = 0 at theta = 0.3 rad"],
        );
        let mut path = UNTOUCHED_PATH;
        fails(
            bssrdf_table_sample_path(c, 1, 0.0, 2.0, u.as_ptr(), &mut path),
            BSSRDF_ERROR_NO_SAMPLE,
            &["no sample"],
        );
        assert_eq!(path, UNTOUCHED_PATH);
        let null_pointer = BSSRDF_ERROR_NULL_POINTER;
        fails(
            bssrdf_table_eval(null(), 0, 0.5, 2.0, 0.3, 0.5, 0.0, out),
            null_pointer,
            &["library is NULL"],
        );
        fails(
            bssrdf_table_eval(c, 0, 0.5, 2.0, 0.3, 0.5, 0.0, null_mut()),
            null_pointer,
            &["out_value is NULL"],
        );
        fails(
            bssrdf_table_pdf(c, 0, 0.5, 2.0, 0.3, 0.5, 0.0, null_mut()),
            null_pointer,
            &["out_pdf is NULL"],
        );
        fails(
            bssrdf_table_sample(c, 0, 0.5, 2.0, 0.3, 0.5, 0.5, null_mut()),
            null_pointer,
            &["out_sample is NULL"],
        );
        fails(
            bssrdf_table_sample_path(c, 0, 0.5, 2.0, null(), &mut path),
            null_pointer,
            &["u is NULL"],
        );
        fails(
            bssrdf_table_sample_path(c, 0, 0.5, 2.0, u.as_ptr(), null_mut()),
            null_pointer,
            &["out_sample is NULL"],
        );
        fails(
            bssrdf_table_pdf_theta(null(), 0, 0.5, 2.0, 0.3, out),
            null_pointer,
            &["library is NULL"],
        );
        fails(
            bssrdf_table_effective_albedo(c, 0, 0.5, 2.0, 0.3, null_mut()),
            null_pointer,
            &["out_albedo is NULL"],
        );
        fails(
            bssrdf_table_diffuse_reflectance(c, 0, 1.5, 2.0, 0.3, out),
            BSSRDF_ERROR_OUT_OF_RANGE,
            &["medium on table 0", "rho' = 1.5 is outside [0, 1]"],
        );
        fails(
            bssrdf_table_diffuse_reflectance(c, 0, 0.5, 2.0, 1.7, out),
            BSSRDF_ERROR_OUT_OF_RANGE,
            &["theta = 1.7 rad is outside the table's theta axis [0, 1.5707964"],
        );
        fails(
            bssrdf_table_diffuse_reflectance(c, 0, 0.5, 2.0, 0.3, null_mut()),
            null_pointer,
            &["out_reflectance is NULL"],
        );
        // The channel handles' separable lookups and reflectance
        let mut radial = bssrdf_radial_sample { r: -7.0, pdf: -7.0 };
        fails(
            bssrdf_channel_sample_radius(null(), 0.3, 0.5, &mut radial),
            null_pointer,
            &["channel is NULL"],
        );
        let mut channel = null_mut();
        assert_eq!(
            bssrdf_library_medium(c, 1, 0.0, 2.0, &mut channel),
            BSSRDF_OK
        );
        fails(
            bssrdf_channel_sample_radius(channel, 0.3, 0.5, &mut radial),
            BSSRDF_ERROR_NO_SAMPLE,
            &["no sample: the table stores no energy for rho' = 0"],
        );
        fails(
            bssrdf_channel_pdf_radius(channel, 0.3, 0.5, null_mut()),
            null_pointer,
            &["out_pdf is NULL"],
        );
        fails(
            bssrdf_channel_angular_factor(channel, 1.7, 0.5, 0.0, out),
            BSSRDF_ERROR_OUT_OF_RANGE,
            &["theta = 1.7 rad is outside the table's theta axis [0, 1.5707964"],
        );
        fails(
            bssrdf_channel_diffuse_reflectance(channel, f64::NAN, out),
            BSSRDF_ERROR_OUT_OF_RANGE,
            &["theta = NaN rad is outside the table's theta axis [0, 1.5707964"],
        );
        bssrdf_channel_release(channel);
        assert_eq!((radial.r, radial.pdf), (-7.0, -7.0));
        bssrdf_library_close(c);
    }
    assert_eq!(value, -7.0, "outputs untouched on failure");
    assert_eq!(sample, UNTOUCHED_SAMPLE);
}

#[test]
fn a_batch_refuses_null_misaligned_and_overlapping_arrays_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let (_, c) = open(dir.path(), BSSRDF_OPEN_MAP);
    let n = 4;
    let inputs = vec![0.5; n];
    let mut outputs = vec![-7.0; 3 * n + 1];
    let x = inputs.as_ptr();
    let (a, b, d) = {
        let p = outputs.as_mut_ptr();
        // SAFETY: inside `outputs` (3n + 1 doubles)
        unsafe { (p, p.add(n), p.add(2 * n)) }
    };
    // SAFETY: a live library handle (or NULL where the test says so); arrays of n doubles or
    // NULL; the misaligned pointer is refused before it is read.
    unsafe {
        fails(
            bssrdf_table_eval_n(null(), 0, n, x, x, x, x, x, a),
            BSSRDF_ERROR_NULL_POINTER,
            &["library is NULL"],
        );
        fails(
            bssrdf_table_eval_n(c, 0, 0, x, x, null(), x, x, a),
            BSSRDF_ERROR_NULL_POINTER,
            &["theta is NULL"],
        );
        fails(
            bssrdf_table_pdf_n(c, 0, n, x, x, x, x, x, null_mut()),
            BSSRDF_ERROR_NULL_POINTER,
            &["out_pdf is NULL"],
        );
        fails(
            bssrdf_table_sample_n(c, 0, n, x, x, x, x, x, a, null_mut(), d),
            BSSRDF_ERROR_NULL_POINTER,
            &["out_phi is NULL"],
        );
        fails(
            bssrdf_table_sample_n(c, 0, n, x, null(), x, x, x, a, b, d),
            BSSRDF_ERROR_NULL_POINTER,
            &["sigma_t_prime is NULL"],
        );
        let misaligned = x.cast::<u8>().add(1).cast::<f64>();
        fails(
            bssrdf_table_eval_n(c, 0, n, x, x, x, misaligned, x, a),
            BSSRDF_ERROR_INVALID_ARGUMENT,
            &["r_mm is not aligned"],
        );
        fails(
            bssrdf_table_eval_n(c, 0, n, x, x, x, x, a, a),
            BSSRDF_ERROR_INVALID_ARGUMENT,
            &["out_value overlaps phi"],
        );
        // out_r's last double is out_phi's first
        let overlapping = a.add(1);
        fails(
            bssrdf_table_sample_n(c, 0, n, x, x, x, x, x, a, overlapping, d),
            BSSRDF_ERROR_INVALID_ARGUMENT,
            &["out_r overlaps out_phi"],
        );
        fails(
            bssrdf_table_pdf_n(c, 0, usize::MAX / 4, x, x, x, x, x, a),
            BSSRDF_ERROR_INVALID_ARGUMENT,
            &["more than memory can hold"],
        );
        fails(
            bssrdf_table_sample_n(c, 5, n, x, x, x, x, x, a, b, d),
            BSSRDF_ERROR_NOT_FOUND,
            &["no table 5"],
        );
        fails(
            bssrdf_table_sample_path_n(c, 0, n, x, x, x, x, x, null(), a, b, d, a, b, d),
            BSSRDF_ERROR_NULL_POINTER,
            &["u3 is NULL"],
        );
        fails(
            bssrdf_table_sample_path_n(c, 0, n, x, x, x, x, x, x, a, b, d, a, b, d),
            BSSRDF_ERROR_INVALID_ARGUMENT,
            &["out_theta overlaps out_phi_prime"],
        );
        fails(
            bssrdf_table_sample_radius_n(c, 0, n, x, x, x, x, a, overlapping),
            BSSRDF_ERROR_INVALID_ARGUMENT,
            &["out_r overlaps out_pdf"],
        );
        fails(
            bssrdf_table_pdf_radius_n(c, 0, n, x, x, x, misaligned, a),
            BSSRDF_ERROR_INVALID_ARGUMENT,
            &["r_mm is not aligned"],
        );
        fails(
            bssrdf_table_angular_factor_n(c, 0, n, x, x, x, x, x, null_mut()),
            BSSRDF_ERROR_NULL_POINTER,
            &["out_factor is NULL"],
        );
        fails(
            bssrdf_table_angular_factor_n(c, 2, n, x, x, x, x, x, a),
            BSSRDF_ERROR_NOT_FOUND,
            &["no table 2"],
        );
        // Inputs may share memory; n = 0 reads and writes nothing.
        assert_eq!(bssrdf_table_eval_n(c, 0, 0, x, x, x, x, x, a), BSSRDF_OK);
        assert!(outputs.iter().all(|&v| v == -7.0), "nothing written");
        assert_eq!(bssrdf_table_eval_n(c, 0, n, x, x, x, x, x, a), BSSRDF_OK);
        assert!(outputs[0] > 0.0, "{}", outputs[0]);
        bssrdf_library_close(c);
    }
}
