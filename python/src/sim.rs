//! The event-driven simulation: built from a scene file, a periodic gas, or spheres and shapes
//! given as arrays; advanced with the GIL released; state and events out as NumPy arrays.

use std::path::PathBuf;
use std::sync::Mutex;

use glam::DVec3;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use spheresweep::io::scene_file::{SceneFile, SceneFileError};
use spheresweep::sim::{self, Boundary, Fixed, Response, SphereState, World, generate};

use crate::arrays::{Expect, floats, row3};
use crate::batch::{AnyStatic, any_static, value_error};
use crate::scene::{KIND_NONE, kind_code};

/// A running event-driven simulation (positions, velocities and times in float64), every
/// collision processed in exact time order. Build one with `Simulation.from_scene_file`,
/// `Simulation.periodic_gas` or `Simulation.from_spheres`; move it on with `advance_to`.
#[pyclass(frozen, module = "spheresweep._native")]
pub struct Simulation {
    sim: Mutex<sim::Simulation>,
    /// What the simulation was built from, kept for `restore` (a checkpoint holds the dynamic
    /// state only, and is checked against this).
    world: World,
    /// The scene file's end time, when built from one.
    t_end: Option<f64>,
}

impl Simulation {
    fn new(world: World, t_end: Option<f64>) -> PyResult<Self> {
        let sim = sim::Simulation::new(world.clone()).map_err(value_error)?;
        Ok(Self {
            sim: Mutex::new(sim),
            world,
            t_end,
        })
    }

    /// The simulation, locked. While another thread holds it (`advance_to` runs without the
    /// GIL), this waits with the GIL released: waiting with it held would deadlock with that
    /// thread taking the GIL back.
    fn lock(&self, py: Python<'_>) -> std::sync::MutexGuard<'_, sim::Simulation> {
        loop {
            match self.sim.try_lock() {
                Ok(guard) => return guard,
                // A panic while the lock was held leaves no half-written state we read here.
                Err(std::sync::TryLockError::Poisoned(e)) => return e.into_inner(),
                Err(std::sync::TryLockError::WouldBlock) => {
                    py.detach(|| drop(self.sim.lock()));
                }
            }
        }
    }

    fn rows<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&SphereState) -> DVec3,
    ) -> Bound<'py, PyArray2<f64>> {
        let spheres = self.lock(py).spheres();
        let data: Vec<f64> = spheres.iter().flat_map(|s| f(s).to_array()).collect();
        Array2::from_shape_vec((spheres.len(), 3), data)
            .expect("3 per sphere")
            .into_pyarray(py)
    }
}

fn scene_file_error(e: SceneFileError) -> PyErr {
    match e {
        SceneFileError::Read { .. } => PyOSError::new_err(e.to_string()),
        e => value_error(e),
    }
}

/// The response of a coefficient of restitution in `[0, 1]`: elastic at 1, inelastic below.
fn response_of(restitution: f64) -> PyResult<Response> {
    if !(0.0..=1.0).contains(&restitution) {
        return Err(PyValueError::new_err(format!(
            "restitution: {restitution} is not in [0, 1]"
        )));
    }
    Ok(if restitution == 1.0 {
        Response::Elastic
    } else {
        Response::Inelastic { restitution }
    })
}

/// The scene's response, as a scene file's `[effects]`: `response` by name (`"none"`,
/// `"elastic"`, `"inelastic"` with `restitution` required, `"sticky"`), a `restitution` only
/// with `"inelastic"`; or, without `response`, the one `restitution` implies (elastic at 1 or
/// when absent, inelastic below).
fn scene_response(response: Option<&str>, restitution: Option<f64>) -> PyResult<Response> {
    match (response, restitution) {
        (None, None) | (Some("elastic"), None) => Ok(Response::Elastic),
        (None, Some(e)) => response_of(e),
        (Some("inelastic"), Some(e)) => {
            response_of(e)?;
            Ok(Response::Inelastic { restitution: e })
        }
        (Some("inelastic"), None) => Err(PyValueError::new_err(
            "restitution: required with response \"inelastic\"",
        )),
        (Some("none"), None) => Ok(Response::None),
        (Some("sticky"), None) => Ok(Response::Sticky),
        (Some(name @ ("none" | "elastic" | "sticky")), Some(e)) => {
            Err(PyValueError::new_err(format!(
                "restitution: {e} given with response {name:?} (it applies to \"inelastic\" only)"
            )))
        }
        (Some(other), _) => Err(PyValueError::new_err(format!(
            "response: {other:?} is not one of \"none\", \"elastic\", \"inelastic\", \"sticky\""
        ))),
    }
}

