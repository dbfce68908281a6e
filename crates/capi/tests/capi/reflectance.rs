//! The diffuse reflectance's entry points, `bssrdf_library_invert_albedo`,
//! `bssrdf_library_reflectance_range` and the forward `bssrdf_table_diffuse_reflectance` and
//! `bssrdf_channel_diffuse_reflectance` (round trips with the inversion), called from Rust: every NULL pointer and failure with
//! its code and a message naming the value and the range, outputs untouched on failure, and
//! values equal to the runtime's bit for bit in both open modes. `c_program.rs` calls them from
//! C (the expectations below), `embed_alloc.rs` counts their allocations.
#![allow(unsafe_code)]

use std::f64::consts::FRAC_PI_2;
use std::fmt::Write as _;
use std::ptr::{null, null_mut};

use bssrdf::*;
use bssrdf_zoo::embed::Library;
use bssrdf_zoo::rng::{SeedableRng, SplitMix64, UnitF64};

use crate::rust::{baked, expect, open};

/// A reflectance to invert on a table whose range at θ is [0, `max`]: mostly inside, some at
/// the ends, some beyond them.
fn draw(rng: &mut SplitMix64, max: f64) -> f64 {
    let u = rng.next_f64();
    match (10.0 * rng.next_f64()) as u32 {
        0 => 0.0,
        1 => max,
        2 => -0.1 * u,
        3 => max * (1.0 + u),
        _ => max * u,
    }
}

#[test]
fn every_null_pointer_and_failure_has_its_code_and_a_message() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let library = open(&path, BSSRDF_OPEN_MAP);
    let (mut rho, mut min, mut max) = (-7.0, -7.0, -7.0);
    let (null_pointer, out_of_range) = (BSSRDF_ERROR_NULL_POINTER, BSSRDF_ERROR_OUT_OF_RANGE);
    // SAFETY: every pointer is NULL, a live handle or a valid output.
    unsafe {
        let invert =
            |table, a, theta, out| bssrdf_library_invert_albedo(library, table, a, theta, out);
        let range =
            |table, theta, lo, hi| bssrdf_library_reflectance_range(library, table, theta, lo, hi);
        expect(
            bssrdf_library_invert_albedo(null(), 0, 0.5, 0.0, &mut rho),
            null_pointer,
            "library",
        );
        expect(
            invert(0, 0.5, 0.0, null_mut()),
            null_pointer,
            "out_rho_prime",
        );
        expect(
            bssrdf_library_reflectance_range(null(), 0, 0.0, &mut min, &mut max),
            null_pointer,
            "library",
        );
        expect(range(0, 0.0, null_mut(), &mut max), null_pointer, "out_min");
        expect(range(0, 0.0, &mut min, null_mut()), null_pointer, "out_max");
        let not_found = BSSRDF_ERROR_NOT_FOUND;
        expect(invert(2, 0.5, 0.0, &mut rho), not_found, "no table 2");
        expect(range(2, 0.0, &mut min, &mut max), not_found, "no table 2");
        for (a, text) in [
            (0.99, "0.99"),
            (-0.1, "-0.1"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
        ] {
            let needle = format!("reflectance {text} is outside [0, 0.9");
            expect(invert(0, a, 0.0, &mut rho), out_of_range, &needle);
        }
        for theta in [f64::NAN, -0.1, 2.0] {
            let needle = "outside the table's incidence axis";
            expect(invert(0, 0.5, theta, &mut rho), out_of_range, needle);
            expect(range(0, theta, &mut min, &mut max), out_of_range, needle);
        }
        for a in [0.0, 0.5] {
            expect(
                invert(1, a, FRAC_PI_2, &mut rho),
                out_of_range,
                "no light enters",
            );
        }
        assert_eq!((rho, min, max), (-7.0, -7.0, -7.0), "outputs untouched");
        // The same pointer for both ends gets the maximum.
        expect(range(0, 0.0, &mut max, &mut max), BSSRDF_OK, "");
        let rust = Library::read(path.to_str().unwrap()).unwrap();
        let [_, top] = rust
            .table(0)
            .unwrap()
            .view()
            .reflectance_range(0.0)
            .unwrap();
        assert_eq!(max, top);
        bssrdf_library_close(library);
    }
}

