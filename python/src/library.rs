//! `Library` (an opened file), `Material` (one of its records) and `Channel` (one colour
//! channel of a material: the renderer's handle, world units).
//!
//! Each object holds the runtime's handle (`embed::Library`, `ChannelLookup`), which keeps the
//! file and its map alive: a table, channel or array view outlives the `Library` it came from.

use std::path::PathBuf;

use bssrdf_zoo::embed::{self, ChannelLookup, Rgb};
use bssrdf_zoo::format;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyAny;

use crate::errors;
use crate::points::{self, Arg};
use crate::table::{
    path_or_zero, path_tracing, path_tuple, sample_or_zero, uniforms, Domain, Path6, Sample3, Table,
};

/// A library file, opened and validated (structure, checksums, every value finite), with its
/// tables and material records.
#[pyclass(frozen, module = "bssrdf_zoo")]
pub struct Library {
    inner: embed::Library,
    path: Option<PathBuf>,
}

impl Library {
    /// A library made in memory (a bake), or opened from `path`.
    pub fn new(inner: embed::Library, path: Option<PathBuf>) -> Self {
        Self { inner, path }
    }
}

#[pymethods]
impl Library {
    /// Opens the file at `path`: mapped read-only (`mmap=True`, lookups read the map) or read
    /// into memory (`mmap=False`, safe against a file that changes while open).
    #[staticmethod]
    #[pyo3(signature = (path, mmap = true))]
    fn open(py: Python<'_>, path: PathBuf, mmap: bool) -> PyResult<Self> {
        let inner = py
            .detach(|| {
                if mmap {
                    embed::Library::open_mmap(&path)
                } else {
                    embed::Library::read(&path)
                }
            })
            .map_err(errors::embed)?;
        Ok(Self::new(inner, Some(path)))
    }

    /// Reads the file at `path` into memory: `Library.open(path, mmap=False)`.
    #[staticmethod]
    fn read(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        Self::open(py, path, false)
    }

    /// The path the library was opened from, or None for a bake in memory.
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        self.path.clone()
    }

    /// Whether lookups read a memory map of the file.
    #[getter]
    fn is_mapped(&self) -> bool {
        self.inner.format().is_mapped()
    }

    /// The file format version (major, minor).
    #[getter]
    fn version(&self) -> (u16, u16) {
        self.inner.format().version()
    }

    /// The tables, in file order (one per η baked).
    #[getter]
    fn tables(&self) -> PyResult<Vec<Table>> {
        (0..self.inner.table_count())
            .map(|index| Table::new(&self.inner, index))
            .collect()
    }

    /// Table `index`; ValueError if the library has no such table.
    fn table(&self, #[pyo3(from_py_with = crate::args::index)] index: usize) -> PyResult<Table> {
        Table::new(&self.inner, index)
    }

    /// The material records, in file order.
    #[getter]
    fn materials(&self) -> Vec<Material> {
        self.inner
            .materials()
            .iter()
            .map(|record| Material {
                library: self.inner.clone(),
                record: record.clone(),
            })
            .collect()
    }

    /// The material record called `name`; ValueError if there is none.
    fn material(&self, name: &str) -> PyResult<Material> {
        match self.inner.format().material(name) {
            Some(record) => Ok(Material {
                library: self.inner.clone(),
                record: record.clone(),
            }),
            // The handle's own refusal, which lists the names the file has.
            None => Err(errors::embed(
                self.inner.channel(name, Rgb::Red).err().unwrap_or_else(|| {
                    embed::EmbedError::NoMaterial {
                        name: name.to_owned(),
                        known: String::new(),
                    }
                }),
            )),
        }
    }

    /// The lookup handle of one colour channel of material `name` ("r", "g", "b", "red",
    /// "green", "blue" or 0, 1, 2): world units, ρ′ and σ′t from the record.
    fn channel(&self, name: &str, channel: &Bound<'_, PyAny>) -> PyResult<Channel> {
        let rgb = rgb(channel)?;
        let lookup = self.inner.channel(name, rgb).map_err(errors::embed)?;
        Ok(Channel::new(
            &self.inner,
            lookup,
            name.to_owned(),
            Some(rgb),
        ))
    }

    /// The provenance (how the file was made) as a dict, or None if the file has none.
    #[getter]
    fn provenance<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(provenance) = self.inner.format().provenance() else {
            return Ok(None);
        };
        let text = String::from_utf8_lossy(&provenance.to_canonical_json()).into_owned();
        Ok(Some(py.import("json")?.call_method1("loads", (text,))?))
    }

    /// Writes the library to `path` atomically (a mappable, uncompressed file); a path the
    /// write would refuse is refused first, naming it (`bake`'s `path=` check).
    fn write(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        crate::bake::check_output(&path)?;
        py.detach(|| self.inner.write(&path)).map_err(errors::embed)
    }

    fn __repr__(&self) -> String {
        let names: Vec<String> = self
            .inner
            .materials()
            .iter()
            .map(|m| format!("{:?}", m.name))
            .collect();
        let etas: Vec<String> = self
            .inner
            .format()
            .tables()
            .map(|t| t.eta().to_string())
            .collect();
        format!(
            "<bssrdf_zoo.Library {}: tables at eta [{}], materials [{}]>",
            self.path
                .as_ref()
                .map_or("in memory".to_owned(), |p| format!(
                    "{:?}",
                    p.display().to_string()
                )),
            etas.join(", "),
            names.join(", ")
        )
    }
}

