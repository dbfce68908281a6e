//! Constants, codes and fixed records of the library file format, as `format-spec.md` defines
//! them. Every record here is `#[repr(C)]`, made only of byte arrays and explicitly
//! little-endian integers, so its layout is the one a C header would declare and reading it is
//! correct on any host; compile-time assertions pin each size to the spec.

use zerocopy::little_endian::{F64, U16, U32, U64};
use zerocopy::{FromBytes, Immutable, IntoBytes, KnownLayout};

/// The 12 bytes every library file starts with: a non-ASCII first byte (so the file is never
/// taken for text), the name, CR LF and LF (so a line-ending conversion shows), and Ctrl-Z
/// (which stops a DOS `type`).
pub const MAGIC: [u8; 12] = *b"\x89BSSRDF\r\n\x1a\n\0";
/// The major version this crate reads and writes. Readers reject any other major.
pub const VERSION_MAJOR: u16 = 1;
/// The minor version this crate writes; it reads every minor of its major. Minor 1 added the
/// required feature bit 1, [`required_features::SIGNED_FLOOR`]; minor 2 the section
/// [`SectionKind::Harmonics`] with required feature bit 2, [`required_features::HARMONICS`];
/// minor 3 the required feature bit 3, [`required_features::SIGNED_LOBES`]; minor 4 the required
/// feature bit 4, [`required_features::MERGED_ROOTS`]; minor 5 the model
/// [`ModelKind::WalkAngular`] with required feature bit 5, [`required_features::WALK_TABLES`];
/// minor 6 the table record's `ridge` with required feature bit 6, [`required_features::RIDGE`].
pub const VERSION_MINOR: u16 = 6;
/// Written as a little-endian u32 at byte 16; a byte-swapped file shows `0x0D0C0B0A`.
pub const BYTE_ORDER_MARK: u32 = 0x0A0B_0C0D;

/// Size of the header at byte 0, in bytes.
pub const HEADER_SIZE: usize = 128;
/// Bytes of the header covered by the header CRC (the CRC field itself follows).
pub const HEADER_CRC_OFFSET: usize = 124;
/// Size of one directory entry, in bytes. The directory follows the header.
pub const ENTRY_SIZE: usize = 64;
/// Size of one table record in the `tables` section, in bytes (version 1.0).
pub const TABLE_RECORD_SIZE: usize = 64;
/// Size of one material record in the `materials` section, in bytes (version 1.0).
pub const MATERIAL_RECORD_SIZE: usize = 512;

/// Section alignment the writer uses unless told otherwise, in bytes.
pub const DEFAULT_ALIGNMENT: u32 = 256;
/// Smallest section alignment a file may declare, in bytes.
pub const MIN_ALIGNMENT: u32 = 256;
/// Largest section alignment a file may declare, in bytes.
pub const MAX_ALIGNMENT: u32 = 65536;

/// Most directory entries a file may have.
pub const MAX_SECTIONS: u32 = 65536;
/// Most bytes one section may hold once decoded (1 GiB): bounds every allocation.
pub const MAX_SECTION_BYTES: u64 = 1 << 30;
/// Most tables a file may hold.
pub const MAX_TABLES: u64 = 65535;
/// Most materials a file may hold.
pub const MAX_MATERIALS: u64 = 65535;
/// Most entries along one table axis.
pub const MAX_AXIS_LEN: u32 = 65536;
/// Most bytes of UTF-8 in a material name.
pub const MAX_NAME_BYTES: usize = 64;
/// Most bytes of UTF-8 in a material source.
pub const MAX_SOURCE_BYTES: usize = 256;
/// Most bytes of JSON in the provenance section.
pub const MAX_PROVENANCE_BYTES: u64 = 1 << 20;
/// Deepest nesting of arrays and objects allowed in provenance JSON.
pub const MAX_JSON_DEPTH: usize = 32;
/// The `table` field of a directory entry for a section that belongs to no table.
pub const NO_TABLE: u32 = u32::MAX;

