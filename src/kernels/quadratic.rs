//! The one quadratic solver of the narrow phase, per accuracy mode, shared by every pair kind.
//!
//! A pair kind describes its relative motion ([`Relative3`] for sphere pairs, containers and
//! cylinders, [`Relative1`] for planes); a [`Solver`] turns it into the earliest admissible
//! time per lane, with the policy of `reference::quadratic` (docs/derivations/policies.md):
//! `+∞` where there is no contact in `[0, t_max]`. Every hit test is an ordered comparison,
//! so a NaN lane (padding, or NaN input) never reports a hit.
//! Why `Stable` keeps its digits: docs/derivations/accuracy.md.

use crate::contact::Side;
use crate::lanes::{Lanes, V3, cross_fused, dot, dot_fused};

/// The seed's quantities of one pair kind, lane-wise, in the two forms the solvers use.
pub trait Relative<L: Lanes> {
    /// `(A, B, C)` exactly as the seed writes them.
    fn textbook(&self) -> (L, L, L);
    /// `(A, b, C, q)` with `b = B/2` and `q = b² − AC` computed without cancellation.
    fn stable(&self) -> (L, L, L, L);
    /// `√q` (NaN where `q < 0`).
    #[inline(always)]
    fn sqrt_q(&self, q: L) -> L {
        q.sqrt()
    }
    /// The velocity's components OR-ed bit by bit: `0` (or `−0`) exactly when `v = 0`.
    fn v_bits(&self) -> L;
    /// `D²`, as the solvers compute it.
    fn d2(&self) -> L {
        let d = self.d();
        d * d
    }
    /// Contact distance.
    fn d(&self) -> L;
}

/// The safe window of the f32 kernels: `2⁻⁹⁰ ≤ m, A, A·m ≤ 2¹²⁰`, with `m = ‖r0‖² + D²` and
/// `A = ‖v‖²`, unless `v = 0` exactly (no motion: never a contact, whatever the scale).
/// Every intermediate of the quadratic is then a normal f32 of size at most `3·2¹²⁰`, and
/// every time lies within `2^±105`.
const SAFE_LO: f32 = 1.0 / (1u128 << 90) as f32;
const SAFE_HI: f32 = (1u128 << 120) as f32;

/// Mask of the lanes whose magnitudes leave the range where f32 arithmetic keeps its relative
/// precision (no overflow, no subnormal intermediate): those are answered again in f64
/// (docs/derivations/range.md). `m = C + 2D² ≈ ‖r0‖² + D²` within a factor two is all the
/// test needs. Never set for f64 lanes, which hold every intermediate of every finite f32
/// input. NaN lanes (padding, or an overflow's `∞ − ∞`) count as at risk: the f64 answer for
/// padding is no contact too.
#[inline(always)]
fn at_risk<L: Lanes>(a: L, c: L, d2: L, v_bits: L) -> L {
    if L::EXACT_DIFFERENCES {
        return L::splat(0.0);
    }
    let (lo, hi, zero) = (L::splat(SAFE_LO), L::splat(SAFE_HI), L::splat(0.0));
    let m = d2.mul_add(L::splat(2.0), c);
    let p = a * m;
    // v = 0 exactly: no motion, never a contact, at any scale (its A and A·m are exempt).
    let slowest = L::select(v_bits.eq(zero), lo, a.min(p)).min(m);
    // `≤` is false for NaN: an overflow's ∞ − ∞ (or a padding lane) counts as at risk.
    let safe = slowest.ge(lo) & m.le(hi) & p.le(hi);
    L::select(safe, zero, L::splat(f32::from_bits(u32::MAX)))
}

/// Relative motion in 3-D: `r0`, `v` and the contact distance `D`.
pub struct Relative3<L> {
    /// Relative position at `t = 0`.
    pub r0: V3<L>,
    /// Relative velocity.
    pub v: V3<L>,
    /// Contact distance.
    pub d: L,
}

/// Relative motion along one direction (a plane's normal): `R0`, `v`, `D`.
pub struct Relative1<L> {
    /// Signed distance at `t = 0`.
    pub r0: L,
    /// Velocity along the normal.
    pub v: L,
    /// Contact distance.
    pub d: L,
}

