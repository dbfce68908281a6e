//! Every way reading or writing a library file can fail: one variant per failure, each with a
//! lowercase message naming the bad value and a stable code (`FormatError::code`) that the
//! conformance vectors in `tests/data/invalid/` are named after.

use std::path::PathBuf;

use thiserror::Error;

use super::spec::SectionKind;
use crate::error::Number;

/// An error from the library file format: opening, validating, writing or converting a file.
#[derive(Debug, Error)]
pub enum FormatError {
    /// The operating system refused an operation on a file or folder.
    #[error("cannot {op} {path}: {source}")]
    Io {
        op: &'static str,
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// This host is big-endian; the zero-copy `&[f32]` views need a little-endian host.
    #[error("this host is big-endian; library files can be read only on little-endian hosts")]
    BigEndianHost,
    /// The file does not start with the library magic.
    #[error(
        "not a bssrdf library file: its first bytes are (hex) {}, where a library file's are {}",
        Hex(found),
        Hex(expected)
    )]
    BadMagic { found: Vec<u8>, expected: Vec<u8> },
    /// The file is shorter than the fixed header.
    #[error("file is {len} bytes long, shorter than the {min}-byte header")]
    TooShort { len: u64, min: u64 },
    /// The byte-order mark is not `0x0A0B0C0D` read little-endian.
    #[error("byte-order mark is {found:#010x}, expected 0x0a0b0c0d{hint}")]
    WrongByteOrder { found: u32, hint: &'static str },
    /// The major version is not the one this reader knows.
    #[error("file format major version {found} is not supported: this reader reads major {supported} only{hint}")]
    UnsupportedMajor {
        found: u16,
        supported: u16,
        hint: &'static str,
    },
    /// The header declares more bytes than the file has.
    #[error("file is truncated: header declares {declared} bytes, file has {actual}")]
    Truncated { declared: u64, actual: u64 },
    /// The file has more bytes than the header declares.
    #[error("file has {actual} bytes but its header declares {declared}: trailing bytes")]
    TrailingBytes { declared: u64, actual: u64 },
    /// The section count is over the cap or the directory runs past the end of the file.
    #[error("section count {count} is invalid: the directory would end at byte {end}, the file has {file_size} (at most {max} sections)")]
    DirectoryOutOfBounds {
        count: u64,
        end: u64,
        file_size: u64,
        max: u32,
    },
    /// The CRC-32 over header and directory does not match.
    #[error("header crc mismatch: stored {stored:#010x}, computed {computed:#010x} (header or directory corrupt)")]
    HeaderCrc { stored: u32, computed: u32 },
    /// The file needs required features this reader lacks.
    #[error("file needs required feature bits {bits:#x} ({names}) that this reader (format {major}.{minor}) lacks")]
    UnsupportedFeatures {
        bits: u64,
        names: String,
        major: u16,
        minor: u16,
    },
    /// A reserved byte (or reserved flag bit) of the header, an entry or a record is not zero.
    #[error("reserved byte {offset} of the {what} is {value:#04x}, must be 0")]
    ReservedNotZero {
        what: String,
        offset: usize,
        value: u8,
    },
    /// The declared section alignment is not a power of two in the allowed range.
    #[error("section alignment {value} is invalid: must be a power of two in [{min}, {max}]")]
    BadAlignment { value: u32, min: u32, max: u32 },
    /// A directory entry names an element type this reader does not know.
    #[error("section {section}: unknown dtype code {dtype}")]
    UnknownDtype { section: usize, dtype: u16 },
    /// A directory entry names a codec this reader does not know.
    #[error("section {section}: unknown codec code {codec}")]
    UnknownCodec { section: usize, codec: u16 },
    /// A section uses a feature whose bit the header does not set.
    #[error(
        "section {section} uses {feature} but the header's required feature bits do not declare it"
    )]
    FeatureNotDeclared {
        section: usize,
        feature: &'static str,
    },
    /// A table has a `gwc-harmonics` section (two lobes) but the file does not set required
    /// feature bit 2: a reader that ignored the section would read one lobe.
    #[error("section {section}: gwc-harmonics (two lobes) in a file without required feature bit 2 (harmonics)")]
    HarmonicsNotDeclared { section: usize },
    /// A `gwc-harmonics` node rebuilds into a signed pair but the file does not set required
    /// feature bit 3: readers of 1.2 read it as one lobe or as the pair (format-spec.md §4).
    #[error("table {table}: gwc-harmonics node {node} is a signed pair (a lobe less a broader one) in a file without required feature bit 3 (signed-lobes)")]
    SignedLobesNotDeclared { table: usize, node: usize },
    /// A directory entry's rank or dimensions are malformed.
    #[error("section {section}: ndim {ndim} with dims {dims:?} is malformed (ndim must be 1..=4, unused dims 0)")]
    BadShape {
        section: usize,
        ndim: u16,
        dims: [u32; 4],
    },
    /// A section would decode to more than the per-section cap.
    #[error("section {section}: dims give {bytes} bytes, more than the {max}-byte cap")]
    SectionTooLarge {
        section: usize,
        bytes: u128,
        max: u64,
    },
    /// The raw length does not equal the product of the dimensions times the element size.
    #[error("section {section}: raw length {raw_len} does not match its dims, which give {expected} bytes")]
    RawLengthMismatch {
        section: usize,
        raw_len: u64,
        expected: u64,
    },
    /// An uncompressed section's stored length differs from its raw length.
    #[error(
        "section {section}: uncompressed but stored length {stored_len} != raw length {raw_len}"
    )]
    StoredLengthMismatch {
        section: usize,
        stored_len: u64,
        raw_len: u64,
    },
    /// A section does not start at a multiple of the alignment.
    #[error("section {section}: offset {offset} is not a multiple of the alignment {alignment}")]
    MisalignedSection {
        section: usize,
        offset: u64,
        alignment: u32,
    },
    /// A section starts before the one listed before it.
    #[error("section {section}: offset {offset} is before the previous section's offset {previous}: sections out of order")]
    SectionsOutOfOrder {
        section: usize,
        offset: u64,
        previous: u64,
    },
    /// A section starts inside the directory or the previous section.
    #[error("section {section}: offset {offset} overlaps the bytes before it, which end at {previous_end}")]
    SectionsOverlap {
        section: usize,
        offset: u64,
        previous_end: u64,
    },
    /// A section starts later than the first aligned offset after the previous one.
    #[error(
        "section {section}: offset {offset} leaves a gap; the next aligned offset is {expected}"
    )]
    SectionGap {
        section: usize,
        offset: u64,
        expected: u64,
    },
    /// A section runs past the end of the file.
    #[error(
        "section {section}: bytes {offset}..{end} run past the end of the file at {file_size}"
    )]
    SectionOutOfBounds {
        section: usize,
        offset: u64,
        end: u64,
        file_size: u64,
    },
    /// Bytes follow the end of the last section.
    #[error("{extra} bytes follow the end of the last section at {end}")]
    DataAfterLastSection { end: u64, extra: u64 },
    /// A padding byte between sections is not zero.
    #[error("padding byte at file offset {offset} is {value:#04x}, must be 0")]
    NonZeroPadding { offset: u64, value: u8 },
    /// A directory entry has unknown flag bits, or a known kind has the wrong `required` flag.
    #[error("section {section}: flags {flags:#06x} are invalid for kind {kind:#x} (expected {expected:#06x})")]
    SectionFlags {
        section: usize,
        kind: u32,
        flags: u16,
        expected: u16,
    },
    /// A section of unknown kind is marked required.
    #[error("section {section}: kind {kind:#x} is unknown to this reader and marked required")]
    UnknownRequiredSection { section: usize, kind: u32 },
    /// A known section kind has the wrong element type.
    #[error("section {section} ({kind}): dtype {dtype} is wrong, the kind stores {expected}")]
    WrongDtype {
        section: usize,
        kind: SectionKind,
        dtype: &'static str,
        expected: &'static str,
    },
    /// A section's table field is out of range or wrong for its kind.
    #[error("section {section} (kind {kind:#x}): table index {table:#x} is invalid (file has {table_count} tables; file-level kinds use 0xffffffff)")]
    SectionTableIndex {
        section: usize,
        kind: u32,
        table: u32,
        table_count: usize,
    },
    /// Two sections share kind and table.
    #[error("section {section}: kind {kind:#x} for table {table:#x} appears twice")]
    DuplicateSection {
        section: usize,
        kind: u32,
        table: u32,
    },
    /// A section the format requires is absent.
    #[error("missing required section {kind}{}", table.map(|t| format!(" for table {t}")).unwrap_or_default())]
    MissingSection {
        kind: SectionKind,
        table: Option<usize>,
    },
    /// A section's stored bytes do not match its CRC-32.
    #[error("section {section} crc mismatch: stored {stored:#010x}, computed {computed:#010x} (section data corrupt)")]
    SectionCrc {
        section: usize,
        stored: u32,
        computed: u32,
    },
    /// A zstd section failed to decode.
    #[error("section {section}: zstd decoding failed: {message}")]
    Zstd { section: usize, message: String },
    /// A zstd section decoded to a length other than its raw length.
    #[error("section {section}: zstd data decoded to {found} bytes, raw length is {expected}")]
    DecodedLength {
        section: usize,
        expected: u64,
        found: u64,
    },
    /// A record section's record size is wrong.
    #[error("{kind} section: record size {found} is invalid, expected {expected}")]
    RecordSize {
        kind: SectionKind,
        found: u32,
        expected: usize,
    },
    /// More tables or materials than the format allows.
    #[error("{kind} section holds {count} records, more than the cap of {max}")]
    TooManyRecords {
        kind: SectionKind,
        count: u64,
        max: u64,
    },
    /// A table's model code is unknown.
    #[error("table {table}: unknown model code {model}")]
    UnknownModel { table: usize, model: u32 },
    /// A walk-angular table (model 3) in a file that does not set required feature bit 5.
    #[error("table {table}: walk-angular (model 3) in a file without required feature bit 5 (walk-tables)")]
    WalkTablesNotDeclared { table: usize },
    /// A walk-angular table's component code is unknown.
    #[error("table {table}: unknown walk component code {component} (0 multiple, 1 total)")]
    UnknownComponent { table: usize, component: u32 },
    /// A table record's `ridge` is not 0, 1 or 2.
    #[error("table {table}: unknown ridge code {ridge} (0 the nodes hold the profile, 1 the profile less the ridge, 2 less the ridge with its fluence part)")]
    UnknownRidge { table: usize, ridge: u32 },
    /// A table whose nodes hold the profile less the ridge (`ridge` = 1 or 2) in a file that
    /// does not set required feature bit 6.
    #[error("table {table}: ridge = {ridge} in a file without required feature bit 6 (ridge)")]
    RidgeNotDeclared { table: usize, ridge: u32 },
    /// A table's Fresnel-moments code is unknown.
    #[error("table {table}: unknown fresnel-moments code {fresnel}")]
    UnknownFresnel { table: usize, fresnel: u32 },
    /// A walk-angular table's Henyey–Greenstein g is not a finite number in (−1, 1).
    #[error("table {table}: the walk's g = {} must be finite and in (-1, 1)", Number(*g))]
    TableG { table: usize, g: f64 },
    /// A table's relative index of refraction is not a finite positive number.
    #[error("table {table}: eta = {} must be finite and > 0", Number(*eta))]
    TableEta { table: usize, eta: f64 },
    /// A table dimension is zero or over the cap.
    #[error("table {table}: dims (n_rho, n_theta, n_r) = {dims:?} must each be in 1..={max}")]
    TableDims {
        table: usize,
        dims: [u32; 3],
        max: u32,
    },
    /// A section's dimensions disagree with its table's (or, for file-level sections, with the
    /// kind's shape).
    #[error("{}section {kind} has dims {found:?}, expected {expected:?}", table.map(|t| format!("table {t}: ")).unwrap_or_default())]
    SectionDims {
        table: Option<usize>,
        kind: SectionKind,
        found: Vec<u32>,
        expected: Vec<u32>,
    },
    /// A table value is NaN or infinite.
    #[error("table {table}: {kind}[{index}] = {} is not finite", Number(*value))]
    NonFinite {
        table: usize,
        kind: SectionKind,
        index: usize,
        value: f32,
    },
    /// A `gwc-params` node's lobe share E_β is negative (an inverted lobe).
    #[error("table {table}: gwc-params node (i, j, k) = {node:?} has E_beta = {}, must be >= 0", Number(*e_beta))]
    NegativeLobe {
        table: usize,
        node: (usize, usize, usize),
        e_beta: f32,
    },
    /// A `gwc-params` node's concentration c is not in (−1, 1).
    #[error("table {table}: gwc-params node (i, j, k) = {node:?} has concentration c = {}, must be in (-1, 1)", Number(*c))]
    ConcentrationOutOfRange {
        table: usize,
        node: (usize, usize, usize),
        c: f32,
    },
    /// A `gwc-params` node's profile is negative at some azimuth: E_β·2|c| > E·(1 + |c|) beyond
    /// the f32 rounding slack.
    #[error("table {table}: gwc-params node (i, j, k) = {node:?} with E = {}, E_beta = {}, c = {} is negative at its minimum: E_beta*2|c| = {} exceeds E*(1+|c|) = {}", Number(*e), Number(*e_beta), Number(*c), Number(*lobe), Number(*floor))]
    NegativeProfile {
        table: usize,
        node: (usize, usize, usize),
        e: f32,
        e_beta: f32,
        c: f32,
        lobe: f64,
        floor: f64,
    },
    /// A `gwc-params` node has a negative floor (E_β > E) but the header does not declare
    /// required feature bit 1.
    #[error("table {table}: gwc-params node (i, j, k) = {node:?} has E_beta = {} > E = {} (a negative floor), but the header does not set required feature bit 1 (signed-floor)", Number(*e_beta), Number(*e))]
    SignedFloorNotDeclared {
        table: usize,
        node: (usize, usize, usize),
        e: f32,
        e_beta: f32,
    },
    /// A `radial-cdf` value is negative or below the one before it along r: a running integral
    /// of a positive part never is.
    #[error("table {table}: radial-cdf at node {node:?} is {} after {}: a running integral over r is >= 0 and never decreases", Number(*value), Number(*previous))]
    RadialCdfDecreasing {
        table: usize,
        node: (usize, usize, usize),
        previous: f32,
        value: f32,
    },
    /// A `theta-cdf` value is negative or below the one before it along θ: a running integral
    /// of ρ_eff ≥ 0 never is.
    #[error("table {table}: theta-cdf at node {node:?} (rho, theta) is {} after {}: a running integral over theta is >= 0 and never decreases", Number(*value), Number(*previous))]
    ThetaCdfDecreasing {
        table: usize,
        node: (usize, usize),
        previous: f32,
        value: f32,
    },
    /// An axis is not strictly increasing.
    #[error("table {table}: axis {axis} is not strictly increasing at index {index} ({} then {})", Number(*previous), Number(*value))]
    AxisNotIncreasing {
        table: usize,
        axis: &'static str,
        index: usize,
        previous: f32,
        value: f32,
    },
    /// An axis value is outside the range its quantity allows.
    #[error("table {table}: axis {axis}[{index}] = {} is outside [{}, {}]", Number(*value), Number(*min), Number(*max))]
    AxisOutOfRange {
        table: usize,
        axis: &'static str,
        index: usize,
        value: f32,
        min: f32,
        max: f32,
    },
    /// A material name is empty.
    #[error("material {material}: name is empty")]
    EmptyName { material: usize },
    /// A material string is longer than its field.
    #[error("material {material}: {field} is {len} bytes, at most {max} allowed")]
    StringTooLong {
        material: usize,
        field: &'static str,
        len: u64,
        max: usize,
    },
    /// A material string is not UTF-8.
    #[error("material {material}: {field} is not valid utf-8")]
    InvalidUtf8 {
        material: usize,
        field: &'static str,
    },
    /// A material string contains a control character.
    #[error("material {material}: {field} contains control character {character:?}")]
    ControlCharacter {
        material: usize,
        field: &'static str,
        character: char,
    },
    /// Two materials share a name.
    #[error("material {material}: name {name:?} is already used by material {first}")]
    DuplicateName {
        material: usize,
        first: usize,
        name: String,
    },
    /// A material refers to a table that does not exist.
    #[error("material {material}: channel {channel} uses table {table}, but the file has {table_count} tables")]
    MaterialTable {
        material: usize,
        channel: usize,
        table: u64,
        table_count: usize,
    },
    /// A material parameter is outside its valid range.
    #[error("material {material}: {field} = {} is invalid: {rule}", Number(*value))]
    MaterialValue {
        material: usize,
        field: String,
        value: f64,
        rule: &'static str,
    },
    /// The provenance section is not valid JSON of the required shape.
    #[error("provenance is invalid: {message}")]
    ProvenanceJson { message: String },
    /// The provenance JSON repeats a key within one object.
    #[error("provenance repeats the key {key:?} within one object")]
    ProvenanceDuplicateKey { key: String },
    /// A builder was given invalid input that no file variant describes.
    #[error("invalid input: {message}")]
    InvalidInput { message: String },
    /// The file's minor version is newer than this writer's, so rewriting it could lose data.
    #[error("file format minor version {found} is newer than this tool's {supported}: it can be read but not rewritten")]
    RewriteNewerMinor { found: u16, supported: u16 },
}

