//! Batches: lookups of `n` points on one table of an open library as structures of arrays
//! (one array of `n` doubles per argument and per output), each point with its own medium
//! (ρ′, σ′t): [`bssrdf_table_eval_n`], [`bssrdf_table_pdf_n`], [`bssrdf_table_sample_n`], the
//! separable renderers' [`bssrdf_table_sample_radius_n`], [`bssrdf_table_pdf_radius_n`] and
//! [`bssrdf_table_angular_factor_n`], and the path-tracing draw [`bssrdf_table_sample_path_n`].
//! Each runs the runtime's batch of the same name (`TableRef::eval_n`, …), so point i gives
//! the bits of the per-call function (`media.rs`, `separable.rs`) at the i-th values, and 0 (a
//! draw: every field 0) where that call would fail. Only NULL, misaligned or overlapping
//! arrays, `n` too large and an unknown table fail a batch, writing nothing; nothing here
//! allocates, failing or not (messages go to a fixed buffer, [`Failure::inline`]).

use bssrdf_runtime::table::{PathSamplesMut, RadialSamplesMut, SamplesMut, TableRef};
use bssrdf_runtime::Error;

use super::media::table_view;
use super::*;

/// A batch's array argument: its pointer and its name, for the messages.
type Array<P> = (P, &'static str);

/// A batch's arrays as slices: the inputs, then the outputs.
type Slices<'a, const I: usize, const O: usize> = ([&'a [f64]; I], [&'a mut [f64]; O]);

/// The `n`-value arrays of a batch as slices, after checking every pointer: not NULL,
/// aligned for a double, `n` doubles addressable, and no output sharing memory with another
/// array (inputs may share memory with each other).
///
/// # Safety
/// Each pointer is NULL or points to `n` doubles, readable (inputs) or writable (outputs),
/// that nothing else writes during `'a`.
unsafe fn arrays<'a, const I: usize, const O: usize>(
    n: usize,
    inputs: [Array<*const f64>; I],
    outputs: [Array<*mut f64>; O],
) -> Result<Slices<'a, I, O>, Failure> {
    let all = || {
        let outputs = outputs.iter().map(|&(p, name)| (p.cast_const(), name));
        inputs.iter().copied().chain(outputs)
    };
    for (ptr, name) in all() {
        if ptr.is_null() {
            return Err(Failure::inline(
                BSSRDF_ERROR_NULL_POINTER,
                format_args!("{name} is NULL"),
            ));
        }
        if !ptr.is_aligned() {
            return Err(Failure::inline(
                BSSRDF_ERROR_INVALID_ARGUMENT,
                format_args!("{name} is not aligned for a double"),
            ));
        }
    }
    let bytes = n
        .checked_mul(size_of::<f64>())
        .filter(|&b| b <= isize::MAX as usize)
        .ok_or_else(|| {
            Failure::inline(
                BSSRDF_ERROR_INVALID_ARGUMENT,
                format_args!("n = {n} doubles is more than memory can hold"),
            )
        })?;
    let range = |p: *const f64| (p as usize, (p as usize).saturating_add(bytes));
    for (k, &(output, name)) in outputs.iter().enumerate() {
        let (start, end) = range(output);
        let others = all().enumerate().filter(|&(j, _)| j != I + k);
        for (_, (other, other_name)) in others {
            let (other_start, other_end) = range(other);
            if bytes > 0 && start < other_end && other_start < end {
                return Err(Failure::inline(
                    BSSRDF_ERROR_INVALID_ARGUMENT,
                    format_args!(
                        "{name} overlaps {other_name}: an output must not share memory with another array"
                    ),
                ));
            }
        }
    }
    // SAFETY: each pointer is non-NULL and aligned, `n` doubles are addressable, the caller
    // guarantees they are readable or writable, and no output overlaps another array.
    let inputs = inputs.map(|(p, _)| unsafe { std::slice::from_raw_parts(p, n) });
    // SAFETY: as above.
    let outputs = outputs.map(|(p, _)| unsafe { std::slice::from_raw_parts_mut(p, n) });
    Ok((inputs, outputs))
}

