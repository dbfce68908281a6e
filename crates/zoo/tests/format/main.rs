//! The format tests: one test binary, a module per area.

mod c_reader;
mod conformance;
mod corruption;
mod harmonics;
mod mapping;
mod proptest;
mod ridge;
mod roundtrip;
mod spec_example;
mod walk;
