//! The package's one per-point loop: numpy arguments broadcast together by numpy's rules, a
//! lookup run once per point with the GIL released, and the results back as arrays of the
//! broadcast shape (a float where every argument was a scalar).
//!
//! Every vectorised call of the package (table, channel and model lookups) goes through
//! [`map`], so the loop lives here alone. The arguments become columns of f64 over the broadcast
//! shape in C order: borrowed where an argument already is one (a C-contiguous float64 array of
//! that shape), one value where it is a scalar, copied otherwise. Columns over the points are
//! what the runtime's batch calls take (structures of arrays), so a lookup can move to them
//! here without touching its callers.

use ndarray::{ArrayViewD, IxDyn};
use numpy::{AllowTypeChange, PyArray1, PyArrayLike, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyFloat;

/// A numpy argument: any array-like, converted to float64 by numpy where it is not.
pub type Arg<'py> = PyArrayLike<'py, f64, IxDyn, AllowTypeChange>;

/// The broadcast shape of `shapes` by numpy's rules (dimensions aligned at the end, each equal
/// or 1), or `None` if they do not broadcast.
pub fn broadcast_shape(shapes: &[&[usize]]) -> Option<Vec<usize>> {
    let ndim = shapes.iter().map(|s| s.len()).max().unwrap_or(0);
    let mut shape = vec![1; ndim];
    for s in shapes {
        for (k, &d) in s.iter().rev().enumerate() {
            let slot = &mut shape[ndim - 1 - k];
            if *slot == 1 {
                *slot = d;
            } else if d != 1 && d != *slot {
                return None;
            }
        }
    }
    Some(shape)
}

/// The position of the point at flat index `flat` in `shape` (C order), as Python prints it.
fn position(flat: usize, shape: &[usize]) -> String {
    let mut rest = flat;
    let mut index = vec![0; shape.len()];
    for (k, &d) in shape.iter().enumerate().rev() {
        index[k] = rest % d.max(1);
        rest /= d.max(1);
    }
    let parts: Vec<String> = index.iter().map(usize::to_string).collect();
    match parts.len() {
        1 => parts[0].clone(),
        _ => format!("({})", parts.join(", ")),
    }
}

/// Why [`map`]'s loop stopped: a point the lookup refused (its flat index and message), or no
/// memory for a column of this many values.
enum Failure {
    Point(usize, String),
    Memory(usize),
}

/// An empty vector with room for `n` values, `Err(n)` where there is no memory for them (a
/// broadcast view can ask for more than exists: numpy's `broadcast_to` makes it without
/// memory).
fn values_of(n: usize) -> Result<Vec<f64>, usize> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| n)?;
    Ok(v)
}

/// An argument over the broadcast shape, in C order.
enum Column<'a> {
    /// The argument's own array: it has the broadcast shape and is C-contiguous.
    Borrowed(&'a [f64]),
    /// The argument broadcast and copied.
    Copied(Vec<f64>),
    /// One value for every point.
    Scalar(f64),
}

impl<'a> Column<'a> {
    /// The column of `view` over `shape` (of `n` points); `Err(n)` where memory for a copy of
    /// `n` values cannot be had.
    fn new(view: &ArrayViewD<'a, f64>, shape: &[usize], n: usize) -> Result<Self, usize> {
        if view.shape() == shape {
            if let Some(slice) = view.to_slice() {
                return Ok(Column::Borrowed(slice));
            }
        }
        if view.len() == 1 {
            return Ok(Column::Scalar(
                view.iter().next().copied().unwrap_or_default(),
            ));
        }
        // Row by row along the last axis: a row iterates with one stride, where an iterator
        // over all of a dynamic-dimension view steps a multi-index per element (10 ns each).
        // `shape` is the broadcast of this view's shape with the others', so `broadcast` succeeds.
        let mut copied = values_of(n)?;
        if let Some(b) = view.broadcast(IxDyn(shape)) {
            for row in b.rows() {
                copied.extend(row.iter().copied());
            }
        }
        Ok(Column::Copied(copied))
    }

    /// The values and the step between points: point i reads entry i × step.
    fn values(&self) -> (&[f64], usize) {
        match self {
            Column::Borrowed(s) => (s, 1),
            Column::Copied(v) => (v, 1),
            Column::Scalar(x) => (std::slice::from_ref(x), 0),
        }
    }
}

