//! Sphere–plane: `R0 = (r_A0 − r_P0)·n̂_P`, `v = v_A·n̂_P`, `D = R_A`.

use super::quadratic::{Relative1, Solver};
use crate::Plane;
use crate::contact::Side;
use crate::lanes::{Lanes, V3, dot, dot_fused, sub};
use crate::store::SphereLanes;

/// One plane in every lane, with its point as given and its foot (the plane's point nearest
/// the origin, computed in f64), which the f32 `Stable` mode uses instead of a far anchor.
/// The normal is normalised again in the lane precision (exactly unit in f64 lanes).
#[derive(Debug, Clone, Copy)]
pub struct PlaneLanes<L> {
    /// `r_P0` as given.
    pub point: V3<L>,
    /// `(r_P0·n̂) n̂`, the point of the plane nearest the origin.
    pub foot: V3<L>,
    /// Unit normal.
    pub n: V3<L>,
}

impl<L: Lanes> PlaneLanes<L> {
    /// The plane in every lane.
    #[inline]
    pub fn splat(p: &Plane) -> Self {
        let (point, n) = (p.point(), p.normal().as_dvec3().normalize());
        let foot = n * point.as_dvec3().dot(n);
        Self {
            point: [L::splat(point.x), L::splat(point.y), L::splat(point.z)],
            foot: [L::splat64(foot.x), L::splat64(foot.y), L::splat64(foot.z)],
            n: [L::splat64(n.x), L::splat64(n.y), L::splat64(n.z)],
        }
    }
}

/// Earliest contact time per lane with the plane (either side), `+∞` for none.
#[inline(always)]
pub fn time_of_impact<L: Lanes, S: Solver>(s: &SphereLanes<L>, p: &PlaneLanes<L>, t_max: L) -> L {
    let rel = if S::LITERAL {
        Relative1 {
            r0: dot(sub(s.c, p.point), p.n),
            v: dot(s.v, p.n),
            d: s.r,
        }
    } else {
        let anchor = if L::EXACT_DIFFERENCES {
            p.point
        } else {
            p.foot
        };
        Relative1 {
            r0: dot_fused(sub(s.c, anchor), p.n),
            v: dot_fused(s.v, p.n),
            d: s.r,
        }
    };
    S::arrival(&rel, Side::Exterior, t_max)
}
