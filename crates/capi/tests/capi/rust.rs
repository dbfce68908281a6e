//! The C interface, called from Rust: every NULL pointer is an error naming the argument,
//! every failure has its documented code and a message, outputs are untouched on failure,
//! channels outlive their library, and every value equals the Rust API's bit for bit.
//! `crates/capi/tests/capi/c_program.rs` runs the same interface from a C program.
#![allow(unsafe_code)]

use std::ffi::{c_int, CStr, CString};
use std::ptr::{null, null_mut};

use bssrdf::*;
use bssrdf_zoo::embed::Library;
use bssrdf_zoo::materials::Rgb;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};
use bssrdf_zoo::table::Grid;

/// The grid of the tables here: small (under Miri no table is baked, see `fixture`).
fn grid() -> Grid {
    Grid::ferrier(10, 5, 14)
}

/// Random points per channel and open mode in the comparison with the Rust API (Miri runs
/// them a thousandfold slower).
pub(crate) const ROUNDS: usize = if cfg!(miri) { 3 } else { 300 };

/// skin1 (η 1.3) and coke (η 1.33; its blue channel has σs = 0, so ρ′ = 0) in a file.
pub(crate) fn baked(dir: &std::path::Path) -> CString {
    let path = crate::fixture::scene(dir, &grid());
    CString::new(path.to_str().unwrap()).unwrap()
}

