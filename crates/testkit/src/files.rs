//! Shared fixtures of the format tests: small deterministic libraries, and a raw editor that
//! changes fields of a file and recomputes its CRCs, for hand-made invalid files.

use bssrdf_zoo::format::{
    AlbedoRange, Compression, FresnelMoments, LibraryBuilder, Material, ModelKind, Provenance,
    TableData, WalkComponent, WalkSource,
};

/// A table of `n_rho × n_theta × n_r` entries with smooth, deterministic made-up values (not
/// physics; the format only asks that every GWC node be a profile ≥ 0 with E_β ≥ 0 and
/// |c| < 1). Every node has 0 ≤ E_β < E (no negative floor) and |c| ≤ 0.25.
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
                let e = p * (-rr).exp() + 0.001 * a as f32;
                gwc.push(e);
                gwc.push(e * (0.5 + 0.25 * th.sin() + (0.01 * t as f32).min(0.2)));
                gwc.push(0.25 * th.cos() - 0.001 * k as f32);
                cdf.push((k + 1) as f32 / n_r as f32 * (0.9 + 0.1 * p));
            }
        }
    }
    // A running integral over θ, 0 at the first angle (format-spec.md §10)
    let theta_cdf = albedo.then(|| {
        rho.iter()
            .flat_map(|&p| theta.iter().map(move |&th| p * th * (0.8 + 0.1 * th.cos())))
            .collect()
    });
    TableData {
        model: ModelKind::PbdAngular,
        walk: None,
        ridge: bssrdf_zoo::table::RidgeKind::None,
        eta,
        fresnel: FresnelMoments::Exact,
        rho,
        theta,
        r,
        gwc,
        cdf,
        theta_cdf,
        harmonics: None,
        rebuild: Default::default(),
    }
}

/// `table` (a [`synthetic_table`]) with a negative floor at every node: E_β = 1.5 E, which
/// keeps the profile ≥ 0 for |c| ≤ 0.5 (E_β·2|c| ≤ 1.5 E ≤ E·(1 + |c|)). Files with it need the
/// `signed-floor` feature bit.
pub fn with_signed_floor(mut table: TableData) -> TableData {
    for node in table.gwc.chunks_exact_mut(3) {
        node[1] = 1.5 * node[0];
    }
    table
}

