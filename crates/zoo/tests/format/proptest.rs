//! The parser never panics: arbitrary bytes, and valid files with random damage, either open
//! or give an error. (The cargo-fuzz target in `fuzz/` explores further; this runs in the
//! normal suite, with proptest's fixed default seed handling and case counts.)

use bssrdf_zoo::format::{Compression, Library, Verify};
use proptest::prelude::*;

fn valid_files() -> Vec<Vec<u8>> {
    vec![
        bssrdf_testkit::files::tiny_builder()
            .to_bytes(Compression::None)
            .unwrap(),
        bssrdf_testkit::files::tiny_builder()
            .to_bytes(Compression::Zstd { level: 1 })
            .unwrap(),
        bssrdf_testkit::files::spec_example_builder()
            .to_bytes(Compression::None)
            .unwrap(),
    ]
}

/// Opens both ways; when a file opens, reads everything it exposes.
fn exercise(bytes: &[u8]) {
    for verify in [Verify::Full, Verify::HeaderOnly] {
        if let Ok(library) = Library::from_bytes(bytes, verify) {
            for table in library.tables() {
                let _ = (table.gwc_params().len(), table.radial_cdf().len());
                let _ = table.theta_cdf();
            }
            let _ = (library.materials().len(), library.provenance());
            let _ = library.verify();
        }
    }
}

/// One kind of damage to a valid file.
#[derive(Debug, Clone)]
enum Damage {
    Set {
        at: usize,
        value: u8,
    },
    Truncate {
        len: usize,
    },
    Insert {
        at: usize,
        bytes: Vec<u8>,
    },
    /// Overwrite a little-endian u32 or u64 field with an extreme value.
    Field {
        at: usize,
        wide: bool,
        value: u64,
    },
}

fn damage() -> impl Strategy<Value = Damage> {
    let extremes = prop_oneof![
        Just(0u64),
        Just(1),
        Just(255),
        Just(256),
        Just(u32::MAX as u64),
        Just(u64::MAX),
        Just(1 << 31),
        Just(1 << 63),
        any::<u64>(),
    ];
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(at, value)| Damage::Set { at, value }),
        any::<usize>().prop_map(|len| Damage::Truncate { len }),
        (any::<usize>(), prop::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(at, bytes)| Damage::Insert { at, bytes }),
        (any::<usize>(), any::<bool>(), extremes).prop_map(|(at, wide, value)| Damage::Field {
            at,
            wide,
            value
        }),
    ]
}

fn apply(bytes: &mut Vec<u8>, d: &Damage) {
    let n = bytes.len();
    if n == 0 {
        // An earlier truncation emptied the file: only insertions still apply.
        if let Damage::Insert { bytes: b, .. } = d {
            bytes.extend_from_slice(b);
        }
        return;
    }
    match d {
        Damage::Set { at, value } => bytes[at % n] = *value,
        Damage::Truncate { len } => bytes.truncate(len % n),
        Damage::Insert { at, bytes: b } => {
            let at = at % n;
            bytes.splice(at..at, b.iter().copied());
        }
        Damage::Field { at, wide, value } => {
            let w = if *wide { 8 } else { 4 };
            // Aligned to the field width, and within the header and directory mostly.
            let at = (at % n.min(1024)) / w * w;
            if at + w <= n {
                bytes[at..at + w].copy_from_slice(&value.to_le_bytes()[..w]);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..4096)) {
        exercise(&bytes);
    }

    #[test]
    fn arbitrary_bytes_after_a_valid_header_never_panic(
        tail in prop::collection::vec(any::<u8>(), 0..2048),
        count in 0u32..16,
    ) {
        let mut bytes = valid_files()[2][..128].to_vec();
        bytes[20..24].copy_from_slice(&count.to_le_bytes());
        bytes.extend(tail);
        let len = bytes.len() as u64;
        bytes[24..32].copy_from_slice(&len.to_le_bytes());
        exercise(&bytes);
    }

    #[test]
    fn damaged_valid_files_never_panic(
        file in 0usize..3,
        damages in prop::collection::vec(damage(), 1..4),
        fix_crcs in any::<bool>(),
    ) {
        let mut raw = bssrdf_testkit::files::Raw::new(valid_files()[file].clone());
        for d in &damages {
            apply(&mut raw.bytes, d);
        }
        if fix_crcs && raw.bytes.len() >= 128 {
            // Past the CRCs, so the structural and record checks see the damage.
            raw.fix_crcs();
        }
        exercise(&raw.bytes);
    }
}