/// A colour channel from a name or an index.
fn rgb(channel: &Bound<'_, PyAny>) -> PyResult<Rgb> {
    if let Ok(index) = channel.extract::<i64>() {
        if let Some(&c) = usize::try_from(index).ok().and_then(|i| Rgb::ALL.get(i)) {
            return Ok(c);
        }
    } else if let Ok(name) = channel.extract::<String>() {
        let found = Rgb::ALL
            .into_iter()
            .find(|c| name == c.name() || name == c.name()[..1]);
        if let Some(c) = found {
            return Ok(c);
        }
    }
    Err(PyValueError::new_err(format!(
        "channel {} is not one of \"r\", \"g\", \"b\", \"red\", \"green\", \"blue\", 0, 1, 2",
        channel.repr()?
    )))
}

/// RGB values as Python's tuple.
fn triple<T: Copy>(v: [T; 3]) -> (T, T, T) {
    (v[0], v[1], v[2])
}

/// Per-channel minima and maxima.
type Triple2 = ((f64, f64, f64), (f64, f64, f64));

/// A material record of a library: a named medium with RGB coefficients and the table each
/// channel is looked up in.
#[pyclass(frozen, module = "bssrdf_zoo")]
pub struct Material {
    library: embed::Library,
    record: format::Material,
}

#[pymethods]
impl Material {
    /// The material's name.
    #[getter]
    fn name(&self) -> &str {
        &self.record.name
    }
    /// Where the coefficients come from.
    #[getter]
    fn source(&self) -> &str {
        &self.record.source
    }
    /// Scattering coefficient σs per RGB channel, mm⁻¹.
    #[getter]
    fn sigma_s(&self) -> (f64, f64, f64) {
        triple(self.record.sigma_s)
    }
    /// Absorption coefficient σa per RGB channel, mm⁻¹.
    #[getter]
    fn sigma_a(&self) -> (f64, f64, f64) {
        triple(self.record.sigma_a)
    }
    /// Henyey–Greenstein asymmetry g per RGB channel.
    #[getter]
    fn g(&self) -> (f64, f64, f64) {
        triple(self.record.g)
    }
    /// Relative index of refraction η.
    #[getter]
    fn eta(&self) -> f64 {
        self.record.eta
    }
    /// The index of the table each RGB channel is looked up in.
    #[getter]
    fn tables(&self) -> (u32, u32, u32) {
        triple(self.record.tables)
    }
    /// The reduced-albedo range a scene declared, ((min r, g, b), (max r, g, b)), or None.
    #[getter]
    fn albedo_range(&self) -> Option<Triple2> {
        self.record
            .albedo_range
            .map(|a| (triple(a.min), triple(a.max)))
    }
    /// The lookup handle of one colour channel (see `Library.channel`).
    fn channel(&self, channel: &Bound<'_, PyAny>) -> PyResult<Channel> {
        let rgb = rgb(channel)?;
        let lookup = self
            .library
            .channel(&self.record.name, rgb)
            .map_err(errors::embed)?;
        Ok(Channel::new(
            &self.library,
            lookup,
            self.record.name.clone(),
            Some(rgb),
        ))
    }
    fn __repr__(&self) -> String {
        format!(
            "<bssrdf_zoo.Material {:?}: sigma_s {:?}, sigma_a {:?}, g {:?}, eta {}>",
            self.record.name,
            self.record.sigma_s,
            self.record.sigma_a,
            self.record.g,
            self.record.eta
        )
    }
}

/// One colour channel of a material on its table, in world units: r in mm, S and densities
/// per mm², θ and φ in radians (θ before refraction, φ = 0 forward). Every lookup is the
/// runtime's `ChannelLookup` at each point, broadcast over its arguments.
#[pyclass(frozen, module = "bssrdf_zoo")]
pub struct Channel {
    library: embed::Library,
    lookup: ChannelLookup,
    /// The material's name, or "medium" for `Table.medium`.
    material: String,
    rgb: Option<Rgb>,
}

