//! The C interface: [`bssrdf_runtime::embed`] behind `extern "C"` functions, declared for C in
//! `include/bssrdf_zoo.h` (written by hand; `crates/capi/tests/capi/header.rs` checks that it declares
//! exactly these functions, structs and constants with the same types).
//!
//! Rules every entry point follows:
//! - it returns a status (`BSSRDF_OK` = 0 or a `BSSRDF_ERROR_*` code), except the release
//!   functions (which return nothing) and the two message functions;
//! - on failure the message is kept in a **thread-local last error**
//!   ([`bssrdf_last_error_message`]), valid until the next failing call on the same thread;
//!   successful calls leave it untouched and do not allocate;
//! - every pointer argument is checked: NULL gives `BSSRDF_ERROR_NULL_POINTER`;
//! - no panic crosses the boundary: each body runs under `catch_unwind`, and a panic (a bug)
//!   gives `BSSRDF_ERROR_PANIC`. This needs `panic = "unwind"`, the default profile setting;
//! - outputs are written only on success, except handle outputs, set to NULL on failure.
//!
//! The lookups with the medium given per call are in `crates/capi/src/media.rs`, the separable
//! renderers' in `separable.rs`, the batches in `batch.rs`.
//!
//! Handles are opaque pointers to Rust values: `bssrdf_library` (from
//! [`bssrdf_library_open`], freed by [`bssrdf_library_close`]) and `bssrdf_channel` (from
//! [`bssrdf_library_channel`] or [`bssrdf_library_medium`], freed by
//! [`bssrdf_channel_release`]). A channel keeps the library's file open by itself, so the
//! library may be closed first. Both are immutable: any number of threads may use the same
//! handle at once; only closing or releasing it must not race with its other uses.
//!
//! This crate and `format::map` are the only places with `unsafe` code. Here it is only
//! pointer reads and writes at the boundary, and `#[no_mangle]` (which the lint also counts).
#![allow(unsafe_code)]
// C names, as the header spells them.
#![allow(non_camel_case_types)]

use std::cell::RefCell;
use std::ffi::{c_char, c_int, CStr, CString};
use std::fmt;
use std::panic::{catch_unwind, AssertUnwindSafe};

use bssrdf_runtime::embed::Rgb;
use bssrdf_runtime::embed::{ChannelLookup, EmbedError, Library, PathSample, Sample};
use bssrdf_runtime::error::Number;
use bssrdf_runtime::format::FormatError;
use bssrdf_runtime::table::TableRef;

mod error;
use error::*;
mod media;
pub use media::*;
// The separable renderers' lookups, through a handle and per call.
mod separable;
pub use separable::*;
// Batches of N points as structures of arrays.
mod batch;
pub use batch::*;
// The diffuse reflectance's inverse and range (header section "Diffuse reflectance").
mod reflectance;
pub use reflectance::{
    bssrdf_channel_diffuse_reflectance, bssrdf_library_invert_albedo,
    bssrdf_library_reflectance_range, bssrdf_table_diffuse_reflectance,
};

/// Success.
pub const BSSRDF_OK: c_int = 0;
/// A pointer argument was NULL.
pub const BSSRDF_ERROR_NULL_POINTER: c_int = 1;
/// An argument is invalid: unknown flag bits, a channel other than 0, 1, 2, a string that is
/// not UTF-8, a medium with σ′t not finite and in [1e-9, 1e12] mm⁻¹, a batch's array
/// misaligned or overlapping an output, or `n` too large.
pub const BSSRDF_ERROR_INVALID_ARGUMENT: c_int = 2;
/// The operating system refused to open, map or read the file.
pub const BSSRDF_ERROR_IO: c_int = 3;
/// The file is not a valid library file (the message names the check that failed).
pub const BSSRDF_ERROR_FORMAT: c_int = 4;
/// No material of that name, or no table of that index.
pub const BSSRDF_ERROR_NOT_FOUND: c_int = 5;
/// A value lies outside what the table covers: θ outside its θ axis (or NaN) in a lookup, or a
/// medium's ρ′ outside its albedo rows (or NaN) when a channel is made or in a per-call
/// lookup. Tables are never extrapolated.
pub const BSSRDF_ERROR_OUT_OF_RANGE: c_int = 6;
/// Sampling found nothing to sample: no energy stored there (ρ′ = 0, light beyond the critical
/// angle), θ outside the table, a radial uniform of 0 (or below about 1e-320: it draws the
/// entry point, whose density per area is infinite), or, for path sampling, a table baked
/// without θ sampling.
pub const BSSRDF_ERROR_NO_SAMPLE: c_int = 7;
/// A bug: the library panicked; the panic was caught at the boundary.
pub const BSSRDF_ERROR_PANIC: c_int = 8;

