//! The event-driven engine: every collision in exact time order, one pending event per sphere
//! in a calendar queue, neighbour lists with a shell (`lists.rs`), lazy positions with a
//! per-sphere time, and re-prediction of only the spheres an event touched.
//!
//! Stages of one event, in order (`step`): pop the earliest sphere's event (a re-predicted
//! sphere's older event was dropped from the calendar); then a shell event rebuilds the
//! sphere's list from the cells around its new centre and predicts it against the entries new
//! to it only; a pair event whose partner
//! changed since the prediction is predicted again; a real collision advances the bodies,
//! applies the [`Responder`] and predicts every changed sphere against its list in f64
//! (`predict`), leaving out the pairs that cannot meet before the sphere's shell event
//! when that event is far (`horizon`; the shell event then predicts the whole list). The cell
//! grid is touched only at shell events.
//!
//! The engine is generic over the response `R` and four switches fixed when it is assembled:
//! `PERIODIC` (wrap or clamp), `WALLS` (any static shape at all), `GEOMETRY` (contact point
//! and normal in the event log) and `GRAVITY` (parabolic paths, the walls' polynomials, a
//! bound on the shell exit, rest hops: docs/derivations/gravity.md), so a scene without them
//! runs none of their code.

use glam::DVec3;

use super::cells::{Cell, Cells, NONE};
use super::queue::Calendar;
use super::response::{Motion, Outcome, Responder, Trajectory, Wall};
use super::{EventRecord, SimError, Stats, walls};
use crate::contact::Body;
use crate::shape::ShapeKind;
use crate::statics::Statics;

mod ahead;
#[cfg(test)]
mod brute_check;
mod dispersal;
mod list_rebuild;
mod lists;
mod pair_prediction;
mod passes;
mod state;

pub(crate) use super::predict::Candidate;
pub(crate) use lists::MAX_SPHERES;
use lists::{NeighbourLists, Quotient, shell_exit_falling, shell_exit_quotient};
use pair_prediction::merge;

/// What a sphere's pending event is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Best {
    /// The two earliest predicted pair contacts (later ones are not kept).
    pub pairs: [Candidate; 2],
    /// Whether `pairs` held every pair contact predicted (else the others are later than
    /// `pairs[1]`, and an emptied list calls for a new prediction).
    pub complete: bool,
    /// Earliest static-shape contact, and the shape (its kind and index apart, so that the
    /// record packs into 56 bytes).
    pub wall_t: f64,
    pub wall_kind: ShapeKind,
    pub wall_index: u32,
    /// When the sphere leaves its shell (its list is then rebuilt).
    pub shell_t: f64,
    /// Whether the prediction left out approaching pairs that meet no earlier than `shell_t`
    /// (the shell event then predicts the whole list again).
    pub beyond: bool,
}

// Seven records a cache line's worth of eight: the prediction is read at every event.
const _: () = assert!(std::mem::size_of::<Best>() == 56);

impl Default for Best {
    fn default() -> Self {
        Self {
            pairs: [Candidate::NONE; 2],
            complete: true,
            wall_t: f64::INFINITY,
            wall_kind: ShapeKind::Plane,
            wall_index: 0,
            shell_t: f64::INFINITY,
            beyond: false,
        }
    }
}

/// The kinds of a sphere's pending event (`Best::next_event`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NextEvent {
    /// Leaving its shell: its list is rebuilt.
    Shell,
    /// Meeting `pairs[0]`'s sphere.
    Pair,
    /// Meeting a static shape.
    Wall,
}

impl Best {
    /// The earliest of its events: as `f64::min` would pick it (a NaN `wall_t` or `shell_t`
    /// is passed over; a pair's time is never NaN), in one compare and move each rather than
    /// `min`'s three instructions.
    #[inline]
    fn time(&self) -> f64 {
        let least = |a: f64, b: f64| if b < a { b } else { a };
        least(least(self.pairs[0].t, self.wall_t), self.shell_t)
    }

    /// Which of its events the sphere meets first (ties go to the shell, then the pair).
    #[inline]
    fn next_event(&self) -> NextEvent {
        if self.shell_t <= self.pairs[0].t && self.shell_t <= self.wall_t {
            NextEvent::Shell
        } else if self.pairs[0].t <= self.wall_t {
            NextEvent::Pair
        } else {
            NextEvent::Wall
        }
    }

    /// The shape of the earliest static-shape contact.
    #[inline]
    fn wall(&self) -> Body {
        Body::new(self.wall_kind, self.wall_index)
    }
}

