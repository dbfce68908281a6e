//! The format tests: one test binary, a module per area.

mod c_reader;
mod conformance;
mod corruption;
mod harmonics;
mod mapping;
mod proptest;
mod ridge;
mod roundtrip;
mod spec_example;
mod walk;

use bssrdf_testkit::files::Raw;
use bssrdf_zoo::format::{Compression, Library, LibraryBuilder, Verify};

/// A file every reader must reject with `code`, its message naming `needle`: by a full open and
/// by a header-only one (record checks are never deferred).
pub(crate) fn assert_rejected(case: &str, raw: &Raw, code: &str, needle: &str) {
    for verify in [Verify::Full, Verify::HeaderOnly] {
        assert_rejected_by(case, raw, verify, code, needle);
    }
}

/// A file an open with `verify` rejects with `code`, its message naming `needle`.
pub(crate) fn assert_rejected_by(case: &str, raw: &Raw, verify: Verify, code: &str, needle: &str) {
    let err = match Library::from_bytes(&raw.bytes, verify) {
        Ok(_) => panic!("{case}: accepted, expected {code}"),
        Err(e) => e,
    };
    assert_eq!(err.code(), code, "{case}: {err}");
    let message = err.to_string();
    assert!(
        message.contains(needle),
        "{case}: {message:?} lacks {needle:?}"
    );
}

/// A file every reader must accept, verified in full.
pub(crate) fn assert_accepted(case: &str, raw: &Raw) -> Library {
    let library =
        Library::from_bytes(&raw.bytes, Verify::Full).unwrap_or_else(|e| panic!("{case}: {e}"));
    library.verify().unwrap();
    library
}

/// The required feature bits of the file `builder` writes (uncompressed), as read back.
pub(crate) fn written_features(builder: &LibraryBuilder) -> u64 {
    Library::from_bytes(&builder.to_bytes(Compression::None).unwrap(), Verify::Full)
        .unwrap()
        .required_features()
}
