//! Test-only: the brute-force check after every event (`step` calls it in tests).

use super::*;

impl<
    R: Responder,
    const PERIODIC: bool,
    const WALLS: bool,
    const GEOMETRY: bool,
    const GRAVITY: bool,
> Engine<R, PERIODIC, WALLS, GEOMETRY, GRAVITY>
{
    /// The periodic shift of shift code `code`, as a vector.
    fn shift_of(&self, code: u8) -> DVec3 {
        let [x, y, z, _] = self.shift[usize::from(code)].to_array();
        DVec3::new(x, y, z)
    }

    /// Test-only: after the event of sphere `s`, no pair of spheres (any image) comes closer
    /// than the overlap tolerance before the earlier of their two pending events, and no
    /// sphere gets through a static shape before its own — checked by brute force in f64 from
    /// the closest approach of the straight lines over that interval (a closed form, no root
    /// solver shared with the predictions). A broken prediction, stale-candidate rule, merge,
    /// wall policy or cluster motion would let a collision through. Members of one cluster
    /// move together and are never in each other's events: they are checked to stay at their
    /// distance.
    pub(super) fn check_invariant(&self, s: u32) {
        self.check_lists(s);
        use crate::sim::OVERLAP_TOLERANCE;
        let n = self.m.bodies.len();
        let len = self.cells.len;
        let g = self.m.g;
        let at_now = |b: &Trajectory| self.centre_at(b, self.now);
        let v_now = |b: &Trajectory| b.at(self.now, g).1;
        // How close `r0 + v t` comes to the origin over `[0, t_end]` (`t_end` may be ∞).
        let closest = |r0: DVec3, v: DVec3, t_end: f64| {
            let a = v.length_squared();
            let t = if a > 0.0 {
                (-r0.dot(v) / a).clamp(0.0, t_end)
            } else {
                0.0
            };
            (r0 + v * t).length()
        };
        for i in 0..n {
            let bi = &self.m.bodies[i];
            let ri = at_now(bi);
            let ti = self.scheduled[i] - self.now;
            for j in i + 1..n {
                let bj = &self.m.bodies[j];
                let mut dr = at_now(bj) - ri;
                if PERIODIC {
                    dr -= len * (dr / len).round();
                }
                let horizon = ti.min(self.scheduled[j] - self.now).max(0.0);
                let d = bi.radius + bj.radius;
                // Both fall alike: their relative motion is a straight line.
                let depth = d - closest(dr, v_now(bj) - v_now(bi), horizon);
                assert!(
                    depth <= OVERLAP_TOLERANCE * d,
                    "after the event of sphere {s} at t = {}: spheres {i} and {j} overlap by \
                     {depth:e} before their next events at {} and {}",
                    self.now,
                    self.scheduled[i],
                    self.scheduled[j]
                );
            }
            // Static shapes: a plane's distance is linear and a container's gap concave in t,
            // so their deepest point is at an end of the interval; a cylinder's perpendicular
            // distance is the closest approach of the projected lines.
            let horizon = ti.max(0.0);
            let tolerance = OVERLAP_TOLERANCE * bi.radius;
            for (body, shape, _) in self.walls.iter() {
                let gap = if GRAVITY {
                    let gap = |x: DVec3| shape.normal_gap(x, bi.radius).1;
                    least_gap_falling(gap, ri, v_now(bi), g, horizon, bi.radius, tolerance)
                } else {
                    shape.least_gap_on_path(ri, bi.v, horizon, bi.radius)
                };
                assert!(
                    -gap <= tolerance,
                    "after the event of sphere {s} at t = {}: sphere {i} gets {:e} through \
                     {body} before its next event at {}",
                    self.now,
                    -gap,
                    self.scheduled[i]
                );
            }
        }
    }

    /// Test-only: after the event of sphere `s`, every sphere is inside its shell, and every
    /// pair whose shell centres are within reach (any periodic image, by brute force over all
    /// pairs and all 27 shifts, not through the cells) is in both lists with that image, and
    /// no list names a sphere twice with one image or names its own sphere. A pair missing from
    /// a list is a collision nobody predicts.
    fn check_lists(&self, s: u32) {
        use super::lists::{entry, mirror};
        let n = self.m.bodies.len();
        let l = &self.lists;
        // The list test on vectors for sphere `j`'s image `code` seen from `i`: the centres'
        // squared distance and the reach it is held to (within: `q ≤ d²`).
        let test = |i: usize, j: usize, code: u8| {
            let (si, sj) = (l.centre[i], l.centre[j]);
            let dr = (sj.c - si.c) + self.shift_of(code);
            (dr.length_squared(), si.radius + sj.radius + l.reach)
        };
        for i in 0..n {
            let b = &self.m.bodies[i];
            let away = (self.centre_at(b, self.now) - l.centre[i].c).length();
            assert!(
                away <= l.delta * (1.0 + super::lists::REACH_MARGIN),
                "after the event of sphere {s} at t = {}: sphere {i} is {away} from its shell \
                 centre, beyond {}",
                self.now,
                l.delta
            );
            let list = l.of(i as u32);
            // Every entry is within reach and in the other sphere's list (nothing stale is
            // left behind by a rebuild); that none is missing is checked below.
            for &e in list {
                let (j, code) = super::lists::split(e);
                let (q, d) = test(i, j as usize, code);
                assert!(
                    q <= d * d && l.of(j).contains(&entry(i as u32, mirror(code))),
                    "after the event of sphere {s} at t = {}: sphere {i}'s list names {j} (shift \
                     {code}) {} apart, beyond reach {d}, or not mirrored",
                    self.now,
                    q.sqrt()
                );
            }
            let mut sorted = list.to_vec();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(
                sorted.len(),
                list.len(),
                "sphere {i}'s list repeats an entry"
            );
        }
        let codes: &[u8] = if PERIODIC {
            &[
                0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22,
                23, 24, 25, 26,
            ]
        } else {
            &[super::lists::NO_SHIFT]
        };
        for i in 0..n {
            assert!(
                l.of(i as u32)
                    .iter()
                    .all(|&e| super::lists::split(e).0 as usize != i),
                "sphere {i}'s list names itself"
            );
            for j in i + 1..n {
                for &code in codes {
                    let (q, d) = test(i, j, code);
                    if q > d * d {
                        continue;
                    }
                    let (i, j) = (i as u32, j as u32);
                    assert!(
                        l.of(i).contains(&entry(j, code))
                            && l.of(j).contains(&entry(i, mirror(code))),
                        "after the event of sphere {s} at t = {}: spheres {i} and {j} (shift \
                         {code}) are {} apart, within reach {d}, and missing from a list",
                        self.now,
                        q.sqrt()
                    );
                }
            }
        }
    }
}

