//! Parsing and validating a whole library file from its bytes, in the order `format-spec.md`
//! gives ("Reading a file"). Every count, length and offset from the file is checked with
//! checked arithmetic against the bytes present and against a hard cap before it is used; all
//! slicing goes through `get`. Nothing here panics on any input.

use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap, HashSet};

use zerocopy::FromBytes;

use super::error::{FormatError, FormatResult};
use super::map::AlignedBuf;
use super::provenance::Provenance;
use super::records::{
    check_axis, check_finite, check_gwc_nodes, check_radial_cdf, check_reserved, check_theta_cdf,
    Material, TableHeader,
};
use super::spec::{
    align_up, crc32, required_features, AxisKind, Codec, Dtype, RawEntry, RawHeader, RawMaterial,
    RawTable, SectionKind, BYTE_ORDER_MARK, ENTRY_RESERVED_OFFSET, ENTRY_SIZE, HEADER_CRC_OFFSET,
    HEADER_RESERVED_OFFSET, HEADER_SIZE, MAGIC, MATERIAL_RECORD_SIZE, MAX_ALIGNMENT, MAX_MATERIALS,
    MAX_SECTIONS, MAX_SECTION_BYTES, MAX_TABLES, MIN_ALIGNMENT, NO_TABLE, SECTION_REQUIRED,
    TABLE_RECORD_SIZE, VERSION_MAJOR, VERSION_MINOR,
};

/// How much of a file to check when opening it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verify {
    /// Everything: structure, header CRC, every section's CRC, every table value finite and
    /// every `gwc-params` node valid (format-spec.md §10). Reads every byte of the file for the
    /// CRCs, and the table sections again for the value checks.
    Full,
    /// Structure and header CRC only (plus the small axis sections and all records, which
    /// are always validated). Section CRCs, NaN scans and the `gwc-params` node checks
    /// (including E_β > E without the `signed-floor` bit) are skipped;
    /// [`super::Library::verify`] runs them later.
    HeaderOnly,
}

/// One directory entry, checked: what a section holds and where its bytes are.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SectionInfo {
    /// Kind code (see [`SectionKind`]; other codes are extension kinds).
    pub kind: u32,
    /// Table the section belongs to, or `None` for file-level sections.
    pub table: Option<usize>,
    /// Element type.
    pub dtype: Dtype,
    /// How the bytes are stored.
    pub codec: Codec,
    /// True if a reader that does not know the kind must reject the file.
    pub required: bool,
    /// Dimensions, outermost first.
    pub dims: Vec<u32>,
    /// Byte offset of the stored bytes in the file.
    pub offset: usize,
    /// Number of stored bytes.
    pub stored_len: usize,
    /// Number of bytes once decoded: product of dims times the element size.
    pub raw_len: usize,
    /// CRC-32 of the stored bytes.
    pub crc32: u32,
}

impl SectionInfo {
    /// The kind, if version 1.0 defines it.
    pub fn known_kind(&self) -> Option<SectionKind> {
        SectionKind::from_code(self.kind)
    }
}

/// A table's record and where its sections are (kind code → entry index).
#[derive(Debug, Clone)]
pub(crate) struct TableSlot {
    pub header: TableHeader,
    pub sections: BTreeMap<u32, usize>,
}

/// Everything learnt from a file apart from its bytes.
#[derive(Debug, Clone)]
pub(crate) struct Parsed {
    pub minor: u16,
    pub required_features: u64,
    pub optional_features: u64,
    pub alignment: u32,
    pub entries: Vec<SectionInfo>,
    /// Decoded bytes of zstd sections, by entry index.
    pub decoded: Vec<Option<AlignedBuf>>,
    /// File-level sections (kind code → entry index).
    pub file_sections: BTreeMap<u32, usize>,
    pub tables: Vec<TableSlot>,
    pub materials: Vec<Material>,
    pub provenance: Option<Provenance>,
}

impl Parsed {
    /// The decoded bytes of entry `index` within the file `bytes`.
    pub fn section_bytes<'a>(&'a self, bytes: &'a [u8], index: usize) -> &'a [u8] {
        section_bytes(bytes, &self.entries, &self.decoded, index)
    }

