//! `include/bssrdf_zoo.h` is written by hand; this test holds it to `crates/capi/src/lib.rs`
//! with its modules `media.rs`, `separable.rs`, `batch.rs` and `reflectance.rs`:
//! the same functions with the same parameter and return types (Rust types mapped to C ones),
//! the same structs with the same fields in the same order, the same opaque types, and the same
//! constants with the same values. Every exported function must be `#[no_mangle]`. The C test
//! (`crates/capi/tests/capi/c_program.rs`) then compiles against the header with `-Wall -Werror` and links.

use std::collections::BTreeMap;

const HEADER: &str = include_str!("../../../../include/bssrdf_zoo.h");
const RUST: &str = concat!(
    include_str!("../../src/lib.rs"),
    include_str!("../../src/media.rs"),
    include_str!("../../src/separable.rs"),
    include_str!("../../src/batch.rs"),
    include_str!("../../src/reflectance.rs")
);

/// A signature as C spells its types with the spaces removed: return type, parameter types.
type Signature = (String, Vec<String>);

/// Removes `/* … */` comments and preprocessor lines.
fn strip_c(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(start) = rest.find("/*") {
        out.push_str(&rest[..start]);
        let end = rest[start..].find("*/").expect("unterminated comment") + start + 2;
        rest = &rest[end..];
    }
    out.push_str(rest);
    out.lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n")
}

fn squash(s: &str) -> String {
    s.split_whitespace().collect()
}

/// A C parameter without its name: `const double *u` → `constdouble*`.
fn c_param_type(param: &str) -> String {
    let param = param.trim();
    let cut = param
        .rfind(|c: char| !(c.is_alphanumeric() || c == '_'))
        .map_or(0, |i| i + 1);
    squash(&param[..cut])
}

fn header_functions(c: &str) -> BTreeMap<String, Signature> {
    let mut functions = BTreeMap::new();
    for declaration in c.split(';') {
        let Some(open) = declaration.find('(') else {
            continue;
        };
        if declaration.contains('{') || declaration.contains("typedef") {
            continue;
        }
        let head = declaration[..open].trim();
        let name_at = head
            .rfind(|c: char| !(c.is_alphanumeric() || c == '_'))
            .map_or(0, |i| i + 1);
        let name = &head[name_at..];
        if !name.starts_with("bssrdf_") {
            continue;
        }
        let close = declaration.rfind(')').expect("unclosed parameter list");
        let params = declaration[open + 1..close].trim();
        let params = if params == "void" {
            Vec::new()
        } else {
            params.split(',').map(c_param_type).collect()
        };
        let previous = functions.insert(name.to_owned(), (squash(&head[..name_at]), params));
        assert!(previous.is_none(), "{name} declared twice in the header");
    }
    functions
}

/// A Rust FFI type in C spelling, spaces removed: `*mut *const c_char` → `constchar**`.
fn c_of_rust(ty: &str) -> String {
    let mut ty = ty.trim();
    let mut pointers = Vec::new();
    while let Some((kind, rest)) = ty
        .strip_prefix("*const ")
        .map(|r| ("const", r))
        .or_else(|| ty.strip_prefix("*mut ").map(|r| ("mut", r)))
    {
        pointers.push(kind);
        ty = rest.trim();
    }
    let base = match ty {
        "c_char" => "char",
        "c_int" => "int",
        "f64" => "double",
        "u32" => "uint32_t",
        "usize" => "size_t",
        "" => "void",
        other if other.starts_with("bssrdf_") => other,
        other => panic!("no C spelling for Rust type {other:?}"),
    };
    // Only the pointee of the innermost pointer may be const (no `T *const *` in this API).
    for outer in pointers.iter().take(pointers.len().saturating_sub(1)) {
        assert_eq!(*outer, "mut", "a const pointer to a pointer: {ty}");
    }
    let constness = if pointers.last() == Some(&"const") {
        "const"
    } else {
        ""
    };
    format!("{constness}{base}{}", "*".repeat(pointers.len()))
}

