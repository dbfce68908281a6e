//! Named materials: the 47 measured media of Jensen et al. 2001 and Narasimhan et al. 2006,
//! compiled into the crate, plus materials a user adds from TOML files or coefficients.
//!
//! | field | unit | valid range | meaning |
//! |---|---|---|---|
//! | `id` | – | kebab-case, unique | what the command line names it by (`white-grapefruit-juice`) |
//! | `name` | – | not empty | display name |
//! | `aliases` | – | kebab-case, unique | optional other ids (`skimmilk` for `skim-milk`) |
//! | `eta` | – | > 0, finite | relative index of refraction η, medium over outside |
//! | `coefficients` | – | `"reduced"` or `"unreduced"` | how `sigma_s` is stated (below) |
//! | `sigma_s` | mm⁻¹ | 3 values ≥ 0, finite | scattering coefficient σs per channel R, G, B |
//! | `sigma_a` | mm⁻¹ | 3 values ≥ 0, finite | absorption coefficient σa per channel |
//! | `g` | – | 3 values in (−1, 1) | Henyey–Greenstein mean cosine per channel |
//! | `[source]` | – | optional table | where the numbers come from (below) |
//!
//! `coefficients = "reduced"`: the source gives only the reduced scattering coefficient
//! σ′s = σs(1 − g) (Jensen et al. 2001); the file states it as `sigma_s` with `g = 0`, which is
//! exact for diffusion models, as they depend on σs and g only through σ′s. `"unreduced"`: σs
//! and g as measured (Narasimhan et al. 2006). Per channel, σ′t = σs(1 − g) + σa must be > 0.
//!
//! `[source]` has `coefficients` (citation of σs, σa, g; required in the table), `eta` (citation
//! of η), `pbrt_reduced_sigma_s` (σ′s as pbrt-v3/v4 store this medium, where it is one of theirs)
//! and `notes` (disagreements between published copies and the like). Every built-in has one.
//!
//! Unknown fields are an error, as is any invalid value: each failure is its own
//! [`MaterialError`] variant naming the file, the field and the value. Loading never panics.
//!
//! **No overriding.** An id or alias may be defined once: a user file that reuses a built-in id
//! (or another user file's) is rejected with [`MaterialError::DuplicateId`], never silently
//! preferred. To change a built-in's numbers, copy its file under a new id. Loading a directory
//! is all or nothing: one bad file leaves the library as it was.
//!
//! Lookups ([`Library::get`]) ignore case and surrounding white space, and read spaces and
//! underscores as hyphens, so `"White Grapefruit Juice"` finds `white-grapefruit-juice`; a miss
//! suggests close ids (optimal-string-alignment distance, see `suggest.rs`).

mod builtin;
mod error;
mod library;
mod parse;
mod suggest;

pub use error::MaterialError;
pub use library::Library;

use crate::medium::Medium;
use serde::{Deserialize, Serialize, Serializer};
use std::fmt;
use std::path::PathBuf;

pub use bssrdf_runtime::embed::Rgb;

/// How a material's source states the scattering coefficient.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Coefficients {
    /// Only σ′s = σs(1 − g) is known; stored as σs = σ′s with g = 0.
    Reduced,
    /// σs and g as measured.
    Unreduced,
}

/// The validated coefficients of one colour channel (σs, σa in mm⁻¹, g), with the material's η.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Channel {
    medium: Medium,
}

impl Channel {
    /// Scattering coefficient σs, mm⁻¹ (σ′s itself for reduced materials, whose g is 0).
    pub fn sigma_s(&self) -> f64 {
        self.medium.sigma_s()
    }
    /// Absorption coefficient σa, mm⁻¹.
    pub fn sigma_a(&self) -> f64 {
        self.medium.sigma_a()
    }
    /// Henyey–Greenstein mean cosine g.
    pub fn g(&self) -> f64 {
        self.medium.g()
    }
    /// Reduced scattering coefficient σ′s = σs(1 − g), mm⁻¹.
    pub fn sigma_s_prime(&self) -> f64 {
        self.medium.sigma_s_prime()
    }
    /// Reduced extinction σ′t = σ′s + σa, mm⁻¹ (> 0).
    pub fn sigma_t_prime(&self) -> f64 {
        self.medium.sigma_t_prime()
    }
    /// Reduced albedo ρ′ = σ′s/σ′t ∈ [0, 1].
    pub fn rho_prime(&self) -> f64 {
        self.medium.rho_prime()
    }
    /// The homogeneous medium of this channel (σs, σa, g, η).
    pub fn medium(&self) -> Medium {
        self.medium
    }
}

impl Serialize for Channel {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut s = serializer.serialize_struct("Channel", 6)?;
        s.serialize_field("sigma_s", &self.sigma_s())?;
        s.serialize_field("sigma_a", &self.sigma_a())?;
        s.serialize_field("g", &self.g())?;
        s.serialize_field("sigma_s_prime", &self.sigma_s_prime())?;
        s.serialize_field("sigma_t_prime", &self.sigma_t_prime())?;
        s.serialize_field("rho_prime", &self.rho_prime())?;
        s.end()
    }
}

/// Where a material's numbers come from, as its file states it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Source {
    coefficients: String,
    eta: Option<String>,
    pbrt_reduced_sigma_s: Option<[f64; 3]>,
    notes: Vec<String>,
}

