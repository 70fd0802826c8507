//! NumPy arrays in: the dtype and shape checks every entry point shares, each error naming the
//! argument. Floating arrays of the target type are borrowed as they are (any strides: ndarray
//! views read them in place); other floating and integer dtypes (real numbers) are converted
//! once by NumPy's `astype` (round to nearest, as Rust's `as f32`); arrays of any other dtype
//! (boolean, complex, strings, objects) are a `TypeError`, and so is a masked array. Lists,
//! tuples, scalars and pandas columns go through `numpy.asarray(x)`: Python ints and floats
//! are read as numbers, strings and booleans keep their dtype and are refused.

use numpy::ndarray::{ArrayViewD, Dimension};
use numpy::{
    Element, PyArrayDescrMethods, PyReadonlyArrayDyn, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::IntoPyDict;

/// The shape an argument must have.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Expect {
    /// One entry per item: `(N,)`.
    Column,
    /// One 3-vector per item: `(N, 3)`.
    Rows3,
    /// One 3-vector: `(3,)`.
    Vector3,
}

impl Expect {
    fn describe(self) -> &'static str {
        match self {
            Expect::Column => "(N,)",
            Expect::Rows3 => "(N, 3)",
            Expect::Vector3 => "(3,)",
        }
    }

    /// The shape of an empty argument.
    fn empty_shape(self) -> Vec<usize> {
        match self {
            Expect::Column => vec![0],
            Expect::Rows3 => vec![0, 3],
            Expect::Vector3 => vec![0],
        }
    }

    fn fits(self, shape: &[usize]) -> bool {
        match self {
            Expect::Column => shape.len() == 1,
            Expect::Rows3 => shape.len() == 2 && shape[1] == 3,
            Expect::Vector3 => shape == [3],
        }
    }
}

/// `obj` as a NumPy array: an array as it is; anything else (lists, tuples, scalars, pandas
/// columns) through `numpy.asarray(obj)`, with no dtype forced, so that strings and booleans
/// keep their own dtype and are refused by the caller (a failure is a `ValueError` naming the
/// argument). An empty sequence becomes an empty array of `empty` (shape with N = 0) and
/// `dtype`, since it has no dtype of its own. A masked array is a `TypeError`: its mask would
/// be ignored.
fn as_ndarray<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    expect: Expect,
    dtype: Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyUntypedArray>> {
    if let Ok(array) = obj.cast::<PyUntypedArray>() {
        if array.hasattr("mask")? && array.hasattr("filled")? {
            return Err(PyTypeError::new_err(format!(
                "{name}: a masked array (its mask would be ignored): pass .filled(value) or \
                 .compressed() instead"
            )));
        }
        return Ok(array.clone());
    }
    let numpy = obj.py().import("numpy")?;
    let array = numpy
        .call_method1("asarray", (obj,))
        .map_err(|e| PyValueError::new_err(format!("{name}: cannot be read as an array ({e})")))?
        .cast_into::<PyUntypedArray>()
        .map_err(|_| {
            PyTypeError::new_err(format!("{name}: numpy.asarray did not give an array"))
        })?;
    if array.len() == 0 && array.ndim() == 1 {
        let empty = numpy.call_method1("zeros", (expect.empty_shape(), dtype))?;
        return empty
            .cast_into::<PyUntypedArray>()
            .map_err(|e| PyTypeError::new_err(e.to_string()));
    }
    Ok(array)
}

fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

fn check_shape(array: &Bound<'_, PyUntypedArray>, name: &str, expect: Expect) -> PyResult<()> {
    let shape = array.shape();
    if expect.fits(shape) {
        Ok(())
    } else {
        Err(PyValueError::new_err(format!(
            "{name}: expected shape {}, got {}",
            expect.describe(),
            shape_text(shape)
        )))
    }
}

/// A real-number array argument as a read-only array of `T` (`f32` or `f64`): borrowed when
/// its dtype is `T`, converted once otherwise (floating or integer dtypes).
///
/// # Errors
/// `TypeError` if its dtype is neither floating nor integer; `ValueError` if its shape is not
/// `expect`.
pub(crate) fn floats<'py, T: Element>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    expect: Expect,
) -> PyResult<PyReadonlyArrayDyn<'py, T>> {
    converted(obj, name, expect, false)
}

/// As [`floats`] for a column of sizes (radii, masses) in `float32`: a positive value so small
/// that `float32` rounds it to zero (below about 1.4·10⁻⁴⁵) is refused too, since a radius of
/// zero is a point and a mass of zero is refused as "not greater than zero", neither of which
/// the caller gave.
pub(crate) fn sizes_f32<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<PyReadonlyArrayDyn<'py, f32>> {
    converted(obj, name, Expect::Column, true)
}

fn converted<'py, T: Element>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    expect: Expect,
    sizes: bool,
) -> PyResult<PyReadonlyArrayDyn<'py, T>> {
    let py = obj.py();
    let array = as_ndarray(obj, name, expect, T::get_dtype(py).into_any())?;
    let dtype = array.dtype();
    if !matches!(dtype.kind(), b'f' | b'i' | b'u') {
        return Err(PyTypeError::new_err(format!(
            "{name}: dtype {} is not a real number type (float or integer)",
            dtype.str()?
        )));
    }
    check_shape(&array, name, expect)?;
    let target = T::get_dtype(py);
    let typed = if dtype.is_equiv_to(&target) {
        array.into_any()
    } else {
        // The copy is refused before NumPy allocates it, as every allocation is.
        converting::<T>(&array, name, &target.str()?.to_string())?;
        if target.kind() == b'f' && target.itemsize() == 4 {
            outside_float32(&array, name, sizes)?;
        }
        array.call_method1("astype", (target,))?
    };
    typed.extract::<PyReadonlyArrayDyn<'py, T>>()
}

