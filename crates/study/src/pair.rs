//! One pair of any kind ([`Pair`], from the library's reference), answered by every path: the
//! f64 reference, the 8-wide kernels in each mode, parry3d, and (in [`super::oracle`]) exact
//! arithmetic.

use glam::{Quat, Vec3};
use parry3d::math::{Pose, Vector};
use parry3d::query::{self, ShapeCastOptions};
use parry3d::shape::{Ball, Cylinder as ParryCylinder, HalfSpace};

pub use spheresweep::reference::Pair;
use spheresweep::{Accuracy, QueryOptions, Shape};

/// The paths beside the reference that answer a [`Pair`]: the 8-wide kernels and parry3d.
pub trait Paths {
    /// The 8-wide kernel's time of impact in `mode`, through the public single-pair entry.
    ///
    /// # Panics
    /// If `t_max` is NaN or negative.
    fn kernel(&self, mode: Accuracy, t_max: f32) -> Option<f32>;

    /// parry3d's time of impact (`query::cast_shapes`, stopping at penetration), or `None`
    /// when parry has no such shape (the inside of a container). A plane is parry's
    /// half-space; the infinite cylinder is a finite one centred on the axis point nearest the
    /// sphere, just long enough to cover the travel to the contact (its best case: parry's
    /// errors grow with the cylinder's length, docs/accuracy.md).
    fn parry(&self, t_max: f32) -> Option<Option<f32>>;
}

impl Paths for Pair {
    fn kernel(&self, mode: Accuracy, t_max: f32) -> Option<f32> {
        let options = QueryOptions::new(t_max, mode).expect("a valid window");
        spheresweep::time_of_impact(&self.sphere, &self.other, options)
    }

    fn parry(&self, t_max: f32) -> Option<Option<f32>> {
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
            Shape::Sphere(b) => Some(cast(
                &Pose::from_translation(b.centre()),
                b.velocity(),
                &Ball::new(b.radius()),
            )),
            Shape::Plane(p) => Some(cast(
                &Pose::from_translation(p.point()),
                Vector::ZERO,
                &HalfSpace::new(p.normal()),
            )),
            Shape::Cylinder(c) => {
                let axis = c.axis().as_dvec3().normalize();
                let x = s.centre().as_dvec3() - c.point().as_dvec3();
                let centre = c.point().as_dvec3() + axis * x.dot(axis);
                let d = f64::from(s.radius() + c.radius()).max(1.0);
                // Just long enough to cover the travel along the axis up to the contact (from the
                // f64 reference): parry's GJK cast loses accuracy as the cylinder grows.
                let travel = s.velocity().as_dvec3().dot(axis).abs()
                    * self.time_of_impact(f64::INFINITY).unwrap_or(0.0);
                let long = ParryCylinder::new((10.0 * d + travel) as f32, c.radius());
                let rotation = Quat::from_rotation_arc(Vec3::Y, axis.as_vec3());
                let pose = Pose::from_parts(centre.as_vec3(), rotation);
                Some(cast(&pose, Vector::ZERO, &long))
            }
            Shape::Container(_) => None,
        }
    }
}

/// The kernels' answers for many pairs in `mode`.
///
/// # Panics
/// If `t_max` is NaN or negative.
pub fn kernel_times(pairs: &[Pair], mode: Accuracy, t_max: f32) -> Vec<Option<f32>> {
    pairs.iter().map(|p| p.kernel(mode, t_max)).collect()
}