impl Channel {
    /// `lookup` at every point (θ, r, φ) of `args`, each point refused for θ outside the table.
    fn at_points<'py>(
        &self,
        py: Python<'py>,
        args: [&Arg<'py>; 3],
        lookup: impl Fn(&ChannelLookup, [f64; 3]) -> f64 + Send + Sync,
    ) -> PyResult<Bound<'py, PyAny>> {
        let domain = Domain::of(&self.lookup.table().view());
        let [value] = points::map(py, ["theta", "r", "phi"], args, |point| {
            domain.theta(point[0])?;
            Domain::exit(point[1], point[2])?;
            Ok([lookup(&self.lookup, point)])
        })?;
        Ok(value)
    }

    /// The handle `lookup` on a table of `library`, for messages called `material` and `rgb`.
    pub fn new(
        library: &embed::Library,
        lookup: ChannelLookup,
        material: String,
        rgb: Option<Rgb>,
    ) -> Self {
        Self {
            library: library.clone(),
            lookup,
            material,
            rgb,
        }
    }
}

#[pymethods]
impl Channel {
    /// Reduced albedo ρ′ = σ′s/σ′t of the channel.
    #[getter]
    fn rho_prime(&self) -> f64 {
        self.lookup.rho_prime()
    }
    /// Reduced extinction σ′t = σs(1 − g) + σa of the channel, mm⁻¹.
    #[getter]
    fn sigma_t(&self) -> f64 {
        self.lookup.sigma_t_prime()
    }
    /// The table the channel is looked up in.
    #[getter]
    fn table(&self) -> PyResult<Table> {
        Table::new(&self.library, self.lookup.table().index())
    }

    /// S_p(r, φ; θ) in mm⁻² (multiple scattering per unit power entering); ValueError for θ
    /// outside the table's θ axis.
    fn eval<'py>(
        &self,
        py: Python<'py>,
        theta: Arg<'py>,
        r: Arg<'py>,
        phi: Arg<'py>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.at_points(py, [&theta, &r, &phi], |c, [t, r, p]| {
            c.eval(t, r, p).unwrap_or(0.0)
        })
    }

    /// Density per mm² of `sample` at (r, φ).
    fn pdf<'py>(
        &self,
        py: Python<'py>,
        theta: Arg<'py>,
        r: Arg<'py>,
        phi: Arg<'py>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.at_points(py, [&theta, &r, &phi], |c, [t, r, p]| c.pdf(t, r, p))
    }

    /// Draws the exit point from two uniforms: (r in mm, φ, pdf per mm²); a point with no draw
    /// has r = φ = pdf = 0.
    fn sample<'py>(
        &self,
        py: Python<'py>,
        theta: Arg<'py>,
        u1: Arg<'py>,
        u2: Arg<'py>,
    ) -> PyResult<Sample3<'py>> {
        let domain = Domain::of(&self.lookup.table().view());
        let [r, phi, pdf] = points::map(
            py,
            ["theta", "u1", "u2"],
            [&theta, &u1, &u2],
            |[t, u1, u2]| {
                domain.theta(t)?;
                uniforms(["u1", "u2"], [u1, u2])?;
                Ok(sample_or_zero(self.lookup.sample(t, u1, u2)))
            },
        )?;
        Ok((r, phi, pdf))
    }

    /// The path-tracing draw from four uniforms: (θ, r in mm, φ, φ′, pdf_theta, pdf per mm²);
    /// a point with no draw is all zeros.
    fn sample_path<'py>(
        &self,
        py: Python<'py>,
        u1: Arg<'py>,
        u2: Arg<'py>,
        u3: Arg<'py>,
        u4: Arg<'py>,
    ) -> PyResult<Path6<'py>> {
        path_tracing(self.lookup.table())?;
        let names = ["u1", "u2", "u3", "u4"];
        let drawn = points::map(py, names, [&u1, &u2, &u3, &u4], |u| {
            uniforms(names, u)?;
            Ok(path_or_zero(self.lookup.sample_path(u)))
        })?;
        Ok(path_tuple(drawn))
    }

    /// Density of θ in `sample_path`, per radian; ValueError for θ outside the table.
    fn pdf_theta<'py>(&self, py: Python<'py>, theta: Arg<'py>) -> PyResult<Bound<'py, PyAny>> {
        let domain = Domain::of(&self.lookup.table().view());
        let [p] = points::map(py, ["theta"], [&theta], |[t]| {
            domain.theta(t)?;
            Ok([self.lookup.pdf_theta(t)])
        })?;
        Ok(p)
    }

    /// Effective albedo ρ_eff(θ) = ∫∫ S dA; ValueError for θ outside the table.
    fn effective_albedo<'py>(
        &self,
        py: Python<'py>,
        theta: Arg<'py>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let domain = Domain::of(&self.lookup.table().view());
        let [a] = points::map(py, ["theta"], [&theta], |[t]| {
            domain.theta(t)?;
            Ok([self.lookup.effective_albedo(t).unwrap_or(0.0)])
        })?;
        Ok(a)
    }

    fn __repr__(&self) -> String {
        format!(
            "<bssrdf_zoo.Channel {:?}{}: rho' {}, sigma_t' {} /mm, table {}>",
            self.material,
            self.rgb.map_or(String::new(), |c| format!(" {}", c.name())),
            self.lookup.rho_prime(),
            self.lookup.sigma_t_prime(),
            self.lookup.table().index()
        )
    }
}
