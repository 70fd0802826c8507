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

/// Placeholder neighbour of unused scratch lanes.
const NONE_WHO: u32 = u32::MAX;

/// A prediction's neighbours, in lanes of eight.
#[derive(Debug, Clone, Default)]
pub(crate) struct PairBatch {
    r0: [Vec<[f32; 8]>; 3],
    v: [Vec<[f32; 8]>; 3],
    d: Vec<[f32; 8]>,
    /// Screened times per lane.
    t: Vec<[f32; 8]>,
    risk: Vec<u8>,
    /// Neighbour index and stencil image per lane (beyond `len`: scratch).
    pub who: Vec<(u32, u8)>,
    len: usize,
}

impl PairBatch {
    /// Empties the batch (keeping its buffers).
    #[inline]
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// Number of neighbours gathered.
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Makes room for `more` neighbours.
    #[inline]
    pub fn reserve(&mut self, more: usize) {
        let need = (self.len + more).div_ceil(8) + 1;
        if self.d.len() < need {
            self.grow(need);
        }
    }

    #[cold]
    fn grow(&mut self, need: usize) {
        while self.d.len() < need {
            let pad = [f32::NAN; 8];
            for k in 0..3 {
                self.r0[k].push(pad);
                self.v[k].push(pad);
            }
            self.d.push(pad);
            self.t.push(pad);
        }
        if self.who.len() < 8 * need {
            self.who.resize(8 * need, (NONE_WHO, 0));
        }
    }

    /// Writes one neighbour (after [`reserve`](Self::reserve)): relative position `r0` and
    /// velocity `v` (its minus the predicted sphere's, f64 at the current time) and contact
    /// distance `d`; it counts only if `keep`, so that culling needs no branch.
    #[inline(always)]
    pub fn push_if(&mut self, keep: bool, r0: DVec3, v: DVec3, d: f64, who: u32, image: u8) {
        let (g, lane) = (self.len / 8, self.len % 8);
        for k in 0..3 {
            self.r0[k][g][lane] = r0[k] as f32;
            self.v[k][g][lane] = v[k] as f32;
        }
        self.d[g][lane] = d as f32;
        self.who[self.len] = (who, image);
        self.len += usize::from(keep);
    }

    /// Screens every lane with the f32 kernel. Padding lanes are NaN and never hit.
    #[inline]
    pub fn screen(&mut self) {
        let groups = self.len.div_ceil(8);
        // Padding of the last group: NaN never hits.
        if !self.len.is_multiple_of(8) {
            let (g, from) = (self.len / 8, self.len % 8);
            for lane in from..8 {
                self.d[g][lane] = f32::NAN;
            }
        }
        self.risk.clear();
        let t_max = f32x8::splat(f32::INFINITY);
        for g in 0..groups {
            let load = |a: &Vec<[f32; 8]>| f32x8::from(a[g]);
            let rel = Relative3 {
                r0: [load(&self.r0[0]), load(&self.r0[1]), load(&self.r0[2])],
                v: [load(&self.v[0]), load(&self.v[1]), load(&self.v[2])],
                d: load(&self.d),
            };
            let (t, risk) = Stable::arrival(&rel, Side::Exterior, t_max);
            self.t[g] = t.to_array();
            // Lanes outside f32's safe range (NaN padding counts) are decided in f64.
            let risky = risk
                .to_array()
                .iter()
                .take(self.len - 8 * g)
                .any(|r| r.to_bits() != 0);
            self.risk.push(u8::from(risky));
        }
    }

    /// The lanes worth answering in f64: those within a near tie of the second earliest
    /// screened time (so the two earliest are settled in f64), and every lane of a group with
    /// a lane outside the f32 safe range. Returns whether every lane with a contact is among
    /// them.
    pub fn candidates(&self, out: &mut Vec<usize>) -> bool {
        out.clear();
        let groups = self.len.div_ceil(8);
        let (mut first, mut second) = (f32::INFINITY, f32::INFINITY);
        for t in &self.t[..groups] {
            for &tl in t {
                if tl < second {
                    if tl < first {
                        second = first;
                        first = tl;
                    } else {
                        second = tl;
                    }
                }
            }
        }
        // Padding lanes are NaN (never less than anything), culled lanes beyond `len` may hold
        // old times: they are excluded below by index.
        let cut = if second.is_finite() { second } else { first } * NEAR_TIE;
        let mut left_out = false;
        for (g, t) in self.t[..groups].iter().enumerate() {
            for (lane, &tl) in t.iter().enumerate() {
                let k = 8 * g + lane;
                if k >= self.len {
                    break;
                }
                if tl <= cut || self.risk[g] != 0 {
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
