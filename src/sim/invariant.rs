//! The state every run keeps, checked from the spheres' positions alone — not from the
//! engine's predictions, calendar or cell lists, so that a broken prediction cannot hide
//! itself: no two spheres overlap by more than [`OVERLAP_TOLERANCE`] of their contact distance;
//! no sphere is through a static shape, outside a container or on the other side of a plane
//! than it started, by more than [`OVERLAP_TOLERANCE`] of its radius (docs/derivations/
//! simulation.md derives why the engine stays far inside both).
//!
//! The neighbour search sorts the spheres by the cell of the engine's grid their position
//! falls in (its geometry only: which cell the engine files a sphere under is not read), then
//! compares each sphere with the spheres of the 27 cells around it.

use super::OVERLAP_TOLERANCE;
use super::cells::Cells;
use super::response::Trajectory;
use crate::ShapeKind;
use crate::contact::Body;
use crate::statics::Statics;

/// The largest overlaps a check found, each relative to its tolerance (`1` is the limit).
///
/// ```
/// use spheresweep::sim::{Simulation, World, generate};
/// let mut world = World::default();
/// generate::periodic_gas(&mut world, 256, 0.3, 0.5, 1.0, 3)?;
/// let mut sim = Simulation::new(world)?;
/// sim.advance_to(2.0)?;
/// let report = sim.check_invariant()?;
/// assert!(report.pairs < 1.0 && report.walls <= 0.0); // no shapes: nothing through one
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InvariantReport {
    /// The time checked.
    pub time: f64,
    /// Deepest overlap of two spheres over its tolerance ([`OVERLAP_TOLERANCE`] of their
    /// contact distance); `≤ 0` when no two spheres overlap.
    pub pairs: f64,
    /// Deepest penetration of a sphere through a static shape (or past a container's wall, or
    /// across a plane) over its tolerance ([`OVERLAP_TOLERANCE`] of the sphere's radius);
    /// `≤ 0` when none is through (`-∞` without shapes).
    pub walls: f64,
}

/// A breach of the invariant, in the engine's internal numbering.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Breach {
    pub sphere: usize,
    pub other: Body,
    /// How far through (a length).
    pub depth: f64,
    /// The tolerance it exceeds (a length).
    pub tolerance: f64,
}

/// Which side of each static shape each sphere is on ([`crate::Static::side`]: for a plane,
/// `true` on the side the normal points to), `walls.len()` entries per sphere.
pub(crate) fn sides(bodies: &[Trajectory], walls: &Statics<u16>) -> Vec<bool> {
    let mut sides = Vec::with_capacity(bodies.len() * walls.len());
    for b in bodies {
        sides.extend(walls.iter().map(|(_, shape, _)| shape.side(b.r)));
    }
    sides
}

/// Checks `bodies` (centres at one common time) against the invariant: the deepest overlaps
/// found, relative to their tolerances, or the first breach. `sides` holds each sphere's side
/// of each shape at the start ([`sides`]), in the same order as `bodies`; empty to take the
/// side each sphere is on now.
pub(crate) fn check(
    bodies: &[Trajectory],
    cells: &Cells,
    periodic: bool,
    walls: &Statics<u16>,
    sides: &[bool],
    images: &[[i64; 3]],
) -> Result<(f64, f64), Breach> {
    let pairs = check_pairs(bodies, cells, periodic)?;
    let walls = check_walls(bodies, walls, sides, images)?;
    Ok((pairs, walls))
}