/// Relative motion in the plane perpendicular to a cylinder's axis: 2-D `r0`, `v`, `D`.
pub struct Relative2<L> {
    /// Relative position at `t = 0`, in the axis' perpendicular frame.
    pub r0: [L; 2],
    /// Relative velocity, in the same frame.
    pub v: [L; 2],
    /// Contact distance.
    pub d: L,
}

impl<L: Lanes> Relative<L> for Relative2<L> {
    #[inline(always)]
    fn textbook(&self) -> (L, L, L) {
        let Relative2 { r0, v, d } = *self;
        let dot2 = |x: [L; 2], y: [L; 2]| x[0] * y[0] + x[1] * y[1];
        (
            dot2(v, v),
            L::splat(2.0) * dot2(r0, v),
            dot2(r0, r0) - d * d,
        )
    }

    #[inline(always)]
    fn stable(&self) -> (L, L, L, L) {
        let Relative2 { r0, v, d } = *self;
        let a = v[0].mul_add(v[0], v[1] * v[1]);
        let b = r0[0].mul_add(v[0], r0[1] * v[1]);
        let d2 = d * d;
        let c = r0[0].mul_add(r0[0], r0[1].mul_add(r0[1], -d2));
        // Lagrange in 2-D: b² − AC = A D² − (r0 × v)², with the scalar cross product.
        let w = r0[0].mul_add(v[1], -(r0[1] * v[0]));
        (a, b, c, a.mul_add(d2, -(w * w)))
    }

    #[inline(always)]
    fn v_bits(&self) -> L {
        self.v[0] | self.v[1]
    }

    #[inline(always)]
    fn d(&self) -> L {
        self.d
    }
}

impl<L: Lanes> Relative<L> for Relative3<L> {
    #[inline(always)]
    fn textbook(&self) -> (L, L, L) {
        let Relative3 { r0, v, d } = *self;
        (dot(v, v), L::splat(2.0) * dot(r0, v), dot(r0, r0) - d * d)
    }

    #[inline(always)]
    fn stable(&self) -> (L, L, L, L) {
        let Relative3 { r0, v, d } = *self;
        let a = dot_fused(v, v);
        let b = dot_fused(r0, v);
        let d2 = d * d;
        let c = r0[0].mul_add(r0[0], r0[1].mul_add(r0[1], r0[2].mul_add(r0[2], -d2)));
        // Lagrange: b² − AC = (r0·v)² − ‖v‖²(‖r0‖² − D²) = A D² − ‖r0 × v‖².
        let w = cross_fused(r0, v);
        (a, b, c, a.mul_add(d2, -dot_fused(w, w)))
    }

    #[inline(always)]
    fn v_bits(&self) -> L {
        self.v[0] | self.v[1] | self.v[2]
    }

    #[inline(always)]
    fn d(&self) -> L {
        self.d
    }
}

impl<L: Lanes> Relative<L> for Relative1<L> {
    #[inline(always)]
    fn textbook(&self) -> (L, L, L) {
        let Relative1 { r0, v, d } = *self;
        (v * v, L::splat(2.0) * r0 * v, r0 * r0 - d * d)
    }

    #[inline(always)]
    fn stable(&self) -> (L, L, L, L) {
        let Relative1 { r0, v, d } = *self;
        let a = v * v;
        // C = (|R0| − D)(|R0| + D): the difference is exact when |R0| is near D (Sterbenz).
        let c = (r0.abs() - d) * (r0.abs() + d);
        // b² − AC = R0²v² − v²(R0² − D²) = v² D² exactly: never negative.
        (a, r0 * v, c, a * (d * d))
    }

    /// `√(v² D²) = |v| D`: no square root, one rounding.
    #[inline(always)]
    fn sqrt_q(&self, _q: L) -> L {
        self.v.abs() * self.d
    }

    #[inline(always)]
    fn v_bits(&self) -> L {
        self.v
    }

    #[inline(always)]
    fn d(&self) -> L {
        self.d
    }
}

/// An accuracy mode's way to find the earliest admissible root.
pub trait Solver: Sync {
    /// Whether the mode is the seed's formula literally: anchors as given, `ŝ × x × ŝ`.
    const LITERAL: bool;
    /// The earliest admissible time per lane, `+∞` where there is none; and the mask of the
    /// lanes outside the f32 safe range (docs/derivations/range.md).
    fn arrival<L: Lanes, R: Relative<L>>(rel: &R, side: Side, t_max: L) -> (L, L);
}

