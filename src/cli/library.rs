//! Opening library files and choosing a table in them, shared by eval, sample and validate.

use super::CliError;
use bssrdf_zoo::format::{Library, Verify};
use bssrdf_zoo::materials::{Material, Rgb};
use bssrdf_zoo::table::FileTable;
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};

/// Opens a library file (mapped, every checksum verified); errors name the file.
pub fn open(path: &Path) -> Result<Library, CliError> {
    Library::open_mmap(path, Verify::Full)
        .map_err(|e| CliError::input(format!("cannot open table file {}: {e}", path.display())))
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
    /// Index of the table in the file (default: the material's, or the first).
    #[arg(long)]
    pub table: Option<usize>,
    /// A material of the library: ρ′ and σ′t come from it, distances are in mm.
    #[arg(long)]
    pub material: Option<String>,
    /// The material's colour channel.
    #[arg(long, value_enum, default_value = "r", requires = "material")]
    pub channel: Channel,
    /// Extra material files (TOML file or folder) for --material.
    #[arg(long, value_name = "PATH")]
    pub materials: Option<PathBuf>,
}

/// What a lookup needs from the choice: the table, and for a material its channel's ρ′ and σ′t.
pub struct Chosen<'a> {
    pub table: FileTable<'a>,
    pub material: Option<(Material, f64, f64)>,
}

impl TableChoice {
    pub fn resolve<'a>(&self, library: &'a Library, path: &Path) -> Result<Chosen<'a>, CliError> {
        let material = match &self.material {
            None => None,
            Some(name) => {
                // A material stored in the file first, else the named-material library.
                if let Some(m) = library.material(name) {
                    let c = self.channel.rgb().index();
                    let found =
                        Material::from_coefficients(&m.name, m.sigma_s, m.sigma_a, m.g, m.eta)
                            .map_err(|e| CliError::input(e.to_string()))?;
                    Some((found, m.tables[c] as usize))
                } else {
                    let lib = super::materials::library(self.materials.as_deref())?;
                    let m = lib
                        .get(name)
                        .map_err(|e| CliError::input(e.to_string()))?
                        .clone();
                    let index = library
                        .tables()
                        .position(|t| t.eta() == m.eta())
                        .ok_or_else(|| {
                            CliError::input(format!(
                                "{} has no table for material {:?} (eta = {}); bake one with `bssrdf bake {}`",
                                path.display(),
                                m.id(),
                                m.eta(),
                                m.id()
                            ))
                        })?;
                    Some((m, index))
                }
            }
        };
        let index = self
            .table
            .or(material.as_ref().map(|(_, i)| *i))
            .unwrap_or(0);
        let record = library.table(index).ok_or_else(|| {
            CliError::input(format!(
                "--table {index}: {} holds {} table(s)",
                path.display(),
                library.table_count()
            ))
        })?;
        let table = FileTable::new(record).map_err(|e| CliError::input(e.to_string()))?;
        let material = material.map(|(m, _)| {
            let ch = m.channel(self.channel.rgb());
            let (rho, st) = (ch.rho_prime(), ch.sigma_t_prime());
            (m, rho, st)
        });
        Ok(Chosen { table, material })
    }
}
