//! A store's spheres as the kernels read them: one lane group, loaded from a block.

use super::SphereBlock;
use wide::f64x4;

use crate::lanes::{Lanes, V3};
use crate::shape::Sphere;

/// `WIDTH` spheres, one per lane, as the kernels read them.
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

    #[inline(always)]
    pub(super) fn load(b: &SphereBlock, lane: usize) -> Self {
        Self {
            c: [
                L::load8(&b.cx, lane),
                L::load8(&b.cy, lane),
                L::load8(&b.cz, lane),
            ],
            v: [
                L::load8(&b.vx, lane),
                L::load8(&b.vy, lane),
                L::load8(&b.vz, lane),
            ],
            r: L::load8(&b.r, lane),
        }
    }

    /// The same spheres widened exactly to two groups of f64 lanes (for the f64 rescue of
    /// lanes outside the f32 safe range).
    #[inline]
    pub fn halves(&self) -> [SphereLanes<f64x4>; 2] {
        let [c0, c1, c2] = self.c.map(L::halves);
        let [v0, v1, v2] = self.v.map(L::halves);
        let r = self.r.halves();
        [0, 1].map(|h| SphereLanes {
            c: [c0[h], c1[h], c2[h]],
            v: [v0[h], v1[h], v2[h]],
            r: r[h],
        })
    }
}
