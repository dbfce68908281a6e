//! The C interface tests: one test binary, a module per area.

mod arbitrary_inputs;
mod c_program;
mod fixture;
mod header;
mod media;
mod reflectance;
mod rust;
mod threads;