pub(crate) fn last_error() -> String {
    // SAFETY: never NULL, NUL-terminated, valid until the next failing call on this thread.
    unsafe { CStr::from_ptr(bssrdf_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

/// Asserts a status and, for a failure, that the message contains `needle`.
#[track_caller]
pub(crate) fn expect(status: c_int, code: c_int, needle: &str) {
    // SAFETY: a static string.
    let name = unsafe { CStr::from_ptr(bssrdf_status_name(status)) };
    assert_eq!(status, code, "got {name:?}: {}", last_error());
    if code != BSSRDF_OK {
        assert!(
            last_error().contains(needle),
            "{:?} lacks {needle:?}",
            last_error()
        );
    }
}

pub(crate) fn open(path: &CStr, flags: u32) -> *mut bssrdf_library {
    let mut library = null_mut();
    // SAFETY: a valid string and output.
    expect(
        unsafe { bssrdf_library_open(path.as_ptr(), flags, &mut library) },
        BSSRDF_OK,
        "",
    );
    library
}

fn channel(library: *const bssrdf_library, name: &CStr, rgb: c_int) -> *mut bssrdf_channel {
    let mut channel = null_mut();
    // SAFETY: a live library, a valid string and output.
    let status = unsafe { bssrdf_library_channel(library, name.as_ptr(), rgb, &mut channel) };
    expect(status, BSSRDF_OK, "");
    channel
}

const NO_SAMPLE: bssrdf_sample = bssrdf_sample {
    r: -1.0,
    phi: -1.0,
    pdf: -1.0,
};
const NO_PATH: bssrdf_path_sample = bssrdf_path_sample {
    theta: -1.0,
    r: -1.0,
    phi: -1.0,
    phi_prime: -1.0,
    pdf_theta: -1.0,
    pdf: -1.0,
};

#[test]
fn every_null_pointer_is_an_error_naming_the_argument() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let library = open(&path, BSSRDF_OPEN_MAP);
    let ch = channel(library, c"skin1", 0);
    let (mut value, mut count, mut name) = (-1.0, 7usize, null());
    let (mut sample, mut path_sample) = (NO_SAMPLE, NO_PATH);
    let mut info = bssrdf_channel_info {
        rho_prime: -1.0,
        sigma_t_prime: -1.0,
        eta: -1.0,
        table: 9,
    };
    let (mut out_library, mut out_channel) = (std::ptr::dangling_mut(), std::ptr::dangling_mut());
    let u = [0.5; 4];
    let null_pointer = BSSRDF_ERROR_NULL_POINTER;
    // SAFETY: every pointer is NULL or valid.
    unsafe {
        expect(
            bssrdf_library_open(null(), 0, &mut out_library),
            null_pointer,
            "path",
        );
        assert!(out_library.is_null(), "handle outputs are NULL on failure");
        expect(
            bssrdf_library_open(path.as_ptr(), 0, null_mut()),
            null_pointer,
            "out_library",
        );
        expect(
            bssrdf_library_table_count(null(), &mut count),
            null_pointer,
            "library",
        );
        expect(
            bssrdf_library_table_count(library, null_mut()),
            null_pointer,
            "out_count",
        );
        expect(
            bssrdf_library_material_count(null(), &mut count),
            null_pointer,
            "library",
        );
        expect(
            bssrdf_library_material_count(library, null_mut()),
            null_pointer,
            "out_count",
        );
        expect(
            bssrdf_library_material_name(null(), 0, &mut name),
            null_pointer,
            "library",
        );
        expect(
            bssrdf_library_material_name(library, 0, null_mut()),
            null_pointer,
            "out_name",
        );
        let skin = c"skin1".as_ptr();
        expect(
            bssrdf_library_channel(null(), skin, 0, &mut out_channel),
            null_pointer,
            "library",
        );
        assert!(out_channel.is_null(), "handle outputs are NULL on failure");
        out_channel = std::ptr::dangling_mut();
        expect(
            bssrdf_library_channel(library, null(), 0, &mut out_channel),
            null_pointer,
            "material",
        );
        assert!(out_channel.is_null());
        expect(
            bssrdf_library_channel(library, skin, 0, null_mut()),
            null_pointer,
            "out_channel",
        );
        expect(
            bssrdf_library_medium(null(), 0, 0.5, 1.0, &mut out_channel),
            null_pointer,
            "library",
        );
        expect(
            bssrdf_library_medium(library, 0, 0.5, 1.0, null_mut()),
            null_pointer,
            "out_channel",
        );
        expect(
            bssrdf_channel_get_info(null(), &mut info),
            null_pointer,
            "channel",
        );
        expect(
            bssrdf_channel_get_info(ch, null_mut()),
            null_pointer,
            "out_info",
        );
        expect(
            bssrdf_channel_eval(null(), 0.1, 1.0, 0.0, &mut value),
            null_pointer,
            "channel",
        );
        expect(
            bssrdf_channel_eval(ch, 0.1, 1.0, 0.0, null_mut()),
            null_pointer,
            "out_value",
        );
        expect(
            bssrdf_channel_pdf(null(), 0.1, 1.0, 0.0, &mut value),
            null_pointer,
            "channel",
        );
        expect(
            bssrdf_channel_pdf(ch, 0.1, 1.0, 0.0, null_mut()),
            null_pointer,
            "out_pdf",
        );
        expect(
            bssrdf_channel_sample(null(), 0.1, 0.5, 0.5, &mut sample),
            null_pointer,
            "channel",
        );
        expect(
            bssrdf_channel_sample(ch, 0.1, 0.5, 0.5, null_mut()),
            null_pointer,
            "out_sample",
        );
        let u = u.as_ptr();
        expect(
            bssrdf_channel_sample_path(null(), u, &mut path_sample),
            null_pointer,
            "channel",
        );
        expect(
            bssrdf_channel_sample_path(ch, null(), &mut path_sample),
            null_pointer,
            "u is",
        );
        expect(
            bssrdf_channel_sample_path(ch, u, null_mut()),
            null_pointer,
            "out_sample",
        );
        expect(
            bssrdf_channel_pdf_theta(null(), 0.1, &mut value),
            null_pointer,
            "channel",
        );
        expect(
            bssrdf_channel_pdf_theta(ch, 0.1, null_mut()),
            null_pointer,
            "out_pdf",
        );
        expect(
            bssrdf_channel_effective_albedo(null(), 0.1, &mut value),
            null_pointer,
            "channel",
        );
        expect(
            bssrdf_channel_effective_albedo(ch, 0.1, null_mut()),
            null_pointer,
            "out_albedo",
        );
        bssrdf_channel_release(null_mut());
        bssrdf_library_close(null_mut());
        bssrdf_channel_release(ch);
        bssrdf_library_close(library);
    }
    assert_eq!(
        (value, count, name),
        (-1.0, 7, null()),
        "outputs untouched on failure"
    );
    assert_eq!((sample, path_sample), (NO_SAMPLE, NO_PATH));
    assert_eq!(info.table, 9);
}

#[test]
fn every_failure_has_its_code_and_a_message_naming_the_value() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let junk = dir.path().join("junk.bssrdf");
    std::fs::write(&junk, vec![9u8; 1024]).unwrap();
    let junk = CString::new(junk.to_str().unwrap()).unwrap();
    let library = open(&path, BSSRDF_OPEN_READ);
    let mut out_library = null_mut();
    let mut out_channel = null_mut();
    let (mut value, mut name) = (0.0, null());
    let mut sample = NO_SAMPLE;
    let mut path_sample = NO_PATH;
    // SAFETY: every pointer is valid; handles are released once, at the end.
    unsafe {
        let missing = c"/no/such/dir/scene.bssrdf";
        let status = bssrdf_library_open(missing.as_ptr(), 0, &mut out_library);
        expect(status, BSSRDF_ERROR_IO, "/no/such/dir/scene.bssrdf");
        let status = bssrdf_library_open(junk.as_ptr(), BSSRDF_OPEN_READ, &mut out_library);
        expect(status, BSSRDF_ERROR_FORMAT, "not a bssrdf library file");
        let status = bssrdf_library_open(path.as_ptr(), 2, &mut out_library);
        expect(status, BSSRDF_ERROR_INVALID_ARGUMENT, "flags = 0x2");
        assert!(out_library.is_null());

        let status = bssrdf_library_material_name(library, 2, &mut name);
        expect(status, BSSRDF_ERROR_NOT_FOUND, "no material 2");
        let status = bssrdf_library_channel(library, c"skin2".as_ptr(), 0, &mut out_channel);
        expect(status, BSSRDF_ERROR_NOT_FOUND, "\"skin2\"");
        let status = bssrdf_library_channel(library, c"skin1".as_ptr(), 3, &mut out_channel);
        expect(status, BSSRDF_ERROR_INVALID_ARGUMENT, "channel = 3");
        let bad_utf8 = c"sk\xffin".as_ptr();
        let status = bssrdf_library_channel(library, bad_utf8, 0, &mut out_channel);
        expect(status, BSSRDF_ERROR_INVALID_ARGUMENT, "not UTF-8");
        let status = bssrdf_library_medium(library, 2, 0.5, 1.0, &mut out_channel);
        expect(status, BSSRDF_ERROR_NOT_FOUND, "no table 2");
        let status = bssrdf_library_medium(library, 0, 0.5, 0.0, &mut out_channel);
        expect(status, BSSRDF_ERROR_INVALID_ARGUMENT, "vacuum");
        // σ′t² of the world units is ∞ beyond 1.3e154, and ∞ · 0 = NaN: refused with Medium's range.
        let status = bssrdf_library_medium(library, 0, 0.5, 1e300, &mut out_channel);
        expect(
            status,
            BSSRDF_ERROR_INVALID_ARGUMENT,
            "outside [1e-9, 1e12]",
        );
        let status = bssrdf_library_medium(library, 0, 1.5, 1.0, &mut out_channel);
        expect(status, BSSRDF_ERROR_OUT_OF_RANGE, "rho' = 1.5");
        assert!(out_channel.is_null());

        let red = channel(library, c"skin1", 0);
        let status = bssrdf_channel_eval(red, 1.7, 1.0, 0.0, &mut value);
        expect(
            status,
            BSSRDF_ERROR_OUT_OF_RANGE,
            "theta = 1.7 rad is outside the table's theta axis [0, 1.5707964",
        );
        let status = bssrdf_channel_effective_albedo(red, f64::NAN, &mut value);
        expect(
            status,
            BSSRDF_ERROR_OUT_OF_RANGE,
            "theta = NaN rad is outside",
        );
        let status = bssrdf_channel_sample(red, -0.5, 0.5, 0.5, &mut sample);
        expect(
            status,
            BSSRDF_ERROR_NO_SAMPLE,
            "no sample: theta = -0.5 rad is outside the table's theta axis [0, 1.5707964",
        );
        // A failed draw names its cause: a uniform a random stream cannot give, or u_r = 0
        for (u_r, u_phi, cause) in [
            (2.0, 0.5, "no sample: u_r = 2 is outside [0, 1]"),
            (f64::NAN, 0.5, "no sample: u_r = NaN is outside [0, 1]"),
            (0.5, f64::NAN, "no sample: u_phi = NaN is not finite"),
            (0.5, f64::INFINITY, "no sample: u_phi = inf is not finite"),
            (
                0.5,
                f64::NEG_INFINITY,
                "no sample: u_phi = -inf is not finite",
            ),
            (
                0.5,
                1.0,
                "no sample: u_phi = 1 is outside [0, 1): a uniform random number",
            ),
            (0.5, -3.0, "no sample: u_phi = -3 is outside [0, 1)"),
            (0.0, 0.5, "no sample: u_r = 0 draws the entry point itself"),
            (
                1.0,
                0.5,
                "no sample: u_r = 1 is the end of [0, 1): it draws the last radius",
            ),
        ] {
            let status = bssrdf_channel_sample(red, 0.3, u_r, u_phi, &mut sample);
            expect(status, BSSRDF_ERROR_NO_SAMPLE, cause);
        }
        // A point outside the lookups' domain is refused by name, not given a value of 0
        let mut value = -7.0;
        let status = bssrdf_channel_eval(red, 0.3, f64::NAN, 0.0, &mut value);
        expect(
            status,
            BSSRDF_ERROR_OUT_OF_RANGE,
            "r = NaN mm is outside [0, inf): a distance",
        );
        let status = bssrdf_channel_eval(red, 0.3, -1.0, 0.0, &mut value);
        expect(
            status,
            BSSRDF_ERROR_OUT_OF_RANGE,
            "r = -1 mm is outside [0, inf)",
        );
        let status = bssrdf_channel_pdf(red, 0.3, 1.0, f64::INFINITY, &mut value);
        expect(
            status,
            BSSRDF_ERROR_OUT_OF_RANGE,
            "phi = inf rad is not a finite angle",
        );
        let status = bssrdf_channel_pdf(red, -1.0, 1.0, 0.0, &mut value);
        let cause = "theta = -1 rad is outside the table's theta axis";
        expect(status, BSSRDF_ERROR_OUT_OF_RANGE, cause);
        let status = bssrdf_channel_pdf_theta(red, f64::NAN, &mut value);
        let cause = "theta = NaN rad is outside the table's theta axis";
        expect(status, BSSRDF_ERROR_OUT_OF_RANGE, cause);
        let status = bssrdf_channel_pdf_radius(red, 0.3, f64::INFINITY, &mut value);
        expect(
            status,
            BSSRDF_ERROR_OUT_OF_RANGE,
            "r = inf mm is outside [0, inf)",
        );
        let status = bssrdf_channel_angular_factor(red, 0.3, 1.0, f64::NAN, &mut value);
        expect(
            status,
            BSSRDF_ERROR_OUT_OF_RANGE,
            "phi = NaN rad is not a finite angle",
        );
        assert_eq!(value, -7.0, "an output written on failure");
        // beyond the last radius the value is 0, as the far tail is
        expect(
            bssrdf_channel_eval(red, 0.3, 1e9, 0.0, &mut value),
            BSSRDF_OK,
            "",
        );
        assert_eq!(value, 0.0);
        let mut radial = bssrdf_radial_sample { r: 0.0, pdf: 0.0 };
        let status = bssrdf_channel_sample_radius(red, 0.3, -1.0, &mut radial);
        expect(
            status,
            BSSRDF_ERROR_NO_SAMPLE,
            "no sample: u_r = -1 is outside [0, 1]",
        );
        let status =
            bssrdf_channel_sample_path(red, [0.5, 0.5, f64::NAN, 0.5].as_ptr(), &mut path_sample);
        expect(
            status,
            BSSRDF_ERROR_NO_SAMPLE,
            "no sample: u[2] = NaN is not finite",
        );
        let status = bssrdf_channel_sample_path(
            red,
            [0.5, 0.5, 0.5, f64::INFINITY].as_ptr(),
            &mut path_sample,
        );
        expect(
            status,
            BSSRDF_ERROR_NO_SAMPLE,
            "no sample: u[3] = inf is not finite",
        );
        for (u, cause) in [
            (
                [1.0, 0.5, 0.5, 0.5],
                "no sample: u[0] = 1 is outside [0, 1): a uniform",
            ),
            (
                [0.5, 0.5, 7.0, 0.5],
                "no sample: u[2] = 7 is outside [0, 1)",
            ),
            (
                [0.5, 0.5, 0.5, -1e300],
                "no sample: u[3] = -1e300 is outside [0, 1)",
            ),
        ] {
            let status = bssrdf_channel_sample_path(red, u.as_ptr(), &mut path_sample);
            expect(status, BSSRDF_ERROR_NO_SAMPLE, cause);
        }
        let status =
            bssrdf_channel_sample_path(red, [0.5, 1.5, 0.5, 0.5].as_ptr(), &mut path_sample);
        expect(
            status,
            BSSRDF_ERROR_NO_SAMPLE,
            "no sample: u[1] = 1.5 is outside [0, 1]",
        );
        // the radial uniform at either end of [0, 1): the entry point, the last radius
        for (u1, cause) in [
            (0.0, "no sample: u[1] = 0 draws the entry point itself"),
            (
                1.0,
                "no sample: u[1] = 1 is the end of [0, 1): it draws the last radius",
            ),
        ] {
            let status =
                bssrdf_channel_sample_path(red, [0.5, u1, 0.5, 0.5].as_ptr(), &mut path_sample);
            expect(status, BSSRDF_ERROR_NO_SAMPLE, cause);
        }
        assert_eq!(
            (value, sample),
            (0.0, NO_SAMPLE),
            "outputs untouched on failure"
        );

        // coke's blue channel scatters nothing (ρ′ = 0): no energy to sample.
        let blue = channel(library, c"coke", 2);
        let status = bssrdf_channel_sample(blue, 0.3, 0.5, 0.5, &mut sample);
        expect(status, BSSRDF_ERROR_NO_SAMPLE, "no energy");
        let status = bssrdf_channel_sample_path(blue, [0.5; 4].as_ptr(), &mut path_sample);
        expect(
            status,
            BSSRDF_ERROR_NO_SAMPLE,
            "no sample: the table stores no energy for rho' = 0",
        );
        expect(
            bssrdf_channel_eval(blue, 0.3, 1.0, 0.0, &mut value),
            BSSRDF_OK,
            "",
        );
        assert_eq!(value, 0.0);
        bssrdf_channel_release(blue);
        bssrdf_channel_release(red);
        bssrdf_library_close(library);
    }
    for (code, name) in [
        (BSSRDF_OK, "BSSRDF_OK"),
        (BSSRDF_ERROR_PANIC, "BSSRDF_ERROR_PANIC"),
        (-1, "unknown status"),
    ] {
        // SAFETY: a static string.
        let got = unsafe { CStr::from_ptr(bssrdf_status_name(code)) };
        assert_eq!(got.to_str().unwrap(), name);
    }
}

#[test]
fn a_valid_file_with_a_table_no_lookup_can_interpolate_opens_and_refuses_its_lookups() {
    // The spec's example: valid, with one albedo node
    let example = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/valid/spec-example.bssrdf");
    let example = CString::new(example.to_str().unwrap()).unwrap();
    let library = open(&example, BSSRDF_OPEN_READ);
    let (mut count, mut channel) = (0, null_mut());
    // SAFETY: a live library and valid outputs; the library is closed once.
    unsafe {
        expect(
            bssrdf_library_table_count(library, &mut count),
            BSSRDF_OK,
            "",
        );
        assert_eq!(count, 1);
        let status = bssrdf_library_medium(library, 0, 0.5, 1.0, &mut channel);
        let reason = "table 0: axis rho has 1 node(s): lookups interpolate along every axis \
                      and need at least 2 (the file itself is valid)";
        expect(status, BSSRDF_ERROR_FORMAT, reason);
        let status = bssrdf_library_channel(library, c"wax".as_ptr(), 0, &mut channel);
        expect(status, BSSRDF_ERROR_FORMAT, reason);
        assert!(channel.is_null());
        // The per-call lookups and the batches too
        let mut value = -1.0;
        let status = bssrdf_table_eval(library, 0, 0.5, 1.0, 0.0, 1.0, 0.0, &mut value);
        expect(status, BSSRDF_ERROR_FORMAT, reason);
        let x = [0.5];
        let mut out = [-1.0];
        let p = x.as_ptr();
        let status = bssrdf_table_eval_n(library, 0, 1, p, p, p, p, p, out.as_mut_ptr());
        expect(status, BSSRDF_ERROR_FORMAT, reason);
        assert_eq!((value, out), (-1.0, [-1.0]));
        let status = bssrdf_table_eval(library, 1, 0.5, 1.0, 0.0, 1.0, 0.0, &mut value);
        expect(status, BSSRDF_ERROR_NOT_FOUND, "no table 1");
        bssrdf_library_close(library);
    }
}

#[test]
fn table_info_names_the_model_and_a_walk_tables_g_and_component() {
    // The conformance vector of a walk-angular table, and the spec's example (PBD)
    let vector = |name: &str| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../tests/data/valid")
            .join(name);
        CString::new(path.to_str().unwrap()).unwrap()
    };
    let file = bssrdf_zoo::format::Library::read(
        std::path::Path::new(vector("walk-table.bssrdf").to_str().unwrap()),
        bssrdf_zoo::format::Verify::Full,
    )
    .unwrap();
    let walk = file.table(0).unwrap().walk().unwrap();
    let mut info = bssrdf_table_info {
        eta: -1.0,
        model: 99,
        walk_component: 99,
        walk_g: -9.0,
    };
    // SAFETY: live libraries and valid outputs; each library is closed once.
    unsafe {
        let library = open(&vector("walk-table.bssrdf"), BSSRDF_OPEN_READ);
        expect(
            bssrdf_library_table_info(library, 0, &mut info),
            BSSRDF_OK,
            "",
        );
        assert_eq!(info.model, BSSRDF_MODEL_WALK_ANGULAR);
        assert_eq!(info.walk_g, walk.g);
        assert_eq!(info.walk_component, walk.component.code());
        assert_eq!(info.eta, file.table(0).unwrap().eta());
        let status = bssrdf_library_table_info(library, 1, &mut info);
        expect(
            status,
            BSSRDF_ERROR_NOT_FOUND,
            "no table 1: the library holds 1",
        );
        let status = bssrdf_library_table_info(library, 0, null_mut());
        expect(status, BSSRDF_ERROR_NULL_POINTER, "out_info is NULL");
        let status = bssrdf_library_table_info(null(), 0, &mut info);
        expect(status, BSSRDF_ERROR_NULL_POINTER, "library is NULL");
        bssrdf_library_close(library);

        let library = open(&vector("spec-example.bssrdf"), BSSRDF_OPEN_READ);
        expect(
            bssrdf_library_table_info(library, 0, &mut info),
            BSSRDF_OK,
            "",
        );
        assert_eq!(
            (info.model, info.walk_component),
            (BSSRDF_MODEL_PBD_ANGULAR, 0)
        );
        assert!(info.walk_g.is_nan());
        bssrdf_library_close(library);
    }
}