/// [`bssrdf_library_open`]: map the file read-only (the default, `0`).
pub const BSSRDF_OPEN_MAP: u32 = 0;
/// [`bssrdf_library_open`]: read the file into memory instead of mapping it (for files another
/// process may truncate while they are open, which kills a mapping process with SIGBUS).
pub const BSSRDF_OPEN_READ: u32 = 1;

/// An opened library file (opaque to C).
pub struct bssrdf_library {
    library: Library,
    /// Material names with their NUL, for [`bssrdf_library_material_name`].
    names: Vec<CString>,
}

/// The lookup handle of one medium on one table (opaque to C).
pub struct bssrdf_channel {
    lookup: ChannelLookup,
}

/// One draw of the exit point (see [`bssrdf_runtime::embed::Sample`]).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct bssrdf_sample {
    /// Exit distance, mm.
    pub r: f64,
    /// Exit azimuth, radians in [−π, π], 0 forward.
    pub phi: f64,
    /// Density per mm² of the exit plane.
    pub pdf: f64,
}

/// One draw of the exit distance alone (see [`bssrdf_runtime::table::RadialSample`]).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct bssrdf_radial_sample {
    /// Exit distance, mm.
    pub r: f64,
    /// Density per mm of the distance.
    pub pdf: f64,
}

/// One path-tracing draw (see [`bssrdf_runtime::embed::PathSample`]).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct bssrdf_path_sample {
    /// Incidence before refraction, radians.
    pub theta: f64,
    /// Exit distance, mm.
    pub r: f64,
    /// Exit azimuth relative to the plane of incidence, radians.
    pub phi: f64,
    /// Azimuth of the entry point seen from the exit point, radians.
    pub phi_prime: f64,
    /// Density of θ, per radian.
    pub pdf_theta: f64,
    /// Joint density pdf_theta · pdf(r, φ | θ) / (2π).
    pub pdf: f64,
}

impl From<Sample> for bssrdf_sample {
    fn from(s: Sample) -> Self {
        bssrdf_sample {
            r: s.r,
            phi: s.phi,
            pdf: s.pdf,
        }
    }
}

impl From<bssrdf_runtime::table::RadialSample> for bssrdf_radial_sample {
    fn from(s: bssrdf_runtime::table::RadialSample) -> Self {
        bssrdf_radial_sample { r: s.r, pdf: s.pdf }
    }
}

impl From<PathSample> for bssrdf_path_sample {
    fn from(p: PathSample) -> Self {
        bssrdf_path_sample {
            theta: p.theta,
            r: p.r,
            phi: p.phi,
            phi_prime: p.phi_prime,
            pdf_theta: p.pdf_theta,
            pdf: p.pdf,
        }
    }
}

/// What a channel handle looks up: its medium and table.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct bssrdf_channel_info {
    /// Reduced albedo ρ′ = σ′s/σ′t.
    pub rho_prime: f64,
    /// Reduced extinction σ′t, mm⁻¹.
    pub sigma_t_prime: f64,
    /// Relative index of refraction the table was baked for.
    pub eta: f64,
    /// Index of the table in the file.
    pub table: usize,
}

/// What a table of a library tabulates ([`bssrdf_library_table_info`]).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct bssrdf_table_info {
    /// Relative index of refraction the table was baked for.
    pub eta: f64,
    /// [`BSSRDF_MODEL_PBD_ANGULAR`] or [`BSSRDF_MODEL_WALK_ANGULAR`].
    pub model: u32,
    /// For a walk-angular table, [`BSSRDF_WALK_MULTIPLE`] or [`BSSRDF_WALK_TOTAL`]; 0 otherwise.
    pub walk_component: u32,
    /// For a walk-angular table, the Henyey–Greenstein g of its walk; NaN otherwise.
    pub walk_g: f64,
}

/// [`bssrdf_table_info::model`]: photon beam diffusion tabulated (format model 1).
pub const BSSRDF_MODEL_PBD_ANGULAR: u32 = 1;
/// [`bssrdf_table_info::model`]: the Monte Carlo walk tabulated for one g (format model 3).
pub const BSSRDF_MODEL_WALK_ANGULAR: u32 = 3;
/// [`bssrdf_table_info::walk_component`]: multiple scattering.
pub const BSSRDF_WALK_MULTIPLE: u32 = 0;
/// [`bssrdf_table_info::walk_component`]: everything that leaves, single scattering included.
pub const BSSRDF_WALK_TOTAL: u32 = 1;

