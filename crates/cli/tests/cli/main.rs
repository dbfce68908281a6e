//! End-to-end tests of the `bssrdf` command line: one test binary, a module per area.

#[path = "../cli_common/mod.rs"]
mod cli_common;

mod bake_check;
mod bake_library;
mod basics;
mod diff;
mod files;
mod outputs;
mod promises;
mod render;
mod rough_edges;
mod scene;
mod values;