#[test]
fn c_values_equal_the_runtimes_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let rust = Library::read(path.to_str().unwrap()).unwrap();
    let mut rng = SplitMix64::seed_from_u64(21);
    for flags in [BSSRDF_OPEN_MAP, BSSRDF_OPEN_READ] {
        let library = open(&path, flags);
        for table in 0..rust.table_count() {
            let view_owner = rust.table(table).unwrap();
            let view = view_owner.view();
            for _ in 0..crate::rust::ROUNDS {
                let theta = 1.05 * FRAC_PI_2 * rng.next_f64();
                let (mut lo, mut hi) = (-7.0, -7.0);
                // SAFETY: a live handle and valid outputs.
                let status = unsafe {
                    bssrdf_library_reflectance_range(library, table, theta, &mut lo, &mut hi)
                };
                let Ok([min, max]) = view.reflectance_range(theta) else {
                    assert_eq!(status, BSSRDF_ERROR_OUT_OF_RANGE);
                    assert_eq!((lo, hi), (-7.0, -7.0));
                    continue;
                };
                assert_eq!(status, BSSRDF_OK);
                assert_eq!((lo.to_bits(), hi.to_bits()), (min.to_bits(), max.to_bits()));
                let a = draw(&mut rng, max);
                let mut rho = -7.0;
                // SAFETY: a live handle and a valid output.
                let status =
                    unsafe { bssrdf_library_invert_albedo(library, table, a, theta, &mut rho) };
                match view.rho_prime_for_reflectance(a, theta) {
                    Ok(expected) => {
                        assert_eq!(status, BSSRDF_OK);
                        assert_eq!(rho.to_bits(), expected.to_bits(), "{a} at {theta}");
                    }
                    Err(_) => {
                        assert_eq!(status, BSSRDF_ERROR_OUT_OF_RANGE);
                        assert_eq!(rho, -7.0);
                    }
                }
            }
        }
        // SAFETY: a handle from above, closed once.
        unsafe { bssrdf_library_close(library) };
    }
}