/// Test-only: the least gap of a sphere falling from `r` at `v` under `g` for `horizon`, by
/// conservative advancement with the shape's own gap function: over a step `Δt` the gap falls
/// by at most the speed bound `‖v‖ + ‖g‖·horizon` times `Δt`, so steps of
/// `(gap + tolerance)/speed` never step over a point deeper than `tolerance` (no polynomial, no
/// root solver shared with the predictions). An endless horizon is cut at the time the
/// sphere takes to fall 10⁶ of its radii. Returns the least gap seen, or `−∞` if one sample
/// was deeper than the tolerance.
fn least_gap_falling(
    gap_at: impl Fn(DVec3) -> f64,
    r: DVec3,
    v: DVec3,
    g: DVec3,
    horizon: f64,
    radius: f64,
    tolerance: f64,
) -> f64 {
    let fall = (2.0e6 * radius / g.length()).sqrt() + 1e6 * radius / v.length().max(1e-300);
    let horizon = horizon.min(fall);
    let speed = v.length() + g.length() * horizon;
    let mut t = 0.0;
    let mut least = f64::INFINITY;
    loop {
        let x = r + v * t + g * (0.5 * t * t);
        let gap = gap_at(x);
        least = least.min(gap);
        if gap < -tolerance {
            return f64::NEG_INFINITY;
        }
        if t >= horizon || speed == 0.0 {
            return least;
        }
        t = (t + (gap + tolerance) / speed).min(horizon);
    }
}
