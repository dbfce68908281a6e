//! Building library files: collect tables, materials, provenance and extension sections, lay
//! them out canonically (so equal content gives byte-identical files), and write atomically.
//! Also `pack` and `unpack`, which convert between the mappable and the compressed form.

use std::collections::BTreeMap;
use std::path::Path;

use zerocopy::little_endian::{U16, U32, U64};
use zerocopy::IntoBytes;

use super::atomic::write_file_atomic;
use super::error::{FormatError, FormatResult};
use super::library::Library;
use super::provenance::Provenance;
use super::reader::{f32_values, first_signed_node, Verify};
use super::records::{
    check_axis, check_finite, check_gwc_nodes, check_radial_cdf, check_theta_cdf, has_signed_floor,
    Material, TableHeader,
};
use super::spec::{
    align_up, crc32, required_features, AxisKind, Codec, Dtype, FresnelMoments, ModelKind,
    RawEntry, RawHeader, SectionKind, WalkSource, BYTE_ORDER_MARK, DEFAULT_ALIGNMENT, ENTRY_SIZE,
    HEADER_CRC_OFFSET, HEADER_SIZE, MAGIC, MATERIAL_RECORD_SIZE, MAX_ALIGNMENT, MAX_MATERIALS,
    MAX_PROVENANCE_BYTES, MAX_SECTIONS, MAX_SECTION_BYTES, MAX_TABLES, MIN_ALIGNMENT, NO_TABLE,
    SECTION_REQUIRED, TABLE_RECORD_SIZE, VERSION_MAJOR, VERSION_MINOR,
};
use crate::gwc::Rebuild;

/// How to store sections.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Compression {
    /// Uncompressed: the file can be mapped and read zero-copy. The default.
    None,
    /// Every section zstd-compressed at `level` (1..=22; zstd's fast negative levels too),
    /// for distribution. Readers decode it
    /// into memory at open; the bytes are deterministic for a given zstd version and level.
    Zstd { level: i32 },
}

impl Compression {
    /// The zstd level `pack` uses by default.
    pub const DEFAULT_ZSTD_LEVEL: i32 = 19;
}

/// One baked table, as the bake hands it over. Values are row-major, outermost axis first.
#[derive(Debug, Clone, PartialEq)]
pub struct TableData {
    /// The model the table was baked for.
    pub model: ModelKind,
    /// The walk of a [`ModelKind::WalkAngular`] table (`Some` exactly for that model, with g in
    /// (−1, 1)); such a table has `harmonics`, and the file needs format 1.5's `walk-tables`
    /// bit.
    pub walk: Option<WalkSource>,
    /// What the nodes hold less, the analytic ridge of grazing incidence that lookups add
    /// back (the record's `ridge`, format-spec.md §10 "The ridge"); with one, the file needs
    /// format 1.6's `ridge` bit.
    pub ridge: crate::table::RidgeKind,
    /// Relative index of refraction η, > 0.
    pub eta: f64,
    /// How the Fresnel moments were computed.
    pub fresnel: FresnelMoments,
    /// Reduced albedo axis ρ′, `[nρ]`, strictly increasing in [0, 1].
    pub rho: Vec<f32>,
    /// Incidence angle axis θ, `[nθ]`, in radians, strictly increasing in [0, π/2].
    pub theta: Vec<f32>,
    /// Radius axis r, `[nr]`, in reduced mean free paths, strictly increasing, ≥ 0.
    pub r: Vec<f32>,
    /// GWC parameters (E, E_β = βr, c) interleaved, `[nρ][nθ][nr][3]`: every node with
    /// E_β ≥ 0, |c| < 1 and a profile ≥ 0 (E_β·2|c| ≤ E·(1 + |c|), format-spec.md §10). E_β > E
    /// (a negative floor) is allowed and makes the file need format 1.1's `signed-floor` bit.
    pub gwc: Vec<f32>,
    /// Radial CDF, `[nρ][nθ][nr]`.
    pub cdf: Vec<f32>,
    /// CDF over θ of the effective albedo, `[nρ][nθ]`, if wanted (path tracing samples θ with it).
    pub theta_cdf: Option<Vec<f32>>,
    /// For a two-lobe table, the profile's third and fourth harmonics times r, (rμ₃, rμ₄),
    /// `[nρ][nθ][nr][2]` (format-spec.md §10); the file then needs format 1.2's `harmonics` bit.
    pub harmonics: Option<Vec<f32>>,
    /// How lookups rebuild a two-lobe table's lobes from its harmonics: with merged roots, as
    /// this crate bakes ([`Rebuild::MergedRoots`], which sets format 1.4's `merged-roots` bit), or
    /// as files without that bit are read ([`Rebuild::Roots`]). The two-lobe tables of a file
    /// share one rule. Ignored for a table without harmonics.
    pub rebuild: Rebuild,
}

