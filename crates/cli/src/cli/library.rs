//! Opening library files and choosing a table in them, shared by eval, sample and validate.

use super::{show, CliError};
use bssrdf_zoo::format::{FormatError, Library, Verify};
use bssrdf_zoo::materials::{Material, Origin, Rgb};
use bssrdf_zoo::medium::{ETA_MAX, ETA_MIN};
use bssrdf_zoo::table::{AngularTable, FileTable};
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};

/// Opens a library file, every checksum verified; errors name the file. The file is read into
/// memory, so that another process rewriting it cannot hurt this one; `mmap` maps it instead
/// (faster to open, but a file truncated underneath kills the process with SIGBUS).
pub fn open(path: &Path, mmap: bool) -> Result<Library, CliError> {
    if path.is_dir() {
        return Err(CliError::input(format!(
            "{} is a folder, not a library file",
            path.display()
        )));
    }
    let opened = if mmap {
        Library::open_mmap(path, Verify::Full)
    } else {
        Library::read(path, Verify::Full)
    };
    opened.map_err(|e| match e {
        // These already name the file.
        FormatError::Io { .. } => CliError::input(e.to_string()),
        _ => CliError::input(format!("{}: {e}", path.display())),
    })
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Channel {
    R,
    G,
    B,
}

impl Channel {
    pub fn rgb(self) -> Rgb {
        match self {
            Channel::R => Rgb::Red,
            Channel::G => Rgb::Green,
            Channel::B => Rgb::Blue,
        }
    }
}

/// Which table of a file to use, and optionally the material whose channel selects it.
#[derive(Debug, Args)]
pub struct TableChoice {
    /// Index of the table in the file (default: the one of --eta or of the material, or the
    /// first).
    #[arg(long, value_parser = super::values::whole::<usize>)]
    pub table: Option<usize>,
    /// Relative index of refraction η in [0.75, 2.5]: selects the file's table with this η
    /// (refused when the file has none); for `eval` without a file, the medium's η (default
    /// 1.33).
    #[arg(long, allow_hyphen_values = true)]
    pub eta: Option<f64>,
    /// A material of the library: its η selects the file's table; for `eval` and `sample`, ρ′
    /// and σ′t come from it too and distances are in mm.
    #[arg(long)]
    pub material: Option<String>,
    /// The material's colour channel [default: r] (only with --material).
    #[arg(long, value_enum)]
    channel: Option<Channel>,
    /// Extra material files (TOML file or folder) for --material.
    #[arg(long, value_name = "PATH")]
    pub materials: Option<PathBuf>,
    /// Map the library file instead of reading it into memory (faster to open; a file
    /// rewritten meanwhile kills the process with SIGBUS).
    #[arg(long)]
    pub mmap: bool,
}

/// What a lookup needs from the choice: the table, and for a material its channel's ρ′ and σ′t.
pub struct Chosen<'a> {
    /// Index of the table in the file.
    pub index: usize,
    pub table: FileTable<'a>,
    pub material: Option<(Material, f64, f64)>,
    /// The file's other tables with the same η, and the albedo rows each keeps
    /// (`values::check_kept` names one that keeps a ρ′ this table does not).
    pub siblings: Vec<(usize, [f64; 2])>,
}

