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

pub(crate) mod falling;
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

/// A static shape kind's kernel and its f64 geometry: the shape prepared once per batch, its
/// time of impact with the at-risk mask of the f32 range check, and the gap functions the
/// simulation and scene assembly use (each kind's own, in its kernel file).
pub trait StaticKernel: Sync {
    /// The shape splatted across lanes.
    type Lanes<L: Lanes>: Sync + Send + Copy;
    /// Prepares the lanes.
    fn prepare<L: Lanes>(&self) -> Self::Lanes<L>;
    /// Times per lane and the mask of lanes outside the f32 safe range.
    fn raw<L: Lanes, S: Solver>(s: &SphereLanes<L>, k: &Self::Lanes<L>, t_max: L) -> (L, L);
    /// Whether a sphere swept inside the box `[lo, hi]` (f64, finite) could touch the shape:
    /// `false` only when none can, so a caller may skip the kernel.
    fn may_reach(&self, lo: DVec3, hi: DVec3) -> bool;
    /// Whether the shape, alone, is what spheres in the periodic box `[0, size)` meet, with
    /// no periodic image of it within `margin` of where they can be: a plane or a cylinder
    /// along a box axis, at least `margin` from the faces it crosses; a container inside the
    /// box. The engine keeps no images of shapes (docs/derivations/simulation.md, "Shapes in
    /// a periodic box").
    fn fits_periodic_box(&self, size: DVec3, margin: f64) -> bool;
    /// The unit normal from the shape towards a sphere centred at `r` and the signed gap
    /// between the sphere and the shape (negative when it is through).
    fn normal_gap(&self, r: DVec3, radius: f64) -> (DVec3, f64);
    /// Which side of the shape `r` is on, for a shape a sphere may be on either side of (a
    /// plane); `true` for the others.
    fn side(&self, r: DVec3) -> bool {
        let _ = r;
        true
    }
    /// The gap of a sphere at `r` that must stay on `side` ([`StaticKernel::side`]).
    fn gap_on_side(&self, r: DVec3, radius: f64, side: bool) -> f64 {
        let _ = side;
        self.normal_gap(r, radius).1
    }
    /// Under a uniform acceleration (`h = g/2`): the polynomial of degree at most four whose
    /// earliest rise through zero ([`falling::earliest_rise`]) is the contact of a sphere at
    /// `r` moving at `v` (each kind's own, in its kernel file).
    fn falling_polynomial(&self, r: DVec3, v: DVec3, h: DVec3, radius: f64) -> falling::Poly;
    /// For a concave wall that keeps spheres inside (a container): its centre and radius.
    fn interior(&self) -> Option<(DVec3, f64)> {
        None
    }
    /// The least gap of a sphere moving from `r` at velocity `v` for `horizon` (may be `∞`),
    /// in closed form: the brute-force check after every event in the engine's tests.
    #[cfg(test)]
    fn least_gap_on_path(&self, r: DVec3, v: DVec3, horizon: f64, radius: f64) -> f64;
}

/// The f64 lanes a static shape is prepared in for the simulation's scalar settle.
pub(crate) type SettleLanes<K> = <K as StaticKernel>::Lanes<f64x4>;

/// The earliest admissible time of a sphere (centre `r`, velocity `v`, `radius`) with the
/// prepared shape, in f64 (the `Stable` kernel on `f64x4`, one lane used).
#[inline]
pub(crate) fn settle_static<K: StaticKernel>(s: &SettleSphere, prepared: &SettleLanes<K>) -> f64 {
    K::raw::<f64x4, Stable>(s, prepared, f64x4::splat(f64::INFINITY))
        .0
        .to_array()[0]
}

/// One sphere in the f64 lanes of the simulation's settle.
pub(crate) type SettleSphere = SphereLanes<f64x4>;

/// One sphere in every f64 lane.
#[inline]
pub(crate) fn sphere_settle_lanes(r: DVec3, v: DVec3, radius: f64) -> SettleSphere {
    SphereLanes {
        c: [r.x, r.y, r.z].map(f64x4::splat),
        v: [v.x, v.y, v.z].map(f64x4::splat),
        r: f64x4::splat(radius),
    }
}

