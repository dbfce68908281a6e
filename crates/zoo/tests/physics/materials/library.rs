//! The built-in materials against the reference table (`tests/data/measured-media.csv`, see
//! `tests/data/README.md`), lookups and suggestions, and loading a user's files.

use bssrdf_zoo::materials::{Coefficients, Library, Material, MaterialError, Origin, Rgb};
use std::path::{Path, PathBuf};

const REFERENCE: &str = include_str!("../../../../../tests/data/measured-media.csv");

/// One row of the reference table, by column name.
struct Row {
    fields: Vec<(String, String)>,
}

impl Row {
    fn text(&self, column: &str) -> &str {
        let found = self.fields.iter().find(|(name, _)| name == column);
        &found.unwrap_or_else(|| panic!("no column {column}")).1
    }
    fn number(&self, column: &str) -> f64 {
        self.text(column).parse().unwrap()
    }
    fn rgb(&self, prefix: &str) -> [f64; 3] {
        ["r", "g", "b"].map(|c| self.number(&format!("{prefix}_{c}")))
    }
}

fn reference_rows() -> Vec<Row> {
    let mut lines = REFERENCE.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .filter(|line| !line.trim().is_empty())
        .map(|line| {
            let values: Vec<&str> = line.split(',').collect();
            assert_eq!(values.len(), header.len(), "{line}");
            let fields = header.iter().zip(values);
            Row {
                fields: fields
                    .map(|(h, v)| (h.to_string(), v.to_string()))
                    .collect(),
            }
        })
        .collect()
}

#[test]
fn every_builtin_parses_validates_and_cites_its_source() {
    let library = Library::builtin();
    assert_eq!(library.len(), 47);
    for material in library.iter() {
        let source = material.source().expect("every built-in has a [source]");
        assert!(!source.coefficients().is_empty(), "{}", material.id());
        assert!(
            source.eta().is_some_and(|s| !s.is_empty()),
            "{}",
            material.id()
        );
        assert!(matches!(material.origin(), Origin::Builtin(_)));
        // Every channel builds a medium.
        for channel in Rgb::ALL {
            assert!(material.medium(channel).sigma_t_prime() > 0.0);
        }
    }
}

#[test]
fn builtin_numbers_match_the_reference_table_exactly() {
    let library = Library::builtin();
    let rows = reference_rows();
    assert_eq!(rows.len(), library.len());
    let mut matched: Vec<&str> = Vec::new();
    for row in &rows {
        // The table's id is the material's id, or an alias where the id splits words.
        let m = library.get(row.text("id")).unwrap();
        matched.push(m.id());
        let renamed = m.id() != row.text("id");
        assert_eq!(renamed, m.aliases().iter().any(|a| a == row.text("id")));
        if !renamed {
            assert_eq!(m.name(), row.text("name"));
        }
        assert_eq!(m.eta(), row.number("eta"), "{}", m.id());
        assert_eq!(m.sigma_s(), row.rgb("sigma_s"), "{}", m.id());
        assert_eq!(m.sigma_a(), row.rgb("sigma_a"), "{}", m.id());
        assert_eq!(m.g(), row.rgb("g"), "{}", m.id());
        let source = m.source().unwrap();
        let pbrt = row.rgb("pbrt_reduced_sigma_s");
        match row.text("coefficients") {
            "reduced" => {
                assert_eq!(m.coefficients(), Coefficients::Reduced);
                assert!(source.coefficients().starts_with("Jensen et al. 2001"));
                // pbrt stores Jensen's σ′s as is.
                assert_eq!(pbrt, m.sigma_s(), "{}", m.id());
            }
            "unreduced" => {
                assert_eq!(m.coefficients(), Coefficients::Unreduced);
                assert!(source.coefficients().starts_with("Narasimhan et al. 2006"));
                assert_eq!(source.pbrt_reduced_sigma_s(), Some(pbrt), "{}", m.id());
            }
            other => panic!("unknown coefficients {other}"),
        }
        assert!(source.coefficients().starts_with(row.text("source")));
    }
    matched.sort_unstable();
    matched.dedup();
    assert_eq!(
        matched.len(),
        rows.len(),
        "two rows found the same material"
    );
}

