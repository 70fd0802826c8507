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
//! The layer sits above the whole-scene query and uses the kernels directly: pair prediction
//! screens neighbours with the f32 8-wide `Stable` kernel and settles the earliest in f64;
//! static shapes use the f64 kernels. Policies and bounds: docs/derivations/simulation.md.

mod cells;
mod checkpoint;
mod demo;
mod engine;
pub mod generate;
mod invariant;
mod model;
mod predict;
mod queue;
mod response;
mod walls;

pub use demo::demo_world;
pub use invariant::InvariantReport;
pub use model::{
    Boundary, Effects, MAX_MATERIALS, MaterialPair, Response, SimError, SphereState, World,
};

use glam::DVec3;

use crate::contact::Body;
use crate::statics::Statics;
use cells::Cells;
use engine::Engine;
use response::{Elastic, Materials, Motion, Outcome, ReportOnly, Responder};

/// Overlap beyond which the engine refuses a start state, relative to the contact distance
/// (docs/derivations/simulation.md derives the engine's own bound, far below it).
pub const OVERLAP_TOLERANCE: f64 = 1.0 / (1u64 << 16) as f64;

/// Kernel evaluations by kind (sphere pairs count neighbours screened in f32 lanes; static
/// shapes count f64 kernel calls): which kernels a scene ran, and how often.
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
/// let kernels = sim.stats().kernels;
/// assert!(kernels.sphere > 0);
/// assert_eq!((kernels.plane, kernels.cylinder, kernels.container), (0, 0, 0)); // no shapes
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KernelCounts {
    /// Sphere–sphere lanes.
    pub sphere: u64,
    /// Sphere–plane evaluations.
    pub plane: u64,
    /// Sphere–cylinder evaluations.
    pub cylinder: u64,
    /// Sphere–container evaluations.
    pub container: u64,
}

/// Counters and accumulated observables since the start.
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
/// let stats = sim.stats();
/// assert_eq!((stats.pair_collisions, stats.wall_collisions, stats.joins), (1, 0, 0));
/// assert_eq!(stats.energy_lost, 0.0); // elastic
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    /// Sphere–sphere collisions (or reported contacts).
    pub pair_collisions: u64,
    /// Sphere–static-shape collisions.
    pub wall_collisions: u64,
    /// Cell crossings.
    pub crossings: u64,
    /// Pair events dropped because the partner had changed since the prediction.
    pub stale: u64,
    /// Full predictions of one sphere.
    pub predictions: u64,
    /// Kernels run.
    pub kernels: KernelCounts,
    /// Kinetic energy taken by inelastic and sticky collisions.
    pub energy_lost: f64,
    /// `Σ r_ij · Δp_j` over pair collisions (the collision virial).
    pub virial: f64,
    /// Largest overlap of two spheres seen at their collision, relative to their contact
    /// distance; 0 while none has overlapped.
    pub max_overlap: f64,
    /// Largest depth of a sphere through a static shape seen at their collision, relative to
    /// the sphere's radius; 0 while none has been through.
    pub max_wall_overlap: f64,
    /// Cluster joins (sticky collisions).
    pub joins: u64,
    /// Collisions whose impulse used the grazing floor.
    pub guarded: u64,
    /// Wall collisions a sphere left at a container's floor angle: sliding along the wall
    /// (docs/derivations/simulation.md, "Concave walls").
    pub slid: u64,
}

/// Contact point and normal of an event.
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
/// let g = sim.take_events()[0].geometry.unwrap(); // the scene asked for geometry
/// assert!((g.point - DVec3::new(1.5, 0.0, 0.0)).length() < 1e-12); // midway at t = 1
/// assert!((g.normal.x.abs() - 1.0).abs() < 1e-12);
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventGeometry {
    /// Where the bodies touch.
    pub point: DVec3,
    /// Unit normal pushing the sphere away from the other body.
    pub normal: DVec3,
}

