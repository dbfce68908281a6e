//! The renderer-facing API: open a library file once, then evaluate and sample its BSSRDFs in
//! world units from any thread, without allocating.
//!
//! | type | what | cost to clone |
//! |---|---|---|
//! | [`Library`] | an opened library file (mapped or read) with every table prepared | one `Arc` |
//! | [`TableLookup`] | one table (one η), reduced units, through [`TableLookup::view`] | one `Arc` |
//! | [`ChannelLookup`] | one medium on one table: ρ′ and σ′t fixed, r in mm, S in mm⁻² | one `Arc` |
//!
//! All three are `Send + Sync` and `'static`: a handle keeps the library (and its map) alive,
//! so it can outlive the [`Library`] it came from. Opening validates the whole file (structure,
//! checksums, every value finite) and converts each table's axes once; afterwards a lookup
//! borrows the mapped arrays, checks nothing it already checked, and never allocates (tested
//! with a counting allocator in `crates/capi/tests/embed_alloc.rs`).
//!
//! Units: coefficients in mm⁻¹, distances in mm, S and densities per mm², angles in radians;
//! θ is the incidence angle before refraction, φ = 0 is forward (in the plane of incidence, on
//! the side the refracted beam travels to). The C interface over this module is
//! the `bssrdf-capi` crate (header `include/bssrdf_zoo.h`).
//!
//! ```
//! use bssrdf_zoo::embed::Library;
//! use bssrdf_zoo::materials::Rgb;
//! # use bssrdf_zoo::table::Grid;
//! # let path = tempfile::tempdir()?.keep().join("scene.bssrdf");
//! # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
//! # bssrdf_zoo::embed::bake_library(&[&skin], &Grid::ferrier(6, 4, 10))?.write(&path)?;
//! // Once, at scene load (`bssrdf bake skin1 -o scene.bssrdf` made the file):
//! let library = Library::open_mmap(&path)?;
//! let green = library.channel("skin1", Rgb::Green)?;
//!
//! // Per shading point, from any thread: S_p(r, φ; θ) in mm⁻² at r = 0.5 mm.
//! let theta = 30f64.to_radians();
//! let s = green.eval(theta, 0.5, 0.0).expect("θ within the table");
//! assert!(s > 0.0);
//! // Importance sampling of the exit point, with its density per mm².
//! if let Some(hit) = green.sample(theta, 0.3, 0.7) {
//!     // The density returned with a sample is `pdf` at that point (to rounding).
//!     assert!((hit.pdf / green.pdf(theta, hit.r, hit.phi) - 1.0).abs() < 1e-12);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod channel;
mod library;

pub use channel::{ChannelLookup, PathSample, Sample};
pub use library::{Library, TableLookup};

use crate::error::Number;
use crate::format::FormatError;
use crate::table::TableError;

/// A colour channel of the RGB coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Rgb {
    Red,
    Green,
    Blue,
}

impl Rgb {
    /// The three channels in file order.
    pub const ALL: [Rgb; 3] = [Rgb::Red, Rgb::Green, Rgb::Blue];

    /// Position in a `[R, G, B]` array.
    pub fn index(self) -> usize {
        self as usize
    }

    /// Lowercase name: `red`, `green`, `blue`.
    pub fn name(self) -> &'static str {
        match self {
            Rgb::Red => "red",
            Rgb::Green => "green",
            Rgb::Blue => "blue",
        }
    }
}

/// Why a library could not be opened or a handle could not be made. Lookups themselves never
/// fail with an error: they return `Option` or a zero density.
///
/// ```
/// use bssrdf_zoo::embed::{EmbedError, Library};
/// let err = Library::open_mmap("/no/such/file.bssrdf").unwrap_err();
/// assert!(matches!(err, EmbedError::Format(_)));
/// assert!(err.to_string().contains("/no/such/file.bssrdf"));
/// ```
#[derive(Debug, thiserror::Error)]
pub enum EmbedError {
    /// The file cannot be read, or is not a valid library file.
    #[error(transparent)]
    Format(#[from] FormatError),
    /// A table's arrays are inconsistent with its axes (the format's checks catch this first).
    #[error("table {index}: {source}")]
    Table {
        /// Position of the table in the file.
        index: usize,
        /// What is wrong with it.
        source: TableError,
    },
    /// A table's sections could not be located in the file's directory (a bug: the format's
    /// checks guarantee them).
    #[error("table {index}: its sections could not be located in the file's directory")]
    Sections {
        /// Position of the table in the file.
        index: usize,
    },
    /// No material of that name is in the file.
    #[error("no material named {name:?} in the library (it has {known})")]
    NoMaterial {
        /// The name asked for.
        name: String,
        /// The names the library has, quoted, or "none".
        known: String,
    },
    /// No table of that index is in the file.
    #[error("no table {index}: the library holds {count} table(s)")]
    NoTable {
        /// The index asked for.
        index: usize,
        /// How many tables there are.
        count: usize,
    },
    /// A medium's coefficients are invalid: σ′t not finite and in [1e-9, 1e12] mm⁻¹ in
    /// [`TableLookup::medium`]
    /// (material records were validated when the file was opened; this also covers them).
    #[error("{what}: {source}")]
    Medium {
        /// The material and channel, or "medium".
        what: String,
        /// The rejected value.
        source: crate::Error,
    },
    /// The medium's reduced albedo lies outside the albedo rows the table keeps (a scene bake
    /// may keep only some): tables are never extrapolated.
    #[error(
        "{what}: reduced albedo rho' = {} is outside [{}, {}], the albedo range table {table} keeps; the table is never extrapolated",
        Number(*rho),
        Number(*min),
        Number(*max)
    )]
    AlbedoOutsideTable {
        /// The material and channel, or "medium".
        what: String,
        /// ρ′ of the medium.
        rho: f64,
        /// The table's index.
        table: usize,
        /// First ρ′ node of the table.
        min: f64,
        /// Last ρ′ node of the table.
        max: f64,
    },
}
