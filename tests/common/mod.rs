//! Shared fixtures of the format tests: small deterministic libraries, and a raw editor that
//! changes fields of a file and recomputes its CRCs, for hand-made invalid files.
#![allow(dead_code)]

use bssrdf_zoo::format::{
    AlbedoRange, FresnelMoments, LibraryBuilder, Material, ModelKind, Provenance, TableData,
};

/// A table of `n_rho × n_theta × n_r` entries with smooth, deterministic made-up values (not
/// physics: the format does not care).
pub fn synthetic_table(
    eta: f64,
    n_rho: usize,
    n_theta: usize,
    n_r: usize,
    albedo: bool,
) -> TableData {
    let rho: Vec<f32> = (0..n_rho)
        .map(|i| (i as f32 + 0.5) / n_rho as f32)
        .collect();
    let theta: Vec<f32> = (0..n_theta)
        .map(|i| 1.5 * i as f32 / n_theta.max(2) as f32)
        .collect();
    let r: Vec<f32> = (0..n_r)
        .map(|i| 0.01 * 1.1f32.powi(i as i32) * (i + 1) as f32)
        .collect();
    let mut gwc = Vec::with_capacity(n_rho * n_theta * n_r * 3);
    let mut cdf = Vec::with_capacity(n_rho * n_theta * n_r);
    for (a, &p) in rho.iter().enumerate() {
        for (t, &th) in theta.iter().enumerate() {
            for (k, &rr) in r.iter().enumerate() {
                gwc.push(p * (-rr).exp() + 0.001 * a as f32);
                gwc.push(1.0 + th.sin() * 0.5 + 0.01 * t as f32);
                gwc.push(0.25 * th.cos() - 0.001 * k as f32);
                cdf.push((k + 1) as f32 / n_r as f32 * (0.9 + 0.1 * p));
            }
        }
    }
    let effective_albedo = albedo.then(|| {
        rho.iter()
            .flat_map(|&p| theta.iter().map(move |&th| p * (0.8 + 0.1 * th.cos())))
            .collect()
    });
    TableData {
        model: ModelKind::PbdAngular,
        eta,
        fresnel: FresnelMoments::Exact,
        rho,
        theta,
        r,
        gwc,
        cdf,
        effective_albedo,
    }
}

pub fn material(name: &str, table: u32) -> Material {
    Material {
        name: name.to_owned(),
        source: "made up for tests".to_owned(),
        sigma_s: [0.74, 0.88, 1.01],
        sigma_a: [0.032, 0.17, 0.48],
        g: [0.0, 0.0, 0.0],
        eta: 1.3,
        tables: [table; 3],
        albedo_range: None,
    }
}

/// The small library of the corruption tests and conformance vectors (about 4 KiB): one
/// 2×2×4 table with effective albedo, two materials (one with an albedo range), provenance
/// with both `settings` and `accuracy` (keys of equal length, used by a vector).
pub fn tiny_builder() -> LibraryBuilder {
    let mut b = LibraryBuilder::new();
    let t = b.add_table(synthetic_table(1.3, 2, 2, 4, true)).unwrap() as u32;
    b.add_material(material("skin1", t)).unwrap();
    let mut milk = material("skimmilk", t);
    milk.source = "Jensen et al. 2001, table 2".into();
    milk.g = [0.1, 0.2, 0.3];
    milk.albedo_range = Some(AlbedoRange {
        min: [0.5, 0.6, 0.7],
        max: [0.9, 0.95, 1.0],
    });
    b.add_material(milk).unwrap();
    let provenance = Provenance::new("bssrdf-zoo test")
        .with_bake_seconds(1.5)
        .unwrap()
        .with_settings(serde_json::json!({"n_r": 4}))
        .unwrap()
        .with_accuracy(serde_json::json!({"max_rel_err": 0.001}))
        .unwrap();
    b.set_provenance(provenance);
    b
}

/// The example of `format-spec.md`: one 1×1×2 table, one material, no provenance.
pub fn spec_example_builder() -> LibraryBuilder {
    let mut b = LibraryBuilder::new();
    let table = TableData {
        model: ModelKind::PbdAngular,
        eta: 1.5,
        fresnel: FresnelMoments::Exact,
        rho: vec![0.5],
        theta: vec![0.0],
        r: vec![0.5, 1.0],
        gwc: vec![1.0, 2.0, 0.25, 0.5, 2.0, 0.125],
        cdf: vec![0.5, 1.0],
        effective_albedo: None,
    };
    let t = b.add_table(table).unwrap() as u32;
    b.add_material(Material {
        name: "wax".into(),
        source: "example".into(),
        sigma_s: [1.0, 1.0, 1.0],
        sigma_a: [0.5, 0.5, 0.5],
        g: [0.0, 0.0, 0.0],
        eta: 1.5,
        tables: [t; 3],
        albedo_range: None,
    })
    .unwrap();
    b
}

