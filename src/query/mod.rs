//! The whole-scene query: a scene and a window in; out the first contact of each sphere, or
//! every contact in the window (each pair once), with geometry only when asked.
//!
//! Pipeline, one named stage each (docs/ARCHITECTURE.md):
//! 1. **cells**: a uniform grid over the spheres' swept boxes ([`crate::broad`]) puts the
//!    spheres in cell order;
//! 2. **records**: the spheres are copied into that order, so the narrow phase reads
//!    neighbours from nearby memory;
//! 3. **fused pairs**: the grid hands its candidate pairs on a few thousand at a time and the
//!    8-wide pair kernel runs on them at once; each hit goes straight to the two spheres'
//!    slots (the earliest, as a [`CompactContact`]) or to the contact list (`fused.rs`);
//! 4. **statics**: every sphere against every plane, cylinder and container, 8 at a time; a
//!    scene without shapes of a kind never runs that kind's kernel;
//! 5. **answer**: the slots in the caller's order (8 bytes a sphere), or every contact sorted
//!    by time;
//! 6. **geometry**: points and normals for the reported contacts, only if asked for.
//!
//! No stage holds a list of all candidate pairs, so memory is linear in the number of spheres
//! whatever the window (plus the contacts themselves for [`all_contacts`]). An infinite window
//! has unbounded swept boxes: it is answered by successive finite windows, then the brute
//! force's rows for the spheres still open (`unbounded.rs`), with the brute force's bits.
//! The passes run on rayon (all but the grid's counting sort, 2 % of the time); the answers
//! are the same bits for any thread count.

pub mod brute_force;
mod compact;
pub mod estimate;
mod fused;
mod unbounded;

pub use compact::{CompactContact, MAX_INDEX};

/// A scene of these spheres and no static shape (the query's unit tests).
#[cfg(test)]
fn scene_of(spheres: &[crate::Sphere]) -> Scene {
    Scene {
        spheres: SphereStore::from_spheres(spheres),
        ..Scene::default()
    }
}

use crate::batch::{self, FirstContact, QueryOptions, StaticShape};
use crate::broad::{Grid, GridOptions};
use crate::contact::{Body, Contact, contact_at};
use crate::scene::Scene;
use crate::statics::{OfKind, Visitor};
use crate::store::SphereStore;
use compact::Slots;

/// One contact in the window: sphere `sphere` touches `other` at `time`. For two spheres,
/// `sphere` is the lower index and each pair appears once.
///
/// ```
/// use spheresweep::{Body, QueryOptions, ShapeKind, query::all_contacts};
/// # use spheresweep::{Plane, Sphere, SphereStore, Statics, scene::Scene};
/// # let scene = Scene {
/// #     spheres: SphereStore::from_spheres(&[
/// #         Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?, // reaches sphere 1 at t = 4
/// #         Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
/// #         Sphere::new([0.0, 20.0, -6.0], [0.0, 0.0, -1.0], 1.0, 1.0)?, // the floor at t = 3
/// #     ]),
/// #     statics: Statics::new().with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?, ()),
/// # };
/// let events = all_contacts(&scene, QueryOptions::default());
/// assert_eq!(events.len(), 2);
/// let pair = &events[1]; // sorted by time: the floor at 3 comes first
/// assert_eq!((pair.time, pair.sphere, pair.other), (4.0, 0, Body::new(ShapeKind::Sphere, 1)));
/// # Ok::<(), spheresweep::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactEvent {
    /// Time of impact in `[0, t_max]`.
    pub time: f32,
    /// The sphere (its index in the scene).
    pub sphere: u32,
    /// What it touches.
    pub other: Body,
    /// Centres, contact point and normal at `time`, if asked for.
    pub geometry: Option<Contact>,
}

