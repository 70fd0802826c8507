//! The Rust side of the binding-overhead benchmark (python/bench/bench_binding.py).

use pyo3::prelude::*;
use spheresweep::batch;

use crate::batch::{Spheres, options, value_error};

/// Hidden: times the Rust `zip_times` call alone on the stores already inside `a` and `b`,
/// into one output buffer allocated and written once before timing, `repeats` times with the
/// GIL released. Returns each call's wall time in nanoseconds.
#[pyfunction]
pub fn _rust_zip_times_ns(
    py: Python<'_>,
    a: PyRef<'_, Spheres>,
    b: PyRef<'_, Spheres>,
    t_max: f64,
    accuracy: &str,
    repeats: usize,
) -> PyResult<Vec<u64>> {
    let opts = options(t_max, accuracy)?;
    let (a, b) = (&a.store, &b.store);
    py.detach(|| {
        let mut out = vec![0.0f32; a.len()];
        batch::zip_times(a, b, opts, &mut out)?;
        (0..repeats)
            .map(|_| {
                let start = std::time::Instant::now();
                batch::zip_times(a, b, opts, &mut out)?;
                Ok(u64::try_from(start.elapsed().as_nanos()).unwrap_or(u64::MAX))
            })
            .collect::<Result<Vec<u64>, spheresweep::BatchError>>()
    })
    .map_err(value_error)
}
