//! The tests of the physics: photon beam diffusion (`pbd`) and the named media (`materials`).
//! One test binary, a module per area.

mod materials;
mod pbd;
