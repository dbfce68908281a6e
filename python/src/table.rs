//! `Table`: one table of a library (one η), its lookups in reduced units or, given σ′t, in world
//! units, and zero-copy views of its stored arrays.

use bssrdf_zoo::embed::{self, TableLookup};
use bssrdf_zoo::error::in_range;
use bssrdf_zoo::table::{PathSample, RidgeKind, Sample, TableRef, World};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyFloat;

use crate::errors;
use crate::library::Channel;
use crate::points::{self, Arg};
use crate::views::readonly_f32;

/// One table of a library: a baked η, looked up in reduced units (r in reduced mean free paths,
/// S per reduced mfp²) or, with `sigma_t=` (the reduced extinction σ′t, mm⁻¹, broadcast like
/// the other arguments), in world units (r in mm, S per mm²). Angles in radians: θ the
/// incidence before refraction, φ = 0 forward. Every lookup is the runtime's `TableRef` (or
/// `World`) call at each point.
#[pyclass(frozen, module = "bssrdf_zoo")]
pub struct Table {
    library: embed::Library,
    index: usize,
    /// The table's lookups; `None` for a valid table no lookup can interpolate (one node on
    /// an axis, η outside [0.75, 2.5]), whose record stays readable.
    lookup: Option<TableLookup>,
}

impl Table {
    /// The table's lookups, or ValueError saying why it takes none.
    pub(crate) fn lookups(&self) -> PyResult<&TableLookup> {
        match &self.lookup {
            Some(lookup) => Ok(lookup),
            None => Err(self.library.table(self.index).err().map_or_else(
                || PyValueError::new_err(format!("table {}: no lookups", self.index)),
                errors::embed,
            )),
        }
    }

    /// The table's lookups in reduced units.
    pub(crate) fn view(&self) -> PyResult<TableRef<'_>> {
        Ok(self.lookups()?.view())
    }

    /// The view, its domain and σ′t of a lookup: `sigma_t`, or 1 (reduced units).
    fn units<'py>(
        &self,
        py: Python<'py>,
        sigma_t: Option<Arg<'py>>,
    ) -> PyResult<(TableRef<'_>, Domain, Arg<'py>)> {
        let view = self.view()?;
        let st = match sigma_t {
            Some(st) => st,
            None => PyFloat::new(py, 1.0).extract()?,
        };
        Ok((view, Domain::of(&view), st))
    }

    /// `lookup` at every point (ρ′, θ, r, φ) of `args` in the units of `sigma_t`, each point
    /// refused outside the table.
    fn at_points<'py>(
        &self,
        py: Python<'py>,
        [rho, theta, r, phi]: [&Arg<'py>; 4],
        sigma_t: Option<Arg<'py>>,
        lookup: impl Fn(Units<'_>, [f64; 4]) -> f64 + Send + Sync,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (view, domain, st) = self.units(py, sigma_t)?;
        let args = [rho, theta, r, phi, &st];
        let [value] = points::map(py, EVAL_NAMES, args, |[rho, t, r, p, st]| {
            domain.point(rho, t)?;
            Domain::exit(r, p)?;
            Ok([lookup(Units::new(view, st)?, [rho, t, r, p])])
        })?;
        Ok(value)
    }

    /// Table `index` of `library`; ValueError if there is none.
    pub fn new(library: &embed::Library, index: usize) -> PyResult<Self> {
        if index >= library.table_count() {
            // The library's own refusal, which says how many tables it has
            return Err(errors::embed(embed::EmbedError::NoTable {
                index,
                count: library.table_count(),
            }));
        }
        Ok(Self {
            library: library.clone(),
            index,
            lookup: library.table(index).ok(),
        })
    }

    /// The table's record in the file, whose arrays the views borrow.
    pub(crate) fn record(&self) -> PyResult<bssrdf_zoo::format::Table<'_>> {
        let index = self.index;
        self.library
            .format()
            .table(index)
            .ok_or_else(|| PyValueError::new_err(format!("no table {index} in the file")))
    }

    /// A read-only view of one of the table's arrays, `[nρ][nθ][nr]` times `per_node` values
    /// (`per_node` 0: `[nρ][nθ]`), or None if the table does not store it.
    fn array<'py>(
        slf: &Bound<'py, Self>,
        data: impl for<'a> Fn(&bssrdf_zoo::format::Table<'a>) -> Option<&'a [f32]>,
        per_node: usize,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        let record = slf.get().record()?;
        let [n_rho, n_theta, n_r] = record.dims();
        let shape = match per_node {
            0 => vec![n_rho, n_theta],
            1 => vec![n_rho, n_theta, n_r],
            k => vec![n_rho, n_theta, n_r, k],
        };
        data(&record)
            .map(|values| readonly_f32(slf.as_any(), values, &shape))
            .transpose()
    }

    /// A read-only view of one axis.
    fn axis<'py>(
        slf: &Bound<'py, Self>,
        axis: bssrdf_zoo::format::AxisKind,
    ) -> PyResult<Bound<'py, PyAny>> {
        let record = slf.get().record()?;
        let values = record.axis(axis);
        readonly_f32(slf.as_any(), values, &[values.len()])
    }
}

