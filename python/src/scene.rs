//! The whole-scene query: `Scene`, `first_contacts` and `all_contacts`, results as NumPy
//! arrays.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use spheresweep::contact::Contact;
use spheresweep::scene::Scene as RustScene;
use spheresweep::{ShapeKind, query};

use crate::batch::{AnyStatic, Spheres, any_static, options};

/// Kind code of "no contact".
pub(crate) const KIND_NONE: u8 = 0;

/// The kind code of a body: 1 sphere, 2 plane, 3 cylinder, 4 container.
pub(crate) fn kind_code(kind: ShapeKind) -> u8 {
    match kind {
        ShapeKind::Sphere => 1,
        ShapeKind::Plane => 2,
        ShapeKind::Cylinder => 3,
        ShapeKind::Container => 4,
    }
}

/// Spheres and the static shapes around them, validated: what `first_contacts` and
/// `all_contacts` query. The spheres are copied once into the scene (one pass, no checks
/// again); later queries read them as they are.
///
/// `Scene(spheres, planes=(), cylinders=(), containers=())`: each shape argument a sequence
/// of that kind (`TypeError` naming the item otherwise).
#[pyclass(frozen, module = "spheresweep._native")]
pub struct Scene {
    pub(crate) scene: RustScene,
    /// The shape arguments as given (planes, cylinders, containers).
    given: [Py<PyTuple>; 3],
}

/// A shape argument as a tuple of its items (`TypeError` if it is not iterable).
fn as_tuple<'py>(
    py: Python<'py>,
    items: Option<&Bound<'py, PyAny>>,
    name: &str,
    kind: &str,
) -> PyResult<Bound<'py, PyTuple>> {
    let Some(items) = items else {
        return Ok(PyTuple::empty(py));
    };
    let iter = items
        .try_iter()
        .map_err(|_| PyTypeError::new_err(format!("{name}: expected a sequence of {kind}s")))?;
    PyTuple::new(py, iter.collect::<PyResult<Vec<_>>>()?)
}

/// The items of `items`, each of the kind `pick` keeps (a `TypeError` naming the item else).
fn shapes_of<T>(
    items: &Bound<'_, PyTuple>,
    name: &str,
    kind: &str,
    pick: impl Fn(AnyStatic) -> Option<T>,
) -> PyResult<Vec<T>> {
    items
        .iter()
        .enumerate()
        .map(|(k, item)| {
            let label = format!("{name}[{k}]");
            let wrong = || {
                PyTypeError::new_err(format!(
                    "{label}: expected a {kind}, got {}",
                    item.get_type()
                        .name()
                        .map(|n| n.to_string())
                        .unwrap_or_default()
                ))
            };
            pick(any_static(&item, &label).map_err(|_| wrong())?).ok_or_else(wrong)
        })
        .collect()
}

#[pymethods]
impl Scene {
    #[new]
    #[pyo3(signature = (spheres, planes = None, cylinders = None, containers = None))]
    fn new(
        spheres: PyRef<'_, Spheres>,
        planes: Option<&Bound<'_, PyAny>>,
        cylinders: Option<&Bound<'_, PyAny>>,
        containers: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let py = spheres.py();
        let planes = as_tuple(py, planes, "planes", "Plane")?;
        let cylinders = as_tuple(py, cylinders, "cylinders", "Cylinder")?;
        let containers = as_tuple(py, containers, "containers", "Container")?;
        let scene = RustScene {
            spheres: spheres.store.clone(),
            planes: shapes_of(&planes, "planes", "Plane", |s| match s {
                AnyStatic::Plane(p) => Some(p),
                _ => None,
            })?,
            cylinders: shapes_of(&cylinders, "cylinders", "Cylinder", |s| match s {
                AnyStatic::Cylinder(c) => Some(c),
                _ => None,
            })?,
            containers: shapes_of(&containers, "containers", "Container", |s| match s {
                AnyStatic::Container(k) => Some(k),
                _ => None,
            })?,
        };
        Ok(Self {
            scene,
            given: [planes.unbind(), cylinders.unbind(), containers.unbind()],
        })
    }

    /// The scene's spheres (a new `Spheres`, copied).
    #[getter]
    fn spheres(&self) -> Spheres {
        Spheres {
            store: self.scene.spheres.clone(),
        }
    }

