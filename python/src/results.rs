//! Results as columns: `FirstContacts` and `Contacts` (arrays as attributes), each also as a
//! dict of 1-D columns (`as_dict`, with `point_x` … `normal_z` for the `(K, 3)` arrays) and as
//! a pandas DataFrame (`to_pandas`); the simulation's events use the same dict form. Both
//! classes pickle as their arrays.

use numpy::{PyArray1, PyArray2, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::PyTypeCheck;
use pyo3::exceptions::{PyImportError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyType};
use spheresweep::ShapeKind;

/// Kind code of "no contact" (`index` is -1 there too). The kinds of bodies have the codes
/// of the Rust `ShapeKind` (and the checkpoint): sphere 0, plane 1, cylinder 2, container 3;
/// the query files code the shapes alike (docs/query-format.md).
pub(crate) const KIND_NONE: u8 = 255;

/// The kind code of a body.
pub(crate) fn kind_code(kind: ShapeKind) -> u8 {
    kind as u8
}

/// Adds `name` to `d`, or for a `(K, 3)` array its three columns `name_x`, `name_y`, `name_z`
/// (copies: a column of a C-order array is strided).
pub(crate) fn put_column(
    d: &Bound<'_, PyDict>,
    name: &str,
    array: &Bound<'_, PyAny>,
) -> PyResult<()> {
    let shape = array.getattr("shape")?.extract::<Vec<usize>>()?;
    if shape.len() == 2 {
        let numpy = d.py().import("numpy")?;
        for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
            let col = array.get_item((pyo3::types::PySlice::full(d.py()), k))?;
            d.set_item(
                format!("{name}_{axis}"),
                numpy.call_method1("ascontiguousarray", (col,))?,
            )?;
        }
        Ok(())
    } else {
        d.set_item(name, array)
    }
}

/// A column given to a result's constructor: an array of exactly its dtype and dimensions
/// (kept as given, not converted: the results pickle as these arrays), else a `TypeError`
/// naming the column and what was given.
fn column<A: PyTypeCheck>(obj: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<Py<A>> {
    obj.cast::<A>().map(|a| a.clone().unbind()).map_err(|_| {
        let got = match obj.cast::<PyUntypedArray>() {
            Ok(a) => format!("a {}-D {} array", a.ndim(), a.dtype()),
            Err(_) => crate::args::type_name(obj),
        };
        PyTypeError::new_err(format!("{name}: expected {what}, got {got}"))
    })
}

/// The optional `(K, 3)` float32 columns `point` and `normal`.
fn geometry_columns(
    point: Option<&Bound<'_, PyAny>>,
    normal: Option<&Bound<'_, PyAny>>,
) -> PyResult<[Option<Py<PyArray2<f32>>>; 2]> {
    let read = |a: Option<&Bound<'_, PyAny>>, name| {
        crate::args::optional(a)
            .map(|a| column(a, name, "a 2-D float32 array"))
            .transpose()
    };
    Ok([read(point, "point")?, read(normal, "normal")?])
}

/// The columns both results have, each read as the dtype its class keeps: `time` float32,
/// `kind` uint8, `index` int64, and the optional geometry.
type SharedColumns = (
    Py<PyArray1<f32>>,
    Py<PyArray1<u8>>,
    Py<PyArray1<i64>>,
    [Option<Py<PyArray2<f32>>>; 2],
);

fn shared_columns(
    time: &Bound<'_, PyAny>,
    kind: &Bound<'_, PyAny>,
    index: &Bound<'_, PyAny>,
    point: Option<&Bound<'_, PyAny>>,
    normal: Option<&Bound<'_, PyAny>>,
) -> PyResult<SharedColumns> {
    Ok((
        column(time, "time", "a 1-D float32 array")?,
        column(kind, "kind", "a 1-D uint8 array")?,
        column(index, "index", "a 1-D int64 array")?,
        geometry_columns(point, normal)?,
    ))
}