/// Relative slack of the non-negative-profile rule of a `gwc-params` node, 2⁻²⁰ (eight f32
/// epsilons): E_β·2|c| may exceed E·(1 + |c|) by this fraction of the latter. Rounding E, E_β
/// and c to f32 moves the two sides of a node on the boundary apart by up to 3.5·2⁻²⁴; the
/// rest leaves room for a reader's f32 pre-check (see `records::node_passes_fast`).
pub const PROFILE_REL_SLACK: f64 = 1.0 / (1u64 << 20) as f64;
/// Absolute slack of the same rule, 2⁻¹²⁴ (four times the smallest normal f32): writers may
/// flush values below the smallest normal f32 to zero, which moves each side by less than
/// 2·2⁻¹²⁶.
pub const PROFILE_ABS_SLACK: f64 = 4.0 * f32::MIN_POSITIVE as f64;

/// Directory entry flag: a reader that does not know this section's kind must reject the file.
pub const SECTION_REQUIRED: u16 = 1;
/// Material flag: the record's reduced-albedo range fields are meaningful.
pub const MATERIAL_HAS_ALBEDO_RANGE: u32 = 1;

/// Feature bits a reader must understand to read the file (header bytes 32..40).
pub mod required_features {
    /// At least one section is zstd-compressed (codec 1).
    pub const ZSTD: u64 = 1 << 0;
    /// At least one `gwc-params` node has E_β > E: a negative floor α = (E − E_β)/(2πr) under
    /// its lobe (format 1.1). Readers that clamp E_β to E would misread such a file.
    pub const SIGNED_FLOOR: u64 = 1 << 1;
    /// At least one table has a `gwc-harmonics` section: its profile is two lobes rebuilt from
    /// four harmonics (format 1.2). Readers that ignore the section would read one lobe.
    pub const HARMONICS: u64 = 1 << 2;
    /// At least one `gwc-harmonics` node rebuilds into a signed pair, a sharp lobe less a
    /// broader one (format 1.3). bssrdf-zoo readers of 1.2 read it as one lobe, later ones as
    /// the pair: it had no one meaning there.
    pub const SIGNED_LOBES: u64 = 1 << 3;
    /// The file's two-lobe tables rebuild their lobes with merged roots where Prony's have
    /// none (format 1.4, `gwc::Rebuild::MergedRoots`). A 1.3 reader would read one lobe there,
    /// at nodes too.
    pub const MERGED_ROOTS: u64 = 1 << 4;
    /// At least one table is walk-angular (model 3): its record holds the walk's g and
    /// component (format 1.5). A 1.4 reader would reject the model anyway; the bit names why.
    pub const WALK_TABLES: u64 = 1 << 5;
    /// At least one table's record sets `ridge`: its nodes hold the profile less the analytic
    /// ridge of grazing incidence, which lookups add back (format 1.6, `table::ridge`). A 1.5
    /// reader would read the nodes as the whole profile.
    pub const RIDGE: u64 = 1 << 6;
    /// Every required feature this reader understands.
    pub const KNOWN: u64 =
        ZSTD | SIGNED_FLOOR | HARMONICS | SIGNED_LOBES | MERGED_ROOTS | WALK_TABLES | RIDGE;
    /// Name of a required feature bit, for messages.
    pub fn name(bit: u32) -> &'static str {
        match bit {
            0 => "zstd-sections",
            1 => "signed-floor",
            2 => "harmonics",
            3 => "signed-lobes",
            4 => "merged-roots",
            5 => "walk-tables",
            6 => "ridge",
            _ => "unknown",
        }
    }

    /// Names of the bits set in `bits`, lowest first (`"bit N"` for bits without a name).
    pub fn names(bits: u64) -> Vec<String> {
        (0..64)
            .filter(|b| bits & (1u64 << b) != 0)
            .map(|b| match name(b) {
                "unknown" => format!("bit {b}"),
                known => known.to_owned(),
            })
            .collect()
    }
}

