//! An open scene whose spheres have flown apart for good: no pair will ever meet and no sphere
//! moves towards a static shape, yet every sphere would leave its shell again and again, for
//! ever (a lone sphere with `t_end = 1e308` never finished). After a long run of shell events
//! with nothing else between them the engine asks whether that is so (`never_meet`, every pair
//! by brute force); if it is, it parks: no sphere has an event any more, and the run ends at
//! once. New velocities wake it (shells centred where the spheres are, lists rebuilt).
//!
//! Only in an open domain without gravity: there straight lines that do not meet now never
//! will (docs/derivations/simulation.md, "A scene that has flown apart"). The brute-force
//! test costs `n²/2` pairs; it runs after `n²/16` quiet shell events at the least, and each
//! test that fails doubles the wait, so it adds at most a constant to a shell event's cost.

use glam::DVec3;
use wide::f64x4;

use super::{Engine, Responder, SimError};
use crate::sim::persist::{COUNT_LIMIT, persist_fields};
use crate::sim::predict::arrivals;
use crate::sim::{MAX_MAGNITUDE, OVERLAP_TOLERANCE};

/// Why the spheres have not flown apart (internal indices).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Meeting {
    /// A periodic box, or gravity (paths wrap or bend): not tested.
    NotOpen,
    /// The sphere has a pending pair or static-shape event.
    Event(u32),
    /// The two spheres will meet.
    Pair(u32, u32),
}

/// When the engine last asked whether its spheres have flown apart, and the answer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Dispersal {
    /// Shell events since the last event of any other kind.
    pub quiet: u64,
    /// How many quiet shell events the next test waits for.
    pub wait: u64,
    /// Whether the spheres have flown apart: no sphere has an event (the shells are stale).
    pub parked: bool,
    /// The time of the last event other than a shell event (the start before any): once
    /// parked, nothing has happened since.
    pub last_event: f64,
}

persist_fields!(Dispersal {
    quiet,
    wait,
    parked,
    last_event
});

impl Dispersal {
    /// Before the first test, for `n` spheres: `n²/16` quiet shell events, and at least 64.
    pub fn new(n: usize) -> Self {
        let n = n as u64;
        Self {
            quiet: 0,
            wait: (n.saturating_mul(n) / 16).clamp(64, COUNT_LIMIT),
            parked: false,
            last_event: 0.0,
        }
    }
}

impl<
    R: Responder,
    const PERIODIC: bool,
    const WALLS: bool,
    const GEOMETRY: bool,
    const GRAVITY: bool,
