//! Event-driven simulation: a [`World`] advanced to any time with every collision in exact time
//! order, assembled from only the effects the scene calls for.
//!
//! ```
//! use spheresweep::sim::{Boundary, Simulation, World, generate};
//! use glam::DVec3;
//! // 500 hard spheres of diameter 1 at packing fraction 0.2 in a periodic box.
//! let mut world = World { boundary: Boundary::Periodic { size: DVec3::ZERO }, ..World::default() };
//! generate::periodic_gas(&mut world, 500, 0.2, 0.5, 1.0, 7)?;
//! let mut sim = Simulation::new(world)?;
//! let e0 = sim.kinetic_energy();
//! sim.advance_to(5.0)?;
//! assert!(sim.stats().pair_collisions > 1000);
//! assert!((sim.kinetic_energy() - e0).abs() < 1e-9 * e0);
//! # Ok::<(), spheresweep::sim::SimError>(())
//! ```
//!
//! The layer sits above the whole-scene query and uses the kernels directly: each sphere has a
//! neighbour list with a shell, and pair prediction answers the approaching entries with the
//! `Stable` kernel on `f64x4` lanes; static shapes use the f64 kernels. Policies and bounds: docs/derivations/simulation.md.
//! Under [`Effects::gravity`] paths are parabolas, pairs still meet on a line, and the static
//! shapes' contacts are the certified roots of a quadratic or quartic
//! (docs/derivations/gravity.md).

mod assemble;
mod cells;
mod checkpoint;
mod demo;
mod engine;
pub mod generate;
mod invariant;
mod model;
pub mod observables;
mod pages;
mod persist;
mod precision;
mod predict;
mod queue;
mod records;
mod response;
mod run;
mod runs;
mod stats;
#[cfg(test)]
mod tests;
mod walls;

pub use demo::demo_world;
pub use invariant::InvariantReport;
#[cfg(feature = "scene-file")]
pub(crate) use model::{BEYOND_RANGE, bounded3};
pub use model::{
    Boundary, Effects, MAX_MAGNITUDE, MAX_MATERIALS, MIN_MAGNITUDE, MaterialPair, OutOfRange,
    Response, SimError, SphereState, World,
};
pub(crate) use model::{OUTSIDE_RANGE, in_range};
pub use precision::CoarseSphere;
pub use records::{EventGeometry, EventRecord};
pub use stats::{KernelCounts, Stats};

use glam::DVec3;

use run::Run;

/// Overlap beyond which the engine refuses a start state, relative to the contact distance
/// (docs/derivations/simulation.md derives the engine's own bound, far below it).
pub const OVERLAP_TOLERANCE: f64 = 1.0 / (1u64 << 16) as f64;

/// A running simulation.
///
/// ```
/// # use glam::DVec3;
/// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
/// # let ball = |x: f64, vx: f64| SphereState {
/// #     centre: DVec3::new(x, 0.0, 0.0),
/// #     velocity: DVec3::new(vx, 0.0, 0.0),
/// #     radius: 0.5,
/// #     mass: 1.0,
/// #     material: 0,
/// # };
/// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
/// let world = World {
///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
///     ..World::default()
/// };
/// let mut sim = Simulation::new(world)?;
/// sim.advance_to(2.0)?;
/// let [a, b] = [sim.spheres()[0], sim.spheres()[1]];
/// assert!((a.centre.x - 0.0).abs() < 1e-12 && (b.centre.x - 3.0).abs() < 1e-12); // back at the start
/// assert_eq!((a.velocity.x, b.velocity.x), (-1.0, 1.0)); // velocities swapped
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
pub struct Simulation {
    engine: Box<dyn Run>,
    /// Each sphere's material and mass, in public order.
    materials: Vec<u16>,
    masses: Vec<f64>,
    /// Identifies the world a checkpoint belongs to.
    fingerprint: u64,
    /// Each sphere's side of each plane at the start (the invariant: it never changes).
    sides: Vec<bool>,
    /// Where the spheres live.
    boundary: Boundary,
    /// The faces each periodic sphere given outside the box was taken across to start in it
    /// (its centre wrapped in); empty if none was.
    start_images: Vec<[i64; 3]>,
    /// The spheres that fill a container, each as the error that refuses it moving
    /// (`assemble::filling`): none may be given a velocity.
    filling: Vec<SimError>,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("engine", &self.engine.name())
            .field("time", &self.engine.now())
            .finish()
    }
}

