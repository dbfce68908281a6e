//! Embedding in a renderer: the runtime's [`Library`] and its lookup handles
//! ([`bssrdf_runtime::embed`], re-exported here), and the in-memory bake of a library for
//! named materials.

pub use bssrdf_runtime::embed::*;

use crate::bake::{BakeError, BakeGrid, Baker, MaterialSpec};
use crate::materials::Material;

/// Bakes a library in memory, with no file: the library `bssrdf bake MATERIAL…` writes, made by
/// the same pipeline ([`Baker::bake`] with its defaults: exact Fresnel moments, the lobes of
/// each η, θ sampling kept). One table per distinct η of `materials`, each checked by the
/// bake's own check, one record each with its file's citation as source, and the same
/// provenance (module docs of [`crate::bake`]). `grid` is a [`GridPreset`](crate::table::GridPreset)
/// (then `bake_library(&[skin], GridPreset::Default)` gives the file of
/// `bssrdf bake skin1` bit for bit) or one [`Grid`](crate::table::Grid) for every table.
///
/// A table above the check's bound is kept, not refused: its regions are in the provenance's
/// `accuracy`. To decide on it, or to keep the check's results, call [`Baker::bake`] and
/// [`BakedLibrary::passes`](crate::bake::BakedLibrary::passes).
/// The default grid takes about half a second per η on two cores; the check adds about 5 %.
///
/// ```
/// use bssrdf_zoo::embed::bake_library;
/// use bssrdf_zoo::table::{Grid, GridPreset};
/// let materials = bssrdf_zoo::materials::Library::builtin();
/// let skin = materials.get("skin1")?;
/// # let grid = Grid::ferrier(6, 4, 10);
/// # /*
/// let grid = GridPreset::Default;
/// # */
/// let library = bake_library(&[skin], grid)?;
/// assert_eq!(library.materials()[0].name, "skin1");
/// let provenance = library.format().provenance().expect("a bake records its provenance");
/// assert!(provenance.get("accuracy").is_some());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn bake_library(
    materials: &[&Material],
    grid: impl Into<BakeGrid>,
) -> Result<Library, BakeError> {
    let specs = materials
        .iter()
        .map(|m| MaterialSpec::named(m))
        .collect::<Result<Vec<_>, _>>()?;
    Baker::new(grid).bake(&specs, &[], None)?.into_library()
}
