//! The whole-scene query: a scene and a window in; out the first contact of each sphere, or
//! every contact in the window (each pair once), with geometry only when asked.
//!
//! Pipeline, one named stage each (docs/ARCHITECTURE.md):
//! 1. **broad phase**: a uniform grid over the spheres' swept boxes ([`crate::broad`]) gives
//!    every candidate sphere pair once, as positions in cell order;
//! 2. **sort**: the spheres are copied into that order, so the narrow phase reads neighbours
//!    from nearby memory;
//! 3. **narrow phase**: the candidate pairs go to the 8-wide kernels as index lanes
//!    ([`batch::pair_times`]);
//! 4. **statics**: every sphere against every plane, cylinder and container, 8 at a time; a
//!    scene without shapes of a kind never runs that kind's kernel;
//! 5. **reduce**: the earliest per sphere (ties: spheres, then planes, cylinders, containers,
//!    each by index), or every contact sorted by time;
//! 6. **geometry**: points and normals for the reported contacts, only if asked for.
//!
//! An infinite window has unbounded swept boxes: no broad phase can cull it, so every pair is
//! a candidate (quadratic in the number of spheres).

pub mod brute_force;
pub mod estimate;

use crate::batch::{self, FirstContact, QueryOptions, StaticShape};
use crate::broad::{Grid, GridOptions};
use crate::contact::{Body, Contact, contact_at};
use crate::scene::Scene;
use crate::shape::ShapeKind;
use crate::statics::{OfKind, Visitor};
use crate::store::{PackedSpheres, SphereStore};

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
    packed: PackedSpheres,
    sorted: PackedSpheres,
    pairs: Vec<[u32; 2]>,
    times: Vec<f32>,
    earliest: Vec<(f32, Body)>,
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
        let n = scene.spheres.len();
        self.sphere_pairs(scene, options);
        // Reduce in cell order, where a pair's two spheres sit near each other in memory, on
        // compact (time, body) records; then scatter once to the scene's order.
        let none = (f32::INFINITY, Body::new(ShapeKind::Sphere, u32::MAX));
        self.earliest.clear();
        self.earliest.resize(n, none);
        for (&[p, q], &time) in self.pairs.iter().zip(&self.times) {
            if !time.is_finite() {
                continue;
            }
            let (i, j) = (self.index(p), self.index(q));
            keep_earlier(
                &mut self.earliest[p as usize],
                time,
                Body::new(ShapeKind::Sphere, j),
            );
            keep_earlier(
                &mut self.earliest[q as usize],
                time,
                Body::new(ShapeKind::Sphere, i),
            );
        }
        best.clear();
        best.resize(n, None);
        for (p, &(time, body)) in self.earliest.iter().enumerate() {
            if time.is_finite() {
                best[self.index(p as u32) as usize] = Some(FirstContact {
                    time,
                    body,
                    geometry: None,
                });
            }
        }
        let times_only = options.with_geometry(false);
        scene.statics.visit(&mut MergeStatic {
            best,
            store: &scene.spheres,
            options: times_only,
        });
        if options.geometry() {
            for (i, slot) in best.iter_mut().enumerate() {
                if let Some(hit) = slot {
                    hit.geometry = Some(geometry(scene, i as u32, hit.body, hit.time));
                }
            }
        }
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
        self.sphere_pairs(scene, options);
        let mut events: Vec<ContactEvent> = self
            .pairs
            .iter()
            .zip(&self.times)
            .filter(|(_, t)| t.is_finite())
            .map(|(&[p, q], &time)| {
                let (i, j) = (self.index(p), self.index(q));
                ContactEvent {
                    time,
                    sphere: i.min(j),
                    other: Body::new(ShapeKind::Sphere, i.max(j)),
                    geometry: None,
                }
            })
            .collect();
        scene.statics.visit(&mut StaticEvents {
            events: &mut events,
            store: &scene.spheres,
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

    /// The scene index of the sphere at position `p` of the last broad phase.
    #[inline]
    fn index(&self, p: u32) -> u32 {
        if self.stats.grid {
            self.grid.order()[p as usize]
        } else {
            p
        }
    }

    /// Stages 1–3 for sphere pairs: fills `self.pairs` (positions, see [`Self::index`]) and
    /// `self.times`.
    fn sphere_pairs(&mut self, scene: &Scene, options: QueryOptions) {
        let store = &scene.spheres;
        let n = store.len();
        let t_max = options.t_max();
        let use_grid = t_max.is_finite() && n >= 2;
        self.pairs.clear();
        if use_grid {
            self.grid.build(store, t_max, self.options);
            self.pairs.extend_from_slice(self.grid.pairs());
            // Packed records first (one pass in order), then gathered into cell order: one
            // cache line per scattered sphere instead of the blocks' seven.
            self.packed.pack(store);
            self.sorted.permute_from(&self.packed, self.grid.order());
        } else {
            // No cull: every pair, in index order.
            for i in 0..n as u32 {
                self.pairs.extend((i + 1..n as u32).map(|j| [i, j]));
            }
            self.sorted.pack(store);
        }
        self.times.clear();
        self.times.resize(self.pairs.len(), 0.0);
        batch::pairs::listed_times(&self.sorted, &self.pairs, options, &mut self.times)
            .expect("the broad phase's positions are in range and one slot per pair");
        self.stats = QueryStats {
            spheres: n,
            candidate_pairs: self.pairs.len(),
            cell_size: if use_grid { self.grid.cell_size() } else { 0.0 },
            oversize: if use_grid { self.grid.oversize() } else { 0 },
            grid: use_grid,
        };
    }
}

/// The tie rule of every first-contact query: the earlier contact, and at equal times the
/// lower body (kind, then index).
#[inline]
fn earlier(time: f32, body: Body, than_time: f32, than_body: Body) -> bool {
    time < than_time || (time == than_time && body < than_body)
}

/// Keeps the earlier contact on a compact record (see [`earlier`]).
#[inline]
fn keep_earlier(slot: &mut (f32, Body), time: f32, body: Body) {
    if earlier(time, body, slot.0, slot.1) {
        *slot = (time, body);
    }
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

/// Each sphere's earliest contact with each kind of static shape, offered to its slot.
struct MergeStatic<'a> {
    best: &'a mut [Option<FirstContact>],
    store: &'a SphereStore,
    options: QueryOptions,
}

impl<P> Visitor<P> for MergeStatic<'_> {
    fn visit<K: StaticShape>(&mut self, shapes: &OfKind<K, P>) {
        if shapes.is_empty() {
            return;
        }
        let hits = batch::earliest_static_contacts(self.store, shapes.shapes(), self.options);
        for (slot, hit) in self.best.iter_mut().zip(hits) {
            if let Some(hit) = hit {
                offer(slot, hit.time, hit.body);
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
