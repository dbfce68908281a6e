//! The bake of materials and bare η: one full table per distinct η, one record per material.

use super::{BakeError, BakedLibrary, BakedMaterial, Baker, OnProgress};
use crate::format::{self, LibraryBuilder};
use crate::materials::Material;
use crate::scene::artist::{self, ReflectanceCurve};
use crate::scene::{check_source, SceneError};
use crate::table::AngularTable;

/// A material to bake into a library: given by its coefficients, or by the artist's
/// parameters, inverted through the table baked at its η. Either way it gets one table (that of
/// its η) for its three channels and a record naming its `source`.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialSpec(Spec);

#[derive(Debug, Clone, PartialEq)]
enum Spec {
    Coefficients {
        material: Box<Material>,
        source: String,
    },
    Diffuse {
        name: String,
        reflectance: [f64; 3],
        mfp: [f64; 3],
        g: [f64; 3],
        eta: f64,
        source: String,
    },
}

impl MaterialSpec {
    /// A material by its coefficients; `source` (at most 256 bytes, without control
    /// characters, which [`Baker::bake`] checks) says where they come from.
    pub fn new(material: Material, source: impl Into<String>) -> Self {
        MaterialSpec(Spec::Coefficients {
            material: Box::new(material),
            source: source.into(),
        })
    }

    /// A named material (built in or from a file) with its file's citation of the coefficients
    /// as its source, as `bssrdf bake MATERIAL` writes it. Refuses a citation longer than the
    /// file keeps ([`BakeError::Scene`]) before any bake.
    pub fn named(material: &Material) -> Result<Self, BakeError> {
        let source = material
            .source()
            .map(|s| s.coefficients().to_string())
            .unwrap_or_default();
        check_source(material.id(), &source)?;
        Ok(Self::new(material.clone(), source))
    }

    /// A material with id `name` from the artist's parameters per channel R, G, B: diffuse
    /// reflectance in [0, 1], unreduced mean free path 1/σt in mm, Henyey–Greenstein g in
    /// (−1, 1), at η ([`crate::scene::artist`]). The bake inverts the reflectance through the
    /// diffuse reflectance at θ = 0 of the table it bakes at η. Checks the parameters
    /// ([`BakeError::Artist`]), then the id and η ([`BakeError::Material`]), before any bake.
    pub fn diffuse(
        name: &str,
        reflectance: [f64; 3],
        mfp: [f64; 3],
        g: [f64; 3],
        eta: f64,
        source: impl Into<String>,
    ) -> Result<Self, BakeError> {
        artist::check(reflectance, mfp, g).map_err(|source| BakeError::Artist {
            name: name.to_string(),
            source,
        })?;
        // The id and η rules, checked now rather than after the bake.
        Material::from_coefficients(name, [1.0; 3], [1.0; 3], g, eta).map_err(|source| {
            BakeError::Material {
                name: name.to_string(),
                source: Box::new(source),
            }
        })?;
        Ok(MaterialSpec(Spec::Diffuse {
            name: name.to_string(),
            reflectance,
            mfp,
            g,
            eta,
            source: source.into(),
        }))
    }

    /// The material's id.
    pub fn id(&self) -> &str {
        match &self.0 {
            Spec::Coefficients { material, .. } => material.id(),
            Spec::Diffuse { name, .. } => name,
        }
    }

    /// Where its coefficients come from, as its record will say.
    fn source(&self) -> &str {
        match &self.0 {
            Spec::Coefficients { source, .. } | Spec::Diffuse { source, .. } => source,
        }
    }

    /// η of the material.
    pub fn eta(&self) -> f64 {
        match &self.0 {
            Spec::Coefficients { material, .. } => material.eta(),
            Spec::Diffuse { eta, .. } => *eta,
        }
    }

