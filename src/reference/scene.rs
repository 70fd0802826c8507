//! First contact of every sphere with anything in a scene, by brute force over every pair.
//! Quadratic in the number of spheres: it is the reference the fast query is tested against.

use super::Contact;
use super::pair::Pair;
use crate::contact::{Body, contact_at};
use crate::scene::Scene;
use crate::shape::{Shape, ShapeKind};

/// For every sphere, its earliest contact in `[0, t_max]` and with what (ties go to the body
/// listed first: spheres, planes, cylinders, containers, each by index).
///
/// ```
/// use spheresweep::{Body, ShapeKind, reference::scene::first_contacts_brute_force, scene::demo};
/// let contacts = first_contacts_brute_force(&demo(), 10.0);
/// assert_eq!(contacts[0].unwrap().0, Body::new(ShapeKind::Sphere, 1));
/// ```
pub fn first_contacts_brute_force(scene: &Scene, t_max: f64) -> Vec<Option<(Body, Contact)>> {
    let spheres = scene.spheres.to_spheres();
    let bodies: Vec<(Body, Shape)> = (spheres.iter().enumerate())
        .map(|(i, &s)| (Body::new(ShapeKind::Sphere, i as u32), Shape::Sphere(s)))
        .chain(scene.statics.iter().map(|(b, s, ())| (b, s.into())))
        .collect();
    spheres
        .iter()
        .enumerate()
        .map(|(i, &sphere)| {
            bodies
                .iter()
                .filter(|(body, _)| *body != Body::new(ShapeKind::Sphere, i as u32))
                .filter_map(|&(body, other)| {
                    let t = Pair { sphere, other }.time_of_impact(t_max)?;
                    Some((body, contact_at(&sphere, &other, t)))
                })
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