/// A length the batch functions cannot get wrong (every array has `n` values); kept as a
/// failure all the same.
#[cold]
fn batch_failure(e: Error) -> Failure {
    Failure::inline(BSSRDF_ERROR_INVALID_ARGUMENT, format_args!("{e}"))
}

/// The inputs of [`bssrdf_table_eval_n`], [`bssrdf_table_pdf_n`] and
/// [`bssrdf_table_angular_factor_n`], as the header names them.
const POINTS: [&str; 5] = ["rho_prime", "sigma_t_prime", "theta", "r_mm", "phi"];

/// The inputs of [`bssrdf_table_sample_n`], as the header names them.
const DRAWS: [&str; 5] = ["rho_prime", "sigma_t_prime", "theta", "u_r", "u_phi"];

/// The body of a batch: the table found, the arrays checked ([`arrays`]; the inputs named by
/// `names`), then `lookup` over them.
///
/// # Safety
/// As [`arrays`], and `library` is NULL or an open handle.
#[inline(always)]
unsafe fn batch<'t, const I: usize, const O: usize>(
    (library, table, n): (*const bssrdf_library, usize, usize),
    (inputs, names): ([*const f64; I], [&'static str; I]),
    outputs: [Array<*mut f64>; O],
    lookup: impl FnOnce(TableRef<'t>, [&[f64]; I], [&mut [f64]; O]) -> bssrdf_runtime::Result<()>,
) -> c_int {
    guard(|| {
        // SAFETY: the caller's contract.
        let view = unsafe { table_view(library, table) }?;
        let inputs = std::array::from_fn(|k| (inputs[k], names[k]));
        // SAFETY: the caller's contract.
        let (inputs, outputs) = unsafe { arrays(n, inputs, outputs) }?;
        lookup(view, inputs, outputs).map_err(batch_failure)
    })
}

/// The body of the batches of one value per point at (θ, r_mm, φ) ([`POINTS`]):
/// [`batch`] running `values_n` (`TableRef::eval_n`, `pdf_n` or `angular_factor_n`).
///
/// # Safety
/// As [`batch`].
#[inline(always)]
unsafe fn values_batch<'t>(
    (library, table, n): (*const bssrdf_library, usize, usize),
    inputs: [*const f64; 5],
    out: Array<*mut f64>,
    values_n: impl FnOnce(
        &TableRef<'t>,
        &[f64],
        &[f64],
        &[f64],
        &[f64],
        &[f64],
        &mut [f64],
    ) -> bssrdf_runtime::Result<()>,
) -> c_int {
    let lookup =
        |view: TableRef<'t>,
         [rho, sigma_t, theta, r_mm, phi]: [&[f64]; 5],
         [out]: [&mut [f64]; 1]| { values_n(&view, rho, sigma_t, theta, r_mm, phi, out) };
    // SAFETY: the caller's contract.
    unsafe { batch((library, table, n), (inputs, POINTS), [out], lookup) }
}

/// S_p in mm⁻² at `n` points into `out_value[0..n]`: point i is [`bssrdf_table_eval`] of the
/// medium (`rho_prime[i]`, `sigma_t_prime[i]`) at (`theta[i]`, `r_mm[i]`, `phi[i]`), with
/// the same bits, or 0 where that call would fail (medium or θ out of range).
///
/// # Safety
/// `library` is NULL or an open handle; every array pointer is NULL or points to `n` doubles,
/// readable (inputs) or writable (`out_value`).
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_eval_n(
    library: *const bssrdf_library,
    table: usize,
    n: usize,
    rho_prime: *const f64,
    sigma_t_prime: *const f64,
    theta: *const f64,
    r_mm: *const f64,
    phi: *const f64,
    out_value: *mut f64,
) -> c_int {
    let inputs = [rho_prime, sigma_t_prime, theta, r_mm, phi];
    let out = (out_value, "out_value");
    // SAFETY: the function's contract.
    unsafe { values_batch((library, table, n), inputs, out, TableRef::eval_n) }
}

/// Density per mm² at `n` points into `out_pdf[0..n]`: point i is [`bssrdf_table_pdf`] of the
/// medium (`rho_prime[i]`, `sigma_t_prime[i]`) at (`theta[i]`, `r_mm[i]`, `phi[i]`), or 0
/// where that call would fail.
///
/// # Safety
/// As [`bssrdf_table_eval_n`], `out_pdf` for `out_value`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_pdf_n(
    library: *const bssrdf_library,
    table: usize,
    n: usize,
    rho_prime: *const f64,
    sigma_t_prime: *const f64,
    theta: *const f64,
    r_mm: *const f64,
    phi: *const f64,
    out_pdf: *mut f64,
) -> c_int {
    let inputs = [rho_prime, sigma_t_prime, theta, r_mm, phi];
    let out = (out_pdf, "out_pdf");
    // SAFETY: the function's contract.
    unsafe { values_batch((library, table, n), inputs, out, TableRef::pdf_n) }
}

