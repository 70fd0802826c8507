//! Assembly: `Simulation::new` validates the world, builds the grid, the bodies and the
//! shapes, and picks the engine for exactly the effects the world uses.

use glam::DVec3;

use super::cells::Cells;
use super::checkpoint::world_fingerprint;
use super::engine::{self, Engine};
use super::invariant;
use super::response::{self, Elastic, Materials, Motion, ReportOnly, Responder};
use super::run::{Clusters, Run};
use super::{Boundary, OVERLAP_TOLERANCE, Response, SimError, Simulation, World};
use crate::statics::Statics;

impl Simulation {
    /// Validates the world, checks that no two bodies overlap beyond [`OVERLAP_TOLERANCE`],
    /// and assembles the engine for exactly the effects the world uses. A world placed so far
    /// from the origin that its coordinates round coarser than its contacts' tolerance is
    /// taken (units are the caller's); [`World::coarse_sphere`] names such a sphere, and
    /// [`Simulation::coarse_sphere`] one that has flown there since.
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
        reserve_memory(n)?;
        let (cells, periodic, delta) = grid(&world)?;
        let m = motion(&world, &cells, periodic);
        let start_images = start_images(&world, &cells, periodic);
        let walls = world.statics.clone();
        // Spheres that only report their contacts pass through each other and the shapes:
        // they may start overlapping or through one.
        if world.effects.response != Response::ReportOnly {
            check_start(&m, &cells, periodic, &walls)?;
        }
        let filling = filling(&world);
        let falls = world.effects.gravity != DVec3::ZERO;
        if let Some(e) = moving_without_room(&filling, |i| world.spheres[i].velocity, falls) {
            return Err(e);
        }
        let sides = invariant::sides(&m.bodies, &walls);
        let response = ResponseChoice::of(&world, &m.material);
        let materials = m.material.clone();
        let masses = m.mass.clone();
        let switches = Switches {
            periodic,
            walls: !walls.is_empty(),
            geometry: world.effects.geometry && world.effects.record_events,
            gravity: world.effects.gravity != DVec3::ZERO,
        };
        let parts = Parts {
            m,
            cells,
            delta,
            walls,
            log: world.effects.record_events,
        };
        let engine = match response {
            ResponseChoice::ReportOnly => pick_motion(ReportOnly::new(n), switches, parts),
            ResponseChoice::Elastic => pick_motion(Elastic, switches, parts),
            ResponseChoice::Materials { table, count } => pick_motion(
                Materials::new(table, count, world.effects.tc, &masses.clone()),
                switches,
                parts,
            ),
        };
        Ok(Self {
            engine,
            materials,
            masses,
            fingerprint,
            sides,
            boundary: world.boundary,
            start_images,
            filling,
        })
    }
}

/// Everything the engine will hold, asked of the allocator at once: a world too large for the
/// memory the process may use is an error here, never an abort later.
fn reserve_memory(n: usize) -> Result<(), SimError> {
    let bytes = Simulation::estimated_bytes(n);
    let mut probe: Vec<u8> = Vec::new();
    probe
        .try_reserve_exact(bytes)
        .map_err(|_| SimError::Memory {
            what: format!("a simulation of {n} spheres"),
            bytes,
        })?;
    drop(probe);
    Ok(())
}

/// The neighbour lists' shell, in largest diameters, for spheres filling a fraction `phi`
/// of the grid's volume: a sphere's list reaches that far beyond contact, and it is rebuilt
/// when the sphere has moved half of it. Half a diameter and the mean free path
/// (`1 / (6√2 φ g)`, `g` Carnahan–Starling's contact value), at most `cap`: a dense fluid
/// rebuilds rarely with short lists, a dilute gas would rebuild every few collisions with a
/// short shell. Chosen by measurement across φ = 0.02–0.5 (docs/benchmarks.md, "Neighbour
/// lists", and "A cheaper calendar key and a wider shell" for the caps).
pub(crate) fn shell(phi: f64, cap: f64) -> f64 {
    let g = (1.0 - phi / 2.0) / (1.0 - phi).powi(3);
    let free_path = 1.0 / (6.0 * std::f64::consts::SQRT_2 * phi * g);
    (0.5 + free_path).min(cap)
}

/// The largest shell in a periodic box, in largest diameters: there the spheres fill the box,
/// so its φ gives their mean free path. Below two, so that a list (the contact distance and
/// the reach, `D (1 + cap)` and its margins) stays shorter than the smallest box allowed,
/// three diameters: no sphere lists its own image. (At φ = 0.05, 1.9 takes 2.8 % fewer
/// instructions a collision than 1.5 and 9 % fewer than 3; at φ = 0.02, 3 takes 6 % fewer:
/// docs/benchmarks.md.)
const PERIODIC_SHELL_CAP: f64 = 1.9;

/// The largest shell elsewhere: φ is then taken over the bounding box or the box given, and
/// spheres may pile up in it far denser than that (a vessel's floor), where a wide shell
/// makes long lists.
const OPEN_SHELL_CAP: f64 = 1.0;

