//! Whole-scene query on the 8-wide kernels: the first contact of every sphere with anything.
//!
//! Sphere pairs are tested all against all for now (the uniform-grid broad phase replaces
//! that in a later step); each static kind runs its kernel only if the scene has such shapes.

use crate::narrow::{self, BatchError, FirstContact, Query, StaticShape};
use crate::reference::Contact;
use crate::reference::scene::Body;
use crate::scene::Scene;
use crate::store::SphereStore;

/// A sphere's first contact in a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneContact {
    /// What it touches.
    pub body: Body,
    /// When, in `[0, t_max]`.
    pub time: f32,
    /// Point and normal, computed by the f64 reference at `time` (only when asked for).
    pub geometry: Option<Contact>,
}

/// For every sphere of `scene`, its earliest contact (ties: spheres, then planes, cylinders,
/// containers, each by index), with the contact geometry if `geometry` is true.
///
/// # Errors
/// As the batch entry points ([`BatchError`]).
///
/// ```
/// use spheresweep::{Accuracy, narrow::Query, query::first_contacts, reference::scene::Body};
/// let scene = spheresweep::scene::demo();
/// let hits = first_contacts(&scene, Query::new(10.0, Accuracy::Stable)?, false)?;
/// assert_eq!(hits[2].unwrap().body, Body::Plane(0));
/// # Ok::<(), spheresweep::narrow::BatchError>(())
/// ```
pub fn first_contacts(
    scene: &Scene,
    query: Query,
    geometry: bool,
) -> Result<Vec<Option<SceneContact>>, BatchError> {
    let store = SphereStore::from_spheres(&scene.spheres);
    let mut best: Vec<Option<(Body, f32)>> = scene
        .spheres
        .iter()
        .map(|s| {
            // A sphere against itself has no relative motion: never a contact.
            narrow::first_contact_against(s, &store, query)
                .map(|f| (Body::Sphere(f.other as usize), f.time))
        })
        .collect();
    fn merge<K: StaticShape>(
        best: &mut [Option<(Body, f32)>],
        store: &SphereStore,
        shapes: &[K],
        query: Query,
        body: fn(usize) -> Body,
    ) -> Result<(), BatchError> {
        for (slot, first) in best
            .iter_mut()
            .zip(narrow::first_contacts(store, shapes, query)?)
        {
            if let Some(FirstContact { time, other }) = first
                && slot.is_none_or(|(_, t)| time < t)
            {
                *slot = Some((body(other as usize), time));
            }
        }
        Ok(())
    }
    merge(&mut best, &store, &scene.planes, query, Body::Plane)?;
    merge(&mut best, &store, &scene.cylinders, query, Body::Cylinder)?;
    merge(&mut best, &store, &scene.containers, query, Body::Container)?;
    Ok(best
        .into_iter()
        .enumerate()
        .map(|(i, b)| {
            let (body, time) = b?;
            let geometry = geometry.then(|| geometry_of(scene, i, body, f64::from(time)));
            Some(SceneContact {
                body,
                time,
                geometry,
            })
        })
        .collect())
}

fn geometry_of(scene: &Scene, i: usize, body: Body, t: f64) -> Contact {
    use crate::reference::{sphere_container, sphere_cylinder, sphere_plane, sphere_sphere};
    let s = &scene.spheres[i];
    match body {
        Body::Sphere(j) => sphere_sphere::contact_at(s, &scene.spheres[j], t),
        Body::Plane(j) => sphere_plane::contact_at(s, &scene.planes[j], t),
        Body::Cylinder(j) => sphere_cylinder::contact_at(s, &scene.cylinders[j], t),
        Body::Container(j) => sphere_container::contact_at(s, &scene.containers[j], t),
    }
}