/// What the last query did: the broad phase's grid and the work each stage saw.
///
/// ```
/// use spheresweep::{Accuracy, QueryOptions, query::SceneQuery};
/// # use spheresweep::{Plane, Sphere, SphereStore, Statics, scene::Scene};
/// # let scene = Scene {
/// #     spheres: SphereStore::from_spheres(&[
/// #         Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?, // reaches sphere 1 at t = 4
/// #         Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
/// #         Sphere::new([0.0, 20.0, -6.0], [0.0, 0.0, -1.0], 1.0, 1.0)?, // the floor at t = 3
/// #     ]),
/// #     statics: Statics::new().with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?, ()),
/// # };
/// let mut query = SceneQuery::new();
/// query.first_contacts(&scene, QueryOptions::new(10.0, Accuracy::Stable)?);
/// let stats = query.stats();
/// assert_eq!((stats.spheres, stats.grid), (3, true));
/// assert_eq!(stats.candidate_pairs, 1); // only spheres 0 and 1 have overlapping swept boxes
/// # Ok::<(), spheresweep::Error>(())
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct QueryStats {
    /// Spheres in the scene.
    pub spheres: usize,
    /// Candidate sphere pairs from the broad phase (all pairs for an infinite window).
    pub candidate_pairs: usize,
    /// Edge of a grid cell (0 when the grid was not used).
    pub cell_size: f32,
    /// Spheres too large or too fast for the cells, tested against all.
    pub oversize: usize,
    /// Whether the broad phase ran (false for an infinite window or fewer than two spheres).
    pub grid: bool,
}

/// A reusable whole-scene query: it keeps the grid, its cell order and its buffers between
/// calls, so a scene that moved a little re-sorts cheaply and no call allocates once the
/// buffers have grown.
///
/// ```
/// use spheresweep::{Accuracy, Body, QueryOptions, ShapeKind, query::SceneQuery};
/// let scene = spheresweep::scene::demo();
/// let mut query = SceneQuery::new();
/// let hits = query.first_contacts(&scene, QueryOptions::new(10.0, Accuracy::Stable)?);
/// assert_eq!(hits[0].unwrap().body, Body::new(ShapeKind::Sphere, 1));
/// assert_eq!(hits[2].unwrap().body, Body::new(ShapeKind::Plane, 0));
/// # Ok::<(), spheresweep::Error>(())
/// ```
#[derive(Debug, Default)]
pub struct SceneQuery {
    grid: Grid,
    options: GridOptions,
    /// Each sphere's earliest contact with a sphere, by cell position.
    slots: Slots,
    /// The compact answer behind [`first_contacts_into`](Self::first_contacts_into).
    compact: Vec<CompactContact>,
    stats: QueryStats,
}

impl SceneQuery {
    /// A query with the grid's automatic cell size.
    ///
    /// ```
    /// use spheresweep::{QueryOptions, query::SceneQuery};
    /// # use spheresweep::{Plane, Sphere, SphereStore, Statics, scene::Scene};
    /// # let scene = Scene {
    /// #     spheres: SphereStore::from_spheres(&[
    /// #         Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?, // reaches sphere 1 at t = 4
    /// #         Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #         Sphere::new([0.0, 20.0, -6.0], [0.0, 0.0, -1.0], 1.0, 1.0)?, // the floor at t = 3
    /// #     ]),
    /// #     statics: Statics::new().with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?, ()),
    /// # };
    /// let mut query = SceneQuery::new();
    /// let hits = query.first_contacts(&scene, QueryOptions::default());
    /// assert_eq!(hits.iter().map(|h| h.unwrap().time).collect::<Vec<_>>(), [4.0, 4.0, 3.0]);
    /// # Ok::<(), spheresweep::Error>(())
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// A query with the given grid options (e.g. a fixed cell size).
    ///
    /// ```
    /// use spheresweep::{Accuracy, QueryOptions, broad::GridOptions, query::SceneQuery};
    /// # use spheresweep::{Plane, Sphere, SphereStore, Statics, scene::Scene};
    /// # let scene = Scene {
    /// #     spheres: SphereStore::from_spheres(&[
    /// #         Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?, // reaches sphere 1 at t = 4
    /// #         Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #         Sphere::new([0.0, 20.0, -6.0], [0.0, 0.0, -1.0], 1.0, 1.0)?, // the floor at t = 3
    /// #     ]),
    /// #     statics: Statics::new().with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?, ()),
    /// # };
    /// let grid = GridOptions { cell_size: Some(16.0), ..GridOptions::default() };
    /// let mut query = SceneQuery::with_grid_options(grid);
    /// query.first_contacts(&scene, QueryOptions::new(10.0, Accuracy::Stable)?);
    /// assert_eq!(query.stats().cell_size, 16.0);
    /// # Ok::<(), spheresweep::Error>(())
    /// ```
    pub fn with_grid_options(options: GridOptions) -> Self {
        Self {
            options,
            ..Self::default()
        }
    }

