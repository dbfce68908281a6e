//! The native module of the Python package `bssrdf_zoo` (`bssrdf_zoo._native`): the library
//! file and its tables, the bake, the model zoo and the random walk from numpy, over the
//! `bssrdf-zoo` crate. The package's Python files (`bssrdf_zoo/`) re-export it with type stubs.
//!
//! | module | what |
//! |---|---|
//! | `points` | the one per-point loop: numpy broadcasting, the GIL released, arrays back |
//! | `library` | `Library`, `Material`, `Channel` (a material's colour channel, world units) |
//! | `table` | `Table`: lookups in reduced or world units, the stored arrays as views |
//! | `views` | zero-copy read-only numpy views over the file (the crate's only `unsafe`) |
//! | `bake` | `bake`, `bake_materials`, `builtin_materials` |
//! | `models` | `model_eval` (`bssrdf_zoo.models.eval`), `model_names` |
//! | `walk` | `walk` and its result `Walk` |
//! | `errors` | the library's errors as Python exceptions, `FormatError` |
//! | `bench` | `_loop_eval`, the Rust loop `python/benches` times the package against |
//!
//! Values are the Rust API's bit for bit: every lookup is one call of the runtime at each point
//! (`python/tests/` compares them with the `bssrdf` command's).

mod args;
mod bake;
mod bench;
mod errors;
mod library;
mod models;
mod points;
mod table;
mod views;
mod walk;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// Runs `work` on a pool of `threads` threads, or on the global pool (all cores) for None.
fn on_threads<T: Send>(threads: Option<usize>, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    match threads {
        None => Ok(work()),
        // The command line's range: thousands of threads only cost their start-up
        Some(n) if !(1..=bssrdf_zoo::MAX_THREADS).contains(&n) => Err(PyValueError::new_err(
            format!("threads = {n} is outside [1, {}]", bssrdf_zoo::MAX_THREADS),
        )),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map(|pool| pool.install(work))
            .map_err(|e| PyValueError::new_err(format!("threads = {n}: {e}"))),
    }
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("FormatError", m.py().get_type::<errors::FormatError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<library::Library>()?;
    m.add_class::<library::Material>()?;
    m.add_class::<library::Channel>()?;
    m.add_class::<table::Table>()?;
    m.add_class::<walk::Walk>()?;
    m.add_function(wrap_pyfunction!(bake::bake, m)?)?;
    m.add_function(wrap_pyfunction!(bake::bake_materials, m)?)?;
    m.add_function(wrap_pyfunction!(bake::builtin_materials, m)?)?;
    m.add_function(wrap_pyfunction!(models::model_eval, m)?)?;
    m.add_function(wrap_pyfunction!(models::model_names, m)?)?;
    m.add_function(wrap_pyfunction!(walk::walk, m)?)?;
    m.add_function(wrap_pyfunction!(bench::_loop_eval, m)?)?;
    Ok(())
}
