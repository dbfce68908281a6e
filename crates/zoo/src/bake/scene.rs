//! The bake of a scene: only the albedo rows, tables and sections its materials need
//! ([`Scene::plan`]), and the size of the full library of the same materials, to compare.

use serde_json::{json, Value};

use super::{BakeError, BakedLibrary, BakedMaterial, Baker, OnProgress};
use crate::format::{Compression, LibraryBuilder, ModelKind, Provenance, TableData};
use crate::gwc::Rebuild;
use crate::scene::{Integrator, Scene};
use crate::table::{Lobes, HARMONICS_PER_NODE};

impl Baker {
    /// Bakes what `scene` needs: the tables of its plan on this bake's albedo rows (in file
    /// order: by η, then by row), each checked, the θ-sampling section only if its integrator
    /// needs it (this overrides [`Baker::with_theta_sampling`]), and one record per scene
    /// material with the table and albedo range of each channel. The provenance's settings hold
    /// the plan under `scene`; the result's [`BakedLibrary::full_bytes`] is the size of the full
    /// library of the same materials, and its warnings are the scene's. Runs on the current
    /// rayon pool.
    pub fn bake_scene(
        &self,
        scene: &Scene,
        progress: Option<OnProgress<'_>>,
    ) -> Result<BakedLibrary, BakeError> {
        let albedo = self.albedo_grid();
        let axis = albedo.rho_axis().map_err(BakeError::Axis)?;
        let plan = scene.plan(&axis)?;
        let theta_sampling = scene.integrator().needs_theta_sampling();
        let tables: Vec<_> = plan
            .tables
            .iter()
            .map(|t| (t.eta, t.rows.clone()))
            .collect();
        let mut builder = LibraryBuilder::new();
        let tables = self.bake_tables(&tables, theta_sampling, &mut builder, progress)?;

        let mut materials = Vec::with_capacity(scene.materials().len());
        for (m, channel_tables) in scene.materials().iter().zip(&plan.channel_tables) {
            let record = m.record(channel_tables.map(|i| i as u32));
            builder.add_material(record.clone())?;
            materials.push(BakedMaterial {
                material: m.material().clone(),
                record,
            });
        }
        let integrator = match scene.integrator() {
            Integrator::Path => "path",
            Integrator::Particle => "particle",
        };
        let plan_json: Vec<Value> = plan
            .tables
            .iter()
            .map(|t| json!({"eta": t.eta, "rows": [t.rows.start, t.rows.end]}))
            .collect();
        let provenance = self.provenance(
            theta_sampling,
            Some(json!({
                "integrator": integrator,
                "full_rho_rows": albedo.rho.len(),
                "tables": plan_json,
            })),
            &tables,
        )?;
        builder.set_provenance(provenance.clone());
        let full_bytes = self.full_library_bytes(scene, provenance.clone())?;
        Ok(BakedLibrary {
            builder,
            tables,
            materials,
            provenance,
            warnings: scene.warnings(),
            full_bytes: Some(full_bytes),
        })
    }

    /// Size of the library [`Baker::bake`] would make of the scene's materials: one full table
    /// per η with the θ-sampling section, uncompressed, with `provenance`. Laid out with zero
    /// values, which take exactly the bytes of the real ones.
    fn full_library_bytes(&self, scene: &Scene, provenance: Provenance) -> Result<u64, BakeError> {
        let mut etas: Vec<f64> = scene
            .materials()
            .iter()
            .map(|m| m.material().eta())
            .collect();
        etas.sort_by(f64::total_cmp);
        etas.dedup();
        let axis = |v: &[f64]| v.iter().map(|&x| x as f32).collect::<Vec<f32>>();
        let mut builder = LibraryBuilder::new();
        for &eta in &etas {
            let grid = &self.grid_at(eta);
            let (n_rho, n_theta, n_r) = (grid.rho.len(), grid.theta.len(), grid.r.len());
            builder.add_table(TableData {
                model: ModelKind::PbdAngular,
                walk: None,
                ridge: crate::table::ridge::RidgeKind::None,
                eta,
                fresnel: self.moments.into(),
                rho: axis(&grid.rho),
                theta: axis(&grid.theta),
                r: axis(&grid.r),
                gwc: vec![0.0; n_rho * n_theta * n_r * 3],
                cdf: vec![0.0; n_rho * n_theta * n_r],
                theta_cdf: Some(vec![0.0; n_rho * n_theta]),
                harmonics: (self.lobes_at(eta) == Lobes::Two)
                    .then(|| vec![0.0; n_rho * n_theta * n_r * HARMONICS_PER_NODE]),
                rebuild: Rebuild::default(),
            })?;
        }
        for m in scene.materials() {
            let index = etas
                .iter()
                .position(|&e| e.to_bits() == m.material().eta().to_bits())
                .unwrap_or(0) as u32;
            let mut record = m.record([index; 3]);
            record.albedo_range = None;
            builder.add_material(record)?;
        }
        builder.set_provenance(provenance);
        let bytes = builder.to_bytes(Compression::None)?;
        Ok(bytes.len() as u64)
    }
}