/// What a table's lookups accept: ρ′ within its albedo rows and θ within its θ axis (a table is
/// never extrapolated). A point outside is refused with the library's message.
pub struct Domain {
    rho: [f64; 2],
    theta: [f64; 2],
}

impl Domain {
    /// The domain of `view`.
    pub fn of(view: &TableRef<'_>) -> Self {
        // The values the lookups take: each axis with its ends' f32 rounding
        Self {
            rho: view.rho_domain(),
            theta: view.theta_domain(),
        }
    }

    /// Refuses θ outside the θ axis (or NaN).
    #[inline]
    pub fn theta(&self, theta: f64) -> Result<(), String> {
        Self::within(
            "theta",
            theta,
            self.theta,
            "the table's theta axis (radians)",
        )
    }

    /// Refuses ρ′ outside the albedo rows (or NaN).
    #[inline]
    pub fn rho(&self, rho: f64) -> Result<(), String> {
        Self::within("rho'", rho, self.rho, "the albedo rows the table keeps")
    }

    /// `value` in `[lo, hi]`, else the library's message for it (`in_range`, out of line: the
    /// comparison is on every point's path).
    #[inline]
    fn within(
        name: &'static str,
        value: f64,
        [lo, hi]: [f64; 2],
        what: &str,
    ) -> Result<(), String> {
        if (lo..=hi).contains(&value) {
            return Ok(());
        }
        Err(match in_range(name, value, lo, hi) {
            Ok(_) => format!("{name} = {value} is outside {what}"),
            Err(e) => format!("{e}, {what}"),
        })
    }

    /// Refuses an exit point no lookup can mean: r NaN, negative or infinite, φ not finite
    /// (the command line's domains; beyond the last radius node the value is 0, a value).
    #[inline]
    pub fn exit(r: f64, phi: f64) -> Result<(), String> {
        if !(r.is_finite() && r >= 0.0) {
            return Err(format!(
                "r = {} is outside [0, inf): a finite distance",
                bssrdf_zoo::error::number(r)
            ));
        }
        if !phi.is_finite() {
            return Err(format!(
                "phi = {} is not a finite angle",
                bssrdf_zoo::error::number(phi)
            ));
        }
        Ok(())
    }

    /// Refuses (ρ′, θ) outside the table.
    pub fn point(&self, rho: f64, theta: f64) -> Result<(), String> {
        self.rho(rho)?;
        self.theta(theta)
    }
}

/// Refuses a uniform random number outside [0, 1) (or NaN), named: the samplers' inputs (a
/// broken random stream is an error, not a plausible draw). [0, 1) is the range the C header
/// documents for every uniform (C itself clamps a finite azimuthal one); a radial uniform of 1
/// would draw the end of the axis, where the table holds nothing.
#[inline]
pub fn uniforms<const N: usize>(names: [&str; N], u: [f64; N]) -> Result<(), String> {
    match names
        .into_iter()
        .zip(u)
        .find(|(_, u)| !(0.0..1.0).contains(u))
    {
        None => Ok(()),
        Some((name, u)) => Err(format!(
            "{name} = {} is outside [0, 1): a uniform random number",
            bssrdf_zoo::error::number(u)
        )),
    }
}

/// Refuses the path-tracing draw on a table without the θ CDF it needs.
pub fn path_tracing(table: &TableLookup) -> PyResult<()> {
    if table.view().has_theta_sampling() {
        return Ok(());
    }
    Err(PyValueError::new_err(format!(
        "table {} was baked without theta sampling: no path-tracing draw",
        table.index()
    )))
}

/// (r, φ, pdf) of a draw, or zeros where there is none.
pub fn sample_or_zero(s: Option<Sample>) -> [f64; 3] {
    s.map_or([0.0; 3], |s| [s.r, s.phi, s.pdf])
}

/// (θ, r, φ, φ′, pdf_theta, pdf) of a path-tracing draw, or zeros where there is none.
pub fn path_or_zero(p: Option<PathSample>) -> [f64; 6] {
    p.map_or([0.0; 6], |p| {
        [p.theta, p.r, p.phi, p.phi_prime, p.pdf_theta, p.pdf]
    })
}