/// `table` (a [`synthetic_table`]) as a walk-angular table (format 1.5) of the walk at `g`
/// for `component`: the same values, with the harmonics of each node's one lobe,
/// rμ₃ = E_β c³ and rμ₄ = E_β c⁴, as its second lobe (a walk-angular table has two). Files
/// with it need the `walk-tables` feature bit, and `harmonics`.
pub fn as_walk_table(mut table: TableData, g: f64, component: WalkComponent) -> TableData {
    let harmonics = table
        .gwc
        .chunks_exact(3)
        .flat_map(|n| [n[1] * n[2].powi(3), n[1] * n[2].powi(4)])
        .collect();
    table.harmonics = Some(harmonics);
    table.model = ModelKind::WalkAngular;
    table.walk = Some(WalkSource { g, component });
    table
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
/// 2×2×4 table with a θ CDF, two materials (one with an albedo range), provenance
/// with both `settings` and `accuracy` (keys of equal length, used by a vector).
pub fn tiny_builder() -> LibraryBuilder {
    tiny_builder_of(synthetic_table(1.3, 2, 2, 4, true))
}

/// The tiny library (see [`tiny_builder`]) with `table` in place of its table.
pub fn tiny_builder_of(table: TableData) -> LibraryBuilder {
    let mut b = LibraryBuilder::new();
    let t = b.add_table(table).unwrap() as u32;
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

/// The sections of the tiny library (see [`tiny_builder`]) followed by a `gwc-harmonics`
/// section for its table: the harmonics of each node's one lobe, rμ₃ = E_β c³ and
/// rμ₄ = E_β c⁴, `[2, 2, 4, 2]`, required flag set. [`Raw::build`] makes a file of them (format
/// 1.2 needs required feature bit 2, `harmonics`, with them).
pub fn tiny_two_lobes_sections() -> Vec<Sec> {
    let mut secs = Raw::new(tiny_builder().to_bytes(Compression::None).unwrap()).sections();
    let gwc = secs.iter().find(|s| s.kind == kind::GWC).unwrap();
    let values: Vec<f32> = gwc
        .data
        .chunks_exact(12)
        .flat_map(|node| {
            let f = |k: usize| f32::from_le_bytes(node[4 * k..4 * k + 4].try_into().unwrap());
            let (e_beta, c) = (f(1), f(2));
            [e_beta * c.powi(3), e_beta * c.powi(4)]
        })
        .collect();
    let mut dims = gwc.dims.clone();
    dims[3] = 2;
    secs.push(Sec {
        kind: kind::HARMONICS,
        table: 0,
        dtype: 2,
        codec: 0,
        flags: 1,
        dims,
        data: values.iter().flat_map(|v| v.to_le_bytes()).collect(),
        raw_len: None,
    });
    secs
}

/// The example of `format-spec.md`: one 1×1×2 table, one material, no provenance.
pub fn spec_example_builder() -> LibraryBuilder {
    let mut b = LibraryBuilder::new();
    let table = TableData {
        model: ModelKind::PbdAngular,
        walk: None,
        ridge: bssrdf_zoo::table::RidgeKind::None,
        eta: 1.5,
        fresnel: FresnelMoments::Exact,
        rho: vec![0.5],
        theta: vec![0.0],
        r: vec![0.5, 1.0],
        gwc: vec![1.0, 2.0, 0.25, 0.5, 2.0, 0.125],
        cdf: vec![0.5, 1.0],
        theta_cdf: None,
        harmonics: None,
        rebuild: Default::default(),
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
    pub const HARMONICS: u32 = 0x23;
    pub const FILE: u32 = u32::MAX;
}

/// One section taken out of a file (or to be put into one by [`Raw::build`]).
#[derive(Clone, Debug)]
pub struct Sec {
    pub kind: u32,
    pub table: u32,
    pub dtype: u16,
    pub codec: u16,
    pub flags: u16,
    pub dims: Vec<u32>,
    /// Stored bytes.
    pub data: Vec<u8>,
    /// Decoded length; `None` means the stored length.
    pub raw_len: Option<u64>,
}

impl Sec {
    /// Compresses the data with zstd (level 3) and marks the section so.
    pub fn zstd(mut self) -> Sec {
        self.raw_len = Some(self.data.len() as u64);
        self.data = zstd::bulk::compress(&self.data, 3).unwrap();
        self.codec = 1;
        self
    }
}

impl Raw {
    /// The sections of a well-formed file, in directory order.
    pub fn sections(&self) -> Vec<Sec> {
        (0..self.section_count())
            .map(|i| {
                let e = self.entry(i);
                let ndim = self.u16(e + 14) as usize;
                Sec {
                    kind: self.u32(e),
                    table: self.u32(e + 4),
                    dtype: self.u16(e + 8),
                    codec: self.u16(e + 10),
                    flags: self.u16(e + 12),
                    dims: (0..ndim).map(|d| self.u32(e + 16 + 4 * d)).collect(),
                    data: self.bytes[self.offset(i)..self.offset(i) + self.stored_len(i)].to_vec(),
                    raw_len: Some(self.u64(e + 48)),
                }
            })
            .collect()
    }

    /// A file laid out as the spec says, from its parts, with every CRC right.
    pub fn build(minor: u16, required: u64, optional: u64, alignment: u32, secs: &[Sec]) -> Raw {
        let dir_end = HEADER + ENTRY * secs.len();
        let mut bytes = vec![0u8; dir_end];
        let mut offsets = Vec::new();
        for s in secs {
            let a = alignment as usize;
            let offset = bytes.len().div_ceil(a) * a;
            bytes.resize(offset, 0);
            bytes.extend_from_slice(&s.data);
            offsets.push(offset);
        }
        let mut raw = Raw::new(bytes);
        raw.bytes[..12].copy_from_slice(b"\x89BSSRDF\r\n\x1a\n\0");
        raw.set_u16(12, 1);
        raw.set_u16(14, minor);
        raw.set_u32(16, 0x0A0B_0C0D);
        raw.set_u32(20, secs.len() as u32);
        raw.set_file_size();
        raw.set_u64(32, required);
        raw.set_u64(40, optional);
        raw.set_u32(48, alignment);
        for (i, (s, &offset)) in secs.iter().zip(&offsets).enumerate() {
            let e = raw.entry(i);
            raw.set_u32(e, s.kind);
            raw.set_u32(e + 4, s.table);
            raw.set_u16(e + 8, s.dtype);
            raw.set_u16(e + 10, s.codec);
            raw.set_u16(e + 12, s.flags);
            raw.set_u16(e + 14, s.dims.len() as u16);
            for (d, &v) in s.dims.iter().enumerate() {
                raw.set_u32(e + 16 + 4 * d, v);
            }
            raw.set_u64(e + 32, offset as u64);
            raw.set_u64(e + 40, s.data.len() as u64);
            raw.set_u64(e + 48, s.raw_len.unwrap_or(s.data.len() as u64));
        }
        raw.fix_crcs();
        raw
    }
}