/// The value behind a handle or input pointer, or a NULL-pointer failure naming it.
///
/// # Safety
/// `ptr` is NULL or points to a live, properly aligned `T` that nothing mutates during `'a`.
#[inline(always)]
unsafe fn input<'a, T>(ptr: *const T, name: &'static CStr) -> Result<&'a T, Failure> {
    // SAFETY: the caller's contract (the header's, passed on): NULL or a live, aligned T.
    unsafe { ptr.as_ref() }.ok_or_else(|| Failure::null(name))
}

/// The place an output goes, or a NULL-pointer failure naming it.
///
/// # Safety
/// `ptr` is NULL or points to writable, properly aligned memory for a `T` that nothing else
/// accesses during `'a` (its old contents are not read; `T` is `Copy` or a pointer).
#[inline(always)]
unsafe fn output<'a, T>(ptr: *mut T, name: &'static CStr) -> Result<&'a mut T, Failure> {
    // SAFETY: the caller's contract (the header's, passed on): NULL or writable, aligned T.
    unsafe { ptr.as_mut() }.ok_or_else(|| Failure::null(name))
}

/// A C string argument as UTF-8.
///
/// # Safety
/// `ptr` is NULL or points to a NUL-terminated string that stays valid during `'a`.
unsafe fn string<'a>(ptr: *const c_char, name: &'static CStr) -> Result<&'a str, Failure> {
    if ptr.is_null() {
        return Err(Failure::text(
            BSSRDF_ERROR_NULL_POINTER,
            format!("{} is NULL", name.to_string_lossy()),
        ));
    }
    // SAFETY: non-NULL, and the header requires a NUL-terminated string valid for the call.
    let text = unsafe { CStr::from_ptr(ptr) };
    text.to_str().map_err(|_| {
        Failure::text(
            BSSRDF_ERROR_INVALID_ARGUMENT,
            format!("{} is not UTF-8: {text:?}", name.to_string_lossy()),
        )
    })
}

/// Opens the library file at `path` (a NUL-terminated path; any bytes on Unix, UTF-8
/// elsewhere), validating all of it, and stores the new handle in `*out_library` (NULL on
/// failure). `flags` is `BSSRDF_OPEN_MAP` (0) or `BSSRDF_OPEN_READ`. A valid table no lookup
/// can interpolate does not fail the open; its lookups fail with `BSSRDF_ERROR_FORMAT`
/// (`embed::Library::from_format`).
///
/// # Safety
/// `path` is NULL or a NUL-terminated string; `out_library` is NULL or points to writable
/// storage for a pointer.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_library_open(
    path: *const c_char,
    flags: u32,
    out_library: *mut *mut bssrdf_library,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let out = unsafe { output(out_library, c"out_library is NULL") }?;
        *out = std::ptr::null_mut();
        if path.is_null() {
            return Err(Failure::null(c"path is NULL"));
        }
        // SAFETY: non-NULL, and the contract requires a NUL-terminated string.
        let bytes = unsafe { CStr::from_ptr(path) }.to_bytes();
        let path = path_of(bytes)?;
        let library = match flags {
            BSSRDF_OPEN_MAP => Library::open_mmap(path)?,
            BSSRDF_OPEN_READ => Library::read(path)?,
            other => {
                return Err(Failure::text(
                    BSSRDF_ERROR_INVALID_ARGUMENT,
                    format!(
                        "flags = {other:#x}: expected BSSRDF_OPEN_MAP (0) or BSSRDF_OPEN_READ (1)"
                    ),
                ))
            }
        };
        let names = library
            .materials()
            .iter()
            .map(|m| CString::new(m.name.as_str()).unwrap_or_default())
            .collect();
        *out = Box::into_raw(Box::new(bssrdf_library { library, names }));
        Ok(())
    })
}

#[cfg(unix)]
fn path_of(bytes: &[u8]) -> Result<&std::path::Path, Failure> {
    use std::os::unix::ffi::OsStrExt;
    Ok(std::path::Path::new(std::ffi::OsStr::from_bytes(bytes)))
}

#[cfg(not(unix))]
fn path_of(bytes: &[u8]) -> Result<&std::path::Path, Failure> {
    std::str::from_utf8(bytes)
        .map(std::path::Path::new)
        .map_err(|_| Failure::fixed(BSSRDF_ERROR_INVALID_ARGUMENT, c"path is not UTF-8"))
}

/// Closes a library handle (NULL is allowed and does nothing). Channels made from it stay
/// valid: the file is unmapped when the last of them is released.
///
/// # Safety
/// `library` is NULL or a handle from [`bssrdf_library_open`] not yet closed, which no other
/// thread is using.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_library_close(library: *mut bssrdf_library) {
    // SAFETY: the contract: NULL or a pointer from `Box::into_raw` in `bssrdf_library_open`,
    // closed once.
    unsafe { release(library) }
}

