//! Lookups with the medium given per call, on a table of an open library, without a channel
//! handle: [`bssrdf_table_eval`] and its siblings, each point with its own ρ′ and σ′t: a
//! textured medium or a spectral renderer's wavelengths on one table (one η). The separable
//! renderers' per-call lookups are in `separable.rs`, the diffuse reflectance's in
//! `reflectance.rs`, and the batches of N points (structures of arrays) in `batch.rs`.
//! Declared in `include/bssrdf_zoo.h` beside the rest; the crate's rules hold (statuses, the
//! thread's last error, NULL checks, no panic across, outputs written only on success), and
//! nothing here allocates, failing or not: messages are formatted into a fixed buffer
//! ([`Failure::inline`]).
//!
//! A single lookup checks the medium as [`bssrdf_library_medium`] does, with the same codes
//! (`BSSRDF_ERROR_INVALID_ARGUMENT` for σ′t, `BSSRDF_ERROR_OUT_OF_RANGE` for ρ′) and a message
//! naming the value and its range, and gives the channel handle's bits for the same medium.

use bssrdf_runtime::table::{MediumRef, TableRef};
use bssrdf_runtime::Error;

use super::*;

/// Table `table` of an open library, or a failure.
///
/// # Safety
/// `library` is NULL or an open handle.
#[inline(always)]
pub(crate) unsafe fn table_view<'a>(
    library: *const bssrdf_library,
    table: usize,
) -> Result<TableRef<'a>, Failure> {
    // SAFETY: the caller's contract.
    let library = unsafe { input(library, c"library is NULL") }?;
    library
        .library
        .view(table)
        .map_err(|e| Failure::inline(super::error::embed_code(&e), format_args!("{e}")))
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
pub(crate) unsafe fn per_call<T>(
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
    let eval = |m: MediumRef| match distance_or_angle_outside(Some(r_mm), Some(phi)) {
        Some(failure) => Err(failure),
        None => m
            .eval(theta, r_mm, phi)
            .ok_or_else(|| theta_outside(theta, &m.table())),
    };
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
    let pdf = |m: MediumRef| match distance_or_angle_outside(Some(r_mm), Some(phi)) {
        Some(failure) => Err(failure),
        None => density_at(m.pdf(theta, r_mm, phi), theta, || m.table()),
    };
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
    let sample = |m: MediumRef| {
        let failure = || no_sample(&m.table(), m.rho_prime(), theta, u_r, Some(u_phi));
        Ok(m.sample(theta, u_r, u_phi).ok_or_else(failure)?.into())
    };
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
        let failure = || no_path_sample(&m.table(), m.rho_prime(), u);
        Ok(m.sample_path(u).ok_or_else(failure)?.into())
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
    let pdf_theta = |m: MediumRef| density_at(m.pdf_theta(theta), theta, || m.table());
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
    let albedo = |m: MediumRef| {
        m.effective_albedo(theta)
            .ok_or_else(|| theta_outside(theta, &m.table()))
    };
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_albedo, c"out_albedo is NULL"), albedo) }
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
