//! Zero-copy, read-only numpy views of a table's stored f32 arrays: the package's only `unsafe`
//! code.

use ndarray::{ArrayViewD, IxDyn};
use numpy::PyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A read-only numpy array of shape `shape` over `data`, whose base is `owner`: numpy holds a
/// reference to `owner` for as long as the array (or any view of it) lives.
///
/// `data` must lie in memory that `owner` keeps alive and unchanged: the sections of a library
/// file, which the `embed::Library` inside the package's `Library`, `Table` and `Channel`
/// objects holds (its map, or its buffer for a file read into memory). The runtime never writes
/// to an opened file's memory.
pub fn readonly_f32<'py>(
    owner: &Bound<'py, PyAny>,
    data: &[f32],
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    let view = ArrayViewD::from_shape(IxDyn(shape), data).map_err(|e| {
        PyValueError::new_err(format!("array of {} values as {shape:?}: {e}", data.len()))
    })?;
    // SAFETY: numpy reads `data` through the array for as long as the array lives, and the array
    // keeps `owner` (its base) alive, which keeps `data` alive and unchanged (the contract
    // above). Nothing writes through it: the array is made read-only before any Python code
    // can see it, and numpy refuses to make it writeable again, since its base is not an array
    // and exposes no writeable buffer.
    let array = unsafe { PyArray::borrow_from_array(&view, owner.clone()) };
    array.getattr("flags")?.setattr("writeable", false)?;
    Ok(array.into_any())
}