/// Refuses result columns that do not line up: each 1-D column as long as `time` (`n` rows),
/// `point` and `normal` both given or neither, each `(n, 3)`, naming the column.
fn same_rows(
    py: Python<'_>,
    n: usize,
    columns: &[(&str, usize)],
    point: &Option<Py<PyArray2<f32>>>,
    normal: &Option<Py<PyArray2<f32>>>,
) -> PyResult<()> {
    let bad = |m: String| Err(pyo3::exceptions::PyValueError::new_err(m));
    for &(name, len) in columns {
        if len != n {
            return bad(format!("{name}: {len} rows, but time has {n}"));
        }
    }
    match (point, normal) {
        (None, None) => Ok(()),
        (Some(p), Some(q)) => {
            for (name, a) in [("point", p), ("normal", q)] {
                let shape = a.bind(py).shape().to_vec();
                if shape != [n, 3] {
                    return bad(format!("{name}: shape {shape:?}, expected [{n}, 3]"));
                }
            }
            Ok(())
        }
        _ => bad("point and normal: give both (the contact geometry) or neither".into()),
    }
}

/// `pandas.DataFrame(columns)`, with an install hint if pandas is missing.
pub(crate) fn data_frame<'py>(columns: &Bound<'py, PyDict>) -> PyResult<Bound<'py, PyAny>> {
    let pandas = columns.py().import("pandas").map_err(|e| {
        PyImportError::new_err(format!(
            "to_pandas needs pandas, which is not installed ({e}): pip install pandas"
        ))
    })?;
    pandas.call_method1("DataFrame", (columns,))
}

/// The earliest contact of every sphere of a scene (from `first_contacts`), as arrays indexed
/// by sphere: `time` float32 (`inf` if none), `kind` uint8 (`KIND_SPHERE`, `KIND_PLANE`,
/// `KIND_CYLINDER`, `KIND_CONTAINER`, or `KIND_NONE`), `index` int64 (the other body's index
/// in its kind, -1 if none), and with `geometry=True` `point` and `normal` float32 `(N, 3)`
/// (NaN if none; else `None`). Ties: spheres, then planes, cylinders, containers, each by
/// index. `as_dict()` and `to_pandas()` give one row per sphere with 1-D columns.
#[pyclass(frozen, module = "spheresweep._native")]
pub struct FirstContacts {
    /// Time of impact per sphere, `inf` for none.
    #[pyo3(get)]
    pub(crate) time: Py<PyArray1<f32>>,
    /// Kind code of the body touched, `KIND_NONE` for none.
    #[pyo3(get)]
    pub(crate) kind: Py<PyArray1<u8>>,
    /// Index of the body touched within its kind, -1 for none.
    #[pyo3(get)]
    pub(crate) index: Py<PyArray1<i64>>,
    /// Contact points `(N, 3)` (NaN for none), or `None` without geometry.
    #[pyo3(get)]
    pub(crate) point: Option<Py<PyArray2<f32>>>,
    /// Unit normals `(N, 3)` pushing the sphere away (NaN for none), or `None`.
    #[pyo3(get)]
    pub(crate) normal: Option<Py<PyArray2<f32>>>,
}

#[pymethods]
impl FirstContacts {
    #[new]
    #[pyo3(signature = (time, kind, index, point = None, normal = None))]
    fn new(
        py: Python<'_>,
        time: &Bound<'_, PyAny>,
        kind: &Bound<'_, PyAny>,
        index: &Bound<'_, PyAny>,
        point: Option<&Bound<'_, PyAny>>,
        normal: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let (time, kind, index, [point, normal]) =
            shared_columns(time, kind, index, point, normal)?;
        let rows = [
            ("kind", kind.bind(py).len()),
            ("index", index.bind(py).len()),
        ];
        same_rows(py, time.bind(py).len(), &rows, &point, &normal)?;
        Ok(Self {
            time,
            kind,
            index,
            point,
            normal,
        })
    }

    fn __len__(&self, py: Python<'_>) -> usize {
        self.time.bind(py).len()
    }

    /// The columns as a dict of 1-D arrays: `time`, `kind`, `index`, and with geometry
    /// `point_x`, `point_y`, `point_z`, `normal_x`, `normal_y`, `normal_z`.
    fn as_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("time", &self.time)?;
        d.set_item("kind", &self.kind)?;
        d.set_item("index", &self.index)?;
        for (name, a) in [("point", &self.point), ("normal", &self.normal)] {
            if let Some(a) = a {
                put_column(&d, name, a.bind(py).as_any())?;
            }
        }
        Ok(d)
    }

    /// A pandas DataFrame of `as_dict()`, one row per sphere (its index the sphere's).
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        data_frame(&self.as_dict(py)?)
    }

    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> (
        Bound<'py, PyType>,
        (
            Py<PyArray1<f32>>,
            Py<PyArray1<u8>>,
            Py<PyArray1<i64>>,
            Option<Py<PyArray2<f32>>>,
            Option<Py<PyArray2<f32>>>,
        ),
    ) {
        let (py, me) = (slf.py(), slf.get());
        (
            slf.get_type(),
            (
                me.time.clone_ref(py),
                me.kind.clone_ref(py),
                me.index.clone_ref(py),
                me.point.as_ref().map(|a| a.clone_ref(py)),
                me.normal.as_ref().map(|a| a.clone_ref(py)),
            ),
        )
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!("FirstContacts(<{} spheres>)", self.__len__(py))
    }
}

