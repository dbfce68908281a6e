//! An opened library with every table prepared for lookups, and the per-table handle.

use std::path::Path;
use std::sync::Arc;

use super::{ChannelLookup, EmbedError};
use zerocopy::FromBytes;

use super::Rgb;
use crate::format::{self, Compression, LibraryBuilder, SectionKind, Verify};
use crate::gwc::Rebuild;
use crate::medium::{Boundary, Medium};
use crate::table::{Axes, FileTable, TableError, TableRef};

/// What every handle shares: the file and, per table, what [`TableRef::new`] derives from it
/// once (axes in f64, C_E of the boundary) after checking it.
struct Inner {
    file: format::Library,
    /// Per table of the file, in file order: its lookups, or why it takes none (a valid file
    /// may hold a table no lookup can interpolate: one node on an axis, η outside the domain).
    tables: Vec<Result<Prepared, TableError>>,
}

/// A table's lookups minus its arrays, which stay in `file` and are borrowed per lookup
/// through the directory positions of their sections (found once: a lookup by position is a
/// few bounds checks, where `format::Table`'s lookup by kind walks the table's section map).
struct Prepared {
    axes: Axes,
    eta: f64,
    boundary: Boundary,
    /// Directory positions of the gwc-params, radial-cdf and theta-cdf sections.
    params: usize,
    radial_cdf: usize,
    theta_cdf: Option<usize>,
    /// Position of the harmonics section of a two-lobe table.
    harmonics: Option<usize>,
    /// How its lookups rebuild the lobes (the file's rule).
    rebuild: Rebuild,
    /// A two-lobe table's `table::harmonic_shares_of`, computed at open: 28 bytes per node,
    /// which take its lookups from dividing 16 rows × 4 nodes each to one blend.
    shares: Option<Vec<f32>>,
    /// What its nodes hold less, the ridge its lookups add back (the record's `ridge`).
    ridge: crate::table::RidgeKind,
}

impl Inner {
    /// The view of table `index` (< `tables.len()`), with or without the θ-sampling CDF.
    #[inline]
    fn view(&self, index: usize, theta_cdf: bool) -> TableRef<'_> {
        let (p, file) = (self.prepared(index), &self.file);
        TableRef::prevalidated(
            p.eta,
            p.boundary,
            &p.axes,
            floats(file, p.params),
            floats(file, p.radial_cdf),
            p.theta_cdf.filter(|_| theta_cdf).map(|t| floats(file, t)),
        )
        .prevalidated_harmonics(
            p.harmonics.map(|h| floats(file, h)),
            p.rebuild,
            p.shares.as_deref(),
        )
        .with_ridge(p.ridge)
    }

    /// The lookups of table `index`, which a handle was made for: [`Library::table`] and
    /// [`Library::view`] make none for a table without lookups.
    fn prepared(&self, index: usize) -> &Prepared {
        match &self.tables[index] {
            Ok(prepared) => prepared,
            Err(_) => unreachable!("a handle of table {index}, which takes no lookups"),
        }
    }

    /// Table `index`'s lookups checked: [`EmbedError::NoTable`] beyond the file's tables,
    /// [`EmbedError::Table`] for one that takes no lookups.
    fn check(&self, index: usize) -> Result<(), EmbedError> {
        match self.tables.get(index) {
            Some(Ok(_)) => Ok(()),
            Some(Err(source)) => Err(EmbedError::Table {
                index,
                source: source.clone(),
            }),
            None => Err(EmbedError::NoTable {
                index,
                count: self.tables.len(),
            }),
        }
    }
}

/// An opened library file, every table validated and prepared for lookups.
///
/// Cheap to clone (one `Arc`) and `Send + Sync`; handles made from it keep it alive.
///
/// ```
/// # use bssrdf_zoo::embed::Library;
/// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
/// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
/// let shared = library.clone(); // shares the file: no copy
/// std::thread::spawn(move || assert_eq!(shared.table_count(), 1)).join().unwrap();
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone)]
pub struct Library {
    inner: Arc<Inner>,
}

impl std::fmt::Debug for Library {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Library")
            .field("file", &self.inner.file)
            .finish()
    }
}

