//! Structure-aware changes to a library file: a header or directory field, a field of a table
//! or material record, a value of a table section, or the directory itself (an entry reshaped
//! with its data, removed, duplicated, moved, given to another table), each set to a value
//! chosen to meet the reader's checks at their edges. The caller repairs the CRCs afterwards
//! ([`crate::layout::repair_crcs`]), so each change reaches the check it aims at instead of
//! the header CRC. Nothing here panics, whatever the bytes.

use bssrdf_zoo::rng::{RngCore, SplitMix64};

use crate::layout::{
    data_range, entry, entry_at, entry_count, get, header, lay_out, sections, set,
};

/// Section kind codes of format 1.1, and two extension codes (optional and required).
const KINDS: [u64; 11] = [
    0x01, 0x02, 0x03, 0x10, 0x11, 0x12, 0x20, 0x21, 0x22, 0x7001, 0x8001,
];
const TABLES_KIND: u32 = 0x01;
const MATERIALS_KIND: u32 = 0x02;

/// Bytes of a table record and a material record.
const TABLE_RECORD: usize = 64;
const MATERIAL_RECORD: usize = 512;

/// (offset, width) of the integer fields of a table record: model, fresnel, nρ, nθ, nr, the
/// u32 at 28 (a pbd-angular record's `ridge`, a walk-angular one's component), the one at 40
/// (a walk-angular record's `ridge`), and a reserved byte; its η (f64) is at 8.
const TABLE_INTS: [(usize, usize); 8] = [
    (0, 4),
    (4, 4),
    (16, 4),
    (20, 4),
    (24, 4),
    (28, 4),
    (40, 4),
    (44, 1),
];
/// (offset, width) of the integer fields of a material record: name and source lengths, three
/// table indices, flags, a reserved byte.
const MATERIAL_INTS: [(usize, usize); 7] =
    [(0, 4), (4, 4), (8, 4), (12, 4), (16, 4), (20, 4), (152, 1)];
/// Offsets of the f64 fields of a material record: σs, σa, g (three each), η, albedo ranges.
const MATERIAL_FLOATS: [usize; 16] = [
    24, 32, 40, 48, 56, 64, 72, 80, 88, 96, 104, 112, 120, 128, 136, 144,
];

fn pick<T: Copy>(rng: &mut SplitMix64, items: &[T]) -> T {
    items[(rng.next_u64() % items.len() as u64) as usize]
}

fn below(rng: &mut SplitMix64, n: usize) -> usize {
    if n == 0 {
        0
    } else {
        (rng.next_u64() % n as u64) as usize
    }
}

/// An integer for a field of `width` bytes now holding `current` in a file of `len` bytes:
/// an edge of a cap or of the width, the file's size, a neighbour of the current value, or
/// anything.
fn integer(rng: &mut SplitMix64, width: usize, current: u64, len: u64) -> u64 {
    let max = if width >= 8 {
        u64::MAX
    } else {
        (1u64 << (8 * width)) - 1
    };
    let edges = [
        0,
        1,
        2,
        3,
        4,
        5,
        63,
        64,
        255,
        256,
        257,
        511,
        512,
        4095,
        4096,
        65535,
        65536,
        65537,
        1 << 20,
        (1 << 30) - 1,
        1 << 30,
        (1 << 30) + 1,
        1 << 31,
        u32::MAX as u64 - 1,
        u32::MAX as u64,
        1 << 32,
        1 << 63,
        u64::MAX,
    ];
    let value = match rng.next_u64() % 8 {
        0 | 1 => pick(rng, &edges),
        2 => pick(
            rng,
            &[len, len.wrapping_sub(1), len + 1, len + 256, len / 2],
        ),
        3 => current.wrapping_add(pick(rng, &[1, 2, 4, 8, 64, 256, 4096])),
        4 => current.wrapping_sub(pick(rng, &[1, 2, 4, 8, 64, 256, 4096])),
        5 => current ^ (1 << (rng.next_u64() % (8 * width as u64))),
        _ => rng.next_u64(),
    };
    value & max
}

/// A float meant for a field that holds `current`: NaN, ±∞, ±0, subnormals, the ends of the
/// ranges the reader checks (η, g, albedos, angles), a neighbour or negation of `current`.
fn float(rng: &mut SplitMix64, current: f64) -> f64 {
    let specials = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        0.0,
        -0.0,
        5e-324,
        f64::MIN_POSITIVE,
        1e-300,
        f32::MIN_POSITIVE as f64,
        1e-45,
        -1.0,
        0.5,
        1.0,
        1.0 - 1e-16,
        1.0 + 1e-15,
        0.75,
        0.749_999_999,
        2.5,
        2.500_000_1,
        std::f64::consts::FRAC_PI_2,
        std::f64::consts::FRAC_PI_2 + 1e-6,
        std::f64::consts::PI,
        f32::MAX as f64,
        3.5e38,
        f64::MAX,
        1e12,
    ];
    match rng.next_u64() % 4 {
        0 | 1 => pick(rng, &specials),
        2 => pick(
            rng,
            &[
                -current,
                current * (1.0 + 1e-7),
                current * (1.0 - 1e-7),
                2.0 * current,
            ],
        ),
        _ => f64::from_bits(rng.next_u64()),
    }
}

