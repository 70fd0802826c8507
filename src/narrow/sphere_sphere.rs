//! Sphere–sphere, eight (or four) pairs at once: `r0 = r_B0 − r_A0`, `v = v_B − v_A`,
//! `D = R_A + R_B`.

use super::lanes::{Lanes, V3, sub};
use super::quadratic::{Relative3, Solver};
use crate::Sphere;
use crate::reference::Side;

/// `WIDTH` spheres, one per lane.
#[derive(Debug, Clone, Copy)]
pub struct SphereLanes<L> {
    /// Centres at `t = 0`.
    pub c: V3<L>,
    /// Velocities.
    pub v: V3<L>,
    /// Radii.
    pub r: L,
}

impl<L: Lanes> SphereLanes<L> {
    /// One sphere in every lane.
    #[inline]
    pub fn splat(s: &Sphere) -> Self {
        let (c, v) = (s.centre(), s.velocity());
        Self {
            c: [L::splat(c.x), L::splat(c.y), L::splat(c.z)],
            v: [L::splat(v.x), L::splat(v.y), L::splat(v.z)],
            r: L::splat(s.radius()),
        }
    }
}

/// Earliest exterior contact time per lane in `[0, t_max]`, `+∞` for none.
#[inline(always)]
pub fn time_of_impact<L: Lanes, S: Solver>(a: &SphereLanes<L>, b: &SphereLanes<L>, t_max: L) -> L {
    let rel = Relative3 {
        r0: sub(b.c, a.c),
        v: sub(b.v, a.v),
        d: a.r + b.r,
    };
    S::arrival(&rel, Side::Exterior, t_max)
}
