//! Helpers shared by the tests of the workspace's crates and by the fuzz targets (a
//! development crate: nothing the libraries ship depends on it).

pub mod files;
pub mod gwc;
pub mod lookups;
pub mod models;
pub mod splines;
pub mod stats;
