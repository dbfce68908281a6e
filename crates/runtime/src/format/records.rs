//! Table and material records: their public types, their encoding into the fixed records of
//! `spec`, and the validation rules that reader and writer share, so a file the writer accepts
//! is exactly a file the reader accepts.

use zerocopy::little_endian::{F64, U32};
use zerocopy::IntoBytes;

use super::error::{FormatError, FormatResult};
use super::spec::{
    required_features, AxisKind, FresnelMoments, ModelKind, RawMaterial, RawPbdFields, RawTable,
    RawWalkFields, SectionKind, WalkComponent, WalkSource, MATERIAL_HAS_ALBEDO_RANGE,
    MATERIAL_RESERVED_OFFSET, MAX_AXIS_LEN, MAX_NAME_BYTES, MAX_SOURCE_BYTES, PBD_RESERVED_OFFSET,
    PROFILE_ABS_SLACK, PROFILE_REL_SLACK, TABLE_BY_MODEL_LEN, TABLE_BY_MODEL_OFFSET,
    WALK_RESERVED_OFFSET,
};
use crate::table::RidgeKind;

/// Names of the three colour channels, in storage order.
pub const CHANNELS: [&str; 3] = ["r", "g", "b"];

/// The reduced-albedo range ρ′ ∈ [min, max] a scene needs, per channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlbedoRange {
    /// Lower bound per channel, dimensionless, in [0, 1].
    pub min: [f64; 3],
    /// Upper bound per channel, dimensionless, in [min, 1].
    pub max: [f64; 3],
}

/// A named participating medium and the tables it is rendered with. Plain data: the builder
/// and the reader validate it (see [`Material::validate`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// Unique name, UTF-8, 1 to 64 bytes, no control characters.
    pub name: String,
    /// Where the coefficients come from (paper, measurement), UTF-8, at most 256 bytes.
    pub source: String,
    /// Scattering coefficient σs per RGB channel, mm⁻¹, ≥ 0.
    pub sigma_s: [f64; 3],
    /// Absorption coefficient σa per RGB channel, mm⁻¹, ≥ 0.
    pub sigma_a: [f64; 3],
    /// Henyey–Greenstein asymmetry g per RGB channel, in (−1, 1).
    pub g: [f64; 3],
    /// Relative index of refraction η of the medium over its surroundings, > 0.
    pub eta: f64,
    /// Index of the table each RGB channel is rendered with.
    pub tables: [u32; 3],
    /// Reduced-albedo range the scene needs, if known.
    pub albedo_range: Option<AlbedoRange>,
}