/// Positions of the records of the first section of `kind`, each `size` bytes.
fn records(file: &[u8], kind: u32, size: usize) -> Vec<usize> {
    let Some(i) =
        (0..entry_count(file)).find(|&i| get(file, entry_at(i), 4) == Some(u64::from(kind)))
    else {
        return Vec::new();
    };
    data_range(file, i)
        .map(|r| {
            r.clone()
                .step_by(size)
                .filter(|&at| at + size <= r.end)
                .collect()
        })
        .unwrap_or_default()
}

/// Changes one header field.
fn header_field(file: &mut [u8], rng: &mut SplitMix64) {
    let fields = [
        (header::MAJOR, 2),
        (header::MINOR, 2),
        (header::BYTE_ORDER, 4),
        (header::SECTION_COUNT, 4),
        (header::FILE_SIZE, 8),
        (header::REQUIRED, 8),
        (header::OPTIONAL, 8),
        (header::ALIGNMENT, 4),
        (header::RESERVED + below(rng, 72), 1),
    ];
    let (at, width) = pick(rng, &fields);
    let current = get(file, at, width).unwrap_or(0);
    let value = match (at, rng.next_u64() % 2) {
        (header::REQUIRED | header::OPTIONAL, 0) => current ^ (1 << (rng.next_u64() % 64)),
        (header::ALIGNMENT, 0) => 1 << (rng.next_u64() % 20),
        _ => integer(rng, width, current, file.len() as u64),
    };
    set(file, at, width, value);
}

/// Changes one field of one directory entry.
fn entry_field(file: &mut [u8], rng: &mut SplitMix64) {
    let count = entry_count(file);
    if count == 0 {
        return header_field(file, rng);
    }
    let e = entry_at(below(rng, count));
    let fields = [
        (entry::KIND, 4),
        (entry::TABLE, 4),
        (entry::DTYPE, 2),
        (entry::CODEC, 2),
        (entry::FLAGS, 2),
        (entry::NDIM, 2),
        (entry::DIMS + 4 * below(rng, 4), 4),
        (entry::OFFSET, 8),
        (entry::STORED_LEN, 8),
        (entry::RAW_LEN, 8),
        (entry::RESERVED + below(rng, 4), 1),
    ];
    let (at, width) = pick(rng, &fields);
    let current = get(file, e + at, width).unwrap_or(0);
    let other = entry_at(below(rng, count));
    let value = match (at, rng.next_u64() % 3) {
        (entry::KIND, 0) => pick(rng, &KINDS),
        (entry::TABLE, 0) => pick(rng, &[0, 1, 2, u32::MAX as u64, u32::MAX as u64 - 1]),
        (entry::DTYPE | entry::CODEC | entry::FLAGS, 0) => pick(rng, &[0, 1, 2, 3, 0x8000, 0x8001]),
        (entry::NDIM, 0) => below(rng, 6) as u64,
        // Another section's place or end: overlaps, gaps, order.
        (entry::OFFSET, 0) => {
            let (o, n) = (
                get(file, other + entry::OFFSET, 8),
                get(file, other + entry::STORED_LEN, 8),
            );
            let (o, n) = (o.unwrap_or(0), n.unwrap_or(0));
            pick(
                rng,
                &[
                    o,
                    o.wrapping_add(n),
                    o.wrapping_add(n).div_ceil(256) * 256,
                    o + 256,
                ],
            )
        }
        // A length one element off, or the other length of the entry.
        (entry::STORED_LEN | entry::RAW_LEN, 0) => {
            let raw = get(file, e + entry::RAW_LEN, 8).unwrap_or(0);
            let stored = get(file, e + entry::STORED_LEN, 8).unwrap_or(0);
            pick(
                rng,
                &[
                    raw,
                    stored,
                    current + 4,
                    current.wrapping_sub(4),
                    current / 2,
                ],
            )
        }
        _ => integer(rng, width, current, file.len() as u64),
    };
    set(file, e + at, width, value);
}

