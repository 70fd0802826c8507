//! `Spheres`: moving spheres from NumPy arrays, validated once into the library's column store;
//! their columns back out as new arrays; length, selection, equality and pickling.

use numpy::ndarray::{Array2, ArrayView1, ArrayView2, Ix1, Ix2};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyReadonlyArrayDyn, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyIndexError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyType;
use spheresweep::store::{Columns, Field, StoreError};
use spheresweep::{Sphere, SphereStore};

use crate::arrays::{Expect, floats, sizes_f32};
use crate::batch::value_error;
use crate::memory;

/// Bytes a sphere takes in a store (seven float32 fields in blocks of eight, and its mass).
pub(crate) const STORE_BYTES: usize = 32;

/// Moving spheres in float32 (centre at t = 0, velocity, radius, mass), validated once and kept
/// in the library's padded column store: every query reads them without another copy or check.
///
/// `Spheres(centres, velocities, radii, masses=None)` takes `(N, 3)`, `(N, 3)`, `(N,)` and
/// optionally `(N,)` arrays (or anything `numpy.asarray` reads as real numbers). float32
/// arrays are read in place, whatever their strides; other floating and integer dtypes are
/// converted to float32 once, rounding to nearest. Without masses every mass is 1.
///
/// `len(s)`, `s[key]` (an int, a slice, an index array or a boolean mask: a new `Spheres` of
/// the selected spheres, copied) and `s == t` (the same spheres in the same order).
///
/// Raises `TypeError` for a dtype that is not real numbers, `ValueError` for a wrong shape,
/// mismatched lengths, or an invalid sphere (the message names the sphere and the field, e.g.
/// `sphere 3: radius is negative`), `MemoryError` for more spheres than memory holds.
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

fn rows_mismatch(name: &str, found: usize, expected: usize) -> PyErr {
    PyValueError::new_err(format!(
        "{name}: {found} entries, expected {expected} (one per sphere, as centres)"
    ))
}

/// An empty store with room for `n` spheres, `MemoryError` if memory cannot hold it.
pub(crate) fn store_for(n: usize, what: &str) -> PyResult<SphereStore> {
    memory::check(
        &format!("{what}: {n} spheres"),
        n.saturating_mul(STORE_BYTES),
    )?;
    Ok(SphereStore::with_capacity(n))
}

impl Spheres {
    /// The store's column `field` as a new vector (`MemoryError` if it cannot be allocated).
    fn column(&self, field: Field) -> PyResult<Vec<f32>> {
        let mut out = memory::filled(self.store.len(), 0.0, "Spheres column")?;
        self.store
            .column(field)
            .copy_to(&mut out)
            .map_err(value_error)?;
        Ok(out)
    }

