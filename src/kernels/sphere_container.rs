//! Spheres inside a container: `r0 = r_sphere0 − r_container`, `v = v_sphere`,
//! `D = R_container − R_sphere`, the larger root.

use glam::DVec3;

use super::falling::Poly;
use super::quadratic::{Relative3, Solver};
use crate::Container;
use crate::contact::Side;
use crate::lanes::{Lanes, V3, sub};
use crate::store::SphereLanes;

/// One container in every lane.
#[derive(Debug, Clone, Copy)]
pub struct ContainerLanes<L> {
    /// Centre.
    pub c: V3<L>,
    /// Inner radius.
    pub r: L,
}

impl<L: Lanes> ContainerLanes<L> {
    /// The container in every lane.
    #[inline]
    pub fn splat(k: &Container) -> Self {
        let c = k.centre();
        Self {
            c: [L::splat(c.x), L::splat(c.y), L::splat(c.z)],
            r: L::splat(k.radius()),
        }
    }
}

/// Earliest time per lane at which the sphere reaches the wall, `+∞` for none; and the mask
/// of lanes outside the f32 kernels' safe range. A sphere larger than the container touches
/// it at `t = 0`.
#[inline(always)]
pub fn time_of_impact<L: Lanes, S: Solver>(
    s: &SphereLanes<L>,
    k: &ContainerLanes<L>,
    t_max: L,
) -> (L, L) {
    let d = k.r - s.r;
    let rel = Relative3 {
        r0: sub(s.c, k.c),
        v: s.v,
        d,
    };
    let (t, risk) = S::arrival(&rel, Side::Interior, t_max);
    let zero = L::splat(0.0);
    let larger = d.lt(zero);
    // A sphere larger than its vessel is answered at once in either precision.
    let t = L::select(larger & zero.le(t_max), zero, t);
    (t, L::select(larger, zero, risk))
}

/// The unit normal of the wall towards the centre `r` (inwards) and the gap between a sphere
/// of `radius` there and the wall: `R_K − R − |r − c_K|` (negative past the wall).
#[inline]
pub(crate) fn normal_gap(k: &Container, r: DVec3, radius: f64) -> (DVec3, f64) {
    let x = r - k.centre().as_dvec3();
    let d = x.length();
    (-x / d, f64::from(k.radius()) - radius - d)
}

/// The least gap over the straight path from `r` to `end`: the distance from the centre is
/// convex along a line, so the farthest point is at an end.
#[cfg(test)]
pub(crate) fn least_gap_on_path(k: &Container, r: DVec3, end: DVec3, radius: f64) -> f64 {
    normal_gap(k, r, radius).1.min(normal_gap(k, end, radius).1)
}

/// Under a uniform acceleration (`h = g/2`), the polynomial whose rise through zero is the
/// contact of a sphere at `r` moving at `v` with the wall from inside:
/// `‖x + v t + h t²‖² − D²` with `x = r − c_K` and `D = R_K − R` — a quartic
/// (docs/derivations/gravity.md).
#[inline]
pub(crate) fn falling_polynomial(k: &Container, r: DVec3, v: DVec3, h: DVec3, radius: f64) -> Poly {
    let x = r - k.centre().as_dvec3();
    let d = f64::from(k.radius()) - radius;
    let q = x.length();
    [
        (q - d) * (q + d),
        2.0 * x.dot(v),
        v.length_squared() + 2.0 * x.dot(h),
        2.0 * v.dot(h),
        h.length_squared(),
    ]
}