/// (r, φ, pdf) arrays of draws.
pub type Sample3<'py> = (Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>);

/// (θ, r, φ, φ′, pdf_theta, pdf) arrays of path-tracing draws.
pub type Path6<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
);

/// The six arrays of path-tracing draws as a tuple.
pub fn path_tuple([a, b, c, d, e, f]: [Bound<'_, PyAny>; 6]) -> Path6<'_> {
    (a, b, c, d, e, f)
}

/// A table's lookups in reduced units, or in world units for σ′t (the runtime's `World`).
/// Reduced units are σ′t = 1, where `World` changes no bit (its factors σ′t, σ′t² and its
/// conversion of r are exact at 1): there the lookups call the `TableRef` itself, a call fewer
/// per point (`python/tests` holds them to `World` at σ′t = 1 and to the `bssrdf` command).
#[derive(Clone, Copy)]
enum Units<'a> {
    Reduced(TableRef<'a>),
    World(World<'a>),
}

impl<'a> Units<'a> {
    /// The lookups of `view` for σ′t, or the library's refusal of σ′t.
    #[inline]
    fn new(view: TableRef<'a>, sigma_t: f64) -> Result<Self, String> {
        if sigma_t == 1.0 {
            return Ok(Units::Reduced(view));
        }
        World::new(view, sigma_t)
            .map(Units::World)
            .map_err(|e| e.to_string())
    }
    #[inline]
    fn eval(&self, rho: f64, theta: f64, r: f64, phi: f64) -> Option<f64> {
        match self {
            Units::Reduced(v) => v.eval(rho, theta, r, phi),
            Units::World(w) => w.eval(rho, theta, r, phi),
        }
    }
    #[inline]
    fn pdf(&self, rho: f64, theta: f64, r: f64, phi: f64) -> f64 {
        match self {
            Units::Reduced(v) => v.pdf(rho, theta, r, phi),
            Units::World(w) => w.pdf(rho, theta, r, phi),
        }
    }
    #[inline]
    fn sample(&self, rho: f64, theta: f64, u1: f64, u2: f64) -> Option<Sample> {
        match self {
            Units::Reduced(v) => v.sample(rho, theta, u1, u2),
            Units::World(w) => w.sample(rho, theta, u1, u2),
        }
    }
    #[inline]
    fn sample_path(&self, rho: f64, u: [f64; 4]) -> Option<PathSample> {
        match self {
            Units::Reduced(v) => v.sample_path(rho, u),
            Units::World(w) => w.sample_path(rho, u),
        }
    }
}

const EVAL_NAMES: [&str; 5] = ["rho", "theta", "r", "phi", "sigma_t"];
const SAMPLE_NAMES: [&str; 5] = ["rho", "theta", "u1", "u2", "sigma_t"];
const PATH_NAMES: [&str; 6] = ["rho", "u1", "u2", "u3", "u4", "sigma_t"];

#[pymethods]
impl Table {
    /// Position of the table in the file.
    #[getter]
    fn index(&self) -> usize {
        self.index
    }
    /// Relative index of refraction η the table was baked for.
    #[getter]
    fn eta(&self) -> PyResult<f64> {
        Ok(self.record()?.eta())
    }
    /// (nρ, nθ, nr).
    #[getter]
    fn dims(&self) -> PyResult<(usize, usize, usize)> {
        let [a, b, c] = self.record()?.dims();
        Ok((a, b, c))
    }
    /// Whether the table keeps the θ CDF that `sample_path` needs.
    #[getter]
    fn has_theta_sampling(&self) -> PyResult<bool> {
        Ok(self.record()?.theta_cdf().is_some())
    }
    /// Whether the table has a second wrapped Cauchy lobe (`harmonics`).
    #[getter]
    fn two_lobes(&self) -> PyResult<bool> {
        Ok(self.record()?.harmonics().is_some())
    }
    /// The model the table tabulates: "pbd-angular" (photon beam diffusion) or "walk-angular"
    /// (the Monte Carlo random walk for one g, format 1.5).
    #[getter]
    fn model(&self) -> PyResult<&'static str> {
        Ok(self.record()?.model().name())
    }
    /// The Henyey–Greenstein g of a walk-angular table's walk, in (−1, 1); None for a table of
    /// another model.
    #[getter]
    fn walk_g(&self) -> PyResult<Option<f64>> {
        Ok(self.record()?.walk().map(|w| w.g))
    }
    /// What a walk-angular table holds: "multiple" (multiple scattering) or "total" (single
    /// scattering included); None for a table of another model.
    #[getter]
    fn walk_component(&self) -> PyResult<Option<&'static str>> {
        Ok(self.record()?.walk().map(|w| w.component.name()))
    }
    /// Whether the table's nodes hold the profile less the analytic ridge of grazing incidence,
    /// which every lookup adds back (its record's `ridge`, format 1.6); False in older files.
    #[getter]
    fn ridge(&self) -> PyResult<bool> {
        Ok(self.record()?.ridge().is_some())
    }
    /// Which ridge the nodes hold the profile less: "none", "flux" (record `ridge` = 1, format
    /// 1.6) or "flux+fluence" (`ridge` = 2).
    #[getter]
    fn ridge_kind(&self) -> PyResult<&'static str> {
        Ok(self.record()?.ridge().name())
    }

    /// ρ′ nodes as stored (f32, read-only, zero-copy).
    #[getter]
    fn rho_nodes<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        Self::axis(slf, bssrdf_zoo::format::AxisKind::Rho)
    }
    /// θ nodes as stored, radians (f32, read-only, zero-copy).
    #[getter]
    fn theta_nodes<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        Self::axis(slf, bssrdf_zoo::format::AxisKind::Theta)
    }
    /// r nodes as stored, reduced mean free paths (f32, read-only, zero-copy).
    #[getter]
    fn r_nodes<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        Self::axis(slf, bssrdf_zoo::format::AxisKind::R)
    }
    /// (E, E_β, c) per node, shape (nρ, nθ, nr, 3) (f32, read-only, zero-copy).
    #[getter]
    fn params<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyAny>>> {
        Self::array(slf, |t| Some(t.gwc_params()), 3)
    }
    /// The radial CDF, shape (nρ, nθ, nr); its last node is ρ_eff (f32, read-only, zero-copy).
    #[getter]
    fn radial_cdf<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyAny>>> {
        Self::array(slf, |t| Some(t.radial_cdf()), 1)
    }
    /// The CDF over θ of ρ_eff, shape (nρ, nθ), or None (f32, read-only, zero-copy).
    #[getter]
    fn theta_cdf<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyAny>>> {
        Self::array(slf, |t| t.theta_cdf(), 0)
    }
    /// (rμ₃, rμ₄) per node of a two-lobe table, shape (nρ, nθ, nr, 2), or None (f32,
    /// read-only, zero-copy).
    #[getter]
    fn harmonics<'py>(slf: &Bound<'py, Self>) -> PyResult<Option<Bound<'py, PyAny>>> {
        Self::array(slf, |t| t.harmonics(), 2)
    }

    /// S(r, φ; ρ′, θ): per reduced mfp² at r in reduced mfp, or with `sigma_t` per mm² at r in
    /// mm. ValueError for (ρ′, θ) outside the table or σ′t outside [1e-9, 1e12] mm⁻¹.
    #[pyo3(signature = (rho, theta, r, phi, *, sigma_t = None))]
    fn eval<'py>(
        &self,
        py: Python<'py>,
        rho: Arg<'py>,
        theta: Arg<'py>,
        r: Arg<'py>,
        phi: Arg<'py>,
        sigma_t: Option<Arg<'py>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.at_points(
            py,
            [&rho, &theta, &r, &phi],
            sigma_t,
            |units, [rho, t, r, p]| units.eval(rho, t, r, p).unwrap_or(0.0),
        )
    }

    /// Density of `sample` at (r, φ), per reduced mfp² (or per mm² with `sigma_t`).
    #[pyo3(signature = (rho, theta, r, phi, *, sigma_t = None))]
    fn pdf<'py>(
        &self,
        py: Python<'py>,
        rho: Arg<'py>,
        theta: Arg<'py>,
        r: Arg<'py>,
        phi: Arg<'py>,
        sigma_t: Option<Arg<'py>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.at_points(
            py,
            [&rho, &theta, &r, &phi],
            sigma_t,
            |units, [rho, t, r, p]| units.pdf(rho, t, r, p),
        )
    }

    /// Draws the exit point from two uniforms: (r, φ, pdf), in reduced units or with `sigma_t`
    /// in mm and per mm². A point with no draw (ρ′ = 0, light beyond the critical angle) has
    /// r = φ = pdf = 0.
    #[pyo3(signature = (rho, theta, u1, u2, *, sigma_t = None))]
    fn sample<'py>(
        &self,
        py: Python<'py>,
        rho: Arg<'py>,
        theta: Arg<'py>,
        u1: Arg<'py>,
        u2: Arg<'py>,
        sigma_t: Option<Arg<'py>>,
    ) -> PyResult<Sample3<'py>> {
        let (view, domain, st) = self.units(py, sigma_t)?;
        let args = [&rho, &theta, &u1, &u2, &st];
        let [r, phi, pdf] = points::map(py, SAMPLE_NAMES, args, |[rho, t, u1, u2, st]| {
            domain.point(rho, t)?;
            uniforms(["u1", "u2"], [u1, u2])?;
            Ok(sample_or_zero(Units::new(view, st)?.sample(rho, t, u1, u2)))
        })?;
        Ok((r, phi, pdf))
    }

    /// The path-tracing draw (Ferrier's algorithm 3) from four uniforms: (θ, r, φ, φ′,
    /// pdf_theta, pdf), r and pdf in reduced units or with `sigma_t` in mm and per mm². A point
    /// with no draw is all zeros; ValueError if the table has no θ CDF.
    #[pyo3(signature = (rho, u1, u2, u3, u4, *, sigma_t = None))]
    #[allow(clippy::too_many_arguments)]
    fn sample_path<'py>(
        &self,
        py: Python<'py>,
        rho: Arg<'py>,
        u1: Arg<'py>,
        u2: Arg<'py>,
        u3: Arg<'py>,
        u4: Arg<'py>,
        sigma_t: Option<Arg<'py>>,
    ) -> PyResult<Path6<'py>> {
        let (view, domain, st) = self.units(py, sigma_t)?;
        path_tracing(self.lookups()?)?;
        let args = [&rho, &u1, &u2, &u3, &u4, &st];
        let drawn = points::map(py, PATH_NAMES, args, |[rho, a, b, c, d, st]| {
            domain.rho(rho)?;
            uniforms(["u1", "u2", "u3", "u4"], [a, b, c, d])?;
            Ok(path_or_zero(
                Units::new(view, st)?.sample_path(rho, [a, b, c, d]),
            ))
        })?;
        Ok(path_tuple(drawn))
    }

    /// Density of θ in `sample_path`, per radian (0 without the θ CDF).
    fn pdf_theta<'py>(
        &self,
        py: Python<'py>,
        rho: Arg<'py>,
        theta: Arg<'py>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let view = self.view()?;
        let domain = Domain::of(&view);
        let [p] = points::map(py, ["rho", "theta"], [&rho, &theta], |[rho, t]| {
            domain.point(rho, t)?;
            Ok([view.pdf_theta(rho, t)])
        })?;
        Ok(p)
    }

    /// Effective albedo ρ_eff(ρ′, θ) = ∫∫ S dA (dimensionless, any units).
    fn effective_albedo<'py>(
        &self,
        py: Python<'py>,
        rho: Arg<'py>,
        theta: Arg<'py>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let view = self.view()?;
        let domain = Domain::of(&view);
        let [a] = points::map(py, ["rho", "theta"], [&rho, &theta], |[rho, t]| {
            domain.point(rho, t)?;
            Ok([view.effective_albedo(rho, t).unwrap_or(0.0)])
        })?;
        Ok(a)
    }

    /// A handle for any medium on this table, ρ′ and σ′t (mm⁻¹) fixed: world units, as a
    /// material's channel. ValueError for ρ′ outside the table's rows or σ′t outside
    /// [1e-9, 1e12] mm⁻¹.
    fn medium(&self, rho_prime: f64, sigma_t: f64) -> PyResult<Channel> {
        // (−0 is 0)
        let lookup = self
            .lookups()?
            .medium(rho_prime + 0.0, sigma_t)
            .map_err(errors::embed)?;
        Ok(Channel::new(
            &self.library,
            lookup,
            "medium".to_owned(),
            None,
        ))
    }

    fn __repr__(&self) -> PyResult<String> {
        let record = self.record()?;
        let [n_rho, n_theta, n_r] = record.dims();
        let walk = record.walk().map_or(String::new(), |w| {
            format!(", walk g {} {}", w.g, w.component.name())
        });
        Ok(format!(
            "<bssrdf_zoo.Table {}: eta {}{walk}, {n_rho} x {n_theta} x {n_r}{}{}{}>",
            self.index,
            record.eta(),
            if record.harmonics().is_some() {
                ", two lobes"
            } else {
                ""
            },
            match record.ridge() {
                RidgeKind::None => "",
                RidgeKind::Flux => ", ridge flux",
                RidgeKind::FluxAndFluence => ", ridge flux+fluence",
            },
            if self.lookup.is_none() {
                ", no lookups"
            } else {
                ""
            }
        ))
    }
}