    /// Section CRCs, NaN scans and `gwc-params` node checks: what [`Verify::Full`] adds to
    /// [`Verify::HeaderOnly`].
    pub fn verify_data(&self, bytes: &[u8]) -> FormatResult<()> {
        check_section_crcs(bytes, &self.entries)?;
        let data = |i: usize| self.section_bytes(bytes, i);
        for (t, slot) in self.tables.iter().enumerate() {
            check_table_values(t, slot, &data, self.required_features)?;
        }
        Ok(())
    }
}

fn check_section_crcs(bytes: &[u8], entries: &[SectionInfo]) -> FormatResult<()> {
    for (section, entry) in entries.iter().enumerate() {
        let stored = bytes
            .get(entry.offset..entry.offset.saturating_add(entry.stored_len))
            .unwrap_or_default();
        let computed = crc32(&[stored]);
        if computed != entry.crc32 {
            return Err(FormatError::SectionCrc {
                section,
                stored: entry.crc32,
                computed,
            });
        }
    }
    Ok(())
}

fn section_bytes<'a>(
    bytes: &'a [u8],
    entries: &[SectionInfo],
    decoded: &'a [Option<AlignedBuf>],
    index: usize,
) -> &'a [u8] {
    if let Some(Some(buf)) = decoded.get(index) {
        return buf.bytes();
    }
    entries
        .get(index)
        .and_then(|e| bytes.get(e.offset..e.offset.checked_add(e.stored_len)?))
        .unwrap_or_default()
}

/// Little-endian f32 values of a byte run (a copy; used for validation only).
pub(crate) fn f32_values(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// The f32 values of a byte run: cast in place where it is aligned (sections are 256-byte
/// aligned in an aligned map or buffer), else [`f32_values`], which keeps this correct for any
/// input.
fn f32_view(bytes: &[u8]) -> Cow<'_, [f32]> {
    match <[f32]>::ref_from_bytes(bytes) {
        Ok(values) => Cow::Borrowed(values),
        Err(_) => Cow::Owned(f32_values(bytes)),
    }
}

/// The values of one table's sections, in kind order: every value finite, for `gwc-params`
/// every node valid, with negative floors allowed when the file sets required feature bit 1,
/// and for `radial-cdf` and `theta-cdf` every row a running integral (≥ 0, never decreasing). One pass over each section; skipped by [`Verify::HeaderOnly`] like the
/// CRCs, and run by [`super::Library::verify`].
fn check_table_values<'a>(
    t: usize,
    slot: &TableSlot,
    data: &impl Fn(usize) -> &'a [u8],
    required: u64,
) -> FormatResult<()> {
    let signed_floor = required & required_features::SIGNED_FLOOR != 0;
    for (&code, &index) in &slot.sections {
        let bytes = data(index);
        match SectionKind::from_code(code) {
            // One pass for finiteness and the node rules.
            Some(SectionKind::GwcParams) => {
                check_gwc_nodes(t, &slot.header, &f32_view(bytes), signed_floor)?
            }
            Some(kind @ SectionKind::RadialCdf) => {
                check_finite_bytes(t, kind, bytes)?;
                check_radial_cdf(t, &slot.header, &f32_view(bytes))?
            }
            Some(kind @ SectionKind::ThetaCdf) => {
                check_finite_bytes(t, kind, bytes)?;
                check_theta_cdf(t, &slot.header, &f32_view(bytes))?
            }
            Some(kind) => check_finite_bytes(t, kind, bytes)?,
            None => {}
        }
    }
    // A signed pair at a node needs bit 3 (§4), in a file of any minor: 1.2 had no one reading
    let params = slot.sections.get(&SectionKind::GwcParams.code());
    let harmonics = slot.sections.get(&SectionKind::Harmonics.code());
    if let (Some(&p), Some(&h), false) = (
        params,
        harmonics,
        required & required_features::SIGNED_LOBES != 0,
    ) {
        let rebuild = super::library::rebuild_of(required);
        if let Some(node) = first_signed_node(&f32_view(data(p)), &f32_view(data(h)), rebuild) {
            return Err(FormatError::SignedLobesNotDeclared { table: t, node });
        }
    }
    Ok(())
}

/// The first node (in storage order) of a two-lobe table's `gwc-params` and `gwc-harmonics`
/// values that rebuilds into a signed pair by `rebuild` (`table::node_is_signed`).
pub(crate) fn first_signed_node(
    params: &[f32],
    harmonics: &[f32],
    rebuild: crate::gwc::Rebuild,
) -> Option<usize> {
    params
        .chunks_exact(3)
        .zip(harmonics.chunks_exact(2))
        .position(|(p, h)| crate::table::node_is_signed([p[0], p[1], p[2], h[0], h[1]], rebuild))
}

