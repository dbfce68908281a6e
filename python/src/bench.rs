//! A timing helper for `python/benches/eval_speed.py`, not part of the package's API: the Rust
//! loop of `crates/zoo/examples/lookup_loop.rs` (one `TableRef::eval` call per point through a
//! view made once, which is also what a point of the runtime's batch call costs) over the same
//! arrays, in the same process, so that the two can be timed in alternation.

use numpy::PyReadonlyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::hint::black_box;
use std::time::Instant;

use crate::table::Table;

/// Σ S over the points by one `TableRef::eval` call each (reduced units), and the seconds the
/// loop took, timed inside it with the GIL released.
#[pyfunction]
pub fn _loop_eval(
    py: Python<'_>,
    table: PyRef<'_, Table>,
    rho: PyReadonlyArray1<'_, f64>,
    theta: PyReadonlyArray1<'_, f64>,
    r: PyReadonlyArray1<'_, f64>,
    phi: PyReadonlyArray1<'_, f64>,
) -> PyResult<(f64, f64)> {
    let slice = |a: &PyReadonlyArray1<'_, f64>| {
        a.as_slice()
            .map(<[f64]>::to_vec)
            .map_err(|_| PyValueError::new_err("the points must be C-contiguous"))
    };
    let (rho, theta, r, phi) = (slice(&rho)?, slice(&theta)?, slice(&r)?, slice(&phi)?);
    let view = table.view()?;
    Ok(py.detach(|| {
        let start = Instant::now();
        let mut acc = 0.0;
        for (((&rho, &theta), &r), &phi) in rho.iter().zip(&theta).zip(&r).zip(&phi) {
            acc += view
                .eval(
                    black_box(rho),
                    black_box(theta),
                    black_box(r),
                    black_box(phi),
                )
                .unwrap_or(0.0);
        }
        (acc, start.elapsed().as_secs_f64())
    }))
}
