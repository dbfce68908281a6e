//! bssrdf-zoo: tabulated BSSRDF models for physically based rendering.
//!
//! The core model is photon beam diffusion (PBD) evaluated at any angle of incidence
//! (Habel, Christensen, Jarosz 2013; Ferrier 2016), with the angular table model of
//! Ferrier's report built on top of it.
//!
//! Conventions used everywhere in the crate:
//! - coefficients in mm⁻¹, distances in mm, unless a name says "reduced" or "optical":
//!   then distances are in reduced mean free paths (σ′t = 1);
//! - the incidence angle θ is measured from the surface normal *before* refraction;
//! - the exit point is at polar coordinates (r, φ) around the entry point, with
//!   **φ = 0 forward**: in the plane of incidence, on the side the refracted beam travels to;
//! - the API takes angles in radians; the command line takes degrees.

// `unsafe` is allowed in two modules only: the file mapping in `format::map`, and the C
// interface in `capi` (FFI cannot be written without it).
#![deny(unsafe_code)]

pub mod capi;
pub mod catmull_rom;
pub mod embed;
pub mod error;
mod float;
pub mod format;
pub mod fresnel;
pub mod gwc;
pub mod materials;
pub mod medium;
pub mod models;
pub mod pbd;
pub mod quadrature;
pub mod render;
pub mod rng;
pub mod scene;
pub mod table;
pub mod walk;

pub use error::{Error, Result};