    /// The planes, cylinders and containers as given, each a tuple.
    #[getter]
    fn shapes<'py>(&self, py: Python<'py>) -> (Py<PyTuple>, Py<PyTuple>, Py<PyTuple>) {
        let [p, c, k] = &self.given;
        (p.clone_ref(py), c.clone_ref(py), k.clone_ref(py))
    }

    fn __len__(&self) -> usize {
        self.scene.spheres.len()
    }

    /// Pickling: the class, the spheres and the shapes as given (each pickles to the same
    /// bits), so a rebuilt scene answers every query bit for bit as this one.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> (
        Bound<'py, pyo3::types::PyType>,
        (Spheres, Py<PyTuple>, Py<PyTuple>, Py<PyTuple>),
    ) {
        let (py, me) = (slf.py(), slf.get());
        let (p, c, k) = me.shapes(py);
        (slf.get_type(), (me.spheres(), p, c, k))
    }

    fn __repr__(&self) -> String {
        let s = &self.scene;
        format!(
            "Scene(<{} spheres, {} planes, {} cylinders, {} containers>)",
            s.spheres.len(),
            s.planes.len(),
            s.cylinders.len(),
            s.containers.len()
        )
    }
}

/// Geometry columns being filled: `(K, 3)` points and normals in float32, NaN where none.
struct GeometryColumns {
    point: Vec<f32>,
    normal: Vec<f32>,
}

impl GeometryColumns {
    fn new(k: usize) -> Self {
        Self {
            point: vec![f32::NAN; 3 * k],
            normal: vec![f32::NAN; 3 * k],
        }
    }

    fn set(&mut self, row: usize, c: &Contact) {
        let p = c.point.as_vec3().to_array();
        let n = c.normal.as_vec3().to_array();
        self.point[3 * row..3 * row + 3].copy_from_slice(&p);
        self.normal[3 * row..3 * row + 3].copy_from_slice(&n);
    }

    fn into_arrays(self, py: Python<'_>) -> (Py<PyArray2<f32>>, Py<PyArray2<f32>>) {
        let k = self.point.len() / 3;
        let arr = |v: Vec<f32>| {
            Array2::from_shape_vec((k, 3), v)
                .expect("3 per row")
                .into_pyarray(py)
                .unbind()
        };
        (arr(self.point), arr(self.normal))
    }
}

/// The earliest contact of every sphere of a scene (from `first_contacts`), as arrays indexed
/// by sphere: `time` float32 (`inf` if none), `kind` uint8 (`KIND_NONE`, `KIND_SPHERE`,
/// `KIND_PLANE`, `KIND_CYLINDER`, `KIND_CONTAINER`), `index` int64 (the other body's index in
/// its kind, -1 if none), and with `geometry=True` `point` and `normal` float32 `(N, 3)`
/// (NaN if none; else `None`). Ties: spheres, then planes, cylinders, containers, each by
/// index.
#[pyclass(frozen, module = "spheresweep._native")]
pub struct FirstContacts {
    /// Time of impact per sphere, `inf` for none.
    #[pyo3(get)]
    time: Py<PyArray1<f32>>,
    /// Kind code of the body touched, 0 for none.
    #[pyo3(get)]
    kind: Py<PyArray1<u8>>,
    /// Index of the body touched within its kind, -1 for none.
    #[pyo3(get)]
    index: Py<PyArray1<i64>>,
    /// Contact points `(N, 3)` (NaN for none), or `None` without geometry.
    #[pyo3(get)]
    point: Option<Py<PyArray2<f32>>>,
    /// Unit normals `(N, 3)` pushing the sphere away (NaN for none), or `None`.
    #[pyo3(get)]
    normal: Option<Py<PyArray2<f32>>>,
    len: usize,
}

#[pymethods]
impl FirstContacts {
    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        format!("FirstContacts(<{} spheres>)", self.len)
    }
}

/// Every contact in a window (from `all_contacts`), one row each, sorted by time, then
/// sphere, then body: `time` float32, `sphere` uint32, `kind` uint8, `index` int64 (for two
/// spheres `sphere < index`, each pair once), and with `geometry=True` `point` and `normal`
/// float32 `(K, 3)` (else `None`).
#[pyclass(frozen, module = "spheresweep._native")]
pub struct Contacts {
    /// Time of each contact.
    #[pyo3(get)]
    time: Py<PyArray1<f32>>,
    /// The sphere.
    #[pyo3(get)]
    sphere: Py<PyArray1<u32>>,
    /// Kind code of the other body.
    #[pyo3(get)]
    kind: Py<PyArray1<u8>>,
    /// Index of the other body within its kind.
    #[pyo3(get)]
    index: Py<PyArray1<i64>>,
    /// Contact points `(K, 3)`, or `None` without geometry.
    #[pyo3(get)]
    point: Option<Py<PyArray2<f32>>>,
    /// Unit normals `(K, 3)` pushing `sphere` away, or `None`.
    #[pyo3(get)]
    normal: Option<Py<PyArray2<f32>>>,
    len: usize,
}