/// Feature bits a reader may ignore (header bytes 40..48). Versions 1.0 and 1.1 define none.
pub mod optional_features {
    /// Every optional feature this reader understands.
    pub const KNOWN: u64 = 0;
}

/// What a section holds. Codes below 16 belong to the file; codes from 16 up to a table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u32)]
pub enum SectionKind {
    /// Table records, `u8 [count][64]`.
    Tables = 0x01,
    /// Material records, `u8 [count][512]`.
    Materials = 0x02,
    /// Provenance as canonical JSON, `u8 [len]`.
    Provenance = 0x03,
    /// Reduced albedo ρ′ axis, `f32 [nρ]`, strictly increasing in [0, 1].
    AxisRho = 0x10,
    /// Incidence angle θ axis in radians, `f32 [nθ]`, strictly increasing in [0, π/2].
    AxisTheta = 0x11,
    /// Radius axis in reduced mean free paths, `f32 [nr]`, strictly increasing, ≥ 0.
    AxisR = 0x12,
    /// General Wrapped Cauchy parameters (E, E_β = βr, c) interleaved, `f32 [nρ][nθ][nr][3]`.
    GwcParams = 0x20,
    /// Radial CDF, `f32 [nρ][nθ][nr]`.
    RadialCdf = 0x21,
    /// CDF over θ of the effective albedo ρ_eff(ρ′, θ), `f32 [nρ][nθ]` (optional: path tracing).
    ThetaCdf = 0x22,
    /// The third and fourth harmonics of the profile times r, (rμ₃, rμ₄), `f32 [nρ][nθ][nr][2]`
    /// (format 1.2, two-lobe tables; required feature bit 2).
    Harmonics = 0x23,
}

impl SectionKind {
    /// Every kind versions 1.0 to 1.2 define, in code order.
    pub const ALL: [SectionKind; 10] = [
        SectionKind::Tables,
        SectionKind::Materials,
        SectionKind::Provenance,
        SectionKind::AxisRho,
        SectionKind::AxisTheta,
        SectionKind::AxisR,
        SectionKind::GwcParams,
        SectionKind::RadialCdf,
        SectionKind::ThetaCdf,
        SectionKind::Harmonics,
    ];

    /// The kind's code in a directory entry.
    pub fn code(self) -> u32 {
        self as u32
    }

    /// The kind with this code, if versions 1.0 to 1.2 define one.
    pub fn from_code(code: u32) -> Option<SectionKind> {
        SectionKind::ALL.into_iter().find(|k| k.code() == code)
    }

    /// Lowercase name used in messages and in the spec.
    pub fn name(self) -> &'static str {
        match self {
            SectionKind::Tables => "tables",
            SectionKind::Materials => "materials",
            SectionKind::Provenance => "provenance",
            SectionKind::AxisRho => "axis-rho",
            SectionKind::AxisTheta => "axis-theta",
            SectionKind::AxisR => "axis-r",
            SectionKind::GwcParams => "gwc-params",
            SectionKind::RadialCdf => "radial-cdf",
            SectionKind::ThetaCdf => "theta-cdf",
            SectionKind::Harmonics => "gwc-harmonics",
        }
    }

    /// Element type of the kind.
    pub fn dtype(self) -> Dtype {
        match self {
            SectionKind::Tables | SectionKind::Materials | SectionKind::Provenance => Dtype::U8,
            _ => Dtype::F32,
        }
    }

    /// True for kinds that belong to one table rather than to the file.
    pub fn per_table(self) -> bool {
        self.code() >= 0x10
    }

    /// Value of the `required` flag a writer sets for this kind.
    pub fn required(self) -> bool {
        !matches!(self, SectionKind::Provenance | SectionKind::ThetaCdf)
    }
}

impl std::fmt::Display for SectionKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One of the three axes of a table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AxisKind {
    /// Reduced albedo ρ′ = σ′s / σ′t, dimensionless, in [0, 1].
    Rho,
    /// Incidence angle θ from the normal before refraction, radians, in [0, π/2].
    Theta,
    /// Radius in reduced mean free paths (σ′t = 1), ≥ 0.
    R,
}

