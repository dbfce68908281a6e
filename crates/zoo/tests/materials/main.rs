//! The materials tests: one test binary, a module per area.

mod errors;
mod library;