/// Stores the number of tables (one per η baked) in `*out_count`.
///
/// # Safety
/// `library` is NULL or an open handle; `out_count` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_library_table_count(
    library: *const bssrdf_library,
    out_count: *mut usize,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let library = unsafe { input(library, c"library is NULL") }?;
        // SAFETY: the function's contract.
        *unsafe { output(out_count, c"out_count is NULL") }? = library.library.table_count();
        Ok(())
    })
}

/// Stores in `*out_info` what table `index` tabulates: its η, model, and for a walk-angular
/// table the walk's g and component. [`BSSRDF_ERROR_NOT_FOUND`] for an index past the end.
///
/// # Safety
/// `library` is NULL or an open handle; `out_info` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_library_table_info(
    library: *const bssrdf_library,
    index: usize,
    out_info: *mut bssrdf_table_info,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let library = unsafe { input(library, c"library is NULL") }?;
        // SAFETY: the function's contract.
        let out = unsafe { output(out_info, c"out_info is NULL") }?;
        let count = library.library.table_count();
        let table = library.library.format().table(index).ok_or_else(|| {
            Failure::text(
                BSSRDF_ERROR_NOT_FOUND,
                format!("no table {index}: the library holds {count}"),
            )
        })?;
        let walk = table.walk();
        *out = bssrdf_table_info {
            eta: table.eta(),
            model: table.model().code(),
            walk_component: walk.map_or(0, |w| w.component.code()),
            walk_g: walk.map_or(f64::NAN, |w| w.g),
        };
        Ok(())
    })
}

/// Stores the number of materials in `*out_count`.
///
/// # Safety
/// `library` is NULL or an open handle; `out_count` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_library_material_count(
    library: *const bssrdf_library,
    out_count: *mut usize,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let library = unsafe { input(library, c"library is NULL") }?;
        // SAFETY: the function's contract.
        *unsafe { output(out_count, c"out_count is NULL") }? = library.names.len();
        Ok(())
    })
}

/// Stores in `*out_name` the name of material `index` (UTF-8, NUL-terminated, owned by the
/// library: valid until it is closed).
///
/// # Safety
/// `library` is NULL or an open handle; `out_name` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_library_material_name(
    library: *const bssrdf_library,
    index: usize,
    out_name: *mut *const c_char,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let library = unsafe { input(library, c"library is NULL") }?;
        // SAFETY: the function's contract.
        let out = unsafe { output(out_name, c"out_name is NULL") }?;
        let name = library.names.get(index).ok_or_else(|| {
            Failure::text(
                BSSRDF_ERROR_NOT_FOUND,
                format!(
                    "no material {index}: the library holds {}",
                    library.names.len()
                ),
            )
        })?;
        *out = name.as_ptr();
        Ok(())
    })
}

/// Makes the lookup handle of colour channel `channel` (0 red, 1 green, 2 blue) of the
/// material called `material`, stored in `*out_channel` (NULL on failure). Release it with
/// [`bssrdf_channel_release`].
///
/// # Safety
/// `library` is NULL or an open handle; `material` is NULL or a NUL-terminated string;
/// `out_channel` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_library_channel(
    library: *const bssrdf_library,
    material: *const c_char,
    channel: c_int,
    out_channel: *mut *mut bssrdf_channel,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let out = unsafe { output(out_channel, c"out_channel is NULL") }?;
        *out = std::ptr::null_mut();
        // SAFETY: the function's contract.
        let library = unsafe { input(library, c"library is NULL") }?;
        // SAFETY: the function's contract.
        let name = unsafe { string(material, c"material") }?;
        let rgb = match channel {
            0 => Rgb::Red,
            1 => Rgb::Green,
            2 => Rgb::Blue,
            other => {
                return Err(Failure::text(
                    BSSRDF_ERROR_INVALID_ARGUMENT,
                    format!("channel = {other}: expected 0 (red), 1 (green) or 2 (blue)"),
                ))
            }
        };
        let lookup = library.library.channel(name, rgb)?;
        *out = Box::into_raw(Box::new(bssrdf_channel { lookup }));
        Ok(())
    })
}

/// Makes the lookup handle of a medium of reduced albedo `rho_prime` and reduced extinction
/// `sigma_t_prime` (mm⁻¹) on table `table`, for media that are not material records of the
/// file; stored in `*out_channel` (NULL on failure).
///
/// # Safety
/// `library` is NULL or an open handle; `out_channel` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_library_medium(
    library: *const bssrdf_library,
    table: usize,
    rho_prime: f64,
    sigma_t_prime: f64,
    out_channel: *mut *mut bssrdf_channel,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let out = unsafe { output(out_channel, c"out_channel is NULL") }?;
        *out = std::ptr::null_mut();
        // SAFETY: the function's contract.
        let library = unsafe { input(library, c"library is NULL") }?;
        let lookup = library
            .library
            .table(table)?
            .medium(rho_prime, sigma_t_prime)?;
        *out = Box::into_raw(Box::new(bssrdf_channel { lookup }));
        Ok(())
    })
}

