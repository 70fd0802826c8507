//! The whole-scene query: `Scene`, `first_contacts` and `all_contacts`, refused up front with
//! a `MemoryError` when the estimated peak (linear in the spheres, plus the contacts of
//! `all_contacts`) exceeds the memory available, results as NumPy arrays.

use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::prelude::*;
use pyo3::types::{PyTuple, PyType};
use spheresweep::contact::Contact;
use spheresweep::query::{self, estimate};
use spheresweep::scene::Scene as RustScene;
use spheresweep::{QueryOptions, ShapeKind, Static};

use crate::args::{self, instance, show};
use crate::memory;
use crate::results::{Contacts, FirstContacts, KIND_NONE, kind_code};
use crate::shapes::{Takes, static_shape};
use crate::spheres::{STORE_BYTES, Spheres};

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

/// A shape argument as a tuple of its items, each checked to be of the kind `takes` names.
pub(crate) fn shape_items<'py>(
    py: Python<'py>,
    items: Option<&Bound<'py, PyAny>>,
    name: &str,
    takes: Takes,
) -> PyResult<(Bound<'py, PyTuple>, Vec<Static>)> {
    let Some(items) = args::optional(items) else {
        return Ok((PyTuple::empty(py), Vec::new()));
    };
    let iter = items
        .try_iter()
        .map_err(|_| args::wrong_type(name, "a sequence of shapes", items))?;
    let tuple = PyTuple::new(py, iter.collect::<PyResult<Vec<_>>>()?)?;
    let shapes = tuple
        .iter()
        .enumerate()
        .map(|(k, item)| static_shape(&item, &format!("{name}[{k}]"), takes))
        .collect::<PyResult<_>>()?;
    Ok((tuple, shapes))
}

#[pymethods]
impl Scene {
    #[new]
    #[pyo3(signature = (spheres, planes = None, cylinders = None, containers = None))]
    fn new(
        spheres: &Bound<'_, PyAny>,
        planes: Option<&Bound<'_, PyAny>>,
        cylinders: Option<&Bound<'_, PyAny>>,
        containers: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let py = spheres.py();
        let spheres = instance::<Spheres>(spheres, "spheres", "Spheres")?;
        let (planes, p) = shape_items(py, planes, "planes", Takes::Only(ShapeKind::Plane))?;
        let (cylinders, c) =
            shape_items(py, cylinders, "cylinders", Takes::Only(ShapeKind::Cylinder))?;
        let (containers, k) = shape_items(
            py,
            containers,
            "containers",
            Takes::Only(ShapeKind::Container),
        )?;
        let n = spheres.store.len();
        memory::check(
            &format!("Scene: {n} spheres"),
            n.saturating_mul(STORE_BYTES),
        )?;
        let scene = RustScene {
            spheres: spheres.store.clone(),
            statics: p.into_iter().chain(c).chain(k).collect(),
        };
        Ok(Self {
            scene,
            given: [planes.unbind(), cylinders.unbind(), containers.unbind()],
        })
    }

    /// The scene's spheres (a new `Spheres`, copied).
    #[getter]
    fn spheres(&self) -> PyResult<Spheres> {
        let n = self.scene.spheres.len();
        memory::check(
            &format!("Scene.spheres: {n} spheres"),
            n.saturating_mul(STORE_BYTES),
        )?;
        Ok(Spheres {
            store: self.scene.spheres.clone(),
        })
    }

    /// The planes, cylinders and containers as given, each a tuple.
    #[getter]
    fn shapes(&self, py: Python<'_>) -> (Py<PyTuple>, Py<PyTuple>, Py<PyTuple>) {
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
    ) -> PyResult<(
        Bound<'py, PyType>,
        (Spheres, Py<PyTuple>, Py<PyTuple>, Py<PyTuple>),
    )> {
        let (py, me) = (slf.py(), slf.get());
        let (p, c, k) = me.shapes(py);
        Ok((slf.get_type(), (me.spheres()?, p, c, k)))
    }