/// Refuses a float64 entry that is finite but beyond `float32`'s range (about ±3.4·10³⁸),
/// which the conversion would make infinite, named by its position: the queries compute in
/// `float32`, and "NaN or infinite" would name a value the caller never gave. With `sizes`,
/// also a nonzero entry the conversion would make zero: a positive one as below the range, a
/// negative one as negative (as `-0.0` a radius would pass for a point). A `float64` in the
/// other byte order is read in this one first; other dtypes convert within range (integers) or
/// are left to the conversion (NumPy's `longdouble`).
fn outside_float32(array: &Bound<'_, PyUntypedArray>, name: &str, sizes: bool) -> PyResult<()> {
    let dtype = array.dtype();
    let native;
    let array = if dtype.kind() == b'f'
        && dtype.itemsize() == 8
        && dtype.is_native_byteorder() == Some(false)
    {
        converting::<f64>(array, name, "float64 in this byte order")?;
        native = array
            .call_method1("astype", (numpy::dtype::<f64>(array.py()),))?
            .cast_into::<PyUntypedArray>()?;
        &native
    } else {
        array
    };
    let Ok(wide) = array.extract::<PyReadonlyArrayDyn<'_, f64>>() else {
        return Ok(());
    };
    let lost = |x: f64| sizes && x != 0.0 && x as f32 == 0.0;
    let far = wide
        .as_array()
        .indexed_iter()
        .find(|&(_, &x)| x.is_finite() && ((x as f32).is_infinite() || lost(x)))
        .map(|(at, &x)| {
            (
                at.slice().iter().map(usize::to_string).collect::<Vec<_>>(),
                x,
            )
        });
    let Some((at, x)) = far else {
        return Ok(());
    };
    let at = at.join(", ");
    Err(PyValueError::new_err(if lost(x) && x < 0.0 {
        format!("{name}[{at}]: {x:e} is negative")
    } else {
        let (side, range) = if lost(x) {
            ("below", "smallest about 1.4e-45")
        } else {
            ("beyond", "about ±3.4e38")
        };
        format!(
            "{name}[{at}]: {x:e} is {side} float32's range ({range}), which the queries \
             compute in: choose units that bring it within"
        )
    }))
}

/// Refuses, as a `MemoryError` under the memory budget (`memory::check`), an array whose copy
/// as `T` would not fit: checked before NumPy makes it.
fn converting<T>(array: &Bound<'_, PyUntypedArray>, name: &str, to: &str) -> PyResult<()> {
    let count: usize = array.shape().iter().product();
    crate::memory::check(
        &format!("{name}: its {count} values converted to {to}"),
        count.saturating_mul(std::mem::size_of::<T>()),
    )
}

/// A 3-vector argument (an array or a sequence of three numbers) in `T`.
pub(crate) fn vector3<T: Element + Copy>(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[T; 3]> {
    let array = floats::<T>(obj, name, Expect::Vector3)?;
    let v = array.as_array();
    Ok([v[[0]], v[[1]], v[[2]]])
}

/// An integer index array argument as `u32` indices.
///
/// # Errors
/// `TypeError` if its dtype is not an integer type; `ValueError` if it is not 1-D, or an entry
/// is negative or above `u32::MAX` (named by position).
pub(crate) fn indices(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<u32>> {
    let int64 = numpy::dtype::<i64>(obj.py()).into_any();
    let array = as_ndarray(obj, name, Expect::Column, int64)?;
    let dtype = array.dtype();
    if !matches!(dtype.kind(), b'i' | b'u') {
        return Err(PyTypeError::new_err(format!(
            "{name}: dtype {} is not an integer type",
            dtype.str()?
        )));
    }
    check_shape(&array, name, Expect::Column)?;
    if dtype.itemsize() != 8 {
        converting::<u64>(&array, name, "a 64-bit integer")?;
    }
    // Unsigned entries read as u64, signed as i64 (no copy when already so): an unsigned
    // index above 2⁶³ read as i64 would be named as a negative number.
    if dtype.kind() == b'u' {
        narrowed::<u64>(&array, name, "uint64")
    } else {
        narrowed::<i64>(&array, name, "int64")
    }
}

/// The entries of an integer array, read as `T` (`as_type`, copied only if not already so),
/// each as a `u32` index or the error naming it.
fn narrowed<T>(array: &Bound<'_, PyUntypedArray>, name: &str, as_type: &str) -> PyResult<Vec<u32>>
where
    T: Element + Copy + std::fmt::Display + TryInto<u32>,
{
    let copy = [("copy", false)].into_py_dict(array.py())?;
    let wide = array.call_method("astype", (as_type,), Some(&copy))?;
    let wide = wide.extract::<PyReadonlyArrayDyn<'_, T>>()?;
    let entries = wide.as_array();
    entries
        .iter()
        .enumerate()
        .map(|(k, &i)| {
            i.try_into().map_err(|_| {
                PyValueError::new_err(format!("{name}[{k}]: index {i} is not in 0..=4294967295"))
            })
        })
        .collect()
}

/// Rows of a `(N, 3)` view as arrays.
pub(crate) fn row3<T: Copy>(view: &ArrayViewD<'_, T>, i: usize) -> [T; 3] {
    [view[[i, 0]], view[[i, 1]], view[[i, 2]]]
}
