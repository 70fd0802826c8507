//! The Rust side of the binding-overhead benchmark (python/bench/bench_binding.py).

use pyo3::prelude::*;
use spheresweep::batch;

use crate::batch::{Spheres, options, value_error};

/// Hidden: times the Rust `zip_times` call alone on the stores already inside `a` and `b`,
/// `repeats` times with the GIL released, and returns each call's wall time in nanoseconds.
/// With `fresh_output` every call writes a newly allocated output vector (allocation timed
/// too, as the Python call without `out=` does); otherwise one buffer, touched once before
/// timing, is reused (the library's best case).
#[pyfunction]
#[pyo3(signature = (a, b, t_max, accuracy, repeats, fresh_output = false))]
pub fn _rust_zip_times_ns(
    py: Python<'_>,
    a: PyRef<'_, Spheres>,
    b: PyRef<'_, Spheres>,
    t_max: f64,
    accuracy: &str,
    repeats: usize,
    fresh_output: bool,
) -> PyResult<Vec<u64>> {
    let opts = options(t_max, accuracy)?;
    let (a, b) = (&a.store, &b.store);
    let elapsed =
        |start: std::time::Instant| u64::try_from(start.elapsed().as_nanos()).unwrap_or(u64::MAX);
    py.detach(|| {
        let mut out = vec![f32::NAN; a.len()];
        (0..repeats)
            .map(|_| {
                let start = std::time::Instant::now();
                if fresh_output {
                    let mut fresh = vec![0.0f32; a.len()];
                    batch::zip_times(a, b, opts, &mut fresh)?;
                    let ns = elapsed(start);
                    drop(std::hint::black_box(fresh));
                    Ok(ns)
                } else {
                    batch::zip_times(a, b, opts, &mut out)?;
                    Ok(elapsed(start))
                }
            })
            .collect::<Result<Vec<u64>, spheresweep::BatchError>>()
    })
    .map_err(value_error)
}
