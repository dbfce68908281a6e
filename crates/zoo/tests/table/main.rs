//! The tests of the angular table: its profile (`gwc`), splines, lookups, bake, check and
//! subsets, and the renderer handles over a file (`embed`). One test binary, a module per area.

mod arbitrary_inputs;
mod artist;
mod below_critical;
mod catmull_rom;
mod catmull_rom_even;
mod check;
mod embed;
mod embed_bake;
mod far_tail;
mod gwc;
mod lookup;
mod pinned;
mod reflectance;
mod ridge;
mod separable;
mod subset;
mod walk;