/// Every pair of spheres in the same or adjacent cells (each pair once).
fn check_pairs(bodies: &[Trajectory], cells: &Cells, periodic: bool) -> Result<f64, Breach> {
    let n = bodies.len();
    let count = cells.cell_count();
    // Counting sort of the spheres by the cell their position falls in.
    let coords: Vec<[i32; 3]> = bodies.iter().map(|b| cells.coords_of(b.r)).collect();
    let mut start = vec![0u32; count + 1];
    for c in &coords {
        start[cells.index(*c) + 1] += 1;
    }
    for k in 0..count {
        start[k + 1] += start[k];
    }
    let mut fill = start.clone();
    let mut order = vec![0u32; n];
    for (i, c) in coords.iter().enumerate() {
        let cell = cells.index(*c);
        order[fill[cell] as usize] = i as u32;
        fill[cell] += 1;
    }
    let mut worst = f64::NEG_INFINITY;
    for (i, bi) in bodies.iter().enumerate() {
        for offset in 0..27 {
            let Some(cell) = neighbour(cells, coords[i], offset, periodic) else {
                continue;
            };
            let members = &order[start[cell] as usize..start[cell + 1] as usize];
            for &j in members.iter().filter(|&&j| j as usize > i) {
                let bj = &bodies[j as usize];
                let mut dr = bj.r - bi.r;
                if periodic {
                    dr -= cells.len * (dr / cells.len).round();
                }
                let d = bi.radius + bj.radius;
                let depth = d - dr.length();
                let tolerance = OVERLAP_TOLERANCE * d;
                if depth.is_nan() || depth > tolerance {
                    return Err(Breach {
                        sphere: i,
                        other: Body::new(ShapeKind::Sphere, j),
                        depth,
                        tolerance,
                    });
                }
                worst = worst.max(depth / tolerance);
            }
        }
    }
    Ok(worst)
}

/// The cell at stencil `offset` (`x + 3y + 9z`, each of `x, y, z` in `0…2` for `−1…+1`) from
/// `c`, wrapped in a periodic box (at least three cells a side, as the engine keeps it, so the
/// 27 cells are distinct); `None` outside an open grid.
fn neighbour(cells: &Cells, c: [i32; 3], offset: usize, periodic: bool) -> Option<usize> {
    let o = [offset % 3, offset / 3 % 3, offset / 9];
    let mut out = [0i32; 3];
    for k in 0..3 {
        let x = c[k] + o[k] as i32 - 1;
        out[k] = if periodic {
            x.rem_euclid(cells.n[k])
        } else if x < 0 || x >= cells.n[k] {
            return None;
        } else {
            x
        };
    }
    Some(cells.index(out))
}