impl Material {
    /// Checks every field against the format's rules; `index` names the material in errors
    /// and `table_count` bounds the table indices.
    pub fn validate(&self, index: usize, table_count: usize) -> FormatResult<()> {
        check_string(index, "name", self.name.as_bytes(), MAX_NAME_BYTES)?;
        if self.name.is_empty() {
            return Err(FormatError::EmptyName { material: index });
        }
        check_string(index, "source", self.source.as_bytes(), MAX_SOURCE_BYTES)?;
        let bad = |field: String, value: f64, rule: &'static str| {
            Err(FormatError::MaterialValue {
                material: index,
                field,
                value,
                rule,
            })
        };
        for (c, ch) in CHANNELS.iter().enumerate() {
            let (s, a, g) = (self.sigma_s[c], self.sigma_a[c], self.g[c]);
            if !(s.is_finite() && s >= 0.0) {
                return bad(
                    format!("sigma_s[{ch}]"),
                    s,
                    "must be finite and >= 0 (mm^-1)",
                );
            }
            if !(a.is_finite() && a >= 0.0) {
                return bad(
                    format!("sigma_a[{ch}]"),
                    a,
                    "must be finite and >= 0 (mm^-1)",
                );
            }
            if !(g.is_finite() && g > -1.0 && g < 1.0) {
                return bad(format!("g[{ch}]"), g, "must be in (-1, 1)");
            }
            let sigma_t_reduced = s * (1.0 - g) + a;
            if sigma_t_reduced <= 0.0 {
                return bad(
                    format!("sigma_t'[{ch}]"),
                    sigma_t_reduced,
                    "sigma_s*(1-g) + sigma_a must be > 0 (the medium is vacuum)",
                );
            }
            let table = self.tables[c];
            if table as usize >= table_count {
                return Err(FormatError::MaterialTable {
                    material: index,
                    channel: c,
                    table: table.into(),
                    table_count,
                });
            }
            if let Some(range) = &self.albedo_range {
                let (lo, hi) = (range.min[c], range.max[c]);
                if !(lo.is_finite() && (0.0..=1.0).contains(&lo)) {
                    return bad(format!("albedo_min[{ch}]"), lo, "must be in [0, 1]");
                }
                if !(hi.is_finite() && (lo..=1.0).contains(&hi)) {
                    return bad(
                        format!("albedo_max[{ch}]"),
                        hi,
                        "must be in [albedo_min, 1]",
                    );
                }
            }
        }
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return bad("eta".into(), self.eta, "must be finite and > 0");
        }
        Ok(())
    }

    pub(crate) fn encode(&self) -> RawMaterial {
        let f = |v: [f64; 3]| v.map(F64::new);
        let mut name = [0u8; MAX_NAME_BYTES];
        let mut source = [0u8; MAX_SOURCE_BYTES];
        name[..self.name.len()].copy_from_slice(self.name.as_bytes());
        source[..self.source.len()].copy_from_slice(self.source.as_bytes());
        let range = self.albedo_range.unwrap_or(AlbedoRange {
            min: [0.0; 3],
            max: [0.0; 3],
        });
        RawMaterial {
            name_len: U32::new(self.name.len() as u32),
            source_len: U32::new(self.source.len() as u32),
            table: self.tables.map(U32::new),
            flags: U32::new(if self.albedo_range.is_some() {
                MATERIAL_HAS_ALBEDO_RANGE
            } else {
                0
            }),
            sigma_s: f(self.sigma_s),
            sigma_a: f(self.sigma_a),
            g: f(self.g),
            eta: F64::new(self.eta),
            albedo_min: f(range.min),
            albedo_max: f(range.max),
            reserved: [0; 40],
            name,
            source,
        }
    }

    /// Decodes and validates record `index`. `strict` (file minor ≤ ours) also requires
    /// reserved bytes and flag bits to be zero.
    pub(crate) fn decode(
        index: usize,
        raw: &RawMaterial,
        strict: bool,
        table_count: usize,
    ) -> FormatResult<Material> {
        let what = || format!("material record {index}");
        let flags = raw.flags.get();
        if strict {
            check_reserved(&what(), MATERIAL_RESERVED_OFFSET, &raw.reserved)?;
            let unknown = flags & !MATERIAL_HAS_ALBEDO_RANGE;
            if unknown != 0 {
                return Err(reserved_bits(what(), 20, unknown));
            }
        }
        let name = decode_string(index, "name", raw.name_len.get(), &raw.name, &what(), 192)?;
        let source = decode_string(
            index,
            "source",
            raw.source_len.get(),
            &raw.source,
            &what(),
            256,
        )?;
        let f = |v: [F64; 3]| v.map(F64::get);
        let albedo_range = if flags & MATERIAL_HAS_ALBEDO_RANGE != 0 {
            Some(AlbedoRange {
                min: f(raw.albedo_min),
                max: f(raw.albedo_max),
            })
        } else {
            // Without the flag the range fields are padding.
            let bytes = [raw.albedo_min.as_bytes(), raw.albedo_max.as_bytes()].concat();
            check_reserved(&what(), 104, &bytes)?;
            None
        };
        let material = Material {
            name,
            source,
            sigma_s: f(raw.sigma_s),
            sigma_a: f(raw.sigma_a),
            g: f(raw.g),
            eta: raw.eta.get(),
            tables: raw.table.map(U32::get),
            albedo_range,
        };
        material.validate(index, table_count)?;
        Ok(material)
    }
}

fn check_string(
    material: usize,
    field: &'static str,
    bytes: &[u8],
    max: usize,
) -> FormatResult<()> {
    if bytes.len() > max {
        return Err(FormatError::StringTooLong {
            material,
            field,
            len: bytes.len() as u64,
            max,
        });
    }
    let text =
        std::str::from_utf8(bytes).map_err(|_| FormatError::InvalidUtf8 { material, field })?;
    if let Some(character) = text.chars().find(|c| c.is_control()) {
        return Err(FormatError::ControlCharacter {
            material,
            field,
            character,
        });
    }
    Ok(())
}

/// Reads a length-prefixed string field whose unused bytes must be zero.
fn decode_string(
    material: usize,
    field: &'static str,
    len: u32,
    bytes: &[u8],
    what: &str,
    field_offset: usize,
) -> FormatResult<String> {
    let len = len as usize;
    let Some(text) = bytes.get(..len) else {
        return Err(FormatError::StringTooLong {
            material,
            field,
            len: len as u64,
            max: bytes.len(),
        });
    };
    check_reserved(
        what,
        field_offset + len,
        bytes.get(len..).unwrap_or_default(),
    )?;
    check_string(material, field, text, bytes.len())?;
    Ok(String::from_utf8_lossy(text).into_owned())
}

