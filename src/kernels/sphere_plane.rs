//! Sphere–plane: `R0 = (r_A0 − r_P0)·n̂_P`, `v = v_A·n̂_P`, `D = R_A`.
//!
//! `Stable` in f32 measures `R0 = r_A0·n̂ − r_P0·n̂` with the plane's offset `r_P0·n̂` and its
//! normal each carried as two f32 (hi + lo) and a compensated dot product: `R0` comes out
//! nearly correctly rounded wherever the sphere, the plane's point and the origin are
//! (docs/derivations/accuracy.md, "Compensated offsets"). `Textbook` is the literal formula;
//! f64 lanes subtract exactly.

use glam::DVec3;

use super::falling::Poly;
use super::quadratic::{Relative1, Solver};

use crate::Plane;
use crate::contact::Side;
use crate::lanes::{Lanes, V3, dot, dot_fused, dot_minus_compensated, sub};
use crate::store::SphereLanes;

/// One plane in every lane: its point as given, its unit normal (normalised in f64) as the
/// lane rounding `n` plus the rest `n_lo`, and the offset `r_P0·n̂` (f64) as `off + off_lo`.
#[derive(Debug, Clone, Copy)]
pub struct PlaneLanes<L> {
    /// `r_P0` as given.
    pub point: V3<L>,
    /// Unit normal, rounded to the lane precision.
    pub n: V3<L>,
    /// `n̂ − n`, rounded.
    pub n_lo: V3<L>,
    /// `r_P0·n̂`, rounded.
    pub off: L,
    /// `r_P0·n̂ − off`, rounded.
    pub off_lo: L,
}

/// `x` as a lane rounding and the rounded rest.
#[inline]
pub(crate) fn split<L: Lanes>(x: f64) -> (L, L) {
    let hi = x as f32;
    (L::splat64(x), L::splat64(x - f64::from(hi)))
}

impl<L: Lanes> PlaneLanes<L> {
    /// The plane in every lane.
    #[inline]
    pub fn splat(p: &Plane) -> Self {
        let point = p.point();
        let n = crate::contact::unit_normal(p);
        let (nx, ny, nz) = (split::<L>(n.x), split::<L>(n.y), split::<L>(n.z));
        let (off, off_lo) = split::<L>(point.as_dvec3().dot(n));
        Self {
            point: [L::splat(point.x), L::splat(point.y), L::splat(point.z)],
            n: [nx.0, ny.0, nz.0],
            n_lo: [nx.1, ny.1, nz.1],
            off,
            off_lo,
        }
    }
}

/// Earliest contact time per lane with the plane (either side), `+∞` for none; and the mask
/// of lanes outside the f32 kernels' safe range.
#[inline(always)]
pub fn time_of_impact<L: Lanes, S: Solver>(
    s: &SphereLanes<L>,
    p: &PlaneLanes<L>,
    t_max: L,
) -> (L, L) {
    let rel = if S::LITERAL {
        Relative1 {
            r0: dot(sub(s.c, p.point), p.n),
            v: dot(s.v, p.n),
            d: s.r,
        }
    } else if L::EXACT_DIFFERENCES {
        Relative1 {
            r0: dot_fused(sub(s.c, p.point), p.n),
            v: dot_fused(s.v, p.n),
            d: s.r,
        }
    } else {
        Relative1 {
            r0: dot_minus_compensated(s.c, p.n, p.n_lo, p.off, p.off_lo),
            v: dot_fused(s.v, p.n),
            d: s.r,
        }
    };
    S::arrival(&rel, Side::Exterior, t_max)
}

/// The plane's unit normal on the side of the centre `r` and the gap between a sphere of
/// `radius` there and the plane (negative when it cuts through): `|(r − r_P)·n̂| − R`.
#[inline]
pub(crate) fn normal_gap(p: &Plane, r: DVec3, radius: f64) -> (DVec3, f64) {
    let n = crate::contact::unit_normal(p);
    let d = (r - p.point().as_dvec3()).dot(n);
    (n * d.signum(), d.abs() - radius)
}

/// The side of the plane the centre `r` is on (`true`: the side its normal points to).
#[inline]
pub(crate) fn side(p: &Plane, r: DVec3) -> bool {
    (r - p.point().as_dvec3()).dot(crate::contact::unit_normal(p)) >= 0.0
}

/// The gap of a sphere at `r` that must stay on side `side`: `±(r − r_P)·n̂ − R`, so a
/// centre across the plane counts the whole way back.
#[inline]
pub(crate) fn gap_on_side(p: &Plane, r: DVec3, radius: f64, side: bool) -> f64 {
    let d = (r - p.point().as_dvec3()).dot(crate::contact::unit_normal(p));
    (if side { d } else { -d }) - radius
}

/// The least gap over the straight path from `r` to `end` of a sphere on its starting side:
/// the distance is linear along the path, so the least is at an end.
#[cfg(test)]
pub(crate) fn least_gap_on_path(p: &Plane, r: DVec3, end: DVec3, radius: f64) -> f64 {
    let side = side(p, r);
    gap_on_side(p, r, radius, side).min(gap_on_side(p, end, radius, side))
}

/// Under a uniform acceleration `g` (`h = g/2`), the polynomial whose rise through zero is the
/// contact of a sphere at `r` moving at `v` with the plane from the centre's side: minus the
/// gap, `R − s·n̂·(x + v t + h t²)` with `x = r − r_P` and `s = ±1` the side — a quadratic
/// (docs/derivations/gravity.md).
#[inline]
pub(crate) fn falling_polynomial(p: &Plane, r: DVec3, v: DVec3, h: DVec3, radius: f64) -> Poly {
    let n = crate::contact::unit_normal(p);
    let d = (r - p.point().as_dvec3()).dot(n);
    let s = if d >= 0.0 { 1.0 } else { -1.0 };
    [radius - d.abs(), -s * v.dot(n), -s * h.dot(n), 0.0, 0.0]
}
