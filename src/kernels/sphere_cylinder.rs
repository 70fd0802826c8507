//! Sphere–cylinder: `r0 = ŝ × (r_A0 − r_C1) × ŝ`, `v = ŝ × v_A × ŝ`, `D = R_A + R_C`.

use super::quadratic::{Relative3, Solver};
use crate::Cylinder;
use crate::contact::Side;
use crate::lanes::{Lanes, V3, cross, reject_fused, sub};
use crate::store::SphereLanes;

/// One cylinder in every lane: its anchor as given, its foot (the axis point nearest the
/// origin, computed in f64) and its unit axis, normalised again in the lane precision.
#[derive(Debug, Clone, Copy)]
pub struct CylinderLanes<L> {
    /// `r_C1` as given.
    pub point: V3<L>,
    /// `r_C1 − (r_C1·ŝ) ŝ`.
    pub foot: V3<L>,
    /// `ŝ`.
    pub s: V3<L>,
    /// `R_C`.
    pub r: L,
}

impl<L: Lanes> CylinderLanes<L> {
    /// The cylinder in every lane.
    #[inline]
    pub fn splat(c: &Cylinder) -> Self {
        let point = c.point();
        let s = c.axis().as_dvec3().normalize();
        let p = point.as_dvec3();
        let foot = p - s * p.dot(s);
        Self {
            point: [L::splat(point.x), L::splat(point.y), L::splat(point.z)],
            foot: [L::splat64(foot.x), L::splat64(foot.y), L::splat64(foot.z)],
            s: [L::splat64(s.x), L::splat64(s.y), L::splat64(s.z)],
            r: L::splat(c.radius()),
        }
    }
}

/// Earliest contact time per lane with the cylinder, `+∞` for none.
#[inline(always)]
pub fn time_of_impact<L: Lanes, S: Solver>(
    a: &SphereLanes<L>,
    cyl: &CylinderLanes<L>,
    t_max: L,
) -> L {
    let d = a.r + cyl.r;
    let s = cyl.s;
    let rel = if S::LITERAL {
        let x = sub(a.c, cyl.point);
        Relative3 {
            r0: cross(cross(s, x), s),
            v: cross(cross(s, a.v), s),
            d,
        }
    } else {
        let anchor = if L::EXACT_DIFFERENCES {
            cyl.point
        } else {
            cyl.foot
        };
        Relative3 {
            r0: reject_fused(sub(a.c, anchor), s),
            v: reject_fused(a.v, s),
            d,
        }
    };
    S::arrival(&rel, Side::Exterior, t_max)
}