/// One processed collision.
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
/// use spheresweep::{Body, ShapeKind};
/// let mut sim = Simulation::new(world)?;
/// sim.advance_to(2.0)?;
/// let events = sim.take_events();
/// assert_eq!(events.len(), 1);
/// let e = events[0];
/// assert!((e.time - 1.0).abs() < 1e-12 && (e.approach - 2.0).abs() < 1e-12);
/// assert_eq!((e.restitution, e.energy_lost), (1.0, 0.0));
/// assert_eq!((e.sphere, e.other), (0, Body::new(ShapeKind::Sphere, 1)));
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventRecord {
    /// When.
    pub time: f64,
    /// The sphere.
    pub sphere: u32,
    /// What it met.
    pub other: Body,
    /// Normal approach speed before the collision.
    pub approach: f64,
    /// Restitution applied (`1` elastic, `0` sticky).
    pub restitution: f64,
    /// Kinetic energy the collision took.
    pub energy_lost: f64,
    /// Contact point and normal, when the scene asked for geometry.
    pub geometry: Option<EventGeometry>,
}

impl EventRecord {
    fn new(time: f64, sphere: u32, other: Body, o: &Outcome, g: Option<(DVec3, DVec3)>) -> Self {
        Self {
            time,
            sphere,
            other,
            approach: o.approach,
            restitution: o.restitution,
            energy_lost: o.energy_lost,
            geometry: g.map(|(point, normal)| EventGeometry { point, normal }),
        }
    }
}

/// The part of the engine the public type sees, whatever the monomorphisation.
trait Run: Send {
    fn run_until(
        &mut self,
        t: f64,
        keep: &mut dyn FnMut(f64, &Stats) -> bool,
    ) -> Result<bool, SimError>;
    fn now(&self) -> f64;
    fn stats(&self) -> &Stats;
    fn motion(&self) -> &Motion;
    fn current(&self) -> Vec<response::Body>;
    fn take_log(&mut self) -> Vec<EventRecord>;
    fn clusters(&self) -> Vec<Vec<u32>>;
    fn name(&self) -> String;
    fn bytes(&self) -> usize;
    fn save(&self, e: &mut checkpoint::Encoder);
    fn load(
        &mut self,
        d: &mut checkpoint::Decoder,
        masses: &[f64],
        materials: &[u16],
    ) -> Result<(), SimError>;
    /// The grid (its geometry: the invariant check sorts positions by it), the shapes, and
    /// whether the box is periodic and the response only reports.
    fn layout(&self) -> (&Cells, &Statics<u16>, bool, bool);
    fn break_walls(&mut self);
    fn set_velocities(&mut self, v: &[DVec3]) -> Result<(), SimError>;
    /// Periodic image counts in public order (empty outside a periodic box).
    fn images(&self) -> Vec<[i64; 3]>;
    /// Test-only: check the prediction invariant after every event.
    #[cfg(test)]
    fn set_checking(&mut self);
}

/// Per-response hooks the public type needs.
trait Clusters {
    fn clusters(&self) -> Vec<Vec<u32>> {
        Vec::new()
    }
}
impl Clusters for ReportOnly {}
impl Clusters for Elastic {}
impl Clusters for Materials {
    fn clusters(&self) -> Vec<Vec<u32>> {
        Materials::clusters(self).map(<[u32]>::to_vec).collect()
    }
}