    /// The scene indices in the cell order of the last query's grid (empty after a query that
    /// used no grid). A caller that keeps its spheres in this order
    /// ([`SphereStore::gathered`]) makes the next query read them in sequence; the answers
    /// stay in the order of the scene it is given.
    ///
    /// ```
    /// use spheresweep::{Accuracy, QueryOptions, query::SceneQuery, scene::Scene};
    /// let mut scene = spheresweep::scene::demo();
    /// let mut query = SceneQuery::new();
    /// let options = QueryOptions::new(1.0, Accuracy::Stable)?;
    /// let before = query.first_contacts(&scene, options);
    /// let order = query.cell_order().to_vec();
    /// scene.spheres = scene.spheres.gathered(&order)?; // the caller's store in cell order
    /// let after = query.first_contacts(&scene, options);
    /// for (k, &i) in order.iter().enumerate() {
    ///     assert_eq!(after[k].map(|c| c.time), before[i as usize].map(|c| c.time));
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn cell_order(&self) -> &[u32] {
        if self.stats.grid {
            self.grid.order()
        } else {
            &[]
        }
    }

    /// What the last call did.
    ///
    /// ```
    /// use spheresweep::{QueryOptions, query::SceneQuery};
    /// # use spheresweep::{Plane, Sphere, SphereStore, Statics, scene::Scene};
    /// # let scene = Scene {
    /// #     spheres: SphereStore::from_spheres(&[
    /// #         Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?, // reaches sphere 1 at t = 4
    /// #         Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #         Sphere::new([0.0, 20.0, -6.0], [0.0, 0.0, -1.0], 1.0, 1.0)?, // the floor at t = 3
    /// #     ]),
    /// #     statics: Statics::new().with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?, ()),
    /// # };
    /// let mut query = SceneQuery::new();
    /// query.all_contacts(&scene, QueryOptions::default()); // an infinite window: no grid
    /// assert_eq!((query.stats().grid, query.stats().candidate_pairs), (false, 3));
    /// # Ok::<(), spheresweep::Error>(())
    /// ```
    pub fn stats(&self) -> QueryStats {
        self.stats
    }

    /// For every sphere of `scene`, its earliest contact in the window (ties: spheres, then
    /// planes, cylinders, containers, each by index), with geometry if the options ask.
    ///
    /// ```
    /// use spheresweep::{Body, QueryOptions, ShapeKind, query::SceneQuery};
    /// # use spheresweep::{Plane, Sphere, SphereStore, Statics, scene::Scene};
    /// # let scene = Scene {
    /// #     spheres: SphereStore::from_spheres(&[
    /// #         Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?, // reaches sphere 1 at t = 4
    /// #         Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #         Sphere::new([0.0, 20.0, -6.0], [0.0, 0.0, -1.0], 1.0, 1.0)?, // the floor at t = 3
    /// #     ]),
    /// #     statics: Statics::new().with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?, ()),
    /// # };
    /// let options = QueryOptions::default().with_geometry(true);
    /// let hits = SceneQuery::new().first_contacts(&scene, options);
    /// let floor = hits[2].unwrap();
    /// assert_eq!((floor.time, floor.body), (3.0, Body::new(ShapeKind::Plane, 0)));
    /// assert_eq!(floor.geometry.unwrap().point.z, -10.0);
    /// # Ok::<(), spheresweep::Error>(())
    /// ```
    pub fn first_contacts(
        &mut self,
        scene: &Scene,
        options: QueryOptions,
    ) -> Vec<Option<FirstContact>> {
        let mut best = Vec::new();
        self.first_contacts_into(scene, options, &mut best);
        best
    }

