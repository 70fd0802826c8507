//! The batch entry points (`zip_times`, `pair_times`, `static_times`): NumPy in, NumPy out,
//! the GIL released while the kernels run.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use spheresweep::Accuracy;
use spheresweep::batch;

use crate::args::{self, instance, optional};
use crate::arrays::indices;
use crate::memory;
use crate::shapes::{Takes, static_shape};
use crate::spheres::Spheres;

/// A Rust error as a Python `ValueError` carrying the Rust message.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// An output array given by the caller: float32, 1-D, C-contiguous, writeable, `n` entries.
fn check_out<'py>(out: &Bound<'py, PyAny>, n: usize) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let array = out
        .cast::<PyArray1<f32>>()
        .map_err(|_| args::wrong_type("out", "a 1-D float32 numpy array", out))?;
    if array.len() != n || !array.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "out: expected a C-contiguous array of {n} entries, got {} entries{}",
            array.len(),
            if array.is_c_contiguous() {
                ""
            } else {
                " (not contiguous)"
            }
        )));
    }
    Ok(array.clone())
}

/// Runs `f` on an output slice of `n` float32 entries with the GIL released: into `out` when
/// given (no allocation), into a new array otherwise (`MemoryError` if it cannot be had).
fn with_output<'py>(
    py: Python<'py>,
    n: usize,
    out: Option<&Bound<'py, PyAny>>,
    f: impl FnOnce(&mut [f32]) -> Result<(), spheresweep::BatchError> + Send,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    match optional(out) {
        Some(out) => {
            let array = check_out(out, n)?;
            {
                let mut rw = array.try_readwrite().map_err(|_| {
                    PyValueError::new_err("out: the array is read-only (or in use)")
                })?;
                let slice = rw.as_slice_mut().map_err(value_error)?;
                py.detach(|| f(slice)).map_err(value_error)?;
            }
            Ok(array)
        }
        None => {
            let mut times = memory::filled(n, 0.0f32, "times")?;
            py.detach(|| f(&mut times)).map_err(value_error)?;
            Ok(times.into_pyarray(py))
        }
    }
}

/// Time of impact of `a[i]` with `b[i]` for every `i`: float32 `(N,)`, `inf` where the pair
/// does not touch in `[0, t_max]`. `t_max` is rounded to float32; `accuracy` is one of
/// `ACCURACIES`. `out`, if given, is a C-contiguous float32 `(N,)` array written in place and
/// returned (no allocation). The GIL is released while the kernels run.
///
/// Raises `TypeError` for arguments of the wrong type, `ValueError` if the lengths differ,
/// `t_max` is NaN or negative, or the accuracy is unknown.
#[pyfunction]
#[pyo3(signature = (a, b, *, t_max = None, accuracy = None, out = None),
       text_signature = "(a, b, *, t_max=math.inf, accuracy='stable', out=None)")]
pub fn zip_times<'py>(
    py: Python<'py>,
    a: &Bound<'py, PyAny>,
    b: &Bound<'py, PyAny>,
    t_max: Option<&Bound<'py, PyAny>>,
    accuracy: Option<&Bound<'py, PyAny>>,
    out: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let a = instance::<Spheres>(a, "a", "Spheres")?;
    let b = instance::<Spheres>(b, "b", "Spheres")?;
    let opts = args::options(t_max, accuracy, None)?;
    let (a, b) = (&a.store, &b.store);
    if a.len() != b.len() {
        return Err(value_error(spheresweep::BatchError::StoreLengths {
            a: a.len(),
            b: b.len(),
        }));
    }
    with_output(py, a.len(), out, |out| batch::zip_times(a, b, opts, out))
}

/// Time of impact of each listed pair `(i[k], j[k])` of spheres of `s`: float32 `(P,)`, `inf`
/// for no contact in `[0, t_max]`. `i` and `j` are integer arrays of the same length.
///
/// Raises `TypeError` for non-integer indices, `ValueError` for lengths that differ, negative
/// indices, or an index beyond `len(s)` (the message names the pair).
#[pyfunction]
#[pyo3(signature = (s, i, j, *, t_max = None, accuracy = None, out = None),
       text_signature = "(s, i, j, *, t_max=math.inf, accuracy='stable', out=None)")]
pub fn pair_times<'py>(
    py: Python<'py>,
    s: &Bound<'py, PyAny>,
    i: &Bound<'py, PyAny>,
    j: &Bound<'py, PyAny>,
    t_max: Option<&Bound<'py, PyAny>>,
    accuracy: Option<&Bound<'py, PyAny>>,
    out: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let s = instance::<Spheres>(s, "s", "Spheres")?;
    let opts = args::options(t_max, accuracy, None)?;
    let (i, j) = (indices(i, "i")?, indices(j, "j")?);
    if i.len() != j.len() {
        return Err(PyValueError::new_err(format!(
            "j: {} entries, expected {} (one per pair, as i)",
            j.len(),
            i.len()
        )));
    }
    let mut pairs = memory::with_capacity(i.len(), "pairs")?;
    pairs.extend(i.iter().zip(&j).map(|(&i, &j)| [i, j]));
    drop((i, j));
    let store = &s.store;
    with_output(py, pairs.len(), out, |out| {
        batch::pair_times(store, &pairs, opts, out)
    })
}

/// Time of impact of every sphere of `s` with each static shape of `shapes` (a sequence of
/// `Plane`, `Cylinder` and `Container` in any mix): float32 `(N, len(shapes))`, column `k`
/// for `shapes[k]`, `inf` for no contact in `[0, t_max]`. The GIL is released while the
/// kernels run.
#[pyfunction]
#[pyo3(signature = (s, shapes, *, t_max = None, accuracy = None),
       text_signature = "(s, shapes, *, t_max=math.inf, accuracy='stable')")]
pub fn static_times<'py>(
    py: Python<'py>,
    s: &Bound<'py, PyAny>,
    shapes: &Bound<'py, PyAny>,
    t_max: Option<&Bound<'py, PyAny>>,
    accuracy: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let s = instance::<Spheres>(s, "s", "Spheres")?;
    let opts = args::options(t_max, accuracy, None)?;
    let shapes: Vec<spheresweep::Static> = shapes
        .try_iter()
        .map_err(|_| args::wrong_type("shapes", "a sequence of shapes", shapes))?
        .enumerate()
        .map(|(k, item)| static_shape(&item?, &format!("shapes[{k}]"), Takes::Any))
        .collect::<PyResult<_>>()?;
    let store = &s.store;
    let (n, k) = (store.len(), shapes.len());
    let mut column = memory::filled(n, 0.0f32, "static_times")?;
    let mut table = memory::filled(n.saturating_mul(k), 0.0f32, "static_times")?;
    py.detach(|| {
        for (c, shape) in shapes.iter().enumerate() {
            batch::static_times_any(store, shape, opts, &mut column).expect("one slot each");
            for (i, &t) in column.iter().enumerate() {
                table[i * k + c] = t;
            }
        }
    });
    Ok(Array2::from_shape_vec((n, k), table)
        .expect("n * k entries")
        .into_pyarray(py))
}

/// The accuracy names, cheapest first.
pub(crate) fn accuracies<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
    PyTuple::new(py, Accuracy::ALL.map(Accuracy::name))
}
