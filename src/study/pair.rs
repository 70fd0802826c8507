//! One pair of any kind, answered by every path: the f64 reference, the 8-wide kernels in each
//! mode, parry3d, and (in [`super::oracle`]) exact arithmetic.

use glam::{DVec3, Quat, Vec3};
use parry3d::math::{Pose, Vector};
use parry3d::query::{self, ShapeCastOptions};
use parry3d::shape::{Ball, Cylinder as ParryCylinder, HalfSpace};

use crate::narrow::{self, Query};
use crate::reference::{self, Side};
use crate::{Accuracy, Container, Cylinder, Plane, Sphere, SphereStore};

/// The other body of a pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Other {
    /// A second moving sphere (exterior contact).
    Sphere(Sphere),
    /// A static plane.
    Plane(Plane),
    /// A static infinite cylinder.
    Cylinder(Cylinder),
    /// The container the sphere is inside.
    Container(Container),
}

/// A moving sphere and the body it may touch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pair {
    /// The moving sphere ("A").
    pub sphere: Sphere,
    /// What it may touch.
    pub other: Other,
}

impl Pair {
    /// The f64 reference's time of impact in `[0, t_max]`.
    pub fn reference(&self, t_max: f64) -> Option<f64> {
        let s = &self.sphere;
        match &self.other {
            Other::Sphere(b) => reference::sphere_sphere::time_of_impact(s, b, t_max),
            Other::Plane(p) => reference::sphere_plane::time_of_impact(s, p, t_max),
            Other::Cylinder(c) => reference::sphere_cylinder::time_of_impact(s, c, t_max),
            Other::Container(k) => reference::sphere_container::time_of_impact(s, k, t_max),
        }
    }

    /// The 8-wide kernel's time of impact in `mode`, through the public batch API.
    ///
    /// # Panics
    /// If `t_max` is NaN or negative.
    pub fn kernel(&self, mode: Accuracy, t_max: f32) -> Option<f32> {
        kernel_times(std::slice::from_ref(self), mode, t_max)[0]
    }

    /// parry3d's time of impact (`query::cast_shapes`, stopping at penetration), or `None`
    /// when parry has no such shape (the inside of a container). A plane is parry's
    /// half-space; the infinite cylinder is a finite one centred on the axis point nearest the
    /// sphere, just long enough to cover the travel to the contact (its best case: parry's
    /// errors grow with the cylinder's length, docs/accuracy.md).
    pub fn parry(&self, t_max: f32) -> Option<Option<f32>> {
        let s = &self.sphere;
        let ball = Ball::new(s.radius());
        let pos = Pose::from_translation(s.centre());
        let options = ShapeCastOptions {
            max_time_of_impact: t_max,
            stop_at_penetration: true,
            ..Default::default()
        };
        let cast = |pose: &Pose, vel: Vector, shape: &dyn parry3d::shape::Shape| {
            query::cast_shapes(&pos, s.velocity(), &ball, pose, vel, shape, options)
                .ok()
                .flatten()
                .map(|hit| hit.time_of_impact)
        };
        match &self.other {
            Other::Sphere(b) => Some(cast(
                &Pose::from_translation(b.centre()),
                b.velocity(),
                &Ball::new(b.radius()),
            )),
            Other::Plane(p) => Some(cast(
                &Pose::from_translation(p.point()),
                Vector::ZERO,
                &HalfSpace::new(p.normal()),
            )),
            Other::Cylinder(c) => {
                let axis = c.axis().as_dvec3().normalize();
                let x = s.centre().as_dvec3() - c.point().as_dvec3();
                let centre = c.point().as_dvec3() + axis * x.dot(axis);
                let d = f64::from(s.radius() + c.radius()).max(1.0);
                // Just long enough to cover the travel along the axis up to the contact (from the
                // f64 reference): parry's GJK cast loses accuracy as the cylinder grows.
                let travel = s.velocity().as_dvec3().dot(axis).abs()
                    * self.reference(f64::INFINITY).unwrap_or(0.0);
                let long = ParryCylinder::new((10.0 * d + travel) as f32, c.radius());
                let rotation = Quat::from_rotation_arc(Vec3::Y, axis.as_vec3());
                let pose = Pose::from_parts(centre.as_vec3(), rotation);
                Some(cast(&pose, Vector::ZERO, &long))
            }
            Other::Container(_) => None,
        }
    }

