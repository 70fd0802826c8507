//! Sphere A – infinite static cylinder C, A outside (seed, third section).
//!
//! `ŝ` unit axis, `r0 = ŝ × (r_A0 − r_C1) × ŝ`, `v = ŝ × v_A × ŝ` (the parts perpendicular to
//! the axis), `D = R_A + R_C`, `A = v·v`, `B = 2 r0·v`, `C = r0·r0 − D²`. Motion along the
//! axis (`v = 0`) is no contact.

use super::{Contact, Quadratic, Side, earliest_contact};
use crate::contact::{perpendicular, unit_axis};
use crate::{Cylinder, Sphere};

/// The seed's coefficients for a sphere and a cylinder, in f64.
///
/// ```
/// use spheresweep::{Cylinder, Sphere, reference::{Quadratic, sphere_cylinder}};
/// // Only the parts across the axis count: r0 = (6, 0, 0), v = (−1, 0, 0), D = 2.
/// let pillar = Cylinder::new([0.0; 3], [0.0, 0.0, 1.0], 1.0)?;
/// let s = Sphere::new([6.0, 0.0, 3.0], [-1.0, 0.0, 0.5], 1.0, 1.0)?;
/// assert_eq!(sphere_cylinder::quadratic(&s, &pillar), Quadratic { a: 1.0, b: -12.0, c: 32.0 });
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn quadratic(sa: &Sphere, cyl: &Cylinder) -> Quadratic {
    let s = unit_axis(cyl);
    let r0 = perpendicular(s, sa.centre().as_dvec3() - cyl.point().as_dvec3());
    let v = perpendicular(s, sa.velocity().as_dvec3());
    let d = f64::from(sa.radius()) + f64::from(cyl.radius());
    Quadratic {
        a: v.dot(v),
        b: 2.0 * r0.dot(v),
        c: r0.dot(r0) - d * d,
    }
}

/// The earliest time in `[0, t_max]` at which the sphere touches the cylinder.
///
/// ```
/// use spheresweep::{Cylinder, Sphere, reference::sphere_cylinder};
/// let pillar = Cylinder::new([0.0; 3], [0.0, 0.0, 1.0], 1.0)?;
/// let s = Sphere::new([6.0, 0.0, 3.0], [-1.0, 0.0, 0.5], 1.0, 1.0)?;
/// assert_eq!(sphere_cylinder::time_of_impact(&s, &pillar, 10.0), Some(4.0)); // roots 4 and 8
/// let along = Sphere::new([6.0, 0.0, 3.0], [0.0, 0.0, 1.0], 1.0, 1.0)?;
/// assert_eq!(sphere_cylinder::time_of_impact(&along, &pillar, 10.0), None); // parallel to the axis
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn time_of_impact(sa: &Sphere, cyl: &Cylinder, t_max: f64) -> Option<f64> {
    earliest_contact(&quadratic(sa, cyl), Side::Exterior, t_max)
}

/// The first contact; the normal is `D⃗/‖D⃗‖` with `D⃗ = ŝ × (r_A − r_C1) × ŝ`.
///
/// ```
/// use spheresweep::{Cylinder, Sphere, reference::sphere_cylinder};
/// // Pillar along z of radius 1; sphere of radius 1 at x = 6 moving at −x speed 1: t = 4.
/// let pillar = Cylinder::new([0.0; 3], [0.0, 0.0, 1.0], 1.0)?;
/// let s = Sphere::new([6.0, 0.0, 3.0], [-1.0, 0.0, 0.5], 1.0, 1.0)?;
/// let c = sphere_cylinder::first_contact(&s, &pillar, 10.0).unwrap();
/// assert_eq!((c.time, c.point.x, c.normal.x), (4.0, 1.0, 1.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn first_contact(sa: &Sphere, cyl: &Cylinder, t_max: f64) -> Option<Contact> {
    let t = time_of_impact(sa, cyl, t_max)?;
    Some(contact_at(sa, cyl, t))
}

pub use crate::contact::sphere_cylinder_at as contact_at;
