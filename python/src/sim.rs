//! The event-driven simulation: built from a scene file, a periodic gas, or spheres and shapes
//! given as arrays; advanced with the GIL released, interruptible (Ctrl-C) and with progress;
//! state and events out as NumPy arrays; pickled through its checkpoint.

use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use glam::DVec3;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::create_exception;
use pyo3::exceptions::{PyMemoryError, PyRuntimeError, PyRuntimeWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyTuple};
use spheresweep::ShapeKind;
use spheresweep::io::scene_file::{SceneFile, SceneFileError};
use spheresweep::sim::{self, Boundary, SphereState, World, generate};

use crate::args::{self, count, flag, optional, real, show, uint64};
use crate::arrays::{Expect, floats, row3};
use crate::batch::value_error;
use crate::effects::{material_pair, scene_response};
use crate::memory;
use crate::results::{KIND_NONE, kind_code, put_column};
use crate::shapes::Takes;
use crate::world::{
    add_shapes, name_materials, scene_file_error, scene_file_world, spheres_world, start_arrays,
};

create_exception!(
    spheresweep,
    InvariantError,
    PyRuntimeError,
    "The simulation's state broke the invariant every run keeps (a sphere overlapping another \
     or through a static shape beyond the derived tolerance): a bug in spheresweep, never the \
     scene's fault. The message names the sphere, the other body and the time."
);

/// A simulation error as Python raises it: `MemoryError` for memory refused up front,
/// `InvariantError` for a breach of the invariant (or a state with NaN in it), `ValueError` for the rest (the scene's or
/// the caller's values, named in the message).
fn sim_error(e: sim::SimError) -> PyErr {
    match e {
        sim::SimError::Memory { .. } => PyMemoryError::new_err(e.to_string()),
        sim::SimError::Breach { .. } | sim::SimError::NotFinite { .. } => {
            InvariantError::new_err(e.to_string())
        }
        e => value_error(e),
    }
}

/// How often at most `advance_to` calls its `progress` callback.
const PROGRESS_EVERY: Duration = Duration::from_millis(100);

/// What a simulation was built from: what pickling rebuilds it from (then restores the
/// checkpoint).
enum Origin {
    /// A scene file's text (JSON or TOML).
    SceneFile { text: String, json: bool },
    /// `periodic_gas`'s arguments.
    Gas { args: Py<PyTuple> },
    /// `from_spheres`' keywords (its arrays are the world's spheres at the start).
    Spheres { kwargs: Py<PyDict> },
}

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
    origin: Origin,
}

/// Bytes a simulation of `n` spheres holds, with the two copies of its world (the one built
/// and the one kept for `restore`).
pub(crate) fn simulation_bytes(n: usize) -> usize {
    sim::Simulation::estimated_bytes(n)
        .saturating_add(n.saturating_mul(2 * std::mem::size_of::<SphereState>()))
}

/// A `RuntimeWarning` (the build goes on): something the engine can only approximate, such as
/// a sphere that starts where its contacts are resolved only coarsely (`World::coarse_sphere`).
fn warn(py: Python<'_>, text: String) -> PyResult<()> {
    let text = std::ffi::CString::new(text).map_err(|e| PyValueError::new_err(e.to_string()))?;
    PyErr::warn(py, &py.get_type::<PyRuntimeWarning>(), &text, 1)
}

