//! The tests of the angular table: its profile (`gwc`), splines, lookups, bake, check and
//! subsets, and the renderer handles over a file (`embed`). One test binary, a module per area.

#[path = "../catmull_rom_common/mod.rs"]
mod catmull_rom_common;
#[path = "../gwc_common/mod.rs"]
mod gwc_common;
#[path = "../lookup_common/mod.rs"]
mod lookup_common;

mod arbitrary_inputs;
mod catmull_rom;
mod catmull_rom_even;
mod check;
mod embed;
mod embed_bake;
mod far_tail;
mod gwc;
mod lookup;
mod pinned;
mod subset;