/// The seed's formula, literally: `B² − 4AC`, `(−B ∓ √disc)/2A`.
#[derive(Debug, Clone, Copy)]
pub struct Textbook;

/// Half-`B`, `q = A D² − ‖r0 × v‖²`, and each root in the form without cancellation.
#[derive(Debug, Clone, Copy)]
pub struct Stable;

impl Solver for Textbook {
    const LITERAL: bool = true;

    #[inline(always)]
    fn arrival<L: Lanes, R: Relative<L>>(rel: &R, side: Side, t_max: L) -> (L, L) {
        let (a, b, c) = rel.textbook();
        let risk = at_risk(a, c, rel.d2(), rel.v_bits());
        let zero = L::splat(0.0);
        let disc = b * b - L::splat(4.0) * a * c;
        let sqrt = disc.sqrt();
        let two_a = L::splat(2.0) * a;
        let moving = a.gt(zero);
        // `towards`: moving towards the contact, where an arrival computed at or before 0 is
        // the literal formula's cancellation within rounding of 0: a contact now
        // (reference::earliest_contact).
        let (root, deeper, towards) = match side {
            Side::Exterior => ((-b - sqrt) / two_a, c.le(zero) & b.lt(zero), b.lt(zero)),
            // Inside: at or past the wall (C ≥ 0) with no way back in: B ≥ 0 (B = 0:
            // g(t) = A t² + C grows at once), or too slow inwards to get back (disc < 0).
            Side::Interior => (
                (-b + sqrt) / two_a,
                c.ge(zero) & (b.ge(zero) | disc.lt(zero)),
                b.gt(zero),
            ),
        };
        let real = disc.ge(zero);
        let ahead = moving & real & root.gt(zero);
        let deeper = deeper | (towards & real & root.le(zero));
        let t = L::select(ahead, root, zero);
        let hit = (ahead | (moving & deeper)) & t.le(t_max);
        (L::select(hit, t, L::splat(f32::INFINITY)), risk)
    }
}

impl Solver for Stable {
    const LITERAL: bool = false;

    #[inline(always)]
    fn arrival<L: Lanes, R: Relative<L>>(rel: &R, side: Side, t_max: L) -> (L, L) {
        let (a, b, c, q) = rel.stable();
        let risk = at_risk(a, c, rel.d2(), rel.v_bits());
        let zero = L::splat(0.0);
        let sqrt = rel.sqrt_q(q);
        let moving = a.gt(zero);
        let (t, hit) = match side {
            Side::Exterior => {
                // Only an approaching pair (b < 0) can arrive; then t1 = C / (−b + √q) adds
                // two positive terms. C ≤ 0 (touching or overlapping): t = 0.
                let touching = c.le(zero);
                let t = L::select(touching, zero, c / (sqrt - b));
                (t, moving & b.lt(zero) & (touching | q.ge(zero)))
            }
            Side::Interior => {
                // Inside (C ≤ 0) q = b² − AC is a sum of two non-negative terms: no
                // cancellation, where Lagrange's form subtracts.
                let q = b.mul_add(b, -(a * c));
                let sqrt = q.sqrt();
                // t2 = (−b + √q)/A if b ≤ 0, else C/(−b − √q): never a difference of
                // like-signed terms. Select numerator and denominator, then divide once.
                let outwards = b.gt(zero);
                let root = L::select(outwards, c, sqrt - b) / L::select(outwards, -b - sqrt, a);
                let ahead = moving & q.ge(zero) & root.gt(zero);
                // At or past the wall with no way back in: moving outwards or tangentially
                // (B = 0 with A > 0: g(t) = A t² + C grows at once), or inwards too slowly ever
                // to get back inside (q < 0). reference::quadratic::in_contact_now.
                let deeper = moving & c.ge(zero) & (b.ge(zero) | q.lt(zero));
                (L::select(ahead, root, zero), ahead | deeper)
            }
        };
        let t = L::select(hit & t.le(t_max), t, L::splat(f32::INFINITY));
        (t, risk)
    }
}
