//! Sphere A – infinite static plane P (seed, second section).
//!
//! `R0 = (r_A0 − r_P0)·n̂_P`, `v = v_A·n̂_P`, `D = R_A`,
//! `A = v²`, `B = 2 R0 v`, `C = R0² − D²`.
//! Motion parallel to the plane (`v = 0`) is no contact; a point sphere (`R_A = 0`) has the
//! single root `t = (r_P0 − r_A0)·n̂_P / (v_A·n̂_P)`.

use super::{Contact, Quadratic, Side, earliest_contact};
use crate::contact::unit_normal;
use crate::{Plane, Sphere};

/// The seed's coefficients for a sphere and a plane, in f64.
///
/// ```
/// use spheresweep::{Plane, Sphere, reference::{Quadratic, sphere_plane}};
/// // R0 = 5, v = −2, D = 1: A = 4, B = −20, C = 24.
/// let floor = Plane::new([0.0; 3], [0.0, 0.0, 1.0])?;
/// let s = Sphere::new([0.0, 0.0, 5.0], [0.0, 0.0, -2.0], 1.0, 1.0)?;
/// assert_eq!(sphere_plane::quadratic(&s, &floor), Quadratic { a: 4.0, b: -20.0, c: 24.0 });
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn quadratic(s: &Sphere, p: &Plane) -> Quadratic {
    let n = unit_normal(p);
    let r0 = (s.centre().as_dvec3() - p.point().as_dvec3()).dot(n);
    let v = s.velocity().as_dvec3().dot(n);
    let d = f64::from(s.radius());
    Quadratic {
        a: v * v,
        b: 2.0 * r0 * v,
        c: r0 * r0 - d * d,
    }
}

/// The earliest time in `[0, t_max]` at which the sphere touches the plane (either side).
///
/// ```
/// use spheresweep::{Plane, Sphere, reference::sphere_plane};
/// let floor = Plane::new([0.0; 3], [0.0, 0.0, 1.0])?;
/// let above = Sphere::new([0.0, 0.0, 5.0], [0.0, 0.0, -2.0], 1.0, 1.0)?;
/// let below = Sphere::new([0.0, 0.0, -5.0], [0.0, 0.0, 2.0], 1.0, 1.0)?;
/// assert_eq!(sphere_plane::time_of_impact(&above, &floor, 10.0), Some(2.0));
/// assert_eq!(sphere_plane::time_of_impact(&below, &floor, 10.0), Some(2.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn time_of_impact(s: &Sphere, p: &Plane, t_max: f64) -> Option<f64> {
    earliest_contact(&quadratic(s, p), Side::Exterior, t_max)
}

/// The first contact: the contact point `r_P = r_A ∓ R_A n̂_P` and the normal `±n̂_P` on the
/// side the sphere is on.
///
/// ```
/// use spheresweep::{Plane, Sphere, reference::sphere_plane};
/// // Floor z = 0; sphere of radius 1 at height 5 falling at speed 2: contact at t = 2.
/// let floor = Plane::new([0.0; 3], [0.0, 0.0, 1.0])?;
/// let s = Sphere::new([0.0, 0.0, 5.0], [0.0, 0.0, -2.0], 1.0, 1.0)?;
/// let c = sphere_plane::first_contact(&s, &floor, 10.0).unwrap();
/// assert_eq!((c.time, c.point.z, c.normal.z), (2.0, 0.0, 1.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn first_contact(s: &Sphere, p: &Plane, t_max: f64) -> Option<Contact> {
    let t = time_of_impact(s, p, t_max)?;
    Some(contact_at(s, p, t))
}

pub use crate::contact::sphere_plane_at as contact_at;