fn check_finite_bytes(table: usize, kind: SectionKind, bytes: &[u8]) -> FormatResult<()> {
    // Exponent all ones means NaN or infinity; test without building a vector.
    let bad = bytes
        .chunks_exact(4)
        .position(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]) & 0x7F80_0000 == 0x7F80_0000);
    match bad {
        None => Ok(()),
        Some(_) => check_finite(table, kind, &f32_values(bytes)),
    }
}

/// True if this reader knows everything a file of `minor` may contain, so reserved bytes
/// and unknown flag bits must be zero ("strict" reading); later minors may use them.
pub(crate) fn knows_minor(minor: u16) -> bool {
    minor <= VERSION_MINOR
}

/// Parses and validates a whole file. `bytes` must start at an address aligned to 256 bytes
/// (a map or an [`AlignedBuf`]), so that section views can be cast to `&[f32]` afterwards.
pub(crate) fn parse(bytes: &[u8], verify: Verify) -> FormatResult<Parsed> {
    if cfg!(target_endian = "big") {
        return Err(FormatError::BigEndianHost);
    }
    let header = parse_header(bytes)?;
    let file_size = bytes.len() as u64;
    let strict = knows_minor(header.minor.get());
    let alignment = header.alignment.get();
    let count = header.section_count.get() as usize;
    let dir_end = HEADER_SIZE + count * ENTRY_SIZE;

    // Directory: shapes, lengths, and a tiling of the file by aligned sections.
    let mut entries = Vec::with_capacity(count);
    let mut previous: Option<(u64, u64)> = None; // (offset, end) of the previous section
    for i in 0..count {
        let start = HEADER_SIZE + i * ENTRY_SIZE;
        let raw = bytes
            .get(start..start + ENTRY_SIZE)
            .and_then(|b| RawEntry::read_from_bytes(b).ok())
            .ok_or(FormatError::TooShort {
                len: file_size,
                min: dir_end as u64,
            })?;
        let entry = parse_entry(i, &raw, &header, strict)?;
        let (offset, stored) = (raw.offset.get(), raw.stored_len.get());
        let after = previous.map_or(dir_end as u64, |(_, end)| end);
        if offset % u64::from(alignment) != 0 {
            return Err(FormatError::MisalignedSection {
                section: i,
                offset,
                alignment,
            });
        }
        if let Some((prev_offset, _)) = previous {
            if offset < prev_offset {
                return Err(FormatError::SectionsOutOfOrder {
                    section: i,
                    offset,
                    previous: prev_offset,
                });
            }
        }
        if offset < after {
            return Err(FormatError::SectionsOverlap {
                section: i,
                offset,
                previous_end: after,
            });
        }
        let expected = align_up(after, alignment.into()).unwrap_or(u64::MAX);
        if offset > expected {
            return Err(FormatError::SectionGap {
                section: i,
                offset,
                expected,
            });
        }
        let end = offset.checked_add(stored).filter(|&e| e <= file_size);
        let Some(end) = end else {
            return Err(FormatError::SectionOutOfBounds {
                section: i,
                offset,
                end: offset.saturating_add(stored),
                file_size,
            });
        };
        check_padding(bytes, after as usize, offset as usize)?;
        previous = Some((offset, end));
        entries.push(entry);
    }
    let data_end = previous.map_or(dir_end as u64, |(_, end)| end);
    if data_end < file_size {
        return Err(FormatError::DataAfterLastSection {
            end: data_end,
            extra: file_size - data_end,
        });
    }

    // Kinds, owners and uniqueness.
    let table_count = table_count(&entries, strict)?;
    let mut seen = HashSet::new();
    let mut file_sections = BTreeMap::new();
    for (i, entry) in entries.iter().enumerate() {
        check_kind(i, entry, strict, table_count)?;
        let owner = entry.table.map_or(NO_TABLE, |t| t as u32);
        if !seen.insert((entry.kind, owner)) {
            return Err(FormatError::DuplicateSection {
                section: i,
                kind: entry.kind,
                table: owner,
            });
        }
        if entry.table.is_none() {
            file_sections.insert(entry.kind, i);
        }
    }

    // Section data: CRCs on request, then zstd sections decoded into aligned buffers.
    if verify == Verify::Full {
        check_section_crcs(bytes, &entries)?;
    }
    let decoded = decode_sections(bytes, &entries)?;
    let data = |i: usize| section_bytes(bytes, &entries, &decoded, i);

    // Records, tables and their sections.
    let tables_index =
        *file_sections
            .get(&SectionKind::Tables.code())
            .ok_or(FormatError::MissingSection {
                kind: SectionKind::Tables,
                table: None,
            })?;
    let mut tables = Vec::with_capacity(table_count);
    for (t, record) in records(&entries[tables_index], data(tables_index)).enumerate() {
        let raw = RawTable::read_from_prefix(record).map(|(r, _)| r).ok();
        let raw = raw.ok_or(FormatError::RecordSize {
            kind: SectionKind::Tables,
            found: record.len() as u32,
            expected: TABLE_RECORD_SIZE,
        })?;
        tables.push(TableSlot {
            header: TableHeader::decode(t, &raw, strict, header.required_features.get())?,
            sections: BTreeMap::new(),
        });
    }
    for (i, entry) in entries.iter().enumerate() {
        if let Some(slot) = entry.table.and_then(|t| tables.get_mut(t)) {
            slot.sections.insert(entry.kind, i);
        }
    }
    for (t, slot) in tables.iter().enumerate() {
        check_table(
            t,
            slot,
            &entries,
            &data,
            verify,
            header.required_features.get(),
        )?;
    }

    let materials_index =
        *file_sections
            .get(&SectionKind::Materials.code())
            .ok_or(FormatError::MissingSection {
                kind: SectionKind::Materials,
                table: None,
            })?;
    check_record_shape(
        &entries[materials_index],
        SectionKind::Materials,
        MATERIAL_RECORD_SIZE,
        MAX_MATERIALS,
        strict,
    )?;
    let mut materials: Vec<Material> = Vec::new();
    let mut names: HashMap<String, usize> = HashMap::new();
    for (m, record) in records(&entries[materials_index], data(materials_index)).enumerate() {
        let raw = RawMaterial::read_from_prefix(record).map(|(r, _)| r).ok();
        let raw = raw.ok_or(FormatError::RecordSize {
            kind: SectionKind::Materials,
            found: record.len() as u32,
            expected: MATERIAL_RECORD_SIZE,
        })?;
        let material = Material::decode(m, &raw, strict, table_count)?;
        if let Some(&first) = names.get(&material.name) {
            return Err(FormatError::DuplicateName {
                material: m,
                first,
                name: material.name,
            });
        }
        names.insert(material.name.clone(), m);
        materials.push(material);
    }

    let provenance = match file_sections.get(&SectionKind::Provenance.code()) {
        Some(&i) if entries[i].dims.len() != 1 => {
            return Err(FormatError::SectionDims {
                table: None,
                kind: SectionKind::Provenance,
                found: entries[i].dims.clone(),
                expected: vec![entries[i].raw_len as u32],
            })
        }
        Some(&i) => Some(Provenance::from_json(data(i))?),
        None => None,
    };

    Ok(Parsed {
        minor: header.minor.get(),
        required_features: header.required_features.get(),
        optional_features: header.optional_features.get(),
        alignment,
        entries,
        decoded,
        file_sections,
        tables,
        materials,
        provenance,
    })
}