/// Refuses a static shape whose periodic images spheres could meet: the engine keeps none
/// (docs/derivations/simulation.md, "Shapes in a periodic box"). `margin`, two largest
/// diameters, is more than a sphere's radius and how far its centre goes past a face before
/// its shell event wraps it (the shell's half-width, at most 0.95 diameters).
fn shapes_fit_periodic_box<P>(
    statics: &Statics<P>,
    size: DVec3,
    margin: f64,
) -> Result<(), SimError> {
    struct Fits(DVec3, f64);
    impl crate::statics::ShapeFn for Fits {
        type Output = bool;
        fn call<K: crate::StaticShape>(self, shape: &K) -> bool {
            shape.fits_periodic_box(self.0, self.1)
        }
    }
    match statics
        .iter()
        .find(|(_, shape, _)| !shape.apply(Fits(size, margin)))
    {
        Some((body, _, _)) => Err(SimError::PeriodicShape {
            shape: body.kind,
            index: body.index as usize,
            margin,
        }),
        None => Ok(()),
    }
}

/// The cell grid over the boundary (cells at least one largest diameter and the shell wide),
/// whether it wraps (a periodic box at least three largest diameters a side, an open box as
/// given, or open space around the spheres and containers), and the shells' half-width.
fn grid(world: &World) -> Result<(Cells, bool, f64), SimError> {
    let n = world.spheres.len();
    if n > engine::MAX_SPHERES {
        return Err(SimError::State(format!(
            "{n} spheres: the engine holds at most {}",
            engine::MAX_SPHERES
        )));
    }
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
    let shells = |extent: DVec3, cap: f64| {
        let volume: f64 = world.spheres.iter().map(|s| s.radius.powi(3)).sum::<f64>()
            * (4.0 / 3.0 * std::f64::consts::PI);
        let phi = (volume / extent.x / extent.y / extent.z).clamp(0.0, 0.74);
        let delta = shell(phi, cap) * min_width / 2.0;
        (delta, min_width + 2.0 * delta * (1.0 + 1e-6))
    };
    Ok(match world.boundary {
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
            shapes_fit_periodic_box(&world.statics, size, 2.0 * min_width)?;
            // At most about four cells per sphere: a sparse box gets wider cells, not a huge
            // grid. A small box may have fewer than three a side: the lists then hold each
            // periodic image apart.
            let (delta, width) = shells(size, PERIODIC_SHELL_CAP);
            let cells = Cells::new(DVec3::ZERO, size, width, (4 * n).max(27));
            (cells, true, delta)
        }
        Boundary::OpenBox { lo, hi } => {
            let (delta, width) = shells(hi - lo, OPEN_SHELL_CAP);
            (Cells::new(lo, hi - lo, width, 2 * n + 64), false, delta)
        }
        Boundary::Open => {
            let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
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
            let (delta, width) = shells(extent, OPEN_SHELL_CAP);
            let extent = extent.max(DVec3::splat(width));
            (Cells::new(lo, extent, width, 2 * n + 64), false, delta)
        }
    })
}

/// How many box lengths each periodic sphere's centre as given lies from the box, per axis
/// (what `motion` wraps away), so that `images()` and unwrapped centres count from the centre
/// given; empty in open space or if every centre is given in the box.
fn start_images(world: &World, cells: &Cells, periodic: bool) -> Vec<[i64; 3]> {
    if !periodic {
        return Vec::new();
    }
    let images: Vec<[i64; 3]> = world
        .spheres
        .iter()
        .map(|s| cells.image(s.centre).to_array().map(|k| k as i64))
        .collect();
    if images.iter().all(|k| *k == [0; 3]) {
        Vec::new()
    } else {
        images
    }
}

/// The spheres as the engine moves them, at time 0 (periodic centres wrapped into the box).
fn motion(world: &World, cells: &Cells, periodic: bool) -> Motion {
    let n = world.spheres.len();
    let mut m = Motion {
        bodies: Vec::with_capacity(n),
        mass: world.spheres.iter().map(|s| s.mass).collect(),
        material: world.spheres.iter().map(|s| s.material).collect(),
        counter: super::pages::filled(0, n),
        g: world.effects.gravity,
    };
    for s in &world.spheres {
        let mut r = s.centre;
        if periodic {
            r = cells.wrap(r);
            // `x − L·floor(x/L)` can round up to `L`.
            r = r.min(cells.len * (1.0 - f64::EPSILON));
        }
        m.bodies.push(response::Trajectory {
            r,
            t: 0.0,
            v: s.velocity,
            radius: s.radius,
        });
    }
    super::pages::settle(&m.bodies);
    m
}

/// Which responder the spheres and shapes actually in the scene call for.
enum ResponseChoice {
    /// The world only reports contacts.
    ReportOnly,
    /// Every pair of materials that can meet is elastic.
    Elastic,
    /// The response of each pair of materials (`count × count`, row-major).
    Materials { table: Vec<Response>, count: usize },
}

