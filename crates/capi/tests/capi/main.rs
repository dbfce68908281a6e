//! The C interface tests: one test binary, a module per area.

#[path = "../../../zoo/tests/lookup_common/mod.rs"]
mod lookup_common;

mod arbitrary_inputs;
mod c_program;
mod fixture;
mod header;
mod rust;
mod threads;
