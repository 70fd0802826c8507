//! The 8-wide kernels: `A`, `B`, `C`, the discriminant and the earliest admissible root for
//! eight pairs at once (`wide::f32x8`, or four in `f64x4` for [`Accuracy::Double`]).
//!
//! Each pair kind is one kernel generic over the lane type and the [`quadratic::Solver`] of
//! the accuracy mode; the batch drivers (`crate::batch`) pick the monomorphised kernel once
//! per call. The SIMD stays in this folder and in the lane layer; nothing here is public.
//! The scalar f64 reference (`crate::reference`) is the specification these kernels are
//! tested against; they do not import it.
//!
//! [`Accuracy::Double`]: crate::Accuracy::Double

pub(crate) mod quadratic;
pub(crate) mod sphere_container;
pub(crate) mod sphere_cylinder;
pub(crate) mod sphere_plane;
pub(crate) mod sphere_sphere;

use glam::DVec3;
use wide::f64x4;

use crate::lanes::Lanes;
use crate::shape::{Container, Cylinder, Plane};
use crate::store::SphereLanes;
use quadratic::{Solver, Stable};
use sphere_container::ContainerLanes;
use sphere_cylinder::CylinderLanes;
use sphere_plane::PlaneLanes;

/// A static shape kind's kernel: the shape prepared once per batch, and its time of impact
/// with the at-risk mask of the f32 range check.
pub trait StaticKernel: Sync {
    /// The shape splatted across lanes.
    type Lanes<L: Lanes>: Sync;
    /// Prepares the lanes.
    fn prepare<L: Lanes>(&self) -> Self::Lanes<L>;
    /// Times per lane and the mask of lanes outside the f32 safe range.
    fn raw<L: Lanes, S: Solver>(s: &SphereLanes<L>, k: &Self::Lanes<L>, t_max: L) -> (L, L);
    /// Whether a sphere swept inside the box `[lo, hi]` (f64, finite) could touch the shape:
    /// `false` only when none can, so a caller may skip the kernel.
    fn may_reach(&self, lo: DVec3, hi: DVec3) -> bool;
}

macro_rules! static_kernel {
    ($t:ident, $lanes:ident, $kernel:ident, $reach:ident) => {
        impl StaticKernel for $t {
            type Lanes<L: Lanes> = $lanes<L>;
            #[inline]
            fn prepare<L: Lanes>(&self) -> $lanes<L> {
                $lanes::splat(self)
            }
            #[inline(always)]
            fn raw<L: Lanes, S: Solver>(s: &SphereLanes<L>, k: &$lanes<L>, t: L) -> (L, L) {
                $kernel::time_of_impact::<L, S>(s, k, t)
            }
            fn may_reach(&self, lo: DVec3, hi: DVec3) -> bool {
                $reach(self, lo, hi)
            }
        }
    };
}
static_kernel!(Plane, PlaneLanes, sphere_plane, plane_may_reach);
static_kernel!(Cylinder, CylinderLanes, sphere_cylinder, cylinder_may_reach);
static_kernel!(
    Container,
    ContainerLanes,
    sphere_container,
    container_may_reach
);

/// The box's extent along the normal straddles the plane.
fn plane_may_reach(p: &Plane, lo: DVec3, hi: DVec3) -> bool {
    let n = crate::contact::unit_normal(p);
    let (centre, half) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
    (centre - p.point().as_dvec3()).dot(n).abs() <= half.dot(n.abs())
}

/// Some point of the box lies within the cylinder's radius of its axis.
fn cylinder_may_reach(c: &Cylinder, lo: DVec3, hi: DVec3) -> bool {
    let s = crate::contact::unit_axis(c);
    let (centre, half) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
    let x = centre - c.point().as_dvec3();
    (x - s * x.dot(s)).length() <= f64::from(c.radius()) + half.length()
}

/// The box's farthest corner from the centre reaches the wall.
fn container_may_reach(k: &Container, lo: DVec3, hi: DVec3) -> bool {
    let c = k.centre().as_dvec3();
    (lo - c).abs().max((hi - c).abs()).length() >= f64::from(k.radius())
}

/// Times of impact of sphere pairs per lane: the mode's kernel, with the lanes outside the
/// f32 safe range answered again in f64 (never silently wrong at any scale). `reload` gives
/// the same lanes again from memory, only on that rare path, so the hot loop keeps them in
/// registers.
#[inline(always)]
pub fn sphere_pair<L: Lanes, S: Solver>(
    a: &SphereLanes<L>,
    b: &SphereLanes<L>,
    t_max: L,
    reload: impl FnOnce() -> [SphereLanes<L>; 2],
) -> L {
    let (t, risk) = sphere_sphere::time_of_impact::<L, S>(a, b, t_max);
    if risk.any() {
        let [a, b] = reload();
        L::select(risk, rescue_pair(&a, &b, t_max), t)
    } else {
        t
    }
}

/// Times of impact with a static shape per lane, with the same f64 rescue as
/// [`sphere_pair`]; `shape` is the shape the lanes were prepared from.
#[inline(always)]
pub fn against_static<L: Lanes, S: Solver, K: StaticKernel>(
    s: &SphereLanes<L>,
    prepared: &K::Lanes<L>,
    shape: &K,
    t_max: L,
    reload: impl FnOnce() -> SphereLanes<L>,
) -> L {
    let (t, risk) = K::raw::<L, S>(s, prepared, t_max);
    if risk.any() {
        L::select(risk, rescue_static(&reload(), shape, t_max), t)
    } else {
        t
    }
}

/// The `double` answer (`Stable` on f64 lanes) for a whole lane group of sphere pairs.
#[cold]
#[inline(never)]
fn rescue_pair<L: Lanes>(a: &SphereLanes<L>, b: &SphereLanes<L>, t_max: L) -> L {
    let (a, b, t) = (a.halves(), b.halves(), t_max.halves());
    L::from_halves(
        [0, 1].map(|h| sphere_sphere::time_of_impact::<f64x4, Stable>(&a[h], &b[h], t[h]).0),
    )
}

/// The `double` answer for a whole lane group against a static shape.
#[cold]
#[inline(never)]
fn rescue_static<L: Lanes, K: StaticKernel>(s: &SphereLanes<L>, shape: &K, t_max: L) -> L {
    let (s, t, k) = (s.halves(), t_max.halves(), shape.prepare::<f64x4>());
    L::from_halves([0, 1].map(|h| K::raw::<f64x4, Stable>(&s[h], &k, t[h]).0))
}