/// Every contact in a window (from `all_contacts`), one row each, sorted by time, then
/// sphere, then body: `time` float32, `sphere` uint32, `kind` uint8, `index` int64 (for two
/// spheres `sphere < index`, each pair once), and with `geometry=True` `point` and `normal`
/// float32 `(K, 3)` (else `None`). `as_dict()` and `to_pandas()` give one row per contact
/// with 1-D columns.
#[pyclass(frozen, module = "spheresweep._native")]
pub struct Contacts {
    /// Time of each contact.
    #[pyo3(get)]
    pub(crate) time: Py<PyArray1<f32>>,
    /// The sphere.
    #[pyo3(get)]
    pub(crate) sphere: Py<PyArray1<u32>>,
    /// Kind code of the other body.
    #[pyo3(get)]
    pub(crate) kind: Py<PyArray1<u8>>,
    /// Index of the other body within its kind.
    #[pyo3(get)]
    pub(crate) index: Py<PyArray1<i64>>,
    /// Contact points `(K, 3)`, or `None` without geometry.
    #[pyo3(get)]
    pub(crate) point: Option<Py<PyArray2<f32>>>,
    /// Unit normals `(K, 3)` pushing `sphere` away, or `None`.
    #[pyo3(get)]
    pub(crate) normal: Option<Py<PyArray2<f32>>>,
}

#[pymethods]
impl Contacts {
    #[new]
    #[pyo3(signature = (time, sphere, kind, index, point = None, normal = None))]
    fn new(
        py: Python<'_>,
        time: &Bound<'_, PyAny>,
        sphere: &Bound<'_, PyAny>,
        kind: &Bound<'_, PyAny>,
        index: &Bound<'_, PyAny>,
        point: Option<&Bound<'_, PyAny>>,
        normal: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let (time, kind, index, [point, normal]) =
            shared_columns(time, kind, index, point, normal)?;
        let sphere = column::<PyArray1<u32>>(sphere, "sphere", "a 1-D uint32 array")?;
        let rows = [
            ("sphere", sphere.bind(py).len()),
            ("kind", kind.bind(py).len()),
            ("index", index.bind(py).len()),
        ];
        same_rows(py, time.bind(py).len(), &rows, &point, &normal)?;
        Ok(Self {
            time,
            sphere,
            kind,
            index,
            point,
            normal,
        })
    }

    fn __len__(&self, py: Python<'_>) -> usize {
        self.time.bind(py).len()
    }

    /// The columns as a dict of 1-D arrays: `time`, `sphere`, `kind`, `index`, and with
    /// geometry `point_x` … `normal_z`.
    fn as_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("time", &self.time)?;
        d.set_item("sphere", &self.sphere)?;
        d.set_item("kind", &self.kind)?;
        d.set_item("index", &self.index)?;
        for (name, a) in [("point", &self.point), ("normal", &self.normal)] {
            if let Some(a) = a {
                put_column(&d, name, a.bind(py).as_any())?;
            }
        }
        Ok(d)
    }

    /// A pandas DataFrame of `as_dict()`, one row per contact.
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        data_frame(&self.as_dict(py)?)
    }

    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> (
        Bound<'py, PyType>,
        (
            Py<PyArray1<f32>>,
            Py<PyArray1<u32>>,
            Py<PyArray1<u8>>,
            Py<PyArray1<i64>>,
            Option<Py<PyArray2<f32>>>,
            Option<Py<PyArray2<f32>>>,
        ),
    ) {
        let (py, me) = (slf.py(), slf.get());
        (
            slf.get_type(),
            (
                me.time.clone_ref(py),
                me.sphere.clone_ref(py),
                me.kind.clone_ref(py),
                me.index.clone_ref(py),
                me.point.as_ref().map(|a| a.clone_ref(py)),
                me.normal.as_ref().map(|a| a.clone_ref(py)),
            ),
        )
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!("Contacts(<{} contacts>)", self.__len__(py))
    }
}
