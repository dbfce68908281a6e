//! Whole-number arguments of unsigned type. pyo3's own conversion answers a negative or too
//! large int with an `OverflowError` that names neither the argument nor the value
//! ("can't convert negative int to unsigned"); these are `ValueError`s that name both, as
//! every other refusal of the package does. Used with `#[pyo3(from_py_with = …)]`; a value that
//! is not an int keeps pyo3's `TypeError`, which names the argument.

use pyo3::exceptions::{PyOverflowError, PyValueError};
use pyo3::prelude::*;

/// `obj` as a u64, or a ValueError naming `name`, the value and the range.
fn whole(name: &str, obj: &Bound<'_, PyAny>, max: u64) -> PyResult<u64> {
    let out_of_range = |obj: &Bound<'_, PyAny>| {
        let shown = obj.str().map(|s| s.to_string()).unwrap_or_default();
        let negative = obj.lt(0).unwrap_or(false);
        let why = if negative {
            "is negative"
        } else {
            "is too large"
        };
        PyValueError::new_err(format!(
            "{name} = {shown} {why}: a whole number in [0, {max}]"
        ))
    };
    match obj.extract::<u64>() {
        Ok(v) if v <= max => Ok(v),
        Ok(_) => Err(out_of_range(obj)),
        Err(e) if e.is_instance_of::<PyOverflowError>(obj.py()) => Err(out_of_range(obj)),
        Err(e) => Err(e),
    }
}

/// `photons`: a count of photons.
pub fn photons(obj: &Bound<'_, PyAny>) -> PyResult<u64> {
    whole("photons", obj, u64::MAX)
}

/// `seed`: a seed of the random stream.
pub fn seed(obj: &Bound<'_, PyAny>) -> PyResult<u64> {
    whole("seed", obj, u64::MAX)
}

/// `index`: a position in a file.
pub fn index(obj: &Bound<'_, PyAny>) -> PyResult<usize> {
    Ok(whole("index", obj, usize::MAX as u64)? as usize)
}

/// `threads`: None (all cores) or a count, whose range `crate::on_threads` checks.
pub fn threads(obj: &Bound<'_, PyAny>) -> PyResult<Option<usize>> {
    if obj.is_none() {
        return Ok(None);
    }
    Ok(Some(whole("threads", obj, usize::MAX as u64)? as usize))
}

/// `lobes`: None (by η), 1 or 2; any other int (negative and huge ones too) is refused by
/// `bake::Settings`, which names the choices, as 0.
pub fn lobes(obj: &Bound<'_, PyAny>) -> PyResult<Option<i64>> {
    if obj.is_none() {
        return Ok(None);
    }
    match obj.extract::<i64>() {
        Ok(n) => Ok(Some(n)),
        Err(e) if e.is_instance_of::<PyOverflowError>(obj.py()) => {
            let shown = obj.str().map(|s| s.to_string()).unwrap_or_default();
            Err(PyValueError::new_err(format!(
                "lobes = {shown} is not one of None (by eta), 1, 2"
            )))
        }
        Err(e) => Err(e),
    }
}

/// `bins`: None, or (r_min, r_max, radial count, azimuthal count), the counts whole numbers
/// named `bins[2]` and `bins[3]` when refused.
pub fn bins(obj: &Bound<'_, PyAny>) -> PyResult<Option<(f64, f64, usize, usize)>> {
    if obj.is_none() {
        return Ok(None);
    }
    let (r_min, r_max, radial, phi): (f64, f64, Bound<'_, PyAny>, Bound<'_, PyAny>) =
        obj.extract()?;
    let count = |name: &str, v: &Bound<'_, PyAny>| -> PyResult<usize> {
        Ok(whole(name, v, usize::MAX as u64)? as usize)
    };
    Ok(Some((
        r_min,
        r_max,
        count("bins[2]", &radial)?,
        count("bins[3]", &phi)?,
    )))
}