/// A material index from Python: an integer in `[0, MAX_MATERIALS)`, or an error naming
/// `what`.
fn material_index(value: &Bound<'_, PyAny>, what: &str) -> PyResult<u16> {
    let i: i64 = value.extract().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(format!("{what}: a material is an integer"))
    })?;
    match u16::try_from(i) {
        Ok(m) if usize::from(m) < sim::MAX_MATERIALS => Ok(m),
        _ => Err(PyValueError::new_err(format!(
            "{what}: material {i} is not in [0, {}]",
            sim::MAX_MATERIALS - 1
        ))),
    }
}

/// One entry of `pairs`: `(a, b, response)` with `response` a restitution in `[0, 1]` or
/// `"elastic"` / `"sticky"`.
fn material_pair(item: &Bound<'_, PyAny>, what: &str) -> PyResult<sim::MaterialPair> {
    let parts: Vec<Bound<'_, PyAny>> = item
        .try_iter()
        .and_then(|it| it.collect())
        .ok()
        .filter(|p: &Vec<_>| p.len() == 3)
        .ok_or_else(|| {
            pyo3::exceptions::PyTypeError::new_err(format!(
                "{what}: expected a tuple (a, b, response)"
            ))
        })?;
    let a = material_index(&parts[0], &format!("{what}.a"))?;
    let b = material_index(&parts[1], &format!("{what}.b"))?;
    let response = if let Ok(name) = parts[2].extract::<String>() {
        match name.as_str() {
            "elastic" => Response::Elastic,
            "sticky" => Response::Sticky,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "{what}.response: {name:?} is not a restitution, \"elastic\" or \"sticky\""
                )));
            }
        }
    } else {
        let e: f64 = parts[2].extract().map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err(format!(
                "{what}.response: expected a restitution or \"elastic\" / \"sticky\""
            ))
        })?;
        response_of(e).map_err(|_| {
            PyValueError::new_err(format!("{what}.response: restitution {e} is not in [0, 1]"))
        })?
    };
    Ok(sim::MaterialPair { a, b, response })
}

#[pymethods]
impl Simulation {
    /// A simulation of the scene file at `path` (TOML, or JSON when the name ends in
    /// `.json`), as `spheresweep run` reads it. `OSError` if it cannot be read; `ValueError`
    /// with the file, line, item and field for anything the file gets wrong.
    #[staticmethod]
    fn from_scene_file(path: PathBuf) -> PyResult<Self> {
        let file = SceneFile::from_path(&path).map_err(scene_file_error)?;
        let (world, run) = file.build().map_err(scene_file_error)?;
        let sim =
            sim::Simulation::new(world.clone()).map_err(|e| scene_file_error(file.locate(e)))?;
        Ok(Self {
            sim: Mutex::new(sim),
            world,
            t_end: Some(run.t_end),
        })
    }

    /// `n` hard spheres of radius `radius` (mass 1) on random sites of an FCC lattice in a
    /// periodic cube at packing fraction `phi` (in (0, 0.7)), with thermal velocities at
    /// temperature `kT` (zero total momentum), elastic collisions. `record_events=True` keeps
    /// every collision for `take_events`.
    #[staticmethod]
    #[pyo3(signature = (n, phi, radius = 0.5, kT = 1.0, seed = 0, record_events = false))]
    #[allow(non_snake_case)]
    fn periodic_gas(
        n: usize,
        phi: f64,
        radius: f64,
        kT: f64,
        seed: u64,
        record_events: bool,
    ) -> PyResult<Self> {
        let mut world = World {
            boundary: Boundary::Periodic { size: DVec3::ZERO },
            ..World::default()
        };
        world.effects.record_events = record_events;
        generate::periodic_gas(&mut world, n, phi, radius, kT, seed).map_err(value_error)?;
        Self::new(world, None)
    }