#[pymethods]
impl Contacts {
    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self) -> String {
        format!("Contacts(<{} contacts>)", self.len)
    }
}

/// For every sphere of `scene`, its earliest contact in `[0, t_max]` (see `FirstContacts`).
/// `t_max` is rounded to float32; an infinite window tests every pair (no broad phase can
/// cull it). The GIL is released during the query.
#[pyfunction]
#[pyo3(signature = (scene, *, t_max = f64::INFINITY, accuracy = "stable", geometry = false))]
pub fn first_contacts(
    py: Python<'_>,
    scene: PyRef<'_, Scene>,
    t_max: f64,
    accuracy: &str,
    geometry: bool,
) -> PyResult<FirstContacts> {
    let opts = options(t_max, accuracy)?.with_geometry(geometry);
    let scene = &scene.scene;
    let (time, kind, index, geo) = py.detach(|| {
        let hits = query::first_contacts(scene, opts);
        let n = hits.len();
        let (mut time, mut kind, mut index) =
            (vec![f32::INFINITY; n], vec![KIND_NONE; n], vec![-1i64; n]);
        let mut geo = geometry.then(|| GeometryColumns::new(n));
        for (i, hit) in hits.iter().enumerate() {
            if let Some(hit) = hit {
                time[i] = hit.time;
                kind[i] = kind_code(hit.body.kind);
                index[i] = i64::from(hit.body.index);
                if let (Some(g), Some(c)) = (geo.as_mut(), hit.geometry.as_ref()) {
                    g.set(i, c);
                }
            }
        }
        (time, kind, index, geo)
    });
    let len = time.len();
    let (point, normal) = match geo.map(|g| g.into_arrays(py)) {
        Some((p, n)) => (Some(p), Some(n)),
        None => (None, None),
    };
    Ok(FirstContacts {
        time: time.into_pyarray(py).unbind(),
        kind: kind.into_pyarray(py).unbind(),
        index: index.into_pyarray(py).unbind(),
        point,
        normal,
        len,
    })
}

/// Every contact in `[0, t_max]` (see `Contacts`): each sphere pair once, and every sphere
/// with every static shape it touches. `t_max` is required; an infinite window tests every
/// pair. The GIL is released during the query.
#[pyfunction]
#[pyo3(signature = (scene, *, t_max, accuracy = "stable", geometry = false))]
pub fn all_contacts(
    py: Python<'_>,
    scene: PyRef<'_, Scene>,
    t_max: f64,
    accuracy: &str,
    geometry: bool,
) -> PyResult<Contacts> {
    let opts = options(t_max, accuracy)?.with_geometry(geometry);
    let scene = &scene.scene;
    let (time, sphere, kind, index, geo) = py.detach(|| {
        let events = query::all_contacts(scene, opts);
        let time: Vec<f32> = events.iter().map(|e| e.time).collect();
        let sphere: Vec<u32> = events.iter().map(|e| e.sphere).collect();
        let kind: Vec<u8> = events.iter().map(|e| kind_code(e.other.kind)).collect();
        let index: Vec<i64> = events.iter().map(|e| i64::from(e.other.index)).collect();
        let geo = geometry.then(|| {
            let mut g = GeometryColumns::new(events.len());
            for (k, e) in events.iter().enumerate() {
                if let Some(c) = &e.geometry {
                    g.set(k, c);
                }
            }
            g
        });
        (time, sphere, kind, index, geo)
    });
    let len = time.len();
    let (point, normal) = match geo.map(|g| g.into_arrays(py)) {
        Some((p, n)) => (Some(p), Some(n)),
        None => (None, None),
    };
    Ok(Contacts {
        time: time.into_pyarray(py).unbind(),
        sphere: sphere.into_pyarray(py).unbind(),
        kind: kind.into_pyarray(py).unbind(),
        index: index.into_pyarray(py).unbind(),
        point,
        normal,
        len,
    })
}