/// Everything that is not the response: the engine state.
pub(crate) struct Engine<
    R: Responder,
    const PERIODIC: bool,
    const WALLS: bool,
    const GEOMETRY: bool,
    const GRAVITY: bool,
> {
    pub m: Motion,
    pub best: Vec<Best>,
    pub cells: Cells,
    /// Each sphere's neighbour list and shell centre.
    lists: NeighbourLists,
    /// The periodic shift of each list entry's shift code, in lanes of four (the fourth zero).
    shift: pair_prediction::ShiftLanes,
    /// The cells around each cell, per axis (`list_rebuild.rs`).
    stencil: list_rebuild::StencilTable,
    queue: Calendar,
    pub now: f64,
    pub walls: Statics<u16>,
    pub responder: R,
    pub stats: Stats,
    pub log: Option<Vec<EventRecord>>,
    /// A rebuild's entries from the cells near (and from the cells' spills), those within
    /// reach, and those of them new to the sphere.
    gathered: Vec<u32>,
    spilled: Vec<u32>,
    found: Vec<u32>,
    fresh: Vec<u32>,
    /// How many of `fresh`'s entries are new (the rest, up to a multiple of four, are zeros).
    fresh_len: usize,
    /// A rebuild's copy of the list it replaces.
    old: Vec<u32>,
    /// A prediction's list entries to answer (the approaching neighbours).
    near: Vec<u32>,
    /// Whether each event also asks ahead for the next sphere's neighbours
    /// (`ahead::FETCH_NEIGHBOURS_FROM`).
    fetch_neighbours: bool,
    /// Whether a sphere is at most once in any list (three cells a side, or an open domain),
    /// so that a rebuild may predict the entries new to it alone.
    once_per_list: bool,
    outcome: Outcome,
    /// The stall watchdog: events since time last advanced by at least `min_progress`.
    same_time: u64,
    stall_limit: u64,
    window_start: f64,
    min_progress: f64,
    /// Test-only: check the prediction invariant after every event, against each sphere's
    /// time in the calendar (`+∞` while it has none).
    #[cfg(test)]
    pub checking: bool,
    #[cfg(test)]
    scheduled: Vec<f64>,
    /// Test-only: predictions that left pairs out past their horizon, and the fault injection
    /// that makes the horizon a quarter of the shell time (`Run::break_horizon`).
    #[cfg(test)]
    pub left_out: u64,
    #[cfg(test)]
    pub broken_horizon: bool,
    /// Each internal index's public sphere index: spheres are renumbered in cell order every
    /// `reorder_every` events, so that neighbours sit close in memory.
    pub id_of: Vec<u32>,
    pub reorder_every: u64,
    since_reorder: u64,
    pub(super) width: f64,
    /// Fault injection for the tests that show the invariant check fires: the concave-wall
    /// floor off and the old container policy (see `Simulation::break_walls_for_testing`).
    pub broken_walls: bool,
    /// Periodic boxes only (else empty): how many times each sphere has been wrapped across
    /// each axis (`+1` leaving through the upper face), so that its unwrapped position is its
    /// position plus `images · len`.
    pub images: Vec<[i64; 3]>,
    /// Whether an open scene's spheres have flown apart for good (`dispersal.rs`).
    dispersal: dispersal::Dispersal,
    /// Parked only (else empty): how far from the origin each sphere may go
    /// (`Engine::never_meet`); derived, not in a checkpoint.
    reach: Vec<f64>,
}

/// Bytes an engine for `n` spheres holds when built on a grid of at most `max_cells` cells,
/// from the sizes of its arrays (the ones [`Engine::bytes`] counts) as [`Engine::new`] sizes
/// them: per sphere its body, mass, material, counter, prediction, order, shell record and a
/// list of [`LIST_ESTIMATE`] entries; the calendar (a slot per sphere, a bucket
/// head per sphere rounded up to a power of two) and a 32-byte record per cell. Known before
/// anything is allocated.
pub(crate) fn estimated_bytes(n: usize, max_cells: usize) -> usize {
    use std::mem::size_of;
    let per_sphere = size_of::<Trajectory>()
        + size_of::<f64>()
        + size_of::<u16>()
        + size_of::<u32>()
        + size_of::<Best>()
        + size_of::<u32>()
        // The shell record, the list's count and rebuild mark, its entries.
        + size_of::<lists::Shell>()
        + 2 * size_of::<u32>()
        + LIST_ESTIMATE * size_of::<u32>();
    // The grid's record per cell, as `Cells::new` makes them.
    let per_cell = size_of::<Cell>();
    n.saturating_mul(per_sphere)
        .saturating_add(Calendar::estimated_bytes(n, n))
        .saturating_add(max_cells.saturating_mul(per_cell))
}

