//! Pair prediction, eight neighbours at a time: the engine gathers each neighbour's relative
//! position and velocity (computed in f64 at the current time, so they are small numbers) into
//! f32 lanes, the `Stable` sphere-pair kernel screens them, and the few lanes that may be the
//! earliest are answered again in f64 (`Stable` on `f64x4`), which sets the event time.
//! Why this keeps the engine exact enough: docs/derivations/simulation.md.

use glam::DVec3;
use wide::{f32x8, f64x4};

use crate::contact::Side;
use crate::kernels::quadratic::{Relative3, Solver, Stable};

/// Lanes a screened time may exceed the earliest by and still be answered again in f64.
const NEAR_TIE: f32 = 1.0 + 1.0 / 1024.0;

/// A pair whose `C = ‖r0‖² − D²` is below this fraction of `‖r0‖² + D²` (within about `2⁻¹⁰ D`
/// of touching) is always answered again in f64: rounding `r0` to f32 moves `C` by up to
/// `3·2⁻²⁴ (‖r0‖² + D²)`, so the screened time of such a pair, `C / (√q − b)`, may be off by far
/// more than the near tie (found in a shell of spheres sliding along a vessel's wall: a pair
/// `7.5·10⁻⁸` from touching, closing at `1.4·10⁻⁵`, screened later than two others and left
/// out, then overlapping). Beyond it, `C`'s relative error is below `3·2⁻¹⁴`
/// (docs/derivations/simulation.md, "Prediction in f32").
const NEAR_CONTACT: f64 = 1.0 / 1024.0;

/// The lane group being filled: eight neighbours' relative motion, on the stack.
#[derive(Debug, Clone, Copy)]
struct Group {
    r0: [[f32; 8]; 3],
    v: [[f32; 8]; 3],
    d: [f32; 8],
}

impl Default for Group {
    fn default() -> Self {
        Self {
            r0: [[0.0; 8]; 3],
            v: [[0.0; 8]; 3],
            d: [f32::NAN; 8],
        }
    }
}

/// A prediction's neighbours, screened eight at a time as they are gathered.
#[derive(Debug, Clone, Default)]
pub(crate) struct PairBatch {
    group: Group,
    /// Screened times per lane, one entry per full (or final) group.
    t: Vec<[f32; 8]>,
    /// Whether each group had a lane outside the f32 safe range.
    risk: Vec<bool>,
    /// Per group, the lanes within [`NEAR_CONTACT`] of touching (bit `lane`).
    near: Vec<u8>,
    /// The filling group's near lanes.
    near_group: u8,
    /// Neighbour index and stencil image per lane.
    pub who: Vec<(u32, u8)>,
    len: usize,
    /// The two earliest screened times so far, and how many lanes hit at all.
    first: f32,
    second: f32,
    hits: usize,
}

impl PairBatch {
    /// Empties the batch (keeping its buffers) and makes room for `more` neighbours.
    #[inline]
    pub fn start(&mut self, more: usize) {
        self.len = 0;
        self.t.clear();
        self.risk.clear();
        self.near.clear();
        self.near_group = 0;
        (self.first, self.second, self.hits) = (f32::INFINITY, f32::INFINITY, 0);
        if self.who.len() < more + 8 {
            self.who.resize(more + 8, (u32::MAX, 0));
        }
    }

