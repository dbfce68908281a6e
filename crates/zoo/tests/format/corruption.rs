//! Damage to a small library file is always detected at open with full verification: every
//! single-byte change at every position, every truncation, any trailing bytes.

use bssrdf_testkit::files::tiny_builder;
use bssrdf_zoo::format::{Compression, Library, Verify};

#[test]
fn every_single_byte_change_is_detected_at_open() {
    let by_code = every_byte_change(Compression::None);
    // The detection is spread over structure and CRC checks, not one catch-all.
    for code in ["bad-magic", "header-crc", "section-crc", "non-zero-padding"] {
        assert!(
            by_code.contains_key(code),
            "{code} never fired: {by_code:?}"
        );
    }
}

#[test]
fn every_single_byte_change_of_a_packed_file_is_detected_at_open() {
    every_byte_change(Compression::Zstd { level: 3 });
}

/// Changes each byte to each of its 255 other values and opens; returns how often each error
/// fired.
fn every_byte_change(compression: Compression) -> std::collections::BTreeMap<&'static str, usize> {
    let original = tiny_builder().to_bytes(compression).unwrap();
    assert!(
        original.len() <= 4096,
        "tiny file is {} bytes",
        original.len()
    );
    Library::from_bytes(&original, Verify::Full).unwrap();
    let mut bytes = original.clone();
    let mut by_code = std::collections::BTreeMap::<&str, usize>::new();
    for position in 0..original.len() {
        // Every other value of the byte: CRC-32 detects any error confined to 32 bits, and
        // the bytes no CRC covers (padding, the CRC fields) are checked structurally.
        for delta in 1..=255u8 {
            bytes[position] = original[position].wrapping_add(delta);
            match Library::from_bytes(&bytes, Verify::Full) {
                Ok(_) => panic!(
                    "byte {position} changed from {:#04x} to {:#04x} was not detected",
                    original[position], bytes[position]
                ),
                Err(e) => *by_code.entry(e.code()).or_default() += 1,
            }
        }
        bytes[position] = original[position];
    }
    by_code
}

#[test]
fn every_truncation_is_rejected() {
    for compression in [Compression::None, Compression::Zstd { level: 3 }] {
        let bytes = tiny_builder().to_bytes(compression).unwrap();
        for len in 0..bytes.len() {
            let err = Library::from_bytes(&bytes[..len], Verify::HeaderOnly)
                .expect_err("truncated file accepted");
            let expected = match len {
                0..=127 => "too-short",
                _ => "truncated",
            };
            assert_eq!(err.code(), expected, "length {len}: {err}");
        }
    }
}

#[test]
fn trailing_bytes_are_rejected() {
    let bytes = tiny_builder().to_bytes(Compression::None).unwrap();
    for extra in [1usize, 3, 255, 256, 4096] {
        for fill in [0u8, 0xAB] {
            let mut longer = bytes.clone();
            longer.resize(bytes.len() + extra, fill);
            let err = Library::from_bytes(&longer, Verify::HeaderOnly).unwrap_err();
            assert_eq!(
                err.code(),
                "trailing-bytes",
                "{extra} bytes of {fill:#x}: {err}"
            );
        }
    }
}

#[test]
fn truncation_and_trailing_bytes_are_rejected_on_disk_both_ways() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = tiny_builder().to_bytes(Compression::None).unwrap();
    let path = dir.path().join("x.bssrdf");
    for (content, code) in [
        (&bytes[..bytes.len() - 1], "truncated"),
        (&bytes[..10], "too-short"),
        (&[][..], "too-short"),
    ] {
        std::fs::write(&path, content).unwrap();
        for open in [Library::open_mmap, Library::read] {
            let err = open(path.as_path(), Verify::Full).unwrap_err();
            assert_eq!(err.code(), code, "{err}");
        }
    }
    let mut longer = bytes.clone();
    longer.push(0);
    std::fs::write(&path, &longer).unwrap();
    let err = Library::open_mmap(&path, Verify::Full).unwrap_err();
    assert_eq!(err.code(), "trailing-bytes");
    let err = Library::read(dir.path().join("missing"), Verify::Full).unwrap_err();
    assert_eq!(err.code(), "io");
    assert!(err.to_string().contains("missing"), "{err}");
}

#[test]
fn extreme_dims_and_offsets_give_errors_not_overflows() {
    let original =
        bssrdf_testkit::files::Raw::new(tiny_builder().to_bytes(Compression::None).unwrap());
    let gwc = original.entry(original.find(bssrdf_testkit::files::kind::GWC, 0));
    type Edit<'a> = &'a dyn Fn(&mut bssrdf_testkit::files::Raw);
    let cases: [(&str, Edit); 3] = [
        ("section-too-large", &|r| {
            for d in 0..4 {
                r.set_u32(gwc + 16 + 4 * d, u32::MAX);
            }
        }),
        ("misaligned-section", &|r| r.set_u64(gwc + 32, u64::MAX)),
        ("section-out-of-bounds", &|r| {
            let last = r.entry(r.section_count() - 1);
            r.set_u64(last + 40, u64::MAX - 255);
            r.set_u16(last + 10, 1); // zstd, so stored and raw lengths may differ
            r.set_u64(32, 1);
        }),
    ];
    for (code, make) in cases {
        let mut raw = original.clone();
        make(&mut raw);
        raw.fix_crcs();
        let err = Library::from_bytes(&raw.bytes, Verify::Full).unwrap_err();
        assert_eq!(err.code(), code, "{err}");
    }
}
