//! The gwc tests: one test binary, a module per area.

#[path = "../gwc_common/mod.rs"]
mod gwc_common;

mod fit;
mod minimax;
mod profile;
mod two_lobe;
