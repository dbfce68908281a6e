//! bssrdf-runtime: what a renderer links to use bssrdf-zoo's tables. It reads, maps and writes
//! the library-file format ([`mod@format`]) and evaluates and importance-samples the angular table
//! it holds ([`table`], [`embed`]); the bake, the physics behind it and the command line live
//! in the crates above it (`bssrdf-zoo`, `bssrdf-cli`; docs/architecture.md).
//!
//! Conventions used everywhere:
//! - coefficients in mm⁻¹, distances in mm, unless a name says "reduced" or "optical":
//!   then distances are in reduced mean free paths (σ′t = 1);
//! - the incidence angle θ is measured from the surface normal *before* refraction;
//! - the exit point is at polar coordinates (r, φ) around the entry point, with
//!   **φ = 0 forward**: in the plane of incidence, on the side the refracted beam travels to;
//! - the API takes angles in radians; the command line takes degrees.

// `unsafe` is allowed in one module only: the file mapping in `format::map`.
#![deny(unsafe_code)]

pub mod catmull_rom;
pub mod embed;
pub mod error;
#[doc(hidden)]
pub mod float;
pub mod format;
pub mod fresnel;
pub mod gwc;
pub mod medium;
pub mod quadrature;
pub mod table;

pub use error::{Error, Result};
