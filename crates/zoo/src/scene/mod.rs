//! Scene manifests: the materials a scene uses, the reduced-albedo range each channel reaches,
//! and the integrator, so that a bake keeps only the albedo rows, tables and sections the scene
//! needs (`bssrdf bake --scene SCENE.toml`).
//!
//! ```toml
//! integrator = "path"              # "path" (default) keeps the θ-sampling table, "particle" drops it
//!
//! [[material]]
//! name = "white-grapefruit-juice"  # a library material; constant: the rows around its three ρ′
//!
//! [[material]]
//! name = "skin1"
//! albedo_range = [[0.85, 0.97], [0.80, 0.90], [0.60, 0.70]]   # ρ′ per channel r, g, b
//!
//! [[material]]
//! name = "my-wax"                  # inline coefficients: σs, σa in mm⁻¹
//! sigma_s = [1.0, 1.1, 1.2]
//! sigma_a = [0.01, 0.02, 0.05]
//! g = 0.3                          # one value or three; default 0
//! eta = 1.45                       # default 1.33 for inline materials
//!
//! [[material]]
//! name = "my-jade"                 # the artist's parameters (see `artist`)
//! reflectance = [0.6, 0.8, 0.5]
//! mfp = [2.0, 3.0, 1.5]            # unreduced mean free path 1/σt, mm
//! ```
//!
//! | field | unit | valid | meaning |
//! |---|---|---|---|
//! | `integrator` | – | `"path"` or `"particle"`, default `"path"` | path tracing samples θ and needs the `theta-cdf` section |
//! | `material.name` | – | a library id (any spelling the library accepts), or with coefficients a new kebab-case id | the material |
//! | `material.albedo_range` | – | in [0, 1], min ≤ max, no NaN | the reduced albedo ρ′ the material's textures reach: `[min, max]` for all channels, or three entries (r, g, b) each `[min, max]` or one value. Default: the material's own ρ′ |
//! | `material.eta` | – | [0.75, 2.5] | η override for a library material; η of an inline one (default 1.33) |
//! | `material.sigma_s`, `sigma_a` | mm⁻¹ | 3 values ≥ 0 | inline unreduced coefficients (both needed) |
//! | `material.g` | – | (−1, 1), 1 or 3 values | Henyey–Greenstein g of an inline material (default 0) |
//! | `material.reflectance`, `mfp` | –, mm | [0, 1]; > 0; 3 values each | inline artist's parameters (both needed) |
//! | `material.source` | – | ≤ 256 bytes | where an inline material's numbers come from |
//!
//! Unknown fields are errors, as are a material named twice, a library name that does not exist
//! (with suggestions), coefficients mixed with artist's parameters, and `g` or `source` on a
//! library material. A library material whose own ρ′ lies outside its declared range is kept
//! as declared and reported by [`Scene::warnings`] (lookups at that ρ′ would be refused).
//!
//! [`Scene::plan`] turns the scene into tables: per η, each channel's range becomes the rows
//! of [`crate::table::rows_for`], rows that overlap or touch merge into one run, and each run is
//! one table (disjoint runs stay separate tables, so a lookup between them is refused instead of
//! being interpolated across the gap); each channel of each material points to its run's table.

pub mod artist;

use crate::catmull_rom::Nodes;
use crate::format;
use crate::materials::{Library, Material, MaterialError};
use crate::table::{merge_runs, rows_for, RhoInterval, SubsetError};
use artist::{ArtistError, ReflectanceCurve};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::ops::Range;
use toml::Value;

/// η of an inline material that gives none (pbrt's default for its subsurface material).
pub const DEFAULT_ETA: f64 = 1.33;

/// Channel names in storage order.
const CHANNELS: [&str; 3] = ["r", "g", "b"];

/// How the renderer uses the tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Integrator {
    /// Path tracing: samples the incidence θ, needs the `theta-cdf` section.
    #[default]
    Path,
    /// Particle tracing: θ is known, the `theta-cdf` section is left out.
    Particle,
}

impl Integrator {
    /// Whether the θ-sampling table is kept.
    pub fn needs_theta_sampling(self) -> bool {
        self == Integrator::Path
    }
}

/// Where a scene material's coefficients come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Origin {
    /// The named-material library.
    Library,
    /// σs, σa, g given in the manifest.
    Coefficients,
    /// Reflectance and mean free path given in the manifest.
    Diffuse,
}

