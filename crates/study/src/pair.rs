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
///
/// ```
/// # use spheresweep::{Sphere, reference::Pair};
/// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
/// let pair = Pair {
///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
/// };
/// use spheresweep::Accuracy;
/// use spheresweep_study::Paths;
/// assert_eq!(pair.kernel(Accuracy::Stable, f32::INFINITY), Some(4.0));
/// let parry = pair.parry(100.0).unwrap().unwrap(); // parry's GJK cast: close, not exact
/// assert!((parry - 4.0).abs() < 1e-3);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub trait Paths {
    /// The 8-wide kernel's time of impact in `mode`, through the public single-pair entry.
    ///
    /// # Panics
    /// If `t_max` is NaN or negative.
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// use spheresweep::Accuracy;
    /// use spheresweep_study::Paths;
    /// assert_eq!(pair.kernel(Accuracy::Double, 3.0), None); // the contact at 4 is outside [0, 3]
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    fn kernel(&self, mode: Accuracy, t_max: f32) -> Option<f32>;

    /// parry3d's time of impact (`query::cast_shapes`, stopping at penetration), or `None`
    /// when parry has no such shape (the inside of a container). A plane is parry's
    /// half-space; the infinite cylinder is a finite one centred on the axis point nearest the
    /// sphere, just long enough to cover the travel to the contact (its best case: parry's
    /// errors grow with the cylinder's length, docs/accuracy.md). The half-space faces the side
    /// of the plane the sphere starts on (ours is two-sided, parry's solid below its plane).
    ///
    /// ```
    /// use spheresweep::{Container, Sphere, reference::Pair};
    /// use spheresweep_study::Paths;
    /// let inside = Pair {
    ///     sphere: Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    ///     other: Container::new([0.0; 3], 5.0)?.into(),
    /// };
    /// assert_eq!(inside.parry(10.0), None); // parry has no container
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
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
            Shape::Plane(p) => {
                // parry's half-space is one-sided (solid below the plane): ours is two-sided,
                // so the half-space faces the side the sphere starts on.
                let side =
                    (s.centre().as_dvec3() - p.point().as_dvec3()).dot(p.normal().as_dvec3());
                let normal = if side < 0.0 { -p.normal() } else { p.normal() };
                Some(cast(
                    &Pose::from_translation(p.point()),
                    Vector::ZERO,
                    &HalfSpace::new(normal),
                ))
            }
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
            // parry has no hollow sphere to be inside of; nor a kind added after these.
            _ => None,
        }
    }
}

/// One case of a family: a pair and the window `[0, t_max]` it is asked about (`+∞` for the
/// families that leave the window open; the window-edge families end it within a few ulps of
/// the contact). The oracle decides hit or miss against the same window (`Exact::time`).
///
/// ```
/// # use spheresweep::{Sphere, reference::Pair};
/// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
/// let pair = Pair {
///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
/// };
/// use spheresweep::Accuracy;
/// use spheresweep_study::Case;
/// let case = Case { pair, t_max: 3.0 };
/// assert_eq!(case.kernel(Accuracy::Double), None); // the contact at 4 is outside [0, 3]
/// assert_eq!(Case::open(pair).kernel(Accuracy::Double), Some(4.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Case {
    /// The pair.
    pub pair: Pair,
    /// The end of the window (never NaN or negative; may be `+∞`).
    pub t_max: f32,
}

impl Case {
    /// A pair with the window `[0, ∞)`.
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// assert_eq!(spheresweep_study::Case::open(pair).t_max, f32::INFINITY);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn open(pair: Pair) -> Self {
        Self {
            pair,
            t_max: f32::INFINITY,
        }
    }

    /// The kernel's answer in `mode` on this case's window.
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// use spheresweep::Accuracy;
    /// let case = spheresweep_study::Case { pair, t_max: 4.0 };
    /// assert_eq!(case.kernel(Accuracy::Textbook), Some(4.0));
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn kernel(&self, mode: Accuracy) -> Option<f32> {
        self.pair.kernel(mode, self.t_max)
    }

    /// parry3d's answer on this case's window (an open window is parry's `f32::MAX`).
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// use spheresweep_study::Case;
    /// assert_eq!(Case { pair, t_max: 3.0 }.parry(), Some(None)); // answered: no contact in [0, 3]
    /// assert!(Case::open(pair).parry().unwrap().is_some());
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn parry(&self) -> Option<Option<f32>> {
        self.pair.parry(self.t_max.min(f32::MAX))
    }
}

/// The kernels' answers for many pairs in `mode`.
///
/// # Panics
/// If `t_max` is NaN or negative.
///
/// ```
/// # use spheresweep::{Sphere, reference::Pair};
/// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
/// let pair = Pair {
///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
/// };
/// use spheresweep::Accuracy;
/// use spheresweep_study::kernel_times;
/// assert_eq!(kernel_times(&[pair, pair], Accuracy::Stable, 10.0), [Some(4.0), Some(4.0)]);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn kernel_times(pairs: &[Pair], mode: Accuracy, t_max: f32) -> Vec<Option<f32>> {
    pairs.iter().map(|p| p.kernel(mode, t_max)).collect()
}

/// The kernels' answers for many cases in `mode`, each on its own window.
///
/// ```
/// # use spheresweep::{Sphere, reference::Pair};
/// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
/// let pair = Pair {
///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
/// };
/// use spheresweep::Accuracy;
/// use spheresweep_study::{Case, case_times};
/// let cases = [Case::open(pair), Case { pair, t_max: 1.0 }];
/// assert_eq!(case_times(&cases, Accuracy::Stable), [Some(4.0), None]);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn case_times(cases: &[Case], mode: Accuracy) -> Vec<Option<f32>> {
    cases.iter().map(|c| c.kernel(mode)).collect()
}
