//! Sphere–cylinder: `r0 = ŝ × (r_A0 − r_C1) × ŝ`, `v = ŝ × v_A × ŝ`, `D = R_A + R_C`.
//!
//! `Stable` in f32 works in the plane perpendicular to the axis: two unit vectors `ê₁`, `ê₂`
//! with `ŝ` (from f64) give `r0 = (r_A0·ê_k − r_C1·ê_k)ₖ`, each a compensated dot product with
//! hi + lo frame and offsets, as for planes (docs/derivations/accuracy.md, "Compensated
//! offsets"). `Textbook` is the literal double cross product; f64 lanes subtract exactly.

use glam::DVec3;

use super::falling::Poly;
use super::quadratic::{Relative2, Relative3, Solver};
use super::sphere_plane::split;
use crate::Cylinder;
use crate::contact::Side;
use crate::lanes::{Lanes, V3, cross, dot_fused, dot_minus_compensated, reject_fused, sub};
use crate::store::SphereLanes;

/// One perpendicular direction of a cylinder's frame, hi + lo, with the axis point's offset
/// along it.
#[derive(Debug, Clone, Copy)]
pub struct FrameAxis<L> {
    /// `ê`, rounded to the lane precision.
    pub e: V3<L>,
    /// `ê − e`, rounded.
    pub e_lo: V3<L>,
    /// `r_C1·ê`, rounded.
    pub off: L,
    /// `r_C1·ê − off`, rounded.
    pub off_lo: L,
}

impl<L: Lanes> FrameAxis<L> {
    fn new(e: DVec3, point: DVec3) -> Self {
        let (x, y, z) = (split::<L>(e.x), split::<L>(e.y), split::<L>(e.z));
        let (off, off_lo) = split::<L>(point.dot(e));
        Self {
            e: [x.0, y.0, z.0],
            e_lo: [x.1, y.1, z.1],
            off,
            off_lo,
        }
    }
}

/// One cylinder in every lane: its anchor as given, its unit axis (normalised in f64 and
/// rounded to the lane precision), the perpendicular frame, and its radius.
#[derive(Debug, Clone, Copy)]
pub struct CylinderLanes<L> {
    /// `r_C1` as given.
    pub point: V3<L>,
    /// `ŝ`.
    pub s: V3<L>,
    /// `ê₁ ⟂ ŝ`.
    pub e1: FrameAxis<L>,
    /// `ê₂ = ŝ × ê₁`.
    pub e2: FrameAxis<L>,
    /// `R_C`.
    pub r: L,
}

impl<L: Lanes> CylinderLanes<L> {
    /// The cylinder in every lane.
    #[inline]
    pub fn splat(c: &Cylinder) -> Self {
        let point = c.point();
        let s = crate::contact::unit_axis(c);
        // ê₁ from the coordinate axis least aligned with ŝ: well away from parallel.
        let helper = if s.x.abs() <= s.y.abs() && s.x.abs() <= s.z.abs() {
            DVec3::X
        } else if s.y.abs() <= s.z.abs() {
            DVec3::Y
        } else {
            DVec3::Z
        };
        let e1 = s.cross(helper).normalize();
        let e2 = s.cross(e1);
        let p = point.as_dvec3();
        Self {
            point: [L::splat(point.x), L::splat(point.y), L::splat(point.z)],
            s: [L::splat64(s.x), L::splat64(s.y), L::splat64(s.z)],
            e1: FrameAxis::new(e1, p),
            e2: FrameAxis::new(e2, p),
            r: L::splat(c.radius()),
        }
    }
}