/// The forward reflectance through C, `bssrdf_table_diffuse_reflectance` (per call, any σ′t)
/// and `bssrdf_channel_diffuse_reflectance` (a handle of the medium), round trips with
/// `bssrdf_library_invert_albedo`: A → ρ′ → A gives A back to 1e-6 (and to 1e-6 of itself for
/// A ≥ 1e-30; the solver's bound, crates/zoo/tests/table/reflectance.rs), both forward calls
/// give the runtime's `diffuse_reflectance` bit for bit, and the channel's equals the product
/// (1 − F_r(θ))·ρ_eff of its own `entry_transmittance` and effective albedo.
#[test]
fn the_forward_reflectance_round_trips_with_the_inversion() {
    let dir = tempfile::tempdir().unwrap();
    let path = baked(dir.path());
    let rust = Library::read(path.to_str().unwrap()).unwrap();
    let library = open(&path, BSSRDF_OPEN_MAP);
    let mut rng = SplitMix64::seed_from_u64(22);
    let mut points = 0;
    for table in 0..rust.table_count() {
        let view = rust.view(table).unwrap();
        for _ in 0..crate::rust::ROUNDS {
            let theta = 0.999 * FRAC_PI_2 * rng.next_f64();
            let [min, max] = view.reflectance_range(theta).unwrap();
            let a = draw(&mut rng, max).clamp(min, max);
            let sigma_t = 10f64.powf(4.0 * rng.next_f64() - 2.0);
            let (mut rho, mut back, mut via_channel, mut albedo) = (-7.0, -7.0, -7.0, -7.0);
            let mut channel = null_mut();
            // SAFETY: a live handle and valid outputs; the channel is released once.
            unsafe {
                let status = bssrdf_library_invert_albedo(library, table, a, theta, &mut rho);
                assert_eq!(status, BSSRDF_OK, "A {a} at θ {theta}");
                let status = bssrdf_table_diffuse_reflectance(
                    library, table, rho, sigma_t, theta, &mut back,
                );
                assert_eq!(status, BSSRDF_OK);
                let status = bssrdf_library_medium(library, table, rho, sigma_t, &mut channel);
                assert_eq!(status, BSSRDF_OK);
                let status = bssrdf_channel_diffuse_reflectance(channel, theta, &mut via_channel);
                assert_eq!(status, BSSRDF_OK);
                let status = bssrdf_channel_effective_albedo(channel, theta, &mut albedo);
                assert_eq!(status, BSSRDF_OK);
                bssrdf_channel_release(channel);
            }
            let expected = view.diffuse_reflectance(rho, theta).unwrap();
            assert_eq!(back.to_bits(), expected.to_bits());
            assert_eq!(via_channel.to_bits(), expected.to_bits());
            let eta = view.eta();
            let product = bssrdf_zoo::fresnel::entry_transmittance(theta, eta) * albedo;
            assert_eq!(back.to_bits(), product.to_bits());
            let error = (back - a).abs();
            let at = format!("table {table}, θ {theta}, A {a:e}: ρ′ {rho:e} gives {back:e}");
            assert!(error <= 1e-6, "{at}");
            assert!(a < 1e-30 || error <= 1e-6 * a, "{at}");
            points += 1;
        }
    }
    // SAFETY: a handle from above, closed once.
    unsafe { bssrdf_library_close(library) };
    assert!(points >= 2 * crate::rust::ROUNDS, "{points}");
}

/// The C program's expectations for the diffuse reflectance (format in
/// `crates/capi/tests/c/capi_test.c`, "Diffuse reflectance"): random (table, A, θ) on every
/// table, with the statuses and bits the Rust API gives.
pub fn expectations(library: &Library) -> String {
    let hex = |x: f64| format!("{:016x}", x.to_bits());
    let mut text = String::new();
    let mut rng = SplitMix64::seed_from_u64(2025);
    for table in 0..=library.table_count() {
        for _ in 0..200 {
            let theta = 1.05 * FRAC_PI_2 * rng.next_f64();
            let lookup = library.table(table);
            let range = lookup
                .as_ref()
                .map_err(|_| BSSRDF_ERROR_NOT_FOUND)
                .and_then(|t| {
                    t.view()
                        .reflectance_range(theta)
                        .map_err(|_| BSSRDF_ERROR_OUT_OF_RANGE)
                });
            let (status, [min, max]) = match range {
                Ok(r) => (BSSRDF_OK, r),
                Err(code) => (code, [0.0; 2]),
            };
            writeln!(
                text,
                "G {table} {} {status} {} {}",
                hex(theta),
                hex(min),
                hex(max)
            )
            .unwrap();
            let a = draw(&mut rng, if status == BSSRDF_OK { max } else { 0.5 });
            let inverted = lookup
                .as_ref()
                .map_err(|_| BSSRDF_ERROR_NOT_FOUND)
                .and_then(|t| {
                    t.view()
                        .rho_prime_for_reflectance(a, theta)
                        .map_err(|_| BSSRDF_ERROR_OUT_OF_RANGE)
                });
            let (status, rho) = match inverted {
                Ok(rho) => (BSSRDF_OK, rho),
                Err(code) => (code, 0.0),
            };
            writeln!(
                text,
                "R {table} {} {} {status} {}",
                hex(a),
                hex(theta),
                hex(rho)
            )
            .unwrap();
        }
    }
    text
}
