//! Sphere A – sphere B, both moving, each outside the other (seed, first section).
//!
//! `r0 = r_B0 − r_A0`, `v = v_B − v_A`, `D = R_A + R_B`,
//! `A = v·v`, `B = 2 r0·v`, `C = r0·r0 − D²`.

use super::{Contact, Quadratic, Side, earliest_contact};
use crate::Sphere;

/// The seed's coefficients for two spheres, in f64.
///
/// ```
/// use spheresweep::{Sphere, reference::{Quadratic, sphere_sphere}};
/// // r0 = (10, 0, 0), v = (−2, 0, 0), D = 2: A = 4, B = −40, C = 96.
/// let a = Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?;
/// let b = Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?;
/// assert_eq!(sphere_sphere::quadratic(&a, &b), Quadratic { a: 4.0, b: -40.0, c: 96.0 });
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn quadratic(sa: &Sphere, sb: &Sphere) -> Quadratic {
    let r0 = sb.centre().as_dvec3() - sa.centre().as_dvec3();
    let v = sb.velocity().as_dvec3() - sa.velocity().as_dvec3();
    let d = f64::from(sa.radius()) + f64::from(sb.radius());
    Quadratic {
        a: v.dot(v),
        b: 2.0 * r0.dot(v),
        c: r0.dot(r0) - d * d,
    }
}

/// The earliest time in `[0, t_max]` at which the spheres touch from outside.
///
/// ```
/// use spheresweep::{Sphere, reference::sphere_sphere};
/// // Roots (40 ∓ 8)/8 = 4 and 6: they touch at 4 (and would part at 6 if they passed through).
/// let a = Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?;
/// let b = Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?;
/// assert_eq!(sphere_sphere::time_of_impact(&a, &b, 100.0), Some(4.0));
/// assert_eq!(sphere_sphere::time_of_impact(&a, &b, 3.0), None); // outside the window
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn time_of_impact(sa: &Sphere, sb: &Sphere, t_max: f64) -> Option<f64> {
    earliest_contact(&quadratic(sa, sb), Side::Exterior, t_max)
}

/// The first contact with positions, contact point and normals.
///
/// ```
/// use spheresweep::{Sphere, reference::sphere_sphere};
/// // A at the origin, B at x = 10 coming back at speed 2; D = 1 + 1: contact at t = 4.
/// let a = Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?;
/// let b = Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?;
/// let c = sphere_sphere::first_contact(&a, &b, 100.0).unwrap();
/// assert_eq!(c.time, 4.0);
/// assert_eq!(c.point.x, 1.0);
/// assert_eq!(c.normal.x, -1.0); // pushes A away from B
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn first_contact(sa: &Sphere, sb: &Sphere, t_max: f64) -> Option<Contact> {
    let t = time_of_impact(sa, sb, t_max)?;
    Some(contact_at(sa, sb, t))
}

pub use crate::contact::sphere_sphere_at as contact_at;
