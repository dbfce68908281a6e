//! Pictures of a beam entering a semi-infinite slab (Ferrier 2016, §5.2 and figure 10): a
//! particle tracer that images the exitance of the surface seen from above, per unit area and
//! per unit incident power, for each of the models below; and the signed luminance difference
//! of two pictures (figure 1c).
//!
//! | parameter | unit | range | default |
//! |---|---|---|---|
//! | `model` | – | one of [`MODELS`]: table, perpendicular, pbd, mc | table |
//! | `theta` | radians | [0, π/2), with `theta + cone` < π/2 | – |
//! | `cone` | radians, half-angle | [0, π/2) | 1° |
//! | `photons` | – | 2 ..= 10¹² (a standard error needs two) | 10⁶ |
//! | `seed` | – | any u64 | 0 |
//! | `width`, `height` | pixels | 1 ..= [`MAX_SIDE`] | 256 × 256 |
//! | `extent` | mm, along the plane of incidence | > 0 | 10 |
//! | `grid` | – | table grid baked for the material's η | default (100 × 10 × 64) |
//! | `orders` | – | what the walk images: all orders, or multiple scattering only | all |
//!
//! # One photon
//! 1. **Light.** A direction uniform in solid angle inside the cone about θ hits the surface at
//!    the origin; its own θᵢ and plane of incidence ψ follow (`source.rs`). Per unit incident
//!    power, the Fresnel reflectance R(θᵢ) leaves specularly (reported as
//!    [`Stats::reflected`], not imaged); T(θᵢ) = 1 − R enters.
//! 2. **Exit.** The model places the exit point(s) at (r, φ) from the entry point, φ measured
//!    from the photon's plane of incidence, 0 forward (`place.rs`):
//!    - `table`: algorithm 2, (r, φ) drawn from the angular table baked for the material's η
//!      (baked once per run, kept in memory);
//!    - `perpendicular`: the θ = 0 slice of the same table, φ uniform (pbrt's assumption);
//!    - `pbd`: drawn from the table, weighted by PBD / table density, so the picture is PBD's
//!      own and unbiased wherever the table's density is positive (everywhere but beyond the
//!      table's last radius, 243 reduced mean free paths);
//!    - `mc`: the random walk of [`crate::walk`] traced in each channel, every score of its exit
//!      estimator imaged where it leaves: the reference, with single scattering.
//! 3. **Channels.** The three sampled models draw one exit point per photon and weight it in
//!    every channel (one-sample multiple importance sampling over the channels, "hero"
//!    channel): the channel h whose density draws the point is chosen uniformly among the
//!    channels holding energy, and channel c gets the weight
//!    T · S_c(x) / ((1/n) Σ_k p_k(x)), the balance heuristic. Unbiased for every channel (the
//!    mixture density is positive wherever S_c is) and bounded by n T ρ_eff,c, while a point
//!    drawn from one fixed channel would weight another's longer tail by an unbounded ratio.
//!    Choosing one channel per photon instead would give each channel a third of the photons
//!    for the same sampling cost; here each photon costs one draw and n − 1 density lookups.
//!    For `table` and `perpendicular`, S_c = ρ_eff,c p_c: the picture is exactly the
//!    distribution algorithm 2 samples (it differs from the table's refined `eval` by a median
//!    8e-5 relative, see [`crate::table`]). The walk cannot share a path between channels
//!    whose σt differ, so `mc` traces every photon once in each channel, from the photon's
//!    per-channel stream.
//!
//! # Tallies
//! Exits are binned on the pixel grid; their total power and first moments are also summed
//! for every exit, inside the picture or not ([`Stats`]), per order (the walk's single and
//! multiple scattering; the diffusion models are multiple scattering only) and band (R, G, B
//! and luminance R + G + B as in Ferrier's figure 1c), with standard errors from per-photon
//! second moments.
//!
//! # Determinism
//! Photon k draws from its own xoshiro256++ stream seeded from (seed, k), and in `mc` channel c
//! from (seed mixed with c, k). Blocks of photons ([`block`]) are traced in parallel (rayon),
//! each summed in photon order; blocks are added in block order. The picture and statistics are
//! bit-identical for a seed on any thread count.
//!
//! # Where it breaks down
//! The models are only as good as their tables: within the table's accuracy (docs/accuracy.md) for
//! `table`, and PBD's diffusion approximation for `table` and `pbd`, which misses single
//! scattering and is least accurate at low albedo and near the entry point. The walk is exact
//! up to statistics. A smooth, flat, homogeneous surface only.

