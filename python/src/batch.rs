//! Spheres, static shapes and the batch entry points (`zip_times`, `pair_times`,
//! `static_times`): NumPy in, NumPy out, the GIL released while the kernels run.

use numpy::ndarray::{Array2, ArrayView1, ArrayView2, Ix1, Ix2};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use spheresweep::batch::{self, StaticShape};
use spheresweep::store::{Columns, Field, StoreError};
use spheresweep::{Accuracy, QueryOptions, Sphere, SphereStore};

use crate::arrays::{Expect, floats, indices, vector3};

/// A Rust error as a Python `ValueError` carrying the Rust message.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// The query options of `t_max` (rounded to float32) and an accuracy name.
pub(crate) fn options(t_max: f64, accuracy: &str) -> PyResult<QueryOptions> {
    let accuracy: Accuracy = accuracy.parse().map_err(value_error)?;
    QueryOptions::new(t_max as f32, accuracy).map_err(value_error)
}

/// Moving spheres in float32 (centre at t = 0, velocity, radius, mass), validated once and kept
/// in the library's padded column store: every query reads them without another copy or check.
///
/// `Spheres(centres, velocities, radii, masses=None)` takes `(N, 3)`, `(N, 3)`, `(N,)` and
/// optionally `(N,)` arrays (or anything `numpy.asarray` reads). float32 arrays are read in
/// place, whatever their strides; float64 (or another floating dtype) is converted to float32
/// once, rounding to nearest. Without masses every mass is 1.
///
/// Raises `TypeError` for a non-floating dtype, `ValueError` for a wrong shape, mismatched
/// lengths, or an invalid sphere (NaN or infinite value, negative radius, mass not above zero:
/// the message names the sphere and the field, e.g. `sphere 3: sphere radius is negative`).
#[pyclass(frozen, module = "spheresweep._native")]
pub struct Spheres {
    pub(crate) store: SphereStore,
}

/// A checked `(N, 3)` argument as a 2-D view (fixed dimensions index faster than dynamic).
fn rows_view<'a>(a: &'a PyReadonlyArrayDyn<'_, f32>) -> ArrayView2<'a, f32> {
    a.as_array()
        .into_dimensionality::<Ix2>()
        .expect("shape checked as (N, 3)")
}

/// A checked `(N,)` argument as a 1-D view.
fn column_view<'a>(a: &'a PyReadonlyArrayDyn<'_, f32>) -> ArrayView1<'a, f32> {
    a.as_array()
        .into_dimensionality::<Ix1>()
        .expect("shape checked as (N,)")
}

fn invalid(index: usize, e: spheresweep::ShapeError) -> PyErr {
    value_error(StoreError::Invalid { index, source: e })
}

fn rows_mismatch(name: &str, found: usize, expected: usize) -> PyErr {
    PyValueError::new_err(format!(
        "{name}: {found} entries, expected {expected} (one per sphere, as centres)"
    ))
}

impl Spheres {
    /// The store's column `field` as a new vector.
    fn column(&self, field: Field) -> Vec<f32> {
        self.store.column(field).to_vec()
    }

    /// `(N, 3)` of three columns.
    fn rows3<'py>(&self, py: Python<'py>, fields: [Field; 3]) -> Bound<'py, PyArray2<f32>> {
        let [x, y, z] = fields.map(|f| self.store.column(f).to_vec());
        let mut data = Vec::with_capacity(3 * x.len());
        for ((x, y), z) in x.into_iter().zip(y).zip(z) {
            data.extend_from_slice(&[x, y, z]);
        }
        Array2::from_shape_vec((self.store.len(), 3), data)
            .expect("3 entries per sphere")
            .into_pyarray(py)
    }
}