    /// A simulation of spheres given as arrays (float64; other floating dtypes converted):
    /// `centres` and `velocities` `(N, 3)`, `radii` and optional `masses` `(N,)` (default 1),
    /// among static `planes`, `cylinders` and `containers`. `periodic_box` (three lengths)
    /// makes the box `[0, L)` periodic; otherwise space is open. Every collision has
    /// coefficient of restitution `restitution` (absent or 1: elastic), or does what `response`
    /// names (`"none"`, `"elastic"`, `"inelastic"` with `restitution`, `"sticky"`), as a scene
    /// file's `[effects]` (docs/scene-format.md); `tc` is the TC model's duration (0: off).
    /// Materials are indices below 1024 (`MAX_MATERIALS`).
    /// `materials` gives each sphere a material index (default 0); a shape may be given as a
    /// `(shape, material)` tuple; `pairs` lists `(a, b, response)` overrides for pairs of
    /// materials, `response` a restitution or `"elastic"` / `"sticky"`. `record_events` keeps
    /// each collision for `take_events`, with its contact point and normal if `geometry`.
    ///
    /// `ValueError` for invalid spheres, shapes, materials or pairs, overlaps at the start, a
    /// sphere through a shape, or a box too small (the message names the item).
    #[staticmethod]
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (centres, velocities, radii, masses = None, *, planes = None,
        cylinders = None, containers = None, periodic_box = None, restitution = None,
        response = None, tc = 0.0, materials = None, pairs = None, record_events = false,
        geometry = false))]
    fn from_spheres(
        centres: &Bound<'_, PyAny>,
        velocities: &Bound<'_, PyAny>,
        radii: &Bound<'_, PyAny>,
        masses: Option<&Bound<'_, PyAny>>,
        planes: Option<&Bound<'_, PyAny>>,
        cylinders: Option<&Bound<'_, PyAny>>,
        containers: Option<&Bound<'_, PyAny>>,
        periodic_box: Option<&Bound<'_, PyAny>>,
        restitution: Option<f64>,
        response: Option<&str>,
        tc: f64,
        materials: Option<&Bound<'_, PyAny>>,
        pairs: Option<&Bound<'_, PyAny>>,
        record_events: bool,
        geometry: bool,
    ) -> PyResult<Self> {
        let c = floats::<f64>(centres, "centres", Expect::Rows3)?;
        let v = floats::<f64>(velocities, "velocities", Expect::Rows3)?;
        let r = floats::<f64>(radii, "radii", Expect::Column)?;
        let m = masses
            .map(|m| floats::<f64>(m, "masses", Expect::Column))
            .transpose()?;
        let n = c.as_array().shape()[0];
        let (c, v, r) = (c.as_array(), v.as_array(), r.as_array());
        let m = m.as_ref().map(|m| m.as_array());
        let material: Vec<u16> = match materials {
            None => vec![0; n],
            Some(list) => list
                .try_iter()?
                .enumerate()
                .map(|(i, x)| material_index(&x?, &format!("materials[{i}]")))
                .collect::<PyResult<_>>()?,
        };
        for (name, len) in [("velocities", v.shape()[0]), ("radii", r.shape()[0])]
            .into_iter()
            .chain(m.as_ref().map(|m| ("masses", m.shape()[0])))
            .chain(materials.map(|_| ("materials", material.len())))
        {
            if len != n {
                return Err(PyValueError::new_err(format!(
                    "{name}: {len} entries, expected {n} (one per sphere, as centres)"
                )));
            }
        }
        let spheres = (0..n)
            .map(|i| SphereState {
                centre: DVec3::from_array(row3(&c, i)),
                velocity: DVec3::from_array(row3(&v, i)),
                radius: r[[i]],
                mass: m.as_ref().map_or(1.0, |m| m[[i]]),
                material: material[i],
            })
            .collect();
        let mut world = World {
            spheres,
            ..World::default()
        };
        for (items, name) in [
            (planes, "planes"),
            (cylinders, "cylinders"),
            (containers, "containers"),
        ] {
            let Some(items) = items else { continue };
            for (k, item) in items.try_iter()?.enumerate() {
                let label = format!("{name}[{k}]");
                let item = item?;
                // A shape, or a (shape, material) tuple.
                let (shape, material) = match item.cast::<pyo3::types::PyTuple>() {
                    Ok(t) if t.len() == 2 => (
                        t.get_item(0)?,
                        material_index(&t.get_item(1)?, &format!("{label}.material"))?,
                    ),
                    _ => (item, 0),
                };
                match any_static(&shape, &label)? {
                    AnyStatic::Plane(shape) => world.planes.push(Fixed { shape, material }),
                    AnyStatic::Cylinder(shape) => world.cylinders.push(Fixed { shape, material }),
                    AnyStatic::Container(shape) => world.containers.push(Fixed { shape, material }),
                }
            }
        }
        if let Some(pairs) = pairs {
            for (k, item) in pairs.try_iter()?.enumerate() {
                world
                    .effects
                    .pairs
                    .push(material_pair(&item?, &format!("pairs[{k}]"))?);
            }
        }
        // Materials are numbered: as many as the largest index used (names "0", "1", ...);
        // none listed when every index is 0, as in every other world of one material (so that
        // checkpoints pass between them).
        let used = world
            .spheres
            .iter()
            .map(|s| s.material)
            .chain(world.planes.iter().map(|p| p.material))
            .chain(world.cylinders.iter().map(|c| c.material))
            .chain(world.containers.iter().map(|c| c.material))
            .chain(world.effects.pairs.iter().flat_map(|p| [p.a, p.b]))
            .max()
            .unwrap_or(0);
        if used > 0 {
            world.materials = (0..=used).map(|i| i.to_string()).collect();
        }
        if let Some(b) = periodic_box {
            let size = crate::arrays::vector3::<f64>(b, "periodic_box")?;
            world.boundary = Boundary::Periodic {
                size: DVec3::from_array(size),
            };
        }
        world.effects.response = scene_response(response, restitution)?;
        if !(tc.is_finite() && tc >= 0.0) {
            return Err(PyValueError::new_err(format!(
                "tc: {tc} is not a finite duration >= 0"
            )));
        }
        world.effects.tc = tc;
        world.effects.record_events = record_events;
        world.effects.geometry = geometry;
        Self::new(world, None)
    }

    /// Processes every collision up to time `t` (inclusive) and moves the clock to `t`, with
    /// the GIL released. `ValueError` if `t` is not finite or before `time`.
    fn advance_to(&self, py: Python<'_>, t: f64) -> PyResult<()> {
        let mut guard = self.lock(py);
        let sim: &mut sim::Simulation = &mut guard;
        py.detach(move || sim.advance_to(t)).map_err(value_error)
    }

    /// The current time.
    #[getter]
    fn time(&self, py: Python<'_>) -> f64 {
        self.lock(py).time()
    }

    /// The end time the scene file asked for (`[run] t_end`), or `None`.
    #[getter]
    fn t_end(&self) -> Option<f64> {
        self.t_end
    }

    /// Number of spheres.
    fn __len__(&self, py: Python<'_>) -> usize {
        self.lock(py).spheres().len()
    }

    /// Centres now, float64 `(N, 3)` (periodic centres wrapped into the box).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.rows(py, |s| s.centre)
    }

    /// Velocities now, float64 `(N, 3)`.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.rows(py, |s| s.velocity)
    }

    /// Radii, float64 `(N,)`.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let r: Vec<f64> = self.lock(py).spheres().iter().map(|s| s.radius).collect();
        r.into_pyarray(py)
    }

    /// Masses, float64 `(N,)`.
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let m: Vec<f64> = self.lock(py).spheres().iter().map(|s| s.mass).collect();
        m.into_pyarray(py)
    }

    /// Total kinetic energy `sum(m v^2 / 2)`.
    fn kinetic_energy(&self, py: Python<'_>) -> f64 {
        self.lock(py).kinetic_energy()
    }

    /// Total momentum `sum(m v)`, a tuple of three floats.
    fn momentum(&self, py: Python<'_>) -> (f64, f64, f64) {
        let p = self.lock(py).momentum();
        (p.x, p.y, p.z)
    }

    /// Counters since the start, as a dict: `collisions` (pair + wall), `pair_collisions`,
    /// `wall_collisions`, `crossings`, `stale`, `predictions`, `kernels_sphere`,
    /// `kernels_plane`, `kernels_cylinder`, `kernels_container`, `energy_lost`, `virial`,
    /// `max_overlap`, `joins`, `guarded`.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = *self.lock(py).stats();
        let d = PyDict::new(py);
        d.set_item("collisions", s.pair_collisions + s.wall_collisions)?;
        d.set_item("pair_collisions", s.pair_collisions)?;
        d.set_item("wall_collisions", s.wall_collisions)?;
        d.set_item("crossings", s.crossings)?;
        d.set_item("stale", s.stale)?;
        d.set_item("predictions", s.predictions)?;
        d.set_item("kernels_sphere", s.kernels.sphere)?;
        d.set_item("kernels_plane", s.kernels.plane)?;
        d.set_item("kernels_cylinder", s.kernels.cylinder)?;
        d.set_item("kernels_container", s.kernels.container)?;
        d.set_item("energy_lost", s.energy_lost)?;
        d.set_item("virial", s.virial)?;
        d.set_item("max_overlap", s.max_overlap)?;
        d.set_item("joins", s.joins)?;
        d.set_item("guarded", s.guarded)?;
        Ok(d)
    }

    /// Which engine the world was assembled into.
    #[getter]
    fn engine(&self, py: Python<'_>) -> String {
        self.lock(py).engine_name()
    }

    /// Bytes the simulation holds.
    fn memory_bytes(&self, py: Python<'_>) -> usize {
        self.lock(py).memory_bytes()
    }

    /// Clusters of two or more spheres (sticky scenes), each a list of sphere indices.
    fn clusters(&self, py: Python<'_>) -> Vec<Vec<u32>> {
        self.lock(py).clusters()
    }

    /// The whole dynamic state as bytes (see the Rust `Simulation::checkpoint`).
    fn checkpoint<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.lock(py).checkpoint())
    }

    /// Puts the simulation back in the state `checkpoint` saved (time, positions, velocities,
    /// counters, pending events), so that it goes on exactly as the saved one would. The bytes
    /// must come from the same system: spheres of the same radii, masses and materials, the
    /// same shapes, boundary and effects (starting positions and velocities may differ: the
    /// checkpoint holds them). `ValueError` saying why otherwise (damaged, truncated, another
    /// world), and the simulation is left as it was.
    fn restore(&self, py: Python<'_>, data: &[u8]) -> PyResult<()> {
        let world = self.world.clone();
        let restored = py
            .detach(move || sim::Simulation::restore(world, data))
            .map_err(value_error)?;
        *self.lock(py) = restored;
        Ok(())
    }

    /// The collisions recorded since the last call (empty unless the simulation records
    /// events), as a dict of arrays one row per event: `time` float64, `sphere` uint32,
    /// `kind` uint8 (`KIND_*`), `index` int64, `approach`, `restitution`, `energy_lost`
    /// float64, and `point`, `normal` float64 `(K, 3)` (NaN without geometry).
    fn take_events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let events = self.lock(py).take_events();
        let k = events.len();
        let d = PyDict::new(py);
        let col_f =
            |f: fn(&sim::EventRecord) -> f64| -> Vec<f64> { events.iter().map(f).collect() };
        d.set_item("time", col_f(|e| e.time).into_pyarray(py))?;
        let sphere: Vec<u32> = events.iter().map(|e| e.sphere).collect();
        d.set_item("sphere", sphere.into_pyarray(py))?;
        let kind: Vec<u8> = events.iter().map(|e| kind_code(e.other.kind)).collect();
        debug_assert!(kind.iter().all(|&c| c != KIND_NONE));
        d.set_item("kind", kind.into_pyarray(py))?;
        let index: Vec<i64> = events.iter().map(|e| i64::from(e.other.index)).collect();
        d.set_item("index", index.into_pyarray(py))?;
        d.set_item("approach", col_f(|e| e.approach).into_pyarray(py))?;
        d.set_item("restitution", col_f(|e| e.restitution).into_pyarray(py))?;
        d.set_item("energy_lost", col_f(|e| e.energy_lost).into_pyarray(py))?;
        let geo = |f: fn(&sim::EventGeometry) -> DVec3| -> Vec<f64> {
            events
                .iter()
                .flat_map(|e| {
                    e.geometry
                        .as_ref()
                        .map_or([f64::NAN; 3], |g| f(g).to_array())
                })
                .collect()
        };
        for (name, data) in [("point", geo(|g| g.point)), ("normal", geo(|g| g.normal))] {
            let array = Array2::from_shape_vec((k, 3), data).expect("3 per event");
            d.set_item(name, array.into_pyarray(py))?;
        }
        Ok(d)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let sim = self.lock(py);
        format!(
            "Simulation(<{} spheres, t = {}, {}>)",
            sim.spheres().len(),
            sim.time(),
            sim.engine_name()
        )
    }
}