/// Releases a channel handle (NULL is allowed and does nothing).
///
/// # Safety
/// `channel` is NULL or a handle not yet released, which no other thread is using.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_release(channel: *mut bssrdf_channel) {
    // SAFETY: the contract: NULL or a pointer from `Box::into_raw` in this module, released once.
    unsafe { release(channel) }
}

/// Frees a handle made by `Box::into_raw`; NULL does nothing. Dropping a handle cannot panic (an
/// `Arc` decrement and perhaps an unmap), but it stays inside the panic guard all the same.
///
/// # Safety
/// `handle` is NULL or a pointer from `Box::into_raw` of a `T`, freed once, which no other
/// thread is using.
unsafe fn release<T>(handle: *mut T) {
    if handle.is_null() {
        return;
    }
    // SAFETY: the caller's contract.
    let handle = unsafe { Box::from_raw(handle) };
    let _ = catch_unwind(AssertUnwindSafe(move || drop(handle)));
}

/// Stores the channel's ρ′, σ′t, η and table index in `*out_info`.
///
/// # Safety
/// `channel` is NULL or a live handle; `out_info` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_get_info(
    channel: *const bssrdf_channel,
    out_info: *mut bssrdf_channel_info,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let lookup = &unsafe { input(channel, c"channel is NULL") }?.lookup;
        // SAFETY: the function's contract.
        *unsafe { output(out_info, c"out_info is NULL") }? = bssrdf_channel_info {
            rho_prime: lookup.rho_prime(),
            sigma_t_prime: lookup.sigma_t_prime(),
            eta: lookup.table().eta(),
            table: lookup.table().index(),
        };
        Ok(())
    })
}

/// The failure of a lookup at θ outside `table`'s θ axis (evaluation, effective albedo,
/// reflectance, angular factor): names θ and the θ the table takes
/// ([`TableRef::theta_domain`]), formatted without allocating.
#[cold]
fn theta_outside(theta: f64, table: &TableRef<'_>) -> Failure {
    let [lo, hi] = table.theta_domain().map(Number);
    Failure::inline(
        BSSRDF_ERROR_OUT_OF_RANGE,
        format_args!(
            "theta = {} rad is outside the table's theta axis [{lo}, {hi}] rad (a table is never extrapolated)",
            Number(theta)
        ),
    )
}

/// The failure of a lookup at r not a distance in [0, ∞) (NaN, ±∞ or negative; with `r_mm`) or
/// φ not finite (with `phi`), naming the value, without allocating; `None` inside. Finite r
/// beyond the table's last radius is inside: the value there is 0, as the profile's far tail is.
#[inline]
fn distance_or_angle_outside(r_mm: Option<f64>, phi: Option<f64>) -> Option<Failure> {
    if let Some(r) = r_mm.filter(|r| !(r.is_finite() && *r >= 0.0)) {
        let why = format_args!("r = {} mm is outside [0, inf): a distance", Number(r));
        return Some(Failure::inline(BSSRDF_ERROR_OUT_OF_RANGE, why));
    }
    if let Some(phi) = phi.filter(|phi| !phi.is_finite()) {
        let why = format_args!("phi = {} rad is not a finite angle", Number(phi));
        return Some(Failure::inline(BSSRDF_ERROR_OUT_OF_RANGE, why));
    }
    None
}

/// A density `value` looked up at θ, or θ's failure where θ is outside the table's axis. A
/// density is 0 there, so the axis (`table`, the lookup's view) is read only where the value is
/// not positive: a lookup that found density pays nothing for the check.
#[inline]
fn density_at<'t>(
    value: f64,
    theta: f64,
    table: impl FnOnce() -> TableRef<'t>,
) -> Result<f64, Failure> {
    if value > 0.0 {
        return Ok(value);
    }
    let table = table();
    if table.keeps_theta(theta) {
        Ok(value)
    } else {
        Err(theta_outside(theta, &table))
    }
}