impl Simulation {
    fn new(world: World, t_end: Option<f64>, origin: Origin) -> PyResult<Self> {
        let sim = sim::Simulation::new(world.clone()).map_err(sim_error)?;
        Ok(Self {
            sim: Mutex::new(sim),
            world,
            t_end,
            origin,
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

    /// The spheres now, `MemoryError` if their copy does not fit.
    fn spheres(&self, py: Python<'_>) -> PyResult<Vec<SphereState>> {
        let sim = self.lock(py);
        let n = self.world.spheres.len();
        memory::check(
            &format!("Simulation: a copy of {n} spheres"),
            n.saturating_mul(std::mem::size_of::<SphereState>() + 24),
        )?;
        Ok(sim.spheres())
    }

    fn rows<'py>(
        &self,
        py: Python<'py>,
        f: impl Fn(&SphereState) -> DVec3,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let spheres = self.spheres(py)?;
        let mut data = memory::with_capacity(3 * spheres.len(), "Simulation rows")?;
        data.extend(spheres.iter().flat_map(|s| f(s).to_array()));
        Ok(Array2::from_shape_vec((spheres.len(), 3), data)
            .expect("3 per sphere")
            .into_pyarray(py))
    }

    /// The periodic box's lengths, if periodic.
    fn periodic_box(&self) -> Option<DVec3> {
        match self.world.boundary {
            Boundary::Periodic { size } => Some(size),
            _ => None,
        }
    }
}

/// The `keep_going` of `advance_to`: every 4096 events it takes the GIL, runs the signal
/// handlers (Ctrl-C raises `KeyboardInterrupt` there) and calls `progress(time)` at most every
/// [`PROGRESS_EVERY`]; the first error stops the run, between two events.
struct Watch<'a> {
    progress: Option<&'a Py<PyAny>>,
    last: Instant,
    error: Option<PyErr>,
}

impl Watch<'_> {
    fn keep_going(&mut self, now: f64) -> bool {
        Python::attach(|py| {
            let result = py.check_signals().and_then(|()| match self.progress {
                Some(p) if self.last.elapsed() >= PROGRESS_EVERY => {
                    self.last = Instant::now();
                    p.call1(py, (now,)).map(drop)
                }
                _ => Ok(()),
            });
            match result {
                Ok(()) => true,
                Err(e) => {
                    self.error = Some(e);
                    false
                }
            }
        })
    }
}

#[pymethods]
impl Simulation {
    /// A simulation of the scene file at `path` (TOML, or JSON when the name ends in
    /// `.json`), as `spheresweep run` reads it. `OSError` if it cannot be read; `ValueError`
    /// with the file, line, item and field for anything the file gets wrong; `MemoryError`
    /// for more spheres than memory holds; a `RuntimeWarning` (the build goes on) for a sphere
    /// so far from the origin that its contacts may overlap past the tolerance, or a shape its
    /// rounding to `f32` moves by more than `2⁻¹⁰` of the smallest radius.
    #[staticmethod]
    fn from_scene_file(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let file = SceneFile::from_path(&path).map_err(scene_file_error)?;
        let text = std::fs::read_to_string(&path).map_err(|source| {
            scene_file_error(SceneFileError::Read {
                path: path.clone(),
                source,
            })
        })?;
        let json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let (world, t_end) = scene_file_world(&file)?;
        let sim =
            sim::Simulation::new(world.clone()).map_err(|e| scene_file_error(file.locate(e)))?;
        for warning in file.warnings(&world) {
            warn(py, warning)?;
        }
        Ok(Self {
            sim: Mutex::new(sim),
            world,
            t_end: Some(t_end),
            origin: Origin::SceneFile { text, json },
        })
    }