/// A section of a kind this version does not define, for extensions and tests.
#[derive(Debug, Clone, PartialEq)]
pub struct ExtraSection {
    /// Kind code; must not be one of [`SectionKind::ALL`].
    pub kind: u32,
    /// Owning table, or `None` for a file-level section.
    pub table: Option<usize>,
    /// True if readers that do not know `kind` must reject the file.
    pub required: bool,
    /// Element type.
    pub dtype: Dtype,
    /// Dimensions, 1 to 4 of them, outermost first.
    pub dims: Vec<u32>,
    /// Little-endian element bytes, `product(dims) × dtype size` of them.
    pub bytes: Vec<u8>,
}

#[derive(Debug, Clone)]
struct Pending {
    dtype: Dtype,
    dims: Vec<u32>,
    required: bool,
    bytes: Vec<u8>,
}

/// Collects the content of a library file. Add tables before the materials that use them.
#[derive(Debug, Clone)]
pub struct LibraryBuilder {
    alignment: u32,
    tables: Vec<(TableHeader, BTreeMap<u32, Pending>)>,
    /// The rule of the two-lobe tables added so far ([`TableData::rebuild`]).
    rebuild: Option<Rebuild>,
    file_sections: BTreeMap<u32, Pending>,
    materials: Vec<Material>,
    provenance: Option<Provenance>,
}

impl Default for LibraryBuilder {
    fn default() -> Self {
        LibraryBuilder::new()
    }
}

fn invalid(message: String) -> FormatError {
    FormatError::InvalidInput { message }
}