/// `n` draws of the exit point into `out_r[0..n]` (mm), `out_phi` (radians) and `out_pdf`
/// (per mm²): point i is [`bssrdf_table_sample`] of the medium (`rho_prime[i]`,
/// `sigma_t_prime[i]`) for incidence `theta[i]` from the uniforms (`u_r[i]`, `u_phi[i]`), or
/// the failed draw r = φ = pdf = 0 where that call would fail (every draw has pdf > 0).
///
/// # Safety
/// `library` is NULL or an open handle; every array pointer is NULL or points to `n` doubles,
/// readable (inputs) or writable (outputs).
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_sample_n(
    library: *const bssrdf_library,
    table: usize,
    n: usize,
    rho_prime: *const f64,
    sigma_t_prime: *const f64,
    theta: *const f64,
    u_r: *const f64,
    u_phi: *const f64,
    out_r: *mut f64,
    out_phi: *mut f64,
    out_pdf: *mut f64,
) -> c_int {
    let inputs = [rho_prime, sigma_t_prime, theta, u_r, u_phi];
    let outputs = [(out_r, "out_r"), (out_phi, "out_phi"), (out_pdf, "out_pdf")];
    let sample_n = |view: TableRef,
                    [rho, sigma_t, theta, u_r, u_phi]: [&[f64]; 5],
                    [r, phi, pdf]: [&mut [f64]; 3]| {
        view.sample_n(rho, sigma_t, theta, u_r, u_phi, SamplesMut { r, phi, pdf })
    };
    // SAFETY: the function's contract.
    unsafe { batch((library, table, n), (inputs, DRAWS), outputs, sample_n) }
}

/// `n` draws of the exit distance alone into `out_r[0..n]` (mm) and `out_pdf` (per mm): point
/// i is [`bssrdf_table_sample_radius`] of the medium (`rho_prime[i]`, `sigma_t_prime[i]`) for
/// incidence `theta[i]` from the uniform `u[i]`, or the failed draw r = pdf = 0 where that call
/// would fail (every draw has pdf > 0).
///
/// # Safety
/// `library` is NULL or an open handle; every array pointer is NULL or points to `n` doubles,
/// readable (inputs) or writable (outputs).
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_sample_radius_n(
    library: *const bssrdf_library,
    table: usize,
    n: usize,
    rho_prime: *const f64,
    sigma_t_prime: *const f64,
    theta: *const f64,
    u: *const f64,
    out_r: *mut f64,
    out_pdf: *mut f64,
) -> c_int {
    let inputs = [rho_prime, sigma_t_prime, theta, u];
    let names = ["rho_prime", "sigma_t_prime", "theta", "u"];
    let outputs = [(out_r, "out_r"), (out_pdf, "out_pdf")];
    let sample_radius_n =
        |view: TableRef, [rho, sigma_t, theta, u]: [&[f64]; 4], [r, pdf]: [&mut [f64]; 2]| {
            view.sample_radius_n(rho, sigma_t, theta, u, RadialSamplesMut { r, pdf })
        };
    // SAFETY: the function's contract.
    unsafe {
        batch(
            (library, table, n),
            (inputs, names),
            outputs,
            sample_radius_n,
        )
    }
}