/// Earliest contact time per lane with the cylinder, `+∞` for none; and the mask of lanes
/// outside the f32 kernels' safe range.
#[inline(always)]
pub fn time_of_impact<L: Lanes, S: Solver>(
    a: &SphereLanes<L>,
    cyl: &CylinderLanes<L>,
    t_max: L,
) -> (L, L) {
    let d = a.r + cyl.r;
    let s = cyl.s;
    if S::LITERAL || L::EXACT_DIFFERENCES {
        let x = sub(a.c, cyl.point);
        let rel = if S::LITERAL {
            Relative3 {
                r0: cross(cross(s, x), s),
                v: cross(cross(s, a.v), s),
                d,
            }
        } else {
            Relative3 {
                r0: reject_fused(x, s),
                v: reject_fused(a.v, s),
                d,
            }
        };
        S::arrival(&rel, Side::Exterior, t_max)
    } else {
        let (e1, e2) = (&cyl.e1, &cyl.e2);
        let rel = Relative2 {
            r0: [
                dot_minus_compensated(a.c, e1.e, e1.e_lo, e1.off, e1.off_lo),
                dot_minus_compensated(a.c, e2.e, e2.e_lo, e2.off, e2.off_lo),
            ],
            // v's perpendicular part first, against the lane axis: its rounding error lies
            // along ŝ, which the frame (⟂ ŝ to u) sees only at second order.
            v: {
                let v_perp = reject_fused(a.v, s);
                [dot_fused(v_perp, e1.e), dot_fused(v_perp, e2.e)]
            },
            d,
        };
        S::arrival(&rel, Side::Exterior, t_max)
    }
}

/// The unit direction from the cylinder's axis to the centre `r` and the gap between a sphere
/// of `radius` there and the cylinder's surface: `|x − ŝ(x·ŝ)| − R − R_C`.
#[inline]
pub(crate) fn normal_gap(c: &Cylinder, r: DVec3, radius: f64) -> (DVec3, f64) {
    let s = crate::contact::unit_axis(c);
    let x = r - c.point().as_dvec3();
    let radial = x - s * x.dot(s);
    let d = radial.length();
    (radial / d, d - radius - f64::from(c.radius()))
}

/// The least gap over the straight path `r + v t`, `t ∈ [0, horizon]` (`horizon` may be
/// `∞`): the closest approach of the paths projected on the plane across the axis.
#[cfg(test)]
pub(crate) fn least_gap_on_path(
    c: &Cylinder,
    r: DVec3,
    v: DVec3,
    horizon: f64,
    radius: f64,
) -> f64 {
    let s = crate::contact::unit_axis(c);
    let perp = |u: DVec3| u - s * u.dot(s);
    let (x, w) = (perp(r - c.point().as_dvec3()), perp(v));
    let a = w.length_squared();
    let t = if a > 0.0 {
        (-x.dot(w) / a).clamp(0.0, horizon)
    } else {
        0.0
    };
    (x + w * t).length() - radius - f64::from(c.radius())
}

/// Under a uniform acceleration (`h = g/2`), the polynomial whose rise through zero is the
/// contact of a sphere at `r` moving at `v` with the cylinder from outside:
/// `L² − ‖x⊥ + v⊥ t + h⊥ t²‖²` with `L = R_C + R` and `⊥` the part across the axis — a quartic,
/// a quadratic when `g` is along the axis (docs/derivations/gravity.md).
#[inline]
pub(crate) fn falling_polynomial(c: &Cylinder, r: DVec3, v: DVec3, h: DVec3, radius: f64) -> Poly {
    let s = crate::contact::unit_axis(c);
    let perp = |u: DVec3| u - s * u.dot(s);
    let (x, w, k) = (perp(r - c.point().as_dvec3()), perp(v), perp(h));
    let reach = f64::from(c.radius()) + radius;
    let q = x.length();
    // ‖x⊥(t)‖² − L², its constant term without cancellation; then negated.
    let f = [
        (q - reach) * (q + reach),
        2.0 * x.dot(w),
        w.length_squared() + 2.0 * x.dot(k),
        2.0 * w.dot(k),
        k.length_squared(),
    ];
    f.map(|a| -a)
}