fn f32_bytes(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

impl LibraryBuilder {
    /// An empty library with the default 256-byte section alignment.
    pub fn new() -> LibraryBuilder {
        LibraryBuilder {
            alignment: DEFAULT_ALIGNMENT,
            tables: Vec::new(),
            rebuild: None,
            file_sections: BTreeMap::new(),
            materials: Vec::new(),
            provenance: None,
        }
    }

    /// Sets the section alignment: a power of two in [256, 65536] (4096 puts every section on
    /// its own page).
    pub fn set_alignment(&mut self, alignment: u32) -> FormatResult<&mut Self> {
        if !alignment.is_power_of_two() || !(MIN_ALIGNMENT..=MAX_ALIGNMENT).contains(&alignment) {
            return Err(FormatError::BadAlignment {
                value: alignment,
                min: MIN_ALIGNMENT,
                max: MAX_ALIGNMENT,
            });
        }
        self.alignment = alignment;
        Ok(self)
    }

    /// Adds a table after validating it; returns its index, which materials refer to.
    pub fn add_table(&mut self, table: TableData) -> FormatResult<usize> {
        let index = self.tables.len();
        if index as u64 >= MAX_TABLES {
            return Err(invalid(format!("more than {MAX_TABLES} tables")));
        }
        let len32 = |v: &[f32]| u32::try_from(v.len()).unwrap_or(u32::MAX);
        let header = TableHeader {
            model: table.model,
            walk: table.walk,
            ridge: table.ridge,
            eta: table.eta,
            fresnel: table.fresnel,
            n_rho: len32(&table.rho),
            n_theta: len32(&table.theta),
            n_r: len32(&table.r),
        };
        header.validate(index)?;
        check_axis(index, AxisKind::Rho, &table.rho)?;
        check_axis(index, AxisKind::Theta, &table.theta)?;
        check_axis(index, AxisKind::R, &table.r)?;
        let mut sections = BTreeMap::new();
        let mut put = |kind: SectionKind, values: &[f32]| -> FormatResult<()> {
            let expected = header.expected_dims(kind).unwrap_or_default();
            let count: u64 = expected.iter().map(|&d| u64::from(d)).product();
            if values.len() as u64 != count {
                return Err(FormatError::SectionDims {
                    table: Some(index),
                    kind,
                    found: vec![len32(values)],
                    expected,
                });
            }
            if count * 4 > MAX_SECTION_BYTES {
                return Err(invalid(format!(
                    "table {index}: {kind} has {count} values, over the {MAX_SECTION_BYTES}-byte cap"
                )));
            }
            check_finite(index, kind, values)?;
            let pending = Pending {
                dtype: Dtype::F32,
                dims: expected,
                required: kind.required(),
                bytes: f32_bytes(values),
            };
            sections.insert(kind.code(), pending);
            Ok(())
        };
        put(SectionKind::AxisRho, &table.rho)?;
        put(SectionKind::AxisTheta, &table.theta)?;
        put(SectionKind::AxisR, &table.r)?;
        put(SectionKind::GwcParams, &table.gwc)?;
        // Negative floors are allowed: `to_bytes` sets the feature bit they need.
        check_gwc_nodes(index, &header, &table.gwc, true)?;
        put(SectionKind::RadialCdf, &table.cdf)?;
        check_radial_cdf(index, &header, &table.cdf)?;
        if let Some(albedo) = &table.theta_cdf {
            put(SectionKind::ThetaCdf, albedo)?;
            check_theta_cdf(index, &header, albedo)?;
        }
        if let Some(harmonics) = &table.harmonics {
            match self.rebuild {
                Some(rule) if rule != table.rebuild => {
                    return Err(invalid(format!(
                        "table {index} rebuilds its lobes by the rule {}, the earlier two-lobe tables by {}: a file has one rule (required feature bit 4, merged-roots)",
                        table.rebuild.name(),
                        rule.name()
                    )));
                }
                _ => self.rebuild = Some(table.rebuild),
            }
            put(SectionKind::Harmonics, harmonics)?;
        }
        // A walk-angular table has two lobes: what the reader requires of the model
        for &kind in header.required_sections() {
            if !sections.contains_key(&kind.code()) {
                return Err(FormatError::MissingSection {
                    kind,
                    table: Some(index),
                });
            }
        }
        self.tables.push((header, sections));
        Ok(index)
    }

    /// Adds a material after validating it against the tables added so far.
    pub fn add_material(&mut self, material: Material) -> FormatResult<&mut Self> {
        let index = self.materials.len();
        if index as u64 >= MAX_MATERIALS {
            return Err(invalid(format!("more than {MAX_MATERIALS} materials")));
        }
        material.validate(index, self.tables.len())?;
        if let Some(first) = self.materials.iter().position(|m| m.name == material.name) {
            return Err(FormatError::DuplicateName {
                material: index,
                first,
                name: material.name,
            });
        }
        self.materials.push(material);
        Ok(self)
    }

    /// Sets the provenance (replacing any earlier one).
    pub fn set_provenance(&mut self, provenance: Provenance) -> &mut Self {
        self.provenance = Some(provenance);
        self
    }

    /// Adds a section of an extension kind.
    pub fn add_extra_section(&mut self, section: ExtraSection) -> FormatResult<&mut Self> {
        if SectionKind::from_code(section.kind).is_some() {
            return Err(invalid(format!(
                "kind {:#x} is defined by the format; add it through its own method",
                section.kind
            )));
        }
        let dims_ok = (1..=4).contains(&section.dims.len());
        let bytes = section
            .dims
            .iter()
            .try_fold(u128::from(section.dtype.size()), |acc, &d| {
                acc.checked_mul(u128::from(d))
            })
            .unwrap_or(u128::MAX);
        if !dims_ok || bytes != section.bytes.len() as u128 || bytes > MAX_SECTION_BYTES.into() {
            return Err(invalid(format!(
                "extension section {:#x}: {} dims {:?} do not match {} bytes (or exceed the cap)",
                section.kind,
                section.dtype.name(),
                section.dims,
                section.bytes.len()
            )));
        }
        let pending = Pending {
            dtype: section.dtype,
            dims: section.dims,
            required: section.required,
            bytes: section.bytes,
        };
        let map = match section.table {
            None => &mut self.file_sections,
            Some(t) => match self.tables.get_mut(t) {
                Some((_, sections)) => sections,
                None => return Err(invalid(format!("extension section for missing table {t}"))),
            },
        };
        if map.contains_key(&section.kind) {
            return Err(invalid(format!(
                "extension section {:#x} added twice",
                section.kind
            )));
        }
        map.insert(section.kind, pending);
        Ok(self)
    }

    /// A builder holding everything `library` holds (for lossless conversion).
    pub fn from_library(library: &Library) -> FormatResult<LibraryBuilder> {
        let (_, minor) = library.version();
        if minor > VERSION_MINOR {
            return Err(FormatError::RewriteNewerMinor {
                found: minor,
                supported: VERSION_MINOR,
            });
        }
        let mut builder = LibraryBuilder::new();
        builder.alignment = library.alignment();
        let pending = |info: &super::reader::SectionInfo, bytes: &[u8]| Pending {
            dtype: info.dtype,
            dims: info.dims.clone(),
            required: info.required,
            bytes: bytes.to_vec(),
        };
        for table in library.tables() {
            let mut sections = BTreeMap::new();
            for info in table.section_infos() {
                let bytes = table.raw_section(info.kind).unwrap_or_default();
                sections.insert(info.kind, pending(info, bytes));
            }
            if table.harmonics().is_some() {
                builder.rebuild = Some(table.rebuild());
            }
            builder.tables.push((*table.header(), sections));
        }
        for info in library.sections().iter().filter(|s| s.table.is_none()) {
            if SectionKind::from_code(info.kind).is_none() {
                let bytes = library.file_section(info.kind).unwrap_or_default();
                builder
                    .file_sections
                    .insert(info.kind, pending(info, bytes));
            }
        }
        builder.materials = library.materials().to_vec();
        builder.provenance = library.provenance().cloned();
        Ok(builder)
    }

    /// The file's bytes, laid out canonically.
    pub fn to_bytes(&self, compression: Compression) -> FormatResult<Vec<u8>> {
        let mut sections: Vec<(u32, u32, Pending)> = Vec::new();
        let mut file_level = self.file_sections.clone();
        let records = |n: usize, size: usize, bytes: Vec<u8>| Pending {
            dtype: Dtype::U8,
            dims: vec![n as u32, size as u32],
            required: true,
            bytes,
        };
        let table_bytes: Vec<u8> = self
            .tables
            .iter()
            .flat_map(|(h, _)| h.encode().as_bytes().to_vec())
            .collect();
        let material_bytes: Vec<u8> = self
            .materials
            .iter()
            .flat_map(|m| m.encode().as_bytes().to_vec())
            .collect();
        file_level.insert(
            SectionKind::Tables.code(),
            records(self.tables.len(), TABLE_RECORD_SIZE, table_bytes),
        );
        file_level.insert(
            SectionKind::Materials.code(),
            records(self.materials.len(), MATERIAL_RECORD_SIZE, material_bytes),
        );
        if let Some(provenance) = &self.provenance {
            let json = provenance.to_canonical_json();
            if json.len() as u64 > MAX_PROVENANCE_BYTES {
                return Err(FormatError::ProvenanceJson {
                    message: format!(
                        "{} bytes, more than the cap of {MAX_PROVENANCE_BYTES}",
                        json.len()
                    ),
                });
            }
            file_level.insert(
                SectionKind::Provenance.code(),
                Pending {
                    dtype: Dtype::U8,
                    dims: vec![json.len() as u32],
                    required: false,
                    bytes: json,
                },
            );
        }
        for (kind, p) in file_level {
            sections.push((kind, NO_TABLE, p));
        }
        for (t, (_, table_sections)) in self.tables.iter().enumerate() {
            for (&kind, p) in table_sections {
                sections.push((kind, t as u32, p.clone()));
            }
        }
        if sections.len() > MAX_SECTIONS as usize {
            return Err(invalid(format!("more than {MAX_SECTIONS} sections")));
        }
        // The bit exactly when some node has a negative floor, so that files without one stay
        // readable by 1.0 readers.
        let signed_floor = self.tables.iter().any(|(_, table_sections)| {
            table_sections
                .get(&SectionKind::GwcParams.code())
                .is_some_and(|p| has_signed_floor_bytes(&p.bytes))
        });
        let harmonics = self
            .tables
            .iter()
            .any(|(_, table_sections)| table_sections.contains_key(&SectionKind::Harmonics.code()));
        // The bit exactly when some node of some two-lobe table is a signed pair, so that
        // files without one stay readable by 1.2 readers; by the two-lobe tables' rule, whose
        // bit 4 a 1.3 reader refuses
        let rebuild = self.rebuild.unwrap_or_default();
        let merged_roots = harmonics && rebuild == Rebuild::MergedRoots;
        let signed_lobes = self.tables.iter().any(|(_, table_sections)| {
            let values = |kind: SectionKind| {
                table_sections
                    .get(&kind.code())
                    .map(|s| f32_values(&s.bytes))
            };
            match (
                values(SectionKind::GwcParams),
                values(SectionKind::Harmonics),
            ) {
                (Some(p), Some(h)) => first_signed_node(&p, &h, rebuild).is_some(),
                _ => false,
            }
        });
        let walk_tables = self
            .tables
            .iter()
            .any(|(header, _)| header.model == ModelKind::WalkAngular);
        let ridge = self.tables.iter().any(|(header, _)| header.ridge.is_some());
        let required = if signed_floor {
            required_features::SIGNED_FLOOR
        } else {
            0
        } | if harmonics {
            required_features::HARMONICS
        } else {
            0
        } | if signed_lobes {
            required_features::SIGNED_LOBES
        } else {
            0
        } | if merged_roots {
            required_features::MERGED_ROOTS
        } else {
            0
        } | if walk_tables {
            required_features::WALK_TABLES
        } else {
            0
        } | if ridge { required_features::RIDGE } else { 0 };
        layout(&sections, self.alignment, compression, required)
    }

    /// Writes the file atomically: a temporary file in the target's folder, synced, renamed
    /// over `path`, then the folder synced. Killed at any moment, it leaves either the old
    /// file or the new one at `path` (and at worst a stray `.NAME.*.tmp` file beside it).
    /// A device or FIFO is written through instead ([`write_file_atomic`]). Returns the number
    /// of bytes written.
    pub fn write_atomic(
        &self,
        path: impl AsRef<Path>,
        compression: Compression,
    ) -> FormatResult<u64> {
        let bytes = self.to_bytes(compression)?;
        write_file_atomic(path.as_ref(), &bytes)?;
        Ok(bytes.len() as u64)
    }
}

/// [`has_signed_floor`] of little-endian f32 bytes.
fn has_signed_floor_bytes(bytes: &[u8]) -> bool {
    has_signed_floor(&f32_values(bytes))
}

/// Places the sections one after another at aligned offsets and writes header and directory.
/// `required` holds the required feature bits of the content; the zstd bit is added here.
fn layout(
    sections: &[(u32, u32, Pending)],
    alignment: u32,
    compression: Compression,
    required: u64,
) -> FormatResult<Vec<u8>> {
    let mut compressor = match compression {
        Compression::None => None,
        Compression::Zstd { level } => {
            if !zstd::compression_level_range().contains(&level) {
                let levels = zstd_levels();
                return Err(invalid(format!(
                    "zstd level {level} is outside [{}, {}]",
                    levels.start(),
                    levels.end()
                )));
            }
            let zstd_error = |e: std::io::Error| invalid(format!("zstd level {level}: {e}"));
            let mut c = zstd::bulk::Compressor::new(level).map_err(zstd_error)?;
            c.set_parameter(zstd::stream::raw::CParameter::ChecksumFlag(true))
                .map_err(zstd_error)?;
            c.set_parameter(zstd::stream::raw::CParameter::ContentSizeFlag(true))
                .map_err(zstd_error)?;
            Some(c)
        }
    };
    let dir_end = HEADER_SIZE + sections.len() * ENTRY_SIZE;
    let mut out = vec![0u8; dir_end];
    let mut entries = Vec::with_capacity(sections.len());
    for &(kind, table, ref p) in sections {
        let (codec, stored) = match compressor.as_mut() {
            None => (Codec::None, p.bytes.clone()),
            Some(c) => {
                let stored = c
                    .compress(&p.bytes)
                    .map_err(|e| invalid(format!("zstd compression failed: {e}")))?;
                (Codec::Zstd, stored)
            }
        };
        let offset = align_up(out.len() as u64, alignment.into()).unwrap_or(u64::MAX);
        out.resize(offset as usize, 0);
        let mut dims = [U32::new(0); 4];
        for (d, &v) in dims.iter_mut().zip(&p.dims) {
            *d = U32::new(v);
        }
        entries.push(RawEntry {
            kind: U32::new(kind),
            table: U32::new(table),
            dtype: U16::new(p.dtype as u16),
            codec: U16::new(codec as u16),
            flags: U16::new(if p.required { SECTION_REQUIRED } else { 0 }),
            ndim: U16::new(p.dims.len() as u16),
            dims,
            offset: U64::new(offset),
            stored_len: U64::new(stored.len() as u64),
            raw_len: U64::new(p.bytes.len() as u64),
            crc32: U32::new(crc32(&[&stored])),
            reserved: [0; 4],
        });
        out.extend_from_slice(&stored);
    }
    let features = if compressor.is_some() {
        required | required_features::ZSTD
    } else {
        required
    };
    let header = RawHeader {
        magic: MAGIC,
        major: U16::new(VERSION_MAJOR),
        minor: U16::new(VERSION_MINOR),
        byte_order: U32::new(BYTE_ORDER_MARK),
        section_count: U32::new(sections.len() as u32),
        file_size: U64::new(out.len() as u64),
        required_features: U64::new(features),
        optional_features: U64::new(0),
        alignment: U32::new(alignment),
        reserved: [0; 72],
        header_crc: U32::new(0),
    };
    out[..HEADER_SIZE].copy_from_slice(header.as_bytes());
    for (i, entry) in entries.iter().enumerate() {
        let at = HEADER_SIZE + i * ENTRY_SIZE;
        out[at..at + ENTRY_SIZE].copy_from_slice(entry.as_bytes());
    }
    let crc = crc32(&[&out[..HEADER_CRC_OFFSET], &out[HEADER_SIZE..dir_end]]);
    out[HEADER_CRC_OFFSET..HEADER_SIZE].copy_from_slice(&crc.to_le_bytes());
    Ok(out)
}

/// Sizes before and after a conversion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Conversion {
    /// Bytes of the input file.
    pub input_bytes: u64,
    /// Bytes of the output file.
    pub output_bytes: u64,
}