/// Magic, byte order, version, size, directory bounds, CRC, features, reserved bytes and
/// alignment of the header, in that order.
fn parse_header(bytes: &[u8]) -> FormatResult<RawHeader> {
    let file_size = bytes.len() as u64;
    let prefix = bytes.get(..MAGIC.len()).unwrap_or(bytes);
    if prefix != &MAGIC[..prefix.len()] {
        return Err(FormatError::BadMagic {
            found: prefix.to_vec(),
            expected: MAGIC.to_vec(),
        });
    }
    let header = bytes
        .get(..HEADER_SIZE)
        .and_then(|b| RawHeader::read_from_bytes(b).ok())
        .ok_or(FormatError::TooShort {
            len: file_size,
            min: HEADER_SIZE as u64,
        })?;
    let bom = header.byte_order.get();
    if bom != BYTE_ORDER_MARK {
        let hint = if bom.swap_bytes() == BYTE_ORDER_MARK {
            ": the file was written big-endian"
        } else {
            ""
        };
        return Err(FormatError::WrongByteOrder { found: bom, hint });
    }
    let major = header.major.get();
    if major != VERSION_MAJOR {
        let hint = if major > VERSION_MAJOR {
            ": the file is newer than this tool, upgrade the tool"
        } else {
            ""
        };
        return Err(FormatError::UnsupportedMajor {
            found: major,
            supported: VERSION_MAJOR,
            hint,
        });
    }
    let declared = header.file_size.get();
    if declared > file_size {
        return Err(FormatError::Truncated {
            declared,
            actual: file_size,
        });
    }
    if declared < file_size {
        return Err(FormatError::TrailingBytes {
            declared,
            actual: file_size,
        });
    }
    let count = u64::from(header.section_count.get());
    let dir_end = HEADER_SIZE as u64 + count * ENTRY_SIZE as u64;
    if count > u64::from(MAX_SECTIONS) || dir_end > file_size {
        return Err(FormatError::DirectoryOutOfBounds {
            count,
            end: dir_end,
            file_size,
            max: MAX_SECTIONS,
        });
    }
    let head = bytes.get(..HEADER_CRC_OFFSET).unwrap_or_default();
    let directory = bytes.get(HEADER_SIZE..dir_end as usize).unwrap_or_default();
    let computed = crc32(&[head, directory]);
    if computed != header.header_crc.get() {
        return Err(FormatError::HeaderCrc {
            stored: header.header_crc.get(),
            computed,
        });
    }
    let unknown = header.required_features.get() & !required_features::KNOWN;
    if unknown != 0 {
        return Err(FormatError::UnsupportedFeatures {
            bits: unknown,
            names: required_features::names(unknown).join(", "),
            major: VERSION_MAJOR,
            minor: VERSION_MINOR,
        });
    }
    // Optional feature bits are ignored by definition (versions 1.0 and 1.1 define none).
    if knows_minor(header.minor.get()) {
        check_reserved("header", HEADER_RESERVED_OFFSET, &header.reserved)?;
    }
    let alignment = header.alignment.get();
    if !alignment.is_power_of_two() || !(MIN_ALIGNMENT..=MAX_ALIGNMENT).contains(&alignment) {
        return Err(FormatError::BadAlignment {
            value: alignment,
            min: MIN_ALIGNMENT,
            max: MAX_ALIGNMENT,
        });
    }
    Ok(header)
}