impl ResponseChoice {
    /// From the world's effects and the spheres' materials: a pair of materials matters if
    /// a sphere of one can meet a body of the other.
    fn of(world: &World, sphere_materials: &[u16]) -> Self {
        if world.effects.response == Response::ReportOnly {
            return Self::ReportOnly;
        }
        let count = world.materials.len().max(1);
        let mut table = vec![world.effects.response; count * count];
        for p in &world.effects.pairs {
            let (a, b) = (usize::from(p.a), usize::from(p.b));
            table[a * count + b] = p.response;
            table[b * count + a] = p.response;
        }
        let mut used = vec![false; count];
        for &mat in sphere_materials
            .iter()
            .chain(world.statics.iter().map(|(_, _, m)| m))
        {
            used[usize::from(mat)] = true;
        }
        let mut sphere_used = vec![false; count];
        for &mat in sphere_materials {
            sphere_used[usize::from(mat)] = true;
        }
        let all_elastic = (0..count).all(|a| {
            (0..count)
                .all(|b| !(sphere_used[a] && used[b]) || table[a * count + b] == Response::Elastic)
        });
        if all_elastic {
            Self::Elastic
        } else {
            Self::Materials { table, count }
        }
    }
}

/// The three compile-time switches of `Engine`, as the world sets them.
#[derive(Debug, Clone, Copy)]
struct Switches {
    /// The box wraps.
    periodic: bool,
    /// Any static shape at all.
    walls: bool,
    /// Contact point and normal in the event log.
    geometry: bool,
    /// A uniform acceleration (never with `periodic`).
    gravity: bool,
}

/// What every engine is built from, whatever its type.
struct Parts {
    m: Motion,
    cells: Cells,
    /// The shells' half-width.
    delta: f64,
    walls: Statics<u16>,
    log: bool,
}

// The choice of engine, one switch at a time: `pick_motion` fixes `PERIODIC` and `GRAVITY`
// (gravity is refused in a periodic box), `pick_walls` `WALLS`, `pick_geometry` `GEOMETRY`;
// each responder therefore has the twelve engines of its switches, and nothing else is
// monomorphised.

fn pick_motion<R: Responder + Clusters + 'static>(r: R, s: Switches, parts: Parts) -> Box<dyn Run> {
    match (s.periodic, s.gravity) {
        (true, _) => pick_walls::<R, true, false>(r, s, parts),
        (false, true) => pick_walls::<R, false, true>(r, s, parts),
        (false, false) => pick_walls::<R, false, false>(r, s, parts),
    }
}

fn pick_walls<R: Responder + Clusters + 'static, const P: bool, const F: bool>(
    r: R,
    s: Switches,
    parts: Parts,
) -> Box<dyn Run> {
    if s.walls {
        pick_geometry::<R, P, true, F>(r, s, parts)
    } else {
        pick_geometry::<R, P, false, F>(r, s, parts)
    }
}

fn pick_geometry<R: Responder + Clusters + 'static, const P: bool, const W: bool, const F: bool>(
    r: R,
    s: Switches,
    parts: Parts,
) -> Box<dyn Run> {
    let Parts {
        m,
        cells,
        delta,
        walls,
        log,
    } = parts;
    if s.geometry {
        Box::new(Engine::<R, P, W, true, F>::new(
            m, cells, delta, walls, r, log,
        ))
    } else {
        Box::new(Engine::<R, P, W, false, F>::new(
            m, cells, delta, walls, r, log,
        ))
    }
}

/// The spheres that fill a container (every sphere starts inside each; a radius at least the
/// container's), each as the error that refuses it moving: touching the wall all round, it has
/// no room, and moving or falling it would meet the wall again at the same time without end (a
/// stall). At rest without gravity it stays, touching.
fn filling(world: &World) -> Vec<SimError> {
    let mut out = Vec::new();
    for (body, shape, _) in world.statics.iter() {
        let Some((_, container_radius)) = shape.interior() else {
            continue;
        };
        let fills = world.spheres.iter().enumerate();
        for (sphere, s) in fills.filter(|(_, s)| s.radius >= container_radius) {
            out.push(SimError::NoRoom {
                sphere,
                container: body.index as usize,
                radius: s.radius,
                container_radius,
            });
        }
    }
    out
}

/// The first of `filling` (see [`filling`]) whose sphere would move: given a velocity (sphere
/// `i`'s is `velocity(i)`), or under gravity.
pub(super) fn moving_without_room(
    filling: &[SimError],
    velocity: impl Fn(usize) -> DVec3,
    falls: bool,
) -> Option<SimError> {
    let moves = |e: &&SimError| matches!(e, SimError::NoRoom { sphere, .. } if falls || velocity(*sphere) != DVec3::ZERO);
    filling.iter().find(moves).cloned()
}

/// No two spheres overlap, and no sphere is through a shape, beyond the tolerance (the
/// invariant's check at the start, where each sphere's side of a plane is the one it is on).
fn check_start(
    m: &Motion,
    cells: &Cells,
    periodic: bool,
    walls: &Statics<u16>,
) -> Result<(), SimError> {
    match invariant::check(&m.bodies, cells, periodic, walls, &[], &[]) {
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
