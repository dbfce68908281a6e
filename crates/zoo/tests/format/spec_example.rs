//! The example file of `format-spec.md` is what the writer produces, byte for byte, and it is
//! also committed as `tests/data/valid/spec-example.bssrdf`.
//!
//! To regenerate the hexdump in the spec after a deliberate format change, run
//! `BSSRDF_REGEN_SPEC=1 cargo test -p bssrdf-zoo --test format spec_example` and review the diff.

use std::path::Path;

use bssrdf_zoo::format::spec::VERSION_MINOR;
use bssrdf_zoo::format::{AxisKind, Compression, Library, Verify};

const BEGIN: &str = "<!-- example-hexdump:begin -->\n```text\n";
const END: &str = "```\n<!-- example-hexdump:end -->";

/// Canonical hexdump (the layout of `hexdump -C`): 16 bytes a line, a `*` line for runs of
/// lines equal to the one before, and the total length last.
fn hexdump(bytes: &[u8]) -> String {
    let mut out = String::new();
    let mut previous: Option<&[u8]> = None;
    let mut starred = false;
    for (i, line) in bytes.chunks(16).enumerate() {
        if previous == Some(line) && line.len() == 16 {
            if !starred {
                out.push_str("*\n");
                starred = true;
            }
            continue;
        }
        starred = false;
        previous = Some(line);
        out.push_str(&format!("{:08x} ", i * 16));
        for (j, b) in line.iter().enumerate() {
            out.push_str(if j == 8 { "  " } else { " " });
            out.push_str(&format!("{b:02x}"));
        }
        for j in line.len()..16 {
            out.push_str(if j == 8 { "    " } else { "   " });
        }
        out.push_str("  |");
        for &b in line {
            out.push(if (0x20..0x7f).contains(&b) {
                b as char
            } else {
                '.'
            });
        }
        out.push_str("|\n");
    }
    out.push_str(&format!("{:08x}\n", bytes.len()));
    out
}

fn manifest(path: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

#[test]
fn spec_example_bytes_match_the_writer() {
    let bytes = bssrdf_testkit::files::spec_example_builder()
        .to_bytes(Compression::None)
        .unwrap();
    let dump = hexdump(&bytes);
    let spec_path = manifest("../../format-spec.md");
    let spec = std::fs::read_to_string(&spec_path).unwrap();
    let start = spec.find(BEGIN).expect("begin marker in format-spec.md") + BEGIN.len();
    let end = spec[start..]
        .find(END)
        .expect("end marker in format-spec.md")
        + start;
    let vector = manifest("../../tests/data/valid/spec-example.bssrdf");
    if std::env::var_os("BSSRDF_REGEN_SPEC").is_some() {
        let updated = format!("{}{}{}", &spec[..start], dump, &spec[end..]);
        std::fs::write(&spec_path, updated).unwrap();
        std::fs::create_dir_all(vector.parent().unwrap()).unwrap();
        std::fs::write(&vector, &bytes).unwrap();
        return;
    }
    assert_eq!(
        &spec[start..end],
        dump,
        "format-spec.md example differs from the writer"
    );
    assert_eq!(
        std::fs::read(&vector).unwrap(),
        bytes,
        "{}",
        vector.display()
    );
    // And it reads back as the spec describes it.
    let library = Library::from_bytes(&bytes, Verify::Full).unwrap();
    let table = library.table(0).unwrap();
    assert_eq!(table.axis(AxisKind::R), [0.5, 1.0]);
    assert_eq!(table.gwc_params()[4], 2.0);
    // Both nodes have E_β = 2 > E: negative floors, declared by required feature bit 1.
    assert_eq!(library.version(), (1, VERSION_MINOR));
    assert_eq!(library.required_features(), 1 << 1);
    assert_eq!(library.materials()[0].name, "wax");
}

#[test]
fn hexdump_matches_the_usual_layout() {
    let dump = hexdump(b"\x89BSSRDF\r\n\x1a\n\0\x01\0\0\0ab");
    assert_eq!(
        dump,
        "00000000  89 42 53 53 52 44 46 0d  0a 1a 0a 00 01 00 00 00  |.BSSRDF.........|\n\
         00000010  61 62                                             |ab|\n\
         00000012\n"
    );
}

#[test]
fn the_embedding_layer_opens_every_valid_vector_and_refuses_only_the_lookups_it_cannot_make() {
    use bssrdf_zoo::embed;
    use bssrdf_zoo::format::LibraryBuilder;
    use bssrdf_zoo::materials::Rgb;
    // Every valid conformance vector opens for lookups (the C API and the Python package open
    // files this way); a table no lookup can interpolate refuses its lookups, saying why
    let valid = manifest("../../tests/data/valid");
    let mut without_lookups = 0;
    for entry in std::fs::read_dir(&valid).unwrap() {
        let path = entry.unwrap().path();
        let library =
            embed::Library::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let count = library.format().table_count();
        assert_eq!(library.table_count(), count);
        for index in 0..count {
            if let Err(e) = library.table(index) {
                assert!(e.to_string().contains("(the file itself is valid)"), "{e}");
                assert!(library.view(index).is_err());
                without_lookups += 1;
            }
        }
        let refused = count - library.tables().count();
        assert!(library.tables().all(|t| library.table(t.index()).is_ok()));
        assert_eq!(
            refused,
            (0..count).filter(|&i| library.table(i).is_err()).count()
        );
    }
    assert!(
        without_lookups >= 2,
        "spec-example and aligned-4096 have one albedo node"
    );
    // The spec's example: one albedo node; its material's channels refuse with the reason
    let library = embed::Library::read(valid.join("spec-example.bssrdf")).unwrap();
    let reason = "table 0: axis rho has 1 node(s): lookups interpolate along every axis and \
                  need at least 2 (the file itself is valid)";
    assert_eq!(library.table(0).unwrap_err().to_string(), reason);
    assert_eq!(library.tables().count(), 0);
    let channel = library.channel("wax", Rgb::Red).unwrap_err().to_string();
    assert_eq!(channel, reason);
    // A table of η outside the lookups' [0.75, 2.5], which the format allows
    let mut builder = LibraryBuilder::new();
    builder
        .add_table(bssrdf_testkit::files::synthetic_table(3.0, 2, 2, 4, true))
        .unwrap();
    builder
        .add_table(bssrdf_testkit::files::synthetic_table(1.3, 2, 2, 4, true))
        .unwrap();
    let file =
        Library::from_bytes(&builder.to_bytes(Compression::None).unwrap(), Verify::Full).unwrap();
    let library = embed::Library::from_format(file).unwrap();
    assert_eq!(
        library.table(0).unwrap_err().to_string(),
        "table 0: eta = 3 is outside [0.75, 2.5]"
    );
    assert_eq!(library.table(1).unwrap().eta(), 1.3);
    assert_eq!(library.tables().map(|t| t.index()).collect::<Vec<_>>(), [1]);
}