/// The failure of a draw with nothing to sample, naming its cause, formatted without
/// allocating: θ outside the table, u_r outside [0, 1] (or NaN), a u_φ outside [0, 1)
/// (`None` for the radial draw, which takes none), no energy stored for the medium (ρ′) at θ, or u_r at 0 (the
/// entry point itself, of infinite density per area).
#[cold]
fn no_sample(table: &TableRef<'_>, rho: f64, theta: f64, u_r: f64, u_phi: Option<f64>) -> Failure {
    let code = BSSRDF_ERROR_NO_SAMPLE;
    let [lo, hi] = table.theta_domain().map(Number);
    let (theta_n, u_n) = (Number(theta), Number(u_r));
    if !table.keeps_theta(theta) {
        let why = format_args!(
            "no sample: theta = {theta_n} rad is outside the table's theta axis [{lo}, {hi}] rad"
        );
        return Failure::inline(code, why);
    }
    if !(0.0..=1.0).contains(&u_r) {
        return Failure::inline(
            code,
            format_args!("no sample: u_r = {u_n} is outside [0, 1]"),
        );
    }
    if let Some(u_phi) = u_phi.filter(|u| !u.is_finite()) {
        let why = format_args!("no sample: u_phi = {} is not finite", Number(u_phi));
        return Failure::inline(code, why);
    }
    if let Some(u_phi) = u_phi.filter(|u| !(0.0..1.0).contains(u)) {
        let why = format_args!(
            "no sample: u_phi = {} is outside [0, 1): a uniform random number",
            Number(u_phi)
        );
        return Failure::inline(code, why);
    }
    if !table.effective_albedo(rho, theta).is_some_and(|a| a > 0.0) {
        let why = format_args!(
            "no sample: the table stores no energy for rho' = {} at theta = {theta_n} rad (none at rho' = 0 or beyond the critical angle)",
            Number(rho)
        );
        return Failure::inline(code, why);
    }
    // Uniforms of 53 bits are 0 or at least 2^-53; far below, the draw is the entry point
    if u_r < 1e-300 {
        let why = format_args!("no sample: u_r = {u_n} {AT_THE_ENTRY_POINT}");
        return Failure::inline(code, why);
    }
    if u_r >= 1.0 {
        return Failure::inline(code, format_args!("no sample: u_r = {u_n} {PAST_THE_END}"));
    }
    let why = format_args!(
        "no sample at theta = {theta_n} rad, u_r = {u_n}: the draw fell where the table holds no energy"
    );
    Failure::inline(code, why)
}

/// Why a radial uniform of 0 (or below about 10⁻³²⁰) draws nothing, on a table whose radii
/// start at 0.
const AT_THE_ENTRY_POINT: &str =
    "draws the entry point itself (r = 0, of infinite density per area)";

/// Why a radial uniform of 1 draws nothing: the uniforms are in [0, 1), and 1 inverts the
/// radial distribution at its end, the last radius, where the density is 0.
const PAST_THE_END: &str =
    "is the end of [0, 1): it draws the last radius, where the table holds no energy";

/// The failure of a path draw with nothing to sample, naming its cause, formatted without
/// allocating: no θ sampling in the table, a uniform that is not finite, a uniform outside
/// [0, 1) (the radial uniform u[1] at 0, the entry point, or 1, the last radius), or no
/// energy stored for the medium (ρ′) at any θ.
#[cold]
fn no_path_sample(table: &TableRef<'_>, rho: f64, u: [f64; 4]) -> Failure {
    let code = BSSRDF_ERROR_NO_SAMPLE;
    if !table.has_theta_sampling() {
        return Failure::fixed(
            code,
            c"no sample: the table was baked without theta sampling (bake it with theta sampling for path draws)",
        );
    }
    if let Some(k) = u.iter().position(|u| !u.is_finite()) {
        let why = format_args!("no sample: u[{k}] = {} is not finite", Number(u[k]));
        return Failure::inline(code, why);
    }
    if let Some(k) = u[..2].iter().position(|u| !(0.0..=1.0).contains(u)) {
        let why = format_args!("no sample: u[{k}] = {} is outside [0, 1]", Number(u[k]));
        return Failure::inline(code, why);
    }
    // (u[0] = 1 as u[2] and u[3]: the uniforms are in [0, 1), a 1 is a broken stream)
    if let Some(k) = [0, 2, 3].into_iter().find(|&k| !(0.0..1.0).contains(&u[k])) {
        let why = format_args!(
            "no sample: u[{k}] = {} is outside [0, 1): a uniform random number",
            Number(u[k])
        );
        return Failure::inline(code, why);
    }
    // (as `no_sample`'s u_r)
    if u[1] < 1e-300 {
        let why = format_args!("no sample: u[1] = {} {AT_THE_ENTRY_POINT}", Number(u[1]));
        return Failure::inline(code, why);
    }
    if u[1] >= 1.0 {
        let why = format_args!("no sample: u[1] = {} {PAST_THE_END}", Number(u[1]));
        return Failure::inline(code, why);
    }
    let why = format_args!(
        "no sample: the table stores no energy for rho' = {} where the draw fell (none at rho' = 0)",
        Number(rho)
    );
    Failure::inline(code, why)
}

