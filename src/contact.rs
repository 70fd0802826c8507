//! What a contact is, shared by the fast path and the reference alike: which side of the
//! contact surface a sphere starts on ([`Side`]), which body it touches ([`Body`]), and the
//! contact geometry at a given time ([`Contact`], computed in f64 from the f32 inputs).
//!
//! The kernels find times only; geometry is computed here, once per reported contact, and only
//! when a caller asks for it.

use glam::DVec3;

use crate::shape::{Container, Cylinder, Plane, Shape, ShapeKind, Sphere};

/// Which side of the contact surface the moving sphere starts on.
///
/// ```
/// use spheresweep::{Container, Side, Sphere, reference::Pair};
/// let pair = Pair {
///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
///     other: Container::new([0.0; 3], 5.0)?.into(),
/// };
/// let (_, _, distance, side) = pair.relative();
/// assert_eq!((distance, side), (4.0, Side::Interior)); // D = R_container − R
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// The bodies approach from outside each other (`D = R_A + R_B`, plane, cylinder).
    Exterior,
    /// A sphere inside a container, reaching its wall from within (`D = R_container − R`).
    Interior,
}

/// The body a sphere touches: its kind and its index among the bodies of that kind (in the
/// scene, store or slice the query was given).
///
/// ```
/// use spheresweep::{Body, ShapeKind};
/// let b = Body::new(ShapeKind::Plane, 2);
/// assert_eq!(b.to_string(), "plane 2");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Body {
    /// What kind of body.
    pub kind: ShapeKind,
    /// Its index among the bodies of that kind.
    pub index: u32,
}

impl Body {
    /// The body `index` of kind `kind`.
    ///
    /// ```
    /// use spheresweep::{Body, ShapeKind};
    /// let b = Body::new(ShapeKind::Cylinder, 3);
    /// assert_eq!((b.kind, b.index), (ShapeKind::Cylinder, 3));
    /// assert!(Body::new(ShapeKind::Sphere, 9) < b); // spheres sort first
    /// ```
    #[inline]
    pub const fn new(kind: ShapeKind, index: u32) -> Self {
        Self { kind, index }
    }
}

impl std::fmt::Display for Body {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}", self.kind, self.index)
    }
}

/// The geometry of a contact at a given time: where the bodies are, where they touch, and
/// which way.
///
/// "A" is always the moving sphere of the query (for a container, the sphere inside it).
/// `normal` is the seed's summary-table normal on A: the unit vector that pushes A away from
/// the other body (for two spheres `(r_A − r_B)/‖r_A − r_B‖`, which the seed's text calls
/// `n̂_B`, the outward surface normal of B; A's own outward surface normal is `−normal`).
///
/// ```
/// use spheresweep::{Shape, Sphere, contact::contact_at};
/// let a = Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?;
/// let b = Shape::Sphere(Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 2.0, 1.0)?);
/// let c = contact_at(&a, &b, 3.0); // centres 3 apart: touching
/// assert_eq!((c.centre.x, c.other_anchor.x, c.point.x), (3.0, 6.0, 4.0));
/// assert_eq!(c.normal.to_array(), [-1.0, 0.0, 0.0]); // pushes A back
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Time of impact, in `[0, t_max]`.
    pub time: f64,
    /// Centre of sphere A at `time` (`r_A = r_A0 + v_A t`).
    pub centre: DVec3,
    /// The other body's anchor at `time`: B's centre, the container's centre, the foot of A's
    /// centre on the plane, or on the cylinder's axis.
    pub other_anchor: DVec3,
    /// The contact point, on A's surface along the normal: on both bodies' surfaces at a
    /// contact that arrives, on A's only for bodies that start overlapping (a contact at 0).
    pub point: DVec3,
    /// Unit normal pushing A away from the other body.
    pub normal: DVec3,
}