/// Why a scene manifest was rejected. Messages name the material, the field and the value.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// Not TOML, a field of the wrong type, or a field the schema does not know.
    #[error("scene manifest: {0}")]
    Toml(String),
    /// No `[[material]]` entry.
    #[error("scene manifest lists no material: add a [[material]] entry with a name")]
    NoMaterials,
    /// A value that must be a number is not one.
    #[error("material {material:?}: {field} = {text} is not a number")]
    NotANumber {
        material: String,
        field: String,
        text: String,
    },
    /// A per-channel field has the wrong number of values.
    #[error("material {material:?}: {field} has {count} values; it needs {expected}")]
    Count {
        material: String,
        field: &'static str,
        count: usize,
        expected: &'static str,
    },
    /// `albedo_range` is not one of its accepted shapes.
    #[error(
        "material {material:?}: albedo_range = {text} must be [min, max] for every channel, or \
         three entries (r, g, b), each a value or [min, max]"
    )]
    AlbedoShape { material: String, text: String },
    /// An albedo range is NaN, outside [0, 1] or reversed.
    #[error("material {material:?}: albedo_range[{channel}]: {source}")]
    Albedo {
        material: String,
        channel: &'static str,
        source: SubsetError,
    },
    /// Two ways of giving coefficients at once.
    #[error("material {material:?}: give {first} or {second}, not both")]
    Conflict {
        material: String,
        first: &'static str,
        second: &'static str,
    },
    /// Half of a pair of fields.
    #[error("material {material:?}: {given} needs {missing} too")]
    Missing {
        material: String,
        given: &'static str,
        missing: &'static str,
    },
    /// A field that only inline materials take, on a library material.
    #[error(
        "material {material:?}: {field} applies to inline materials only (with sigma_s/sigma_a or \
         reflectance/mfp); a library material brings its own"
    )]
    NeedsCoefficients {
        material: String,
        field: &'static str,
    },
    /// The library has no such material, or the inline coefficients are invalid.
    #[error("material {material:?}: {source}")]
    Material {
        material: String,
        source: Box<MaterialError>,
    },
    /// The artist's parameters cannot be inverted.
    #[error("material {material:?}: {source}")]
    Artist {
        material: String,
        source: ArtistError,
    },
    /// The η a manifest gives a library material, outside [`crate::medium::ETA_MIN`,
    /// `ETA_MAX`].
    #[error(
        "material {material:?}: eta = {} is outside [{}, {}] (the manifest's eta for this library material)",
        crate::error::number(*eta),
        crate::error::number(crate::medium::ETA_MIN),
        crate::error::number(crate::medium::ETA_MAX)
    )]
    EtaOverride { material: String, eta: f64 },
    /// The same material twice.
    #[error("material {0:?} is listed twice")]
    Duplicate(String),
    /// A `source` longer than the file format keeps.
    #[error("material {material:?}: source is {bytes} bytes; a library file keeps at most {MAX_SOURCE_BYTES}")]
    SourceTooLong { material: String, bytes: usize },
    /// An inline material (coefficients or the artist's parameters) named like a library one.
    #[error("material {material:?}: inline coefficients need a new id, but this names the library material {library:?}; choose another name, or drop the coefficients to use the library's")]
    InlineTakesLibraryName { material: String, library: String },
    /// A `source` with a control character, which the file format refuses.
    #[error("material {material:?}: source has the control character {character:?} at byte {at}; a library file keeps text without them")]
    SourceControl {
        material: String,
        character: char,
        at: usize,
    },
    /// A range is not covered by the table's albedo axis.
    #[error("albedo rows for material {material:?}, channel {channel}: {source}")]
    Plan {
        material: String,
        channel: &'static str,
        source: SubsetError,
    },
}

/// The manifest as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawManifest {
    #[serde(default)]
    integrator: Integrator,
    #[serde(default)]
    material: Vec<RawMaterial>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMaterial {
    name: String,
    albedo_range: Option<Value>,
    eta: Option<Value>,
    sigma_s: Option<Value>,
    sigma_a: Option<Value>,
    g: Option<Value>,
    reflectance: Option<Value>,
    mfp: Option<Value>,
    source: Option<String>,
}

/// One material of a resolved scene: its coefficients, the ranges its channels need and where
/// it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneMaterial {
    material: Material,
    source: String,
    ranges: [RhoInterval; 3],
    declared: bool,
    origin: Origin,
    /// Per channel, where the reflectance was above the largest the table reaches: it and that
    /// largest (ρ′ clamped to 1).
    clamped: [Option<(f64, f64)>; 3],
}

