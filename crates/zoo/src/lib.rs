//! bssrdf-zoo: tabulated BSSRDF models for physically based rendering, on top of
//! `bssrdf-runtime` (the file format and the table lookups, re-exported here).
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

#![forbid(unsafe_code)]

// The runtime's parts, whole (the layer below: docs/architecture.md).
use bssrdf_runtime::float;
pub use bssrdf_runtime::{catmull_rom, error, format, fresnel, medium, quadrature};

// The runtime's parts this crate adds to: the bake of tables, the fits of the GWC profile, the
// in-memory bake of a library.
pub mod embed;
pub mod gwc;
pub mod table;

pub mod bake;
pub mod materials;
pub mod models;
pub mod pbd;
pub mod render;
pub mod rng;
pub mod scene;
pub mod walk;

pub use error::{Error, Result};

/// Most threads a bake, walk or render may ask for (`--threads`, Python's `threads=`): far
/// more than any machine this runs on has cores, and few enough that spawning them cannot
/// exhaust the system (5,000 threads made a tiny bake take 19 s).
pub const MAX_THREADS: usize = 1024;