impl Source {
    /// Citation for σs, σa and g.
    pub fn coefficients(&self) -> &str {
        &self.coefficients
    }
    /// Citation for η, if the file gives one.
    pub fn eta(&self) -> Option<&str> {
        self.eta.as_deref()
    }
    /// σ′s (mm⁻¹, R, G, B) as pbrt-v3/v4 store this medium, which keep no g.
    pub fn pbrt_reduced_sigma_s(&self) -> Option<[f64; 3]> {
        self.pbrt_reduced_sigma_s
    }
    /// Remarks: disagreements between published copies, placeholders, renamings.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }
}

/// Where a material was defined.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Origin {
    /// Compiled into the crate from this file of the repository (`materials/….toml`).
    Builtin(&'static str),
    /// Loaded from a user's file.
    File(PathBuf),
    /// Built from coefficients in code or on the command line.
    Inline,
    /// A material record of this library file (`.bssrdf`).
    Record(PathBuf),
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Origin::Builtin(file) => write!(f, "built-in {file}"),
            Origin::File(path) => write!(f, "{}", path.display()),
            Origin::Inline => f.write_str("inline material"),
            Origin::Record(path) => write!(f, "{}, material record", path.display()),
        }
    }
}

impl Serialize for Origin {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

/// A named, validated material: η and per-channel coefficients, with their source.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Material {
    id: String,
    name: String,
    aliases: Vec<String>,
    eta: f64,
    coefficients: Coefficients,
    channels: [Channel; 3],
    source: Option<Source>,
    origin: Origin,
}

impl Material {
    /// Parses and validates one material from the text of a TOML file (schema in the module
    /// documentation); `origin` names it in errors.
    pub fn from_toml_str(text: &str, origin: Origin) -> Result<Self, MaterialError> {
        parse::material_from_toml(text, origin)
    }

    /// A user's material from unreduced coefficients (σs, σa in mm⁻¹, g per channel R, G, B;
    /// pass `[g; 3]` for one g), validated like a file. Its name is its id and its origin
    /// [`Origin::Inline`].
    pub fn from_coefficients(
        id: &str,
        sigma_s: [f64; 3],
        sigma_a: [f64; 3],
        g: [f64; 3],
        eta: f64,
    ) -> Result<Self, MaterialError> {
        Self::from_coefficients_of(Origin::Inline, id, sigma_s, sigma_a, g, eta)
    }

    /// [`Material::from_coefficients`] with the origin its errors name (a library file's
    /// material record, say).
    pub fn from_coefficients_of(
        origin: Origin,
        id: &str,
        sigma_s: [f64; 3],
        sigma_a: [f64; 3],
        g: [f64; 3],
        eta: f64,
    ) -> Result<Self, MaterialError> {
        let file = origin.to_string();
        parse::check_id(&file, "id", id)?;
        let channels =
            parse::channels(&file, Coefficients::Unreduced, &sigma_s, &sigma_a, &g, eta)?;
        Ok(Self {
            id: id.to_string(),
            name: id.to_string(),
            aliases: Vec::new(),
            eta,
            coefficients: Coefficients::Unreduced,
            channels,
            source: None,
            origin,
        })
    }

    /// Kebab-case id.
    pub fn id(&self) -> &str {
        &self.id
    }
    /// Display name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// Other ids this material answers to.
    pub fn aliases(&self) -> &[String] {
        &self.aliases
    }
    /// Relative index of refraction η.
    pub fn eta(&self) -> f64 {
        self.eta
    }
    /// Whether the source gave reduced or unreduced scattering.
    pub fn coefficients(&self) -> Coefficients {
        self.coefficients
    }
    /// Coefficients per channel, R, G, B.
    pub fn channels(&self) -> &[Channel; 3] {
        &self.channels
    }
    /// Coefficients of one channel.
    pub fn channel(&self, channel: Rgb) -> &Channel {
        &self.channels[channel.index()]
    }
    /// The homogeneous medium of one channel: unreduced σs, σa, g (for reduced materials
    /// σs = σ′s and g = 0) and η.
    pub fn medium(&self, channel: Rgb) -> Medium {
        self.channel(channel).medium()
    }
    /// σs per channel, mm⁻¹.
    pub fn sigma_s(&self) -> [f64; 3] {
        self.channels.map(|c| c.sigma_s())
    }
    /// σa per channel, mm⁻¹.
    pub fn sigma_a(&self) -> [f64; 3] {
        self.channels.map(|c| c.sigma_a())
    }
    /// g per channel.
    pub fn g(&self) -> [f64; 3] {
        self.channels.map(|c| c.g())
    }
    /// Reduced albedo ρ′ per channel.
    pub fn rho_prime(&self) -> [f64; 3] {
        self.channels.map(|c| c.rho_prime())
    }
    /// Reduced extinction σ′t per channel, mm⁻¹.
    pub fn sigma_t_prime(&self) -> [f64; 3] {
        self.channels.map(|c| c.sigma_t_prime())
    }
    /// Where the numbers come from, if the file says.
    pub fn source(&self) -> Option<&Source> {
        self.source.as_ref()
    }
    /// Where this material was defined.
    pub fn origin(&self) -> &Origin {
        &self.origin
    }
}