#[pymethods]
impl Spheres {
    #[new]
    #[pyo3(signature = (centres, velocities, radii, masses = None))]
    fn new(
        centres: &Bound<'_, PyAny>,
        velocities: &Bound<'_, PyAny>,
        radii: &Bound<'_, PyAny>,
        masses: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let c = floats::<f32>(centres, "centres", Expect::Rows3)?;
        let v = floats::<f32>(velocities, "velocities", Expect::Rows3)?;
        let r = floats::<f32>(radii, "radii", Expect::Column)?;
        let m = masses
            .map(|m| floats::<f32>(m, "masses", Expect::Column))
            .transpose()?;
        let n = c.shape()[0];
        for (name, len) in [("velocities", v.shape()[0]), ("radii", r.shape()[0])]
            .into_iter()
            .chain(m.as_ref().map(|m| ("masses", m.shape()[0])))
        {
            if len != n {
                return Err(rows_mismatch(name, len, n));
            }
        }
        let (c, v) = (rows_view(&c), rows_view(&v));
        let r = column_view(&r);
        let m = m.as_ref().map(column_view);
        let mut store = SphereStore::with_capacity(n);
        for i in 0..n {
            let row = |a: &ArrayView2<'_, f32>| [a[[i, 0]], a[[i, 1]], a[[i, 2]]];
            let mass = m.as_ref().map_or(1.0, |m| m[i]);
            let s = Sphere::new(row(&c), row(&v), r[i], mass).map_err(|e| invalid(i, e))?;
            store.push(&s);
        }
        Ok(Self { store })
    }

    /// Spheres from eight separate columns `x, y, z, vx, vy, vz, r` and optionally `m`, each
    /// `(N,)` (float32 read in place when contiguous; other floating dtypes converted once).
    /// Errors as for the constructor; a column of another length is named.
    #[staticmethod]
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (x, y, z, vx, vy, vz, r, m = None))]
    fn from_columns(
        x: &Bound<'_, PyAny>,
        y: &Bound<'_, PyAny>,
        z: &Bound<'_, PyAny>,
        vx: &Bound<'_, PyAny>,
        vy: &Bound<'_, PyAny>,
        vz: &Bound<'_, PyAny>,
        r: &Bound<'_, PyAny>,
        m: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let arrays = [
            (x, "x"),
            (y, "y"),
            (z, "z"),
            (vx, "vx"),
            (vy, "vy"),
            (vz, "vz"),
        ]
        .into_iter()
        .chain([(r, "r")])
        .map(|(a, name)| floats::<f32>(a, name, Expect::Column))
        .collect::<PyResult<Vec<_>>>()?;
        let mass = m
            .map(|m| floats::<f32>(m, "m", Expect::Column))
            .transpose()?;
        // Contiguous columns are borrowed as slices; strided ones are copied into a vector.
        let owned: Vec<std::borrow::Cow<'_, [f32]>> = arrays
            .iter()
            .chain(mass.as_ref())
            .map(|a| match a.as_slice() {
                Ok(s) => std::borrow::Cow::Borrowed(s),
                Err(_) => std::borrow::Cow::Owned(column_view(a).to_vec()),
            })
            .collect();
        let columns = Columns {
            x: &owned[0],
            y: &owned[1],
            z: &owned[2],
            vx: &owned[3],
            vy: &owned[4],
            vz: &owned[5],
            r: &owned[6],
            m: owned.get(7).map(|m| &**m),
        };
        let store = SphereStore::from_columns(&columns).map_err(value_error)?;
        Ok(Self { store })
    }

    fn __len__(&self) -> usize {
        self.store.len()
    }

    fn __repr__(&self) -> String {
        format!("Spheres(<{} spheres>)", self.store.len())
    }

    /// Centres at t = 0, a new float32 array `(N, 3)`.
    #[getter]
    fn centres<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        self.rows3(py, [Field::X, Field::Y, Field::Z])
    }

    /// Velocities, a new float32 array `(N, 3)`.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        self.rows3(py, [Field::Vx, Field::Vy, Field::Vz])
    }

    /// Radii, a new float32 array `(N,)`.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        self.column(Field::R).into_pyarray(py)
    }

    /// Masses, a new float32 array `(N,)`.
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        self.store.masses().to_vec().into_pyarray(py)
    }

    /// Pickling: the class and its float32 columns, which rebuild the same bits.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> (
        Bound<'py, pyo3::types::PyType>,
        (
            Bound<'py, PyArray2<f32>>,
            Bound<'py, PyArray2<f32>>,
            Bound<'py, PyArray1<f32>>,
            Bound<'py, PyArray1<f32>>,
        ),
    ) {
        let (py, me) = (slf.py(), slf.get());
        (
            slf.get_type(),
            (
                me.centres(py),
                me.velocities(py),
                me.radii(py),
                me.masses(py),
            ),
        )
    }
}