    /// [`first_contacts`](Self::first_contacts) into a vector the caller keeps between calls
    /// (cleared, then one entry per sphere): no allocation once it has grown, and no fresh
    /// pages to fault in — at a million spheres that is most of the output's cost.
    ///
    /// ```
    /// use spheresweep::{QueryOptions, query::SceneQuery};
    /// # use spheresweep::{Plane, Sphere, SphereStore, Statics, scene::Scene};
    /// # let scene = Scene {
    /// #     spheres: SphereStore::from_spheres(&[
    /// #         Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?, // reaches sphere 1 at t = 4
    /// #         Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #         Sphere::new([0.0, 20.0, -6.0], [0.0, 0.0, -1.0], 1.0, 1.0)?, // the floor at t = 3
    /// #     ]),
    /// #     statics: Statics::new().with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?, ()),
    /// # };
    /// let (mut query, mut hits) = (SceneQuery::new(), Vec::new());
    /// for _ in 0..2 {
    ///     query.first_contacts_into(&scene, QueryOptions::default(), &mut hits);
    /// }
    /// assert_eq!(hits.len(), 3); // cleared before each call, one entry per sphere
    /// assert_eq!(hits, query.first_contacts(&scene, QueryOptions::default()));
    /// # Ok::<(), spheresweep::Error>(())
    /// ```
    pub fn first_contacts_into(
        &mut self,
        scene: &Scene,
        options: QueryOptions,
        best: &mut Vec<Option<FirstContact>>,
    ) {
        let mut compact = std::mem::take(&mut self.compact);
        self.first_contacts_compact_into(scene, options, &mut compact);
        best.clear();
        best.extend(compact.iter().map(|c| {
            c.get().map(|(time, body)| FirstContact {
                time,
                body,
                geometry: None,
            })
        }));
        self.compact = compact;
        if options.geometry() {
            for (i, slot) in best.iter_mut().enumerate() {
                if let Some(hit) = slot {
                    hit.geometry = Some(geometry(scene, i as u32, hit.body, hit.time));
                }
            }
        }
    }

    /// Each sphere's earliest contact in 8 bytes ([`CompactContact`]), into a vector the
    /// caller keeps (cleared, then one entry per sphere): the fastest form of the answer.
    /// Geometry, if wanted, comes from [`geometry_of`] for just the contacts that need it.
    ///
    /// # Panics
    /// If a kind of static shape has more than [`MAX_INDEX`] shapes.
    ///
    /// ```
    /// use spheresweep::{Body, QueryOptions, ShapeKind, query::{CompactContact, SceneQuery}};
    /// let scene = spheresweep::scene::demo();
    /// let (mut query, mut hits) = (SceneQuery::new(), Vec::new());
    /// query.first_contacts_compact_into(&scene, QueryOptions::default(), &mut hits);
    /// assert_eq!(hits.len(), scene.spheres.len());
    /// assert_eq!(hits[2].body(), Some(Body::new(ShapeKind::Plane, 0)));
    /// assert_eq!(std::mem::size_of::<CompactContact>(), 8);
    /// ```
    pub fn first_contacts_compact_into(
        &mut self,
        scene: &Scene,
        options: QueryOptions,
        out: &mut Vec<CompactContact>,
    ) {
        let store = &scene.spheres;
        let n = store.len();
        out.clear();
        out.resize(n, CompactContact::NONE);
        let t_max = options.t_max();
        let candidates = if n < 2 {
            0
        } else if t_max.is_finite() {
            self.sphere_firsts_in_window(store, options, out)
        } else {
            self.sphere_firsts_unbounded(store, options, out)
        };
        self.record_stats(n, candidates, t_max);
        scene.statics.visit(&mut OfferStatics {
            out,
            store,
            options: options.with_geometry(false),
        });
    }