impl Library {
    /// Maps the file read-only and validates all of it (checksums and every value finite).
    /// Lookups read the map directly. Another process truncating the file while it is mapped
    /// kills this process with SIGBUS: use [`Library::read`] for files that may change.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let path = tempfile::tempdir()?.keep().join("scene.bssrdf");
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?.write(&path)?;
    /// let library = Library::open_mmap(&path)?;
    /// assert!(library.format().is_mapped());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn open_mmap(path: impl AsRef<Path>) -> Result<Library, EmbedError> {
        Library::from_format(format::Library::open_mmap(path, Verify::Full)?)
    }

    /// Reads the whole file into memory and validates it: safe against files that change.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let path = tempfile::tempdir()?.keep().join("scene.bssrdf");
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?.write(&path)?;
    /// let library = Library::read(&path)?;
    /// assert!(!library.format().is_mapped());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn read(path: impl AsRef<Path>) -> Result<Library, EmbedError> {
        Library::from_format(format::Library::read(path, Verify::Full)?)
    }

    /// Prepares an already opened file: checks every table's arrays against its axes and for
    /// finite values (O(size), once) and converts the axes. A file opened with
    /// [`Verify::HeaderOnly`] is therefore still fully checked for NaN here, though not for
    /// section checksums. A table no lookup can interpolate (one node on an axis, η outside
    /// [0.75, 2.5]: the format allows both) does not fail the file: [`Library::table`] and
    /// [`Library::view`] refuse it with the reason, and its record stays readable.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// use bssrdf_zoo::format::{self, Verify};
    /// # let path = tempfile::tempdir()?.keep().join("scene.bssrdf");
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?.write(&path)?;
    /// let file = format::Library::open_mmap(&path, Verify::HeaderOnly)?;
    /// let library = Library::from_format(file)?;
    /// # let _ = library;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_format(file: format::Library) -> Result<Library, EmbedError> {
        let mut tables = Vec::with_capacity(file.table_count());
        for (index, record) in file.tables().enumerate() {
            let table = match FileTable::new(record) {
                Ok(table) => table,
                Err(reason) => {
                    tables.push(Err(reason));
                    continue;
                }
            };
            let view = match table.view() {
                Ok(view) => view,
                Err(reason) => {
                    tables.push(Err(reason));
                    continue;
                }
            };
            let eta = view.eta();
            // `TableRef::new` accepted η, so this cannot fail; it is the boundary exactly as it
            // computed it.
            let boundary =
                Boundary::new(eta, table.moments()).map_err(|source| EmbedError::Medium {
                    what: format!("table {index}"),
                    source,
                })?;
            let position = |kind: SectionKind| {
                file.sections()
                    .iter()
                    .position(|s| s.table == Some(index) && s.kind == kind.code())
            };
            let unlocated = || EmbedError::Sections { index };
            let prepared = Prepared {
                axes: view.axes().clone(),
                eta,
                boundary,
                params: position(SectionKind::GwcParams).ok_or_else(unlocated)?,
                radial_cdf: position(SectionKind::RadialCdf).ok_or_else(unlocated)?,
                theta_cdf: position(SectionKind::ThetaCdf),
                harmonics: position(SectionKind::Harmonics),
                rebuild: view.rebuild(),
                shares: view.harmonics().map(|h| {
                    let n_r = view.axes().dims().2;
                    let params = table.record().gwc_params();
                    crate::table::harmonic_shares_of(params, h, n_r, view.rebuild())
                }),
                ridge: view.ridge(),
            };
            // The arrays found by position must be the very ones `TableRef::new` just checked.
            let same =
                |position: usize, checked: &[f32]| std::ptr::eq(floats(&file, position), checked);
            let record = table.record();
            let located = same(prepared.params, record.gwc_params())
                && same(prepared.radial_cdf, record.radial_cdf())
                && match (prepared.theta_cdf, record.theta_cdf()) {
                    (Some(position), Some(checked)) => same(position, checked),
                    (None, None) => true,
                    _ => false,
                }
                && match (prepared.harmonics, view.harmonics()) {
                    (Some(position), Some(checked)) => same(position, checked),
                    (None, None) => true,
                    _ => false,
                };
            if !located {
                return Err(unlocated());
            }
            tables.push(Ok(prepared));
        }
        Ok(Library {
            inner: Arc::new(Inner { file, tables }),
        })
    }

    /// Writes the library to `path` atomically (a mappable, uncompressed file).
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let path = tempfile::tempdir()?.keep().join("scene.bssrdf");
    /// library.write(&path)?;
    /// assert_eq!(Library::open_mmap(&path)?.materials(), library.materials());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), EmbedError> {
        LibraryBuilder::from_library(&self.inner.file)?.write_atomic(path, Compression::None)?;
        Ok(())
    }

    /// The underlying file: version, sections, provenance, raw table arrays.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// assert_eq!(library.format().version().0, 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn format(&self) -> &format::Library {
        &self.inner.file
    }

    /// Number of tables (one per η baked).
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// assert_eq!(library.table_count(), 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn table_count(&self) -> usize {
        self.inner.tables.len()
    }

    /// Table `index` (materials refer to tables by index), or [`EmbedError::NoTable`].
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let table = library.table(0)?;
    /// assert_eq!(table.eta(), 1.3);
    /// assert!(library.table(1).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn table(&self, index: usize) -> Result<TableLookup, EmbedError> {
        self.inner.check(index)?;
        Ok(TableLookup {
            inner: Arc::clone(&self.inner),
            index,
        })
    }

    /// Table `index`'s lookups in reduced units, borrowed from the library: what
    /// [`TableLookup::view`] gives, without making a handle (no reference to count), for media
    /// given per call ([`TableRef::medium`]) and batches ([`TableRef::eval_n`]). O(1), allocates
    /// nothing; [`EmbedError::NoTable`] for an index past the end.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// // Per shading point, a textured medium: ρ′ and σ′t (mm⁻¹) from its textures
    /// let (rho_prime, sigma_t_prime) = (0.93, 1.7);
    /// let medium = library.view(0)?.medium(rho_prime, sigma_t_prime)?;
    /// assert!(medium.eval(0.5, 0.2, 0.0).unwrap() > 0.0); // mm⁻²
    /// assert!(library.view(1).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn view(&self, index: usize) -> Result<TableRef<'_>, EmbedError> {
        self.inner.check(index)?;
        Ok(self.inner.view(index, true))
    }

    /// Every table that takes lookups, in file order ([`Library::table_count`] counts them
    /// all; [`Library::table`] says why one takes none).
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// for table in library.tables() {
    ///     println!("table {}: eta = {}", table.index(), table.eta());
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn tables(&self) -> impl Iterator<Item = TableLookup> + '_ {
        (0..self.inner.tables.len())
            .filter(|&index| self.inner.tables[index].is_ok())
            .map(|index| TableLookup {
                inner: Arc::clone(&self.inner),
                index,
            })
    }

    /// The material records of the file, in file order (name, source, σs, σa, g, η, tables).
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let names: Vec<&str> = library.materials().iter().map(|m| m.name.as_str()).collect();
    /// assert_eq!(names, ["skin1"]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn materials(&self) -> &[format::Material] {
        self.inner.file.materials()
    }

    /// The lookup handle of one colour channel of the material called `name`: its table, its
    /// ρ′ = σ′s/σ′t and its σ′t = σs(1 − g) + σa (mm⁻¹). Fails if there is no such material, the
    /// channel is vacuum, or ρ′ lies outside the table's albedo rows.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// use bssrdf_zoo::materials::Rgb;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let [r, g, b] = Rgb::ALL.map(|c| library.channel("skin1", c));
    /// let (r, g, b) = (r?, g?, b?);
    /// assert!(r.rho_prime() > g.rho_prime() && g.rho_prime() > b.rho_prime());
    /// assert!(library.channel("skin2", Rgb::Red).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn channel(&self, name: &str, channel: Rgb) -> Result<ChannelLookup, EmbedError> {
        let materials = self.materials();
        let Some(m) = materials.iter().find(|m| m.name == name) else {
            let known = if materials.is_empty() {
                "none".to_owned()
            } else {
                let names: Vec<String> =
                    materials.iter().map(|m| format!("{:?}", m.name)).collect();
                names.join(", ")
            };
            return Err(EmbedError::NoMaterial {
                name: name.to_owned(),
                known,
            });
        };
        let c = channel.index();
        let what = || format!("material {name:?}, channel {}", channel.name());
        let medium = Medium::new(m.sigma_s[c], m.sigma_a[c], m.g[c], m.eta).map_err(|source| {
            EmbedError::Medium {
                what: what(),
                source,
            }
        })?;
        self.table(m.tables[c] as usize)?.medium_named(
            medium.rho_prime(),
            medium.sigma_t_prime(),
            what,
        )
    }
}