/// A library file as bytes, with helpers to edit fields by name and fix the CRCs after.
#[derive(Clone)]
pub struct Raw {
    pub bytes: Vec<u8>,
}

pub const HEADER: usize = 128;
pub const ENTRY: usize = 64;

impl Raw {
    pub fn new(bytes: Vec<u8>) -> Raw {
        Raw { bytes }
    }

    pub fn u16(&self, at: usize) -> u16 {
        u16::from_le_bytes(self.bytes[at..at + 2].try_into().unwrap())
    }
    pub fn u32(&self, at: usize) -> u32 {
        u32::from_le_bytes(self.bytes[at..at + 4].try_into().unwrap())
    }
    pub fn u64(&self, at: usize) -> u64 {
        u64::from_le_bytes(self.bytes[at..at + 8].try_into().unwrap())
    }
    pub fn set_u16(&mut self, at: usize, v: u16) {
        self.bytes[at..at + 2].copy_from_slice(&v.to_le_bytes());
    }
    pub fn set_u32(&mut self, at: usize, v: u32) {
        self.bytes[at..at + 4].copy_from_slice(&v.to_le_bytes());
    }
    pub fn set_u64(&mut self, at: usize, v: u64) {
        self.bytes[at..at + 8].copy_from_slice(&v.to_le_bytes());
    }
    pub fn set_f32(&mut self, at: usize, v: f32) {
        self.bytes[at..at + 4].copy_from_slice(&v.to_le_bytes());
    }
    pub fn set_f64(&mut self, at: usize, v: f64) {
        self.bytes[at..at + 8].copy_from_slice(&v.to_le_bytes());
    }

    pub fn section_count(&self) -> usize {
        self.u32(20) as usize
    }
    /// File offset of directory entry `i`.
    pub fn entry(&self, i: usize) -> usize {
        HEADER + ENTRY * i
    }
    /// Index of the entry with this kind code and table (`u32::MAX` for file-level).
    pub fn find(&self, kind: u32, table: u32) -> usize {
        (0..self.section_count())
            .find(|&i| self.u32(self.entry(i)) == kind && self.u32(self.entry(i) + 4) == table)
            .unwrap_or_else(|| panic!("no section {kind:#x} for table {table:#x}"))
    }
    pub fn offset(&self, i: usize) -> usize {
        self.u64(self.entry(i) + 32) as usize
    }
    pub fn stored_len(&self, i: usize) -> usize {
        self.u64(self.entry(i) + 40) as usize
    }
    /// File offset of the data of the section with this kind and table.
    pub fn data(&self, kind: u32, table: u32) -> usize {
        self.offset(self.find(kind, table))
    }
    pub fn set_file_size(&mut self) {
        let n = self.bytes.len() as u64;
        self.set_u64(24, n);
    }

    /// Recomputes every section CRC (of sections within the file) and the header CRC.
    pub fn fix_crcs(&mut self) {
        let count = self
            .section_count()
            .min((self.bytes.len() - HEADER) / ENTRY);
        for i in 0..count {
            let (o, n) = (self.offset(i), self.stored_len(i));
            if let Some(data) = o.checked_add(n).and_then(|end| self.bytes.get(o..end)) {
                let crc = crc32fast::hash(data);
                let at = self.entry(i) + 56;
                self.set_u32(at, crc);
            }
        }
        self.fix_header_crc();
    }

    pub fn fix_header_crc(&mut self) {
        let dir_end = (HEADER + ENTRY * self.section_count()).min(self.bytes.len());
        let mut h = crc32fast::Hasher::new();
        h.update(&self.bytes[..124]);
        h.update(&self.bytes[HEADER..dir_end]);
        let crc = h.finalize();
        self.set_u32(124, crc);
    }
}

/// Kind codes, as in `format-spec.md`.
pub mod kind {
    pub const TABLES: u32 = 0x01;
    pub const MATERIALS: u32 = 0x02;
    pub const PROVENANCE: u32 = 0x03;
    pub const AXIS_RHO: u32 = 0x10;
    pub const AXIS_THETA: u32 = 0x11;
    pub const AXIS_R: u32 = 0x12;
    pub const GWC: u32 = 0x20;
    pub const CDF: u32 = 0x21;
    pub const ALBEDO: u32 = 0x22;
    pub const FILE: u32 = u32::MAX;
}