> Engine<R, PERIODIC, WALLS, GEOMETRY, GRAVITY>
{
    /// Counts an event (`shell`: a shell event); after a long enough quiet run, tests whether
    /// the spheres have flown apart and parks them if so.
    #[inline(always)]
    pub(super) fn note_quiet(&mut self, shell: bool) {
        if PERIODIC || GRAVITY {
            return;
        }
        let d = &mut self.dispersal;
        if shell {
            d.quiet += 1;
        } else {
            (d.quiet, d.last_event) = (0, self.now);
        }
        if d.quiet >= d.wait {
            self.test_dispersal();
        }
    }

    /// The test itself, out of line (it is rare).
    #[inline(never)]
    fn test_dispersal(&mut self) {
        if let Ok(reach) = self.never_meet() {
            self.reach = reach;
            self.park();
        } else {
            let d = &mut self.dispersal;
            d.quiet = 0;
            d.wait = d.wait.saturating_mul(2).min(COUNT_LIMIT);
        }
    }

    /// No sphere has an event any more: the calendar is empty.
    fn park(&mut self) {
        self.dispersal.parked = true;
        for i in 0..self.best.len() as u32 {
            self.best[i as usize].shell_t = f64::INFINITY;
            self.schedule(i);
        }
    }

    /// New velocities are an event: the quiet run starts again, and a parked engine wakes,
    /// every shell centred where its sphere is now (the bodies are not moved: their positions
    /// stay the same bits) and the lists built again from them.
    pub(super) fn wake(&mut self) {
        let parked = self.dispersal.parked;
        if parked {
            self.dispersal = Dispersal::new(self.best.len());
        }
        (self.dispersal.quiet, self.dispersal.last_event) = (0, self.now);
        if parked {
            self.reach = Vec::new();
            self.recentre_shells();
            self.build_lists();
        }
    }

    /// Since when nothing has met anything, if the spheres have flown apart for good.
    pub fn flown_apart(&self) -> Option<f64> {
        self.dispersal.parked.then_some(self.dispersal.last_event)
    }

    /// A parked engine asked to go on to `t`: refused if a sphere would then be past its
    /// reach (`never_meet`), naming the time the run can go on to.
    pub(super) fn check_flight(&self, t: f64) -> Result<(), SimError> {
        if !self.dispersal.parked {
            return Ok(());
        }
        let mut first = None;
        let mut reachable = f64::INFINITY;
        for (k, b) in self.m.bodies.iter().enumerate() {
            // A sphere with no number for a state has not flown: the engine failed.
            if !(b.r.is_finite() && b.v.is_finite()) {
                return Err(SimError::NotFinite {
                    time: self.now,
                    sphere: self.id_of[k] as usize,
                });
            }
            if b.v == DVec3::ZERO {
                continue; // at rest, it stays where it is
            }
            let reach = self.reach[k];
            let r = b.on_line(t);
            let beyond = !r.is_finite() || r.abs().max_element() > reach;
            if first.is_none() && beyond {
                first = Some(self.id_of[k] as usize);
            }
            // Each axis' time to `reach`, a little short of it (rounding).
            let near = reach * (1.0 - f64::EPSILON * 8.0);
            for a in 0..3 {
                if b.v[a] != 0.0 {
                    let s = (near.copysign(b.v[a]) - b.r[a]) / b.v[a];
                    reachable = reachable.min(b.t + s);
                }
            }
        }
        match first {
            None => Ok(()),
            Some(sphere) => Err(SimError::Flown {
                sphere,
                time: t,
                since: self.dispersal.last_event,
                reachable: reachable.max(self.now),
            }),
        }
    }

    /// Every shell centre moved to its sphere's position now, and the cells with it.
    fn recentre_shells(&mut self) {
        self.cells.clear();
        for (k, b) in self.m.bodies.iter().enumerate() {
            let r = b.on_line(self.now);
            self.lists.centre[k].c = r;
            self.cells.insert(k as u32, self.cells.coords_of(r));
        }
    }

    /// Whether the spheres have flown apart: an open domain without gravity, no sphere with a
    /// pending pair or static-shape event, and no pair (by brute force, in the prediction's
    /// own kernel) that will ever meet; else why not. If they have, each sphere's reach: how
    /// far from the origin it may go, at most [`MAX_MAGNITUDE`], while its position rounds
    /// (`2⁻⁵² |x|` a coordinate, `√3 · 2⁻⁵²` of it a distance) by less than half the gap it
    /// keeps to a sphere moving with it plus the overlap tolerance, so that the invariant
    /// check still reads the pair apart (`2⁵⁰` times that margin; docs/derivations/
    /// simulation.md, "A scene that has flown apart").
    pub(super) fn never_meet(&self) -> Result<Vec<f64>, Meeting> {
        if PERIODIC || GRAVITY {
            return Err(Meeting::NotOpen);
        }
        for (i, b) in self.best.iter().enumerate() {
            if b.pairs[0].t.is_finite() || b.wall_t.is_finite() {
                return Err(Meeting::Event(i as u32));
            }
        }
        let now: Vec<(DVec3, DVec3, f64)> = (self.m.bodies.iter())
            .map(|b| (b.on_line(self.now), b.v, b.radius))
            .collect();
        let mut margin = vec![f64::INFINITY; now.len()];
        for (i, &(ri, vi, ai)) in now.iter().enumerate() {
            for (k, &(rj, vj, aj)) in now[i + 1..].iter().enumerate() {
                let j = i + 1 + k;
                let (r0, v, d) = (rj - ri, vj - vi, ai + aj);
                if meets(r0, v, d) {
                    return Err(Meeting::Pair(i as u32, j as u32));
                }
                // A pair moving together keeps its gap while both go far; any other pair's
                // distance grows as fast as `‖v‖ t`, at least `2²⁴` times faster than what
                // its rounding needs (`2⁻⁵⁰ ‖vᵢ‖ t`). The least distance from now on: at the
                // closest approach, or now.
                if v.length() > CO_MOVING * vi.length().max(vj.length()) {
                    continue;
                }
                let a = v.length_squared();
                let s = if a > 0.0 {
                    (-r0.dot(v) / a).max(0.0)
                } else {
                    0.0
                };
                let gap = (r0 + v * s).length() - d + OVERLAP_TOLERANCE * d;
                margin[i] = margin[i].min(gap);
                margin[j] = margin[j].min(gap);
            }
        }
        let two_50 = (1u64 << 50) as f64;
        Ok(margin
            .into_iter()
            .map(|m| (m.max(0.0) * two_50).min(MAX_MAGNITUDE))
            .collect())
    }
}

/// Relative speeds at most this fraction of the faster sphere's count as moving together
/// (`never_meet`).
const CO_MOVING: f64 = 1.0 / (1u64 << 26) as f64;

/// Whether a pair at `r0`, moving at `v` relative to each other, meets at contact distance
/// `d` from now on, as the prediction's kernel answers (`predict::arrivals`, one lane).
fn meets(r0: DVec3, v: DVec3, d: f64) -> bool {
    let lanes = |a: DVec3, w: f64| f64x4::new([a.x, a.y, a.z, w]);
    let (far, still) = (lanes(DVec3::X, 0.0), lanes(DVec3::X, 0.0));
    let (_, finite) = arrivals(
        [lanes(r0, 0.0), far, far, far],
        [lanes(v, d), still, still, still],
    );
    finite & 1 != 0
}