    /// `n` hard spheres of radius `radius` (mass 1) on random sites of an FCC lattice in a
    /// periodic cube at packing fraction `phi` (in (0, 0.7)), with thermal velocities at
    /// temperature `kT` (zero total momentum), elastic collisions. `record_events=True` keeps
    /// every collision for `take_events`.
    #[staticmethod]
    #[pyo3(signature = (n, phi, radius = None, kT = None, seed = None, record_events = None),
           text_signature = "(n, phi, radius=0.5, kT=1.0, seed=0, record_events=False)")]
    #[allow(non_snake_case)]
    fn periodic_gas(
        py: Python<'_>,
        n: &Bound<'_, PyAny>,
        phi: &Bound<'_, PyAny>,
        radius: Option<&Bound<'_, PyAny>>,
        kT: Option<&Bound<'_, PyAny>>,
        seed: Option<&Bound<'_, PyAny>>,
        record_events: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let n = count(n, "n")?;
        let phi = real(phi, "phi")?;
        let radius = optional(radius).map_or(Ok(0.5), |r| real(r, "radius"))?;
        let kt = optional(kT).map_or(Ok(1.0), |k| real(k, "kT"))?;
        let seed = optional(seed).map_or(Ok(0), |s| uint64(s, "seed"))?;
        let record = optional(record_events).map_or(Ok(false), |r| flag(r, "record_events"))?;
        memory::check(&format!("periodic_gas: {n} spheres"), simulation_bytes(n))?;
        let mut world = World {
            boundary: Boundary::Periodic { size: DVec3::ZERO },
            ..World::default()
        };
        world.effects.record_events = record;
        generate::periodic_gas(&mut world, n, phi, radius, kt, seed).map_err(sim_error)?;
        let args = PyTuple::new(
            py,
            [
                n.into_pyobject(py)?.into_any(),
                phi.into_pyobject(py)?.into_any(),
                radius.into_pyobject(py)?.into_any(),
                kt.into_pyobject(py)?.into_any(),
                seed.into_pyobject(py)?.into_any(),
                pyo3::types::PyBool::new(py, record).to_owned().into_any(),
            ],
        )?;
        Self::new(
            world,
            None,
            Origin::Gas {
                args: args.unbind(),
            },
        )
    }

    /// A simulation of spheres given as arrays (float64; other real dtypes converted):
    /// `centres` and `velocities` `(N, 3)`, `radii` and optional `masses` `(N,)` (default 1),
    /// among static `planes`, `cylinders` and `containers` (each a sequence of that kind).
    /// `periodic_box` (three lengths) makes the box `[0, L)` periodic; otherwise space is
    /// open. Every collision has coefficient of restitution `restitution` (absent or 1:
    /// elastic), or does what `response` names (`"none"`, `"elastic"`, `"inelastic"` with
    /// `restitution`, `"sticky"`), as a scene file's `[effects]` (docs/scene-format.md); `tc`
    /// is the TC model's duration (0: off). Materials are indices below 1024
    /// (`MAX_MATERIALS`). `materials` gives each sphere a material index (default 0); a shape
    /// may be given as a `(shape, material)` tuple; `pairs` lists `(a, b, response)`
    /// overrides for pairs of materials, `response` a restitution or `"elastic"` /
    /// `"sticky"`. `record_events` keeps each collision for `take_events`, with its contact
    /// point and normal if `geometry`. `gravity` (three floats) is a uniform acceleration
    /// every sphere feels (refused with `periodic_box` and with `"sticky"`).
    ///
    /// `ValueError` for invalid spheres, shapes, materials or pairs, overlaps at the start, a
    /// sphere through a shape, or a box too small (the message names the item); `TypeError`
    /// for an argument of the wrong type or a shape of another kind; a `RuntimeWarning` (the
    /// build goes on) for a sphere so far from the origin that its contacts may overlap past
    /// the tolerance.
    #[staticmethod]
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (centres, velocities, radii, masses = None, *, planes = None,
        cylinders = None, containers = None, periodic_box = None, restitution = None,
        response = None, tc = None, materials = None, pairs = None, record_events = None,
        geometry = None, gravity = None),
        text_signature = "(centres, velocities, radii, masses=None, *, planes=None, cylinders=None, containers=None, periodic_box=None, restitution=None, response=None, tc=0.0, materials=None, pairs=None, record_events=False, geometry=False, gravity=None)")]
    fn from_spheres<'py>(
        py: Python<'py>,
        centres: &Bound<'py, PyAny>,
        velocities: &Bound<'py, PyAny>,
        radii: &Bound<'py, PyAny>,
        masses: Option<&Bound<'py, PyAny>>,
        planes: Option<&Bound<'py, PyAny>>,
        cylinders: Option<&Bound<'py, PyAny>>,
        containers: Option<&Bound<'py, PyAny>>,
        periodic_box: Option<&Bound<'py, PyAny>>,
        restitution: Option<&Bound<'py, PyAny>>,
        response: Option<&Bound<'py, PyAny>>,
        tc: Option<&Bound<'py, PyAny>>,
        materials: Option<&Bound<'py, PyAny>>,
        pairs: Option<&Bound<'py, PyAny>>,
        record_events: Option<&Bound<'py, PyAny>>,
        geometry: Option<&Bound<'py, PyAny>>,
        gravity: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Self> {
        let mut world = spheres_world(centres, velocities, radii, masses, materials)?;
        let kwargs = PyDict::new(py);
        for (items, name, takes) in [
            (planes, "planes", Takes::Only(ShapeKind::Plane)),
            (cylinders, "cylinders", Takes::Only(ShapeKind::Cylinder)),
            (containers, "containers", Takes::Only(ShapeKind::Container)),
        ] {
            kwargs.set_item(name, add_shapes(py, &mut world, items, name, takes)?)?;
        }
        let mut given_pairs = Vec::new();
        if let Some(pairs) = optional(pairs) {
            let iter = pairs
                .try_iter()
                .map_err(|_| args::wrong_type("pairs", "a sequence of (a, b, response)", pairs))?;
            for (k, item) in iter.enumerate() {
                let item = item?;
                world
                    .effects
                    .pairs
                    .push(material_pair(&item, &format!("pairs[{k}]"))?);
                given_pairs.push(item);
            }
        }
        kwargs.set_item("pairs", PyTuple::new(py, given_pairs)?)?;
        name_materials(&mut world);
        if let Some(b) = optional(periodic_box) {
            let size = crate::arrays::vector3::<f64>(b, "periodic_box")?;
            world.boundary = Boundary::Periodic {
                size: DVec3::from_array(size),
            };
            kwargs.set_item("periodic_box", size.to_vec())?;
        }
        world.effects.response = scene_response(optional(response), optional(restitution))?;
        let tc = optional(tc).map_or(Ok(0.0), |t| real(t, "tc"))?;
        if !(tc.is_finite() && tc >= 0.0) {
            return Err(PyValueError::new_err(format!(
                "tc: {} is not a finite duration >= 0",
                show(tc)
            )));
        }
        world.effects.tc = tc;
        world.effects.record_events =
            optional(record_events).map_or(Ok(false), |r| flag(r, "record_events"))?;
        world.effects.geometry = optional(geometry).map_or(Ok(false), |g| flag(g, "geometry"))?;
        for (name, value) in [("restitution", restitution), ("response", response)] {
            kwargs.set_item(name, optional(value))?;
        }
        kwargs.set_item("tc", tc)?;
        if let Some(g) = optional(gravity) {
            let g = crate::arrays::vector3::<f64>(g, "gravity")?;
            world.effects.gravity = DVec3::from_array(g);
            kwargs.set_item("gravity", g.to_vec())?;
        }
        kwargs.set_item("record_events", world.effects.record_events)?;
        kwargs.set_item("geometry", world.effects.geometry)?;
        let materials: Vec<u16> = world.spheres.iter().map(|s| s.material).collect();
        kwargs.set_item("materials", materials.into_pyarray(py))?;
        let coarse = world.coarse_sphere();
        let sim = Self::new(
            world,
            None,
            Origin::Spheres {
                kwargs: kwargs.unbind(),
            },
        )?;
        // Once the world is known to be valid.
        if let Some(c) = coarse {
            warn(py, format!("centres[{}]: {}", c.sphere, c.problem()))?;
        }
        Ok(sim)
    }

    /// Processes every collision up to time `t` (inclusive) and moves the clock to `t`, with
    /// the GIL released. Every 4096 events it checks for signals: Ctrl-C stops it between two
    /// events and raises `KeyboardInterrupt`, the simulation left usable at the time it
    /// reached (`time`). `progress`, if given, is called as `progress(time)` at most ten times
    /// a second while it runs, and once with `t` at the end (an exception from it stops the
    /// run likewise). `ValueError` if `t` is not finite or before `time`. With `check` (the
    /// default) the state reached is checked against the invariant (`check_invariant`), as
    /// `spheresweep run` checks every snapshot: `InvariantError` naming the sphere, the other
    /// body and the time if it is broken. A `SimulationError` found on the way (the spheres
    /// flown apart beyond their reach, a stall) leaves the simulation at the last event it
    /// processed (`time`), usable: after "beyond what the simulation can reach", advancing
    /// to the time the message names succeeds.
    #[pyo3(signature = (t, *, progress = None, check = None),
           text_signature = "($self, t, *, progress=None, check=True)")]
    fn advance_to(
        &self,
        py: Python<'_>,
        t: &Bound<'_, PyAny>,
        progress: Option<&Bound<'_, PyAny>>,
        check: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let t = real(t, "t")?;
        let check = optional(check).map_or(Ok(true), |c| flag(c, "check"))?;
        let progress = optional(progress).map(|p| p.clone().unbind());
        if let Some(p) = &progress
            && !p.bind(py).is_callable()
        {
            return Err(args::wrong_type("progress", "a callable", p.bind(py)));
        }
        let mut guard = self.lock(py);
        let now = guard.time();
        if !t.is_finite() {
            return Err(PyValueError::new_err(format!(
                "t: cannot advance to t = {}: the end time must be finite (the simulation is at t = {})",
                show(t),
                show(now)
            )));
        }
        if t < now {
            return Err(PyValueError::new_err(format!(
                "t: cannot advance to t = {}: the simulation is at t = {} (time runs forward only)",
                show(t),
                show(now)
            )));
        }
        let sim: &mut sim::Simulation = &mut guard;
        let mut watch = Watch {
            progress: progress.as_ref(),
            last: Instant::now(),
            error: None,
        };
        let finished = py
            .detach(|| sim.advance_with(t, &mut |now, _| watch.keep_going(now)))
            .map_err(sim_error)?;
        if check {
            // `&mut`: the simulation is `Send`, not `Sync`.
            let sim = &mut *sim;
            py.detach(move || sim.check_invariant().map(drop))
                .map_err(sim_error)?;
        }
        if let Some(e) = watch.error {
            return Err(e);
        }
        debug_assert!(finished);
        if let Some(p) = &progress {
            p.call1(py, (t,))?;
        }
        Ok(())
    }

    /// The current time.
    #[getter]
    fn time(&self, py: Python<'_>) -> f64 {
        self.lock(py).time()
    }

    /// Once an open scene's spheres have flown apart for good (no pair ever meets, no sphere
    /// moves towards a shape), the time of the last thing that happened; `None` until then.
    #[getter]
    fn flown_apart(&self, py: Python<'_>) -> Option<f64> {
        self.lock(py).flown_apart()
    }

    /// The end time the scene file asked for (`[run] t_end`), or `None`.
    #[getter]
    fn t_end(&self) -> Option<f64> {
        self.t_end
    }

    /// The periodic box's lengths `(Lx, Ly, Lz)`, or `None` in open space.
    #[getter(r#box)]
    fn periodic_box_lengths(&self) -> Option<(f64, f64, f64)> {
        self.periodic_box().map(|b| (b.x, b.y, b.z))
    }

    /// Number of spheres.
    fn __len__(&self) -> usize {
        self.world.spheres.len()
    }

    /// Centres now, float64 `(N, 3)` (periodic centres wrapped into the box).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.rows(py, |s| s.centre)
    }

    /// Velocities now, float64 `(N, 3)`.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.rows(py, |s| s.velocity)
    }

    /// Radii, float64 `(N,)`.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut r = memory::with_capacity(self.world.spheres.len(), "radii")?;
        r.extend(self.world.spheres.iter().map(|s| s.radius));
        Ok(r.into_pyarray(py))
    }

    /// Masses, float64 `(N,)`.
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut m = memory::with_capacity(self.world.spheres.len(), "masses")?;
        m.extend(self.world.spheres.iter().map(|s| s.mass));
        Ok(m.into_pyarray(py))
    }

    /// Total kinetic energy `sum(m v^2 / 2)`.
    fn kinetic_energy(&self, py: Python<'_>) -> f64 {
        self.lock(py).kinetic_energy()
    }

    /// Total potential energy in the uniform gravity `g`, `sum(-m g . r)` (0 without gravity).
    fn potential_energy(&self, py: Python<'_>) -> f64 {
        self.lock(py).potential_energy()
    }

    /// The energy balance now, a dict: `kinetic`, `potential`, `lost` (what collisions took,
    /// less what rest hops gave) and `total`, their sum, which stays what it was at the start.
    fn energy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (k, u, lost) = {
            let sim = self.lock(py);
            (
                sim.kinetic_energy(),
                sim.potential_energy(),
                sim.stats().energy_lost,
            )
        };
        let d = PyDict::new(py);
        d.set_item("kinetic", k)?;
        d.set_item("potential", u)?;
        d.set_item("lost", lost)?;
        d.set_item("total", k + u + lost)?;
        Ok(d)
    }

    /// Total momentum `sum(m v)`, a tuple of three floats.
    fn momentum(&self, py: Python<'_>) -> (f64, f64, f64) {
        let p = self.lock(py).momentum();
        (p.x, p.y, p.z)
    }

    /// Checks the state now against the invariant every run keeps, from the positions alone:
    /// no two spheres overlap, and none is through a static shape or past a container's wall,
    /// beyond the derived tolerance (docs/derivations/simulation.md, "The invariant every run
    /// keeps"). Returns `{"time", "pairs", "walls"}`: the deepest overlap of a pair and of a
    /// sphere with a shape, each divided by its tolerance (`<= 0` when nothing overlaps, at most
    /// 1 within the tolerance; `-inf` for `walls` without shapes). A world with
    /// `response="none"` (spheres pass through each other and through shapes) is measured but
    /// never refused. `InvariantError` naming the sphere, the other body and the time otherwise.
    fn check_invariant<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let mut guard = self.lock(py);
        // `&mut`: the simulation is `Send`, not `Sync`.
        let sim: &mut sim::Simulation = &mut guard;
        let report = py
            .detach(move || sim.check_invariant())
            .map_err(sim_error)?;
        let d = PyDict::new(py);
        d.set_item("time", report.time)?;
        d.set_item("pairs", report.pairs)?;
        d.set_item("walls", report.walls)?;
        Ok(d)
    }

    /// Breaks the concave-wall rules on purpose (the rules under which spheres left inelastic
    /// vessels), so that a test can show `advance_to` catch the breach. Not for other use.
    fn _break_walls_for_testing(&self, py: Python<'_>) {
        self.lock(py).break_walls_for_testing();
    }

    /// Gives every sphere a new velocity now (float64 `(N, 3)`, one row per sphere), as a
    /// thermostat or a restart at another temperature would; every event is predicted again.
    /// `ValueError` naming the sphere for a non-finite row, and for a sticky cluster whose
    /// members are given different velocities (or one stuck to a shape given a non-zero one).
    fn set_velocities(&self, py: Python<'_>, velocities: &Bound<'_, PyAny>) -> PyResult<()> {
        let n = self.world.spheres.len();
        let v = floats::<f64>(velocities, "velocities", Expect::Rows3)?;
        let v = v.as_array();
        if v.shape()[0] != n {
            return Err(PyValueError::new_err(format!(
                "velocities: {} rows, expected {n} (one per sphere)",
                v.shape()[0]
            )));
        }
        let mut rows = memory::with_capacity(n, "velocities")?;
        rows.extend((0..n).map(|i| DVec3::from_array(row3(&v, i))));
        let mut guard = self.lock(py);
        let sim: &mut sim::Simulation = &mut guard;
        py.detach(|| sim.set_velocities(&rows)).map_err(sim_error)
    }

    /// How many times each sphere has crossed each face of the periodic box, int64 `(N, 3)`
    /// (`+1` out through the upper face), counted from the centre given (a centre given
    /// outside the box starts with the faces it was wrapped across); all zero in open space.
    fn images<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let n = self.world.spheres.len();
        memory::check("images", n.saturating_mul(2 * 24))?;
        let data: Vec<i64> = self.lock(py).images().into_iter().flatten().collect();
        Ok(Array2::from_shape_vec((n, 3), data)
            .expect("3 per sphere")
            .into_pyarray(py))
    }

    /// Centres as if the periodic box did not wrap them, float64 `(N, 3)`:
    /// `positions + images() * box` (the same as `positions` in open space), for a
    /// mean-squared displacement.
    fn unwrapped_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let size = self.periodic_box().unwrap_or(DVec3::ZERO);
        let n = self.world.spheres.len();
        memory::check(
            "unwrapped positions",
            n.saturating_mul(std::mem::size_of::<SphereState>() + 48),
        )?;
        // One lock for both: another thread's `advance_to` must not come between them.
        let (images, spheres) = {
            let sim = self.lock(py);
            (sim.images(), sim.spheres())
        };
        let mut data = memory::with_capacity(3 * spheres.len(), "unwrapped positions")?;
        for (s, k) in spheres.iter().zip(&images) {
            let k = DVec3::new(k[0] as f64, k[1] as f64, k[2] as f64);
            data.extend((s.centre + k * size).to_array());
        }
        Ok(Array2::from_shape_vec((spheres.len(), 3), data)
            .expect("3 per sphere")
            .into_pyarray(py))
    }

    /// Counters since the start, as a dict: `collisions` (pair + wall), `pair_collisions`,
    /// `wall_collisions`, `crossings`, `stale`, `predictions`, `kernels_sphere`,
    /// `kernels_plane`, `kernels_cylinder`, `kernels_container`, `energy_lost`, `virial`,
    /// `max_overlap` (of a pair, over its contact distance), `max_wall_overlap` (of a sphere
    /// with a shape, over its radius), `slid` (collisions with a concave wall answered by the
    /// sliding floor), `joins`, `guarded`.
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
        d.set_item("max_wall_overlap", s.max_wall_overlap)?;
        d.set_item("slid", s.slid)?;
        d.set_item("joins", s.joins)?;
        d.set_item("guarded", s.guarded)?;
        Ok(d)
    }

    /// The pressure of a periodic box since the start, from the collision virial
    /// (`Simulation::pressure` of the library), as a dict: `p`, `z` (`PV/(NkT)`), `phi` (the
    /// packing fraction), `kt`, and `carnahan_starling` (that equation of state's `Z` at
    /// `phi`, for comparison in an elastic gas of equal spheres); `None` outside a periodic
    /// box or before any time has passed.
    #[getter]
    fn pressure<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(p) = self.lock(py).pressure() else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("p", p.p)?;
        d.set_item("z", p.z)?;
        d.set_item("phi", p.phi)?;
        d.set_item("kt", p.kt)?;
        d.set_item(
            "carnahan_starling",
            sim::observables::carnahan_starling_z(p.phi),
        )?;
        Ok(Some(d))
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
    fn checkpoint<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let sim = self.lock(py);
        memory::check("checkpoint", sim.memory_bytes())?;
        Ok(PyBytes::new(py, &sim.checkpoint()))
    }

    /// Puts the simulation back in the state `checkpoint` saved (time, positions, velocities,
    /// counters, pending events), so that it goes on exactly as the saved one would. The bytes
    /// must come from the same system: spheres of the same radii, masses and materials, the
    /// same shapes, boundary and effects (starting positions and velocities may differ: the
    /// checkpoint holds them). `ValueError` saying why otherwise (damaged, truncated, another
    /// world), and the simulation is left as it was.
    fn restore(&self, py: Python<'_>, data: &Bound<'_, PyAny>) -> PyResult<()> {
        let data = data
            .cast::<PyBytes>()
            .map_err(|_| args::wrong_type("data", "bytes", data))?
            .as_bytes();
        let world = self.world.clone();
        memory::check("restore", simulation_bytes(world.spheres.len()))?;
        let restored = py
            .detach(move || sim::Simulation::restore(world, data))
            .map_err(sim_error)?;
        *self.lock(py) = restored;
        Ok(())
    }

    /// The collisions recorded since the last call (empty unless the simulation records
    /// events), as a dict of 1-D arrays, one row per event (so `pandas.DataFrame(...)` of it
    /// is a table): `time` float64, `sphere` uint32, `kind` uint8 (`KIND_*`), `index` int64,
    /// `approach`, `restitution`, `energy_lost` float64, and `point_x`, `point_y`, `point_z`,
    /// `normal_x`, `normal_y`, `normal_z` float64 (NaN without geometry).
    fn take_events<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let events = self.lock(py).take_events();
        let k = events.len();
        let d = PyDict::new(py);
        let col_f = |f: fn(&sim::EventRecord) -> f64| -> PyResult<Vec<f64>> {
            let mut v = memory::with_capacity(k, "events")?;
            v.extend(events.iter().map(f));
            Ok(v)
        };
        d.set_item("time", col_f(|e| e.time)?.into_pyarray(py))?;
        let mut sphere = memory::with_capacity(k, "events")?;
        sphere.extend(events.iter().map(|e| e.sphere));
        d.set_item("sphere", sphere.into_pyarray(py))?;
        let mut kind = memory::with_capacity(k, "events")?;
        kind.extend(events.iter().map(|e| kind_code(e.other.kind)));
        debug_assert!(kind.iter().all(|&c| c != KIND_NONE));
        d.set_item("kind", kind.into_pyarray(py))?;
        let mut index = memory::with_capacity(k, "events")?;
        index.extend(events.iter().map(|e| i64::from(e.other.index)));
        d.set_item("index", index.into_pyarray(py))?;
        d.set_item("approach", col_f(|e| e.approach)?.into_pyarray(py))?;
        d.set_item("restitution", col_f(|e| e.restitution)?.into_pyarray(py))?;
        d.set_item("energy_lost", col_f(|e| e.energy_lost)?.into_pyarray(py))?;
        let geo = |f: fn(&sim::EventGeometry) -> DVec3| -> PyResult<Vec<f64>> {
            let mut v = memory::with_capacity(3 * k, "events")?;
            v.extend(events.iter().flat_map(|e| {
                e.geometry
                    .as_ref()
                    .map_or([f64::NAN; 3], |g| f(g).to_array())
            }));
            Ok(v)
        };
        for (name, data) in [("point", geo(|g| g.point)?), ("normal", geo(|g| g.normal)?)] {
            let array = Array2::from_shape_vec((k, 3), data).expect("3 per event");
            put_column(&d, name, array.into_pyarray(py).as_any())?;
        }
        Ok(d)
    }

    /// Pickling: how the simulation was built (a scene file's text, `periodic_gas`'s or
    /// `from_spheres`' arguments) and its checkpoint; unpickled, it is rebuilt so and restored,
    /// to go on bit for bit as this one.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let (py, me) = (slf.py(), slf.get());
        let rebuild = slf.get_type().getattr("_unpickle")?;
        let how = match &me.origin {
            Origin::SceneFile { text, json } => (
                "scene_file",
                (text.as_str(), *json).into_pyobject(py)?.into_any(),
            ),
            Origin::Gas { args } => ("periodic_gas", args.bind(py).clone().into_any()),
            Origin::Spheres { kwargs } => (
                "from_spheres",
                (start_arrays(py, &me.world.spheres)?, kwargs.bind(py))
                    .into_pyobject(py)?
                    .into_any(),
            ),
        };
        let state = me.checkpoint(py)?;
        Ok((rebuild, (how.0, how.1, state).into_pyobject(py)?))
    }

    /// Unpickling: the simulation `how` built, restored to `state` (see `__reduce__`).
    #[staticmethod]
    fn _unpickle<'py>(
        py: Python<'py>,
        constructor: &str,
        how: &Bound<'py, PyAny>,
        state: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let cls = py.get_type::<Simulation>();
        let sim = match constructor {
            "scene_file" => {
                let (text, json): (String, bool) = how.extract()?;
                let file = if json {
                    SceneFile::from_json_str(&text)
                } else {
                    SceneFile::from_toml_str(&text)
                }
                .map_err(scene_file_error)?;
                let (world, t_end) = scene_file_world(&file)?;
                let sim = Self::new(world, Some(t_end), Origin::SceneFile { text, json })?;
                Bound::new(py, sim)?.into_any()
            }
            "periodic_gas" => cls.call_method1("periodic_gas", how.cast::<PyTuple>()?)?,
            "from_spheres" => {
                let (args, kwargs): (Bound<'py, PyTuple>, Bound<'py, PyDict>) = how.extract()?;
                // Its warnings were given when it was first built (as a scene file's are not
                // given again below): a pickle sent to many workers would repeat them.
                let quiet = py.import("warnings")?.call_method0("catch_warnings")?;
                quiet.call_method0("__enter__")?;
                py.import("warnings")?.call_method1(
                    "simplefilter",
                    ("ignore", py.get_type::<PyRuntimeWarning>()),
                )?;
                let built = cls.call_method("from_spheres", args, Some(&kwargs));
                let none = py.None();
                quiet.call_method1("__exit__", (&none, &none, &none))?;
                built?
            }
            other => {
                return Err(PyValueError::new_err(format!(
                    "unpickling: unknown constructor {other:?}"
                )));
            }
        };
        sim.call_method1("restore", (state,))?;
        Ok(sim)
    }

    /// Appends the state now as one frame of extended XYZ to the file at `path` (created if
    /// absent): the format of `spheresweep run`'s `trajectory.xyz`, which `read_xyz`, OVITO
    /// and ASE read (periodic centres wrapped, the box as `Lattice`).
    fn write_xyz(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let spheres = self.spheres(py)?;
        let time = self.lock(py).time();
        crate::xyz::append_frame(&path, &spheres, time, self.periodic_box())
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let sim = self.lock(py);
        format!(
            "Simulation(<{} spheres, t = {}, {}>)",
            self.world.spheres.len(),
            show(sim.time()),
            sim.engine_name()
        )
    }
}
