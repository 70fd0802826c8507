//! The whole-scene query by brute force: every sphere against every sphere and every shape,
//! through the same 8-wide kernels, with no broad phase. Quadratic in the number of spheres;
//! it is what the grid query is tested against, bit for bit (`tests/query.rs`). The f64
//! specification of the same query is `reference::scene::first_contacts_brute_force`.

use super::{ContactEvent, sort_events};
use crate::batch::{self, FirstContact, QueryOptions, StaticShape};
use crate::contact::{Body, contact_at};
use crate::scene::Scene;
use crate::shape::ShapeKind;

/// Every sphere's earliest contact, every pair tested (ties: spheres, then planes, cylinders,
/// containers, each by index).
///
/// ```
/// use spheresweep::{QueryOptions, query};
/// let scene = spheresweep::scene::demo();
/// let options = QueryOptions::new(10.0, Default::default())?;
/// assert_eq!(query::brute_force::first_contacts(&scene, options), query::first_contacts(&scene, options));
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub fn first_contacts(scene: &Scene, options: QueryOptions) -> Vec<Option<FirstContact>> {
    let events = all_contacts(scene, options.with_geometry(false));
    let mut best: Vec<Option<FirstContact>> = vec![None; scene.spheres.len()];
    // Every event once per sphere it involves; events are in time order, so the first one a
    // sphere sees is its earliest, and equal times come in body order.
    let mut seen = |i: u32, time: f32, body: Body| {
        let slot = &mut best[i as usize];
        let better = slot.is_none_or(|b| time < b.time || (time == b.time && body < b.body));
        if better {
            *slot = Some(FirstContact {
                time,
                body,
                geometry: None,
            });
        }
    };
    for e in &events {
        seen(e.sphere, e.time, e.other);
        if e.other.kind == ShapeKind::Sphere {
            seen(
                e.other.index,
                e.time,
                Body::new(ShapeKind::Sphere, e.sphere),
            );
        }
    }
    if options.geometry() {
        for (i, slot) in best.iter_mut().enumerate() {
            if let Some(hit) = slot {
                let s = scene.spheres.get(i).expect("a sphere of the scene");
                let other = scene.body(hit.body).expect("a body of the scene");
                hit.geometry = Some(contact_at(&s, &other, hit.time.into()));
            }
        }
    }
    best
}

/// Every contact in the window, every pair tested, sorted by time, then sphere, then body.
pub fn all_contacts(scene: &Scene, options: QueryOptions) -> Vec<ContactEvent> {
    let store = &scene.spheres;
    let n = store.len();
    let mut events = Vec::new();
    let mut times = vec![0.0; n];
    for (i, sphere) in store.iter().enumerate() {
        batch::one_against_times(&sphere, store, options, &mut times).expect("one slot each");
        for (j, &time) in times.iter().enumerate().skip(i + 1) {
            if time.is_finite() {
                events.push(ContactEvent {
                    time,
                    sphere: i as u32,
                    other: Body::new(ShapeKind::Sphere, j as u32),
                    geometry: None,
                });
            }
        }
    }
    fn statics<K: StaticShape>(
        events: &mut Vec<ContactEvent>,
        scene: &Scene,
        shapes: &[K],
        options: QueryOptions,
    ) {
        let mut times = vec![0.0; scene.spheres.len()];
        for (j, shape) in shapes.iter().enumerate() {
            batch::static_times(&scene.spheres, shape, options, &mut times)
                .expect("one slot per sphere");
            for (i, &time) in times.iter().enumerate() {
                if time.is_finite() {
                    events.push(ContactEvent {
                        time,
                        sphere: i as u32,
                        other: Body::new(K::KIND, j as u32),
                        geometry: None,
                    });
                }
            }
        }
    }
    statics(&mut events, scene, &scene.planes, options);
    statics(&mut events, scene, &scene.cylinders, options);
    statics(&mut events, scene, &scene.containers, options);
    sort_events(&mut events);
    if options.geometry() {
        for e in &mut events {
            let s = store.get(e.sphere as usize).expect("a sphere of the scene");
            let other = scene.body(e.other).expect("a body of the scene");
            e.geometry = Some(contact_at(&s, &other, e.time.into()));
        }
    }
    events
}