/// Whether two η agree to the precision files and material lists give them.
fn same_eta(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// The file's tables as "1.3 (table 0), 1.33 (table 1)".
fn list_etas(library: &Library) -> String {
    library
        .tables()
        .enumerate()
        .map(|(i, t)| format!("{} (table {i})", show(t.eta())))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Whether table `index` of `library` keeps albedo rows around `rho`.
fn keeps(library: &Library, index: usize, rho: f64) -> bool {
    kept_range(library, index).is_some_and(|[lo, hi]| (lo..=hi).contains(&rho))
}

/// The albedos table `index` takes: its albedo rows' range with the ends' f32 rounding
/// (`TableRef::rho_domain`); `None` if it cannot be read.
fn kept_range(library: &Library, index: usize) -> Option<[f64; 2]> {
    let table = FileTable::new(library.table(index)?).ok()?;
    Some(table.view().ok()?.rho_domain())
}

/// The tables other than `index` with its η, each with the albedo rows it keeps: where a ρ′
/// that table `index` does not keep may be (a scene bake keeps several tables per η).
fn siblings(library: &Library, index: usize) -> Vec<(usize, [f64; 2])> {
    let Some(eta) = library.table(index).map(|t| t.eta()) else {
        return Vec::new();
    };
    library
        .tables()
        .enumerate()
        .filter(|&(i, ref t)| i != index && same_eta(t.eta(), eta))
        .filter_map(|(i, _)| Some((i, kept_range(library, i)?)))
        .collect()
}

impl TableChoice {
    /// A choice by --table and --eta only (no material), for commands that take no material.
    pub fn of_table(table: Option<usize>, eta: Option<f64>, mmap: bool) -> Self {
        Self {
            table,
            eta,
            material: None,
            channel: None,
            materials: None,
            mmap,
        }
    }

    /// The colour channel of --material (red unless --channel says otherwise).
    pub fn channel(&self) -> Rgb {
        self.channel.unwrap_or(Channel::R).rgb()
    }

    /// Checks --eta (its domain) and that --materials and --channel come with --material.
    pub fn check_eta(&self) -> Result<(), CliError> {
        if self.materials.is_some() && self.material.is_none() {
            return Err(CliError::input(
                "--materials adds files to look --material up in; give --material NAME, or drop --materials",
            ));
        }
        // clap's `requires` lets this pass when --rho (which conflicts with --material) is given.
        if self.channel.is_some() && self.material.is_none() {
            return Err(CliError::input(
                "--channel picks a colour channel of --material; give --material NAME, or drop --channel",
            ));
        }
        match self.eta {
            Some(eta) => super::check_range("--eta", eta, ETA_MIN..=ETA_MAX),
            None => Ok(()),
        }
    }

    /// The material named by --material without a file (η, ρ′ and σ′t from the library);
    /// --eta must agree with it.
    pub fn named_material(&self) -> Result<Option<Material>, CliError> {
        self.check_eta()?;
        let Some(name) = &self.material else {
            return Ok(None);
        };
        let lib = super::materials::library(self.materials.as_deref())?;
        let m = lib
            .get(name)
            .map_err(|e| CliError::input(e.to_string()))?
            .clone();
        if let Some(eta) = self.eta.filter(|&e| !same_eta(e, m.eta())) {
            return Err(CliError::input(format!(
                "--eta {} conflicts with --material {name}, whose eta is {}: give one or the other",
                show(eta),
                show(m.eta())
            )));
        }
        Ok(Some(m))
    }

    /// Chooses the table of `library` (read from `path`): --table, else the table of --eta or
    /// of the material, else the first. Inputs that disagree (--eta against the material's η or
    /// --table's η) are refused with a message naming both.
    pub fn resolve<'a>(&self, library: &'a Library, path: &Path) -> Result<Chosen<'a>, CliError> {
        self.check_eta()?;
        let file = path.display();
        let material = match &self.material {
            None => None,
            Some(name) => {
                // A material stored in the file first, else the named-material library.
                if let Some(m) = file_material(library, name, path)? {
                    if self.materials.is_some() {
                        return Err(CliError::input(format!(
                            "--materials adds files to look --material up in, but {name} is a material of {file}: drop --materials"
                        )));
                    }
                    let c = self.channel().index();
                    let origin = Origin::Record(path.to_path_buf());
                    let found = Material::from_coefficients_of(
                        origin, &m.name, m.sigma_s, m.sigma_a, m.g, m.eta,
                    )
                    .map_err(|e| CliError::input(e.to_string()))?;
                    let index = m.tables[c] as usize;
                    // The format lets a file written elsewhere point a material at a table of
                    // another η: its lookups would be neither the material's nor the table's
                    if let Some(held) = library
                        .table(index)
                        .map(|t| t.eta())
                        .filter(|&held| !same_eta(held, m.eta))
                    {
                        return Err(CliError::input(format!(
                            "material {name} of {file} has eta {}, but its table {index} ({} channel) holds eta {}: the file pairs a material with a table of another eta; look the table up with --table {index} --rho instead",
                            show(m.eta),
                            self.channel().name(),
                            show(held)
                        )));
                    }
                    Some((found, index))
                } else {
                    let m = super::materials::named(name, self.materials.as_deref())
                        .map_err(|e| with_file_materials(e, library, path))?;
                    // Of the tables with the material's η, one whose albedo rows hold the
                    // channel's ρ′ (a scene bake keeps several such tables), else the first.
                    let rho = m.channel(self.channel()).rho_prime();
                    let same: Vec<usize> = library
                        .tables()
                        .enumerate()
                        .filter(|(_, t)| same_eta(t.eta(), m.eta()))
                        .map(|(i, _)| i)
                        .collect();
                    let index = same
                        .iter()
                        .copied()
                        .find(|&i| keeps(library, i, rho))
                        .or_else(|| same.first().copied())
                        .ok_or_else(|| {
                            CliError::input(format!(
                                "{file} has no table for material {:?} (eta = {}); its tables: {}; bake one with `bssrdf bake {}`",
                                m.id(),
                                show(m.eta()),
                                list_etas(library),
                                m.id()
                            ))
                        })?;
                    Some((m, index))
                }
            }
        };
        if let (Some(eta), Some((m, _))) = (self.eta, &material) {
            if !same_eta(eta, m.eta()) {
                return Err(CliError::input(format!(
                    "--eta {} conflicts with --material {}, whose eta is {}: give one or the other",
                    show(eta),
                    m.id(),
                    show(m.eta())
                )));
            }
        }
        let by_eta = match (self.eta, &material) {
            (Some(eta), None) if self.table.is_none() => Some(
                library
                    .tables()
                    .position(|t| same_eta(t.eta(), eta))
                    .ok_or_else(|| {
                        CliError::input(format!(
                            "--eta {}: {file} has no table at this eta; its tables: {}",
                            show(eta),
                            list_etas(library)
                        ))
                    })?,
            ),
            _ => None,
        };
        let index = self
            .table
            .or(by_eta)
            .or(material.as_ref().map(|(_, i)| *i))
            .unwrap_or(0);
        let record = library.table(index).ok_or_else(|| {
            CliError::input(format!(
                "--table {index}: {file} holds {} table(s)",
                library.table_count()
            ))
        })?;
        if let Some(table) = self.table {
            let held = record.eta();
            let conflict = match (&material, self.eta) {
                (Some((m, _)), _) if !same_eta(m.eta(), held) => Some(format!(
                    "--table {table} holds eta {}, but --material {} has eta {}",
                    show(held),
                    m.id(),
                    show(m.eta())
                )),
                (None, Some(eta)) if !same_eta(eta, held) => Some(format!(
                    "--table {table} holds eta {}, not --eta {}",
                    show(held),
                    show(eta)
                )),
                _ => None,
            };
            if let Some(message) = conflict {
                return Err(CliError::input(format!("{message}: give one or the other")));
            }
        }
        let table = FileTable::new(record)
            .map_err(|e| CliError::input(format!("{file}: table {index}: {e}")))?;
        let material = material.map(|(m, _)| {
            let ch = m.channel(self.channel());
            let (rho, st) = (ch.rho_prime(), ch.sigma_t_prime());
            (m, rho, st)
        });
        Ok(Chosen {
            index,
            table,
            material,
            siblings: siblings(library, index),
        })
    }
}