/// S_p(r, φ; θ) in mm⁻², stored in `*out_value` (see [`ChannelLookup::eval`]): θ in radians
/// before refraction, r in mm, φ in radians with 0 forward. `BSSRDF_ERROR_OUT_OF_RANGE` for θ
/// outside the table, r NaN, infinite or negative, or φ not finite.
///
/// # Safety
/// `channel` is NULL or a live handle; `out_value` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_eval(
    channel: *const bssrdf_channel,
    theta: f64,
    r_mm: f64,
    phi: f64,
    out_value: *mut f64,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let lookup = &unsafe { input(channel, c"channel is NULL") }?.lookup;
        // SAFETY: the function's contract.
        let out = unsafe { output(out_value, c"out_value is NULL") }?;
        if let Some(failure) = distance_or_angle_outside(Some(r_mm), Some(phi)) {
            return Err(failure);
        }
        *out = (lookup.eval(theta, r_mm, phi))
            .ok_or_else(|| theta_outside(theta, &lookup.table().view()))?;
        Ok(())
    })
}

/// Density per mm² of [`bssrdf_channel_sample`] at (r, φ) (0 where it cannot sample), stored in
/// `*out_pdf`. `BSSRDF_ERROR_OUT_OF_RANGE` at a point outside the domain of
/// [`bssrdf_channel_eval`].
///
/// # Safety
/// `channel` is NULL or a live handle; `out_pdf` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_pdf(
    channel: *const bssrdf_channel,
    theta: f64,
    r_mm: f64,
    phi: f64,
    out_pdf: *mut f64,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let lookup = &unsafe { input(channel, c"channel is NULL") }?.lookup;
        // SAFETY: the function's contract.
        let out = unsafe { output(out_pdf, c"out_pdf is NULL") }?;
        if let Some(failure) = distance_or_angle_outside(Some(r_mm), Some(phi)) {
            return Err(failure);
        }
        *out = density_at(lookup.pdf(theta, r_mm, phi), theta, || {
            lookup.table().view()
        })?;
        Ok(())
    })
}

/// Draws the exit point for incidence θ from two uniforms in [0, 1) into `*out_sample` (r in
/// mm, φ, density per mm²). `BSSRDF_ERROR_NO_SAMPLE` where there is nothing to sample.
///
/// # Safety
/// `channel` is NULL or a live handle; `out_sample` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_sample(
    channel: *const bssrdf_channel,
    theta: f64,
    u_r: f64,
    u_phi: f64,
    out_sample: *mut bssrdf_sample,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let lookup = &unsafe { input(channel, c"channel is NULL") }?.lookup;
        // SAFETY: the function's contract.
        let out = unsafe { output(out_sample, c"out_sample is NULL") }?;
        *out = (lookup.sample(theta, u_r, u_phi))
            .ok_or_else(|| {
                let table = lookup.table().view();
                no_sample(&table, lookup.rho_prime(), theta, u_r, Some(u_phi))
            })?
            .into();
        Ok(())
    })
}

/// The path-tracing draw from the four uniforms `u[0..4]` in [0, 1) into `*out_sample`.
/// `BSSRDF_ERROR_NO_SAMPLE` without θ sampling in the table or where there is nothing to sample.
///
/// # Safety
/// `channel` is NULL or a live handle; `u` is NULL or points to 4 readable doubles;
/// `out_sample` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_sample_path(
    channel: *const bssrdf_channel,
    u: *const f64,
    out_sample: *mut bssrdf_path_sample,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let lookup = &unsafe { input(channel, c"channel is NULL") }?.lookup;
        // SAFETY: the contract: 4 readable doubles, and [f64; 4] has the alignment of f64.
        let u = *unsafe { input(u.cast::<[f64; 4]>(), c"u is NULL") }?;
        // SAFETY: the function's contract.
        let out = unsafe { output(out_sample, c"out_sample is NULL") }?;
        *out = (lookup.sample_path(u))
            .ok_or_else(|| no_path_sample(&lookup.table().view(), lookup.rho_prime(), u))?
            .into();
        Ok(())
    })
}

/// Density of θ in [`bssrdf_channel_sample_path`], per radian (0 without θ sampling), stored in
/// `*out_pdf`. `BSSRDF_ERROR_OUT_OF_RANGE` for θ outside the table.
///
/// # Safety
/// `channel` is NULL or a live handle; `out_pdf` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_pdf_theta(
    channel: *const bssrdf_channel,
    theta: f64,
    out_pdf: *mut f64,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let lookup = &unsafe { input(channel, c"channel is NULL") }?.lookup;
        // SAFETY: the function's contract.
        let out = unsafe { output(out_pdf, c"out_pdf is NULL") }?;
        *out = density_at(lookup.pdf_theta(theta), theta, || lookup.table().view())?;
        Ok(())
    })
}