/// Every sphere against every static shape. In a periodic box (`images`, each sphere's face
/// crossings, in the order of `bodies`; empty elsewhere) a sphere that wraps across the faces
/// a plane's normal crosses comes back on the plane's other side in the box, where it meets
/// the plane's image: its side flips with each such crossing.
fn check_walls(
    bodies: &[Trajectory],
    walls: &Statics<u16>,
    sides: &[bool],
    images: &[[i64; 3]],
) -> Result<f64, Breach> {
    let mut worst = f64::NEG_INFINITY;
    let count = walls.len();
    for (i, b) in bodies.iter().enumerate() {
        let tolerance = OVERLAP_TOLERANCE * b.radius;
        for (k, (body, shape, _)) in walls.iter().enumerate() {
            let side = match (sides.get(i * count + k), shape, images.get(i)) {
                (Some(&side), crate::Static::Plane(p), Some(crossed)) => {
                    // A plane in a periodic box has its normal along a box axis.
                    let n = p.normal().as_dvec3().abs();
                    side ^ (crossed[n.max_position()] % 2 != 0)
                }
                (Some(&side), _, _) => side,
                (None, _, _) => shape.side(b.r),
            };
            // On its own side of a plane: `radius − |d|` deep; across: the whole way back.
            let depth = -shape.gap_on_side(b.r, b.radius, side);
            if depth <= tolerance {
                worst = worst.max(depth / tolerance);
            } else {
                return Err(Breach {
                    sphere: i,
                    other: body,
                    depth,
                    tolerance,
                });
            }
        }
    }
    Ok(worst)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Container, Plane};
    use glam::DVec3;

    /// A body at `r` of radius `radius`, at rest.
    fn body(r: DVec3, radius: f64) -> Trajectory {
        Trajectory {
            r,
            t: 0.0,
            v: DVec3::ZERO,
            radius,
        }
    }

    fn grid() -> Cells {
        Cells::new(DVec3::ZERO, DVec3::splat(10.0), 1.0, 1000)
    }

    /// Each breach is found and named, and the measures are relative to the tolerances.
    #[test]
    fn breaches_are_found_and_named() {
        let walls = Statics::new()
            .with(Plane::new([0.0, 0.0, 2.0], [0.0, 0.0, 1.0]).unwrap(), 0)
            .with(Container::new([5.0; 3], 4.0).unwrap(), 0);
        let apart = [
            body(DVec3::new(5.0, 5.0, 6.0), 0.5),
            body(DVec3::new(6.0, 5.0, 6.0), 0.5),
        ];
        let sides = sides(&apart, &walls);
        let (pairs, w) = check(&apart, &grid(), false, &walls, &sides, &[]).unwrap();
        assert_eq!(pairs, 0.0); // touching exactly
        assert!(w <= 0.0, "{w}");
        // Overlapping by 2⁻¹⁴ of the contact distance: 4 times the tolerance.
        let close = [
            apart[0],
            body(DVec3::new(6.0 - 1.0 / 16384.0, 5.0, 6.0), 0.5),
        ];
        let b = check(&close, &grid(), false, &walls, &sides, &[]).unwrap_err();
        assert_eq!((b.sphere, b.other), (0, Body::new(ShapeKind::Sphere, 1)));
        assert!((b.depth / b.tolerance - 4.0).abs() < 1e-6, "{b:?}");
        // Outside the container.
        let out = [apart[0], body(DVec3::new(9.0, 5.0, 5.0), 0.5)];
        let b = check(&out, &grid(), false, &walls, &sides, &[]).unwrap_err();
        assert_eq!((b.sphere, b.other), (1, Body::new(ShapeKind::Container, 0)));
        assert!((b.depth - 0.5).abs() < 1e-12);
        // Across the plane, well clear of it: a breach by the whole way back.
        let across = [apart[0], body(DVec3::new(6.0, 5.0, 0.5), 0.5)];
        let b = check(&across, &grid(), false, &walls, &sides, &[]).unwrap_err();
        assert_eq!((b.sphere, b.other), (1, Body::new(ShapeKind::Plane, 0)));
        assert!((b.depth - 2.0).abs() < 1e-12, "{b:?}");
        // In a periodic box the same sphere is on its side after an odd number of crossings of
        // the faces across the plane's normal (z), where it meets the plane's image; after none,
        // or crossings of another axis only, it went through: a breach.
        let plane = Statics::new().with(Plane::new([0.0, 0.0, 2.0], [0.0, 0.0, 1.0]).unwrap(), 0);
        let sides = super::sides(&apart, &plane);
        for (crossed, through) in [
            ([0, 0, 0], true),
            ([0, 0, -1], false),
            ([0, 0, 2], true),
            ([1, -1, 0], true),
            ([1, 0, 3], false),
        ] {
            let result = check(&across, &grid(), true, &plane, &sides, &[[0; 3], crossed]);
            assert_eq!(result.is_err(), through, "{crossed:?}: {result:?}");
        }
    }

    /// Pairs across a periodic box's faces and in far cells of an open grid are found.
    #[test]
    fn neighbours_across_faces_and_beyond_the_grid_are_found() {
        let none = Statics::default();
        let wrap = [
            body(DVec3::new(0.2, 5.0, 5.0), 0.5),
            body(DVec3::new(9.3, 5.0, 5.0), 0.5),
        ];
        let b = check(&wrap, &grid(), true, &none, &[], &[]).unwrap_err();
        assert_eq!(b.other, Body::new(ShapeKind::Sphere, 1));
        assert!(check(&wrap, &grid(), false, &none, &[], &[]).is_ok());
        // Both far outside the grid, clamped into the same edge cell.
        let far = [
            body(DVec3::new(100.0, 5.0, 5.0), 0.5),
            body(DVec3::new(100.5, 5.0, 5.0), 0.5),
        ];
        assert!(check(&far, &grid(), false, &none, &[], &[]).is_err());
        // A box of three cells a side: every pair is checked once.
        let small = Cells::new(DVec3::ZERO, DVec3::splat(3.0), 1.0, 27);
        let pair = [
            body(DVec3::new(0.5, 0.5, 0.5), 0.5),
            body(DVec3::new(2.6, 0.5, 0.5), 0.5),
        ];
        assert!(check(&pair, &small, true, &none, &[], &[]).is_err());
    }
}