mod diff;
mod error;
pub mod exr;
mod place;
pub mod png;
mod source;
mod tally;

#[cfg(test)]
mod tests;

pub use diff::{centroid_x, difference, Difference};
pub use error::RenderError;
pub use tally::{band_name, part_name, Band, BandStats, Frame, Part, Stats};

use crate::fresnel::Moments;
use crate::materials::{Material, Rgb};
use crate::models::ModelKind;
use crate::pbd::Pbd;
use crate::rng::mix64;
use crate::table::{bake, AngularTable, GridPreset};
use crate::walk::ExitWalk;
use rayon::prelude::*;
use source::Source;
use std::f64::consts::FRAC_PI_2;
use tally::{Recorder, Sums};

/// Largest picture side, pixels (the picture is summed in f64: 4096² pixels take 400 MB).
pub const MAX_SIDE: usize = 4096;
/// Prefix of the metadata keys a render writes.
pub const META_PREFIX: &str = "bssrdf:";
/// What the pixel values are.
pub const UNITS: &str = "exitance per mm^2 per unit incident power, linear";
/// Most photons in one render.
pub const MAX_PHOTONS: u64 = 1_000_000_000_000;

/// The models a render can place exit points with (of the registry, [`ModelKind`]): Ferrier's
/// angular table (algorithm 2), its θ = 0 slice uniform in φ, photon beam diffusion (table
/// samples weighted by PBD over the table's density), and the Monte Carlo walk, the reference.
pub const MODELS: [ModelKind; 5] = [
    ModelKind::Table,
    ModelKind::Perpendicular,
    ModelKind::Pbd,
    ModelKind::WalkTable,
    ModelKind::MonteCarlo,
];

/// Photons per block, the unit of parallel work and of the fixed summation order: smaller for
/// the walk, whose photons cost ~20 µs and leave ~170 exits each.
pub fn block(model: ModelKind) -> u64 {
    match model {
        ModelKind::MonteCarlo => 512,
        _ => 8192,
    }
}

/// Which exits of the walk go into the picture (its statistics always keep both).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Orders {
    /// Single and multiple scattering: the true picture.
    All,
    /// Multiple scattering only, like the diffusion models.
    Multiple,
}

/// Parameters of a render; checked by [`Config::validate`] (and by [`Renderer::new`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// How exit points are placed, one of [`MODELS`].
    pub model: ModelKind,
    /// Incidence of the cone's axis, radians before refraction.
    pub theta: f64,
    /// Half-angle of the cone of incident directions, radians (0: collimated).
    pub cone: f64,
    /// Photons traced.
    pub photons: u64,
    /// Seed of the per-photon streams.
    pub seed: u64,
    /// Pixels along x (the plane of incidence).
    pub width: usize,
    /// Pixels along y.
    pub height: usize,
    /// Width of the picture, mm (its height is extent · height / width: square pixels).
    pub extent: f64,
    /// Grid of the table baked for the sampled models.
    pub grid: GridPreset,
    /// What the walk images.
    pub orders: Orders,
    /// The table of the walk-table model: a walk-angular table at the material's η and g
    /// (every channel's), drawn as the table model draws its own.
    pub walk_table: Option<std::sync::Arc<AngularTable>>,
}

impl Config {
    /// A 256 × 256 picture of 10 mm, 10⁶ photons, seed 0, a cone of 1°, the default grid.
    pub fn new(model: ModelKind, theta: f64) -> Self {
        Self {
            model,
            theta,
            cone: 1f64.to_radians(),
            photons: 1_000_000,
            seed: 0,
            width: 256,
            height: 256,
            extent: 10.0,
            grid: GridPreset::Default,
            orders: Orders::All,
            walk_table: None,
        }
    }