/// Fails on the first non-zero byte of `bytes`, which start at `offset` in the structure.
pub(crate) fn check_reserved(what: &str, offset: usize, bytes: &[u8]) -> FormatResult<()> {
    match bytes.iter().position(|&b| b != 0) {
        None => Ok(()),
        Some(i) => Err(FormatError::ReservedNotZero {
            what: what.to_owned(),
            offset: offset + i,
            value: bytes[i],
        }),
    }
}

/// The error for reserved bits set in a little-endian flags field at `offset`.
pub(crate) fn reserved_bits(what: String, offset: usize, bits: u32) -> FormatError {
    let byte = bits.trailing_zeros() as usize / 8;
    FormatError::ReservedNotZero {
        what,
        offset: offset + byte,
        value: (bits >> (8 * byte)) as u8,
    }
}

/// The fixed description of one table: model, η, Fresnel convention, dimensions and whether
/// its nodes hold the profile less the ridge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableHeader {
    /// The model the table was baked for.
    pub model: ModelKind,
    /// The walk of a [`ModelKind::WalkAngular`] table (`Some` exactly for that model).
    pub walk: Option<WalkSource>,
    /// The record's `ridge` (format 1.6; value 2 added since): the nodes hold the profile S less
    /// the analytic ridge of grazing incidence, and every lookup adds it back (format-spec.md
    /// §10, "The ridge"; `table::ridge`). Files that set it need required feature bit 6.
    pub ridge: RidgeKind,
    /// Relative index of refraction η the table was baked for, > 0.
    pub eta: f64,
    /// How the Fresnel moments were computed.
    pub fresnel: FresnelMoments,
    /// Number of reduced-albedo rows nρ.
    pub n_rho: u32,
    /// Number of incidence angles nθ.
    pub n_theta: u32,
    /// Number of radii nr.
    pub n_r: u32,
}

impl TableHeader {
    /// Checks the walk (present exactly for a walk-angular table, its g finite and in
    /// (−1, 1)), η and the dimensions.
    pub fn validate(&self, index: usize) -> FormatResult<()> {
        match (self.model, self.walk) {
            (ModelKind::WalkAngular, Some(walk)) => {
                if !(walk.g > -1.0 && walk.g < 1.0) {
                    return Err(FormatError::TableG {
                        table: index,
                        g: walk.g,
                    });
                }
            }
            (ModelKind::WalkAngular, None) | (ModelKind::PbdAngular, Some(_)) => {
                return Err(FormatError::InvalidInput {
                    message: format!(
                        "table {index}: a {} table {} a walk (g and component): walk-angular tables have one, other models none",
                        self.model.name(),
                        if self.walk.is_some() { "has" } else { "lacks" }
                    ),
                });
            }
            (ModelKind::PbdAngular, None) => {}
        }
        if !(self.eta.is_finite() && self.eta > 0.0) {
            return Err(FormatError::TableEta {
                table: index,
                eta: self.eta,
            });
        }
        let dims = [self.n_rho, self.n_theta, self.n_r];
        if dims.iter().any(|&n| n == 0 || n > MAX_AXIS_LEN) {
            return Err(FormatError::TableDims {
                table: index,
                dims,
                max: MAX_AXIS_LEN,
            });
        }
        Ok(())
    }

    /// Dimensions a section of this kind must have in this table, or `None` for kinds that
    /// do not belong to tables.
    pub fn expected_dims(&self, kind: SectionKind) -> Option<Vec<u32>> {
        let (a, t, r) = (self.n_rho, self.n_theta, self.n_r);
        Some(match kind {
            SectionKind::AxisRho => vec![a],
            SectionKind::AxisTheta => vec![t],
            SectionKind::AxisR => vec![r],
            SectionKind::GwcParams => vec![a, t, r, 3],
            SectionKind::RadialCdf => vec![a, t, r],
            SectionKind::ThetaCdf => vec![a, t],
            SectionKind::Harmonics => vec![a, t, r, 2],
            SectionKind::Tables | SectionKind::Materials | SectionKind::Provenance => return None,
        })
    }

