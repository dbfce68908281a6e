//! The table tests: one test binary, a module per area.

#[path = "../catmull_rom_common/mod.rs"]
mod catmull_rom_common;
#[path = "../lookup_common/mod.rs"]
mod lookup_common;

mod arbitrary_inputs;
mod catmull_rom;
mod catmull_rom_even;
mod check;
mod far_tail;
mod lookup;
mod pinned;
mod subset;
