//! Scalar and object arguments from Python, each error naming the argument and the type it
//! expects (`t_max: expected a real number, got str`), as docs/python.md promises. Every entry
//! point takes its arguments as `&Bound<PyAny>` and reads them through these functions, since
//! PyO3's own conversion errors do not name the argument.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyString};
use pyo3::{PyClass, PyTypeCheck};
use spheresweep::{Accuracy, QueryOptions};

/// The Python type name of `obj`, for messages.
pub(crate) fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "object".into())
}

/// `TypeError: {name}: expected {what}, got {type of obj}`; a NumPy array is described by
/// its dimensions and dtype (`got a 1-D float64 ndarray`), which its type name does not say.
pub(crate) fn wrong_type(name: &str, what: &str, obj: &Bound<'_, PyAny>) -> PyErr {
    use numpy::{PyUntypedArray, PyUntypedArrayMethods};
    let got = match obj.cast::<PyUntypedArray>() {
        Ok(a) => format!("a {}-D {} ndarray", a.ndim(), a.dtype()),
        Err(_) => type_name(obj),
    };
    PyTypeError::new_err(format!("{name}: expected {what}, got {got}"))
}

/// A float the way Python prints it: shortest round trip, exponent form for large values (so
/// `1e300` is not printed as 301 digits).
pub(crate) fn show(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else {
        format!("{x:?}")
    }
}

/// Whether `obj` is a boolean (Python's or NumPy's), which no numeric argument takes.
pub(crate) fn is_bool(obj: &Bound<'_, PyAny>) -> bool {
    obj.is_instance_of::<PyBool>() || type_name(obj) == "bool"
}

/// An instance of the class `T` (its Python name `class`).
pub(crate) fn instance<'py, T: PyClass + PyTypeCheck>(
    obj: &Bound<'py, PyAny>,
    name: &str,
    class: &str,
) -> PyResult<PyRef<'py, T>> {
    obj.cast::<T>()
        .map(|b| b.borrow())
        .map_err(|_| wrong_type(name, &format!("a {class}"), obj))
}

/// A real number: a Python or NumPy int or float (not a boolean, string or array).
pub(crate) fn real(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    if is_bool(obj) || obj.is_instance_of::<PyString>() || obj.is_instance_of::<PyBytes>() {
        return Err(wrong_type(name, "a real number", obj));
    }
    obj.extract::<f64>()
        .map_err(|_| wrong_type(name, "a real number", obj))
}

/// An integer (a Python or NumPy int, not a boolean or a float) as `i128`, wide enough for
/// every count and seed.
pub(crate) fn integer(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<i128> {
    if is_bool(obj) {
        return Err(wrong_type(name, "an integer", obj));
    }
    let index = obj
        .call_method0("__index__")
        .map_err(|_| wrong_type(name, "an integer", obj))?;
    index
        .extract::<i128>()
        .map_err(|_| PyValueError::new_err(format!("{name}: {index} is out of range")))
}

/// A count: an integer `>= 0`.
pub(crate) fn count(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<usize> {
    let i = integer(obj, name)?;
    usize::try_from(i)
        .map_err(|_| PyValueError::new_err(format!("{name}: {i} is not a count >= 0")))
}

/// An unsigned 64-bit integer (a seed).
pub(crate) fn uint64(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<u64> {
    let i = integer(obj, name)?;
    u64::try_from(i)
        .map_err(|_| PyValueError::new_err(format!("{name}: {i} is not in 0..={}", u64::MAX)))
}

/// A flag: `True` or `False` (Python's or NumPy's), not an integer.
pub(crate) fn flag(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<bool> {
    if !is_bool(obj) {
        return Err(wrong_type(name, "True or False", obj));
    }
    obj.is_truthy()
}

/// A string.
pub(crate) fn text(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<String> {
    obj.cast::<PyString>()
        .map_err(|_| wrong_type(name, "a string", obj))?
        .extract::<String>()
}

/// An optional argument: `None` (or absent) is `None`, and means the argument's default.
pub(crate) fn optional<'a, 'py>(
    obj: Option<&'a Bound<'py, PyAny>>,
) -> Option<&'a Bound<'py, PyAny>> {
    obj.filter(|o| !o.is_none())
}

/// The accuracy mode named by `obj` (default `stable`).
pub(crate) fn accuracy(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Accuracy> {
    let Some(obj) = optional(obj) else {
        return Ok(Accuracy::default());
    };
    let names = Accuracy::ALL
        .map(Accuracy::name)
        .map(|n| format!("{n:?}"))
        .join(", ");
    let name = obj
        .cast::<PyString>()
        .map_err(|_| wrong_type("accuracy", &format!("one of {names}"), obj))?
        .extract::<String>()?;
    name.parse()
        .map_err(|e| PyValueError::new_err(format!("accuracy: {e}")))
}

/// The window's end (default `inf`): a real number `>= 0`.
pub(crate) fn t_max(obj: Option<&Bound<'_, PyAny>>) -> PyResult<f64> {
    optional(obj).map_or(Ok(f64::INFINITY), |o| real(o, "t_max"))
}

/// The query options of `t_max` (rounded to float32), `accuracy` and `geometry`.
pub(crate) fn options(
    t_max_arg: Option<&Bound<'_, PyAny>>,
    accuracy_arg: Option<&Bound<'_, PyAny>>,
    geometry: Option<&Bound<'_, PyAny>>,
) -> PyResult<QueryOptions> {
    let t = t_max(t_max_arg)?;
    let accuracy = accuracy(accuracy_arg)?;
    let geometry = optional(geometry).map_or(Ok(false), |g| flag(g, "geometry"))?;
    Ok(QueryOptions::new(t as f32, accuracy)
        .map_err(|e| PyValueError::new_err(e.to_string()))?
        .with_geometry(geometry))
}