/// `v` normalised, or `fallback` normalised when `v` is zero (a contact of two point-like
/// bodies, where the normal is the limit of the direction just before contact), or `+x` when
/// both are: only a sphere at rest at the centre of a container too small for it (a contact at
/// 0 by policy) has neither, and there every direction is a normal.
#[inline]
fn unit_or(v: DVec3, fallback: DVec3) -> DVec3 {
    v.try_normalize()
        .or_else(|| fallback.try_normalize())
        .unwrap_or(DVec3::X)
}

/// The stored f32 normal normalised again in f64: the f32 normal is unit only to one f32
/// rounding, which would scale every distance by `‖n̂‖`.
#[inline]
pub(crate) fn unit_normal(p: &Plane) -> DVec3 {
    p.normal().as_dvec3().normalize()
}

/// The stored f32 axis normalised again in f64 (as [`unit_normal`]).
#[inline]
pub(crate) fn unit_axis(cyl: &Cylinder) -> DVec3 {
    cyl.axis().as_dvec3().normalize()
}

/// `ŝ × x × ŝ = (ŝ × x) × ŝ`, the part of `x` perpendicular to the unit axis `ŝ`.
#[inline]
pub(crate) fn perpendicular(s: DVec3, x: DVec3) -> DVec3 {
    s.cross(x).cross(s)
}

/// The geometry of `sphere` touching `other` at time `t` (a root found by any path).
///
/// ```
/// use spheresweep::{Plane, Shape, Sphere, contact::contact_at};
/// let floor = Shape::Plane(Plane::new([0.0; 3], [0.0, 0.0, 1.0])?);
/// let ball = Sphere::new([0.0, 0.0, 5.0], [0.0, 0.0, -2.0], 1.0, 1.0)?;
/// let c = contact_at(&ball, &floor, 2.0);
/// assert_eq!((c.point.z, c.normal.z), (0.0, 1.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn contact_at(sphere: &Sphere, other: &Shape, t: f64) -> Contact {
    match other {
        Shape::Sphere(b) => sphere_sphere_at(sphere, b, t),
        Shape::Plane(p) => sphere_plane_at(sphere, p, t),
        Shape::Cylinder(c) => sphere_cylinder_at(sphere, c, t),
        Shape::Container(k) => sphere_container_at(sphere, k, t),
    }
}

/// Two spheres at time `t`: the normal is `n̂_B = (r_A − r_B)/‖r_A − r_B‖`.
///
/// ```
/// use spheresweep::{Sphere, contact::sphere_sphere_at};
/// let a = Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?;
/// let b = Sphere::new([0.0, 5.0, 0.0], [0.0, -1.0, 0.0], 1.0, 1.0)?;
/// let c = sphere_sphere_at(&a, &b, 3.0);
/// assert_eq!((c.point.y, c.normal.y), (1.0, -1.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn sphere_sphere_at(sa: &Sphere, sb: &Sphere, t: f64) -> Contact {
    let r_a = sa.centre().as_dvec3() + sa.velocity().as_dvec3() * t;
    let r_b = sb.centre().as_dvec3() + sb.velocity().as_dvec3() * t;
    // For two point spheres meeting head-on, the limit direction just before contact is that
    // of v = v_B − v_A.
    let n_b = unit_or(
        r_a - r_b,
        sb.velocity().as_dvec3() - sa.velocity().as_dvec3(),
    );
    Contact {
        time: t,
        centre: r_a,
        other_anchor: r_b,
        point: r_a - n_b * f64::from(sa.radius()),
        normal: n_b,
    }
}