#[test]
fn disagreements_between_published_copies_are_noted() {
    let library = Library::builtin();
    let notes = |id: &str| {
        library
            .get(id)
            .unwrap()
            .source()
            .unwrap()
            .notes()
            .join("\n")
    };
    for m in library.iter() {
        let Some(pbrt) = m.source().unwrap().pbrt_reduced_sigma_s() else {
            continue;
        };
        // Where σs(1 − g) from the published figures is more than 1 % off pbrt's σ′s
        // (sprite, white zinfandel, Budweiser), the file says so.
        let worst = (0..3)
            .filter(|&i| pbrt[i] > 0.0)
            .map(|i| (m.channels()[i].sigma_s_prime() - pbrt[i]).abs() / pbrt[i])
            .fold(0.0, f64::max);
        let noted = notes(m.id()).contains("differs from pbrt's stored value");
        assert_eq!(worst > 0.01, noted, "{}: worst {worst}", m.id());
    }
    assert!(notes("sprite").contains("4.0 %"));
    assert!(notes("chicken1").contains("0.0015"));
    assert!(notes("chicken2").contains("0.0018"));
    assert!(notes("marble").contains("eta = 1.5"));
}

#[test]
fn ids_are_kebab_case_unique_and_name_their_files() {
    let library = Library::builtin();
    let kebab = |id: &str| {
        id.split('-').all(|w| {
            !w.is_empty()
                && w.bytes()
                    .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit())
        })
    };
    let mut keys: Vec<&str> = Vec::new();
    for m in library.iter() {
        assert!(kebab(m.id()), "{}", m.id());
        let file = format!("built-in materials/{}.toml", m.id());
        assert_eq!(m.origin().to_string(), file);
        keys.push(m.id());
        keys.extend(m.aliases().iter().map(|a| a.as_str()));
    }
    let count = keys.len();
    keys.sort_unstable();
    keys.dedup();
    assert_eq!(keys.len(), count, "an id or alias is repeated");
    // Ids that squash words in the reference table are split, with the old id as alias.
    for (id, alias) in [("skim-milk", "skimmilk"), ("whole-milk", "wholemilk")] {
        assert_eq!(library.get(alias).unwrap().id(), id);
    }
}

#[test]
fn white_grapefruit_juice_is_present_with_eta_1_33() {
    let library = Library::builtin();
    let m = library.get("white-grapefruit-juice").unwrap();
    assert_eq!(m.name(), "White Grapefruit Juice");
    assert_eq!(m.eta(), 1.33);
    assert_eq!(m.coefficients(), Coefficients::Unreduced);
    assert_eq!(m.g(), [0.548, 0.545, 0.565]);
}

#[test]
fn lookups_ignore_case_space_and_underscores() {
    let library = Library::builtin();
    for query in [
        "KETCHUP",
        "Ketchup",
        " ketchup ",
        "White Grapefruit Juice",
        "white_grapefruit_juice",
        "Skimmilk",
    ] {
        assert!(library.get(query).is_ok(), "{query}");
    }
    assert_eq!(library.get("Skim Milk").unwrap().id(), "skim-milk");
}

fn suggestions(library: &Library, query: &str) -> Vec<String> {
    match library.get(query) {
        Err(MaterialError::NotFound {
            query: q,
            suggestions,
        }) => {
            assert_eq!(q, query);
            suggestions
        }
        other => panic!("{query}: expected NotFound, got {other:?}"),
    }
}

#[test]
fn typos_get_the_right_suggestion() {
    let library = Library::builtin();
    for (typo, expected) in [
        ("white-grapfruit-juice", "white-grapefruit-juice"),
        ("ketchap", "ketchup"),
        ("Ketchap", "ketchup"),
        ("expresso", "espresso"),
        ("chiken1", "chicken1"),
        ("skimilk", "skim-milk"),
        ("spectarlon", "spectralon"),
    ] {
        let s = suggestions(&library, typo);
        assert_eq!(
            s.first().map(String::as_str),
            Some(expected),
            "{typo}: {s:?}"
        );
    }
    let message = library.get("ketchap").unwrap_err().to_string();
    assert_eq!(
        message,
        "no material named \"ketchap\"; did you mean `ketchup`?"
    );
    // A word of several names suggests them; nonsense suggests nothing.
    let grapefruit = suggestions(&library, "grapefruit");
    assert!(grapefruit.contains(&"white-grapefruit-juice".to_string()));
    assert!(grapefruit.contains(&"ruby-grapefruit-juice".to_string()));
    assert!(suggestions(&library, "zzzzzzzzzzzz").is_empty());
}