impl AxisKind {
    /// The section that stores this axis.
    pub fn section(self) -> SectionKind {
        match self {
            AxisKind::Rho => SectionKind::AxisRho,
            AxisKind::Theta => SectionKind::AxisTheta,
            AxisKind::R => SectionKind::AxisR,
        }
    }

    /// Closed range of values the axis may hold, as f32.
    pub fn range(self) -> (f32, f32) {
        match self {
            AxisKind::Rho => (0.0, 1.0),
            AxisKind::Theta => (0.0, std::f32::consts::FRAC_PI_2),
            AxisKind::R => (0.0, f32::MAX),
        }
    }

    /// Lowercase name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            AxisKind::Rho => "rho",
            AxisKind::Theta => "theta",
            AxisKind::R => "r",
        }
    }
}

/// Element type of a section.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u16)]
pub enum Dtype {
    /// Bytes: records or UTF-8 text.
    U8 = 1,
    /// IEEE 754 binary32, little-endian.
    F32 = 2,
}

impl Dtype {
    /// The type with this code, if version 1.0 defines one.
    pub fn from_code(code: u16) -> Option<Dtype> {
        match code {
            1 => Some(Dtype::U8),
            2 => Some(Dtype::F32),
            _ => None,
        }
    }

    /// Size of one element in bytes.
    pub fn size(self) -> u64 {
        match self {
            Dtype::U8 => 1,
            Dtype::F32 => 4,
        }
    }

    /// Lowercase name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            Dtype::U8 => "u8",
            Dtype::F32 => "f32",
        }
    }
}

/// How a section's bytes are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u16)]
pub enum Codec {
    /// Stored as is; mappable.
    None = 0,
    /// One or more zstd frames; decoded into an aligned buffer at open.
    Zstd = 1,
}

impl Codec {
    /// The codec with this code, if version 1.0 defines one.
    pub fn from_code(code: u16) -> Option<Codec> {
        match code {
            0 => Some(Codec::None),
            1 => Some(Codec::Zstd),
            _ => None,
        }
    }
}

/// Which model a table was baked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum ModelKind {
    /// Photon beam diffusion at any incidence, tabulated as Ferrier's General Wrapped Cauchy
    /// (GWC) fit over (ρ′, θ, r).
    PbdAngular = 1,
    /// The Monte Carlo random walk at any incidence, for one Henyey–Greenstein g, tabulated
    /// as a pbd-angular table with two lobes ([`WalkSource`]; format 1.5).
    WalkAngular = 3,
}

impl ModelKind {
    /// The model with this code, if this version defines one. Code 2 is reserved for
    /// "pbd-perpendicular".
    pub fn from_code(code: u32) -> Option<ModelKind> {
        match code {
            1 => Some(ModelKind::PbdAngular),
            3 => Some(ModelKind::WalkAngular),
            _ => None,
        }
    }

    /// The model's code in a table record.
    pub fn code(self) -> u32 {
        self as u32
    }

    /// Lowercase name used in messages and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::PbdAngular => "pbd-angular",
            ModelKind::WalkAngular => "walk-angular",
        }
    }
}

/// What a walk-angular table tabulates: its table record's `component`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum WalkComponent {
    /// Multiple scattering: exits after two or more scattering vertices (what PBD models).
    Multiple = 0,
    /// Everything that leaves: single scattering included.
    Total = 1,
}

impl WalkComponent {
    /// The component with this code, if this version defines one.
    pub fn from_code(code: u32) -> Option<WalkComponent> {
        match code {
            0 => Some(WalkComponent::Multiple),
            1 => Some(WalkComponent::Total),
            _ => None,
        }
    }

    /// The component's code in a table record.
    pub fn code(self) -> u32 {
        self as u32
    }

