//! Table and material records: their public types, their encoding into the fixed records of
//! `spec`, and the validation rules that reader and writer share, so a file the writer accepts
//! is exactly a file the reader accepts.

use zerocopy::little_endian::{F64, U32};
use zerocopy::IntoBytes;

use super::error::{FormatError, FormatResult};
use super::spec::{
    AxisKind, FresnelMoments, ModelKind, RawMaterial, RawTable, SectionKind,
    MATERIAL_HAS_ALBEDO_RANGE, MATERIAL_RESERVED_OFFSET, MAX_AXIS_LEN, MAX_NAME_BYTES,
    MAX_SOURCE_BYTES, TABLE_RESERVED_OFFSET,
};

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

/// The fixed description of one table: model, η, Fresnel convention and dimensions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableHeader {
    /// The model the table was baked for.
    pub model: ModelKind,
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
    /// Checks η and the dimensions.
    pub fn validate(&self, index: usize) -> FormatResult<()> {
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
            SectionKind::Tables | SectionKind::Materials | SectionKind::Provenance => return None,
        })
    }

    /// Sections a table of this model must have.
    pub fn required_sections(&self) -> &'static [SectionKind] {
        match self.model {
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
        RawTable {
            model: U32::new(self.model.code()),
            fresnel: U32::new(self.fresnel.code()),
            eta: F64::new(self.eta),
            n_rho: U32::new(self.n_rho),
            n_theta: U32::new(self.n_theta),
            n_r: U32::new(self.n_r),
            reserved: [0; 36],
        }
    }

    pub(crate) fn decode(index: usize, raw: &RawTable, strict: bool) -> FormatResult<TableHeader> {
        if strict {
            check_reserved(
                &format!("table record {index}"),
                TABLE_RESERVED_OFFSET,
                &raw.reserved,
            )?;
        }
        let model = ModelKind::from_code(raw.model.get()).ok_or(FormatError::UnknownModel {
            table: index,
            model: raw.model.get(),
        })?;
        let fresnel =
            FresnelMoments::from_code(raw.fresnel.get()).ok_or(FormatError::UnknownFresnel {
                table: index,
                fresnel: raw.fresnel.get(),
            })?;
        let header = TableHeader {
            model,
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