    /// Number of neighbours gathered.
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Writes one neighbour: relative position `r0` and velocity `v` (its minus the predicted
    /// sphere's, f64 at the current time) and contact distance `d`; it counts only if `keep`,
    /// so that culling needs no branch. A full group is screened at once.
    #[inline(always)]
    pub fn push_if(&mut self, keep: bool, r0: DVec3, v: DVec3, d: f64, who: u32, image: u8) {
        let lane = self.len & 7;
        for k in 0..3 {
            self.group.r0[k][lane] = r0[k] as f32;
            self.group.v[k][lane] = v[k] as f32;
        }
        self.group.d[lane] = d as f32;
        let (r2, d2) = (r0.length_squared(), d * d);
        let near = r2 - d2 <= NEAR_CONTACT * (r2 + d2);
        self.near_group |= u8::from(keep & near) << lane;
        self.who[self.len] = (who, image);
        self.len += usize::from(keep);
        if keep && lane == 7 {
            self.screen_group(8);
        }
    }

    /// Screens the group's first `lanes` lanes with the f32 `Stable` kernel (the others are
    /// NaN and never hit).
    #[inline]
    fn screen_group(&mut self, lanes: usize) {
        let g = &mut self.group;
        for lane in lanes..8 {
            g.d[lane] = f32::NAN;
        }
        let rel = Relative3 {
            r0: g.r0.map(f32x8::from),
            v: g.v.map(f32x8::from),
            d: f32x8::from(g.d),
        };
        let (t, risk) = Stable::arrival(&rel, Side::Exterior, f32x8::splat(f32::INFINITY));
        let t = t.to_array();
        // Most groups have no hit at all: one mask test skips them.
        if t.iter().any(|x| x.is_finite()) {
            for &tl in &t {
                self.hits += usize::from(tl.is_finite());
                if tl < self.second {
                    if tl < self.first {
                        self.second = self.first;
                        self.first = tl;
                    } else {
                        self.second = tl;
                    }
                }
            }
        }
        self.t.push(t);
        // Lanes outside f32's safe range (NaN padding counts) are decided in f64.
        let risky = risk.to_array().iter().take(lanes).any(|r| r.to_bits() != 0);
        self.risk.push(risky);
        self.near.push(std::mem::take(&mut self.near_group));
    }

    /// Screens the last, partly filled group.
    #[inline]
    pub fn finish(&mut self) {
        let lanes = self.len & 7;
        if lanes != 0 {
            self.screen_group(lanes);
        }
    }

    /// The lanes worth answering in f64: those within a near tie of the second earliest
    /// screened time (so the two earliest are settled in f64), those within
    /// [`NEAR_CONTACT`] of touching (whose screened time may be far off), and every lane of a
    /// group with a lane outside the f32 safe range. Returns whether every lane with a contact
    /// is among them.
    pub fn candidates(&self, out: &mut Vec<usize>) -> bool {
        out.clear();
        if self.hits == 0 && !self.risk.iter().any(|&r| r) && self.near.iter().all(|&m| m == 0) {
            return true;
        }
        let (first, second) = (self.first, self.second);
        let cut = if second.is_finite() { second } else { first } * NEAR_TIE;
        let mut left_out = false;
        for (g, t) in self.t.iter().enumerate() {
            for (lane, &tl) in t.iter().enumerate() {
                let k = 8 * g + lane;
                if k >= self.len {
                    break;
                }
                if tl <= cut || self.risk[g] || self.near[g] & (1 << lane) != 0 {
                    out.push(k);
                } else if tl.is_finite() {
                    left_out = true;
                }
            }
        }
        !left_out
    }
}

/// Earliest exterior contact times of up to four pairs in f64 (`+∞` for none): the `Stable`
/// kernel on `f64x4` lanes, the same formula the screen used.
#[inline]
pub(crate) fn refine(r0: [DVec3; 4], v: [DVec3; 4], d: [f64; 4]) -> [f64; 4] {
    let lane = |f: &dyn Fn(usize) -> f64| f64x4::from([f(0), f(1), f(2), f(3)]);
    let rel = Relative3 {
        r0: [0, 1, 2].map(|k| lane(&|i| r0[i][k])),
        v: [0, 1, 2].map(|k| lane(&|i| v[i][k])),
        d: lane(&|i| d[i]),
    };
    let (t, _) = Stable::arrival(&rel, Side::Exterior, f64x4::splat(f64::INFINITY));
    t.to_array()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// The two earliest contacts the engine keeps from these neighbours (the screen, then f64
    /// for the lanes it selects), as `predict_pairs` keeps them.
    fn kept(pairs: &[(DVec3, DVec3, f64)]) -> Vec<(f64, usize)> {
        let mut batch = PairBatch::default();
        batch.start(pairs.len());
        for (k, &(r0, v, d)) in pairs.iter().enumerate() {
            batch.push_if(r0.dot(v) < 0.0, r0, v, d, k as u32, 13);
        }
        batch.finish();
        let mut lanes = Vec::new();
        batch.candidates(&mut lanes);
        let mut found = Vec::new();
        for chunk in lanes.chunks(4) {
            let mut r0 = [DVec3::ZERO; 4];
            let mut v = [DVec3::ZERO; 4];
            let mut d = [f64::NAN; 4];
            for (lane, &k) in chunk.iter().enumerate() {
                let who = batch.who[k].0 as usize;
                (r0[lane], v[lane], d[lane]) = pairs[who];
            }
            let t = refine(r0, v, d);
            for (lane, &k) in chunk.iter().enumerate() {
                if t[lane].is_finite() {
                    found.push((t[lane], batch.who[k].0 as usize));
                }
            }
        }
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        found.truncate(2);
        found
    }

    /// A pair within f32 rounding of touching, closing slowly while sliding past, beside two
    /// neighbours met a little later: the screen's time for the close pair is far off (its `C`
    /// is a few f32 ulps), and it must still be the earliest kept — the case that let spheres
    /// sliding along a vessel's wall overlap by 2.5·10⁻⁵ of their contact distance.
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
            let exact = refine([close.0; 4], [close.1; 4], [d; 4])[0];
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
            assert_eq!(
                top[0].1, at,
                "case {case}: {top:?}, the close pair meets at {exact}"
            );
        }
    }
}