/// List entries per sphere the estimate counts: a list holds about `8φ(1 + s)³` entries at
/// volume fraction `φ` with shell `s` (times the largest diameter), 14 at φ = 0.5.
const LIST_ESTIMATE: usize = 24;

impl<
    R: Responder,
    const PERIODIC: bool,
    const WALLS: bool,
    const GEOMETRY: bool,
    const GRAVITY: bool,
> Engine<R, PERIODIC, WALLS, GEOMETRY, GRAVITY>
{
    /// Assembles the engine at time 0 with shells of half-width `delta`, builds every list and
    /// predicts every sphere.
    pub fn new(
        m: Motion,
        cells: Cells,
        delta: f64,
        walls: Statics<u16>,
        responder: R,
        log: bool,
    ) -> Self {
        let n = m.bodies.len();
        let centres = crate::sim::pages::collected(m.bodies.iter().map(|b| lists::Shell {
            c: b.r,
            radius: b.radius,
        }));
        let mut e = Self {
            lists: NeighbourLists::new(delta, centres),
            shift: pair_prediction::shift_lanes(lists::shifts(cells.len, PERIODIC)),
            stencil: list_rebuild::StencilTable::new(&cells, PERIODIC),
            once_per_list: !PERIODIC || cells.n.iter().all(|&k| k >= 3),
            fetch_neighbours: n >= ahead::FETCH_NEIGHBOURS_FROM,
            best: crate::sim::pages::filled(Best::default(), n),
            cells,
            queue: Calendar::new(1.0, 2, n, 0.0),
            now: 0.0,
            walls,
            responder,
            stats: Stats::default(),
            log: log.then(Vec::new),
            gathered: Vec::new(),
            spilled: Vec::new(),
            found: Vec::new(),
            fresh: Vec::new(),
            fresh_len: 0,
            old: Vec::new(),
            near: Vec::new(),
            outcome: Outcome::default(),
            same_time: 0,
            stall_limit: 1_000_000 + 1000 * n as u64,
            window_start: 0.0,
            min_progress: 0.0,
            #[cfg(test)]
            checking: false,
            #[cfg(test)]
            scheduled: vec![f64::INFINITY; n],
            #[cfg(test)]
            left_out: 0,
            #[cfg(test)]
            broken_horizon: false,
            id_of: (0..n as u32).collect(),
            reorder_every: 32 * n as u64 + 1024,
            since_reorder: 0,
            width: 1.0,
            broken_walls: false,
            images: if PERIODIC {
                vec![[0; 3]; n]
            } else {
                Vec::new()
            },
            dispersal: dispersal::Dispersal::new(n),
            reach: Vec::new(),
            m,
        };
        for i in 0..n as u32 {
            let c = e.cells.coords_of(e.m.bodies[i as usize].r);
            e.cells.insert(i, c);
        }
        e.build_lists();
        for i in 0..n as u32 {
            e.predict(i);
        }
        e.size_calendar();
        // Start in cell order (this also fills the calendar).
        e.reorder();
        e
    }

    /// Sizes the calendar from the predictions just made (at the start, or for new
    /// velocities): buckets about two pending events wide (over the spheres with an event: a
    /// packing at rest with one sphere moving would otherwise step through half the buckets
    /// between two of its events); the responder's time scale and the stall watchdog's least
    /// progress follow from the mean time to an event over every sphere.
    fn size_calendar(&mut self) {
        let n = self.m.bodies.len();
        let now = self.now;
        let finite: Vec<f64> = self
            .best
            .iter()
            .map(|b| b.time() - now)
            .filter(|t| t.is_finite())
            .collect();
        let mean = if finite.is_empty() {
            1.0
        } else {
            finite.iter().sum::<f64>() / finite.len() as f64
        };
        let over = |count: usize| {
            let width = (2.0 * mean / count.max(1) as f64).max(f64::MIN_POSITIVE * 1e10);
            if width.is_finite() && width > 0.0 {
                width
            } else {
                1.0
            }
        };
        let (width, per_sphere) = (over(finite.len()), over(n));
        // The calendar itself is built by `reschedule`, which every caller runs next.
        self.width = width;
        self.responder
            .set_time_scale(per_sphere * n.max(1) as f64 / 2.0);
        // Progress the stall watchdog asks for: 2⁻³⁰ of a sphere's mean time between events
        // (the time scale is 2²⁹ times it: `Engine::load` takes it from there).
        self.min_progress = per_sphere * n as f64 / (1u64 << 30) as f64;
    }

    /// Advances every event up to and including time `t_end`; stops early (returning `false`)
    /// when `keep_going` says so, which it is asked every 4096 events.
    pub fn run_until(
        &mut self,
        t_end: f64,
        keep_going: &mut dyn FnMut(f64, &Stats) -> bool,
    ) -> Result<bool, SimError> {
        let mut tick = 0u32;
        while let Some((t, i)) = self.queue.pop() {
            if t > t_end {
                self.queue.schedule(i, t);
                break;
            }
            self.now = self.now.max(t);
            if self.now - self.window_start > self.min_progress {
                self.same_time = 0;
                self.window_start = self.now;
            } else {
                self.same_time += 1;
                if self.same_time > self.stall_limit {
                    return Err(SimError::Stalled {
                        time: self.now,
                        events: self.same_time,
                        inelastic: R::INELASTIC,
                    });
                }
            }
            #[cfg(test)]
            {
                self.scheduled[i as usize] = f64::INFINITY;
            }
            self.fetch_next();
            if self.fetch_neighbours {
                self.fetch_partner_neighbours(i);
            }
            self.step(i);
            if self.fetch_neighbours {
                self.fetch_next_neighbours();
            }
            if let Some(s) = self.outcome.collapsing.take() {
                return Err(SimError::Collapse {
                    time: self.now,
                    sphere: self.id_of[s as usize] as usize,
                    collisions: u64::from(super::response::RAPID_LIMIT),
                });
            }
            #[cfg(test)]
            if self.checking {
                self.check_invariant(i);
            }
            self.since_reorder += 1;
            if self.since_reorder >= self.reorder_every {
                self.since_reorder = 0;
                self.reorder();
            }
            tick += 1;
            if tick == 4096 {
                tick = 0;
                if !keep_going(self.now, &self.stats) {
                    return Ok(false);
                }
            }
        }
        if !PERIODIC {
            self.check_flight(t_end)?;
        }
        self.now = self.now.max(t_end);
        Ok(true)
    }

    /// One event of sphere `i` at `self.now`.
    #[inline]
    fn step(&mut self, i: u32) {
        let b = self.best[i as usize];
        match b.next_event() {
            NextEvent::Shell => {
                self.leave_shell(i);
                self.note_quiet(true);
            }
            NextEvent::Pair => {
                self.note_quiet(false);
                let c = b.pairs[0];
                if self.m.counter[c.j as usize] == c.counter {
                    self.collide_pair(i, c.j);
                } else {
                    // The partner changed: its own prediction covers this pair. The next kept
                    // candidate takes over, or, if none is left and some were not kept, predict.
                    self.stats.stale += 1;
                    if self.prune(i) {
                        let anchor = self.m.bodies[i as usize];
                        self.predict(i);
                        self.keep_anchor(i, anchor);
                    }
                    self.schedule(i);
                }
            }
            NextEvent::Wall => {
                self.note_quiet(false);
                self.collide_wall(i, b.wall());
            }
        }
    }

    /// Drops sphere `i`'s stale pair candidates; `true` when none is left but some were not
    /// kept (a full prediction is then due).
    #[inline]
    fn prune(&mut self, i: u32) -> bool {
        let counter = &self.m.counter;
        let b = &mut self.best[i as usize];
        let valid = |c: &Candidate| c.t.is_finite() && counter[c.j as usize] == c.counter;
        let (v0, v1) = (valid(&b.pairs[0]), valid(&b.pairs[1]));
        b.pairs = match (v0, v1) {
            (true, true) => b.pairs,
            (true, false) => [b.pairs[0], Candidate::NONE],
            (false, true) => [b.pairs[1], Candidate::NONE],
            (false, false) => [Candidate::NONE; 2],
        };
        !b.pairs[0].t.is_finite() && !b.complete
    }

    /// Sphere `i` leaves its shell: its centre moves to where it is (into the box, periodic),
    /// its list is rebuilt, and it is predicted against the entries new to it (the others are
    /// covered by the candidates it keeps or by their own predictions).
    fn leave_shell(&mut self, i: u32) {
        self.stats.crossings += 1;
        let anchor = self.m.bodies[i as usize];
        self.advance(i);
        let mut crossed = false;
        if PERIODIC {
            let len = self.cells.len;
            let r = &mut self.m.bodies[i as usize].r;
            for k in 0..3 {
                if r[k] < 0.0 {
                    r[k] += len[k];
                    self.images[i as usize][k] -= 1;
                    crossed = true;
                } else if r[k] >= len[k] {
                    r[k] -= len[k];
                    self.images[i as usize][k] += 1;
                    crossed = true;
                }
            }
        }
        let r = self.m.bodies[i as usize].r;
        let was = self.cells.coords_of(self.lists.centre[i as usize].c);
        self.lists.centre[i as usize].c = r;
        let c = self.cells.coords_of(r);
        if c != was {
            self.cells.remove(i, was);
            self.cells.insert(i, c);
        }
        self.rebuild_list(i, c, self.once_per_list);
        // A wrapped sphere's static contacts were predicted from its place a box length away,
        // where the shapes (which have no images) are not: they are predicted again with all.
        if self.prune(i)
            || !self.once_per_list
            || self.best[i as usize].beyond
            || (WALLS && crossed)
        {
            self.predict(i);
        } else {
            let horizon = self.predict_shell(i);
            let (fresh, fresh_complete, beyond) = self.predict_pairs(i, true, horizon);
            let bi = &mut self.best[i as usize];
            (bi.pairs, bi.complete) = merge((bi.pairs, bi.complete), (fresh, fresh_complete));
            bi.beyond = beyond;
        }
        self.keep_anchor(i, anchor);
        self.schedule(i);
    }

    /// In an open domain without gravity, sphere `i`'s body goes back to where it was before
    /// an event that did not change its velocity (a shell event, a stale pair event) moved it
    /// to now: its position is then always its line from its last velocity change, rounded
    /// once, not once per shell event (a free flight `10⁸` from the origin drifted by
    /// `2.7·10⁻³` over `3·10⁶` shell events). A periodic body wraps at its shell events, and
    /// a falling one keeps its parabola's own time.
    #[inline(always)]
    fn keep_anchor(&mut self, i: u32, anchor: Trajectory) {
        if !PERIODIC && !GRAVITY {
            self.m.bodies[i as usize] = anchor;
        }
    }

    fn collide_pair(&mut self, i: u32, j: u32) {
        let now = self.now;
        self.advance(i);
        self.advance(j);
        let (bi, bj) = (self.m.bodies[i as usize], self.m.bodies[j as usize]);
        let mut dr = bj.r - bi.r;
        if PERIODIC {
            // The nearest image by a product, not a quotient: the division sat on the chain from
            // the collision to the next predictions. The two round alike unless `dr / len` is
            // within a few ulps of a half-integer, and a colliding pair's nearest image is one
            // contact distance away, at most a third of a box length (`assemble.rs`), so each
            // component of `dr` is within a third of a box length of a whole number of them.
            let len = self.cells.len;
            dr -= len * (dr * self.cells.inv_len).round();
        }
        let d = bi.radius + bj.radius;
        // The quotient only when it may be a new largest: its division held up the chain
        // to the next predictions. The test by a product can differ from one by the quotient
        // only when the two are within an ulp of each other.
        let depth = d - dr.length();
        #[cfg(test)]
        if self.checking {
            // A pair collides in contact, not at a distance. The brute-force check sees only
            // collisions missed: every contact time made 10 % early passed it, and this fails.
            assert!(
                -depth <= crate::sim::OVERLAP_TOLERANCE * d,
                "spheres {i} and {j} collide at t = {now} {:e} apart",
                -depth
            );
        }
        if depth >= self.stats.max_overlap * d {
            self.stats.max_overlap = self.stats.max_overlap.max(depth / d);
            // Centres that round to one point (far from the origin) give no direction: the
            // whole contact distance deep, the most an overlap can be, they are found here.
            if depth == d {
                dr = head_on(bi.v - bj.v, d);
            }
        }
        self.outcome.clear();
        self.responder
            .pair(&mut self.m, i, j, dr, now, &mut self.outcome);
        // This event consumed `i`'s calendar entry: `i` is predicted again even when its
        // velocity did not change (a cluster stuck to a shape has infinite mass).
        let changed = &mut self.outcome.changed;
        if !changed.contains(&i) {
            changed.push(i);
        }
        self.stats.pair_collisions += 1;
        self.account();
        if let Some(log) = &mut self.log {
            let geometry = GEOMETRY.then(|| {
                let n = dr.normalize();
                (wrapped::<PERIODIC>(&self.cells, bi.r + n * bi.radius), -n)
            });
            let (a, b) = (self.id_of[i as usize], self.id_of[j as usize]);
            log.push(EventRecord::new(
                now,
                a,
                Body::new(ShapeKind::Sphere, b),
                &self.outcome,
                geometry,
            ));
        }
        self.renew_changed();
    }

    fn collide_wall(&mut self, i: u32, wall: Body) {
        let now = self.now;
        self.advance(i);
        let bi = self.m.bodies[i as usize];
        let (n, gap, material) = self.walls.normal_gap(wall, bi.r, bi.radius);
        #[cfg(test)]
        if self.checking {
            // In contact with the shape, not short of it (as for a pair).
            assert!(
                gap <= crate::sim::OVERLAP_TOLERANCE * bi.radius,
                "sphere {i} meets {wall} at t = {now} {gap:e} short of it"
            );
        }
        self.stats.max_wall_overlap = self.stats.max_wall_overlap.max(-gap / bi.radius);
        let floor = if self.broken_walls {
            0.0
        } else {
            self.walls.floor(wall, bi.radius, gap, bi.v.length(), now)
        };
        self.outcome.clear();
        let hop = if GRAVITY {
            super::walls::hop_speed(self.m.g, n, bi.r, bi.radius)
        } else {
            0.0
        };
        let contact = Wall {
            n,
            material,
            floor,
            hop,
            body: wall,
        };
        self.responder
            .wall(&mut self.m, i, contact, now, &mut self.outcome);
        self.stats.wall_collisions += 1;
        self.account();
        if let Some(log) = &mut self.log {
            let geometry =
                GEOMETRY.then(|| (wrapped::<PERIODIC>(&self.cells, bi.r - n * bi.radius), n));
            log.push(EventRecord::new(
                now,
                self.id_of[i as usize],
                wall,
                &self.outcome,
                geometry,
            ));
        }
        self.renew_changed();
    }

    /// Predicts every sphere the collision changed (`outcome.changed`), then schedules each:
    /// the one tail of a pair and a wall collision.
    #[inline]
    fn renew_changed(&mut self) {
        for k in 0..self.outcome.changed.len() {
            self.predict(self.outcome.changed[k]);
        }
        for k in 0..self.outcome.changed.len() {
            self.schedule(self.outcome.changed[k]);
        }
    }

    /// Adds the collision's outcome to the run's statistics.
    fn account(&mut self) {
        let out = &self.outcome;
        self.stats.energy_lost += out.energy_lost;
        self.stats.virial += out.virial;
        self.stats.joins += u64::from(out.joined);
        self.stats.guarded += u64::from(out.guarded);
        self.stats.slid += u64::from(out.slid);
    }

    /// Moves sphere `i` to now: along its line, or its parabola under gravity.
    #[inline(always)]
    fn advance(&mut self, i: u32) {
        if GRAVITY {
            self.m.advance_falling(i, self.now);
        } else {
            self.m.advance(i, self.now);
        }
    }

    /// Puts sphere `i`'s pending event in the calendar (its earlier one is dropped).
    #[inline]
    fn schedule(&mut self, i: u32) {
        let t = self.best[i as usize].time();
        #[cfg(test)]
        {
            self.scheduled[i as usize] = t;
        }
        self.queue.schedule(i, t);
    }

    /// Predicts sphere `i`'s next pair contact, static contact and shell event from now.
    /// One body out of line, with its stages inlined into it, so that the sphere's centre
    /// and the prediction's result pass between them in registers: through memory, each was
    /// stored in parts and loaded whole, which the store buffer cannot forward (2–5 % of the
    /// gas's time, docs/benchmarks.md, "Latency").
    #[inline(never)]
    fn predict(&mut self, i: u32) {
        self.stats.predictions += 1;
        self.advance(i);
        let horizon = self.predict_shell(i);
        let (pairs, complete, beyond) = self.predict_pairs(i, false, horizon);
        // The static contact's fields are written below with walls; without, they keep their
        // defaults (no static contact) for good.
        let best = &mut self.best[i as usize];
        (best.pairs, best.complete, best.beyond) = (pairs, complete, beyond);
        if WALLS {
            let b = self.m.bodies[i as usize];
            // Report-only: the shapes last met are not met again (`ReportOnly::shape`), nor
            // one the sphere is through (`walls::Skip`).
            let skip = walls::Skip {
                met: self.responder.shape_touched(i),
                through: R::REPORT_ONLY,
            };
            let counts = &mut self.stats.kernels;
            let (mut t, wall) = if GRAVITY {
                let g = self.m.g;
                (self.walls).earliest_falling((b.r, b.v, b.radius), g, skip, counts)
            } else {
                (self.walls).earliest((b.r, b.v, b.radius), skip, counts)
            };
            if self.broken_walls
                && t == 0.0
                && self.walls.past_and_inwards(wall, b.r, b.v, b.radius)
            {
                // The policy before 2026-12-01: past the wall, inwards, never back in: none.
                t = f64::INFINITY;
            }
            let best = &mut self.best[i as usize];
            best.wall_t = self.now + t;
            (best.wall_kind, best.wall_index) = (wall.kind, wall.index);
        }
    }

    /// How far ahead a prediction answers pairs, given the time to the sphere's shell event
    /// (`shell`, undivided): that time when the spheres collide clearly more often than they
    /// leave their shells (fewer than three crossings to four collisions so far: φ above about
    /// 0.28 in a gas) and the sphere's shell event is farther than a sphere's mean time
    /// between collisions; else every pair (`None`). Pairs met later are then left out: the
    /// sphere will most likely collide, and be predicted again, before its shell event, which
    /// would otherwise have to predict its whole list (docs/benchmarks.md, "The horizon").
    /// From the run's own time and counters, which a checkpoint holds, so a resumed run
    /// decides alike (docs/derivations/simulation.md, rule 6).
    #[inline]
    fn horizon(&self, shell: Quotient) -> Option<Quotient> {
        #[cfg(test)]
        if self.broken_horizon {
            return Some(Quotient {
                num: 0.25 * shell.num,
                den: shell.den,
            });
        }
        if 4 * self.stats.crossings >= 3 * self.stats.pair_collisions {
            return None;
        }
        let changes = 2 * self.stats.pair_collisions + self.stats.wall_collisions;
        // `shell > now · n / changes`, multiplied out (`den` and `changes` are positive).
        // Through `i64`, one instruction where `u64` takes a sequence (both counts are far
        // below 2⁶³, and round alike).
        let n = self.m.bodies.len() as i64 as f64;
        let far = shell.num * changes as i64 as f64 > self.now * n * shell.den;
        far.then(|| shell.reaching(self.now))
    }

    /// Sets when sphere `i` (advanced to now) leaves its shell; returns its prediction's
    /// horizon, no shorter than the time to that event as scheduled (rule 6 of
    /// docs/derivations/simulation.md).
    #[inline(always)]
    fn predict_shell(&mut self, i: u32) -> Option<Quotient> {
        let b = self.m.bodies[i as usize];
        let p = b.r - self.lists.centre[i as usize].c;
        if GRAVITY {
            // No horizon under gravity: with it a resting pile (python/tests/test_gravity.py)
            // made three times the events its test allows at rest, not understood yet
            // (rule 6 of docs/derivations/simulation.md).
            let t = shell_exit_falling(p, b.v, self.m.g, self.lists.delta);
            self.best[i as usize].shell_t = self.now + t;
            return None;
        }
        let shell = shell_exit_quotient(p, b.v, self.lists.delta);
        self.best[i as usize].shell_t = self.now + shell.map_or(f64::INFINITY, Quotient::value);
        shell.and_then(|q| self.horizon(q))
    }

    /// Where body `b` is at time `t` (unwrapped): on its parabola under gravity, else on its
    /// line (the parabola with `g = 0` is NaN once `Δt²` overflows, past `Δt ≈ 10¹⁵⁴`).
    #[inline(always)]
    pub(super) fn centre_at(&self, b: &Trajectory, t: f64) -> DVec3 {
        if GRAVITY {
            b.at(t, self.m.g).0
        } else {
            b.on_line(t)
        }
    }

    /// Every sphere's centre and velocity at the current time (periodic centres wrapped), in
    /// public order.
    pub fn current(&self) -> Vec<Trajectory> {
        let mut out = vec![Trajectory::default(); self.m.bodies.len()];
        for (b, &id) in self.m.bodies.iter().zip(&self.id_of) {
            let (r, v) = if GRAVITY {
                b.at(self.now, self.m.g)
            } else {
                (b.on_line(self.now), b.v)
            };
            out[id as usize] = Trajectory {
                r: wrapped::<PERIODIC>(&self.cells, r),
                t: self.now,
                v,
                ..*b
            };
        }
        out
    }

    /// Bytes the engine holds: per-sphere arrays, grid, calendar, scratch (not the response's
    /// own state, which is a few bytes per sphere when present).
    pub fn bytes(&self) -> usize {
        fn b<T>(v: &Vec<T>) -> usize {
            v.capacity() * std::mem::size_of::<T>()
        }
        b(&self.m.bodies)
            + b(&self.m.mass)
            + b(&self.m.material)
            + b(&self.m.counter)
            + b(&self.best)
            + b(&self.id_of)
            + self.cells.bytes()
            + self.stencil.bytes()
            + self.queue.bytes()
            + self.lists.bytes()
            + b(&self.gathered)
            + b(&self.spilled)
            + b(&self.found)
            + b(&self.near)
            + b(&self.fresh)
            + b(&self.old)
    }

    /// Renumbers the spheres in cell order (then by index, so the result is deterministic):
    /// every per-sphere array, the candidates' partners, the lists, the response's state and
    /// the cells follow, and the calendar is rebuilt from each sphere's pending event.
    fn reorder(&mut self) {
        let n = self.m.bodies.len();
        let mut order: Vec<u32> = (0..n as u32).collect();
        let cell: Vec<usize> = (self.lists.centre.iter())
            .map(|s| self.cells.index(self.cells.coords_of(s.c)))
            .collect();
        order.sort_by_key(|&i| (cell[i as usize], i));
        let mut new_of_old = vec![0u32; n];
        for (new, &old) in order.iter().enumerate() {
            new_of_old[old as usize] = new as u32;
        }
        fn take<T: Copy>(v: &[T], order: &[u32]) -> Vec<T> {
            crate::sim::pages::collected(order.iter().map(|&o| v[o as usize]))
        }
        self.m.bodies = take(&self.m.bodies, &order);
        self.m.mass = take(&self.m.mass, &order);
        self.m.material = take(&self.m.material, &order);
        self.m.counter = take(&self.m.counter, &order);
        self.id_of = take(&self.id_of, &order);
        self.best = take(&self.best, &order);
        for b in &mut self.best {
            for c in &mut b.pairs {
                if c.j != NONE {
                    c.j = new_of_old[c.j as usize];
                }
            }
        }
        if PERIODIC {
            self.images = take(&self.images, &order);
        }
        self.lists.permute(&order, &new_of_old);
        self.cells.clear();
        for i in 0..n as u32 {
            self.cells
                .insert(i, self.cells.coords_of(self.lists.centre[i as usize].c));
        }
        self.responder.permute(&new_of_old);
        self.reschedule();
    }

    /// A fresh calendar holding each sphere's pending event (older entries all dropped).
    fn reschedule(&mut self) {
        let n = self.m.bodies.len();
        self.queue = Calendar::new(self.width, n, n, self.now);
        for i in 0..n as u32 {
            self.schedule(i);
        }
    }

    /// Gives every sphere a new velocity now (`v` in public order, already checked finite,
    /// the responder's own rules checked here) and predicts every sphere again.
    pub fn set_velocities(&mut self, v: &[DVec3]) -> Result<(), SimError> {
        let n = self.m.bodies.len();
        let id_of = &self.id_of;
        self.responder
            .check_velocities(&|k| v[id_of[k as usize] as usize], n)
            .map_err(|(k, why)| {
                SimError::State(format!("velocities: sphere {}: {why}", id_of[k as usize]))
            })?;
        self.wake();
        self.responder.new_velocities();
        for k in 0..n {
            let new = v[self.id_of[k] as usize];
            self.m.set_velocity(k as u32, new, self.now);
        }
        for k in 0..n as u32 {
            self.predict(k);
        }
        // The time between events is the new velocities': a calendar sized for the old ones
        // (for spheres at rest, for none) would hold them all in a few buckets.
        self.size_calendar();
        self.reschedule();
        Ok(())
    }
}

/// The separation of a pair in contact whose centres give no direction (they round to one
/// point, far from the origin): `length` along the approach `towards`, so that the contact is
/// head-on, as the queries' fallback normal takes it (`contact.rs`; zero if nothing moves).
#[cold]
fn head_on(towards: DVec3, length: f64) -> DVec3 {
    towards.normalize_or_zero() * length
}

/// A point in the periodic box (elsewhere as it is): centres are read out wrapped, and an
/// event's contact point lies in the box with the spheres it is drawn with.
#[inline]
fn wrapped<const PERIODIC: bool>(cells: &Cells, p: DVec3) -> DVec3 {
    if PERIODIC { cells.wrap(p) } else { p }
}
