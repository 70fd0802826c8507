//! Memory: a `MemoryError` instead of an aborted interpreter. Two means, used by every entry
//! point whose allocations grow with its input:
//!
//! - an **up-front estimate** against the memory available ([`check`]), for what the library
//!   allocates inside one call (a sphere store, a scene query, a simulation);
//! - **fallible allocation** ([`filled`], [`with_capacity`]) for the buffers the binding
//!   allocates itself (result columns, copies).
//!
//! The memory available is the library's `spheresweep::io::memory` figure, as for the CLI:
//! `SPHERESWEEP_MAX_MEMORY` when set, else the least of `MemAvailable`, what `ulimit -v` leaves
//! and what the cgroup's limit leaves.

use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;

use spheresweep::io::memory::{self, MemoryError, human};

/// `MemoryError` if `bytes` (what `what` needs, estimated) exceed the memory available: raised
/// before anything is allocated, with the estimate and the figure it was compared with
/// (`ValueError` for a malformed `SPHERESWEEP_MAX_MEMORY`).
pub(crate) fn check(what: &str, bytes: usize) -> PyResult<()> {
    memory::check(what, bytes as u64).map_err(|e| match e {
        MemoryError::Setting(m) => PyValueError::new_err(m),
        MemoryError::Refused(m) => PyMemoryError::new_err(m),
    })
}

fn failed<T>(what: &str, n: usize) -> PyErr {
    let bytes = n.saturating_mul(std::mem::size_of::<T>()) as u64;
    PyMemoryError::new_err(format!(
        "{what}: cannot allocate {} ({n} entries)",
        human(bytes)
    ))
}

/// An empty vector with room for `n` entries, or `MemoryError` naming `what`.
pub(crate) fn with_capacity<T>(n: usize, what: &str) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| failed::<T>(what, n))?;
    Ok(v)
}

/// A vector of `n` copies of `value`, or `MemoryError` naming `what`.
pub(crate) fn filled<T: Clone>(n: usize, value: T, what: &str) -> PyResult<Vec<T>> {
    let mut v = with_capacity(n, what)?;
    v.resize(n, value);
    Ok(v)
}