impl SceneMaterial {
    /// The validated material (its id is the name stored in the file).
    pub fn material(&self) -> &Material {
        &self.material
    }
    /// The reduced-albedo range of each channel.
    pub fn ranges(&self) -> &[RhoInterval; 3] {
        &self.ranges
    }
    /// Whether the ranges were declared (`albedo_range`) rather than the material's own ρ′.
    pub fn declared(&self) -> bool {
        self.declared
    }
    /// Where the coefficients come from.
    pub fn origin(&self) -> Origin {
        self.origin
    }
    /// The file's record of this material with the tables of its channels and its ranges.
    pub fn record(&self, tables: [u32; 3]) -> format::Material {
        let m = &self.material;
        format::Material {
            name: m.id().to_string(),
            source: truncate(&self.source, MAX_SOURCE_BYTES),
            sigma_s: m.sigma_s(),
            sigma_a: m.sigma_a(),
            g: m.g(),
            eta: m.eta(),
            tables,
            albedo_range: Some(format::AlbedoRange {
                min: self.ranges.map(|r| r.lo()),
                max: self.ranges.map(|r| r.hi()),
            }),
        }
    }
}

/// A parsed and resolved scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    integrator: Integrator,
    materials: Vec<SceneMaterial>,
}

/// One table to bake: η and a run of albedo rows of the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedTable {
    /// Relative index of refraction.
    pub eta: f64,
    /// Albedo rows of the grid's ρ′ axis.
    pub rows: Range<usize>,
    /// The declared ranges the table serves.
    pub serves: Vec<RhoInterval>,
}

/// The tables of a scene and the table of every material channel.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenePlan {
    /// Tables in file order: by η, then by row.
    pub tables: Vec<PlannedTable>,
    /// Per scene material (in scene order), the index into `tables` of each channel.
    pub channel_tables: Vec<[usize; 3]>,
}

impl Scene {
    /// Parses a manifest and resolves its materials in `library`. `curve(η)` gives the
    /// diffuse-reflectance curve that inverts the artist's parameters of materials at η (called
    /// only for such materials, once per η).
    pub fn from_toml_str(
        text: &str,
        library: &Library,
        curve: &mut dyn FnMut(f64) -> Result<ReflectanceCurve, ArtistError>,
    ) -> Result<Scene, SceneError> {
        let raw: RawManifest = toml::from_str(text).map_err(|e| SceneError::Toml(e.to_string()))?;
        if raw.material.is_empty() {
            return Err(SceneError::NoMaterials);
        }
        let mut curves: BTreeMap<u64, ReflectanceCurve> = BTreeMap::new();
        let mut materials: Vec<SceneMaterial> = Vec::with_capacity(raw.material.len());
        for entry in &raw.material {
            let m = resolve(entry, library, &mut |eta| {
                if let Some(c) = curves.get(&eta.to_bits()) {
                    return Ok(c.clone());
                }
                let c = curve(eta)?;
                curves.insert(eta.to_bits(), c.clone());
                Ok(c)
            })?;
            if materials
                .iter()
                .any(|other| other.material.id() == m.material.id())
            {
                return Err(SceneError::Duplicate(m.material.id().to_string()));
            }
            materials.push(m);
        }
        Ok(Scene {
            integrator: raw.integrator,
            materials,
        })
    }

    /// The integrator.
    pub fn integrator(&self) -> Integrator {
        self.integrator
    }
    /// The materials, in manifest order.
    pub fn materials(&self) -> &[SceneMaterial] {
        &self.materials
    }