    /// `(N, 3)` of three columns.
    fn rows3<'py>(
        &self,
        py: Python<'py>,
        fields: [Field; 3],
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let n = self.store.len();
        let mut data = memory::with_capacity(3 * n, "Spheres rows")?;
        let columns = fields.map(|f| self.store.column(f));
        for i in 0..n {
            data.extend(columns.iter().map(|c| c.get(i).expect("i < len")));
        }
        Ok(Array2::from_shape_vec((n, 3), data)
            .expect("3 entries per sphere")
            .into_pyarray(py))
    }

    /// The spheres at `indices` (each in range), in that order, as a new `Spheres`.
    fn select(&self, indices: &[i64]) -> PyResult<Self> {
        let mut store = store_for(indices.len(), "Spheres selection")?;
        for &i in indices {
            let s = usize::try_from(i).ok().and_then(|i| self.store.get(i));
            store.push(&s.expect("numpy checked the indices"));
        }
        Ok(Self { store })
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
        let r = sizes_f32(radii, "radii")?;
        let m = crate::args::optional(masses)
            .map(|m| sizes_f32(m, "masses"))
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
        let mut store = store_for(n, "Spheres")?;
        for i in 0..n {
            let row = |a: &ArrayView2<'_, f32>| [a[[i, 0]], a[[i, 1]], a[[i, 2]]];
            let mass = m.as_ref().map_or(1.0, |m| m[i]);
            let s = Sphere::new(row(&c), row(&v), r[i], mass)
                .map_err(|source| value_error(StoreError::Invalid { index: i, source }))?;
            store.push(&s);
        }
        Ok(Self { store })
    }

    /// Spheres from eight separate columns `x, y, z, vx, vy, vz, r` and optionally `m`, each
    /// `(N,)` (float32 read in place when contiguous; other real dtypes converted once).
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
        let named = [
            (x, "x"),
            (y, "y"),
            (z, "z"),
            (vx, "vx"),
            (vy, "vy"),
            (vz, "vz"),
            (r, "r"),
        ];
        let arrays = named
            .into_iter()
            .chain(crate::args::optional(m).map(|m| (m, "m")))
            .map(|(a, name)| match name {
                "r" | "m" => sizes_f32(a, name),
                _ => floats::<f32>(a, name, Expect::Column),
            })
            .collect::<PyResult<Vec<_>>>()?;
        let n = arrays[0].len();
        // The store, and a copy of each strided column, must fit.
        let strided = arrays.iter().filter(|a| a.as_slice().is_err()).count();
        memory::check(
            &format!("Spheres.from_columns: {n} spheres"),
            n.saturating_mul(STORE_BYTES + 4 * strided),
        )?;
        // Contiguous columns are borrowed as slices; strided ones are copied into a vector.
        let owned: Vec<std::borrow::Cow<'_, [f32]>> = arrays
            .iter()
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

    /// The spheres `key` selects (an int, a slice, an integer array or a boolean mask, as
    /// NumPy indexes a 1-D array), as a new `Spheres`; an int gives a `Spheres` of one.
    fn __getitem__(&self, key: &Bound<'_, PyAny>) -> PyResult<Self> {
        let n = self.store.len();
        match int_key(key, n)? {
            Some(k) => self.select(&[k]),
            None => self.select(&array_key(key, n)?),
        }
    }

    /// The same spheres in the same order (every field equal).
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        let Ok(other) = other.cast::<Spheres>() else {
            return false;
        };
        let other = &other.get().store;
        other.len() == self.store.len() && self.store.iter().eq(other.iter())
    }

    fn __repr__(&self) -> String {
        format!("Spheres(<{} spheres>)", self.store.len())
    }

    /// Centres at t = 0, a new float32 array `(N, 3)`.
    #[getter]
    fn centres<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        self.rows3(py, [Field::X, Field::Y, Field::Z])
    }

    /// Velocities, a new float32 array `(N, 3)`.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        self.rows3(py, [Field::Vx, Field::Vy, Field::Vz])
    }

    /// Radii, a new float32 array `(N,)`.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f32>>> {
        Ok(self.column(Field::R)?.into_pyarray(py))
    }

    /// Masses, a new float32 array `(N,)`.
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let mut out = memory::with_capacity(self.store.len(), "Spheres masses")?;
        out.extend_from_slice(self.store.masses());
        Ok(out.into_pyarray(py))
    }

    /// Pickling: the class and its float32 columns, which rebuild the same bits.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(
        Bound<'py, PyType>,
        (
            Bound<'py, PyArray2<f32>>,
            Bound<'py, PyArray2<f32>>,
            Bound<'py, PyArray1<f32>>,
            Bound<'py, PyArray1<f32>>,
        ),
    )> {
        let (py, me) = (slf.py(), slf.get());
        Ok((
            slf.get_type(),
            (
                me.centres(py)?,
                me.velocities(py)?,
                me.radii(py)?,
                me.masses(py)?,
            ),
        ))
    }
}

/// `s[i]` out of range, in Python's own words for lists.
fn out_of_range(i: i128, n: usize) -> PyErr {
    PyIndexError::new_err(format!("index {i} is out of range for {n} spheres"))
}

/// A Python or NumPy int key (not a bool, not an array) as an index in `0..n`, counted from
/// the end if negative; `None` for any other key. Read whole: NumPy's own reading overflows
/// past 2⁶³, and a key past i128 (`s[2**200]`) is out of range too.
fn int_key(key: &Bound<'_, PyAny>, n: usize) -> PyResult<Option<i64>> {
    if key.cast::<PyUntypedArray>().is_ok()
        || crate::args::is_bool(key)
        || !key.hasattr("__index__")?
    {
        return Ok(None);
    }
    let i = crate::args::integer(key, "index")
        .map_err(|e| PyIndexError::new_err(e.value(key.py()).to_string()))?;
    let k = if i < 0 { i + n as i128 } else { i };
    if !(0..n as i128).contains(&k) {
        return Err(out_of_range(i, n));
    }
    Ok(Some(k as i64))
}

/// The indices a slice, an integer array or a boolean mask selects from `n` spheres, as NumPy
/// selects them from `arange(n)`. Unsigned indices are checked first: NumPy casts them to
/// signed ones, which reads one past 2⁶³ as negative (and so in range, from the end).
fn array_key(key: &Bound<'_, PyAny>, n: usize) -> PyResult<Vec<i64>> {
    let numpy = key.py().import("numpy")?;
    let array = numpy.call_method1("asarray", (key,))?;
    let kind = array
        .getattr("dtype")?
        .getattr("kind")?
        .extract::<String>()?;
    if kind == "u" && array.getattr("size")?.extract::<usize>()? > 0 {
        let largest = (array.call_method0("max")?.call_method0("__int__")?).extract::<i128>()?;
        if largest >= n as i128 {
            return Err(out_of_range(largest, n));
        }
    }
    let picked = numpy.call_method1("arange", (n as i64,))?.get_item(key)?;
    let picked = numpy.call_method1("atleast_1d", (picked,))?;
    let picked: PyReadonlyArrayDyn<'_, i64> = picked.extract()?;
    Ok(picked
        .as_slice()
        .map(<[i64]>::to_vec)
        .unwrap_or_else(|_| picked.as_array().iter().copied().collect()))
}