    /// Every contact in the window: each sphere pair once (the lower index first), and every
    /// sphere with every static shape it touches, sorted by time, then sphere, then body.
    ///
    /// ```
    /// use spheresweep::{QueryOptions, ShapeKind, query::SceneQuery};
    /// # use spheresweep::{Plane, Sphere, SphereStore, Statics, scene::Scene};
    /// # let scene = Scene {
    /// #     spheres: SphereStore::from_spheres(&[
    /// #         Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?, // reaches sphere 1 at t = 4
    /// #         Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #         Sphere::new([0.0, 20.0, -6.0], [0.0, 0.0, -1.0], 1.0, 1.0)?, // the floor at t = 3
    /// #     ]),
    /// #     statics: Statics::new().with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?, ()),
    /// # };
    /// let events = SceneQuery::new().all_contacts(&scene, QueryOptions::default());
    /// let kinds: Vec<_> = events.iter().map(|e| (e.time, e.sphere, e.other.kind)).collect();
    /// assert_eq!(kinds, [(3.0, 2, ShapeKind::Plane), (4.0, 0, ShapeKind::Sphere)]);
    /// # Ok::<(), spheresweep::Error>(())
    /// ```
    pub fn all_contacts(&mut self, scene: &Scene, options: QueryOptions) -> Vec<ContactEvent> {
        let store = &scene.spheres;
        let n = store.len();
        let mut events = Vec::new();
        let t_max = options.t_max();
        let candidates = if n < 2 {
            0
        } else if t_max.is_finite() {
            self.sphere_contacts_in_window(store, options, &mut events)
        } else {
            self.sphere_contacts_unbounded(store, options, &mut events)
        };
        self.record_stats(n, candidates, t_max);
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

    /// What the sphere stages did, for [`stats`](Self::stats).
    fn record_stats(&mut self, n: usize, candidates: usize, t_max: f32) {
        let grid = t_max.is_finite() && n >= 2;
        self.stats = QueryStats {
            spheres: n,
            candidate_pairs: candidates,
            cell_size: if grid { self.grid.cell_size() } else { 0.0 },
            oversize: if grid { self.grid.oversize() } else { 0 },
            grid,
        };
    }
}

/// The tie rule of every first-contact query: the earlier contact, and at equal times the
/// lower body (kind, then index).
#[inline]
fn earlier(time: f32, body: Body, than_time: f32, than_body: Body) -> bool {
    time < than_time || (time == than_time && body < than_body)
}

/// Keeps the earlier contact (see [`earlier`]).
#[inline]
fn offer(slot: &mut Option<FirstContact>, time: f32, body: Body) {
    if slot.is_none_or(|b| earlier(time, body, b.time, b.body)) {
        *slot = Some(FirstContact {
            time,
            body,
            geometry: None,
        });
    }
}

/// Each sphere's earliest contact with each kind of static shape, offered to its compact slot
/// ([`batch::earliest_static_contacts`]: every shape of the kind in one pass of the lane
/// groups, shapes a group cannot reach skipped).
struct OfferStatics<'a> {
    out: &'a mut [CompactContact],
    store: &'a SphereStore,
    options: QueryOptions,
}

impl<P> Visitor<P> for OfferStatics<'_> {
    fn visit<K: StaticShape>(&mut self, shapes: &OfKind<K, P>) {
        if shapes.is_empty() {
            return;
        }
        assert!(
            shapes.len() <= MAX_INDEX as usize + 1,
            "{} {}s: a first-contact query takes at most {} of a kind",
            shapes.len(),
            K::KIND.name(),
            MAX_INDEX as u64 + 1
        );
        let hits = batch::earliest_static_contacts(self.store, shapes.shapes(), self.options);
        for (slot, hit) in self.out.iter_mut().zip(hits) {
            if let Some(hit) = hit {
                *slot = (*slot).min(CompactContact::key(hit.time, hit.body));
            }
        }
    }
}

/// Every contact of every sphere with every static shape in the window, appended.
pub(crate) struct StaticEvents<'a> {
    pub events: &'a mut Vec<ContactEvent>,
    pub store: &'a SphereStore,
    pub options: QueryOptions,
}

impl<P> Visitor<P> for StaticEvents<'_> {
    fn visit<K: StaticShape>(&mut self, shapes: &OfKind<K, P>) {
        static_events(self.events, self.store, shapes.shapes(), self.options);
    }
}