/// Codes, shape and lengths of entry `i` (its position is checked by the caller).
fn parse_entry(
    i: usize,
    raw: &RawEntry,
    header: &RawHeader,
    strict: bool,
) -> FormatResult<SectionInfo> {
    let dtype = Dtype::from_code(raw.dtype.get()).ok_or(FormatError::UnknownDtype {
        section: i,
        dtype: raw.dtype.get(),
    })?;
    let codec = Codec::from_code(raw.codec.get()).ok_or(FormatError::UnknownCodec {
        section: i,
        codec: raw.codec.get(),
    })?;
    if codec == Codec::Zstd && header.required_features.get() & required_features::ZSTD == 0 {
        return Err(FormatError::FeatureNotDeclared {
            section: i,
            feature: "zstd codec (required feature bit 0)",
        });
    }
    if raw.kind.get() == SectionKind::Harmonics.code()
        && header.required_features.get() & required_features::HARMONICS == 0
    {
        return Err(FormatError::HarmonicsNotDeclared { section: i });
    }
    let ndim = raw.ndim.get();
    let all_dims = raw.dims.map(|d| d.get());
    let shape_ok = (1..=4).contains(&ndim) && all_dims[ndim as usize..].iter().all(|&d| d == 0);
    if !shape_ok {
        return Err(FormatError::BadShape {
            section: i,
            ndim,
            dims: all_dims,
        });
    }
    let dims = all_dims[..ndim as usize].to_vec();
    // Four u32 dims times 4 can overflow even u128: saturate, then compare with the cap.
    let bytes = dims
        .iter()
        .try_fold(u128::from(dtype.size()), |acc, &d| {
            acc.checked_mul(u128::from(d))
        })
        .unwrap_or(u128::MAX);
    if bytes > u128::from(MAX_SECTION_BYTES) {
        return Err(FormatError::SectionTooLarge {
            section: i,
            bytes,
            max: MAX_SECTION_BYTES,
        });
    }
    let expected = bytes as u64;
    let (raw_len, stored_len) = (raw.raw_len.get(), raw.stored_len.get());
    if raw_len != expected {
        return Err(FormatError::RawLengthMismatch {
            section: i,
            raw_len,
            expected,
        });
    }
    if codec == Codec::None && stored_len != raw_len {
        return Err(FormatError::StoredLengthMismatch {
            section: i,
            stored_len,
            raw_len,
        });
    }
    let flags = raw.flags.get();
    if strict && flags & !SECTION_REQUIRED != 0 {
        return Err(FormatError::SectionFlags {
            section: i,
            kind: raw.kind.get(),
            flags,
            expected: flags & SECTION_REQUIRED,
        });
    }
    if strict {
        check_reserved(
            &format!("directory entry {i}"),
            ENTRY_RESERVED_OFFSET,
            &raw.reserved,
        )?;
    }
    // Both lengths are bounded by the file size (checked by the caller) or by the cap.
    let stored_len = usize::try_from(stored_len).unwrap_or(usize::MAX);
    Ok(SectionInfo {
        kind: raw.kind.get(),
        table: match raw.table.get() {
            NO_TABLE => None,
            t => Some(t as usize),
        },
        dtype,
        codec,
        required: flags & SECTION_REQUIRED != 0,
        dims,
        offset: usize::try_from(raw.offset.get()).unwrap_or(usize::MAX),
        stored_len,
        raw_len: expected as usize,
        crc32: raw.crc32.get(),
    })
}