impl Simulation {
    /// Where the spheres live: the world's boundary (a periodic gas's generated box included).
    ///
    /// ```
    /// use spheresweep::sim::{Boundary, Simulation, World, generate};
    /// let mut world = World::default();
    /// generate::periodic_gas(&mut world, 256, 0.3, 0.5, 1.0, 3)?;
    /// let sim = Simulation::new(world)?;
    /// assert!(matches!(sim.boundary(), Boundary::Periodic { size } if size.x > 6.0));
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn boundary(&self) -> Boundary {
        self.boundary
    }

    /// How many times each sphere has crossed each face of a periodic box (`+1` out through
    /// the upper face, `−1` through the lower), in sphere order, up to now: its unwrapped centre
    /// is `centre + images · size`, which follows its path at every time read (for a
    /// mean-squared displacement), from the centre given: a sphere given outside the box
    /// starts with the faces its centre was wrapped across. All zero in open space.
    ///
    /// ```
    /// use spheresweep::sim::{Boundary, Simulation, World, generate};
    /// let mut world = World::default();
    /// generate::periodic_gas(&mut world, 256, 0.1, 0.5, 1.0, 3)?;
    /// let mut sim = Simulation::new(world)?;
    /// sim.advance_to(20.0)?;
    /// let moved = sim.images().iter().filter(|i| **i != [0; 3]).count();
    /// assert!(moved > 10); // a dilute gas crosses the box's faces
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn images(&self) -> Vec<[i64; 3]> {
        let mut images = self.crossed();
        for (k, start) in images.iter_mut().zip(&self.start_images) {
            // Saturating: a centre given past 2⁶³ box lengths counts as that many.
            *k = std::array::from_fn(|a| k[a].saturating_add(start[a]));
        }
        images
    }

    /// The faces each sphere has crossed since it started in the box.
    fn crossed(&self) -> Vec<[i64; 3]> {
        let images = self.engine.images();
        if images.is_empty() {
            vec![[0; 3]; self.masses.len()]
        } else {
            images
        }
    }

    /// Gives every sphere a new velocity now (in sphere order), as a thermostat or a restart
    /// at another temperature would, and predicts every event again. The members of a sticky
    /// cluster move as one, so each must be given the same velocity, and a cluster stuck to a
    /// static shape must be given zero.
    ///
    /// # Errors
    /// [`SimError::State`] for a wrong count or a rule above broken, [`SimError::Sphere`] for
    /// a value that is not finite or has a component beyond [`MAX_MAGNITUDE`],
    /// [`SimError::Range`] when the fastest moves slower than [`MIN_MAGNITUDE`] (as a new world
    /// is refused); nothing is changed then.
    ///
    /// ```
    /// use glam::DVec3;
    /// use spheresweep::sim::{Simulation, World, generate};
    /// let mut world = World::default();
    /// generate::periodic_gas(&mut world, 256, 0.3, 0.5, 1.0, 3)?;
    /// let mut sim = Simulation::new(world)?;
    /// sim.advance_to(1.0)?;
    /// // Twice the temperature: every velocity times √2.
    /// let v: Vec<DVec3> = sim.spheres().iter().map(|s| s.velocity * 2f64.sqrt()).collect();
    /// let e = sim.kinetic_energy();
    /// sim.set_velocities(&v)?;
    /// assert!((sim.kinetic_energy() - 2.0 * e).abs() < 1e-9 * e);
    /// sim.advance_to(2.0)?;
    /// assert!(sim.set_velocities(&v[..10]).is_err()); // one velocity per sphere
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn set_velocities(&mut self, velocities: &[DVec3]) -> Result<(), SimError> {
        let n = self.masses.len();
        if velocities.len() != n {
            return Err(SimError::State(format!(
                "velocities: {} given for {n} spheres",
                velocities.len()
            )));
        }
        if let Some(index) = velocities.iter().position(|v| !v.is_finite()) {
            return Err(SimError::Sphere {
                index,
                field: "velocity",
                problem: crate::error::Problem::NotFinite,
            });
        }
        // The range a new world is held to (`World::validate`): past it, the engine's
        // arithmetic overflows or its watchdog stalls.
        if let Some(index) = velocities.iter().position(|&v| !model::bounded3(v)) {
            return Err(SimError::Sphere {
                index,
                field: "velocity",
                problem: crate::error::Problem::OutOfRange,
            });
        }
        model::fastest_in_range(velocities.iter().copied())?;
        if let Some(e) = assemble::moving_without_room(&self.filling, |i| velocities[i], false) {
            return Err(e);
        }
        self.engine.set_velocities(velocities)
    }