/// The walk-angular table (`bssrdf bake --source walk`) at `eta` and `g` of the library at
/// `path`, given by the command's `flag`: the first such table of the file, or an error saying
/// what the file holds.
pub fn walk_table(flag: &str, path: &Path, eta: f64, g: f64) -> Result<AngularTable, CliError> {
    let library = open(path, false)?;
    let mut found = Vec::new();
    for (i, record) in library.tables().enumerate() {
        let table = FileTable::new(record)
            .and_then(|t| t.to_owned_table())
            .map_err(|e| CliError::input(format!("{flag} {}: table {i}: {e}", path.display())))?;
        if table.is_walk_at(eta, g) {
            return Ok(table);
        }
        match table.walk() {
            Some(walk) => found.push(format!(
                "a walk table at eta {}, g {}",
                super::show(table.eta()),
                super::show(walk.g)
            )),
            None => found.push(format!("a PBD table at eta {}", super::show(table.eta()))),
        }
    }
    let held = if found.is_empty() {
        "no table".to_string()
    } else {
        found.join("; ")
    };
    Err(CliError::input(format!(
        "{flag} {} holds no walk table at eta {} and g {} (it holds {held}); bake one with `bssrdf bake --source walk --eta {} --g {}`",
        path.display(),
        super::show(eta),
        super::show(g),
        super::show(eta),
        super::show(g)
    )))
}

/// The material record of `library` (read from `path`) that --material `name` names, read as
/// the named-material library reads names (`format::Library::materials_named`); `None` if no
/// record does, an input error if several do.
fn file_material<'a>(
    library: &'a Library,
    name: &str,
    path: &Path,
) -> Result<Option<&'a bssrdf_zoo::format::Material>, CliError> {
    match library.materials_named(name).as_slice() {
        [] => Ok(None),
        [one] => Ok(Some(one)),
        several => Err(CliError::input(format!(
            "--material {name} reads as {} materials of {}: {}; give one exactly",
            several.len(),
            path.display(),
            several
                .iter()
                .map(|m| format!("{:?}", m.name))
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

/// `error` (a name found neither in the file nor in the named-material library) with the
/// names of the file's own materials, where it has any.
fn with_file_materials(error: CliError, library: &Library, path: &Path) -> CliError {
    let names: Vec<String> = library
        .materials()
        .iter()
        .map(|m| format!("{:?}", m.name))
        .collect();
    match error {
        CliError::Input(message) if !names.is_empty() => CliError::input(format!(
            "{message} (nor in {}, whose materials are {})",
            path.display(),
            names.join(", ")
        )),
        other => other,
    }
}
