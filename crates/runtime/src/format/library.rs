//! An opened library file: its tables with zero-copy `&[f32]` views, its materials and its
//! provenance.

use std::path::Path;

use zerocopy::FromBytes;

use super::error::FormatResult;
use super::map::{AlignedBuf, Backing};
use super::provenance::Provenance;
use super::reader::{parse, Parsed, SectionInfo, Verify};
use super::records::{Material, TableHeader};
use super::spec::{
    AxisKind, Codec, FresnelMoments, ModelKind, SectionKind, WalkSource, VERSION_MAJOR,
};
use crate::gwc::Rebuild;

/// A validated library file, mapped or in memory. Cheap to share between threads.
pub struct Library {
    backing: Backing,
    parsed: Parsed,
}

impl std::fmt::Debug for Library {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Library")
            .field("mapped", &self.is_mapped())
            .field("sections", &self.parsed.entries.len())
            .field("tables", &self.parsed.tables.len())
            .field("materials", &self.parsed.materials.len())
            .finish()
    }
}

impl Library {
    /// Maps the file read-only and validates it. Table views point into the map (zstd
    /// sections are decoded into aligned buffers instead). Another process truncating the file
    /// while it is mapped kills this process with SIGBUS: use [`Library::read`] for files that
    /// may change underneath.
    pub fn open_mmap(path: impl AsRef<Path>, verify: Verify) -> FormatResult<Library> {
        Library::from_backing(Backing::map(path.as_ref())?, verify)
    }

    /// Reads the whole file into an aligned buffer and validates it.
    pub fn read(path: impl AsRef<Path>, verify: Verify) -> FormatResult<Library> {
        Library::from_backing(Backing::read(path.as_ref())?, verify)
    }

    /// Validates a file held in memory (copied into an aligned buffer first).
    pub fn from_bytes(bytes: &[u8], verify: Verify) -> FormatResult<Library> {
        Library::from_backing(Backing::Owned(AlignedBuf::copy_from(bytes)), verify)
    }

    fn from_backing(backing: Backing, verify: Verify) -> FormatResult<Library> {
        let parsed = parse(backing.bytes(), verify)?;
        Ok(Library { backing, parsed })
    }

    /// Runs the checks [`Verify::Full`] adds: every section CRC, a NaN scan of every table
    /// section and the `gwc-params` node rules (format-spec.md §10, including a negative floor
    /// E_β > E without the `signed-floor` feature bit). Useful after opening with
    /// [`Verify::HeaderOnly`].
    pub fn verify(&self) -> FormatResult<()> {
        self.parsed.verify_data(self.backing.bytes())
    }

    /// Format version of the file as (major, minor).
    pub fn version(&self) -> (u16, u16) {
        (VERSION_MAJOR, self.parsed.minor)
    }

    /// Required feature bits the file sets.
    pub fn required_features(&self) -> u64 {
        self.parsed.required_features
    }

    /// Optional feature bits the file sets (unknown ones are ignored).
    pub fn optional_features(&self) -> u64 {
        self.parsed.optional_features
    }

    /// Section alignment the file declares, in bytes.
    pub fn alignment(&self) -> u32 {
        self.parsed.alignment
    }

    /// Size of the file in bytes.
    pub fn file_size(&self) -> usize {
        self.backing.bytes().len()
    }

    /// True if the library is a map of its file.
    pub fn is_mapped(&self) -> bool {
        self.backing.is_mapped()
    }

    /// True if any section is zstd-compressed (a distribution file; `unpack` makes it mappable).
    pub fn is_compressed(&self) -> bool {
        self.parsed.entries.iter().any(|e| e.codec == Codec::Zstd)
    }

    /// The directory, in file order.
    pub fn sections(&self) -> &[SectionInfo] {
        &self.parsed.entries
    }

    /// Decoded bytes of the file-level section with kind code `kind`, if present. Extension
    /// kinds that this reader does not know are reachable this way.
    pub fn file_section(&self, kind: u32) -> Option<&[u8]> {
        let index = *self.parsed.file_sections.get(&kind)?;
        Some(self.section_bytes(index))
    }

    pub(crate) fn section_bytes(&self, index: usize) -> &[u8] {
        self.parsed.section_bytes(self.backing.bytes(), index)
    }

    /// Number of tables.
    pub fn table_count(&self) -> usize {
        self.parsed.tables.len()
    }

    /// The tables, in file order.
    pub fn tables(&self) -> impl ExactSizeIterator<Item = Table<'_>> + '_ {
        (0..self.parsed.tables.len()).map(move |index| Table {
            library: self,
            index,
        })
    }

    /// Table `index`, if it exists.
    pub fn table(&self, index: usize) -> Option<Table<'_>> {
        (index < self.parsed.tables.len()).then_some(Table {
            library: self,
            index,
        })
    }

    /// The materials, in file order.
    pub fn materials(&self) -> &[Material] {
        &self.parsed.materials
    }

    /// The material called `name`, if any.
    pub fn material(&self, name: &str) -> Option<&Material> {
        self.parsed.materials.iter().find(|m| m.name == name)
    }

    /// The materials a person's `query` names, as the command line reads names: the record
    /// called exactly `query` if there is one, else every record whose name reads the same as
    /// it by [`loose_name`] (case, surrounding white space, and spaces against underscores
    /// against hyphens ignored), in file order. Record names are unique only exactly, so more
    /// than one may match loosely; the caller refuses that as ambiguous.
    pub fn materials_named(&self, query: &str) -> Vec<&Material> {
        if let Some(exact) = self.material(query) {
            return vec![exact];
        }
        let key = loose_name(query);
        let materials = self.parsed.materials.iter();
        materials.filter(|m| loose_name(&m.name) == key).collect()
    }

    /// The provenance, if the file has one.
    pub fn provenance(&self) -> Option<&Provenance> {
        self.parsed.provenance.as_ref()
    }
}

