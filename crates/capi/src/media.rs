//! Lookups with the medium given per call, on a table of an open library, without a channel
//! handle: one point ([`bssrdf_table_eval`] and its siblings) or N points as structures of
//! arrays ([`bssrdf_table_eval_n`], [`bssrdf_table_pdf_n`], [`bssrdf_table_sample_n`]), each
//! point with its own ρ′ and σ′t: a textured medium or a spectral renderer's wavelengths on one
//! table (one η). Declared in `include/bssrdf_zoo.h` beside the rest; the crate's rules hold
//! (statuses, the thread's last error, NULL checks, no panic across, outputs written only on
//! success), and nothing here allocates, failing or not: messages are formatted into a fixed
//! buffer ([`Failure::inline`]).
//!
//! A single lookup checks the medium as [`bssrdf_library_medium`] does, with the same codes
//! (`BSSRDF_ERROR_INVALID_ARGUMENT` for σ′t, `BSSRDF_ERROR_OUT_OF_RANGE` for ρ′) and a message
//! naming the value and its range, and gives the channel handle's bits for the same medium. A
//! batch writes 0 (a draw: r = φ = pdf = 0) for a point outside the domain and goes on; only
//! NULL, misaligned or overlapping arrays and an unknown table fail it.

use bssrdf_runtime::table::{MediumRef, SamplesMut, TableRef};
use bssrdf_runtime::Error;

use super::*;

/// Table `table` of an open library, or a failure.
///
/// # Safety
/// `library` is NULL or an open handle.
#[inline(always)]
unsafe fn table_view<'a>(
    library: *const bssrdf_library,
    table: usize,
) -> Result<TableRef<'a>, Failure> {
    // SAFETY: the caller's contract.
    let library = unsafe { input(library, c"library is NULL") }?;
    library
        .library
        .view(table)
        .map_err(|e| Failure::inline(BSSRDF_ERROR_NOT_FOUND, format_args!("{e}")))
}

/// The medium (ρ′, σ′t) on table `table` of an open library, or a failure naming the value.
///
/// # Safety
/// `library` is NULL or an open handle.
#[inline(always)]
unsafe fn medium<'a>(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
) -> Result<MediumRef<'a>, Failure> {
    // SAFETY: the caller's contract.
    let view = unsafe { table_view(library, table) }?;
    view.medium(rho_prime, sigma_t_prime)
        .map_err(|e| medium_failure(table, e))
}

/// The status and message of a medium [`TableRef::medium`] refuses: ρ′ outside the table's
/// rows is out of range, σ′t outside its domain an invalid argument (as for
/// [`bssrdf_library_medium`]).
#[cold]
fn medium_failure(table: usize, e: Error) -> Failure {
    let code = match e {
        Error::AlbedoOutsideTable { .. } => BSSRDF_ERROR_OUT_OF_RANGE,
        _ => BSSRDF_ERROR_INVALID_ARGUMENT,
    };
    Failure::inline(code, format_args!("medium on table {table}: {e}"))
}

/// The body of a lookup with the medium given per call and one output: the output checked,
/// then the medium found and checked, then `lookup` on it into `*out`.
///
/// # Safety
/// `library` is NULL or an open handle; `out` is NULL or writable.
#[inline(always)]
unsafe fn per_call<T>(
    (library, table, rho_prime, sigma_t_prime): (*const bssrdf_library, usize, f64, f64),
    (out, name): (*mut T, &'static CStr),
    lookup: impl FnOnce(MediumRef<'_>) -> Result<T, Failure>,
) -> c_int {
    guard(|| {
        // SAFETY: the caller's contract.
        let out = unsafe { output(out, name) }?;
        // SAFETY: the caller's contract.
        *out = lookup(unsafe { medium(library, table, rho_prime, sigma_t_prime) }?)?;
        Ok(())
    })
}

/// S_p(r, φ; θ) in mm⁻² of the medium (`rho_prime`, `sigma_t_prime` in mm⁻¹) on table `table`,
/// stored in `*out_value`: [`bssrdf_channel_eval`] without a handle.
///
/// # Safety
/// `library` is NULL or an open handle; `out_value` is NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_eval(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    theta: f64,
    r_mm: f64,
    phi: f64,
    out_value: *mut f64,
) -> c_int {
    let medium = (library, table, rho_prime, sigma_t_prime);
    let eval = |m: MediumRef| m.eval(theta, r_mm, phi).ok_or_else(theta_outside);
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_value, c"out_value is NULL"), eval) }
}

