//! One sphere and the body it may touch, answered by the reference; with the seed's relative
//! quantities in f64 and the scales the rounding-error models of the tests and the accuracy
//! study are written in (docs/derivations/accuracy.md).

use glam::{DVec3, Vec3};

use super::{Side, sphere_container, sphere_cylinder, sphere_plane, sphere_sphere};
use crate::{Accuracy, Shape, Sphere};

/// A moving sphere ("A") and the body it may touch.
///
/// ```
/// use spheresweep::{Cylinder, Sphere, reference::Pair};
/// let pair = Pair {
///     sphere: Sphere::new([6.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 1.0, 1.0)?,
///     other: Cylinder::new([0.0; 3], [0.0, 0.0, 1.0], 1.0)?.into(),
/// };
/// assert_eq!(pair.time_of_impact(10.0), Some(4.0));
/// assert_eq!(spheresweep::time_of_impact(&pair.sphere, &pair.other, Default::default()), Some(4.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pair {
    /// The moving sphere.
    pub sphere: Sphere,
    /// What it may touch.
    pub other: Shape,
}

impl Pair {
    /// The reference's time of impact in `[0, t_max]`.
    ///
    /// ```
    /// use spheresweep::{Plane, Sphere, reference::Pair};
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0)?,
    ///     other: Plane::new([0.0; 3], [0.0, 0.0, 1.0])?.into(),
    /// };
    /// assert_eq!(pair.time_of_impact(10.0), Some(2.0));
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn time_of_impact(&self, t_max: f64) -> Option<f64> {
        let s = &self.sphere;
        match &self.other {
            Shape::Sphere(b) => sphere_sphere::time_of_impact(s, b, t_max),
            Shape::Plane(p) => sphere_plane::time_of_impact(s, p, t_max),
            Shape::Cylinder(c) => sphere_cylinder::time_of_impact(s, c, t_max),
            Shape::Container(k) => sphere_container::time_of_impact(s, k, t_max),
        }
    }

    /// `(r0, v, D, side)` of the seed's quadratic in f64 (a plane's embedded along x).
    ///
    /// ```
    /// use glam::DVec3;
    /// use spheresweep::{Plane, Side, Sphere, reference::Pair};
    /// let pair = Pair {
    ///     sphere: Sphere::new([6.0, 0.0, 3.0], [-1.0, 0.0, 0.5], 1.0, 1.0)?,
    ///     other: Plane::new([0.0; 3], [0.0, 0.0, 1.0])?.into(),
    /// };
    /// // Height 3 above the plane, rising at 0.5, D = R_A = 1.
    /// let (r0, v) = (DVec3::new(3.0, 0.0, 0.0), DVec3::new(0.5, 0.0, 0.0));
    /// assert_eq!(pair.relative(), (r0, v, 1.0, Side::Exterior));
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn relative(&self) -> (DVec3, DVec3, f64, Side) {
        let s = &self.sphere;
        let (c, v, r) = (
            s.centre().as_dvec3(),
            s.velocity().as_dvec3(),
            f64::from(s.radius()),
        );
        match &self.other {
            Shape::Sphere(b) => (
                b.centre().as_dvec3() - c,
                b.velocity().as_dvec3() - v,
                r + f64::from(b.radius()),
                Side::Exterior,
            ),
            Shape::Container(k) => (
                c - k.centre().as_dvec3(),
                v,
                f64::from(k.radius()) - r,
                Side::Interior,
            ),
            Shape::Plane(p) => {
                let n = p.normal().as_dvec3();
                let r0 = (c - p.point().as_dvec3()).dot(n);
                (DVec3::X * r0, DVec3::X * v.dot(n), r, Side::Exterior)
            }
            Shape::Cylinder(cy) => {
                let s_ = cy.axis().as_dvec3().normalize();
                let perp = |w: DVec3| w - s_ * w.dot(s_);
                let d = r + f64::from(cy.radius());
                (perp(c - cy.point().as_dvec3()), perp(v), d, Side::Exterior)
            }
        }
    }

    /// `X`: the size of the position-like operands `mode`'s kernel subtracts (its absolute
    /// rounding scale; see docs/derivations/accuracy.md). `stable` measures a plane's or a
    /// cylinder's `r0` with compensated dot products: its rounding scale is `|r0|` plus a
    /// second-order `2⁻²⁰(|c| + |r_P0|)` ("Compensated offsets").
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // A at rest at (3, 4, 0); B from the origin up z at speed 12.
    /// let pair = Pair {
    ///     sphere: Sphere::new([3.0, 4.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([0.0; 3], [0.0, 0.0, 12.0], 1.0, 1.0)?.into(),
    /// };
    /// assert_eq!(pair.operand_scale(spheresweep::Accuracy::Stable), 5.0); // ‖r_B0 − r_A0‖
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn operand_scale(&self, mode: Accuracy) -> f64 {
        let c = self.sphere.centre().as_dvec3();
        let compensated = |point: DVec3| {
            let (r0, ..) = self.relative();
            r0.length() + (c.length() + point.length()) * 2f64.powi(-20)
        };
        match &self.other {
            Shape::Sphere(b) => (b.centre().as_dvec3() - c).length(),
            Shape::Container(k) => (c - k.centre().as_dvec3()).length(),
            Shape::Plane(p) if mode == Accuracy::Stable => compensated(p.point().as_dvec3()),
            Shape::Cylinder(cy) if mode == Accuracy::Stable => compensated(cy.point().as_dvec3()),
            Shape::Plane(p) => (c - p.point().as_dvec3()).length(),
            Shape::Cylinder(cy) => (c - cy.point().as_dvec3()).length(),
        }
    }

    /// The largest coordinate magnitude of the bodies' positions at `t = 0` and at time `t`:
    /// the scale of the scene's own f32 rounding. A plane or a cylinder is placed by its foot
    /// (its point nearest the origin), not by the arbitrary point it was given.
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // A at rest at (3, 4, 0); B from the origin up z at speed 12.
    /// let pair = Pair {
    ///     sphere: Sphere::new([3.0, 4.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([0.0; 3], [0.0, 0.0, 12.0], 1.0, 1.0)?.into(),
    /// };
    /// assert_eq!(pair.coordinate_scale(0.0), 5.0); // A's ‖(3, 4, 0)‖
    /// assert_eq!(pair.coordinate_scale(1.0), 12.0); // B at (0, 0, 12)
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn coordinate_scale(&self, t: f64) -> f64 {
        let s = &self.sphere;
        let at = |c: Vec3, v: Vec3| (c.as_dvec3() + v.as_dvec3() * t).length();
        let own = s
            .centre()
            .as_dvec3()
            .length()
            .max(at(s.centre(), s.velocity()));
        let other = match &self.other {
            Shape::Sphere(b) => b
                .centre()
                .as_dvec3()
                .length()
                .max(at(b.centre(), b.velocity())),
            Shape::Plane(p) => {
                let n = p.normal().as_dvec3().normalize();
                p.point().as_dvec3().dot(n).abs()
            }
            Shape::Cylinder(c) => {
                let (s_, point) = (c.axis().as_dvec3().normalize(), c.point().as_dvec3());
                (point - s_ * point.dot(s_)).length()
            }
            Shape::Container(k) => k.centre().as_dvec3().length() + f64::from(k.radius()),
        };
        own.max(other)
    }

    /// Full relative speed (sphere pairs) or the sphere's speed (static shapes).
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // A at rest at (3, 4, 0); B from the origin up z at speed 12.
    /// let pair = Pair {
    ///     sphere: Sphere::new([3.0, 4.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([0.0; 3], [0.0, 0.0, 12.0], 1.0, 1.0)?.into(),
    /// };
    /// assert_eq!(pair.speed(), 12.0);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn speed(&self) -> f64 {
        let v = self.sphere.velocity().as_dvec3();
        match &self.other {
            Shape::Sphere(b) => (b.velocity().as_dvec3() - v).length(),
            _ => v.length(),
        }
    }
}