fn convert(input: &Path, output: &Path, compression: Compression) -> FormatResult<Conversion> {
    // A plain read, fully verified: `output` may be `input`, and nothing corrupt is repacked.
    let library = Library::read(input, Verify::Full)?;
    let bytes = LibraryBuilder::from_library(&library)?.to_bytes(compression)?;
    write_file_atomic(output, &bytes)?;
    Ok(Conversion {
        input_bytes: library.file_size() as u64,
        output_bytes: bytes.len() as u64,
    })
}

/// The zstd levels [`pack`] takes: from the fast negative levels to 22.
pub fn zstd_levels() -> std::ops::RangeInclusive<i32> {
    zstd::compression_level_range()
}

/// Rewrites `input` with every section zstd-compressed at `level` into `output` (which may be
/// `input`). Lossless: `unpack` gives back the canonical mappable file byte for byte.
pub fn pack(
    input: impl AsRef<Path>,
    output: impl AsRef<Path>,
    level: i32,
) -> FormatResult<Conversion> {
    convert(input.as_ref(), output.as_ref(), Compression::Zstd { level })
}

/// Rewrites `input` uncompressed into `output` (which may be `input`), so it can be mapped.
pub fn unpack(input: impl AsRef<Path>, output: impl AsRef<Path>) -> FormatResult<Conversion> {
    convert(input.as_ref(), output.as_ref(), Compression::None)
}