    /// Lowercase name used in messages and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            WalkComponent::Multiple => "multiple",
            WalkComponent::Total => "total",
        }
    }
}

/// The walk a walk-angular table was measured with: its table record's `g` and `component`.
/// A walk depends on g beyond the reduced coefficients, so each table holds one g.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkSource {
    /// Henyey–Greenstein asymmetry g of the walk, in (−1, 1).
    pub g: f64,
    /// What the table tabulates.
    pub component: WalkComponent,
}

/// How the table's Fresnel moments were computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum FresnelMoments {
    /// Exact integrals of the dielectric Fresnel reflectance.
    Exact = 0,
    /// The polynomial fits used by pbrt.
    PbrtPolynomial = 1,
}

impl FresnelMoments {
    /// The convention with this code, if version 1.0 defines one.
    pub fn from_code(code: u32) -> Option<FresnelMoments> {
        match code {
            0 => Some(FresnelMoments::Exact),
            1 => Some(FresnelMoments::PbrtPolynomial),
            _ => None,
        }
    }

    /// The convention's code in a table record.
    pub fn code(self) -> u32 {
        self as u32
    }
}

/// The header at byte 0 (128 bytes).
#[derive(Debug, Clone, Copy, FromBytes, IntoBytes, KnownLayout, Immutable)]
#[repr(C)]
pub(crate) struct RawHeader {
    pub magic: [u8; 12],
    pub major: U16,
    pub minor: U16,
    pub byte_order: U32,
    pub section_count: U32,
    pub file_size: U64,
    pub required_features: U64,
    pub optional_features: U64,
    pub alignment: U32,
    pub reserved: [u8; 72],
    pub header_crc: U32,
}

/// Offset of the header's reserved bytes.
pub(crate) const HEADER_RESERVED_OFFSET: usize = 52;

/// One directory entry (64 bytes).
#[derive(Debug, Clone, Copy, FromBytes, IntoBytes, KnownLayout, Immutable)]
#[repr(C)]
pub(crate) struct RawEntry {
    pub kind: U32,
    pub table: U32,
    pub dtype: U16,
    pub codec: U16,
    pub flags: U16,
    pub ndim: U16,
    pub dims: [U32; 4],
    pub offset: U64,
    pub stored_len: U64,
    pub raw_len: U64,
    pub crc32: U32,
    pub reserved: [u8; 4],
}

/// Offset of the reserved bytes within an entry.
pub(crate) const ENTRY_RESERVED_OFFSET: usize = 60;

/// One table record (64 bytes) in the `tables` section: the fields of every model, then
/// bytes 28..63, whose fields depend on the model ([`RawPbdFields`], [`RawWalkFields`]).
#[derive(Debug, Clone, Copy, FromBytes, IntoBytes, KnownLayout, Immutable)]
#[repr(C)]
pub(crate) struct RawTable {
    pub model: U32,
    pub fresnel: U32,
    pub eta: F64,
    pub n_rho: U32,
    pub n_theta: U32,
    pub n_r: U32,
    pub by_model: [u8; TABLE_BY_MODEL_LEN],
}

/// Bytes 28..63 of a pbd-angular record (model 1): `ridge` (format 1.6: 0, 1 or 2,
/// `table::RidgeKind`), then reserved.
#[derive(Debug, Clone, Copy, FromBytes, IntoBytes, KnownLayout, Immutable)]
#[repr(C)]
pub(crate) struct RawPbdFields {
    pub ridge: U32,
    pub reserved: [u8; 32],
}

/// Bytes 28..63 of a walk-angular record (model 3): the walk's component and g (format 1.5),
/// `ridge` (format 1.6: 0, 1 or 2, `table::RidgeKind`), then reserved.
#[derive(Debug, Clone, Copy, FromBytes, IntoBytes, KnownLayout, Immutable)]
#[repr(C)]
pub(crate) struct RawWalkFields {
    pub component: U32,
    pub g: F64,
    pub ridge: U32,
    pub reserved: [u8; 20],
}