#[test]
fn channels_give_unreduced_media_and_reduced_quantities() {
    let library = Library::builtin();
    let juice = library.get("white-grapefruit-juice").unwrap();
    let red = juice.medium(Rgb::Red);
    assert_eq!(
        (red.sigma_s(), red.sigma_a(), red.g()),
        (0.50499, 0.0138, 0.548)
    );
    assert_eq!(red.eta(), 1.33);
    let s_prime = 0.50499 * (1.0 - 0.548);
    assert!((juice.sigma_t_prime()[0] - (s_prime + 0.0138)).abs() < 1e-15);
    assert!((juice.rho_prime()[0] - s_prime / (s_prime + 0.0138)).abs() < 1e-15);
    // Jensen's reduced rows: σs = σ′s with g = 0.
    let ketchup = library.get("ketchup").unwrap();
    let blue = ketchup.medium(Rgb::Blue);
    assert_eq!(
        (blue.sigma_s(), blue.sigma_a(), blue.g()),
        (0.03, 1.45, 0.0)
    );
    assert_eq!(blue.eta(), 1.3);
    assert_eq!(ketchup.channel(Rgb::Blue).sigma_s_prime(), 0.03);
    assert!((ketchup.rho_prime()[2] - 0.03 / 1.48).abs() < 1e-15);
}

#[test]
fn json_carries_coefficients_derived_quantities_and_source() {
    let library = Library::builtin();
    let json = serde_json::to_value(library.get("skim-milk").unwrap()).unwrap();
    assert_eq!(json["id"], "skim-milk");
    assert_eq!(json["aliases"][0], "skimmilk");
    assert_eq!(json["eta"], 1.3);
    assert_eq!(json["coefficients"], "reduced");
    assert_eq!(json["channels"][0]["sigma_s"], 0.7);
    assert_eq!(json["channels"][0]["sigma_a"], 0.0014);
    assert_eq!(json["channels"][0]["g"], 0.0);
    assert!(json["channels"][2]["rho_prime"].as_f64().unwrap() > 0.9);
    assert!(json["channels"][1]["sigma_t_prime"].is_number());
    assert!(json["source"]["coefficients"].is_string());
    assert_eq!(json["origin"], "built-in materials/skim-milk.toml");
}

/// A fresh, empty directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "bssrdf-zoo-materials-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn user_material(id: &str, aliases: &str) -> String {
    format!(
        "id = \"{id}\"\nname = \"My {id}\"\naliases = [{aliases}]\neta = 1.4\n\
         coefficients = \"unreduced\"\nsigma_s = [1.0, 2.0, 3.0]\n\
         sigma_a = [0.1, 0.2, 0.3]\ng = [0.8, 0.8, 0.8]\n"
    )
}

