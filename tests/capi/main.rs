//! The C interface tests: one test binary, a module per area.

mod c_program;
mod header;
mod rust;