/// The flags, dtype and owner of entry `i` against what its kind allows.
fn check_kind(i: usize, entry: &SectionInfo, strict: bool, table_count: usize) -> FormatResult<()> {
    let flags = u16::from(entry.required);
    let bad_table = || FormatError::SectionTableIndex {
        section: i,
        kind: entry.kind,
        table: entry.table.map_or(NO_TABLE, |t| t as u32),
        table_count,
    };
    let Some(kind) = SectionKind::from_code(entry.kind) else {
        if entry.required {
            return Err(FormatError::UnknownRequiredSection {
                section: i,
                kind: entry.kind,
            });
        }
        if entry.table.is_some_and(|t| t >= table_count) {
            return Err(bad_table());
        }
        return Ok(());
    };
    let expected = u16::from(kind.required());
    if strict && flags != expected {
        return Err(FormatError::SectionFlags {
            section: i,
            kind: entry.kind,
            flags,
            expected,
        });
    }
    if entry.dtype != kind.dtype() {
        return Err(FormatError::WrongDtype {
            section: i,
            kind,
            dtype: entry.dtype.name(),
            expected: kind.dtype().name(),
        });
    }
    let owner_ok = match entry.table {
        None => !kind.per_table(),
        Some(t) => kind.per_table() && t < table_count,
    };
    if !owner_ok {
        return Err(bad_table());
    }
    Ok(())
}

/// Number of tables, from the shape of the `tables` section (0 if it is missing; the caller
/// reports that).
fn table_count(entries: &[SectionInfo], strict: bool) -> FormatResult<usize> {
    let Some(entry) = entries
        .iter()
        .find(|e| e.kind == SectionKind::Tables.code() && e.table.is_none())
    else {
        return Ok(0);
    };
    check_record_shape(
        entry,
        SectionKind::Tables,
        TABLE_RECORD_SIZE,
        MAX_TABLES,
        strict,
    )?;
    Ok(entry.dims[0] as usize)
}

fn check_record_shape(
    entry: &SectionInfo,
    kind: SectionKind,
    size: usize,
    max: u64,
    strict: bool,
) -> FormatResult<()> {
    let [count, record] = entry.dims[..] else {
        return Err(FormatError::SectionDims {
            table: None,
            kind,
            found: entry.dims.clone(),
            expected: vec![entry.dims.first().copied().unwrap_or(0), size as u32],
        });
    };
    // Version 1.0 records; a later minor may append fields, which this reader skips.
    if (record as usize) < size || (strict && record as usize != size) {
        return Err(FormatError::RecordSize {
            kind,
            found: record,
            expected: size,
        });
    }
    if u64::from(count) > max {
        return Err(FormatError::TooManyRecords {
            kind,
            count: count.into(),
            max,
        });
    }
    Ok(())
}