/// Offset of the fields that depend on the model within a table record; in a record of a
/// model this reader does not know, every byte from here on is reserved.
pub(crate) const TABLE_BY_MODEL_OFFSET: usize = 28;
/// Length of the fields that depend on the model.
pub(crate) const TABLE_BY_MODEL_LEN: usize = TABLE_RECORD_SIZE - TABLE_BY_MODEL_OFFSET;
/// Offset of the reserved bytes within a pbd-angular table record (after `ridge`).
pub(crate) const PBD_RESERVED_OFFSET: usize = 32;
/// Offset of the reserved bytes within a walk-angular table record (after `ridge`).
pub(crate) const WALK_RESERVED_OFFSET: usize = 44;

/// One material record (512 bytes) in the `materials` section.
#[derive(Debug, Clone, Copy, FromBytes, IntoBytes, KnownLayout, Immutable)]
#[repr(C)]
pub(crate) struct RawMaterial {
    pub name_len: U32,
    pub source_len: U32,
    pub table: [U32; 3],
    pub flags: U32,
    pub sigma_s: [F64; 3],
    pub sigma_a: [F64; 3],
    pub g: [F64; 3],
    pub eta: F64,
    pub albedo_min: [F64; 3],
    pub albedo_max: [F64; 3],
    pub reserved: [u8; 40],
    pub name: [u8; 64],
    pub source: [u8; 256],
}

/// Offset of the reserved bytes within a material record.
pub(crate) const MATERIAL_RESERVED_OFFSET: usize = 152;

const _: () = assert!(std::mem::size_of::<RawHeader>() == HEADER_SIZE);
const _: () = assert!(std::mem::size_of::<RawEntry>() == ENTRY_SIZE);
const _: () = assert!(std::mem::size_of::<RawTable>() == TABLE_RECORD_SIZE);
const _: () = assert!(std::mem::size_of::<RawMaterial>() == MATERIAL_RECORD_SIZE);
const _: () = assert!(HEADER_RESERVED_OFFSET + 72 == HEADER_CRC_OFFSET);
const _: () = assert!(MATERIAL_RESERVED_OFFSET + 40 == 192);
const _: () = assert!(std::mem::offset_of!(RawTable, by_model) == TABLE_BY_MODEL_OFFSET);
const _: () = assert!(std::mem::size_of::<RawPbdFields>() == TABLE_BY_MODEL_LEN);
const _: () = assert!(std::mem::size_of::<RawWalkFields>() == TABLE_BY_MODEL_LEN);
// Offsets within the record: ridge at 28 and reserved from 32 (model 1); component at 28, g at
// 32, ridge at 40 and reserved from 44 (model 3)
const _: () = assert!(TABLE_BY_MODEL_OFFSET + std::mem::offset_of!(RawPbdFields, ridge) == 28);
const _: () = assert!(
    TABLE_BY_MODEL_OFFSET + std::mem::offset_of!(RawPbdFields, reserved) == PBD_RESERVED_OFFSET
);
const _: () = assert!(TABLE_BY_MODEL_OFFSET + std::mem::offset_of!(RawWalkFields, g) == 32);
const _: () = assert!(TABLE_BY_MODEL_OFFSET + std::mem::offset_of!(RawWalkFields, ridge) == 40);
const _: () = assert!(
    TABLE_BY_MODEL_OFFSET + std::mem::offset_of!(RawWalkFields, reserved) == WALK_RESERVED_OFFSET
);

/// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320, as in zlib) of several byte runs.
pub(crate) fn crc32(parts: &[&[u8]]) -> u32 {
    let mut hasher = crc32fast::Hasher::new();
    for part in parts {
        hasher.update(part);
    }
    hasher.finalize()
}

/// Rounds `value` up to a multiple of `alignment` (a power of two), or `None` on overflow.
pub(crate) fn align_up(value: u64, alignment: u64) -> Option<u64> {
    let mask = alignment.checked_sub(1)?;
    value.checked_add(mask).map(|v| v & !mask)
}