fn rust_functions(rust: &str) -> BTreeMap<String, Signature> {
    let mut functions = BTreeMap::new();
    let mut rest = rust;
    while let Some(at) = rest.find("extern \"C\" fn ") {
        let before = &rest[..at];
        assert!(
            before.trim_end().ends_with("pub unsafe") || before.trim_end().ends_with("pub"),
            "an extern function that is not pub"
        );
        let attributes = before.rsplit("\n}\n").next().unwrap_or_default();
        let after = &rest[at + "extern \"C\" fn ".len()..];
        let open = after.find('(').unwrap();
        let name = after[..open].trim().to_owned();
        assert!(
            attributes.contains("#[no_mangle]"),
            "{name} is not #[no_mangle]"
        );
        let close = after.find(')').unwrap();
        let params = after[open + 1..close]
            .split(',')
            .filter(|p| !p.trim().is_empty())
            .map(|p| c_of_rust(p.split_once(':').expect("name: type").1))
            .collect();
        let brace = after.find('{').unwrap();
        let ret = after[close + 1..brace].trim().trim_start_matches("->");
        functions.insert(name, (c_of_rust(ret), params));
        rest = &after[brace..];
    }
    functions
}

#[test]
fn the_header_declares_exactly_the_exported_functions_with_their_types() {
    let header = header_functions(&strip_c(HEADER));
    let rust = rust_functions(RUST);
    assert!(rust.len() >= 17, "found only {} Rust exports", rust.len());
    for (name, signature) in &rust {
        assert_eq!(header.get(name), Some(signature), "{name}: header vs Rust");
    }
    let extra: Vec<_> = header.keys().filter(|k| !rust.contains_key(*k)).collect();
    assert!(
        extra.is_empty(),
        "declared in the header, not exported: {extra:?}"
    );
}

#[test]
fn the_header_structs_match_the_repr_c_structs_field_by_field() {
    let c = strip_c(HEADER);
    let mut checked = 0;
    for block in c.split("typedef struct ").skip(1) {
        let name: String = block
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let Some(body) = block
            .split_once('{')
            .map(|(_, b)| b.split('}').next().unwrap())
        else {
            // Opaque: `typedef struct x x;` and a Rust struct without repr(C).
            let rust = RUST.split(&format!("pub struct {name} {{")).next().unwrap();
            assert!(
                RUST.contains(&format!("pub struct {name} {{")),
                "opaque {name} missing"
            );
            assert!(
                !rust.trim_end().ends_with("#[repr(C)]"),
                "opaque {name} is repr(C)"
            );
            continue;
        };
        let c_fields: Vec<String> = body
            .split(';')
            .filter(|f| !f.trim().is_empty())
            .map(squash)
            .collect();
        let rust_body = RUST
            .split(&format!("pub struct {name} {{"))
            .nth(1)
            .unwrap_or_else(|| panic!("no Rust struct {name}"))
            .split("\n}")
            .next()
            .unwrap();
        let rust_prefix = RUST.split(&format!("pub struct {name} {{")).next().unwrap();
        let attributes = rust_prefix.rsplit("\n\n").next().unwrap();
        assert!(
            attributes.contains("#[repr(C)]"),
            "{name} is not #[repr(C)]"
        );
        let rust_fields: Vec<String> = rust_body
            .lines()
            .map(str::trim)
            .filter_map(|l| l.strip_prefix("pub "))
            .map(|l| {
                let (field, ty) = l.trim_end_matches(',').split_once(':').unwrap();
                format!("{}{}", c_of_rust(ty), field.trim())
            })
            .collect();
        assert_eq!(c_fields, rust_fields, "fields of {name}");
        checked += 1;
    }
    assert_eq!(
        checked, 5,
        "bssrdf_sample, bssrdf_radial_sample, bssrdf_path_sample, bssrdf_channel_info, bssrdf_table_info"
    );
}

#[test]
fn the_header_constants_have_the_rust_values() {
    let defines: BTreeMap<&str, &str> = HEADER
        .lines()
        .filter_map(|l| l.strip_prefix("#define BSSRDF_"))
        .filter_map(|l| l.split_once(' '))
        .filter(|(name, _)| !name.ends_with("_H"))
        .map(|(name, value)| (name, value.trim().trim_end_matches('u')))
        .collect();
    let consts: BTreeMap<&str, &str> = RUST
        .lines()
        .filter_map(|l| l.strip_prefix("pub const BSSRDF_"))
        .filter_map(|l| {
            let (name, rest) = l.split_once(':')?;
            Some((name, rest.split_once('=')?.1.trim().trim_end_matches(';')))
        })
        .collect();
    assert!(consts.len() >= 11, "{consts:?}");
    assert_eq!(defines, consts);
}