    /// Sections a table of this model must have.
    pub fn required_sections(&self) -> &'static [SectionKind] {
        match self.model {
            ModelKind::WalkAngular => &[
                SectionKind::AxisRho,
                SectionKind::AxisTheta,
                SectionKind::AxisR,
                SectionKind::GwcParams,
                SectionKind::RadialCdf,
                SectionKind::Harmonics,
            ],
            ModelKind::PbdAngular => &[
                SectionKind::AxisRho,
                SectionKind::AxisTheta,
                SectionKind::AxisR,
                SectionKind::GwcParams,
                SectionKind::RadialCdf,
            ],
        }
    }

    pub(crate) fn encode(&self) -> RawTable {
        let ridge = U32::new(self.ridge.code());
        // Bytes 28..63 in the layout of the model (a table has a walk exactly when it is
        // walk-angular: `validate`)
        let by_model: [u8; TABLE_BY_MODEL_LEN] = match self.walk {
            Some(walk) => zerocopy::transmute!(RawWalkFields {
                component: U32::new(walk.component.code()),
                g: F64::new(walk.g),
                ridge,
                reserved: [0; 20],
            }),
            None => zerocopy::transmute!(RawPbdFields {
                ridge,
                reserved: [0; 32],
            }),
        };
        RawTable {
            model: U32::new(self.model.code()),
            fresnel: U32::new(self.fresnel.code()),
            eta: F64::new(self.eta),
            n_rho: U32::new(self.n_rho),
            n_theta: U32::new(self.n_theta),
            n_r: U32::new(self.n_r),
            by_model,
        }
    }

    /// Decodes and validates record `index` of a file whose required feature bits are
    /// `required`, in the order of format-spec.md §14. `strict` (file minor ≤ ours) also
    /// requires the reserved bytes to be zero: from byte 44 in a walk-angular record, from
    /// byte 32 in a pbd-angular one and from byte 28 in a record of an unknown model.
    pub(crate) fn decode(
        index: usize,
        raw: &RawTable,
        strict: bool,
        required: u64,
    ) -> FormatResult<TableHeader> {
        // The layout of bytes 28..63 by model code; none for a code rejected below
        let (walk_fields, ridge_code, reserved_from) = match ModelKind::from_code(raw.model.get()) {
            Some(ModelKind::WalkAngular) => {
                let fields: RawWalkFields = zerocopy::transmute!(raw.by_model);
                (Some(fields), fields.ridge.get(), WALK_RESERVED_OFFSET)
            }
            Some(ModelKind::PbdAngular) => {
                let fields: RawPbdFields = zerocopy::transmute!(raw.by_model);
                (None, fields.ridge.get(), PBD_RESERVED_OFFSET)
            }
            None => (None, 0, TABLE_BY_MODEL_OFFSET),
        };
        if strict {
            let reserved = raw.as_bytes().get(reserved_from..).unwrap_or_default();
            check_reserved(&format!("table record {index}"), reserved_from, reserved)?;
        }
        let model = ModelKind::from_code(raw.model.get()).ok_or(FormatError::UnknownModel {
            table: index,
            model: raw.model.get(),
        })?;
        let walk = match walk_fields {
            Some(fields) => {
                if required & required_features::WALK_TABLES == 0 {
                    return Err(FormatError::WalkTablesNotDeclared { table: index });
                }
                let code = fields.component.get();
                let component =
                    WalkComponent::from_code(code).ok_or(FormatError::UnknownComponent {
                        table: index,
                        component: code,
                    })?;
                Some(WalkSource {
                    g: fields.g.get(),
                    component,
                })
            }
            None => None,
        };
        let ridge = RidgeKind::from_code(ridge_code).ok_or(FormatError::UnknownRidge {
            table: index,
            ridge: ridge_code,
        })?;
        if ridge.is_some() && required & required_features::RIDGE == 0 {
            return Err(FormatError::RidgeNotDeclared {
                table: index,
                ridge: ridge_code,
            });
        }
        let fresnel =
            FresnelMoments::from_code(raw.fresnel.get()).ok_or(FormatError::UnknownFresnel {
                table: index,
                fresnel: raw.fresnel.get(),
            })?;
        let header = TableHeader {
            model,
            walk,
            ridge,
            eta: raw.eta.get(),
            fresnel,
            n_rho: raw.n_rho.get(),
            n_theta: raw.n_theta.get(),
            n_r: raw.n_r.get(),
        };
        header.validate(index)?;
        Ok(header)
    }
}

/// Checks that every value is finite.
pub(crate) fn check_finite(table: usize, kind: SectionKind, values: &[f32]) -> FormatResult<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(FormatError::NonFinite {
            table,
            kind,
            index,
            value: values[index],
        }),
    }
}