/// Effective albedo ρ_eff(θ) (dimensionless) stored in `*out_albedo`.
/// `BSSRDF_ERROR_OUT_OF_RANGE` for θ outside the table.
///
/// # Safety
/// `channel` is NULL or a live handle; `out_albedo` is NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn bssrdf_channel_effective_albedo(
    channel: *const bssrdf_channel,
    theta: f64,
    out_albedo: *mut f64,
) -> c_int {
    guard(|| {
        // SAFETY: the function's contract.
        let lookup = &unsafe { input(channel, c"channel is NULL") }?.lookup;
        // SAFETY: the function's contract.
        let out = unsafe { output(out_albedo, c"out_albedo is NULL") }?;
        *out = (lookup.effective_albedo(theta))
            .ok_or_else(|| theta_outside(theta, &lookup.table().view()))?;
        Ok(())
    })
}

/// The message of the last failed call on this thread (UTF-8, NUL-terminated; "no error" if
/// none failed yet). Valid until the next failing call on this thread; never NULL.
#[no_mangle]
pub extern "C" fn bssrdf_last_error_message() -> *const c_char {
    catch_unwind(|| {
        LAST_ERROR
            .try_with(|slot| {
                let slot = slot.borrow();
                // The pointer outlives the borrow: the CString is replaced, and so freed, and
                // the buffer rewritten, only by a later failing call on this thread, which the
                // contract rules out.
                match &slot.message {
                    Message::Static(s) => s.as_ptr(),
                    Message::Inline => slot.inline.bytes.as_ptr().cast(),
                    Message::Owned(s) => s.as_ptr(),
                }
            })
            .unwrap_or(c"error message unavailable during thread teardown".as_ptr())
    })
    .unwrap_or(c"internal error".as_ptr())
}

/// The constant's name of a status code ("BSSRDF_OK", "BSSRDF_ERROR_IO", …), or
/// "unknown status"; a static string.
#[no_mangle]
pub extern "C" fn bssrdf_status_name(status: c_int) -> *const c_char {
    let name: &'static CStr = match status {
        BSSRDF_OK => c"BSSRDF_OK",
        BSSRDF_ERROR_NULL_POINTER => c"BSSRDF_ERROR_NULL_POINTER",
        BSSRDF_ERROR_INVALID_ARGUMENT => c"BSSRDF_ERROR_INVALID_ARGUMENT",
        BSSRDF_ERROR_IO => c"BSSRDF_ERROR_IO",
        BSSRDF_ERROR_FORMAT => c"BSSRDF_ERROR_FORMAT",
        BSSRDF_ERROR_NOT_FOUND => c"BSSRDF_ERROR_NOT_FOUND",
        BSSRDF_ERROR_OUT_OF_RANGE => c"BSSRDF_ERROR_OUT_OF_RANGE",
        BSSRDF_ERROR_NO_SAMPLE => c"BSSRDF_ERROR_NO_SAMPLE",
        BSSRDF_ERROR_PANIC => c"BSSRDF_ERROR_PANIC",
        _ => c"unknown status",
    };
    name.as_ptr()
}

#[cfg(test)]
mod tests {
    //! What only the module itself can check; the rest of the boundary's rules are tested
    //! through the exported functions in `crates/capi/tests/capi/rust.rs` (from Rust) and `crates/capi/tests/capi/c_program.rs`
    //! (from C).

    use super::*;

    fn last_error() -> String {
        // SAFETY: a NUL-terminated string valid until the next failing call on this thread.
        unsafe { CStr::from_ptr(bssrdf_last_error_message()) }
            .to_string_lossy()
            .into_owned()
    }

    #[test]
    fn a_panic_is_caught_and_reported() {
        let status = guard(|| panic!("deliberate"));
        assert_eq!(status, BSSRDF_ERROR_PANIC);
        assert!(last_error().contains("panicked"), "{}", last_error());
        assert_eq!(guard(|| Ok(())), BSSRDF_OK);
        assert!(
            last_error().contains("panicked"),
            "success leaves the message"
        );
    }

    #[test]
    fn the_last_error_is_per_thread() {
        let status = guard(|| Err(Failure::text(BSSRDF_ERROR_IO, "on this thread".into())));
        assert_eq!(status, BSSRDF_ERROR_IO);
        let other = std::thread::spawn(last_error).join().unwrap();
        assert_eq!(other, "no error");
        assert_eq!(last_error(), "on this thread");
    }
}
