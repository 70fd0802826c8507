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
    /// screened time (so the two earliest are settled in f64), and every lane of a group with
    /// a lane outside the f32 safe range. Returns whether every lane with a contact is among
    /// them.
    pub fn candidates(&self, out: &mut Vec<usize>) -> bool {
        out.clear();
        if self.hits == 0 && !self.risk.iter().any(|&r| r) {
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
                if tl <= cut || self.risk[g] {
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