impl<R: Responder + Clusters, const P: bool, const W: bool, const G: bool> Run
    for Engine<R, P, W, G>
{
    fn run_until(
        &mut self,
        t: f64,
        keep: &mut dyn FnMut(f64, &Stats) -> bool,
    ) -> Result<bool, SimError> {
        Engine::run_until(self, t, keep)
    }
    fn now(&self) -> f64 {
        self.now
    }
    fn stats(&self) -> &Stats {
        &self.stats
    }
    fn motion(&self) -> &Motion {
        &self.m
    }
    fn current(&self) -> Vec<response::Body> {
        Engine::current(self)
    }
    fn take_log(&mut self) -> Vec<EventRecord> {
        self.log.as_mut().map(std::mem::take).unwrap_or_default()
    }
    fn clusters(&self) -> Vec<Vec<u32>> {
        let mut c = self.responder.clusters();
        for members in &mut c {
            for s in members.iter_mut() {
                *s = self.id_of[*s as usize];
            }
            members.sort_unstable();
        }
        c.sort_unstable();
        c
    }
    fn save(&self, e: &mut checkpoint::Encoder) {
        Engine::save(self, e)
    }
    fn load(
        &mut self,
        d: &mut checkpoint::Decoder,
        masses: &[f64],
        materials: &[u16],
    ) -> Result<(), SimError> {
        Engine::load(self, d, masses, materials)
    }
    fn layout(&self) -> (&Cells, &Statics<u16>, bool, bool) {
        (&self.cells, &self.walls, P, R::REPORT_ONLY)
    }
    fn break_walls(&mut self) {
        self.broken_walls = true;
    }
    fn set_velocities(&mut self, v: &[DVec3]) -> Result<(), SimError> {
        Engine::set_velocities(self, v)
    }
    fn images(&self) -> Vec<[i64; 3]> {
        let mut out = vec![[0; 3]; self.images.len()];
        for (k, &id) in self.id_of.iter().enumerate().take(self.images.len()) {
            out[id as usize] = self.images[k];
        }
        out
    }
    fn bytes(&self) -> usize {
        Engine::bytes(self)
            + self
                .log
                .as_ref()
                .map_or(0, |l| l.capacity() * std::mem::size_of::<EventRecord>())
    }
    #[cfg(test)]
    fn set_checking(&mut self) {
        self.checking = true;
        // Renumber often, so that the check covers it.
        self.reorder_every = 97;
    }
    fn name(&self) -> String {
        format!(
            "{}{}{}{}",
            R::NAME,
            if P { ", periodic" } else { ", open" },
            if W { ", static shapes" } else { "" },
            if G { ", contact geometry" } else { "" }
        )
    }
}

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
    /// Validates the world, checks that no two bodies overlap beyond [`OVERLAP_TOLERANCE`],
    /// and assembles the engine for exactly the effects the world uses.
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
    /// use spheresweep::sim::SimError;
    /// assert!(Simulation::new(world.clone()).is_ok());
    /// let overlapping = World { spheres: vec![ball(0.0, 0.0), ball(0.5, 0.0)], ..world };
    /// assert!(matches!(Simulation::new(overlapping), Err(SimError::Overlap { a: 0, b: 1, .. })));
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn new(world: World) -> Result<Self, SimError> {
        world.validate()?;
        let fingerprint = world_fingerprint(&world);
        let n = world.spheres.len();
        // Everything the engine will hold, asked of the allocator at once: a world too large
        // for the memory the process may use is an error here, never an abort later.
        let bytes = Self::estimated_bytes(n);
        let mut probe: Vec<u8> = Vec::new();
        probe
            .try_reserve_exact(bytes)
            .map_err(|_| SimError::Memory {
                what: format!("a simulation of {n} spheres"),
                bytes,
            })?;
        drop(probe);
        let max_d = world
            .spheres
            .iter()
            .map(|s| 2.0 * s.radius)
            .fold(0.0, f64::max);
        let min_width = if max_d > 0.0 {
            max_d * (1.0 + 1e-6)
        } else {
            1.0
        };
        let (cells, periodic) = match world.boundary {
            Boundary::Periodic { size } => {
                for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
                    if !(size[k].is_finite() && size[k] >= 3.0 * min_width) {
                        return Err(SimError::Box {
                            axis,
                            length: size[k],
                            needed: 3.0 * min_width,
                        });
                    }
                }
                // At most about four cells per sphere (and 27, three a side, at least): a
                // sparse box gets wider cells, not a huge grid.
                let cells = Cells::new(DVec3::ZERO, size, min_width, (4 * n).max(27), n);
                if cells.n.iter().any(|&k| k < 3) {
                    return Err(SimError::Box {
                        axis: "x, y or z",
                        length: size.min_element(),
                        needed: 3.0 * min_width,
                    });
                }
                (cells, true)
            }
            Boundary::OpenBox { lo, hi } => {
                (Cells::new(lo, hi - lo, min_width, 2 * n + 64, n), false)
            }
            Boundary::Open => {
                let (mut lo, mut hi) =
                    (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
                for s in &world.spheres {
                    lo = lo.min(s.centre - s.radius);
                    hi = hi.max(s.centre + s.radius);
                }
                for (k, r) in world.statics.iter().filter_map(|(_, s, _)| s.interior()) {
                    lo = lo.min(k - r);
                    hi = hi.max(k + r);
                }
                if n == 0 {
                    (lo, hi) = (DVec3::ZERO, DVec3::ONE);
                }
                let extent = (hi - lo).max(DVec3::splat(min_width));
                (Cells::new(lo, extent, min_width, 2 * n + 64, n), false)
            }
        };
        let mut m = Motion {
            bodies: Vec::with_capacity(n),
            mass: world.spheres.iter().map(|s| s.mass).collect(),
            material: world.spheres.iter().map(|s| s.material).collect(),
            counter: vec![0; n],
        };
        for s in &world.spheres {
            let mut r = s.centre;
            if periodic {
                r -= cells.len * (r / cells.len).floor();
                // `x − L·floor(x/L)` can round up to `L`.
                r = r.min(cells.len * (1.0 - f64::EPSILON));
            }
            m.bodies.push(response::Body {
                r,
                t: 0.0,
                v: s.velocity,
                radius: s.radius,
            });
        }
        let walls = world.statics.clone();
        check_start(&m, &cells, periodic, &walls)?;
        let sides = invariant::sides(&m.bodies, &walls);
        // Which response the spheres and shapes actually in the scene call for.
        let count = world.materials.len().max(1);
        let mut table = vec![world.effects.response; count * count];
        for p in &world.effects.pairs {
            let (a, b) = (usize::from(p.a), usize::from(p.b));
            table[a * count + b] = p.response;
            table[b * count + a] = p.response;
        }
        let mut used = vec![false; count];
        for &mat in m
            .material
            .iter()
            .chain(world.statics.iter().map(|(_, _, m)| m))
        {
            used[usize::from(mat)] = true;
        }
        let sphere_used: Vec<bool> = {
            let mut u = vec![false; count];
            for &mat in &m.material {
                u[usize::from(mat)] = true;
            }
            u
        };
        // A pair of materials matters if a sphere of one can meet a body of the other.
        let mut all_elastic = true;
        for a in 0..count {
            for b in 0..count {
                if sphere_used[a] && used[b] && table[a * count + b] != Response::Elastic {
                    all_elastic = false;
                }
            }
        }
        let report_only = world.effects.response == Response::None;
        let walls_present = !walls.is_empty();
        let log = world.effects.record_events;
        let geometry = world.effects.geometry && log;
        let materials = m.material.clone();
        let masses = m.mass.clone();
        macro_rules! build {
            ($r:expr) => {{
                let r = $r;
                match (periodic, walls_present, geometry) {
                    (false, false, false) => Box::new(Engine::<_, false, false, false>::new(
                        m, cells, walls, r, log,
                    )) as Box<dyn Run>,
                    (false, false, true) => Box::new(Engine::<_, false, false, true>::new(
                        m, cells, walls, r, log,
                    )),
                    (false, true, false) => Box::new(Engine::<_, false, true, false>::new(
                        m, cells, walls, r, log,
                    )),
                    (false, true, true) => {
                        Box::new(Engine::<_, false, true, true>::new(m, cells, walls, r, log))
                    }
                    (true, false, false) => Box::new(Engine::<_, true, false, false>::new(
                        m, cells, walls, r, log,
                    )),
                    (true, false, true) => {
                        Box::new(Engine::<_, true, false, true>::new(m, cells, walls, r, log))
                    }
                    (true, true, false) => {
                        Box::new(Engine::<_, true, true, false>::new(m, cells, walls, r, log))
                    }
                    (true, true, true) => {
                        Box::new(Engine::<_, true, true, true>::new(m, cells, walls, r, log))
                    }
                }
            }};
        }
        let engine: Box<dyn Run> = if report_only {
            build!(ReportOnly {
                partner: vec![cells::NONE; n]
            })
        } else if all_elastic {
            build!(Elastic)
        } else {
            build!(Materials::new(
                table,
                count,
                world.effects.tc,
                &masses.clone()
            ))
        };
        Ok(Self {
            engine,
            materials,
            masses,
            fingerprint,
            sides,
            boundary: world.boundary,
        })
    }

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
    /// the upper face, `−1` through the lower), in sphere order: its unwrapped centre is
    /// `centre + images · size` (for a mean-squared displacement). All zero in open space.
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
    /// a value that is not finite; nothing is changed then.
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
    /// [`SimError::Breach`] naming the sphere, the other body, the depth and the time: the
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
        match invariant::check(&bodies, cells, periodic, walls, sides) {
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
    /// the per-sphere mass and material it reports back), for sizing runs.
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
        self.engine.bytes() + self.masses.capacity() * 8 + self.materials.capacity() * 2
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

    /// The whole dynamic state as bytes: restored with [`restore`](Self::restore) into the same
    /// world, the run continues bit for bit as this one would. Take it between
    /// [`advance_with`](Self::advance_with) calls (or when one stops early); unread event
    /// records are not part of it.
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
    /// let mut sim = Simulation::new(world.clone())?;
    /// sim.advance_to(0.5)?;
    /// let saved = sim.checkpoint();
    /// let mut again = Simulation::restore(world, &saved)?;
    /// assert_eq!(again.time(), 0.5);
    /// again.advance_to(2.0)?;
    /// sim.advance_to(2.0)?;
    /// assert_eq!(again.spheres(), sim.spheres()); // bit for bit
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn checkpoint(&self) -> Vec<u8> {
        let mut e = checkpoint::Encoder::default();
        e.0.extend_from_slice(checkpoint::MAGIC);
        e.u32(checkpoint::VERSION);
        e.u64(self.fingerprint);
        self.engine.save(&mut e);
        let sum = checkpoint::checksum(&e.0);
        e.u64(sum);
        e.0
    }

    /// The simulation of `world` at the state a [`checkpoint`](Self::checkpoint) holds.
    ///
    /// # Errors
    /// [`SimError::Checkpoint`] if the bytes are not a checkpoint of this format, belong to
    /// another world, or are damaged (every index is checked; nothing panics).
    ///
    /// ```
    /// use spheresweep::sim::{Simulation, World, generate};
    /// let mut world = World::default();
    /// generate::periodic_gas(&mut world, 256, 0.3, 0.5, 1.0, 3)?;
    /// let mut a = Simulation::new(world.clone())?;
    /// a.advance_to(1.0)?;
    /// let saved = a.checkpoint();
    /// a.advance_to(2.0)?;
    /// let mut b = Simulation::restore(world, &saved)?;
    /// b.advance_to(2.0)?;
    /// assert_eq!(a.spheres(), b.spheres());
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn restore(world: World, bytes: &[u8]) -> Result<Self, SimError> {
        let mut sim = Simulation::new(world)?;
        let Some((body, sum)) = bytes.split_last_chunk::<8>() else {
            return Err(SimError::Checkpoint(format!(
                "truncated: {} bytes",
                bytes.len()
            )));
        };
        let mut d = checkpoint::Decoder::new(body);
        let magic = [d.u8()?, d.u8()?, d.u8()?, d.u8()?];
        if &magic != checkpoint::MAGIC {
            return Err(SimError::Checkpoint("not a spheresweep checkpoint".into()));
        }
        if checkpoint::checksum(body) != u64::from_le_bytes(*sum) {
            return Err(SimError::Checkpoint(
                "damaged: the checksum does not match".into(),
            ));
        }
        let version = d.u32()?;
        if version != checkpoint::VERSION {
            return Err(SimError::Checkpoint(format!(
                "format version {version}; this build reads version {}",
                checkpoint::VERSION
            )));
        }
        if d.u64()? != sim.fingerprint {
            return Err(SimError::Checkpoint(
                "written for another world (shapes, boundary, effects, masses or materials differ)"
                    .into(),
            ));
        }
        let (masses, materials) = (sim.masses.clone(), sim.materials.clone());
        sim.engine.load(&mut d, &masses, &materials)?;
        d.finish()?;
        Ok(sim)
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
        let m = self.engine.motion();
        m.bodies
            .iter()
            .zip(&m.mass)
            .map(|(b, &mass)| 0.5 * mass * b.v.length_squared())
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
        let m = self.engine.motion();
        m.bodies
            .iter()
            .zip(&m.mass)
            .map(|(b, &mass)| b.v * mass)
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

/// What a checkpoint must match: everything in the world but the spheres' positions and
/// velocities (which the checkpoint carries) and what is recorded (`record_events`, `geometry`:
/// they change what is written, not the dynamics).
fn world_fingerprint(w: &World) -> u64 {
    let per_sphere: Vec<(u64, u64, u16)> = w
        .spheres
        .iter()
        .map(|s| (s.radius.to_bits(), s.mass.to_bits(), s.material))
        .collect();
    checkpoint::fingerprint(&format!(
        "{:?}{:?}{:?}{:?}{:?}",
        per_sphere,
        w.statics,
        w.boundary,
        w.materials,
        Effects {
            record_events: false,
            geometry: false,
            ..w.effects.clone()
        }
    ))
}

/// No two spheres overlap, and no sphere is through a shape, beyond the tolerance (the
/// invariant's check at the start, where each sphere's side of a plane is the one it is on).
fn check_start(
    m: &Motion,
    cells: &Cells,
    periodic: bool,
    walls: &Statics<u16>,
) -> Result<(), SimError> {
    match invariant::check(&m.bodies, cells, periodic, walls, &[]) {
        Ok(_) => Ok(()),
        Err(b) if b.other.kind == crate::ShapeKind::Sphere => Err(SimError::Overlap {
            a: b.sphere,
            b: b.other.index as usize,
            depth: b.depth,
            tolerance: OVERLAP_TOLERANCE,
        }),
        Err(b) => Err(SimError::Penetrates {
            sphere: b.sphere,
            shape: b.other.kind,
            index: b.other.index as usize,
            depth: b.depth,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` spheres placed at random in a container of radius 4, every third of material 1,
    /// which sticks to its own kind; every other collision is inelastic with restitution `e`
    /// and the TC model.
    fn sticky_mix(n: usize, e: f64) -> World {
        let inside = |p: DVec3| p.length() < 3.4;
        let mut spheres = generate::random_spheres(
            DVec3::splat(-3.5),
            DVec3::splat(3.5),
            &inside,
            n,
            0.4,
            1.0,
            0,
            3,
        )
        .unwrap();
        for s in spheres.iter_mut().step_by(3) {
            s.material = 1;
        }
        World {
            spheres,
            statics: Statics::new().with(crate::Container::new([0.0; 3], 4.0).unwrap(), 0),
            materials: vec!["a".into(), "b".into()],
            effects: Effects {
                response: Response::Inelastic { restitution: e },
                pairs: vec![MaterialPair {
                    a: 1,
                    b: 1,
                    response: Response::Sticky,
                }],
                tc: 1e-3,
                ..Effects::default()
            },
            ..World::default()
        }
    }

    /// The up-front estimate is an upper bound on what a fresh simulation holds, and not
    /// more than twice it: for periodic gases (four cells per sphere at most), an open scene
    /// in a container (`2n + 64` cells at most), one sphere and none. Tiny worlds may also
    /// get the fixed part of the largest grid (`2n + 64` cells of 36 B and two buckets of
    /// 88 B: under 4 KiB for `n ≤ 1`).
    #[test]
    fn the_memory_estimate_bounds_a_fresh_simulation_within_a_factor_of_two() {
        let mut worlds = Vec::new();
        for (n, phi) in [(500, 0.3), (4000, 0.25), (20_000, 0.05)] {
            let mut w = World::default();
            generate::periodic_gas(&mut w, n, phi, 0.5, 1.0, 1).unwrap();
            worlds.push(w);
        }
        worlds.push(sticky_mix(200, 0.5));
        let mut one = World::default();
        one.spheres.push(SphereState {
            centre: DVec3::ZERO,
            velocity: DVec3::X,
            radius: 1.0,
            mass: 1.0,
            material: 0,
        });
        worlds.push(one);
        worlds.push(World::default());
        for w in worlds {
            let n = w.spheres.len();
            let sim = Simulation::new(w).unwrap();
            let (actual, estimate) = (sim.memory_bytes(), Simulation::estimated_bytes(n));
            assert!(
                actual <= estimate && estimate <= 2 * actual + if n <= 1 { 4096 } else { 0 },
                "{n} spheres: estimate {estimate} B, a fresh simulation holds {actual} B"
            );
        }
    }

    /// A run restored from a checkpoint ends bit for bit where the uninterrupted run ends: the
    /// gas, a sticky and inelastic mix with clusters in a container (renumbering in between),
    /// and report-only; a damaged checkpoint or another world is refused, never a panic.
    #[test]
    fn checkpoints_resume_bit_for_bit() {
        let mut worlds = Vec::new();
        let mut gas = World::default();
        generate::periodic_gas(&mut gas, 500, 0.35, 0.5, 1.0, 4).unwrap();
        worlds.push((gas.clone(), 3.0));
        let mix = sticky_mix(80, 0.8);
        worlds.push((mix.clone(), 20.0));
        worlds.push((
            World {
                spheres: mix.spheres,
                materials: vec!["a".into(), "b".into()],
                effects: Effects {
                    response: Response::None,
                    ..Effects::default()
                },
                ..World::default()
            },
            3.0,
        ));
        for (world, t) in worlds {
            let mut a = Simulation::new(world.clone()).unwrap();
            a.advance_to(t / 3.0).unwrap();
            let saved = a.checkpoint();
            a.advance_to(t).unwrap();
            let mut b = Simulation::restore(world.clone(), &saved).unwrap();
            b.advance_to(t).unwrap();
            assert!(
                a.stats().pair_collisions > 50,
                "{}: {:?}",
                a.engine_name(),
                a.stats()
            );
            assert_eq!(a.spheres(), b.spheres(), "{}", a.engine_name());
            assert_eq!(a.stats(), b.stats());
            assert_eq!(a.clusters(), b.clusters());
            // Damage: every truncation and a flipped byte in the header are refused.
            for cut in [0, 3, 8, 20, saved.len() / 2, saved.len() - 1] {
                assert!(Simulation::restore(world.clone(), &saved[..cut]).is_err());
            }
            let mut flipped = saved.clone();
            flipped[9] ^= 1;
            assert!(
                Simulation::restore(world.clone(), &flipped)
                    .unwrap_err()
                    .to_string()
                    .contains("damaged")
            );
        }
        // What is recorded is not the world: a checkpoint restores with events on or off.
        let mut a = Simulation::new(gas.clone()).unwrap();
        a.advance_to(0.2).unwrap();
        let recording = World {
            effects: Effects {
                record_events: true,
                geometry: true,
                ..gas.effects.clone()
            },
            ..gas.clone()
        };
        let mut b = Simulation::restore(recording, &a.checkpoint()).unwrap();
        a.advance_to(1.0).unwrap();
        b.advance_to(1.0).unwrap();
        assert_eq!(a.spheres(), b.spheres());
        assert!(!b.take_events().is_empty());
        // Another world (one radius differs) is refused by its fingerprint.
        let mut other = gas.clone();
        other.spheres[7].radius *= 0.999;
        let mut a = Simulation::new(gas.clone()).unwrap();
        a.advance_to(0.2).unwrap();
        assert!(
            Simulation::restore(other, &a.checkpoint())
                .unwrap_err()
                .to_string()
                .contains("another world")
        );
        // Random damage anywhere is refused, never a panic.
        let mut rng = crate::rng::Rng::new(1);
        let mut a = Simulation::new(gas.clone()).unwrap();
        a.advance_to(0.5).unwrap();
        let saved = a.checkpoint();
        for _ in 0..200 {
            let mut bytes = saved.clone();
            let k = 16 + (rng.unit() * (bytes.len() - 16) as f64) as usize;
            bytes[k] ^= 1 << (rng.unit() * 8.0) as u32;
            assert!(Simulation::restore(gas.clone(), &bytes).is_err());
        }
    }

    /// The scene that left its vessel: one sphere in a container, restitution 0.3
    /// (docs/derivations/simulation.md, "Concave walls").
    fn one_in_a_vessel(e: f64, tc: f64) -> World {
        World {
            spheres: vec![SphereState {
                centre: DVec3::new(3.0, 0.0, 0.0),
                velocity: DVec3::new(0.3, 1.0, 0.2),
                radius: 0.5,
                mass: 1.0,
                material: 0,
            }],
            statics: Statics::new().with(crate::Container::new([0.0; 3], 6.0).unwrap(), 0),
            effects: Effects {
                response: Response::Inelastic { restitution: e },
                tc,
                ..Effects::default()
            },
            ..World::default()
        }
    }

    /// Concave walls, brute force after every event (the check of
    /// `no_collision_is_ever_missed`, walls included): one sphere whose bounces collapse onto
    /// the wall and slide, and forty strongly inelastic spheres without the TC model.
    #[test]
    fn no_collision_with_a_concave_wall_is_ever_missed() {
        let mut sim = Simulation::new(one_in_a_vessel(0.3, 0.0)).unwrap();
        sim.engine.set_checking();
        sim.advance_to(100.0).unwrap();
        let stats = *sim.stats();
        assert!(
            stats.wall_collisions > 10_000 && stats.slid > 10_000,
            "{stats:?}"
        );
        let inside = |p: DVec3| p.length() < 5.0;
        let spheres = generate::random_spheres(
            DVec3::splat(-5.0),
            DVec3::splat(5.0),
            &inside,
            40,
            0.5,
            1.0,
            0,
            6,
        )
        .unwrap();
        let w = World {
            spheres,
            ..one_in_a_vessel(0.1, 0.0)
        };
        let mut sim = Simulation::new(w).unwrap();
        sim.engine.set_checking();
        match sim.advance_to(60.0) {
            Ok(()) => {}
            // A collapse of pairs is caught by the watchdog; the check held up to it.
            Err(SimError::Stalled { .. }) => {}
            Err(e) => panic!("{e}"),
        }
        assert!(sim.stats().wall_collisions > 2000, "{:?}", sim.stats());
    }

    /// The invariant check fires on a real engine fault: with the concave-wall rules of before
    /// 2026-12-01 the sphere leaves its vessel (the user's report: at t ≈ 15.5), and the check
    /// names it; with today's rules it stays inside.
    #[test]
    fn a_broken_wall_rule_is_caught() {
        let mut sim = Simulation::new(one_in_a_vessel(0.3, 0.0)).unwrap();
        sim.break_walls_for_testing();
        sim.advance_to(200.0).unwrap();
        match sim.check_invariant() {
            Err(SimError::Breach {
                sphere: 0,
                other,
                depth,
                ..
            }) => {
                assert_eq!(other, Body::new(crate::ShapeKind::Container, 0));
                assert!(depth > 10.0, "{depth}");
            }
            r => panic!("the escape went unseen: {r:?}"),
        }
        let mut sim = Simulation::new(one_in_a_vessel(0.3, 0.0)).unwrap();
        sim.advance_to(200.0).unwrap();
        assert!(sim.check_invariant().unwrap().walls < 1e-6);
    }

    /// After every event, no pair meets before both of its spheres' next events (brute force
    /// over all pairs and images): the engine's prediction rules (stale partners, the two kept
    /// candidates, the merge at a crossing) never let a collision through. Small periodic boxes
    /// (three to five cells a side) make wrap-around and several images common.
    #[test]
    fn no_collision_is_ever_missed() {
        for (n, phi, seed, t) in [
            (108, 0.3, 11, 4.0),
            (32, 0.35, 2, 10.0),
            (256, 0.45, 5, 0.7),
        ] {
            let mut w = World::default();
            generate::periodic_gas(&mut w, n, phi, 0.5, 1.0, seed).unwrap();
            let mut sim = Simulation::new(w).unwrap();
            sim.engine.set_checking();
            sim.advance_to(t).unwrap();
            assert!(sim.stats().pair_collisions > 1000, "{n}: {:?}", sim.stats());
        }
        // Walls and clusters: a sticky and inelastic mix in a container, then clusters stuck to
        // a floor (infinite mass) hit by free spheres.
        let floor = crate::Plane::new([0.0, 0.0, -2.0], [0.0, 0.0, 1.0]).unwrap();
        let inside = |p: DVec3| p.length() < 3.4 && p.z > -1.5;
        let mut spheres = generate::random_spheres(
            DVec3::splat(-3.5),
            DVec3::splat(3.5),
            &inside,
            70,
            0.4,
            1.0,
            0,
            8,
        )
        .unwrap();
        for s in spheres.iter_mut().step_by(2) {
            s.material = 1;
        }
        let w = World {
            spheres,
            statics: Statics::new()
                .with(floor, 1)
                .with(crate::Container::new([0.0; 3], 4.0).unwrap(), 0),
            materials: vec!["glass".into(), "glue".into()],
            effects: Effects {
                pairs: vec![MaterialPair {
                    a: 1,
                    b: 1,
                    response: Response::Sticky,
                }],
                ..Effects::default()
            },
            ..World::default()
        };
        let mut sim = Simulation::new(w).unwrap();
        sim.engine.set_checking();
        sim.advance_to(40.0).unwrap();
        assert!(
            sim.stats().joins > 10 && sim.stats().pair_collisions > 500,
            "{:?}",
            sim.stats()
        );
        // Walls and clusters: a sticky and inelastic mix in a container.
        let w = sticky_mix(60, 0.9);
        let mut sim = Simulation::new(w).unwrap();
        sim.engine.set_checking();
        sim.advance_to(20.0).unwrap();
        assert!(
            sim.stats().wall_collisions > 100 && sim.stats().joins > 0,
            "{:?}",
            sim.stats()
        );
    }
}