/// Checks that every (ρ′, θ) row of a `radial-cdf` section is what a running integral over r
/// of a positive part is (format-spec.md §10): its values ≥ 0 and never decreasing along r.
/// NaN fails too (it is checked for finiteness first, in reading).
pub(crate) fn check_radial_cdf(
    table: usize,
    header: &TableHeader,
    values: &[f32],
) -> FormatResult<()> {
    // Dimensions are validated to be ≥ 1; `max` only keeps this free of panics regardless.
    let n_r = (header.n_r as usize).max(1);
    let n_theta = (header.n_theta as usize).max(1);
    match first_fall(values, n_r) {
        None => Ok(()),
        Some((row, k, previous, value)) => Err(FormatError::RadialCdfDecreasing {
            table,
            node: (row / n_theta, row % n_theta, k),
            previous,
            value,
        }),
    }
}

/// Checks that every ρ′ row of a `theta-cdf` section is what a running integral over θ of
/// ρ_eff ≥ 0 is (format-spec.md §10), as [`check_radial_cdf`] along r: its values ≥ 0 and
/// never decreasing along θ. A path tracer draws θ by inverting it.
pub(crate) fn check_theta_cdf(
    table: usize,
    header: &TableHeader,
    values: &[f32],
) -> FormatResult<()> {
    let n_theta = (header.n_theta as usize).max(1);
    match first_fall(values, n_theta) {
        None => Ok(()),
        Some((row, j, previous, value)) => Err(FormatError::ThetaCdfDecreasing {
            table,
            node: (row, j),
            previous,
            value,
        }),
    }
}

/// The first value, in rows of `len`, that is below 0 or below the one before it in its row
/// (NaN included): (row, index in the row, the value before it or 0, the value).
fn first_fall(values: &[f32], len: usize) -> Option<(usize, usize, f32, f32)> {
    // One branch-free pass (it vectorises), then the first failure named where there is one
    let fast = values.chunks_exact(len).all(|row| {
        let rising = row[1..]
            .iter()
            .zip(row)
            .fold(true, |ok, (next, before)| ok & (next >= before));
        rising & (row[0] >= 0.0)
    });
    if fast {
        return None;
    }
    for (row, cdf) in values.chunks_exact(len).enumerate() {
        let mut previous = 0.0f32;
        for (k, &value) in cdf.iter().enumerate() {
            // Not ≥ (NaN included)
            if value.partial_cmp(&previous).is_none_or(|o| o.is_lt()) {
                return Some((row, k, previous, value));
            }
            previous = value;
        }
    }
    None
}

/// Checks that an axis is finite, strictly increasing and within its quantity's range.
pub(crate) fn check_axis(table: usize, axis: AxisKind, values: &[f32]) -> FormatResult<()> {
    check_finite(table, axis.section(), values)?;
    let (min, max) = axis.range();
    for (index, &value) in values.iter().enumerate() {
        if !(min..=max).contains(&value) {
            return Err(FormatError::AxisOutOfRange {
                table,
                axis: axis.name(),
                index,
                value,
                min,
                max,
            });
        }
        if let Some(&previous) = index.checked_sub(1).and_then(|i| values.get(i)) {
            if value <= previous {
                return Err(FormatError::AxisNotIncreasing {
                    table,
                    axis: axis.name(),
                    index,
                    previous,
                    value,
                });
            }
        }
    }
    Ok(())
}

/// Whether a finite `gwc-params` node (E, E_β, c) describes a profile that is ≥ 0 at every
/// azimuth (format-spec.md §10), exactly as the spec states the rule: E_β ≥ 0, |c| < 1 and
/// E_β·2|c| ≤ E·(1 + |c|) up to [`PROFILE_REL_SLACK`] and [`PROFILE_ABS_SLACK`], in f64 from
/// the widened f32 values. The last is α + β·min pdf_WC ≥ 0 with α = (E − E_β)/(2πr),
/// β = E_β/r and min pdf_WC = (1 − |c|)/(2π(1 + |c|)), multiplied by 2πr(1 + |c|) > 0.
fn node_is_valid(e: f32, e_beta: f32, c: f32) -> bool {
    let (e, e_beta, c) = (f64::from(e), f64::from(e_beta), f64::from(c).abs());
    let (lobe, bound) = profile_sides(e, e_beta, c);
    (e_beta >= 0.0) & (c < 1.0) & (lobe <= bound)
}

/// The two sides of the profile rule in the order the spec evaluates them: (2·E_β)·|c|, and
/// E·(1 + |c|) widened by the slacks. `abs_c` is |c|.
fn profile_sides(e: f64, e_beta: f64, abs_c: f64) -> (f64, f64) {
    let floor = e * (1.0 + abs_c);
    (
        2.0 * e_beta * abs_c,
        floor + floor.abs() * PROFILE_REL_SLACK + PROFILE_ABS_SLACK,
    )
}