    /// Things worth telling the user that are not errors: a material's own ρ′ outside its
    /// declared range, a reflectance above the table's largest diffuse reflectance.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        for m in &self.materials {
            let id = m.material.id();
            for (c, name) in CHANNELS.iter().enumerate() {
                let own = m.material.rho_prime()[c];
                let r = m.ranges[c];
                if m.declared && !(r.lo()..=r.hi()).contains(&own) {
                    out.push(format!(
                        "material {id:?}, channel {name}: its own reduced albedo {own} is outside the declared range [{}, {}]; lookups at it will be refused",
                        r.lo(),
                        r.hi()
                    ));
                }
                if let Some((reflectance, max)) = m.clamped[c] {
                    out.push(format!(
                        "material {id:?}, channel {name}: reflectance {} is above the largest diffuse reflectance the table reaches at normal incidence, {:.4} ((1 - F_r) rho_eff: multiple scattering only); clamped to reduced albedo 1",
                        crate::error::number(reflectance),
                        max
                    ));
                }
            }
        }
        out
    }

    /// The tables to bake on the albedo axis `rho_axis` (the grid's nodes as stored, see
    /// [`crate::table::Grid::rho_axis`]); see the module docs.
    pub fn plan(&self, rho_axis: &Nodes) -> Result<ScenePlan, SceneError> {
        // Per η (in increasing order): every channel's rows.
        let mut by_eta: BTreeMap<u64, Vec<(usize, usize, Range<usize>)>> = BTreeMap::new();
        let mut etas: Vec<f64> = self.materials.iter().map(|m| m.material.eta()).collect();
        etas.sort_by(f64::total_cmp);
        etas.dedup();
        for (k, m) in self.materials.iter().enumerate() {
            for (c, &channel) in CHANNELS.iter().enumerate() {
                let rows = rows_for(rho_axis, m.ranges[c]).map_err(|source| SceneError::Plan {
                    material: m.material.id().to_string(),
                    channel,
                    source,
                })?;
                by_eta
                    .entry(m.material.eta().to_bits())
                    .or_default()
                    .push((k, c, rows));
            }
        }
        let mut plan = ScenePlan {
            tables: Vec::new(),
            channel_tables: vec![[0; 3]; self.materials.len()],
        };
        for eta in etas {
            let channels = by_eta.remove(&eta.to_bits()).unwrap_or_default();
            let runs = merge_runs(channels.iter().map(|(_, _, r)| r.clone()));
            let first = plan.tables.len();
            for run in &runs {
                plan.tables.push(PlannedTable {
                    eta,
                    rows: run.clone(),
                    serves: Vec::new(),
                });
            }
            for (k, c, rows) in channels {
                // Every channel's rows lie in exactly one merged run.
                let Some(offset) = runs
                    .iter()
                    .position(|run| run.start <= rows.start && rows.end <= run.end)
                else {
                    continue;
                };
                let (Some(table), Some(m), Some(slot)) = (
                    plan.tables.get_mut(first + offset),
                    self.materials.get(k),
                    plan.channel_tables.get_mut(k).and_then(|t| t.get_mut(c)),
                ) else {
                    continue;
                };
                if !table.serves.contains(&m.ranges[c]) {
                    table.serves.push(m.ranges[c]);
                }
                *slot = first + offset;
            }
        }
        Ok(plan)
    }
}