    /// Checks every parameter, naming the first bad one.
    pub fn validate(&self) -> Result<(), RenderError> {
        if !MODELS.contains(&self.model) {
            return Err(RenderError::Model {
                name: self.model.name(),
                expected: ModelKind::names(&MODELS),
            });
        }
        crate::error::in_range("theta", self.theta, 0.0, FRAC_PI_2)?;
        crate::error::in_range("cone", self.cone, 0.0, FRAC_PI_2)?;
        if self.theta + self.cone >= FRAC_PI_2 {
            return Err(RenderError::Grazing {
                theta_deg: self.theta.to_degrees(),
                cone_deg: self.cone.to_degrees(),
            });
        }
        if !(crate::walk::MIN_PHOTONS..=MAX_PHOTONS).contains(&self.photons) {
            return Err(crate::Error::CountOutOfRange {
                name: "photons",
                value: self.photons,
                min: crate::walk::MIN_PHOTONS,
                max: MAX_PHOTONS,
            }
            .into());
        }
        let side = 1..=MAX_SIDE;
        if !side.contains(&self.width) || !side.contains(&self.height) {
            return Err(RenderError::Size {
                width: self.width,
                height: self.height,
                max: MAX_SIDE,
            });
        }
        crate::error::finite("extent", self.extent)?;
        if self.extent <= 0.0 {
            return Err(crate::Error::NotPositive {
                name: "extent",
                value: self.extent,
            }
            .into());
        }
        Ok(())
    }
}

/// Ferrier's figure 10 material: σs = 1 mm⁻¹, σa = (0.01, 0.1, 1) mm⁻¹, g = 0, η = 1.33.
pub fn figure_10_material() -> Material {
    // The coefficients are valid constants: construction cannot fail.
    Material::from_coefficients(
        "ferrier-figure-10",
        [1.0; 3],
        [0.01, 0.1, 1.0],
        [0.0; 3],
        1.33,
    )
    .unwrap_or_else(|e| unreachable!("figure 10 material: {e}"))
}

/// One colour channel of the material, in the forms the models want.
#[derive(Debug, Clone, Copy)]
struct Channel {
    /// Reduced albedo ρ′.
    rho: f64,
    /// Reduced extinction σ′t, mm⁻¹.
    sigma_t_prime: f64,
    /// Extinction σt = σs + σa, mm⁻¹ (the walk's unit of length).
    sigma_t: f64,
}

/// A render's picture: exitance per mm² per unit incident power, linear RGB, with the text
/// metadata that goes into its file.
#[derive(Debug, Clone, PartialEq)]
pub struct Picture {
    frame: Frame,
    rgb: Vec<f32>,
    meta: Vec<(String, String)>,
}

impl Picture {
    /// Checks that `rgb` holds 3 values per pixel of `frame`.
    pub fn new(
        frame: Frame,
        rgb: Vec<f32>,
        meta: Vec<(String, String)>,
    ) -> Result<Self, RenderError> {
        let need = 3 * frame.width() * frame.height();
        if rgb.len() != need {
            return Err(RenderError::Mismatch {
                what: "pixel count",
                a: format!("{} values", rgb.len()),
                b: format!("{need} for {}x{}", frame.width(), frame.height()),
            });
        }
        Ok(Self { frame, rgb, meta })
    }
    /// The pixel grid.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }
    /// Row-major RGB exitance, mm⁻² per unit incident power.
    pub fn rgb(&self) -> &[f32] {
        &self.rgb
    }
    /// Metadata (key, value), as written to the file's attributes.
    pub fn meta(&self) -> &[(String, String)] {
        &self.meta
    }
    /// The value of one metadata key.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.meta
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
    /// Luminance R + G + B per pixel, row-major.
    pub fn luminance(&self) -> Vec<f64> {
        self.rgb
            .chunks_exact(3)
            .map(|p| p.iter().map(|&v| f64::from(v)).sum())
            .collect()
    }
}

/// A finished render.
#[derive(Debug, Clone)]
pub struct Render {
    /// The picture and its metadata.
    pub picture: Picture,
    /// Power, centroids and their errors.
    pub stats: Stats,
}

/// The walk table of `config` for `material`: its η and every channel's g the table's.
fn walk_table_for(config: &Config, material: &Material) -> Result<AngularTable, RenderError> {
    let table = config.walk_table.as_deref().ok_or(RenderError::WalkTable {
        why: "no walk table: give one (`bssrdf render --walk-table FILE`, baked by `bssrdf bake --source walk`)".into(),
    })?;
    let Some(walk) = table.walk() else {
        return Err(RenderError::WalkTable {
            why: "the table is a PBD table, not a walk-angular one".into(),
        });
    };
    for c in Rgb::ALL {
        let g = material.channel(c).g();
        if !table.is_walk_at(material.eta(), g) {
            return Err(RenderError::WalkTable {
                why: format!(
                    "the table is the walk at eta {}, g {}; the material's channel {c:?} has eta {}, g {} (a walk table holds one g)",
                    table.eta(),
                    walk.g,
                    material.eta(),
                    g
                ),
            });
        }
    }
    Ok(table.clone())
}