/// Density per mm² of [`bssrdf_table_sample`] at (r, φ) (0 where it cannot sample), stored in
/// `*out_pdf`: [`bssrdf_channel_pdf`] without a handle.
///
/// # Safety
/// `library` is NULL or an open handle; `out_pdf` is NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_pdf(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    theta: f64,
    r_mm: f64,
    phi: f64,
    out_pdf: *mut f64,
) -> c_int {
    let medium = (library, table, rho_prime, sigma_t_prime);
    let pdf = |m: MediumRef| Ok(m.pdf(theta, r_mm, phi));
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_pdf, c"out_pdf is NULL"), pdf) }
}

/// Draws the exit point for incidence θ from two uniforms into `*out_sample`:
/// [`bssrdf_channel_sample`] without a handle.
///
/// # Safety
/// `library` is NULL or an open handle; `out_sample` is NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_sample(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    theta: f64,
    u_r: f64,
    u_phi: f64,
    out_sample: *mut bssrdf_sample,
) -> c_int {
    let medium = (library, table, rho_prime, sigma_t_prime);
    let sample = |m: MediumRef| Ok(m.sample(theta, u_r, u_phi).ok_or_else(no_sample)?.into());
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_sample, c"out_sample is NULL"), sample) }
}

/// The path-tracing draw from the four uniforms `u[0..4]` into `*out_sample`:
/// [`bssrdf_channel_sample_path`] without a handle.
///
/// # Safety
/// `library` is NULL or an open handle; `u` is NULL or points to 4 readable doubles;
/// `out_sample` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_table_sample_path(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    u: *const f64,
    out_sample: *mut bssrdf_path_sample,
) -> c_int {
    let medium = (library, table, rho_prime, sigma_t_prime);
    let sample_path = |m: MediumRef| {
        // SAFETY: the contract: 4 readable doubles, and [f64; 4] has the alignment of f64.
        let u = *unsafe { input(u.cast::<[f64; 4]>(), c"u is NULL") }?;
        Ok(m.sample_path(u).ok_or_else(no_path_sample)?.into())
    };
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_sample, c"out_sample is NULL"), sample_path) }
}

/// Density of θ in [`bssrdf_table_sample_path`], per radian (0 without θ sampling), stored in
/// `*out_pdf`: [`bssrdf_channel_pdf_theta`] without a handle (σ′t is checked, but does not
/// enter it).
///
/// # Safety
/// `library` is NULL or an open handle; `out_pdf` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_table_pdf_theta(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    theta: f64,
    out_pdf: *mut f64,
) -> c_int {
    let medium = (library, table, rho_prime, sigma_t_prime);
    let pdf_theta = |m: MediumRef| Ok(m.pdf_theta(theta));
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_pdf, c"out_pdf is NULL"), pdf_theta) }
}

/// Effective albedo ρ_eff(θ) stored in `*out_albedo`: [`bssrdf_channel_effective_albedo`]
/// without a handle (σ′t is checked, but does not enter it).
///
/// # Safety
/// `library` is NULL or an open handle; `out_albedo` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_table_effective_albedo(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    theta: f64,
    out_albedo: *mut f64,
) -> c_int {
    let medium = (library, table, rho_prime, sigma_t_prime);
    let albedo = |m: MediumRef| m.effective_albedo(theta).ok_or_else(theta_outside);
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_albedo, c"out_albedo is NULL"), albedo) }
}

/// Draws the exit distance for incidence θ from one uniform `u` into `*out_sample` (r in mm,
/// density per mm): the radial step of [`bssrdf_table_sample`] (the same `u` gives the same r),
/// for separable renderers ([`MediumRef::sample_radius`]). `BSSRDF_ERROR_NO_SAMPLE` where
/// `bssrdf_table_sample` fails with it.
///
/// # Safety
/// `library` is NULL or an open handle; `out_sample` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_table_sample_radius(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    theta: f64,
    u: f64,
    out_sample: *mut bssrdf_radial_sample,
) -> c_int {
    let medium = (library, table, rho_prime, sigma_t_prime);
    let sample = |m: MediumRef| Ok(m.sample_radius(theta, u).ok_or_else(no_sample)?.into());
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_sample, c"out_sample is NULL"), sample) }
}