/// Changes one field of a table or material record.
fn record_field(file: &mut [u8], rng: &mut SplitMix64) {
    let tables = records(file, TABLES_KIND, TABLE_RECORD);
    let materials = records(file, MATERIALS_KIND, MATERIAL_RECORD);
    let use_tables = rng.next_u64().is_multiple_of(2);
    let (list, ints, floats): (&[usize], &[(usize, usize)], &[usize]) =
        if use_tables && !tables.is_empty() || materials.is_empty() {
            (&tables, &TABLE_INTS, &[8])
        } else {
            (&materials, &MATERIAL_INTS, &MATERIAL_FLOATS)
        };
    if list.is_empty() {
        return entry_field(file, rng);
    }
    let record = pick(rng, list);
    if rng.next_u64().is_multiple_of(2) {
        let at = record + pick(rng, floats);
        let current = get(file, at, 8).map_or(0.0, f64::from_bits);
        set(file, at, 8, float(rng, current).to_bits());
    } else {
        let (at, width) = pick(rng, ints);
        let current = get(file, record + at, width).unwrap_or(0);
        let value = integer(rng, width, current, 64);
        set(file, record + at, width, value);
    }
}

/// Changes one f32 value of a table section (an axis, GWC parameters, a CDF): a special float,
/// or its neighbour's value (an axis no longer increasing), or a nudge.
fn table_value(file: &mut [u8], rng: &mut SplitMix64) {
    let candidates: Vec<std::ops::Range<usize>> = (0..entry_count(file))
        .filter(|&i| (0x10..=0x22).contains(&get(file, entry_at(i), 4).unwrap_or(0)))
        .filter_map(|i| data_range(file, i))
        .filter(|r| r.len() >= 4)
        .collect();
    if candidates.is_empty() {
        return record_field(file, rng);
    }
    let range = &candidates[below(rng, candidates.len())];
    let at = range.start + 4 * below(rng, range.len() / 4);
    let current = get(file, at, 4).map_or(0.0, |b| f32::from_bits(b as u32));
    let value = match rng.next_u64() % 4 {
        0 if at >= range.start + 4 => {
            get(file, at - 4, 4).map_or(0.0, |b| f32::from_bits(b as u32))
        }
        1 => f32::from_bits(current.to_bits().wrapping_add(pick(rng, &[1, u32::MAX]))),
        _ => float(rng, f64::from(current)) as f32,
    };
    set(file, at, 4, u64::from(value.to_bits()));
}

/// Changes the directory and lays the file out again: an entry reshaped with its data (new
/// dims, raw length to match, data cut or grown), removed, duplicated, moved, or given to
/// another table; or the alignment changed.
fn directory(file: &mut Vec<u8>, rng: &mut SplitMix64) {
    let mut list = sections(file);
    let n = list.len();
    match rng.next_u64() % 6 {
        0 if n > 0 => {
            let s = &mut list[below(rng, n)];
            let ndim = 1 + below(rng, 4);
            let element: usize = if get(&s.entry, entry::DTYPE, 2) == Some(1) {
                1
            } else {
                4
            };
            let mut count = element;
            for d in 0..4 {
                let dim = if d < ndim {
                    let current = get(&s.entry, entry::DIMS + 4 * d, 4).unwrap_or(1);
                    pick(
                        rng,
                        &[
                            0,
                            1,
                            2,
                            3,
                            current,
                            current + 1,
                            current.saturating_sub(1),
                            64,
                            512,
                        ],
                    )
                } else {
                    0
                };
                set(&mut s.entry, entry::DIMS + 4 * d, 4, dim);
                count = count.saturating_mul(dim as usize);
            }
            // Keep the fuzzer's inputs small: files up to 256 KiB.
            let count = count.min(1 << 18);
            set(&mut s.entry, entry::NDIM, 2, ndim as u64);
            set(&mut s.entry, entry::RAW_LEN, 8, count as u64);
            let fill = s.data.last().copied().unwrap_or(0);
            s.data.resize(count, fill);
        }
        1 if n > 0 => {
            list.remove(below(rng, n));
        }
        2 if n > 0 => {
            let s = list[below(rng, n)].clone();
            list.insert(below(rng, n + 1), s);
        }
        3 if n > 1 => {
            let (a, b) = (below(rng, n), below(rng, n));
            list.swap(a, b);
        }
        4 if n > 0 => {
            let s = &mut list[below(rng, n)];
            let table = pick(rng, &[0, 1, 2, u32::MAX as u64]);
            set(&mut s.entry, entry::TABLE, 4, table);
        }
        _ => {
            let alignment = pick(rng, &[256, 512, 4096, 65536, 128, 300]);
            set(file, header::ALIGNMENT, 4, alignment);
        }
    }
    *file = lay_out(file, &list);
}

/// One structure-aware change to `file`, chosen by `rng` (CRCs not yet repaired).
pub fn mutate(file: &mut Vec<u8>, rng: &mut SplitMix64) {
    match rng.next_u64() % 10 {
        0 | 1 => header_field(file, rng),
        2..=4 => entry_field(file, rng),
        5 | 6 => record_field(file, rng),
        7 => table_value(file, rng),
        _ => directory(file, rng),
    }
}
