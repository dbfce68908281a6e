//! The models tests: one test binary, a module per area.

#[path = "../models_common/mod.rs"]
mod models_common;

mod compare;
mod dirpole;
mod properties;
mod sampling;