/// Density per mm of [`bssrdf_table_sample_radius`] at `r_mm` (0 where it cannot sample),
/// stored in `*out_pdf` ([`MediumRef::pdf_radius`]).
///
/// # Safety
/// `library` is NULL or an open handle; `out_pdf` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_table_pdf_radius(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    theta: f64,
    r_mm: f64,
    out_pdf: *mut f64,
) -> c_int {
    let medium = (library, table, rho_prime, sigma_t_prime);
    let pdf = |m: MediumRef| Ok(m.pdf_radius(theta, r_mm));
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_pdf, c"out_pdf is NULL"), pdf) }
}

/// The angular factor S(r, φ; θ)/S̄(r; θ), dimensionless, stored in `*out_factor`
/// ([`MediumRef::angular_factor`]): [`bssrdf_table_eval`] = S̄·factor with
/// S̄ = (1/2π) ∫ S dφ; `BSSRDF_ERROR_OUT_OF_RANGE` for θ outside the table.
///
/// # Safety
/// `library` is NULL or an open handle; `out_factor` is NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn bssrdf_table_angular_factor(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    theta: f64,
    r_mm: f64,
    phi: f64,
    out_factor: *mut f64,
) -> c_int {
    let medium = (library, table, rho_prime, sigma_t_prime);
    let factor = |m: MediumRef| m.angular_factor(theta, r_mm, phi).ok_or_else(theta_outside);
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_factor, c"out_factor is NULL"), factor) }
}

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

/// The inputs of [`bssrdf_table_eval_n`] and [`bssrdf_table_pdf_n`], as the header names them.
const POINTS: [&str; 5] = ["rho_prime", "sigma_t_prime", "theta", "r_mm", "phi"];

/// The inputs of [`bssrdf_table_sample_n`], as the header names them.
const DRAWS: [&str; 5] = ["rho_prime", "sigma_t_prime", "theta", "u_r", "u_phi"];

/// The body of a batch: the table found, the arrays checked ([`arrays`]; the inputs named by
/// `names`), then `lookup` over them.
///
/// # Safety
/// As [`arrays`], and `library` is NULL or an open handle.
#[inline(always)]
unsafe fn batch<const O: usize>(
    (library, table, n): (*const bssrdf_library, usize, usize),
    (inputs, names): ([*const f64; 5], [&'static str; 5]),
    outputs: [Array<*mut f64>; O],
    lookup: impl FnOnce(TableRef<'_>, [&[f64]; 5], [&mut [f64]; O]) -> bssrdf_runtime::Result<()>,
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
    let eval_n =
        |view: TableRef, [rho, sigma_t, theta, r_mm, phi]: [&[f64]; 5], [out]: [&mut [f64]; 1]| {
            view.eval_n(rho, sigma_t, theta, r_mm, phi, out)
        };
    let outputs = [(out_value, "out_value")];
    // SAFETY: the function's contract.
    unsafe { batch((library, table, n), (inputs, POINTS), outputs, eval_n) }
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
    let pdf_n =
        |view: TableRef, [rho, sigma_t, theta, r_mm, phi]: [&[f64]; 5], [out]: [&mut [f64]; 1]| {
            view.pdf_n(rho, sigma_t, theta, r_mm, phi, out)
        };
    // SAFETY: the function's contract.
    unsafe {
        batch(
            (library, table, n),
            (inputs, POINTS),
            [(out_pdf, "out_pdf")],
            pdf_n,
        )
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_inline_message_is_cut_at_a_character_boundary_and_stays_terminated() {
        let long = "é".repeat(INLINE);
        let status = guard(|| Err(Failure::inline(BSSRDF_ERROR_IO, format_args!("{long}"))));
        assert_eq!(status, BSSRDF_ERROR_IO);
        // SAFETY: NUL-terminated, valid until the next failing call on this thread.
        let text = unsafe { CStr::from_ptr(bssrdf_last_error_message()) };
        assert_eq!(text.to_str().unwrap(), "é".repeat((INLINE - 1) / 2));
        let status = guard(|| Err(Failure::inline(BSSRDF_ERROR_IO, format_args!("short"))));
        assert_eq!(status, BSSRDF_ERROR_IO);
        // SAFETY: as above.
        let text = unsafe { CStr::from_ptr(bssrdf_last_error_message()) };
        assert_eq!(text.to_str().unwrap(), "short");
    }
}