/// A static infinite plane through `point` with normal `normal` (any non-zero length,
/// normalised here; the sphere is kept on the side the normal points to). Each vector is three
/// real numbers (ints or floats, as a sequence or a NumPy array), rounded to float32.
/// `ValueError` for NaN, infinite or zero-length input, naming the field. Pickles as the
/// float32 inputs, so a rebuilt plane has the same bits.
#[pyclass(frozen, module = "spheresweep._native")]
#[derive(Clone)]
pub struct Plane {
    pub(crate) shape: spheresweep::Plane,
    /// The normal as given (rounded to float32), before normalising: what pickling rebuilds
    /// from, since normalising a normalised vector can change its last bit.
    given_normal: [f32; 3],
}

#[pymethods]
impl Plane {
    #[new]
    fn new(point: &Bound<'_, PyAny>, normal: &Bound<'_, PyAny>) -> PyResult<Self> {
        let given_normal = vector3(normal, "normal")?;
        let shape =
            spheresweep::Plane::new(vector3(point, "point")?, given_normal).map_err(value_error)?;
        Ok(Self {
            shape,
            given_normal,
        })
    }

    /// A point of the plane, as given.
    #[getter]
    fn point(&self) -> (f32, f32, f32) {
        self.shape.point().into()
    }

    /// The unit normal: the normal given, normalised (then rounded to float32).
    #[getter]
    fn normal(&self) -> (f32, f32, f32) {
        self.shape.normal().into()
    }

    /// Pickling: the class and the float32 point and normal as given, which rebuild the same
    /// bits (the normalised normal would not always: re-normalising can move its last bit).
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> (
        Bound<'py, pyo3::types::PyType>,
        ((f32, f32, f32), (f32, f32, f32)),
    ) {
        let me = slf.get();
        (slf.get_type(), (me.point(), me.given_normal.into()))
    }

    fn __repr__(&self) -> String {
        format!(
            "Plane(point={:?}, normal={:?})",
            self.point(),
            self.normal()
        )
    }
}

/// A static infinite cylinder of radius `radius` around the line through `p1` and `p2`
/// (`p1 != p2`). Points are three real numbers each and the radius a real number (ints or
/// floats), rounded to float32. `ValueError` for NaN, infinite or negative input, or
/// `p1 == p2`. Pickles as the float32 inputs (same bits when rebuilt).
#[pyclass(frozen, module = "spheresweep._native")]
#[derive(Clone)]
pub struct Cylinder {
    pub(crate) shape: spheresweep::Cylinder,
    p1: [f32; 3],
    p2: [f32; 3],
}

#[pymethods]
impl Cylinder {
    #[new]
    fn new(p1: &Bound<'_, PyAny>, p2: &Bound<'_, PyAny>, radius: f32) -> PyResult<Self> {
        let (p1, p2) = (vector3(p1, "p1")?, vector3(p2, "p2")?);
        let shape = spheresweep::Cylinder::new(p1, p2, radius).map_err(value_error)?;
        Ok(Self { shape, p1, p2 })
    }

    /// First point of the axis, as given.
    #[getter]
    fn p1(&self) -> (f32, f32, f32) {
        self.p1.into()
    }

    /// Second point of the axis, as given.
    #[getter]
    fn p2(&self) -> (f32, f32, f32) {
        self.p2.into()
    }

    /// Radius.
    #[getter]
    fn radius(&self) -> f32 {
        self.shape.radius()
    }