/// A material and configuration made ready to trace: the table baked, the channels derived.
#[derive(Debug)]
pub struct Renderer {
    config: Config,
    material_id: String,
    eta: f64,
    frame: Frame,
    source: Source,
    channels: [Channel; 3],
    table: Option<AngularTable>,
    pbd: Option<[Pbd; 3]>,
    walks: Option<[ExitWalk; 3]>,
    /// T(θ) ρ_eff,PBD(θ) per channel at the axis, for a collimated `pbd` render.
    pbd_expected: Option<[f64; 3]>,
    /// The table's ρ_eff per channel where every photon looks it up at the same incidence
    /// (perpendicular, or a collimated beam).
    rho_eff_fixed: Option<[f64; 3]>,
    channel_seeds: [u64; 3],
}

impl Renderer {
    /// Validates the configuration and prepares the model (bakes the table for the material's
    /// η with exact Fresnel moments, for the sampled models).
    pub fn new(config: &Config, material: &Material) -> Result<Self, RenderError> {
        config.validate()?;
        let channels = Rgb::ALL.map(|c| {
            let ch = material.channel(c);
            Channel {
                rho: ch.rho_prime(),
                sigma_t_prime: ch.sigma_t_prime(),
                sigma_t: ch.sigma_s() + ch.sigma_a(),
            }
        });
        let eta = material.eta();
        let moments = Moments::Exact;
        let table = match config.model {
            ModelKind::MonteCarlo => None,
            ModelKind::WalkTable => Some(walk_table_for(config, material)?),
            _ => {
                let grid = config.grid.grid(eta, crate::table::Lobes::for_eta(eta));
                Some(bake(eta, moments, &grid, false)?.0)
            }
        };
        let (mut pbd, mut pbd_expected) = (None, None);
        if config.model == ModelKind::Pbd {
            let models = Rgb::ALL.map(|c| Pbd::for_medium(&material.medium(c), moments));
            if config.cone == 0.0 {
                let t = crate::fresnel::transmittance(config.theta.cos(), eta);
                pbd_expected = Some(models.map(|p| t * p.effective_albedo(config.theta)));
            }
            pbd = Some(models);
        }
        let rho_eff_fixed = match config.model {
            ModelKind::Perpendicular => Some(0.0),
            _ if config.cone == 0.0 => Some(config.theta),
            _ => None,
        }
        .and_then(|theta| {
            let t = table.as_ref()?.view();
            Some(channels.map(|c| t.effective_albedo(c.rho, theta).unwrap_or(0.0)))
        });
        let walks = match config.model {
            ModelKind::MonteCarlo => {
                let mut w = Vec::with_capacity(3);
                for c in Rgb::ALL {
                    let ch = material.channel(c);
                    let albedo = ch.sigma_s() / (ch.sigma_s() + ch.sigma_a());
                    w.push(ExitWalk::new(albedo, ch.g(), eta)?);
                }
                <[ExitWalk; 3]>::try_from(w).ok()
            }
            _ => None,
        };
        Ok(Self {
            config: config.clone(),
            material_id: material.id().to_string(),
            eta,
            frame: Frame::new(config.width, config.height, config.extent),
            source: Source::new(config.theta, config.cone, eta),
            channels,
            table,
            pbd,
            walks,
            pbd_expected,
            rho_eff_fixed,
            channel_seeds: [1u64, 2, 3].map(|c| mix64(config.seed ^ mix64(c))),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Traces every photon of the configuration on the current rayon pool, calling `progress`
    /// with the number of photons finished after each block (from any thread).
    pub fn run(&self, progress: &(dyn Fn(u64) + Sync)) -> Render {
        let blocks = self.config.photons.div_ceil(block(self.config.model));
        let mut total = Sums::new();
        let mut image = vec![0.0; 3 * self.frame.width() * self.frame.height()];
        // Blocks go a chunk at a time to bound memory (a block's deposits take ~16 bytes per
        // exit); chunks never change the order in which block sums are added.
        let chunk = 2 * rayon::current_num_threads().max(1) as u64;
        let mut start = 0;
        while start < blocks {
            let end = blocks.min(start + chunk);
            let parts: Vec<Sums> = (start..end)
                .into_par_iter()
                .map(|b| {
                    let sums = self.trace_block(b);
                    progress(sums.photons);
                    sums
                })
                .collect();
            for part in &parts {
                total.merge(part, &mut image);
            }
            start = end;
        }
        self.finish(&total, &image)
    }

    /// Traces photons `first .. first + count` into one block's sums.
    fn trace_block(&self, block: u64) -> Sums {
        let size = self::block(self.config.model);
        let first = block * size;
        let last = self.config.photons.min(first + size);
        let image_single = self.config.orders == Orders::All;
        let mut rec = Recorder::new(&self.frame, image_single);
        for index in first..last {
            self.trace_photon(index, &mut rec);
            rec.end_photon();
        }
        rec.into_sums()
    }

    fn finish(&self, sums: &Sums, image: &[f64]) -> Render {
        let n = sums.photons.max(1) as f64;
        let area = self.frame.pixel_mm() * self.frame.pixel_mm();
        let scale = 1.0 / (n * area);
        let rgb: Vec<f32> = image.iter().map(|&v| (v * scale) as f32).collect();
        let mut in_picture = [0.0; 4];
        for p in image.chunks_exact(3) {
            for c in 0..3 {
                in_picture[c] += p[c] / n;
                in_picture[3] += p[c] / n;
            }
        }
        let expected = matches!(
            self.config.model,
            ModelKind::Table | ModelKind::Perpendicular | ModelKind::WalkTable
        );
        let mut stats = Stats::new(sums, expected, in_picture);
        if self.total_table() {
            stats = stats.unsplit();
        }
        if let Some(e) = self.pbd_expected {
            stats.expected = Some(e);
        }
        let picture = Picture {
            frame: self.frame,
            rgb,
            meta: self.meta(&stats),
        };
        Render { picture, stats }
    }

    /// Whether the model is a `total` walk table: its exits are single and multiple scattering
    /// together.
    fn total_table(&self) -> bool {
        self.config.model == ModelKind::WalkTable
            && self
                .config
                .walk_table
                .as_deref()
                .and_then(AngularTable::walk)
                .is_some_and(|w| w.component == crate::format::WalkComponent::Total)
    }

    fn meta(&self, stats: &Stats) -> Vec<(String, String)> {
        let c = &self.config;
        let lum = stats.get(Part::Total, Band::Luminance);
        // The grid of the table the render baked; none for the walk and a walk table (its own)
        let grid = match (c.model, c.grid) {
            (ModelKind::MonteCarlo | ModelKind::WalkTable, _) => "none",
            (_, GridPreset::Coarse) => "coarse",
            (_, GridPreset::Default) => "default",
            (_, GridPreset::Fine) => "fine",
        };
        let orders = match (c.model, c.orders) {
            (ModelKind::MonteCarlo, Orders::All) => "single+multiple",
            (ModelKind::WalkTable, _) if self.total_table() => "single+multiple",
            _ => "multiple",
        };
        let mut meta: Vec<(String, String)> = [
            ("model", c.model.name().to_string()),
            ("material", self.material_id.clone()),
            ("photons", c.photons.to_string()),
            ("theta_deg", degrees(c.theta)),
            ("cone_deg", degrees(c.cone)),
            ("seed", c.seed.to_string()),
            ("extent_mm", c.extent.to_string()),
            ("eta", self.eta.to_string()),
            ("grid", grid.to_string()),
            ("orders", orders.to_string()),
            ("units", UNITS.to_string()),
            ("reflected_at_entry", stats.reflected.value.to_string()),
            // Undefined where no light leaves the surface (σs = 0): "none", never "NaN"
            ("centroid_x_mm", finite_or_none(lum.centroid_x_mm.value)),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
        for (band, ch) in ["red", "green", "blue"].iter().zip(&self.channels) {
            meta.push((
                format!("channel_{band}"),
                format!(
                    "rho'={} sigma_t'={}/mm sigma_t={}/mm",
                    ch.rho, ch.sigma_t_prime, ch.sigma_t
                ),
            ));
        }
        meta.into_iter()
            .map(|(k, v)| (format!("{META_PREFIX}{k}"), v))
            .collect()
    }
}

/// Radians as degrees rounded to 1e-9 (so 60° reads back as "60").
fn degrees(radians: f64) -> String {
    ((radians.to_degrees() * 1e9).round() / 1e9).to_string()
}

/// Renders `config` for `material`: prepares the model, then traces (see [`Renderer`]).
pub fn render(
    config: &Config,
    material: &Material,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Render, RenderError> {
    Ok(Renderer::new(config, material)?.run(progress))
}

/// `x` as text, or "none" where it is not finite (a centroid of no light).
fn finite_or_none(x: f64) -> String {
    if x.is_finite() {
        x.to_string()
    } else {
        "none".to_string()
    }
}