    /// The material and its source; a diffuse one inverted through `table` (baked at its η),
    /// with a warning per clamped channel.
    fn resolve(
        &self,
        table: &AngularTable,
        warnings: &mut Vec<String>,
    ) -> Result<(Material, &str), BakeError> {
        let (name, reflectance, mfp, g, eta, source) = match &self.0 {
            Spec::Coefficients { material, source } => return Ok((*material.clone(), source)),
            Spec::Diffuse {
                name,
                reflectance,
                mfp,
                g,
                eta,
                source,
            } => (name, *reflectance, *mfp, *g, *eta, source),
        };
        let artist = |source| BakeError::Artist {
            name: name.clone(),
            source,
        };
        let curve = ReflectanceCurve::from_table(table).map_err(artist)?;
        let d = curve.diffuse(reflectance, mfp, g).map_err(artist)?;
        for (c, inv) in d.inverted.iter().enumerate() {
            if inv.clamped {
                warnings.push(format!(
                    "material {name:?}, channel {}: reflectance {} is above the largest diffuse reflectance of the table at normal incidence, {:.4} ((1 - F_r) rho_eff: multiple scattering only, at reduced albedo 1); clamped to reduced albedo 1",
                    ["r", "g", "b"][c],
                    reflectance[c],
                    curve.max()
                ));
            }
        }
        let material =
            Material::from_coefficients(name, d.sigma_s, d.sigma_a, g, eta).map_err(|source| {
                BakeError::Material {
                    name: name.clone(),
                    source: Box::new(source),
                }
            })?;
        Ok((material, source))
    }
}

impl Baker {
    /// Bakes a library: one table per distinct η of `materials` and `etas` (every albedo row,
    /// in increasing η), each checked ([`table::check`](crate::table::check)), and one record
    /// per material, in the order given, on the table of its η. `progress` is called as the
    /// tables go (module docs). Runs on the current rayon pool. A material given twice (by
    /// id) or a source the file cannot keep ([`check_source`]) is refused
    /// ([`BakeError::Scene`]) before any table is baked.
    pub fn bake(
        &self,
        materials: &[MaterialSpec],
        etas: &[f64],
        progress: Option<OnProgress<'_>>,
    ) -> Result<BakedLibrary, BakeError> {
        // The records' rules, checked now rather than by the file's writer after the bake
        for (k, spec) in materials.iter().enumerate() {
            check_source(spec.id(), spec.source())?;
            if materials[..k].iter().any(|m| m.id() == spec.id()) {
                return Err(SceneError::Duplicate(spec.id().to_string()).into());
            }
        }
        let mut all: Vec<f64> = materials.iter().map(MaterialSpec::eta).collect();
        all.extend_from_slice(etas);
        all.sort_by(f64::total_cmp);
        all.dedup();
        let rows = 0..self.albedo_grid().rho.len();
        let plan: Vec<_> = all.iter().map(|&eta| (eta, rows.clone())).collect();
        let mut builder = LibraryBuilder::new();
        let tables = self.bake_tables(&plan, self.theta_sampling, &mut builder, progress)?;

        let mut warnings = Vec::new();
        let mut baked = Vec::with_capacity(materials.len());
        for spec in materials {
            // `all` holds every material's η, and `tables` one table per η of `all`.
            let Some(table) = all
                .iter()
                .zip(&tables)
                .find(|(eta, _)| eta.to_bits() == spec.eta().to_bits())
                .map(|(_, table)| table)
            else {
                continue;
            };
            let (material, source) = spec.resolve(table.table(), &mut warnings)?;
            let record = format::Material {
                name: material.id().to_string(),
                source: source.to_string(),
                sigma_s: material.sigma_s(),
                sigma_a: material.sigma_a(),
                g: material.g(),
                eta: material.eta(),
                tables: [table.index() as u32; 3],
                albedo_range: None,
            };
            baked.push(BakedMaterial { material, record });
        }
        for m in &baked {
            builder.add_material(m.record.clone())?;
        }
        let provenance = self.provenance(self.theta_sampling, None, &tables)?;
        builder.set_provenance(provenance.clone());
        Ok(BakedLibrary {
            builder,
            tables,
            materials: baked,
            provenance,
            warnings,
            full_bytes: None,
        })
    }
}
