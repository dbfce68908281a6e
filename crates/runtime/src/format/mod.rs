//! The library file format: versioned, checksummed, memory-mappable files holding baked BSSRDF
//! tables, the materials that use them and how they were made. `format-spec.md` at the top of
//! the repository is the normative definition; this module implements it.
//!
//! Writing:
//! ```no_run
//! # use bssrdf_zoo::format::*;
//! # fn demo(table: TableData, skin: Material) -> Result<(), FormatError> {
//! let mut builder = LibraryBuilder::new();
//! let index = builder.add_table(table)?; // materials refer to tables by this index
//! builder.add_material(Material { tables: [index as u32; 3], ..skin })?;
//! builder.set_provenance(Provenance::new("bssrdf-zoo 0.1.0").with_bake_seconds(12.5)?);
//! builder.write_atomic("skin.bssrdf", Compression::None)?;
//! # Ok(()) }
//! ```
//! Reading:
//! ```no_run
//! # use bssrdf_zoo::format::*;
//! # fn demo() -> Result<(), FormatError> {
//! let library = Library::open_mmap("skin.bssrdf", Verify::Full)?;
//! for table in library.tables() {
//!     let rho: &[f32] = table.axis(AxisKind::Rho); // zero-copy view into the map
//!     let cdf = table.radial_cdf();
//!     # let _ = (rho, cdf);
//! }
//! # Ok(()) }
//! ```
//! Files opened with [`Library::open_mmap`] are mapped; another process truncating a mapped
//! file kills the reader with SIGBUS, so use [`Library::read`] for files that may change.
//!
//! Comparing two files (what `bssrdf diff` prints): [`diff::compare`].

mod atomic;
pub mod diff;
mod error;
mod library;
mod map;
mod provenance;
mod reader;
mod records;
pub mod spec;
mod writer;

pub use atomic::{check_writable, through_descriptor, write_file_atomic};
pub use error::{FormatError, FormatResult};
pub use library::{loose_name, Library, Table};
pub use provenance::{json_number, Provenance, KEY_ACCURACY};
pub use reader::{SectionInfo, Verify};
pub use records::{AlbedoRange, Material, TableHeader, CHANNELS};
pub use spec::{
    AxisKind, Codec, Dtype, FresnelMoments, ModelKind, SectionKind, WalkComponent, WalkSource,
};
pub use writer::{
    pack, unpack, zstd_levels, Compression, Conversion, ExtraSection, LibraryBuilder, TableData,
};
