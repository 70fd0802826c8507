//! Whole-scene query on the 8-wide kernels: the first contact of every sphere with anything.
//!
//! Sphere pairs are tested all against all for now (the uniform-grid broad phase replaces
//! that in a later step); each static kind runs its kernel only if the scene has such shapes.

use crate::batch::{self, FirstContact, QueryOptions, StaticShape};
use crate::contact::{Body, contact_at};
use crate::scene::Scene;
use crate::store::SphereStore;

/// For every sphere of `scene`, its earliest contact (ties: spheres, then planes, cylinders,
/// containers, each by index), with the contact geometry if the options ask for it.
///
/// ```
/// use spheresweep::{Accuracy, Body, QueryOptions, ShapeKind, query::first_contacts};
/// let scene = spheresweep::scene::demo();
/// let hits = first_contacts(&scene, QueryOptions::new(10.0, Accuracy::Stable)?);
/// assert_eq!(hits[2].unwrap().body, Body::new(ShapeKind::Plane, 0));
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub fn first_contacts(scene: &Scene, options: QueryOptions) -> Vec<Option<FirstContact>> {
    let store = &scene.spheres;
    let times_only = options.with_geometry(false);
    let mut best: Vec<Option<FirstContact>> = (0..store.len())
        .map(|i| {
            let s = store.get(i).expect("index below len");
            // A sphere against itself has no relative motion: never a contact.
            batch::earliest_sphere_contact(&s, store, times_only)
        })
        .collect();
    fn merge<K: StaticShape>(
        best: &mut [Option<FirstContact>],
        store: &SphereStore,
        shapes: &[K],
        options: QueryOptions,
    ) {
        for (slot, first) in best
            .iter_mut()
            .zip(batch::earliest_static_contacts(store, shapes, options))
        {
            if let Some(hit) = first
                && slot.is_none_or(|b| hit.time < b.time)
            {
                *slot = Some(hit);
            }
        }
    }
    merge(&mut best, store, &scene.planes, times_only);
    merge(&mut best, store, &scene.cylinders, times_only);
    merge(&mut best, store, &scene.containers, times_only);
    if options.geometry() {
        for (i, slot) in best.iter_mut().enumerate() {
            if let Some(hit) = slot {
                hit.geometry = Some(geometry_of(scene, i, hit.body, hit.time.into()));
            }
        }
    }
    best
}

fn geometry_of(scene: &Scene, i: usize, body: Body, t: f64) -> crate::Contact {
    let sphere = scene.spheres.get(i).expect("index below len");
    let other = scene.body(body).expect("a body the query found");
    contact_at(&sphere, &other, t)
}
