//! The models tests: one test binary, a module per area.

#[path = "../lookup_common/mod.rs"]
mod lookup_common;
#[path = "../models_common/mod.rs"]
mod models_common;

mod arbitrary_inputs;
mod compare;
mod dirpole;
mod properties;
mod render;
mod sampling;