fn static_events<K: StaticShape>(
    events: &mut Vec<ContactEvent>,
    store: &SphereStore,
    shapes: &[K],
    options: QueryOptions,
) {
    let mut times = vec![0.0; store.len()];
    for (j, shape) in shapes.iter().enumerate() {
        batch::static_times(store, shape, options, &mut times).expect("one slot per sphere");
        events.extend(
            times
                .iter()
                .enumerate()
                .filter(|(_, t)| t.is_finite())
                .map(|(i, &time)| ContactEvent {
                    time,
                    sphere: i as u32,
                    other: Body::new(K::KIND, j as u32),
                    geometry: None,
                }),
        );
    }
}

/// Time, then sphere, then body: a total order (times are finite), the same for any path.
fn sort_events(events: &mut [ContactEvent]) {
    events.sort_unstable_by(|a, b| {
        a.time
            .total_cmp(&b.time)
            .then(a.sphere.cmp(&b.sphere))
            .then(a.other.cmp(&b.other))
    });
}

fn geometry(scene: &Scene, sphere: u32, body: Body, time: f32) -> Contact {
    let s = scene
        .spheres
        .get(sphere as usize)
        .expect("a sphere of the scene");
    let other = scene.body(body).expect("a body the query found");
    contact_at(&s, &other, time.into())
}

/// Points and normals of compact answers ([`SceneQuery::first_contacts_compact_into`]) into
/// `out` (cleared, one entry per answer, `None` for no contact): geometry only where asked.
///
/// ```
/// use spheresweep::{QueryOptions, query::{SceneQuery, geometry_of}};
/// # use spheresweep::{Plane, Sphere, SphereStore, Statics, scene::Scene};
/// # let scene = Scene {
/// #     spheres: SphereStore::from_spheres(&[
/// #         Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?, // reaches sphere 1 at t = 4
/// #         Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
/// #         Sphere::new([0.0, 20.0, -6.0], [0.0, 0.0, -1.0], 1.0, 1.0)?, // the floor at t = 3
/// #     ]),
/// #     statics: Statics::new().with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0])?, ()),
/// # };
/// let (mut hits, mut points) = (Vec::new(), Vec::new());
/// SceneQuery::new().first_contacts_compact_into(&scene, QueryOptions::default(), &mut hits);
/// geometry_of(&scene, &hits, &mut points);
/// assert_eq!(points[2].unwrap().point.z, -10.0); // sphere 2 lands on the floor
/// assert_eq!(points[0].unwrap().point.x, 5.0); // spheres 0 and 1 meet half way
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub fn geometry_of(scene: &Scene, hits: &[CompactContact], out: &mut Vec<Option<Contact>>) {
    out.clear();
    out.extend(hits.iter().enumerate().map(|(i, c)| {
        c.get()
            .map(|(time, body)| geometry(scene, i as u32, body, time))
    }));
}

/// For every sphere of `scene`, its earliest contact: [`SceneQuery::first_contacts`] on a new
/// query (use a [`SceneQuery`] to keep its buffers and cell order between calls).
///
/// ```
/// use spheresweep::{Accuracy, Body, QueryOptions, ShapeKind, query::first_contacts};
/// let scene = spheresweep::scene::demo();
/// let hits = first_contacts(&scene, QueryOptions::new(10.0, Accuracy::Stable)?);
/// assert_eq!(hits[2].unwrap().body, Body::new(ShapeKind::Plane, 0));
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub fn first_contacts(scene: &Scene, options: QueryOptions) -> Vec<Option<FirstContact>> {
    SceneQuery::new().first_contacts(scene, options)
}

/// Every contact in the window: [`SceneQuery::all_contacts`] on a new query.
///
/// ```
/// use spheresweep::{QueryOptions, query::{SceneQuery, all_contacts}};
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
/// assert_eq!(all_contacts(&scene, options), SceneQuery::new().all_contacts(&scene, options));
/// assert_eq!(all_contacts(&scene, options)[0].time, 3.0);
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub fn all_contacts(scene: &Scene, options: QueryOptions) -> Vec<ContactEvent> {
    SceneQuery::new().all_contacts(scene, options)
}
