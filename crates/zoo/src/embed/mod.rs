//! Embedding in a renderer: the runtime's [`Library`] and its lookup handles
//! ([`bssrdf_runtime::embed`], re-exported here), and the in-memory bake of a library for
//! named materials.

pub use bssrdf_runtime::embed::*;

use std::collections::BTreeMap;

use crate::format::{self, Compression, LibraryBuilder, Verify};
use crate::fresnel::Moments;
use crate::table::{bake, Grid};

/// Bakes a library in memory, with no file: one table per distinct η of `materials` (exact
/// Fresnel moments, θ sampling kept) and one material record each, like `bssrdf bake`
/// (without its provenance record).
/// The default grid takes about half a second per η on two cores.
///
/// ```
/// use bssrdf_zoo::embed::bake_library;
/// use bssrdf_zoo::table::{Grid, GridPreset};
/// let materials = bssrdf_zoo::materials::Library::builtin();
/// let skin = materials.get("skin1")?;
/// # let grid = Grid::ferrier(6, 4, 10);
/// # /*
/// let grid = Grid::preset(GridPreset::Default);
/// # */
/// let library = bake_library(&[skin], &grid)?;
/// assert_eq!(library.materials()[0].name, "skin1");
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn bake_library(
    materials: &[&crate::materials::Material],
    grid: &Grid,
) -> Result<Library, EmbedError> {
    let mut builder = LibraryBuilder::new();
    let mut table_of_eta = BTreeMap::new();
    for m in materials {
        if let std::collections::btree_map::Entry::Vacant(slot) =
            table_of_eta.entry(m.eta().to_bits())
        {
            let (table, _) = bake(m.eta(), Moments::Exact, grid, true).map_err(EmbedError::Bake)?;
            slot.insert(builder.add_table(table.to_table_data())? as u32);
        }
    }
    for m in materials {
        builder.add_material(format::Material {
            name: m.id().to_owned(),
            source: String::new(),
            sigma_s: m.sigma_s(),
            sigma_a: m.sigma_a(),
            g: m.g(),
            eta: m.eta(),
            tables: [table_of_eta[&m.eta().to_bits()]; 3],
            albedo_range: None,
        })?;
    }
    let bytes = builder.to_bytes(Compression::None)?;
    Library::from_format(format::Library::from_bytes(&bytes, Verify::Full)?)
}
