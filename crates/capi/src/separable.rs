//! For separable renderers (pbrt's `SeparableBSSRDF` and its kin): the exit distance drawn
//! alone, its density per mm and the angular factor S/S̄, through a channel handle
//! ([`bssrdf_channel_sample_radius`], [`bssrdf_channel_pdf_radius`],
//! [`bssrdf_channel_angular_factor`]) or with the medium given per call
//! ([`bssrdf_table_sample_radius`] and its siblings, checked as in `media.rs`); the batches are
//! in `batch.rs`. Each gives the bits of the runtime's `MediumRef` lookup of the same name (a
//! channel handle computes through one) under the crate's rules (a status, NULL checks,
//! `catch_unwind`, outputs written only on success), and none allocates, failing or not.

use bssrdf_runtime::embed::ChannelLookup;
use bssrdf_runtime::table::MediumRef;

use super::media::per_call;
use super::*;

/// The body of a lookup through a channel handle with one output: the handle and the output
/// checked, then `lookup` on the handle into `*out`.
///
/// # Safety
/// `channel` is NULL or a live handle; `out` is NULL or writable.
#[inline(always)]
pub(crate) unsafe fn per_channel<T>(
    channel: *const bssrdf_channel,
    (out, name): (*mut T, &'static CStr),
    lookup: impl FnOnce(&ChannelLookup) -> Result<T, Failure>,
) -> c_int {
    guard(|| {
        // SAFETY: the caller's contract.
        let lookup_handle = &unsafe { input(channel, c"channel is NULL") }?.lookup;
        // SAFETY: the caller's contract.
        let out = unsafe { output(out, name) }?;
        *out = lookup(lookup_handle)?;
        Ok(())
    })
}

/// Draws the exit distance for incidence θ from one uniform `u` ∈ [0, 1) into `*out_sample`
/// (r in mm, density per mm): the radial step of [`bssrdf_channel_sample`] (the same `u` gives
/// the same r), [`ChannelLookup::sample_radius`]. `BSSRDF_ERROR_NO_SAMPLE` where
/// `bssrdf_channel_sample` fails with it.
///
/// # Safety
/// `channel` is NULL or a live handle; `out_sample` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_sample_radius(
    channel: *const bssrdf_channel,
    theta: f64,
    u: f64,
    out_sample: *mut bssrdf_radial_sample,
) -> c_int {
    let sample = |h: &ChannelLookup| {
        let failure = || no_sample(&h.table().view(), h.rho_prime(), theta, u, None);
        Ok(h.sample_radius(theta, u).ok_or_else(failure)?.into())
    };
    // SAFETY: the function's contract.
    unsafe { per_channel(channel, (out_sample, c"out_sample is NULL"), sample) }
}

/// Density per mm of [`bssrdf_channel_sample_radius`] at `r_mm` (0 where it cannot sample),
/// stored in `*out_pdf` ([`ChannelLookup::pdf_radius`]).
///
/// # Safety
/// `channel` is NULL or a live handle; `out_pdf` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_pdf_radius(
    channel: *const bssrdf_channel,
    theta: f64,
    r_mm: f64,
    out_pdf: *mut f64,
) -> c_int {
    let pdf = |h: &ChannelLookup| match distance_or_angle_outside(Some(r_mm), None) {
        Some(failure) => Err(failure),
        None => density_at(h.pdf_radius(theta, r_mm), theta, || h.table().view()),
    };
    // SAFETY: the function's contract.
    unsafe { per_channel(channel, (out_pdf, c"out_pdf is NULL"), pdf) }
}

/// The angular factor S(r, φ; θ)/S̄(r; θ), dimensionless, stored in `*out_factor`
/// ([`ChannelLookup::angular_factor`]): [`bssrdf_channel_eval`] = S̄·factor with
/// S̄ = (1/2π) ∫ S dφ; `BSSRDF_ERROR_OUT_OF_RANGE` for θ outside the table.
///
/// # Safety
/// `channel` is NULL or a live handle; `out_factor` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_angular_factor(
    channel: *const bssrdf_channel,
    theta: f64,
    r_mm: f64,
    phi: f64,
    out_factor: *mut f64,
) -> c_int {
    let factor = |h: &ChannelLookup| {
        if let Some(failure) = distance_or_angle_outside(Some(r_mm), Some(phi)) {
            return Err(failure);
        }
        h.angular_factor(theta, r_mm, phi)
            .ok_or_else(|| theta_outside(theta, &h.table().view()))
    };
    // SAFETY: the function's contract.
    unsafe { per_channel(channel, (out_factor, c"out_factor is NULL"), factor) }
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
    let sample = |m: MediumRef| {
        let failure = || no_sample(&m.table(), m.rho_prime(), theta, u, None);
        Ok(m.sample_radius(theta, u).ok_or_else(failure)?.into())
    };
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
    let pdf = |m: MediumRef| match distance_or_angle_outside(Some(r_mm), None) {
        Some(failure) => Err(failure),
        None => density_at(m.pdf_radius(theta, r_mm), theta, || m.table()),
    };
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
    let factor = |m: MediumRef| {
        if let Some(failure) = distance_or_angle_outside(Some(r_mm), Some(phi)) {
            return Err(failure);
        }
        m.angular_factor(theta, r_mm, phi)
            .ok_or_else(|| theta_outside(theta, &m.table()))
    };
    // SAFETY: the function's contract.
    unsafe { per_call(medium, (out_factor, c"out_factor is NULL"), factor) }
}