/// Resolves one manifest entry into a material with its ranges.
fn resolve(
    entry: &RawMaterial,
    library: &Library,
    curve: &mut dyn FnMut(f64) -> Result<ReflectanceCurve, ArtistError>,
) -> Result<SceneMaterial, SceneError> {
    let name = entry.name.as_str();
    let owned = || name.to_string();
    let eta = entry
        .eta
        .as_ref()
        .map(|v| number(name, "eta", v))
        .transpose()?;
    let triple = |field: &'static str, v: &Option<Value>| -> Result<Option<[f64; 3]>, SceneError> {
        v.as_ref()
            .map(|v| channels(name, field, v, false))
            .transpose()
    };
    let (sigma_s, sigma_a) = (
        triple("sigma_s", &entry.sigma_s)?,
        triple("sigma_a", &entry.sigma_a)?,
    );
    let (reflectance, mfp) = (
        triple("reflectance", &entry.reflectance)?,
        triple("mfp", &entry.mfp)?,
    );
    let g = entry
        .g
        .as_ref()
        .map(|v| channels(name, "g", v, true))
        .transpose()?;
    if let Some(source) = &entry.source {
        check_source(name, source)?;
    }
    let coefficients = sigma_s.is_some() || sigma_a.is_some();
    let diffuse = reflectance.is_some() || mfp.is_some();
    if coefficients && diffuse {
        return Err(SceneError::Conflict {
            material: owned(),
            first: "sigma_s/sigma_a",
            second: "reflectance/mfp",
        });
    }
    if coefficients || diffuse {
        check_new_id(name, library)?;
    }
    let pair = |a: Option<[f64; 3]>, b: Option<[f64; 3]>, na, nb| match (a, b) {
        (Some(a), Some(b)) => Ok((a, b)),
        (Some(_), None) => Err(SceneError::Missing {
            material: owned(),
            given: na,
            missing: nb,
        }),
        _ => Err(SceneError::Missing {
            material: owned(),
            given: nb,
            missing: na,
        }),
    };
    let invalid = |source| SceneError::Material {
        material: owned(),
        source: Box::new(source),
    };
    let (material, origin, source, clamped) = if coefficients {
        let (s, a) = pair(sigma_s, sigma_a, "sigma_s", "sigma_a")?;
        let m = Material::from_coefficients(
            name,
            s,
            a,
            g.unwrap_or([0.0; 3]),
            eta.unwrap_or(DEFAULT_ETA),
        )
        .map_err(invalid)?;
        let source = entry
            .source
            .clone()
            .unwrap_or_else(|| "scene manifest: inline coefficients".into());
        (m, Origin::Coefficients, source, [None; 3])
    } else if diffuse {
        let (refl, path) = pair(reflectance, mfp, "reflectance", "mfp")?;
        let eta = eta.unwrap_or(DEFAULT_ETA);
        let artist = |source| SceneError::Artist {
            material: owned(),
            source,
        };
        let c = curve(eta).map_err(artist)?;
        let d = c
            .diffuse(refl, path, g.unwrap_or([0.0; 3]))
            .map_err(artist)?;
        let max = c.max();
        let m = Material::from_coefficients(name, d.sigma_s, d.sigma_a, g.unwrap_or([0.0; 3]), eta)
            .map_err(invalid)?;
        let source = entry.source.clone().unwrap_or_else(|| {
            format!("scene manifest: reflectance {refl:?}, mfp {path:?} mm, inverted through the table's (1 - F_r) rho_eff at theta = 0")
        });
        let clamped = std::array::from_fn(|k| d.inverted[k].clamped.then_some((refl[k], max)));
        (m, Origin::Diffuse, source, clamped)
    } else {
        for (field, given) in [("g", entry.g.is_some()), ("source", entry.source.is_some())] {
            if given {
                return Err(SceneError::NeedsCoefficients {
                    material: owned(),
                    field,
                });
            }
        }
        let found = library.get(name).map_err(invalid)?;
        let mut source = found
            .source()
            .map(|s| s.coefficients().to_string())
            .unwrap_or_default();
        let m = match eta {
            Some(eta) => {
                if !(crate::medium::ETA_MIN..=crate::medium::ETA_MAX).contains(&eta) {
                    return Err(SceneError::EtaOverride {
                        material: owned(),
                        eta,
                    });
                }
                source = format!("{source}; eta {eta} set by the scene manifest");
                Material::from_coefficients(
                    found.id(),
                    found.sigma_s(),
                    found.sigma_a(),
                    found.g(),
                    eta,
                )
                .map_err(invalid)?
            }
            None => found.clone(),
        };
        (m, Origin::Library, source, [None; 3])
    };
    // A library material's source (from a --materials file, plus the η note) obeys the same
    // limit as the manifest's own.
    check_source(name, &source)?;
    let id = material.id().to_string();
    let (ranges, declared) = match &entry.albedo_range {
        Some(v) => (albedo_ranges(&id, v)?, true),
        None => {
            let rho = material.rho_prime();
            let point = |c: usize| RhoInterval::point(rho[c]).map_err(|s| albedo_error(&id, c, s));
            ([point(0)?, point(1)?, point(2)?], false)
        }
    };
    Ok(SceneMaterial {
        material,
        source,
        ranges,
        declared,
        origin,
        clamped,
    })
}

fn albedo_error(material: &str, channel: usize, source: SubsetError) -> SceneError {
    SceneError::Albedo {
        material: material.to_string(),
        channel: CHANNELS[channel],
        source,
    }
}

/// A TOML number (integer or float) as f64.
fn as_number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(f) => Some(*f),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

fn number(material: &str, field: &str, v: &Value) -> Result<f64, SceneError> {
    as_number(v).ok_or_else(|| SceneError::NotANumber {
        material: material.to_string(),
        field: field.to_string(),
        text: show(v),
    })
}

/// Three values (r, g, b), or with `one_allowed` also a single value for every channel.
fn channels(
    material: &str,
    field: &'static str,
    v: &Value,
    one_allowed: bool,
) -> Result<[f64; 3], SceneError> {
    let expected = if one_allowed {
        "1 or 3 (r, g, b)"
    } else {
        "3 (r, g, b)"
    };
    let count = |count| SceneError::Count {
        material: material.to_string(),
        field,
        count,
        expected,
    };
    match v {
        Value::Array(items) => {
            let values = items
                .iter()
                .enumerate()
                .map(|(i, x)| number(material, &format!("{field}[{i}]"), x))
                .collect::<Result<Vec<f64>, _>>()?;
            match values.as_slice() {
                [a, b, c] => Ok([*a, *b, *c]),
                [a] if one_allowed => Ok([*a; 3]),
                _ => Err(count(values.len())),
            }
        }
        other if one_allowed => Ok([number(material, field, other)?; 3]),
        _ => Err(count(1)),
    }
}

