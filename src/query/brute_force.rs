//! The whole-scene query by brute force: every sphere against every sphere and every shape,
//! through the same 8-wide kernels, with no broad phase. Quadratic in the number of spheres;
//! it is what the grid query is tested against, bit for bit (`tests/query.rs`). The f64
//! specification of the same query is `reference::scene::first_contacts_brute_force`.

use super::{ContactEvent, StaticEvents, geometry, offer, sort_events};
use crate::batch::{self, FirstContact, QueryOptions};
use crate::contact::Body;
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
    // Every event offered to each sphere it involves, under the query's tie rule.
    for e in &events {
        offer(&mut best[e.sphere as usize], e.time, e.other);
        if e.other.kind == ShapeKind::Sphere {
            let this = Body::new(ShapeKind::Sphere, e.sphere);
            offer(&mut best[e.other.index as usize], e.time, this);
        }
    }
    if options.geometry() {
        for (i, slot) in best.iter_mut().enumerate() {
            if let Some(hit) = slot {
                hit.geometry = Some(geometry(scene, i as u32, hit.body, hit.time));
            }
        }
    }
    best
}

/// Every contact in the window, every pair tested, sorted by time, then sphere, then body.
///
/// ```
/// use spheresweep::{QueryOptions, query};
/// # use spheresweep::{Plane, Sphere, SphereStore, Statics, scene::Scene};
/// # let scene = Scene {
/// #     spheres: SphereStore::from_spheres(&[
/// #         Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?, // reaches sphere 1 at t = 4
/// #         Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
/// #         Sphere::new([0.0, 20.0, -6.0], [0.0, 0.0, -1.0], 1.0, 1.0)?, // the floor at t = 3
/// #     ]),
/// #     statics: Statics::new().with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?, ()),
/// # };
/// let options = QueryOptions::default();
/// let events = query::brute_force::all_contacts(&scene, options);
/// assert_eq!(events, query::all_contacts(&scene, options)); // the grid misses nothing
/// assert_eq!(events.iter().map(|e| e.time).collect::<Vec<_>>(), [3.0, 4.0]);
/// # Ok::<(), spheresweep::Error>(())
/// ```
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
    // The shapes are tested every sphere against every shape in the query too (no broad
    // phase there): the same function.
    scene.statics.visit(&mut StaticEvents {
        events: &mut events,
        store,
        options,
    });
    sort_events(&mut events);
    if options.geometry() {
        for e in &mut events {
            e.geometry = Some(geometry(scene, e.sphere, e.other, e.time));
        }
    }
    events
}
