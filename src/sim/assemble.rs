//! Assembly: `Simulation::new` validates the world, builds the grid, the bodies and the
//! shapes, and picks the engine for exactly the effects the world uses.

use glam::DVec3;

use super::cells::{self, Cells};
use super::checkpoint::world_fingerprint;
use super::engine::Engine;
use super::invariant;
use super::response::{self, Elastic, Materials, Motion, ReportOnly};
use super::run::Run;
use super::{Boundary, OVERLAP_TOLERANCE, Response, SimError, Simulation, World};
use crate::statics::Statics;

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
            m.bodies.push(response::Trajectory {
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
        let report_only = world.effects.response == Response::ReportOnly;
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