    /// Pickling: the class and the float32 inputs, which rebuild the same bits.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> (
        Bound<'py, pyo3::types::PyType>,
        ((f32, f32, f32), (f32, f32, f32), f32),
    ) {
        let me = slf.get();
        (slf.get_type(), (me.p1(), me.p2(), me.radius()))
    }

    fn __repr__(&self) -> String {
        format!(
            "Cylinder(p1={:?}, p2={:?}, radius={:?})",
            self.p1,
            self.p2,
            self.radius()
        )
    }
}

/// A static spherical container: the inside of the sphere of `radius` around `centre`; every
/// sphere is meant to move inside it. The centre is three real numbers and the radius a real
/// number (ints or floats), rounded to float32. `ValueError` for NaN, infinite or negative
/// input. Pickles as the float32 inputs (same bits when rebuilt).
#[pyclass(frozen, module = "spheresweep._native")]
#[derive(Clone)]
pub struct Container {
    pub(crate) shape: spheresweep::Container,
}

#[pymethods]
impl Container {
    #[new]
    fn new(centre: &Bound<'_, PyAny>, radius: f32) -> PyResult<Self> {
        let shape =
            spheresweep::Container::new(vector3(centre, "centre")?, radius).map_err(value_error)?;
        Ok(Self { shape })
    }

    /// Centre.
    #[getter]
    fn centre(&self) -> (f32, f32, f32) {
        self.shape.centre().into()
    }

    /// Inner radius.
    #[getter]
    fn radius(&self) -> f32 {
        self.shape.radius()
    }

    /// Pickling: the class and the float32 inputs, which rebuild the same bits.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> (Bound<'py, pyo3::types::PyType>, ((f32, f32, f32), f32)) {
        let me = slf.get();
        (slf.get_type(), (me.centre(), me.radius()))
    }

    fn __repr__(&self) -> String {
        format!(
            "Container(centre={:?}, radius={:?})",
            self.centre(),
            self.radius()
        )
    }
}

/// An output array given by the caller: float32, 1-D, C-contiguous, `n` entries.
fn check_out<'py>(out: &Bound<'py, PyAny>, n: usize) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let array = out
        .cast::<PyArray1<f32>>()
        .map_err(|_| PyTypeError::new_err("out: expected a 1-D float32 numpy array"))?;
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
/// given (no allocation), into a new array otherwise.
fn with_output<'py>(
    py: Python<'py>,
    n: usize,
    out: Option<&Bound<'py, PyAny>>,
    f: impl FnOnce(&mut [f32]) -> Result<(), spheresweep::BatchError> + Send,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    match out {
        Some(out) => {
            let array = check_out(out, n)?;
            {
                let mut rw = array.try_readwrite().map_err(value_error)?;
                let slice = rw.as_slice_mut().map_err(value_error)?;
                py.detach(|| f(slice)).map_err(value_error)?;
            }
            Ok(array)
        }
        None => {
            let times = py.detach(|| {
                let mut times = vec![0.0f32; n];
                f(&mut times).map(|()| times)
            });
            Ok(times.map_err(value_error)?.into_pyarray(py))
        }
    }
}

/// Time of impact of `a[i]` with `b[i]` for every `i`: float32 `(N,)`, `inf` where the pair
/// does not touch in `[0, t_max]`. `t_max` is rounded to float32; `accuracy` is one of
/// `ACCURACIES`. `out`, if given, is a C-contiguous float32 `(N,)` array written in place and
/// returned (no allocation). The GIL is released while the kernels run.
///
/// Raises `ValueError` if the lengths differ, `t_max` is NaN or negative, or the accuracy is
/// unknown.
#[pyfunction]
#[pyo3(signature = (a, b, *, t_max = f64::INFINITY, accuracy = "stable", out = None))]
pub fn zip_times<'py>(
    py: Python<'py>,
    a: PyRef<'py, Spheres>,
    b: PyRef<'py, Spheres>,
    t_max: f64,
    accuracy: &str,
    out: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let opts = options(t_max, accuracy)?;
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
#[pyo3(signature = (s, i, j, *, t_max = f64::INFINITY, accuracy = "stable", out = None))]
pub fn pair_times<'py>(
    py: Python<'py>,
    s: PyRef<'py, Spheres>,
    i: &Bound<'py, PyAny>,
    j: &Bound<'py, PyAny>,
    t_max: f64,
    accuracy: &str,
    out: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyArray1<f32>>> {
    let opts = options(t_max, accuracy)?;
    let (i, j) = (indices(i, "i")?, indices(j, "j")?);
    if i.len() != j.len() {
        return Err(PyValueError::new_err(format!(
            "j: {} entries, expected {} (one per pair, as i)",
            j.len(),
            i.len()
        )));
    }
    let pairs: Vec<[u32; 2]> = i.iter().zip(&j).map(|(&i, &j)| [i, j]).collect();
    let store = &s.store;
    with_output(py, pairs.len(), out, |out| {
        batch::pair_times(store, &pairs, opts, out)
    })
}