/// Density per mm at `n` points into `out_pdf[0..n]`: point i is [`bssrdf_table_pdf_radius`]
/// of the medium (`rho_prime[i]`, `sigma_t_prime[i]`) at (`theta[i]`, `r_mm[i]`), or 0 where
/// that call would fail.
///
/// # Safety
/// As [`bssrdf_table_sample_radius_n`].
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_pdf_radius_n(
    library: *const bssrdf_library,
    table: usize,
    n: usize,
    rho_prime: *const f64,
    sigma_t_prime: *const f64,
    theta: *const f64,
    r_mm: *const f64,
    out_pdf: *mut f64,
) -> c_int {
    let inputs = [rho_prime, sigma_t_prime, theta, r_mm];
    let names = ["rho_prime", "sigma_t_prime", "theta", "r_mm"];
    let pdf_radius_n =
        |view: TableRef, [rho, sigma_t, theta, r_mm]: [&[f64]; 4], [out]: [&mut [f64]; 1]| {
            view.pdf_radius_n(rho, sigma_t, theta, r_mm, out)
        };
    let outputs = [(out_pdf, "out_pdf")];
    // SAFETY: the function's contract.
    unsafe { batch((library, table, n), (inputs, names), outputs, pdf_radius_n) }
}

/// The angular factor S/S̄ (dimensionless) at `n` points into `out_factor[0..n]`: point i is
/// [`bssrdf_table_angular_factor`] of the medium (`rho_prime[i]`, `sigma_t_prime[i]`) at
/// (`theta[i]`, `r_mm[i]`, `phi[i]`), or 0 where that call would fail (medium or θ out of
/// range).
///
/// # Safety
/// As [`bssrdf_table_sample_radius_n`].
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_angular_factor_n(
    library: *const bssrdf_library,
    table: usize,
    n: usize,
    rho_prime: *const f64,
    sigma_t_prime: *const f64,
    theta: *const f64,
    r_mm: *const f64,
    phi: *const f64,
    out_factor: *mut f64,
) -> c_int {
    let inputs = [rho_prime, sigma_t_prime, theta, r_mm, phi];
    let out = (out_factor, "out_factor");
    // SAFETY: the function's contract.
    unsafe { values_batch((library, table, n), inputs, out, TableRef::angular_factor_n) }
}

/// `n` path-tracing draws (θ, r, φ, φ′) into `out_theta[0..n]` (radians), `out_r` (mm),
/// `out_phi`, `out_phi_prime` (radians), `out_pdf_theta` (per radian) and `out_pdf` (the joint
/// density): point i is [`bssrdf_table_sample_path`] of the medium (`rho_prime[i]`,
/// `sigma_t_prime[i]`) from the uniforms u = (`u0[i]`, `u1[i]`, `u2[i]`, `u3[i]`), or the
/// failed draw, every field 0, where that call would fail (every draw has pdf > 0).
///
/// # Safety
/// As [`bssrdf_table_sample_radius_n`].
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_sample_path_n(
    library: *const bssrdf_library,
    table: usize,
    n: usize,
    rho_prime: *const f64,
    sigma_t_prime: *const f64,
    u0: *const f64,
    u1: *const f64,
    u2: *const f64,
    u3: *const f64,
    out_theta: *mut f64,
    out_r: *mut f64,
    out_phi: *mut f64,
    out_phi_prime: *mut f64,
    out_pdf_theta: *mut f64,
    out_pdf: *mut f64,
) -> c_int {
    let inputs = [rho_prime, sigma_t_prime, u0, u1, u2, u3];
    let names = ["rho_prime", "sigma_t_prime", "u0", "u1", "u2", "u3"];
    let outputs = [
        (out_theta, "out_theta"),
        (out_r, "out_r"),
        (out_phi, "out_phi"),
        (out_phi_prime, "out_phi_prime"),
        (out_pdf_theta, "out_pdf_theta"),
        (out_pdf, "out_pdf"),
    ];
    let sample_path_n =
        |view: TableRef, [rho, sigma_t, u @ ..]: [&[f64]; 6], out: [&mut [f64]; 6]| {
            view.sample_path_n(rho, sigma_t, u, PathSamplesMut::from(out))
        };
    // SAFETY: the function's contract.
    unsafe { batch((library, table, n), (inputs, names), outputs, sample_path_n) }
}