/// A sphere and a plane at time `t`: the contact point `r_A ∓ R_A n̂_P` and the normal `±n̂_P`
/// on the side the sphere is on.
///
/// ```
/// use spheresweep::{Plane, Sphere, contact::sphere_plane_at};
/// let floor = Plane::new([0.0; 3], [0.0, 0.0, 1.0])?;
/// let below = Sphere::new([0.0, 0.0, -4.0], [0.0, 0.0, 1.0], 1.0, 1.0)?; // comes from below
/// let c = sphere_plane_at(&below, &floor, 3.0);
/// assert_eq!((c.point.z, c.normal.z), (0.0, -1.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn sphere_plane_at(s: &Sphere, p: &Plane, t: f64) -> Contact {
    let n_p = unit_normal(p);
    let v_a = s.velocity().as_dvec3();
    let r_a = s.centre().as_dvec3() + v_a * t;
    let side = (r_a - p.point().as_dvec3()).dot(n_p);
    // In front: n̂ = n̂_P; behind: −n̂_P. A point sphere's centre is on the plane at contact:
    // it arrives from the side opposite to its motion along the normal.
    let sign = if side > 0.0 {
        1.0
    } else if side < 0.0 {
        -1.0
    } else {
        -v_a.dot(n_p).signum()
    };
    let normal = n_p * sign;
    Contact {
        time: t,
        centre: r_a,
        other_anchor: r_a - n_p * side,
        point: r_a - normal * f64::from(s.radius()),
        normal,
    }
}

/// A sphere and a cylinder at time `t`: the normal is `D⃗/‖D⃗‖` with
/// `D⃗ = ŝ × (r_A − r_C1) × ŝ`.
///
/// ```
/// use spheresweep::{Cylinder, Sphere, contact::sphere_cylinder_at};
/// let pillar = Cylinder::new([0.0; 3], [0.0, 0.0, 1.0], 1.0)?;
/// let ball = Sphere::new([0.0, 4.0, 7.0], [0.0, -1.0, 0.0], 1.0, 1.0)?;
/// let c = sphere_cylinder_at(&ball, &pillar, 2.0);
/// assert_eq!(c.other_anchor.to_array(), [0.0, 0.0, 7.0]); // the foot on the axis
/// assert_eq!((c.point.y, c.normal.y), (1.0, 1.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn sphere_cylinder_at(sa: &Sphere, cyl: &Cylinder, t: f64) -> Contact {
    let s = unit_axis(cyl);
    let v_a = sa.velocity().as_dvec3();
    let r_a = sa.centre().as_dvec3() + v_a * t;
    let d_vec = perpendicular(s, r_a - cyl.point().as_dvec3());
    // A point sphere on a zero-radius cylinder meets the axis: the limit direction just
    // before contact is −v_⊥.
    let normal = unit_or(d_vec, -perpendicular(s, v_a));
    Contact {
        time: t,
        centre: r_a,
        other_anchor: r_a - d_vec,
        point: r_a - normal * f64::from(sa.radius()),
        normal,
    }
}

/// A sphere inside a container at time `t`: the normal points from the wall back towards the
/// container's centre (it pushes the sphere inwards).
///
/// ```
/// use spheresweep::{Container, Sphere, contact::sphere_container_at};
/// let vessel = Container::new([0.0; 3], 5.0)?;
/// let ball = Sphere::new([0.0; 3], [0.0, 0.0, 2.0], 1.0, 1.0)?;
/// let c = sphere_container_at(&ball, &vessel, 2.0);
/// assert_eq!((c.point.z, c.normal.z), (5.0, -1.0));
/// // Too large for the vessel, at rest at its centre: every direction is a normal; −x.
/// let big = Sphere::new([0.0; 3], [0.0; 3], 6.0, 1.0)?;
/// assert_eq!(sphere_container_at(&big, &vessel, 0.0).normal, glam::DVec3::NEG_X);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn sphere_container_at(s: &Sphere, k: &Container, t: f64) -> Contact {
    let r = s.centre().as_dvec3() + s.velocity().as_dvec3() * t;
    let centre = k.centre().as_dvec3();
    let outward = unit_or(r - centre, s.velocity().as_dvec3());
    Contact {
        time: t,
        centre: r,
        other_anchor: centre,
        point: r + outward * f64::from(s.radius()),
        normal: -outward,
    }
}
