//! The diffuse reflectance of a library's table, for artists' colours: the reflectance A of a
//! medium ([`bssrdf_channel_diffuse_reflectance`] through a handle,
//! [`bssrdf_table_diffuse_reflectance`] with the medium given per call), the reduced albedo
//! that gives a reflectance ([`bssrdf_library_invert_albedo`]) and the reflectances a table
//! reaches ([`bssrdf_library_reflectance_range`]), over [`bssrdf_runtime::table::TableRef`]'s
//! `diffuse_reflectance` and its one inversion (`rho_prime_for_reflectance`,
//! `reflectance_range`). The header declares them in its section "Diffuse reflectance". The
//! module's rules are the crate's (`lib.rs`): a status, NULL checks, `catch_unwind`, outputs
//! written only on success. The forward lookups allocate nothing, failing or not, as every
//! lookup; the inversion and the range allocate nothing on success, and a failure formats its
//! message (it names the value and the range).

use std::ffi::c_int;

use bssrdf_runtime::table::ReflectanceError;

use bssrdf_runtime::embed::ChannelLookup;
use bssrdf_runtime::table::MediumRef;

use super::media::per_call;
use super::separable::per_channel;
use super::{
    bssrdf_channel, bssrdf_library, guard, input, output, theta_outside, Failure,
    BSSRDF_ERROR_OUT_OF_RANGE,
};

impl From<ReflectanceError> for Failure {
    fn from(e: ReflectanceError) -> Failure {
        Failure::text(BSSRDF_ERROR_OUT_OF_RANGE, e.to_string())
    }
}

/// Stores in `*out_rho_prime` the reduced albedo ρ′ whose diffuse reflectance on table `table`
/// at incidence `theta` (radians, before refraction) is `reflectance`:
/// A(ρ′, θ) = (1 − F_r(cos θ; η)) ρ_eff(ρ′, θ), the multiply scattered power leaving per unit
/// power arriving, the entry Fresnel transmittance included (single scattering is not in the
/// model). Solved on the table's own curve to its resolution, monotone in the reflectance.
/// `BSSRDF_ERROR_NOT_FOUND` for a table past the end; `BSSRDF_ERROR_OUT_OF_RANGE` for a
/// reflectance outside [`bssrdf_library_reflectance_range`] or NaN (the message names the value
/// and the range), θ outside the table or NaN, or no light entering at θ (grazing incidence,
/// beyond the critical angle).
///
/// # Safety
/// `library` is NULL or an open handle; `out_rho_prime` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_library_invert_albedo(
    library: *const bssrdf_library,
    table: usize,
    reflectance: f64,
    theta: f64,
    out_rho_prime: *mut f64,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let library = unsafe { input(library, c"library is NULL") }?;
        // SAFETY: the function's contract.
        let out = unsafe { output(out_rho_prime, c"out_rho_prime is NULL") }?;
        let lookup = library.library.table(table)?;
        *out = lookup
            .view()
            .rho_prime_for_reflectance(reflectance, theta)?;
        Ok(())
    })
}

/// Stores in `*out_min` and `*out_max` the diffuse reflectance of table `table` at incidence
/// `theta` (radians) at its first and its last albedo row: the reflectances
/// [`bssrdf_library_invert_albedo`] accepts there ([0, A(ρ′ = 1)] for a full table; [0, 0]
/// where no light enters). `BSSRDF_ERROR_NOT_FOUND` for a table past the end,
/// `BSSRDF_ERROR_OUT_OF_RANGE` for θ outside the table or NaN. (The same pointer for both
/// outputs gets the maximum.)
///
/// # Safety
/// `library` is NULL or an open handle; `out_min` and `out_max` are NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_library_reflectance_range(
    library: *const bssrdf_library,
    table: usize,
    theta: f64,
    out_min: *mut f64,
    out_max: *mut f64,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let library = unsafe { input(library, c"library is NULL") }?;
        if out_min.is_null() {
            return Err(Failure::null(c"out_min is NULL"));
        }
        if out_max.is_null() {
            return Err(Failure::null(c"out_max is NULL"));
        }
        let [min, max] = library
            .library
            .table(table)?
            .view()
            .reflectance_range(theta)?;
        // One output at a time: a caller may pass the same pointer twice (it then holds max).
        // SAFETY: the function's contract, and not NULL.
        *unsafe { output(out_min, c"out_min is NULL") }? = min;
        // SAFETY: the function's contract, and not NULL.
        *unsafe { output(out_max, c"out_max is NULL") }? = max;
        Ok(())
    })
}

/// Stores in `*out_reflectance` the diffuse reflectance A = (1 − F_r(cos θ; η)) ρ_eff(θ) of the
/// channel's medium for light arriving at incidence `theta` (radians, before refraction):
/// the inverse of [`bssrdf_library_invert_albedo`] ([`ChannelLookup::diffuse_reflectance`]).
/// `BSSRDF_ERROR_OUT_OF_RANGE` for θ outside the table or NaN. Allocates nothing.
///
/// # Safety
/// `channel` is NULL or a live handle; `out_reflectance` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_diffuse_reflectance(
    channel: *const bssrdf_channel,
    theta: f64,
    out_reflectance: *mut f64,
) -> c_int {
    let reflectance = |h: &ChannelLookup| {
        h.diffuse_reflectance(theta)
            .ok_or_else(|| theta_outside(theta, &h.table().view()))
    };
    let out = (out_reflectance, c"out_reflectance is NULL");
    // SAFETY: the function's contract.
    unsafe { per_channel(channel, out, reflectance) }
}

/// [`bssrdf_channel_diffuse_reflectance`] with the medium given per call
/// ([`MediumRef::diffuse_reflectance`]), checked as the other `bssrdf_table_*` lookups check
/// it; σ′t is checked but does not enter A. Allocates nothing, failing or not.
///
/// # Safety
/// `library` is NULL or an open handle; `out_reflectance` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_table_diffuse_reflectance(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    theta: f64,
    out_reflectance: *mut f64,
) -> c_int {
    let medium = (library, table, rho_prime, sigma_t_prime);
    let reflectance = |m: MediumRef| {
        m.diffuse_reflectance(theta)
            .ok_or_else(|| theta_outside(theta, &m.table()))
    };
    let out = (out_reflectance, c"out_reflectance is NULL");
    // SAFETY: the function's contract.
    unsafe { per_call(medium, out, reflectance) }
}