/// The most dimensions an array argument may have (ndarray's limit; numpy's is 64).
const MAX_DIMENSIONS: usize = 32;

/// Runs `lookup` at every point of the broadcast of `args` (named `names` in messages) with
/// the GIL released and returns its `M` results per point, each as an array of the broadcast
/// shape, or as a float where every argument is a scalar. The first point the lookup refuses
/// (its message, the library's) stops the loop and becomes a ValueError naming the point's
/// index; arguments that do not broadcast are a ValueError naming their shapes.
pub fn map<'py, const N: usize, const M: usize>(
    py: Python<'py>,
    names: [&str; N],
    args: [&Arg<'py>; N],
    mut lookup: impl FnMut([f64; N]) -> Result<[f64; M], String> + Send,
) -> PyResult<[Bound<'py, PyAny>; M]> {
    // ndarray takes at most 32 dimensions (numpy allows 64): refused, naming the argument,
    // before the view that would panic
    for (name, arg) in names.iter().zip(args) {
        if arg.ndim() > MAX_DIMENSIONS {
            return Err(PyValueError::new_err(format!(
                "{name} has {} dimensions: at most {MAX_DIMENSIONS} are taken",
                arg.ndim()
            )));
        }
    }
    // A float64 array that is not aligned (a view at a byte offset into a buffer) is copied
    // first: ndarray reads only aligned values
    let mut aligned: Vec<Option<Arg<'py>>> = Vec::with_capacity(N);
    for arg in args {
        let misaligned = (arg.data() as usize) % std::mem::align_of::<f64>() != 0;
        aligned.push(if misaligned {
            Some(arg.as_any().call_method0("copy")?.extract()?)
        } else {
            None
        });
    }
    let views: [ArrayViewD<'_, f64>; N] =
        std::array::from_fn(|k| aligned[k].as_ref().unwrap_or(args[k]).as_array());
    let shapes: Vec<&[usize]> = views.iter().map(|v| v.shape()).collect();
    let Some(shape) = broadcast_shape(&shapes) else {
        let described: Vec<String> = names
            .iter()
            .zip(&shapes)
            .map(|(name, s)| format!("{name} {s:?}"))
            .collect();
        return Err(PyValueError::new_err(format!(
            "the arguments do not broadcast to one shape: {}",
            described.join(", ")
        )));
    };
    let Some(n) = shape.iter().try_fold(1usize, |n, &d| n.checked_mul(d)) else {
        return Err(PyValueError::new_err(format!(
            "the arguments broadcast to shape {shape:?}, more points than an index can count"
        )));
    };
    let computed = py.detach(|| {
        let mut columns = Vec::with_capacity(N);
        for view in &views {
            columns.push(Column::new(view, &shape, n).map_err(Failure::Memory)?);
        }
        let columns: [(&[f64], usize); N] = std::array::from_fn(|k| columns[k].values());
        let mut out: [Vec<f64>; M] = std::array::from_fn(|_| Vec::new());
        for column in &mut out {
            *column = values_of(n).map_err(Failure::Memory)?;
        }
        for i in 0..n {
            // −0 is 0, in and out (x + 0 changes no other value)
            let point = std::array::from_fn(|k| columns[k].0[i * columns[k].1] + 0.0);
            match lookup(point) {
                Ok(values) => {
                    for (column, value) in out.iter_mut().zip(values) {
                        column.push(value + 0.0);
                    }
                }
                Err(message) => return Err(Failure::Point(i, message)),
            }
        }
        Ok(out)
    });
    let out = computed.map_err(|failure| match failure {
        Failure::Point(i, message) => PyValueError::new_err(if shape.is_empty() {
            message
        } else {
            format!("at index {}: {message}", position(i, &shape))
        }),
        Failure::Memory(n) => PyMemoryError::new_err(format!(
            "the arguments broadcast to shape {shape:?}: no memory for {n} values"
        )),
    })?;
    let mut arrays = Vec::with_capacity(M);
    for column in out {
        arrays.push(if shape.is_empty() {
            PyFloat::new(py, column[0]).into_any()
        } else {
            PyArray1::from_vec(py, column)
                .reshape(shape.clone())?
                .into_any()
        });
    }
    arrays
        .try_into()
        .map_err(|_| PyValueError::new_err("internal error: wrong number of results"))
}