/// `albedo_range`: a value, `[min, max]`, or three entries each a value or `[min, max]`.
fn albedo_ranges(material: &str, v: &Value) -> Result<[RhoInterval; 3], SceneError> {
    let shape = || SceneError::AlbedoShape {
        material: material.to_string(),
        text: show(v),
    };
    let interval = |c: usize, lo: f64, hi: f64| {
        RhoInterval::new(lo, hi).map_err(|s| albedo_error(material, c, s))
    };
    let entry = |c: usize, x: &Value| -> Result<RhoInterval, SceneError> {
        if let Some(x) = as_number(x) {
            return interval(c, x, x);
        }
        match x
            .as_array()
            .map(|a| a.iter().map(as_number).collect::<Vec<_>>())
            .as_deref()
        {
            Some([Some(lo), Some(hi)]) => interval(c, *lo, *hi),
            _ => Err(shape()),
        }
    };
    if as_number(v).is_some() {
        return Ok([entry(0, v)?, entry(1, v)?, entry(2, v)?]);
    }
    let items = v.as_array().ok_or_else(shape)?;
    match items.as_slice() {
        [lo, hi] if as_number(lo).is_some() && as_number(hi).is_some() => {
            let (lo, hi) = (
                as_number(lo).unwrap_or(f64::NAN),
                as_number(hi).unwrap_or(f64::NAN),
            );
            Ok([
                interval(0, lo, hi)?,
                interval(1, lo, hi)?,
                interval(2, lo, hi)?,
            ])
        }
        [r, g, b] => Ok([entry(0, r)?, entry(1, g)?, entry(2, b)?]),
        _ => Err(shape()),
    }
}

/// A TOML value as written (arrays, numbers, strings; tables and dates abbreviated).
fn show(v: &Value) -> String {
    match v {
        Value::Array(items) => {
            let inner: Vec<String> = items.iter().map(show).collect();
            format!("[{}]", inner.join(", "))
        }
        Value::Float(f) => format!("{f:?}"),
        Value::Integer(i) => i.to_string(),
        Value::String(s) => format!("{s:?}"),
        Value::Boolean(b) => b.to_string(),
        Value::Table(_) => "{ … }".to_string(),
        Value::Datetime(d) => format!("{d:?}"),
    }
}

/// Refuses `name` as the id of a material given by its coefficients or the artist's parameters
/// when it names a material of `library`, as [`Library::get`] finds one (any case, spaces or
/// underscores for hyphens, an alias): the file would hold two materials of one name, and a
/// lookup by name would find the library's. The one check of scene manifests, `bssrdf bake
/// --name` and the Python package's bakes.
pub fn check_new_id(name: &str, library: &Library) -> Result<(), SceneError> {
    match library.get(name) {
        Ok(m) => Err(SceneError::InlineTakesLibraryName {
            material: name.to_string(),
            library: m.id().to_string(),
        }),
        Err(_) => Ok(()),
    }
}

/// Most bytes of a material's `source` in a library file (format-spec.md, material records).
pub const MAX_SOURCE_BYTES: usize = 256;

/// Refuses a `source` longer than a library file keeps ([`MAX_SOURCE_BYTES`]) or with a control
/// character (which the format refuses too): the one check
/// of scene manifests and of `--materials` files at bake, so no source is ever cut silently.
pub fn check_source(material: &str, source: &str) -> Result<(), SceneError> {
    let bytes = source.len();
    if bytes > MAX_SOURCE_BYTES {
        return Err(SceneError::SourceTooLong {
            material: material.to_string(),
            bytes,
        });
    }
    // The format's own rule (records: no control characters), checked before any bake
    if let Some((at, character)) = source.char_indices().find(|(_, c)| c.is_control()) {
        return Err(SceneError::SourceControl {
            material: material.to_string(),
            character,
            at,
        });
    }
    Ok(())
}

/// The longest prefix of `text` of at most `max` bytes that ends on a character boundary. The
/// generated sources are short and a user's longer one is refused by [`check_source`] before
/// this; it only guards the format's limit.
fn truncate(text: &str, max: usize) -> String {
    let mut end = text.len().min(max);
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    text[..end].to_string()
}

#[cfg(test)]
mod tests;