#[test]
fn path_sampling_without_the_theta_table_is_no_sample() {
    let dir = tempfile::tempdir().unwrap();
    let path = crate::fixture::without_theta_sampling(dir.path(), &grid());
    let library = open(&CString::new(path.to_str().unwrap()).unwrap(), 0);
    let mut ch = null_mut();
    let mut out = NO_PATH;
    let mut pdf = -1.0;
    // SAFETY: valid handles and outputs, released once.
    unsafe {
        expect(
            bssrdf_library_medium(library, 0, 0.8, 2.0, &mut ch),
            BSSRDF_OK,
            "",
        );
        let status = bssrdf_channel_sample_path(ch, [0.5; 4].as_ptr(), &mut out);
        expect(status, BSSRDF_ERROR_NO_SAMPLE, "without theta sampling");
        expect(bssrdf_channel_pdf_theta(ch, 0.5, &mut pdf), BSSRDF_OK, "");
        bssrdf_channel_release(ch);
        bssrdf_library_close(library);
    }
    assert_eq!(pdf, 0.0);
}

#[test]
fn c_values_equal_the_rust_api_bit_for_bit_and_channels_outlive_the_library() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let rust = Library::open_mmap(path.to_str().unwrap()).unwrap();
    for flags in [BSSRDF_OPEN_MAP, BSSRDF_OPEN_READ] {
        let library = open(&path, flags);
        let (mut tables, mut materials) = (0, 0);
        // SAFETY: a live handle and valid outputs.
        unsafe {
            expect(
                bssrdf_library_table_count(library, &mut tables),
                BSSRDF_OK,
                "",
            );
            expect(
                bssrdf_library_material_count(library, &mut materials),
                BSSRDF_OK,
                "",
            );
        }
        assert_eq!((tables, materials), (2, 2));
        let mut channels = Vec::new();
        for (k, m) in rust.materials().iter().enumerate() {
            let mut name = null();
            // SAFETY: a live handle and a valid output.
            expect(
                unsafe { bssrdf_library_material_name(library, k, &mut name) },
                0,
                "",
            );
            // SAFETY: NUL-terminated, owned by the open library.
            assert_eq!(unsafe { CStr::from_ptr(name) }.to_str().unwrap(), m.name);
            let c_name = CString::new(m.name.as_str()).unwrap();
            for rgb in Rgb::ALL {
                let ch = channel(library, &c_name, rgb as c_int);
                channels.push((rust.channel(&m.name, rgb).unwrap(), ch));
            }
        }
        // SAFETY: the library's last use; its channels stay valid.
        unsafe { bssrdf_library_close(library) };
        let mut rng = SplitMix64::seed_from_u64(21);
        for (lookup, ch) in channels {
            let mut info = bssrdf_channel_info {
                rho_prime: 0.0,
                sigma_t_prime: 0.0,
                eta: 0.0,
                table: 0,
            };
            // SAFETY: a live channel and a valid output.
            expect(
                unsafe { bssrdf_channel_get_info(ch, &mut info) },
                BSSRDF_OK,
                "",
            );
            assert_eq!(info.rho_prime.to_bits(), lookup.rho_prime().to_bits());
            assert_eq!(
                info.sigma_t_prime.to_bits(),
                lookup.sigma_t_prime().to_bits()
            );
            assert_eq!(
                (info.eta, info.table),
                (lookup.table().eta(), lookup.table().index())
            );
            for _ in 0..ROUNDS {
                let theta = 1.05 * std::f64::consts::FRAC_PI_2 * rng.next_f64();
                let r = 4.0 / lookup.sigma_t_prime() * rng.next_f64();
                let phi = 7.0 * rng.next_f64() - 3.5;
                let u = [0; 4].map(|_| rng.next_f64());
                let (mut value, mut sample, mut path) = (f64::NAN, NO_SAMPLE, NO_PATH);
                // SAFETY: a live channel and valid outputs.
                unsafe {
                    let status = bssrdf_channel_eval(ch, theta, r, phi, &mut value);
                    match lookup.eval(theta, r, phi) {
                        Some(v) => assert_eq!((status, value.to_bits()), (0, v.to_bits())),
                        None => assert_eq!(status, BSSRDF_ERROR_OUT_OF_RANGE),
                    }
                    let status = bssrdf_channel_pdf(ch, theta, r, phi, &mut value);
                    if lookup.table().view().keeps_theta(theta) {
                        assert_eq!(status, BSSRDF_OK);
                        assert_eq!(value.to_bits(), lookup.pdf(theta, r, phi).to_bits());
                    } else {
                        assert_eq!(status, BSSRDF_ERROR_OUT_OF_RANGE);
                    }
                    let status = bssrdf_channel_sample(ch, theta, u[0], u[1], &mut sample);
                    match lookup.sample(theta, u[0], u[1]) {
                        Some(s) => {
                            assert_eq!(status, BSSRDF_OK);
                            assert_eq!(
                                [sample.r, sample.phi, sample.pdf].map(f64::to_bits),
                                [s.r, s.phi, s.pdf].map(f64::to_bits)
                            );
                        }
                        None => assert_eq!(status, BSSRDF_ERROR_NO_SAMPLE),
                    }
                    let status = bssrdf_channel_sample_path(ch, u.as_ptr(), &mut path);
                    match lookup.sample_path(u) {
                        Some(p) => {
                            assert_eq!(status, BSSRDF_OK);
                            let got = [path.theta, path.r, path.phi, path.phi_prime];
                            let want = [p.theta, p.r, p.phi, p.phi_prime];
                            assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits));
                            let got = [path.pdf_theta, path.pdf].map(f64::to_bits);
                            assert_eq!(got, [p.pdf_theta, p.pdf].map(f64::to_bits));
                        }
                        None => assert_eq!(status, BSSRDF_ERROR_NO_SAMPLE),
                    }
                    let status = bssrdf_channel_pdf_theta(ch, theta, &mut value);
                    if lookup.table().view().keeps_theta(theta) {
                        assert_eq!(status, BSSRDF_OK);
                        assert_eq!(value.to_bits(), lookup.pdf_theta(theta).to_bits());
                    } else {
                        assert_eq!(status, BSSRDF_ERROR_OUT_OF_RANGE);
                    }
                    let status = bssrdf_channel_effective_albedo(ch, theta, &mut value);
                    match lookup.effective_albedo(theta) {
                        Some(v) => assert_eq!((status, value.to_bits()), (0, v.to_bits())),
                        None => assert_eq!(status, BSSRDF_ERROR_OUT_OF_RANGE),
                    }
                }
            }
            // SAFETY: released once.
            unsafe { bssrdf_channel_release(ch) };
        }
    }
}