fn write(dir: &Path, file: &str, text: &str) -> PathBuf {
    let path = dir.join(file);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn loading_a_directory_adds_every_toml_file() {
    let dir = scratch("dir");
    write(&dir, "jade.toml", &user_material("jade", ""));
    write(&dir, "wax.TOML", &user_material("candle-wax", "\"wax\""));
    write(&dir, "notes.txt", "not a material");
    std::fs::create_dir(dir.join("nested")).unwrap();
    write(&dir.join("nested"), "x.toml", "not even TOML");
    let mut library = Library::builtin();
    assert_eq!(library.load_path(&dir).unwrap(), 2);
    assert_eq!(library.len(), 49);
    let wax = library.get("Wax").unwrap();
    assert_eq!(wax.id(), "candle-wax");
    assert_eq!(wax.origin(), &Origin::File(dir.join("wax.TOML")));
    assert_eq!(wax.g(), [0.8; 3]);
    // Sorted by id, user materials among the built-ins.
    let ids: Vec<&str> = library.iter().map(Material::id).collect();
    assert!(ids.windows(2).all(|w| w[0] < w[1]));
    // A single file loads too.
    let mut one = Library::new();
    assert_eq!(one.load_path(dir.join("jade.toml")).unwrap(), 1);
    assert_eq!(one.get("jade").unwrap().eta(), 1.4);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn missing_paths_and_empty_directories_are_errors() {
    let dir = scratch("empty");
    let mut library = Library::builtin();
    let err = library.load_path(&dir).unwrap_err();
    assert!(matches!(&err, MaterialError::EmptyDirectory { path } if path == &dir));
    let missing = dir.join("absent.toml");
    let err = library.load_path(&missing).unwrap_err();
    assert!(matches!(&err, MaterialError::Io { path, .. } if path == &missing));
    assert!(err.to_string().contains("absent.toml"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn clashing_with_a_builtin_is_an_error_and_changes_nothing() {
    let dir = scratch("clash");
    let mut library = Library::builtin();
    // The same id as a built-in, in another spelling of the file name.
    let file = write(&dir, "my-ketchup.toml", &user_material("ketchup", ""));
    let err = library.load_path(&file).unwrap_err();
    match &err {
        MaterialError::DuplicateId { id, first, second } => {
            assert_eq!(id, "ketchup");
            assert_eq!(first, "built-in materials/ketchup.toml");
            assert_eq!(second, &file.display().to_string());
        }
        other => panic!("expected DuplicateId, got {other:?}"),
    }
    assert_eq!(library.get("ketchup").unwrap().eta(), 1.3);
    // An alias may not take a built-in's alias either.
    std::fs::remove_file(&file).unwrap();
    write(&dir, "a.toml", &user_material("new-milk", ""));
    write(&dir, "b.toml", &user_material("other-milk", "\"skimmilk\""));
    let err = library.load_path(&dir).unwrap_err();
    assert!(
        matches!(&err, MaterialError::DuplicateId { id, .. } if id == "skimmilk"),
        "{err:?}"
    );
    // All or nothing: the good file of the directory was not added.
    assert_eq!(library.len(), 47);
    assert!(library.get("new-milk").is_err());
    // Two user files may not share an id either.
    std::fs::remove_file(dir.join("b.toml")).unwrap();
    write(&dir, "c.toml", &user_material("new-milk", ""));
    let err = library.load_path(&dir).unwrap_err();
    assert!(
        matches!(&err, MaterialError::DuplicateId { id, first, .. }
            if id == "new-milk" && first.ends_with("a.toml")),
        "{err:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn materials_from_coefficients_join_the_library() {
    let mut library = Library::builtin();
    let m = Material::from_coefficients("my-skin", [1.0, 1.5, 2.0], [0.1, 0.2, 0.3], [0.9; 3], 1.4)
        .unwrap();
    assert_eq!(m.name(), "my-skin");
    assert_eq!(m.origin(), &Origin::Inline);
    assert!((m.channel(Rgb::Green).sigma_s_prime() - 0.15).abs() < 1e-15);
    library.insert(m).unwrap();
    assert_eq!(library.get("My_Skin").unwrap().eta(), 1.4);
    let again = Material::from_coefficients("apple", [1.0; 3], [1.0; 3], [0.0; 3], 1.3).unwrap();
    assert!(matches!(
        library.insert(again),
        Err(MaterialError::DuplicateId { .. })
    ));
}

/// Errors print numbers in the messages' one form (1e300, not 301 digits) and name where the
/// material came from: a library file's material record by its path.
#[test]
fn material_errors_print_numbers_shortest_and_name_a_record_by_its_file() {
    let record = Origin::Record(PathBuf::from("lib.bssrdf"));
    let err = Material::from_coefficients_of(record, "wax", [1.0; 3], [0.1; 3], [0.0; 3], 1e300)
        .unwrap_err()
        .to_string();
    assert_eq!(
        err,
        "lib.bssrdf, material record: eta = 1e300 is outside [0.75, 2.5]"
    );
    let err = Material::from_coefficients("wax", [-1e-300, 1.0, 1.0], [0.1; 3], [0.0; 3], 1.3)
        .unwrap_err()
        .to_string();
    assert!(err.contains("= -1e-300 is negative"), "{err}");
}
