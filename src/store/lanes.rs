//! A store's spheres as the kernels read them: one lane group, loaded from a block.

use super::SphereBlock;
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
}