macro_rules! static_kernel {
    ($t:ident, $lanes:ident, $kernel:ident, $reach:ident, $fits:ident { $($extra:item)* }) => {
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
            fn fits_periodic_box(&self, size: DVec3, margin: f64) -> bool {
                $fits(self, size, margin)
            }
            #[inline]
            fn normal_gap(&self, r: DVec3, radius: f64) -> (DVec3, f64) {
                $kernel::normal_gap(self, r, radius)
            }
            #[inline]
            fn falling_polynomial(
                &self,
                r: DVec3,
                v: DVec3,
                h: DVec3,
                radius: f64,
            ) -> falling::Poly {
                $kernel::falling_polynomial(self, r, v, h, radius)
            }
            $($extra)*
        }
    };
}
static_kernel!(Plane, PlaneLanes, sphere_plane, plane_may_reach, plane_fits {
    fn side(&self, r: DVec3) -> bool {
        sphere_plane::side(self, r)
    }
    fn gap_on_side(&self, r: DVec3, radius: f64, side: bool) -> f64 {
        sphere_plane::gap_on_side(self, r, radius, side)
    }
    #[cfg(test)]
    fn least_gap_on_path(&self, r: DVec3, v: DVec3, horizon: f64, radius: f64) -> f64 {
        sphere_plane::least_gap_on_path(self, r, far_end(r, v, horizon), radius)
    }
});
static_kernel!(Cylinder, CylinderLanes, sphere_cylinder, cylinder_may_reach, cylinder_fits {
    #[cfg(test)]
    fn least_gap_on_path(&self, r: DVec3, v: DVec3, horizon: f64, radius: f64) -> f64 {
        sphere_cylinder::least_gap_on_path(self, r, v, horizon, radius)
    }
});
static_kernel!(Container, ContainerLanes, sphere_container, container_may_reach, container_fits {
    fn interior(&self) -> Option<(DVec3, f64)> {
        Some((self.centre().as_dvec3(), f64::from(self.radius())))
    }
    #[cfg(test)]
    fn least_gap_on_path(&self, r: DVec3, v: DVec3, horizon: f64, radius: f64) -> f64 {
        sphere_container::least_gap_on_path(self, r, far_end(r, v, horizon), radius)
    }
});

/// Where a path from `r` at `v` ends after `horizon`, a long way out for an endless one.
#[cfg(test)]
fn far_end(r: DVec3, v: DVec3, horizon: f64) -> DVec3 {
    if horizon.is_finite() {
        r + v * horizon
    } else {
        r + v * 1e12
    }
}

/// The axis `d` runs along, if it is a box axis (its other two components exactly zero).
fn box_axis(d: DVec3) -> Option<usize> {
    let along = [d.x, d.y, d.z].map(|x| x != 0.0);
    (along.iter().filter(|&&a| a).count() == 1).then(|| along.iter().position(|&a| a))?
}

/// `x` within `[lo, size − lo]`.
fn within(x: f64, lo: f64, size: f64) -> bool {
    lo <= x && x <= size - lo
}

/// A plane across a box axis, at least `margin` from the two faces across that axis: a sphere
/// that wraps past them meets the plane itself, not an image of it.
fn plane_fits(p: &Plane, size: DVec3, margin: f64) -> bool {
    box_axis(p.normal().as_dvec3())
        .is_some_and(|k| within(f64::from(p.point()[k]), margin, size[k]))
}

/// A cylinder along a box axis, its surface at least `margin` from the faces across it.
fn cylinder_fits(c: &Cylinder, size: DVec3, margin: f64) -> bool {
    let (q, r) = (c.point().as_dvec3(), f64::from(c.radius()));
    box_axis(c.axis().as_dvec3()).is_some_and(|k| {
        (0..3)
            .filter(|&j| j != k)
            .all(|j| within(q[j], r + margin, size[j]))
    })
}

/// A container inside the box: the spheres it holds never reach a face.
fn container_fits(c: &Container, size: DVec3, _margin: f64) -> bool {
    let (q, r) = (c.centre().as_dvec3(), f64::from(c.radius()));
    (0..3).all(|k| within(q[k], r, size[k]))
}

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
