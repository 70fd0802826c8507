//! A sphere moving inside a static spherical container (seed: containment).
//!
//! Same formulas as sphere–sphere with the container as the static sphere "A" and
//! `D = R_container − R_sphere`; the contact is the *larger* root (the sphere arrives at the
//! wall from inside). A sphere larger than its container (`D < 0`) touches the wall at once.

use super::{Contact, Quadratic, Side, earliest_contact};
use crate::{Container, Sphere};

/// `D = R_container − R_sphere`.
#[inline]
fn contact_distance(s: &Sphere, k: &Container) -> f64 {
    f64::from(k.radius()) - f64::from(s.radius())
}

/// The seed's coefficients: `r0 = r_sphere0 − r_container`, `v = v_sphere`.
///
/// ```
/// use spheresweep::{Container, Sphere, reference::{Quadratic, sphere_container}};
/// // r0 = 0, v = (0, 0, 2), D = 5 − 1: A = 4, B = 0, C = −16.
/// let vessel = Container::new([0.0; 3], 5.0)?;
/// let s = Sphere::new([0.0; 3], [0.0, 0.0, 2.0], 1.0, 1.0)?;
/// assert_eq!(sphere_container::quadratic(&s, &vessel), Quadratic { a: 4.0, b: 0.0, c: -16.0 });
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn quadratic(s: &Sphere, k: &Container) -> Quadratic {
    let r0 = s.centre().as_dvec3() - k.centre().as_dvec3();
    let v = s.velocity().as_dvec3();
    let d = contact_distance(s, k);
    Quadratic {
        a: v.dot(v),
        b: 2.0 * r0.dot(v),
        c: r0.dot(r0) - d * d,
    }
}

/// The earliest time in `[0, t_max]` at which the sphere reaches the container's wall.
///
/// ```
/// use spheresweep::{Container, Sphere, reference::sphere_container};
/// let vessel = Container::new([0.0; 3], 5.0)?;
/// let s = Sphere::new([0.0; 3], [0.0, 0.0, 2.0], 1.0, 1.0)?;
/// // Roots ±2: the sphere arrives at the wall at the larger one.
/// assert_eq!(sphere_container::time_of_impact(&s, &vessel, 10.0), Some(2.0));
/// let too_big = Sphere::new([0.0; 3], [0.0; 3], 6.0, 1.0)?;
/// assert_eq!(sphere_container::time_of_impact(&too_big, &vessel, 10.0), Some(0.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn time_of_impact(s: &Sphere, k: &Container, t_max: f64) -> Option<f64> {
    if contact_distance(s, k) < 0.0 {
        return Some(0.0).filter(|_| t_max >= 0.0);
    }
    earliest_contact(&quadratic(s, k), Side::Interior, t_max)
}

/// The first contact with the wall. `normal` points from the wall back towards the
/// container's centre (it pushes the sphere inwards).
///
/// ```
/// use spheresweep::{Container, Sphere, reference::sphere_container};
/// // Sphere of radius 1 at the centre of a vessel of radius 5, speed 2: D = 4, t = 2.
/// let s = Sphere::new([0.0; 3], [0.0, 2.0, 0.0], 1.0, 1.0)?;
/// let k = Container::new([0.0; 3], 5.0)?;
/// let c = sphere_container::first_contact(&s, &k, 10.0).unwrap();
/// assert_eq!((c.time, c.point.y, c.normal.y), (2.0, 5.0, -1.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn first_contact(s: &Sphere, k: &Container, t_max: f64) -> Option<Contact> {
    let t = time_of_impact(s, k, t_max)?;
    Some(contact_at(s, k, t))
}

pub use crate::contact::sphere_container_at as contact_at;