    fn __repr__(&self) -> String {
        let s = &self.scene;
        format!(
            "Scene(<{} spheres, {}>)",
            s.spheres.len(),
            (s.statics.counts().into_iter())
                .map(|(kind, n)| format!("{n} {kind}s"))
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}

/// `MemoryError` if the query's estimated peak (the library's estimate: linear in the spheres,
/// plus the contacts for `all_contacts`; and the result columns, `row_bytes` a row) exceeds
/// the memory available.
fn check_query(
    name: &str,
    scene: &RustScene,
    opts: QueryOptions,
    every: bool,
    row_bytes: usize,
) -> PyResult<()> {
    let e = estimate::estimate(scene, opts, every);
    let rows = if every {
        e.contacts as usize
    } else {
        scene.spheres.len()
    };
    let bytes = (e.bytes as usize).saturating_add(rows.saturating_mul(row_bytes));
    let contacts = if every {
        format!(", about {} contacts to return", e.contacts)
    } else {
        String::new()
    };
    memory::check(
        &format!(
            "{name}: {} spheres, t_max = {}{contacts}",
            scene.spheres.len(),
            show(f64::from(opts.t_max())),
        ),
        bytes,
    )
}

/// Geometry columns being filled: `(K, 3)` points and normals in float32, NaN where none.
struct GeometryColumns {
    point: Vec<f32>,
    normal: Vec<f32>,
}

impl GeometryColumns {
    fn new(k: usize) -> PyResult<Self> {
        Ok(Self {
            point: memory::filled(3 * k, f32::NAN, "contact points")?,
            normal: memory::filled(3 * k, f32::NAN, "contact normals")?,
        })
    }

    fn set(&mut self, row: usize, c: &Contact) {
        let p = c.point.as_vec3().to_array();
        let n = c.normal.as_vec3().to_array();
        self.point[3 * row..3 * row + 3].copy_from_slice(&p);
        self.normal[3 * row..3 * row + 3].copy_from_slice(&n);
    }

    #[allow(clippy::type_complexity)]
    fn into_arrays(
        geo: Option<Self>,
        py: Python<'_>,
    ) -> (
        Option<Py<numpy::PyArray2<f32>>>,
        Option<Py<numpy::PyArray2<f32>>>,
    ) {
        let Some(g) = geo else {
            return (None, None);
        };
        let k = g.point.len() / 3;
        let arr = |v: Vec<f32>| {
            Array2::from_shape_vec((k, 3), v)
                .expect("3 per row")
                .into_pyarray(py)
                .unbind()
        };
        (Some(arr(g.point)), Some(arr(g.normal)))
    }
}

/// Bytes of one row of `first_contacts`' columns (time, kind, index; points and normals).
const FIRST_ROW: usize = 4 + 1 + 8 + 24;
/// Bytes of one row of `all_contacts`' columns (time, sphere, kind, index; geometry).
const ALL_ROW: usize = 4 + 4 + 1 + 8 + 24;

/// For every sphere of `scene`, its earliest contact in `[0, t_max]` (see `FirstContacts`).
/// `t_max` is rounded to float32. Memory is linear in the spheres whatever the window; an
/// infinite window (the default) has no cull, so it takes time (successive windows, then a
/// brute-force row for each sphere still open). The GIL is released during the query.
#[pyfunction]
#[pyo3(signature = (scene, *, t_max = None, accuracy = None, geometry = None),
       text_signature = "(scene, *, t_max=math.inf, accuracy='stable', geometry=False)")]
pub fn first_contacts(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    t_max: Option<&Bound<'_, PyAny>>,
    accuracy: Option<&Bound<'_, PyAny>>,
    geometry: Option<&Bound<'_, PyAny>>,
) -> PyResult<FirstContacts> {
    let scene = instance::<Scene>(scene, "scene", "Scene")?;
    let opts = args::options(t_max, accuracy, geometry)?;
    let scene = &scene.scene;
    check_query("first_contacts", scene, opts, false, FIRST_ROW)?;
    let n = scene.spheres.len();
    let mut time = memory::filled(n, f32::INFINITY, "time")?;
    let mut kind = memory::filled(n, KIND_NONE, "kind")?;
    let mut index = memory::filled(n, -1i64, "index")?;
    let mut geo = opts
        .geometry()
        .then(|| GeometryColumns::new(n))
        .transpose()?;
    py.detach(|| {
        let hits = query::first_contacts(scene, opts);
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
    });
    let (point, normal) = GeometryColumns::into_arrays(geo, py);
    Ok(FirstContacts {
        time: time.into_pyarray(py).unbind(),
        kind: kind.into_pyarray(py).unbind(),
        index: index.into_pyarray(py).unbind(),
        point,
        normal,
    })
}

/// Every contact in `[0, t_max]` (see `Contacts`): each sphere pair once, and every sphere
/// with every static shape it touches. `t_max` is required; the contacts are held at once
/// (the candidate pairs never are): `MemoryError` (with the estimate) before anything is
/// allocated when they would not fit. The GIL is released during the query.
#[pyfunction]
#[pyo3(signature = (scene, *, t_max, accuracy = None, geometry = None),
       text_signature = "(scene, *, t_max, accuracy='stable', geometry=False)")]
pub fn all_contacts(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    t_max: &Bound<'_, PyAny>,
    accuracy: Option<&Bound<'_, PyAny>>,
    geometry: Option<&Bound<'_, PyAny>>,
) -> PyResult<Contacts> {
    let scene = instance::<Scene>(scene, "scene", "Scene")?;
    if t_max.is_none() {
        return Err(args::wrong_type("t_max", "a real number", t_max));
    }
    let opts = args::options(Some(t_max), accuracy, geometry)?;
    let scene = &scene.scene;
    check_query("all_contacts", scene, opts, true, ALL_ROW)?;
    let events = py.detach(|| query::all_contacts(scene, opts));
    let k = events.len();
    let mut time = memory::with_capacity(k, "time")?;
    let mut sphere = memory::with_capacity(k, "sphere")?;
    let mut kind = memory::with_capacity(k, "kind")?;
    let mut index = memory::with_capacity(k, "index")?;
    let mut geo = opts
        .geometry()
        .then(|| GeometryColumns::new(k))
        .transpose()?;
    for (row, e) in events.iter().enumerate() {
        time.push(e.time);
        sphere.push(e.sphere);
        kind.push(kind_code(e.other.kind));
        index.push(i64::from(e.other.index));
        if let (Some(g), Some(c)) = (geo.as_mut(), e.geometry.as_ref()) {
            g.set(row, c);
        }
    }
    drop(events);
    let (point, normal) = GeometryColumns::into_arrays(geo, py);
    Ok(Contacts {
        time: time.into_pyarray(py).unbind(),
        sphere: sphere.into_pyarray(py).unbind(),
        kind: kind.into_pyarray(py).unbind(),
        index: index.into_pyarray(py).unbind(),
        point,
        normal,
    })
}