/// Relative slack of the f32 pre-check [`node_passes_fast`], 2⁻²¹.
const FAST_REL_SLACK: f32 = 1.0 / (1u32 << 21) as f32;

/// A sufficient test of [`node_is_valid`] in f32, which also fails any non-finite value: true
/// only for finite nodes that `node_is_valid` accepts. Proof: with u = 2⁻²⁴, each f32 product
/// or sum below errs by at most u relative (0.5·E is exact; underflow adds at most 2⁻¹⁴⁹ per
/// operation, far below [`PROFILE_ABS_SLACK`]), so passing here means
/// 2E_β|c| ≤ E(1 + |c|)·(1 + 2⁻²¹)(1 + u)³/(1 − u) < E(1 + |c|)·(1 + 2⁻²⁰). The right side
/// cannot overflow to a false pass: (0.5·E)(1 + |c|) < E ≤ f32::MAX, and where the last factor
/// overflows, E(1 + |c|) is within 2⁻²¹ of 2·f32::MAX while 2E_β|c| < 2·f32::MAX. Conversely a
/// node that lies on the boundary before its values are rounded to f32 is off by at most
/// 3.5u after rounding and (away from underflow) passes here. NaN fails every comparison; E = +∞ fails the first.
#[inline(always)]
fn node_passes_fast(e: f32, e_beta: f32, c: f32) -> bool {
    let abs_c = c.abs();
    let bound = 0.5 * e * (1.0 + abs_c) * (1.0 + FAST_REL_SLACK);
    // `&`, not `&&`: no branches, so the scan over all nodes vectorises.
    (e <= f32::MAX) & (e_beta >= 0.0) & (abs_c < 1.0) & (e_beta * abs_c <= bound)
}

/// True if some node of a `gwc-params` array `[..][3]` has E_β > E, a negative floor: the
/// file must then set the required feature bit `signed-floor`.
pub(crate) fn has_signed_floor(values: &[f32]) -> bool {
    values
        .chunks_exact(3)
        .fold(false, |any, n| any | (n[1] > n[0]))
}

