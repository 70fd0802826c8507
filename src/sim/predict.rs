//! Pair prediction in f64: the engine computes each approaching neighbour's relative position
//! and velocity (in f64 at the current time, so they are small numbers), [`arrivals`] answers
//! four of them at once with the `Stable` sphere-pair kernel on `f64x4` lanes, and [`Kept`]
//! keeps the two earliest contacts. Every event time is an f64 root of the same formula the
//! batch kernels use: the same code. Why f64 and not an f32 screen:
//! docs/derivations/simulation.md, "Prediction in f64".

use wide::f64x4;

use super::cells::NONE;
use crate::contact::Side;
use crate::kernels::quadratic::{Relative3, Solver, Stable};

/// A predicted pair contact: when, with whom, and the partner's counter at the prediction (the
/// prediction is stale once the partner's velocity has changed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Candidate {
    pub t: f64,
    pub j: u32,
    pub counter: u32,
}

impl Candidate {
    pub(crate) const NONE: Self = Self {
        t: f64::INFINITY,
        j: NONE,
        counter: 0,
    };

    #[inline]
    pub(crate) fn before(&self, o: &Self) -> bool {
        self.t < o.t || (self.t == o.t && self.j < o.j)
    }
}

/// The earliest exterior contact times from now of four pairs (`+∞` for none), one a lane:
/// pair `k` is at `r0[k]`, moving at `v[k]`, relative to each other, in the first three lanes,
/// with its contact distance in the fourth lane of `v[k]` (the fourth of `r0[k]` is ignored).
/// They are transposed into the `Stable` sphere-pair kernel's lanes. Also the mask of the
/// finite times (bit `k` for pair `k`).
#[inline(always)]
pub(crate) fn arrivals(r0: [f64x4; 4], v: [f64x4; 4]) -> ([f64; 4], u32) {
    let [x, y, z, _] = f64x4::transpose(r0);
    let [vx, vy, vz, d] = f64x4::transpose(v);
    let rel = Relative3 {
        r0: [x, y, z],
        v: [vx, vy, vz],
        d,
    };
    let (t, _) = Stable::arrival(&rel, Side::Exterior, f64x4::splat(f64::INFINITY));
    (t.to_array(), t.is_finite().to_bitmask())
}

/// The two earliest contacts answered so far, and how many contacts there were.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Kept {
    pub top: [Candidate; 2],
    pub found: usize,
}

impl Default for Kept {
    fn default() -> Self {
        Self {
            top: [Candidate::NONE; 2],
            found: 0,
        }
    }
}

impl Kept {
    /// Adds a contact; the two earliest by time, then partner, stay (`Candidate::before`).
    #[inline]
    pub fn add(&mut self, c: Candidate) {
        self.found += 1;
        if c.before(&self.top[0]) {
            self.top = [c, self.top[0]];
        } else if c.before(&self.top[1]) {
            self.top[1] = c;
        }
    }

    /// The two earliest, and whether they are all there were.
    #[inline]
    pub fn result(&self) -> ([Candidate; 2], bool) {
        (self.top, self.found <= 2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use glam::DVec3;

    /// One pair's answer: lane 0 of [`arrivals`], the other lanes at rest.
    fn arrival(r0: DVec3, v: DVec3, d: f64) -> f64 {
        let lanes = |a: DVec3, w: f64| f64x4::new([a.x, a.y, a.z, w]);
        let rest = f64x4::splat(0.0);
        arrivals(
            [lanes(r0, 0.0), rest, rest, rest],
            [lanes(v, d), rest, rest, rest],
        )
        .0[0]
    }

    /// The two earliest contacts kept from these neighbours, as `predict_pairs` keeps them
    /// (receding pairs skipped).
    fn kept(pairs: &[(DVec3, DVec3, f64)]) -> Vec<(f64, usize)> {
        let mut kept = Kept::default();
        for (k, &(r0, v, d)) in pairs.iter().enumerate() {
            let t = arrival(r0, v, d);
            if r0.dot(v) < 0.0 && t.is_finite() {
                kept.add(Candidate {
                    t,
                    j: k as u32,
                    counter: 0,
                });
            }
        }
        let (top, complete) = kept.result();
        assert_eq!(complete, kept.found <= 2);
        top.iter()
            .filter(|c| c.t.is_finite())
            .map(|c| (c.t, c.j as usize))
            .collect()
    }

    /// A pair within f32 rounding of touching, closing slowly while sliding past, beside two
    /// neighbours met a little later, anywhere in the list: it is the earliest kept (an
    /// f32 screen once left it out, and spheres sliding along a vessel's wall overlapped by
    /// 2.5·10⁻⁵ of their contact distance).
    #[test]
    fn a_pair_about_to_touch_is_never_left_out() {
        let mut rng = Rng::new(5);
        let d = 0.6;
        for case in 0..2000 {
            let n = rng.direction();
            let t = rng.perpendicular(n);
            let gap = d * (1e-8 + 4e-7 * rng.unit());
            let u = 1e-5 * (1.0 + rng.unit());
            let close = (n * (d + gap), -n * u + t * 3.5e-3, d);
            let exact = kept(&[close])[0].0;
            // Two neighbours met head-on a little after it, and some never met.
            let head_on = |at: f64, rng: &mut Rng| {
                let dir = rng.direction();
                (dir * (d + 0.05), -dir * (0.05 / at), d)
            };
            let mut pairs = vec![
                head_on(exact * 1.3, &mut rng),
                head_on(exact * 2.0, &mut rng),
            ];
            for _ in 0..9 {
                let dir = rng.direction();
                pairs.push((dir * 1.5, dir * 0.1, d));
            }
            let at = (rng.unit() * pairs.len() as f64) as usize;
            pairs.insert(at, close);
            let top = kept(&pairs);
            assert_eq!(top[0].1, at, "case {case}: {top:?}");
            assert_eq!(
                top.len(),
                2,
                "case {case}: the later head-on pair is kept second"
            );
        }
    }

    /// Ties keep the lower partner first; a third contact makes the answer incomplete.
    #[test]
    fn the_two_earliest_are_kept_in_order() {
        let head_on = |dir: DVec3, at: f64| (dir * 1.5, -dir * (0.5 / at), 1.0);
        let pairs = [
            head_on(DVec3::X, 3.0),
            head_on(DVec3::Y, 1.0),
            head_on(DVec3::Z, 1.0),
            head_on(-DVec3::X, 2.0),
            head_on(-DVec3::Y, 0.5),
        ];
        assert_eq!(kept(&pairs), vec![(0.5, 4), (1.0, 1)]);
        let mut k = Kept::default();
        k.add(Candidate {
            t: 10.0 + arrival(pairs[0].0, pairs[0].1, 1.0),
            j: 0,
            counter: 7,
        });
        assert_eq!(k.result().0[0].counter, 7);
        assert_eq!(k.result().0[0].t, 13.0);
        assert!(k.result().1);
    }
}
