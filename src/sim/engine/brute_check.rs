//! Test-only: the brute-force check after every event (`step` calls it in tests).

use super::*;

impl<R: Responder, const PERIODIC: bool, const WALLS: bool, const GEOMETRY: bool>
    Engine<R, PERIODIC, WALLS, GEOMETRY>
{
    /// Test-only: after the event of sphere `s`, no pair of spheres (any image) comes closer
    /// than the overlap tolerance before the earlier of their two pending events, and no
    /// sphere gets through a static shape before its own — checked by brute force in f64 from
    /// the closest approach of the straight lines over that interval (a closed form, no root
    /// solver shared with the predictions). A broken prediction, stale-candidate rule, merge,
    /// wall policy or cluster motion would let a collision through. Members of one cluster
    /// move together and are never in each other's events: they are checked to stay at their
    /// distance.
    pub(super) fn check_invariant(&self, s: u32) {
        use crate::sim::OVERLAP_TOLERANCE;
        let n = self.m.bodies.len();
        let len = self.cells.len;
        let at_now = |b: &Trajectory| b.r + b.v * (self.now - b.t);
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
                let depth = d - closest(dr, bj.v - bi.v, horizon);
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
                let gap = shape.least_gap_on_path(ri, bi.v, horizon, bi.radius);
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
}
