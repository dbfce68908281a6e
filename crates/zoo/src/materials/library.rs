//! A set of materials keyed by id: the built-ins, plus what a user loads. Ids and aliases share
//! one namespace and are never redefined.

use super::builtin::BUILTIN;
use super::suggest::suggest;
use super::{Material, MaterialError, Origin};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Materials by id, iterated in id order.
#[derive(Debug, Clone, Default)]
pub struct Library {
    materials: BTreeMap<String, Material>,
    /// Alias → id.
    aliases: BTreeMap<String, String>,
}

impl Library {
    /// An empty library.
    pub fn new() -> Self {
        Self::default()
    }

    /// The 47 built-in measured media (see `materials/`).
    pub fn builtin() -> Self {
        let mut library = Self::new();
        for (file, text) in BUILTIN {
            // The test suite parses every built-in file and checks it against the reference
            // table, so a failure here is a bug in the crate, not in anyone's input.
            let material = Material::from_toml_str(text, Origin::Builtin(file))
                .and_then(|m| library.insert(m));
            if let Err(e) = material {
                panic!("invalid built-in material: {e}");
            }
        }
        library
    }

    /// Number of materials.
    pub fn len(&self) -> usize {
        self.materials.len()
    }

    /// Whether the library holds no material.
    pub fn is_empty(&self) -> bool {
        self.materials.is_empty()
    }

    /// Materials sorted by id.
    pub fn iter(&self) -> impl Iterator<Item = &Material> {
        self.materials.values()
    }

    /// Adds a material. Fails with [`MaterialError::DuplicateId`] if its id or an alias is
    /// already an id or alias of the library (or repeats within the material).
    pub fn insert(&mut self, material: Material) -> Result<(), MaterialError> {
        let mut keys: Vec<&str> = Vec::with_capacity(1 + material.aliases.len());
        for key in std::iter::once(material.id()).chain(material.aliases().iter().map(|a| &**a)) {
            let first = if keys.contains(&key) {
                Some(material.origin().to_string())
            } else {
                self.owner(key).map(|m| m.origin().to_string())
            };
            if let Some(first) = first {
                return Err(MaterialError::DuplicateId {
                    id: key.to_string(),
                    first,
                    second: material.origin().to_string(),
                });
            }
            keys.push(key);
        }
        for alias in material.aliases() {
            self.aliases.insert(alias.clone(), material.id.clone());
        }
        self.materials.insert(material.id.clone(), material);
        Ok(())
    }

    /// Loads a user's material file, or every `*.toml` file directly inside a directory
    /// ([`Library::files_of`]). Returns how many materials were added. All or nothing: on any
    /// error the library is left as it was.
    pub fn load_path(&mut self, path: impl AsRef<Path>) -> Result<usize, MaterialError> {
        let files = Self::files_of(path.as_ref())?;
        let mut staged = self.clone();
        for file in &files {
            let bytes = std::fs::read(file).map_err(|source| MaterialError::Io {
                path: file.clone(),
                source,
            })?;
            let text = String::from_utf8(bytes).map_err(|e| MaterialError::NotText {
                path: file.clone(),
                library: e.as_bytes().starts_with(&crate::format::spec::MAGIC),
            })?;
            staged.insert(Material::from_toml_str(&text, Origin::File(file.clone()))?)?;
        }
        *self = staged;
        Ok(files.len())
    }

    /// The files [`Library::load_path`] reads for `path`: the path itself, or for a directory
    /// every `*.toml` file directly inside it, sorted by name (subdirectories are not entered).
    /// A directory without one is [`MaterialError::EmptyDirectory`].
    pub fn files_of(path: &Path) -> Result<Vec<PathBuf>, MaterialError> {
        let io = |source| MaterialError::Io {
            path: path.to_path_buf(),
            source,
        };
        if !std::fs::metadata(path).map_err(io)?.is_dir() {
            return Ok(vec![path.to_path_buf()]);
        }
        let mut files = Vec::new();
        for entry in std::fs::read_dir(path).map_err(io)? {
            let file = entry.map_err(io)?.path();
            let is_toml = file
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
            if is_toml && file.is_file() {
                files.push(file);
            }
        }
        if files.is_empty() {
            return Err(MaterialError::EmptyDirectory {
                path: path.to_path_buf(),
            });
        }
        files.sort();
        Ok(files)
    }

    /// The material with this id or alias. Case and surrounding white space are ignored, and
    /// spaces and underscores read as hyphens. A miss is [`MaterialError::NotFound`] with up to
    /// five close ids as suggestions.
    pub fn get(&self, query: &str) -> Result<&Material, MaterialError> {
        let key = normalize(query);
        self.owner(&key).ok_or_else(|| {
            let ids = self.materials.keys().map(|id| (id.as_str(), id.as_str()));
            let aliases = self.aliases.iter().map(|(a, id)| (a.as_str(), id.as_str()));
            MaterialError::NotFound {
                query: query.to_string(),
                suggestions: suggest(&key, ids.chain(aliases)),
            }
        })
    }

    /// The material whose id or alias is exactly `key`.
    fn owner(&self, key: &str) -> Option<&Material> {
        let id = self.aliases.get(key).map_or(key, |id| id.as_str());
        self.materials.get(id)
    }
}

/// Lowercase, trimmed, with spaces and underscores as hyphens (the runtime's reading of names,
/// which a library file's material records share).
fn normalize(query: &str) -> String {
    bssrdf_runtime::format::loose_name(query)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalize_reads_names_as_ids() {
        assert_eq!(
            normalize("  White Grapefruit_Juice "),
            "white-grapefruit-juice"
        );
        assert_eq!(normalize("KETCHUP"), "ketchup");
    }

    #[test]
    fn builtin_files_are_exactly_the_materials_directory() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("materials");
        let mut on_disk: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter_map(|name| name.strip_suffix(".toml").map(str::to_string))
            .collect();
        on_disk.sort();
        let listed: Vec<&str> = BUILTIN
            .iter()
            .map(|(file, _)| &file["materials/".len()..file.len() - ".toml".len()])
            .collect();
        assert_eq!(listed, on_disk, "BUILTIN must list materials/ sorted by id");
    }

    #[test]
    fn a_material_may_not_repeat_its_own_id_as_alias() {
        let text = "id = \"a\"\nname = \"A\"\naliases = [\"a\"]\neta = 1.3\n\
                    coefficients = \"unreduced\"\nsigma_s = [1, 1, 1]\nsigma_a = [1, 1, 1]\n\
                    g = [0, 0, 0]\n";
        let material = Material::from_toml_str(text, Origin::Inline).unwrap();
        let err = Library::new().insert(material).unwrap_err();
        assert!(
            matches!(&err, MaterialError::DuplicateId { id, .. } if id == "a"),
            "{err:?}"
        );
    }
}
