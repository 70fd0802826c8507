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
}

macro_rules! static_kernel {
    ($t:ident, $lanes:ident, $kernel:ident) => {
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
        }
    };
}
static_kernel!(Plane, PlaneLanes, sphere_plane);
static_kernel!(Cylinder, CylinderLanes, sphere_cylinder);
static_kernel!(Container, ContainerLanes, sphere_container);

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