/// A material name as people type it: lowercase, trimmed, with spaces and underscores read as
/// hyphens ("White Grapefruit_Juice" reads as "white-grapefruit-juice"). The named-material
/// library and [`Library::materials_named`] compare names this way.
pub fn loose_name(name: &str) -> String {
    name.trim().to_lowercase().replace([' ', '_'], "-")
}

/// One table of a library: a model baked for one η.
#[derive(Clone, Copy)]
pub struct Table<'a> {
    library: &'a Library,
    index: usize,
}

impl std::fmt::Debug for Table<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Table")
            .field("index", &self.index)
            .field("header", self.header())
            .finish()
    }
}

impl<'a> Table<'a> {
    /// Position of the table in the file; materials refer to tables by this index.
    pub fn index(&self) -> usize {
        self.index
    }

    /// Model, η, Fresnel convention and dimensions.
    pub fn header(&self) -> &'a TableHeader {
        &self.library.parsed.tables[self.index].header
    }

    /// The model the table was baked for.
    pub fn model(&self) -> ModelKind {
        self.header().model
    }

    /// The walk a walk-angular table was measured with (its g and component), `None` for a
    /// table of another model.
    pub fn walk(&self) -> Option<WalkSource> {
        self.header().walk
    }

    /// What the table's nodes hold less, the analytic ridge of grazing incidence that every
    /// lookup adds back (its record's `ridge`, format 1.6; format-spec.md §10, "The ridge").
    /// `RidgeKind::None` in files of older minors.
    pub fn ridge(&self) -> crate::table::RidgeKind {
        self.header().ridge
    }

    /// Relative index of refraction η the table was baked for.
    pub fn eta(&self) -> f64 {
        self.header().eta
    }

    /// How the Fresnel moments were computed.
    pub fn fresnel(&self) -> FresnelMoments {
        self.header().fresnel
    }

    /// How lookups rebuild the lobes of a two-lobe table from its harmonics: the file's rule,
    /// [`Rebuild::MergedRoots`] where it sets required feature bit 4 (`merged-roots`, format
    /// 1.4), else [`Rebuild::Roots`] (format-spec.md §10 step 4).
    pub fn rebuild(&self) -> Rebuild {
        rebuild_of(self.library.required_features())
    }

    /// Dimensions (nρ, nθ, nr).
    pub fn dims(&self) -> [usize; 3] {
        let h = self.header();
        [h.n_rho as usize, h.n_theta as usize, h.n_r as usize]
    }

    /// Values of an axis: ρ′ (dimensionless), θ (radians) or r (reduced mean free paths).
    pub fn axis(&self, axis: AxisKind) -> &'a [f32] {
        self.section(axis.section()).unwrap_or_default()
    }

    /// The values of a section of this table, row-major, or `None` if the table does not have
    /// it. Zero-copy for uncompressed sections.
    pub fn section(&self, kind: SectionKind) -> Option<&'a [f32]> {
        if !kind.per_table() {
            return None;
        }
        let bytes = self.raw_section(kind.code())?;
        // Sections start at multiples of 256 bytes within a 256-byte-aligned map or buffer,
        // and their length is a multiple of 4 (checked at open), so this cast succeeds.
        <[f32]>::ref_from_bytes(bytes).ok()
    }

    /// General Wrapped Cauchy parameters (E, E_β = βr, c) interleaved, `[nρ][nθ][nr][3]`.
    pub fn gwc_params(&self) -> &'a [f32] {
        self.section(SectionKind::GwcParams).unwrap_or_default()
    }

    /// Radial CDF, `[nρ][nθ][nr]`.
    pub fn radial_cdf(&self) -> &'a [f32] {
        self.section(SectionKind::RadialCdf).unwrap_or_default()
    }

    /// CDF over θ of the effective albedo, `[nρ][nθ]`, if the table has it.
    pub fn theta_cdf(&self) -> Option<&'a [f32]> {
        self.section(SectionKind::ThetaCdf)
    }

    /// The third and fourth harmonics times r, `[nρ][nθ][nr][2]`, if the table has two lobes.
    pub fn harmonics(&self) -> Option<&'a [f32]> {
        self.section(SectionKind::Harmonics)
    }

    /// Decoded bytes of this table's section with kind code `kind` (including extension kinds
    /// this reader does not know), if present.
    pub fn raw_section(&self, kind: u32) -> Option<&'a [u8]> {
        let slot = &self.library.parsed.tables[self.index];
        let index = *slot.sections.get(&kind)?;
        Some(self.library.section_bytes(index))
    }

    /// Directory entries of this table's sections, in kind order.
    pub fn section_infos(&self) -> impl Iterator<Item = &'a SectionInfo> + 'a {
        let library = self.library;
        library.parsed.tables[self.index]
            .sections
            .values()
            .map(move |&i| &library.parsed.entries[i])
    }
}

/// The rule of [`Table::rebuild`] for a file's required features.
pub(crate) fn rebuild_of(required: u64) -> Rebuild {
    if required & super::spec::required_features::MERGED_ROOTS != 0 {
        Rebuild::MergedRoots
    } else {
        Rebuild::Roots
    }
}
