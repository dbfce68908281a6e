//! A library file's layout read leniently from any bytes, laid out again, and its CRCs
//! recomputed: what the structure-aware mutator needs to change a field and still reach the
//! checks behind the header CRC (format-spec.md: header, directory, sections). Nothing here
//! panics, whatever the bytes.

/// Bytes of the header.
pub const HEADER: usize = 128;
/// Bytes of a directory entry.
pub const ENTRY: usize = 64;
/// Offset of the header CRC; it covers the bytes before it and the directory.
pub const HEADER_CRC: usize = 124;
/// Offsets of fields in the header.
pub mod header {
    pub const MAJOR: usize = 12;
    pub const MINOR: usize = 14;
    pub const BYTE_ORDER: usize = 16;
    pub const SECTION_COUNT: usize = 20;
    pub const FILE_SIZE: usize = 24;
    pub const REQUIRED: usize = 32;
    pub const OPTIONAL: usize = 40;
    pub const ALIGNMENT: usize = 48;
    pub const RESERVED: usize = 52;
}
/// Offsets of fields in a directory entry.
pub mod entry {
    pub const KIND: usize = 0;
    pub const TABLE: usize = 4;
    pub const DTYPE: usize = 8;
    pub const CODEC: usize = 10;
    pub const FLAGS: usize = 12;
    pub const NDIM: usize = 14;
    pub const DIMS: usize = 16;
    pub const OFFSET: usize = 32;
    pub const STORED_LEN: usize = 40;
    pub const RAW_LEN: usize = 48;
    pub const CRC: usize = 56;
    pub const RESERVED: usize = 60;
}

/// The little-endian unsigned integer of `width` bytes at `at`, if inside `bytes`.
pub fn get(bytes: &[u8], at: usize, width: usize) -> Option<u64> {
    let field = bytes.get(at..at.checked_add(width)?)?;
    Some(
        field
            .iter()
            .rev()
            .fold(0u64, |acc, &b| (acc << 8) | u64::from(b)),
    )
}

/// Writes the low `width` bytes of `value` little-endian at `at`; nothing outside `bytes`.
pub fn set(bytes: &mut [u8], at: usize, width: usize, value: u64) {
    let Some(field) = at.checked_add(width).and_then(|end| bytes.get_mut(at..end)) else {
        return;
    };
    for (k, b) in field.iter_mut().enumerate() {
        *b = (value >> (8 * k)) as u8;
    }
}

/// Number of directory entries that lie inside the file (at most the declared count).
pub fn entry_count(bytes: &[u8]) -> usize {
    let declared = get(bytes, header::SECTION_COUNT, 4).unwrap_or(0) as usize;
    declared.min(bytes.len().saturating_sub(HEADER) / ENTRY)
}

/// Offset of directory entry `i`.
pub fn entry_at(i: usize) -> usize {
    HEADER + ENTRY * i
}

/// The stored bytes of entry `i`, if its offset and length lie inside the file.
pub fn data_range(bytes: &[u8], i: usize) -> Option<std::ops::Range<usize>> {
    let e = entry_at(i);
    let offset = usize::try_from(get(bytes, e + entry::OFFSET, 8)?).ok()?;
    let len = usize::try_from(get(bytes, e + entry::STORED_LEN, 8)?).ok()?;
    let end = offset.checked_add(len)?;
    (end <= bytes.len()).then_some(offset..end)
}

/// One directory entry and the bytes it points at (empty where they leave the file).
#[derive(Clone, Debug)]
pub struct Section {
    pub entry: [u8; ENTRY],
    pub data: Vec<u8>,
}

impl Section {
    pub fn kind(&self) -> u32 {
        get(&self.entry, entry::KIND, 4).unwrap_or(0) as u32
    }
}

/// The sections of the entries inside the file, in directory order.
pub fn sections(bytes: &[u8]) -> Vec<Section> {
    (0..entry_count(bytes))
        .map(|i| {
            let mut entry = [0u8; ENTRY];
            if let Some(e) = bytes.get(entry_at(i)..entry_at(i) + ENTRY) {
                entry.copy_from_slice(e);
            }
            let data = data_range(bytes, i)
                .and_then(|r| bytes.get(r))
                .unwrap_or_default()
                .to_vec();
            Section { entry, data }
        })
        .collect()
}

/// A file with the header of `bytes` (the first 128 bytes, zero-filled if shorter) and
/// `sections` laid out as the spec lays them out: each at the next multiple of the header's
/// alignment (256 where that is not a power of two from 256 to 65536), zero padding, the
/// entries' offsets and stored lengths, the section count and the file size set, and every
/// CRC computed. Each entry keeps its other fields, raw length included.
pub fn lay_out(bytes: &[u8], sections: &[Section]) -> Vec<u8> {
    let mut file = vec![0u8; HEADER];
    let head = bytes.get(..HEADER.min(bytes.len())).unwrap_or_default();
    file[..head.len()].copy_from_slice(head);
    let alignment = get(&file, header::ALIGNMENT, 4).unwrap_or(0) as usize;
    let alignment = if alignment.is_power_of_two() && (256..=65536).contains(&alignment) {
        alignment
    } else {
        256
    };
    for s in sections {
        file.extend_from_slice(&s.entry);
    }
    for (i, s) in sections.iter().enumerate() {
        let offset = file.len().div_ceil(alignment) * alignment;
        file.resize(offset, 0);
        file.extend_from_slice(&s.data);
        let e = entry_at(i);
        set(&mut file, e + entry::OFFSET, 8, offset as u64);
        set(&mut file, e + entry::STORED_LEN, 8, s.data.len() as u64);
    }
    set(&mut file, header::SECTION_COUNT, 4, sections.len() as u64);
    let size = file.len() as u64;
    set(&mut file, header::FILE_SIZE, 8, size);
    repair_crcs(&mut file);
    file
}

/// Recomputes the CRC of every section that lies inside the file, then the header CRC over
/// the header and the part of the directory inside the file.
pub fn repair_crcs(bytes: &mut [u8]) {
    for i in 0..entry_count(bytes) {
        if let Some(range) = data_range(bytes, i) {
            let crc = crc32fast::hash(&bytes[range]);
            set(bytes, entry_at(i) + entry::CRC, 4, crc.into());
        }
    }
    if bytes.len() < HEADER {
        return;
    }
    let dir_end = entry_at(entry_count(bytes));
    let mut hasher = crc32fast::Hasher::new();
    hasher.update(&bytes[..HEADER_CRC]);
    hasher.update(&bytes[HEADER..dir_end]);
    let crc = hasher.finalize();
    set(bytes, HEADER_CRC, 4, crc.into());
}
