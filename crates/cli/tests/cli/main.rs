//! End-to-end tests of the `bssrdf` command line: one test binary, a module per area.

mod bake_check;
mod bake_library;
mod bake_walk;
mod basics;
mod common;
mod completions;
mod diff;
mod doc_numbers;
mod edges;
mod files;
mod invert;
mod outputs;
mod promises;
mod render;
mod rough_edges;
mod scene;
mod values;
