//! The Rust side of the binding-overhead benchmark (python/bench/bench_binding.py).

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use spheresweep::batch;

use crate::batch::value_error;
use crate::spheres::Spheres;

/// Hidden: times the Rust `zip_times` call alone on the stores already inside `a` and `b`,
/// `repeats` times with the GIL released, and returns each call's wall time in nanoseconds.
/// With `out` (a C-contiguous float32 array of `len(a)` entries) every call writes into it:
/// the same memory the Python call with `out=` writes. Without it every call writes a newly
/// allocated vector (the allocation timed too, as the Python call without `out=` does).
#[pyfunction]
#[pyo3(signature = (a, b, t_max, accuracy, repeats, out = None))]
pub fn _rust_zip_times_ns(
    py: Python<'_>,
    a: PyRef<'_, Spheres>,
    b: PyRef<'_, Spheres>,
    t_max: f64,
    accuracy: &str,
    repeats: usize,
    out: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<u64>> {
    let accuracy: spheresweep::Accuracy = accuracy.parse().map_err(value_error)?;
    let opts = spheresweep::QueryOptions::new(t_max as f32, accuracy).map_err(value_error)?;
    let (a, b) = (&a.store, &b.store);
    let elapsed =
        |start: std::time::Instant| u64::try_from(start.elapsed().as_nanos()).unwrap_or(u64::MAX);
    let result = match out {
        Some(out) => {
            let array = out
                .cast::<PyArray1<f32>>()
                .map_err(|_| PyTypeError::new_err("out: expected a 1-D float32 numpy array"))?;
            let mut rw = array.try_readwrite().map_err(value_error)?;
            let slice = rw.as_slice_mut().map_err(value_error)?;
            py.detach(|| {
                (0..repeats)
                    .map(|_| {
                        let start = std::time::Instant::now();
                        batch::zip_times(a, b, opts, slice)?;
                        Ok(elapsed(start))
                    })
                    .collect::<Result<Vec<u64>, spheresweep::BatchError>>()
            })
        }
        None => py.detach(|| {
            (0..repeats)
                .map(|_| {
                    let start = std::time::Instant::now();
                    let mut fresh = vec![0.0f32; a.len()];
                    batch::zip_times(a, b, opts, &mut fresh)?;
                    let ns = elapsed(start);
                    drop(std::hint::black_box(fresh));
                    Ok(ns)
                })
                .collect::<Result<Vec<u64>, spheresweep::BatchError>>()
        }),
    };
    result.map_err(value_error)
}