/// A static shape handed over from Python.
#[derive(Clone, Copy)]
pub(crate) enum AnyStatic {
    Plane(spheresweep::Plane),
    Cylinder(spheresweep::Cylinder),
    Container(spheresweep::Container),
}

/// `obj` as one of the static shapes, or a `TypeError` naming `name`.
pub(crate) fn any_static(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<AnyStatic> {
    if let Ok(p) = obj.cast::<Plane>() {
        Ok(AnyStatic::Plane(p.get().shape))
    } else if let Ok(c) = obj.cast::<Cylinder>() {
        Ok(AnyStatic::Cylinder(c.get().shape))
    } else if let Ok(k) = obj.cast::<Container>() {
        Ok(AnyStatic::Container(k.get().shape))
    } else {
        Err(PyTypeError::new_err(format!(
            "{name}: expected a Plane, Cylinder or Container, got {}",
            obj.get_type().name()?
        )))
    }
}

fn times_against<K: StaticShape>(
    store: &SphereStore,
    shape: &K,
    opts: QueryOptions,
    out: &mut [f32],
) {
    batch::static_times(store, shape, opts, out).expect("one slot per sphere");
}

/// Time of impact of every sphere of `s` with each static shape of `shapes` (a sequence of
/// `Plane`, `Cylinder` and `Container` in any mix): float32 `(N, len(shapes))`, column `k`
/// for `shapes[k]`, `inf` for no contact in `[0, t_max]`. The GIL is released while the
/// kernels run.
#[pyfunction]
#[pyo3(signature = (s, shapes, *, t_max = f64::INFINITY, accuracy = "stable"))]
pub fn static_times<'py>(
    py: Python<'py>,
    s: PyRef<'py, Spheres>,
    shapes: &Bound<'py, PyAny>,
    t_max: f64,
    accuracy: &str,
) -> PyResult<Bound<'py, PyArray2<f32>>> {
    let opts = options(t_max, accuracy)?;
    let shapes: Vec<AnyStatic> = shapes
        .try_iter()
        .map_err(|_| PyTypeError::new_err("shapes: expected a sequence of shapes"))?
        .enumerate()
        .map(|(k, item)| any_static(&item?, &format!("shapes[{k}]")))
        .collect::<PyResult<_>>()?;
    let store = &s.store;
    let (n, k) = (store.len(), shapes.len());
    let table = py.detach(|| {
        let mut column = vec![0.0f32; n];
        let mut table = vec![0.0f32; n * k];
        for (c, shape) in shapes.iter().enumerate() {
            match shape {
                AnyStatic::Plane(p) => times_against(store, p, opts, &mut column),
                AnyStatic::Cylinder(p) => times_against(store, p, opts, &mut column),
                AnyStatic::Container(p) => times_against(store, p, opts, &mut column),
            }
            for (i, &t) in column.iter().enumerate() {
                table[i * k + c] = t;
            }
        }
        table
    });
    Ok(Array2::from_shape_vec((n, k), table)
        .expect("n * k entries")
        .into_pyarray(py))
}

/// The accuracy names, cheapest first.
pub(crate) fn accuracies<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
    PyTuple::new(py, Accuracy::ALL.map(Accuracy::name))
}
