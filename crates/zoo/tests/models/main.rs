//! The models tests: one test binary, a module per area.

mod arbitrary_inputs;
mod compare;
mod dirpole;
mod properties;
mod render;
mod sampling;