    /// `(r0, v, D, side)` of the seed's quadratic in f64 (the plane's embedded along x).
    pub fn relative(&self) -> (DVec3, DVec3, f64, Side) {
        let s = &self.sphere;
        let (c, v, r) = (
            s.centre().as_dvec3(),
            s.velocity().as_dvec3(),
            f64::from(s.radius()),
        );
        match &self.other {
            Other::Sphere(b) => (
                b.centre().as_dvec3() - c,
                b.velocity().as_dvec3() - v,
                r + f64::from(b.radius()),
                Side::Exterior,
            ),
            Other::Container(k) => (
                c - k.centre().as_dvec3(),
                v,
                f64::from(k.radius()) - r,
                Side::Interior,
            ),
            Other::Plane(p) => {
                let n = p.normal().as_dvec3();
                let r0 = (c - p.point().as_dvec3()).dot(n);
                (DVec3::X * r0, DVec3::X * v.dot(n), r, Side::Exterior)
            }
            Other::Cylinder(cy) => {
                let s_ = cy.axis().as_dvec3().normalize();
                let perp = |w: DVec3| w - s_ * w.dot(s_);
                let d = r + f64::from(cy.radius());
                (perp(c - cy.point().as_dvec3()), perp(v), d, Side::Exterior)
            }
        }
    }

    /// `X`: the size of the position-like operands `mode`'s kernel subtracts (its absolute
    /// rounding scale; see docs/derivations/accuracy.md).
    pub fn operand_scale(&self, mode: Accuracy) -> f64 {
        let c = self.sphere.centre().as_dvec3();
        let moved = mode == Accuracy::Stable;
        match &self.other {
            Other::Sphere(b) => (b.centre().as_dvec3() - c).length(),
            Other::Container(k) => (c - k.centre().as_dvec3()).length(),
            Other::Plane(p) => {
                let (n, point) = (p.normal().as_dvec3(), p.point().as_dvec3());
                let foot = n * point.dot(n);
                if moved {
                    (c - foot).length() + foot.length()
                } else {
                    (c - point).length()
                }
            }
            Other::Cylinder(cy) => {
                let s_ = cy.axis().as_dvec3().normalize();
                let point = cy.point().as_dvec3();
                let foot = point - s_ * point.dot(s_);
                if moved {
                    (c - foot).length() + foot.length()
                } else {
                    (c - point).length()
                }
            }
        }
    }

    /// The largest coordinate magnitude of the bodies' positions at `t = 0` and at time `t`:
    /// the scale of the scene's own f32 rounding. A plane or a cylinder is placed by its foot
    /// (its point nearest the origin), not by the arbitrary point it was given.
    pub fn coordinate_scale(&self, t: f64) -> f64 {
        let s = &self.sphere;
        let at = |c: Vec3, v: Vec3| (c.as_dvec3() + v.as_dvec3() * t).length();
        let own = s
            .centre()
            .as_dvec3()
            .length()
            .max(at(s.centre(), s.velocity()));
        let other = match &self.other {
            Other::Sphere(b) => b
                .centre()
                .as_dvec3()
                .length()
                .max(at(b.centre(), b.velocity())),
            Other::Plane(p) => {
                let n = p.normal().as_dvec3().normalize();
                p.point().as_dvec3().dot(n).abs()
            }
            Other::Cylinder(c) => {
                let (s_, point) = (c.axis().as_dvec3().normalize(), c.point().as_dvec3());
                (point - s_ * point.dot(s_)).length()
            }
            Other::Container(k) => k.centre().as_dvec3().length() + f64::from(k.radius()),
        };
        own.max(other)
    }

    /// Full relative speed (sphere pairs) or the sphere's speed (static shapes).
    pub fn speed(&self) -> f64 {
        let v = self.sphere.velocity().as_dvec3();
        match &self.other {
            Other::Sphere(b) => (b.velocity().as_dvec3() - v).length(),
            _ => v.length(),
        }
    }
}

/// The kernels' answers for many pairs in `mode`: sphere pairs in one batch, each static
/// shape in its own call.
///
/// # Panics
/// If `t_max` is NaN or negative.
pub fn kernel_times(pairs: &[Pair], mode: Accuracy, t_max: f32) -> Vec<Option<f32>> {
    let q = Query::new(t_max, mode).expect("a valid window");
    let mut result = vec![None; pairs.len()];
    let (mut idx, mut a, mut b) = (Vec::new(), SphereStore::new(), SphereStore::new());
    for (i, pair) in pairs.iter().enumerate() {
        let one = || SphereStore::from_spheres(&[pair.sphere]);
        let first = |r: Result<Vec<Option<narrow::FirstContact>>, _>| {
            r.expect("one shape")
                .first()
                .copied()
                .flatten()
                .map(|f| f.time)
        };
        result[i] = match &pair.other {
            Other::Sphere(other) => {
                idx.push(i);
                a.push(&pair.sphere);
                b.push(other);
                continue;
            }
            Other::Plane(p) => first(narrow::first_contacts(&one(), &[*p], q)),
            Other::Cylinder(c) => first(narrow::first_contacts(&one(), &[*c], q)),
            Other::Container(k) => first(narrow::first_contacts(&one(), &[*k], q)),
        };
    }
    let mut times = vec![0.0; a.len()];
    narrow::zip_times(&a, &b, q, &mut times).expect("stores of equal length");
    for (i, t) in idx.into_iter().zip(times) {
        result[i] = t.is_finite().then_some(t);
    }
    result
}