impl FormatError {
    /// Stable, lowercase, kebab-case name of the variant. The conformance vectors in
    /// `tests/data/invalid/` are named `<code>.bssrdf`.
    pub fn code(&self) -> &'static str {
        match self {
            FormatError::Io { .. } => "io",
            FormatError::BigEndianHost => "big-endian-host",
            FormatError::BadMagic { .. } => "bad-magic",
            FormatError::TooShort { .. } => "too-short",
            FormatError::WrongByteOrder { .. } => "wrong-byte-order",
            FormatError::UnsupportedMajor { .. } => "unsupported-major",
            FormatError::Truncated { .. } => "truncated",
            FormatError::TrailingBytes { .. } => "trailing-bytes",
            FormatError::DirectoryOutOfBounds { .. } => "directory-out-of-bounds",
            FormatError::HeaderCrc { .. } => "header-crc",
            FormatError::UnsupportedFeatures { .. } => "unsupported-features",
            FormatError::ReservedNotZero { .. } => "reserved-not-zero",
            FormatError::BadAlignment { .. } => "bad-alignment",
            FormatError::UnknownDtype { .. } => "unknown-dtype",
            FormatError::UnknownCodec { .. } => "unknown-codec",
            FormatError::FeatureNotDeclared { .. } => "feature-not-declared",
            FormatError::HarmonicsNotDeclared { .. } => "harmonics-not-declared",
            FormatError::SignedLobesNotDeclared { .. } => "signed-lobes-not-declared",
            FormatError::BadShape { .. } => "bad-shape",
            FormatError::SectionTooLarge { .. } => "section-too-large",
            FormatError::RawLengthMismatch { .. } => "raw-length-mismatch",
            FormatError::StoredLengthMismatch { .. } => "stored-length-mismatch",
            FormatError::MisalignedSection { .. } => "misaligned-section",
            FormatError::SectionsOutOfOrder { .. } => "sections-out-of-order",
            FormatError::SectionsOverlap { .. } => "sections-overlap",
            FormatError::SectionGap { .. } => "section-gap",
            FormatError::SectionOutOfBounds { .. } => "section-out-of-bounds",
            FormatError::DataAfterLastSection { .. } => "data-after-last-section",
            FormatError::NonZeroPadding { .. } => "non-zero-padding",
            FormatError::SectionFlags { .. } => "section-flags",
            FormatError::UnknownRequiredSection { .. } => "unknown-required-section",
            FormatError::WrongDtype { .. } => "wrong-dtype",
            FormatError::SectionTableIndex { .. } => "section-table-index",
            FormatError::DuplicateSection { .. } => "duplicate-section",
            FormatError::MissingSection { .. } => "missing-section",
            FormatError::SectionCrc { .. } => "section-crc",
            FormatError::Zstd { .. } => "zstd",
            FormatError::DecodedLength { .. } => "decoded-length",
            FormatError::RecordSize { .. } => "record-size",
            FormatError::TooManyRecords { .. } => "too-many-records",
            FormatError::UnknownModel { .. } => "unknown-model",
            FormatError::WalkTablesNotDeclared { .. } => "walk-tables-not-declared",
            FormatError::UnknownComponent { .. } => "unknown-component",
            FormatError::UnknownRidge { .. } => "unknown-ridge",
            FormatError::RidgeNotDeclared { .. } => "ridge-not-declared",
            FormatError::UnknownFresnel { .. } => "unknown-fresnel",
            FormatError::TableG { .. } => "table-g",
            FormatError::TableEta { .. } => "table-eta",
            FormatError::TableDims { .. } => "table-dims",
            FormatError::SectionDims { .. } => "section-dims",
            FormatError::NonFinite { .. } => "non-finite",
            FormatError::NegativeLobe { .. } => "negative-lobe",
            FormatError::ConcentrationOutOfRange { .. } => "concentration-out-of-range",
            FormatError::NegativeProfile { .. } => "negative-profile",
            FormatError::SignedFloorNotDeclared { .. } => "signed-floor-not-declared",
            FormatError::RadialCdfDecreasing { .. } => "radial-cdf-decreasing",
            FormatError::ThetaCdfDecreasing { .. } => "theta-cdf-decreasing",
            FormatError::AxisNotIncreasing { .. } => "axis-not-increasing",
            FormatError::AxisOutOfRange { .. } => "axis-out-of-range",
            FormatError::EmptyName { .. } => "empty-name",
            FormatError::StringTooLong { .. } => "string-too-long",
            FormatError::InvalidUtf8 { .. } => "invalid-utf8",
            FormatError::ControlCharacter { .. } => "control-character",
            FormatError::DuplicateName { .. } => "duplicate-name",
            FormatError::MaterialTable { .. } => "material-table",
            FormatError::MaterialValue { .. } => "material-value",
            FormatError::ProvenanceJson { .. } => "provenance-json",
            FormatError::ProvenanceDuplicateKey { .. } => "provenance-duplicate-key",
            FormatError::InvalidInput { .. } => "invalid-input",
            FormatError::RewriteNewerMinor { .. } => "rewrite-newer-minor",
        }
    }

    pub(crate) fn io(op: &'static str, path: &std::path::Path, source: std::io::Error) -> Self {
        FormatError::Io {
            op,
            path: path.to_path_buf(),
            source,
        }
    }
}

/// Result with the format module's error type.
pub type FormatResult<T> = std::result::Result<T, FormatError>;

/// Bytes in hexadecimal, two digits each, separated by spaces: `89 42 53`.
struct Hex<'a>(&'a [u8]);

impl std::fmt::Display for Hex<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (k, byte) in self.0.iter().enumerate() {
            let gap = if k > 0 { " " } else { "" };
            write!(f, "{gap}{byte:02x}")?;
        }
        Ok(())
    }
}
