//! First contact of every sphere with anything in a scene, by brute force over every pair.
//! Quadratic in the number of spheres: it is the reference the fast query is tested against.

use super::{Contact, sphere_container, sphere_cylinder, sphere_plane, sphere_sphere};
use crate::scene::Scene;

/// The other body of a contact, by its index in the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Body {
    /// `scene.spheres[i]`.
    Sphere(usize),
    /// `scene.planes[i]`.
    Plane(usize),
    /// `scene.cylinders[i]`.
    Cylinder(usize),
    /// `scene.containers[i]`.
    Container(usize),
}

/// For every sphere, its earliest contact in `[0, t_max]` and with what (ties go to the body
/// listed first: spheres, planes, cylinders, containers, each by index).
///
/// ```
/// use spheresweep::{reference::scene::{first_contacts, Body}, scene::demo};
/// let contacts = first_contacts(&demo(), 10.0);
/// assert_eq!(contacts[0].unwrap().0, Body::Sphere(1));
/// ```
pub fn first_contacts(scene: &Scene, t_max: f64) -> Vec<Option<(Body, Contact)>> {
    scene
        .spheres
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let others = scene
                .spheres
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(j, o)| (Body::Sphere(j), sphere_sphere::first_contact(s, o, t_max)));
            let planes = (scene.planes.iter().enumerate())
                .map(|(j, p)| (Body::Plane(j), sphere_plane::first_contact(s, p, t_max)));
            let cylinders = (scene.cylinders.iter().enumerate()).map(|(j, c)| {
                (
                    Body::Cylinder(j),
                    sphere_cylinder::first_contact(s, c, t_max),
                )
            });
            let containers = (scene.containers.iter().enumerate()).map(|(j, k)| {
                (
                    Body::Container(j),
                    sphere_container::first_contact(s, k, t_max),
                )
            });
            others
                .chain(planes)
                .chain(cylinders)
                .chain(containers)
                .filter_map(|(body, c)| Some((body, c?)))
                .fold(
                    None,
                    |best: Option<(Body, Contact)>, (body, c)| match best {
                        Some(b) if b.1.time <= c.time => Some(b),
                        _ => Some((body, c)),
                    },
                )
        })
        .collect()
}