/// The f32 values of the section at directory position `index` (aligned and a multiple of 4
/// bytes long: checked when the file was opened).
#[inline]
fn floats(file: &format::Library, index: usize) -> &[f32] {
    <[f32]>::ref_from_bytes(file.section_bytes(index)).unwrap_or_default()
}

/// One table of a library (one η): a handle for lookups in reduced units through
/// [`TableLookup::view`], and the maker of [`ChannelLookup`]s for any medium.
///
/// Cheap to clone (one `Arc`), `Send + Sync`, keeps the library alive.
///
/// ```
/// # use bssrdf_zoo::embed::Library;
/// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
/// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
/// let table = library.table(0)?;
/// drop(library); // the handle keeps the file open
/// assert!(table.view().eval(0.9, 0.5, 1.0, 0.0).is_some());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone)]
pub struct TableLookup {
    inner: Arc<Inner>,
    index: usize,
}

impl std::fmt::Debug for TableLookup {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TableLookup")
            .field("index", &self.index)
            .field("eta", &self.eta())
            .finish()
    }
}

impl TableLookup {
    /// Position of the table in the file.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// assert_eq!(library.table(0)?.index(), 0);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn index(&self) -> usize {
        self.index
    }

    fn prepared(&self) -> &Prepared {
        // `index` was checked when the handle was made; the tables never change.
        self.inner.prepared(self.index)
    }

    /// Relative index of refraction η the table was baked for.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// assert_eq!(library.table(0)?.eta(), skin.eta());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn eta(&self) -> f64 {
        self.prepared().eta
    }

    /// The table's lookups in reduced units (ρ′ explicit, r in reduced mean free paths): the
    /// full [`TableRef`] API. O(1) and allocation-free: it borrows the file's arrays and the
    /// prepared axes, which were checked when the library was opened.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// let table = library.table(0)?;
    /// let view = table.view();
    /// let rho_eff = view.effective_albedo(0.9, 0.0).unwrap();
    /// assert!(rho_eff > 0.0 && rho_eff < 1.0);
    /// assert!(view.has_theta_sampling());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    #[inline]
    pub fn view(&self) -> TableRef<'_> {
        self.view_with(true)
    }

    /// The view, with or without the θ-sampling CDF: only `sample_path` and `pdf_theta` read
    /// it, so the other lookups skip locating it (one section fewer per call).
    #[inline]
    pub(super) fn view_with(&self, theta_cdf: bool) -> TableRef<'_> {
        self.inner.view(self.index, theta_cdf)
    }

    /// A handle for a medium of reduced albedo ρ′ = σ′s/σ′t and reduced extinction σ′t (mm⁻¹)
    /// on this table: for media that are not material records of the file (η is the table's).
    /// Fails if σ′t is not finite and in [1e-9, 1e12] mm⁻¹ (the range of
    /// [`crate::medium::Medium`]) or ρ′ lies outside the table's albedo rows.
    ///
    /// ```
    /// # use bssrdf_zoo::embed::Library;
    /// # let skin = bssrdf_zoo::materials::Library::builtin().get("skin1")?.clone();
    /// # let library = bssrdf_zoo::embed::bake_library(&[&skin], &bssrdf_zoo::table::Grid::ferrier(6, 4, 10))?;
    /// use bssrdf_zoo::medium::Medium;
    /// let wax = Medium::new(2.0, 0.01, 0.5, 1.3)?; // σs, σa (mm⁻¹), g, η
    /// let lookup = library.table(0)?.medium(wax.rho_prime(), wax.sigma_t_prime())?;
    /// assert!(lookup.eval(0.0, 1.0, 0.0).unwrap() > 0.0);
    /// assert!(library.table(0)?.medium(0.5, 0.0).is_err()); // σ′t = 0: vacuum
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn medium(&self, rho_prime: f64, sigma_t_prime: f64) -> Result<ChannelLookup, EmbedError> {
        self.medium_named(rho_prime, sigma_t_prime, || "medium".to_owned())
    }

    fn medium_named(
        &self,
        rho: f64,
        sigma_t_prime: f64,
        what: impl Fn() -> String,
    ) -> Result<ChannelLookup, EmbedError> {
        let medium_error = |source| EmbedError::Medium {
            what: what(),
            source,
        };
        crate::medium::check_sigma_t_prime(sigma_t_prime).map_err(medium_error)?;
        let axes = &self.prepared().axes;
        if !axes.keeps_rho(rho) {
            let [min, max] = axes.rho_domain();
            return Err(EmbedError::AlbedoOutsideTable {
                what: what(),
                rho,
                table: self.index,
                min,
                max,
            });
        }
        Ok(ChannelLookup::new(self.clone(), rho, sigma_t_prime))
    }
}