/// The records of a record section, each `dims[1]` bytes long.
fn records<'a>(entry: &SectionInfo, data: &'a [u8]) -> std::slice::ChunksExact<'a, u8> {
    let size = entry.dims.get(1).copied().unwrap_or(1).max(1) as usize;
    data.chunks_exact(size)
}

/// Decodes every zstd section into its own aligned buffer of exactly its raw length.
fn decode_sections(bytes: &[u8], entries: &[SectionInfo]) -> FormatResult<Vec<Option<AlignedBuf>>> {
    let mut decoded = Vec::with_capacity(entries.len());
    let mut decompressor = None;
    for (section, entry) in entries.iter().enumerate() {
        if entry.codec != Codec::Zstd {
            decoded.push(None);
            continue;
        }
        let stored = bytes
            .get(entry.offset..entry.offset.saturating_add(entry.stored_len))
            .unwrap_or_default();
        let zstd_error = |e: std::io::Error| FormatError::Zstd {
            section,
            message: e.to_string(),
        };
        if stored.is_empty() {
            // zstd decodes no input to no output; §7 asks for one frame or more
            return Err(FormatError::Zstd {
                section,
                message: "no zstd frame: a compressed section holds one or more".into(),
            });
        }
        if decompressor.is_none() {
            decompressor = Some(zstd::bulk::Decompressor::new().map_err(zstd_error)?);
        }
        let Some(d) = decompressor.as_mut() else {
            continue;
        };
        let mut buf = AlignedBuf::zeroed(entry.raw_len);
        let found = match d.decompress_to_buffer(stored, buf.bytes_mut()) {
            Ok(found) => found,
            // Frames that decode to more than the raw length fail for want of room: that is a
            // decoded length (§7), not corrupt data
            Err(e) => match decoded_len(stored) {
                Some(found) if found > entry.raw_len as u64 => {
                    return Err(FormatError::DecodedLength {
                        section,
                        expected: entry.raw_len as u64,
                        found,
                    })
                }
                _ => return Err(zstd_error(e)),
            },
        };
        if found != entry.raw_len {
            return Err(FormatError::DecodedLength {
                section,
                expected: entry.raw_len as u64,
                found: found as u64,
            });
        }
        decoded.push(Some(buf));
    }
    Ok(decoded)
}

/// The number of bytes the zstd frames `stored` decode to, counted without keeping them (up to
/// 4 GiB); `None` where they do not decode.
fn decoded_len(stored: &[u8]) -> Option<u64> {
    let decoder = zstd::stream::read::Decoder::with_buffer(stored).ok()?;
    let mut counted = std::io::Read::take(decoder, u64::from(u32::MAX));
    std::io::copy(&mut counted, &mut std::io::sink()).ok()
}

fn check_padding(bytes: &[u8], from: usize, to: usize) -> FormatResult<()> {
    let padding = bytes.get(from..to).unwrap_or_default();
    match padding.iter().position(|&b| b != 0) {
        None => Ok(()),
        Some(i) => Err(FormatError::NonZeroPadding {
            offset: (from + i) as u64,
            value: padding[i],
        }),
    }
}

/// A table's required sections, their dims, its axes and (when verifying fully) its values;
/// `required` is the file's required feature bits.
fn check_table<'a>(
    t: usize,
    slot: &TableSlot,
    entries: &[SectionInfo],
    data: &impl Fn(usize) -> &'a [u8],
    verify: Verify,
    required: u64,
) -> FormatResult<()> {
    for &kind in slot.header.required_sections() {
        if !slot.sections.contains_key(&kind.code()) {
            return Err(FormatError::MissingSection {
                kind,
                table: Some(t),
            });
        }
    }
    for (&code, &index) in &slot.sections {
        let Some(kind) = SectionKind::from_code(code) else {
            continue;
        };
        let Some(expected) = slot.header.expected_dims(kind) else {
            continue;
        };
        if entries[index].dims != expected {
            return Err(FormatError::SectionDims {
                table: Some(t),
                kind,
                found: entries[index].dims.clone(),
                expected,
            });
        }
    }
    for axis in [AxisKind::Rho, AxisKind::Theta, AxisKind::R] {
        if let Some(&index) = slot.sections.get(&axis.section().code()) {
            check_axis(t, axis, &f32_values(data(index)))?;
        }
    }
    if verify == Verify::Full {
        check_table_values(t, slot, data, required)?;
    }
    Ok(())
}