    /// Fault injection, for tests that show a broken engine is caught: from now on the
    /// engine leaves container walls without the floor angle and answers a sphere past the
    /// wall that never gets back in as no contact — the rules before 2026-12-01, under which
    /// spheres left inelastic vessels. Not for use outside tests.
    #[doc(hidden)]
    pub fn break_walls_for_testing(&mut self) {
        self.engine.break_walls();
    }

    /// Checks the state now against the invariant every run keeps, from the spheres' positions
    /// alone (not the engine's predictions): no two spheres overlap by more than
    /// [`OVERLAP_TOLERANCE`] of their contact distance, and none is through a static shape, past
    /// a container's wall or across a plane from where it started by more than
    /// [`OVERLAP_TOLERANCE`] of its radius. A report-only world (spheres pass through each
    /// other and through shapes) is measured but never refused. Costs about as much as a
    /// snapshot: one pass over the spheres with a cell sort, and every sphere against every
    /// shape.
    ///
    /// # Errors
    /// [`SimError::Breach`] naming the sphere, the other body, the depth and the time, or
    /// [`SimError::NotFinite`] naming a sphere whose centre or velocity is NaN or infinite: the
    /// engine broke its invariant (a bug).
    ///
    /// ```
    /// # use glam::DVec3;
    /// use spheresweep::sim::{Effects, Response, Simulation, SphereState, World};
    /// use spheresweep::{Container, Statics};
    /// // One inelastic sphere in a vessel: its bounces decay until it slides along the wall.
    /// let world = World {
    ///     spheres: vec![SphereState {
    ///         centre: DVec3::new(3.0, 0.0, 0.0),
    ///         velocity: DVec3::new(0.3, 1.0, 0.2),
    ///         radius: 0.5,
    ///         mass: 1.0,
    ///         material: 0,
    ///     }],
    ///     statics: Statics::new().with(Container::new([0.0; 3], 6.0)?, 0),
    ///     effects: Effects { response: Response::Inelastic { restitution: 0.3 }, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// sim.advance_to(200.0)?;
    /// let report = sim.check_invariant()?;
    /// assert!(report.walls < 1e-3); // far inside the tolerance
    /// assert!(sim.spheres()[0].centre.length() <= 5.5 * (1.0 + 1e-12));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn check_invariant(&self) -> Result<InvariantReport, SimError> {
        let bodies = self.engine.current();
        let (cells, walls, periodic, report_only) = self.engine.layout();
        let sides = if report_only { &[][..] } else { &self.sides };
        let time = self.engine.now();
        // The sides were taken where the spheres started in the box.
        let images = if periodic { self.crossed() } else { Vec::new() };
        // A NaN compares as no overlap: a sphere with no number for a centre is named first.
        if let Some(sphere) = bodies
            .iter()
            .position(|b| !(b.r.is_finite() && b.v.is_finite()))
        {
            return Err(SimError::NotFinite { time, sphere });
        }
        match invariant::check(&bodies, cells, periodic, walls, sides, &images) {
            Ok((pairs, walls)) => Ok(InvariantReport { time, pairs, walls }),
            Err(_) if report_only => Ok(InvariantReport {
                time,
                pairs: f64::NAN,
                walls: f64::NAN,
            }),
            Err(b) => Err(SimError::Breach {
                time,
                sphere: b.sphere,
                other: b.other,
                depth: b.depth,
                tolerance: b.tolerance,
            }),
        }
    }

    /// Processes every event up to time `t` (inclusive) and moves the clock to `t`.
    ///
    /// # Errors
    /// [`SimError::Time`] if `t` is not finite or before [`time`](Self::time), nothing done;
    /// an error found on the way ([`SimError::Flown`] once the spheres have flown apart for
    /// good and `t` is beyond their reach, [`SimError::Stalled`], [`SimError::Collapse`])
    /// leaves the simulation at the last event it processed, consistent and usable: after
    /// `Flown`, advancing to the time it names succeeds.
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// sim.advance_to(0.5)?;
    /// assert_eq!((sim.time(), sim.stats().pair_collisions), (0.5, 0)); // not yet
    /// sim.advance_to(1.5)?;
    /// assert_eq!(sim.stats().pair_collisions, 1);
    /// assert!(sim.advance_to(1.0).is_err()); // time runs forward only
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn advance_to(&mut self, t: f64) -> Result<(), SimError> {
        self.advance_with(t, &mut |_, _| true).map(|_| ())
    }

    /// As [`advance_to`](Self::advance_to), asking `keep_going(time, stats)` every 4096
    /// events whether to continue (for progress bars and interruption). Returns `false` when
    /// stopped early, at a consistent state between two events.
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// let mut asked = 0;
    /// let finished = sim.advance_with(2.0, &mut |_, _| { asked += 1; true })?;
    /// assert!(finished && sim.time() == 2.0);
    /// assert!(asked <= 1); // one event here: at most one question, at the end
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn advance_with(
        &mut self,
        t: f64,
        keep_going: &mut dyn FnMut(f64, &Stats) -> bool,
    ) -> Result<bool, SimError> {
        let now = self.engine.now();
        if !(t.is_finite() && t >= now) {
            return Err(SimError::Time { now, to: t });
        }
        self.engine.run_until(t, keep_going)
    }

    /// If an open scene's spheres have flown apart for good (no pair will ever meet, no sphere
    /// moves towards a static shape), the time of the last thing that happened (a collision;
    /// the start if none did): the simulation has nothing left to do, and advancing it costs
    /// nothing (docs/derivations/simulation.md, "A scene that has flown apart").
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Simulation, SphereState, World};
    /// let lone = SphereState {
    ///     centre: DVec3::ZERO,
    ///     velocity: DVec3::X,
    ///     radius: 0.5,
    ///     mass: 1.0,
    ///     material: 0,
    /// };
    /// let mut sim = Simulation::new(World { spheres: vec![lone], ..World::default() })?;
    /// sim.advance_to(1e12)?; // a few dozen shell events, then none
    /// assert_eq!(sim.flown_apart(), Some(0.0)); // nothing ever happened
    /// assert_eq!(sim.spheres()[0].centre.x, 1e12);
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn flown_apart(&self) -> Option<f64> {
        self.engine.flown_apart()
    }

    /// The current time.
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// assert_eq!(sim.time(), 0.0);
    /// sim.advance_to(0.25)?;
    /// assert_eq!(sim.time(), 0.25);
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn time(&self) -> f64 {
        self.engine.now()
    }

    /// Counters and accumulated observables.
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// assert_eq!(sim.stats().pair_collisions, 0);
    /// sim.advance_to(2.0)?;
    /// assert_eq!(sim.stats().pair_collisions, 1);
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn stats(&self) -> &Stats {
        self.engine.stats()
    }

    /// Which engine the world was assembled into (response, boundary, shapes, geometry).
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let sim = Simulation::new(world)?;
    /// assert!(sim.engine_name().starts_with("elastic, open"));
    /// assert!(sim.engine_name().contains("contact geometry")); // the scene records geometry
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn engine_name(&self) -> String {
        self.engine.name()
    }

    /// Bytes the simulation holds (engine arrays, grid, calendar, unread event records, and
    /// the per-sphere mass, material, sides of planes and start images it keeps), for sizing
    /// runs.
    ///
    /// ```
    /// use spheresweep::sim::{Simulation, World, generate};
    /// let mut world = World::default();
    /// generate::periodic_gas(&mut world, 4000, 0.25, 0.5, 1.0, 1)?;
    /// let sim = Simulation::new(world)?;
    /// assert!(sim.memory_bytes() / 4000 < 512);
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn memory_bytes(&self) -> usize {
        self.engine.bytes()
            + self.masses.capacity() * 8
            + self.materials.capacity() * 2
            + self.sides.capacity()
            + self.start_images.capacity() * 24
    }

    /// Bytes a simulation of `spheres` spheres will hold, estimated before its world is built
    /// (from the sizes of the engine's arrays, with the largest grid `new` makes: four cells
    /// per sphere), so that a caller can refuse a scene too large for memory up front. The
    /// world handed to [`new`](Self::new) (about 72 bytes a sphere) is not counted. Within a
    /// factor of two above [`memory_bytes`](Self::memory_bytes) of a fresh simulation (tested).
    ///
    /// ```
    /// use spheresweep::sim::Simulation;
    /// let bytes = Simulation::estimated_bytes(1_000_000);
    /// assert!(bytes > 100_000_000 && bytes < 1_000_000_000);
    /// ```
    pub fn estimated_bytes(spheres: usize) -> usize {
        let max_cells = spheres
            .saturating_mul(4)
            .max(27)
            .max(spheres.saturating_mul(2).saturating_add(64));
        engine::estimated_bytes(spheres, max_cells)
            .saturating_add(spheres.saturating_mul(std::mem::size_of::<f64>() + 2))
    }

    /// Every sphere at the current time (periodic centres wrapped into the box).
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// sim.advance_to(0.5)?;
    /// let s = sim.spheres();
    /// assert_eq!((s.len(), s[0].centre.x, s[1].centre.x), (2, 0.5, 2.5));
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn spheres(&self) -> Vec<SphereState> {
        self.engine
            .current()
            .into_iter()
            .enumerate()
            .map(|(i, b)| SphereState {
                centre: b.r,
                velocity: b.v,
                radius: b.radius,
                mass: self.masses[i],
                material: self.materials[i],
            })
            .collect()
    }

    /// The spheres now and the static shapes as a query's [`Scene`](crate::scene::Scene):
    /// each sphere's centre now is its centre at the query's `t = 0`, in f32 (`Sphere::try_from`),
    /// so [`query::first_contacts`](crate::query::first_contacts) asks what each would meet
    /// next on a straight line from here. The query knows no gravity (its lines are not the
    /// parabolas the simulation follows) and no periodic box (a sphere near a face does not
    /// meet the images across it). Rounded to f32, a pair that has just collided may read as
    /// touching or overlapping by a rounding: receding, it is not a contact.
    ///
    /// # Errors
    /// [`StoreError::Invalid`](crate::store::StoreError::Invalid) naming a sphere whose centre
    /// or velocity has grown beyond f32's range (about 3.4·10³⁸; under gravity, after a long
    /// fall): every value a new simulation takes is within it.
    ///
    /// ```
    /// # use glam::DVec3;
    /// use spheresweep::sim::{Simulation, SphereState, World};
    /// use spheresweep::{Plane, QueryOptions, Statics, query};
    /// let bead = |x: f64, vx: f64| SphereState {
    ///     centre: DVec3::new(x, 0.0, 0.0),
    ///     velocity: DVec3::new(vx, 0.0, 0.0),
    ///     radius: 1.0,
    ///     mass: 1.0,
    ///     material: 0,
    /// };
    /// let world = World {
    ///     spheres: vec![bead(0.0, 1.0), bead(10.0, 0.0)],
    ///     statics: Statics::new().with(Plane::new([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0])?, 0),
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// sim.advance_to(4.0)?;
    /// let scene = sim.query_scene()?;
    /// let first = query::first_contacts(&scene, QueryOptions::default());
    /// // Sphere 0 is at x = 4, 4 short of touching sphere 1: it meets it 4 from now.
    /// assert_eq!(first[0].unwrap().time, 4.0);
    /// assert_eq!(scene.statics.len(), 1);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn query_scene(&self) -> Result<crate::scene::Scene, crate::store::StoreError> {
        let spheres = self
            .spheres()
            .iter()
            .enumerate()
            .map(|(index, s)| {
                crate::Sphere::try_from(s)
                    .map_err(|source| crate::store::StoreError::Invalid { index, source })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(crate::scene::Scene {
            spheres: crate::SphereStore::from_spheres(&spheres),
            statics: self.engine.layout().1.map(|_, _| ()),
        })
    }

    /// Total kinetic energy `Σ ½ m v²`.
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// assert_eq!(sim.kinetic_energy(), 1.0); // 2 × ½ · 1 · 1²
    /// sim.advance_to(2.0)?;
    /// assert!((sim.kinetic_energy() - 1.0).abs() < 1e-12); // elastic
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn kinetic_energy(&self) -> f64 {
        let (m, now) = (self.engine.motion(), self.engine.now());
        m.bodies
            .iter()
            .zip(&m.mass)
            .map(|(b, &mass)| 0.5 * mass * b.at(now, m.g).1.length_squared())
            .sum()
    }

    /// Total potential energy in the uniform gravity `g` of [`Effects::gravity`],
    /// `Σ −m g·r` (zero at the origin; always `0` without gravity). Under gravity
    /// `kinetic_energy() + potential_energy() + stats().energy_lost` stays what it was at the
    /// start (docs/derivations/gravity.md, "Energy").
    ///
    /// ```
    /// use glam::DVec3;
    /// use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// // A ball dropped from height 2 in g = −9.81 ẑ, with no floor.
    /// let world = World {
    ///     spheres: vec![SphereState {
    ///         centre: DVec3::new(0.0, 0.0, 2.0),
    ///         velocity: DVec3::ZERO,
    ///         radius: 0.5,
    ///         mass: 1.0,
    ///         material: 0,
    ///     }],
    ///     effects: Effects { gravity: DVec3::new(0.0, 0.0, -9.81), ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// let e0 = sim.kinetic_energy() + sim.potential_energy();
    /// assert!((sim.potential_energy() - 2.0 * 9.81).abs() < 1e-12);
    /// sim.advance_to(0.5)?;
    /// assert!((sim.spheres()[0].centre.z - (2.0 - 0.5 * 9.81 * 0.25)).abs() < 1e-12);
    /// assert!((sim.kinetic_energy() + sim.potential_energy() - e0).abs() < 1e-12);
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn potential_energy(&self) -> f64 {
        let (m, now) = (self.engine.motion(), self.engine.now());
        if m.g == DVec3::ZERO {
            return 0.0;
        }
        m.bodies
            .iter()
            .zip(&m.mass)
            .map(|(b, &mass)| -mass * m.g.dot(b.at(now, m.g).0))
            .sum()
    }

    /// Total momentum `Σ m v`.
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// assert_eq!(sim.momentum(), DVec3::ZERO); // equal and opposite
    /// sim.advance_to(2.0)?;
    /// assert!(sim.momentum().length() < 1e-12);
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn momentum(&self) -> DVec3 {
        let (m, now) = (self.engine.motion(), self.engine.now());
        m.bodies
            .iter()
            .zip(&m.mass)
            .map(|(b, &mass)| b.at(now, m.g).1 * mass)
            .sum()
    }

    /// The events recorded since the last call (empty unless `Effects::record_events`).
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world)?;
    /// sim.advance_to(2.0)?;
    /// assert_eq!(sim.take_events().len(), 1);
    /// assert!(sim.take_events().is_empty()); // taken
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn take_events(&mut self) -> Vec<EventRecord> {
        self.engine.take_log()
    }

    /// Clusters of two or more spheres (sticky scenes), as sphere indices.
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// use spheresweep::sim::Response;
    /// let sticky = World { effects: Effects { response: Response::Sticky, ..Effects::default() }, ..world };
    /// let mut sim = Simulation::new(sticky)?;
    /// assert!(sim.clusters().is_empty());
    /// sim.advance_to(2.0)?;
    /// assert_eq!(sim.clusters(), [vec![0, 1]]); // they met and stuck
    /// assert!(sim.momentum().length() < 1e-12 && sim.kinetic_energy() < 1e-12); // and stopped
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn clusters(&self) -> Vec<Vec<u32>> {
        self.engine.clusters()
    }
}