/// Checks table `table`'s `gwc-params` (`[nρ][nθ][nr][3]` with the table's `n_theta`, `n_r`):
/// every value finite, then every node in index order with E_β ≥ 0, |c| < 1, a profile ≥ 0,
/// and E_β ≤ E unless `signed_floor` (the file's required feature bit 1) allows a negative
/// floor; the first failing node is reported, its rules checked in that order. One
/// branch-free f32 pass over the values decides for every valid section (it also covers
/// finiteness, so the reader runs no separate NaN scan here); only a section it does not pass
/// is looked at node by node, in f64 where the f32 test is not conclusive.
pub(crate) fn check_gwc_nodes(
    table: usize,
    header: &TableHeader,
    values: &[f32],
    signed_floor: bool,
) -> FormatResult<()> {
    let (fast, negative_floor) = values
        .chunks_exact(3)
        .fold((true, false), |(ok, floor), n| {
            (
                ok & node_passes_fast(n[0], n[1], n[2]),
                floor | (n[1] > n[0]),
            )
        });
    if fast && (signed_floor || !negative_floor) {
        return Ok(());
    }
    check_finite(table, SectionKind::GwcParams, values)?;
    // Dimensions are validated to be ≥ 1; `max` only keeps this free of panics regardless.
    let n_r = (header.n_r as usize).max(1);
    let n_theta = (header.n_theta as usize).max(1);
    for (flat, n) in values.chunks_exact(3).enumerate() {
        let (e, e_beta, c) = (n[0], n[1], n[2]);
        let floor_ok = signed_floor || e_beta <= e;
        if floor_ok && node_passes_fast(e, e_beta, c) {
            continue;
        }
        let node = (flat / n_r / n_theta, flat / n_r % n_theta, flat % n_r);
        if e_beta < 0.0 {
            return Err(FormatError::NegativeLobe {
                table,
                node,
                e_beta,
            });
        }
        if c.abs() >= 1.0 {
            return Err(FormatError::ConcentrationOutOfRange { table, node, c });
        }
        if !node_is_valid(e, e_beta, c) {
            let (lobe, _) = profile_sides(e.into(), e_beta.into(), f64::from(c).abs());
            return Err(FormatError::NegativeProfile {
                table,
                node,
                e,
                e_beta,
                c,
                lobe,
                floor: f64::from(e) * (1.0 + f64::from(c).abs()),
            });
        }
        if !floor_ok {
            return Err(FormatError::SignedFloorNotDeclared {
                table,
                node,
                e,
                e_beta,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(n_rho: u32, n_theta: u32, n_r: u32) -> TableHeader {
        TableHeader {
            model: ModelKind::PbdAngular,
            walk: None,
            ridge: RidgeKind::None,
            eta: 1.3,
            fresnel: FresnelMoments::Exact,
            n_rho,
            n_theta,
            n_r,
        }
    }

    /// A radial CDF row may stay flat (E = 0 over a segment) and start above 0 (the spec's
    /// example does); a value below 0, below the one before it or NaN is named by its node.
    #[test]
    fn radial_cdf_rows_are_running_integrals() {
        let h = header(1, 2, 3);
        assert!(check_radial_cdf(0, &h, &[0.0, 0.0, 1.0, 0.5, 0.5, 2.0]).is_ok());
        for (values, node) in [
            ([-1e-30, 0.0, 1.0, 0.0, 1.0, 2.0], (0, 0, 0)),
            ([0.0, 0.5, 1.0, 0.0, 1.0, 0.999], (0, 1, 2)),
            ([0.0, f32::NAN, 1.0, 0.0, 1.0, 2.0], (0, 0, 1)),
        ] {
            match check_radial_cdf(7, &h, &values) {
                Err(FormatError::RadialCdfDecreasing {
                    table: 7, node: n, ..
                }) => {
                    assert_eq!(n, node, "{values:?}")
                }
                other => panic!("{values:?}: {other:?}"),
            }
        }
    }

    /// The same rule along θ, per ρ′ row.
    #[test]
    fn theta_cdf_rows_are_running_integrals() {
        let h = header(2, 3, 1);
        assert!(check_theta_cdf(0, &h, &[0.0, 0.0, 1.0, 0.0, 0.5, 0.5]).is_ok());
        for (values, node) in [
            ([0.0, 0.5, 0.4, 0.0, 1.0, 2.0], (0, 2)),
            ([0.0, 0.5, 1.0, -1e-30, 1.0, 2.0], (1, 0)),
            ([0.0, 0.5, 1.0, 0.0, f32::NAN, 2.0], (1, 1)),
        ] {
            match check_theta_cdf(3, &h, &values) {
                Err(FormatError::ThetaCdfDecreasing {
                    table: 3, node: n, ..
                }) => {
                    assert_eq!(n, node, "{values:?}")
                }
                other => panic!("{values:?}: {other:?}"),
            }
        }
    }

    #[test]
    fn profile_slacks_are_the_spec_values() {
        assert_eq!(PROFILE_REL_SLACK, 2f64.powi(-20));
        assert_eq!(PROFILE_REL_SLACK, 8.0 * f64::from(f32::EPSILON));
        assert_eq!(f64::from(FAST_REL_SLACK), 2f64.powi(-21));
        assert_eq!(PROFILE_ABS_SLACK, 2f64.powi(-124));
    }

    #[test]
    fn node_rule_is_the_minimum_of_the_profile() {
        // E_β = E(1 + |c|)/(2|c|) puts the minimum at exactly 0: (1, 2.5, ±0.25) is exact.
        assert!(node_is_valid(1.0, 2.5, 0.25) && node_is_valid(1.0, 2.5, -0.25));
        assert!(!node_is_valid(1.0, 2.5001, 0.25));
        // c = 0: any lobe over E ≥ 0 is the flat profile E/(2πr).
        assert!(node_is_valid(0.5, 1e6, 0.0) && node_is_valid(0.0, 0.0, 0.0));
        assert!(!node_is_valid(-0.5, 0.0, 0.0));
        // 0 ≤ E_β ≤ E is always a profile ≥ 0 for |c| < 1.
        assert!(node_is_valid(1.0, 1.0, 0.99) && node_is_valid(1.0, 0.0, -0.99));
        assert!(!node_is_valid(1.0, -0.01, 0.0));
        assert!(!node_is_valid(1.0, 0.5, 1.0) && !node_is_valid(1.0, 0.5, -1.0));
        // Below the smallest normal f32 a writer may have flushed E to 0: up to 2^-124 passes.
        assert!(node_is_valid(0.0, 1e-38, 0.5));
        assert!(!node_is_valid(0.0, 1e-37, 0.5));
    }

    #[test]
    fn the_f32_pre_check_is_sufficient_and_passes_rounded_boundary_nodes() {
        // Nodes around the boundary E_β = E(1 + |c|)/(2|c|), over many decades of E and c
        // from a fixed LCG: a node on it in f64, with all three values rounded to f32.
        let mut state = 0x853c_49e6_748f_ea9bu64;
        let mut uniform = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut fast, mut exact) = (0, 0);
        for _ in 0..20_000 {
            let e64 = 10f64.powf(-30.0 + 60.0 * uniform());
            let c64 = (1.0 - 10f64.powf(-6.0 * uniform())) * (2.0 * uniform() - 1.0);
            let boundary = (e64 * (1.0 + c64.abs()) / (2.0 * c64.abs())) as f32;
            let (e, c) = (e64 as f32, c64 as f32);
            if c == 0.0 || !boundary.is_finite() {
                continue;
            }
            assert!(node_passes_fast(e, boundary, c), "({e}, {boundary}, {c})");
            for ulps in -20i32..=20 {
                let e_beta = f32::from_bits((boundary.to_bits() as i32 + ulps) as u32);
                let passes = node_passes_fast(e, e_beta, c);
                assert!(
                    !passes || node_is_valid(e, e_beta, c),
                    "({e}, {e_beta}, {c})"
                );
                fast += usize::from(passes);
                exact += usize::from(node_is_valid(e, e_beta, c));
            }
        }
        // The f32 test is not much stricter than the rule: a few ulps of E_β at most.
        assert!(fast > exact * 3 / 4, "{fast} of {exact}");
        // Non-finite values never pass.
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            assert!(!node_passes_fast(bad, 0.5, 0.25));
            assert!(!node_passes_fast(1.0, bad, 0.25));
            assert!(!node_passes_fast(1.0, 0.5, bad));
        }
        // Near f32::MAX the bound may overflow, still only for valid nodes.
        assert!(node_is_valid(f32::MAX, f32::MAX, 0.999_999_9));
        assert!(!node_passes_fast(f32::MAX / 4.0, f32::MAX, 0.999_999_9));
        assert!(!node_is_valid(f32::MAX / 4.0, f32::MAX, 0.999_999_9));
    }

    #[test]
    fn node_errors_name_the_node_and_the_values() {
        let h = header(2, 3, 5);
        let values = [1.0f32, 0.5, 0.25].repeat(2 * 3 * 5);
        assert!(check_gwc_nodes(4, &h, &values, false).is_ok());
        assert!(!has_signed_floor(&values));
        // Node (1, 2, 3) is flat index (1·3 + 2)·5 + 3 = 28.
        let at = 28 * 3;
        let cases: [([f32; 3], &str, &str); 4] = [
            ([1.0, -0.5, 0.25], "negative-lobe", "E_beta = -0.5"),
            ([1.0, 0.5, -1.0], "concentration-out-of-range", "c = -1"),
            (
                [0.2, 1.0, 0.5],
                "negative-profile",
                "E_beta*2|c| = 1 exceeds",
            ),
            (
                [1.0, 1.5, 0.25],
                "signed-floor-not-declared",
                "E_beta = 1.5 > E = 1",
            ),
        ];
        for (node, code, needle) in cases {
            let mut bad = values.clone();
            bad[at..at + 3].copy_from_slice(&node);
            let err = check_gwc_nodes(4, &h, &bad, false).unwrap_err();
            assert_eq!(err.code(), code, "{err}");
            let message = err.to_string();
            assert!(message.contains("table 4"), "{message}");
            assert!(message.contains("(1, 2, 3)"), "{message}");
            assert!(message.contains(needle), "{message}");
            // The signed-floor bit only lifts E_β ≤ E.
            let declared = check_gwc_nodes(4, &h, &bad, true);
            assert_eq!(declared.is_ok(), code == "signed-floor-not-declared");
        }
    }

    #[test]
    fn the_first_bad_node_in_index_order_is_reported() {
        let h = header(2, 3, 5);
        let mut values = [1.0f32, 0.5, 0.25].repeat(2 * 3 * 5);
        values[3 * 7 + 1] = 2.0; // node 7 = (0, 1, 2): a negative floor
        values[3 * 9 + 1] = -1.0; // node 9 = (0, 1, 4): a negative lobe
        assert!(has_signed_floor(&values));
        let err = check_gwc_nodes(0, &h, &values, false).unwrap_err();
        assert_eq!(err.code(), "signed-floor-not-declared");
        assert!(err.to_string().contains("(0, 1, 2)"), "{err}");
        let err = check_gwc_nodes(0, &h, &values, true).unwrap_err();
        assert_eq!(err.code(), "negative-lobe");
        assert!(err.to_string().contains("(0, 1, 4)"), "{err}");
    }
}
