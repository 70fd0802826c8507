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

use wide::f64x4;

use super::{Engine, Responder, SimError};
use crate::sim::MAX_MAGNITUDE;
use crate::sim::persist::{COUNT_LIMIT, persist_fields};
use crate::sim::predict::arrivals;

/// Why the spheres have not flown apart (internal indices).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Meeting {
    /// A periodic box, or gravity: every sphere meets something again.
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
    /// When they were found to have flown apart (`+∞` while they have not).
    pub since: f64,
}

persist_fields!(Dispersal {
    quiet,
    wait,
    parked,
    since
});

impl Dispersal {
    /// Before the first test, for `n` spheres: `n²/16` quiet shell events, and at least 64.
    pub fn new(n: usize) -> Self {
        let n = n as u64;
        Self {
            quiet: 0,
            wait: (n.saturating_mul(n) / 16).clamp(64, COUNT_LIMIT),
            parked: false,
            since: f64::INFINITY,
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
        d.quiet = if shell { d.quiet + 1 } else { 0 };
        if d.quiet >= d.wait {
            self.test_dispersal();
        }
    }

    /// The test itself, out of line (it is rare).
    #[inline(never)]
    fn test_dispersal(&mut self) {
        if self.never_meet().is_ok() {
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
        self.dispersal.since = self.now;
        for i in 0..self.best.len() as u32 {
            self.best[i as usize].shell_t = f64::INFINITY;
            self.schedule(i);
        }
    }

    /// After new velocities: every shell centred where its sphere is now (the bodies are not
    /// moved: their positions stay the same bits), the lists built again from them.
    pub(super) fn wake(&mut self) {
        if !self.dispersal.parked {
            return;
        }
        self.dispersal = Dispersal::new(self.best.len());
        self.recentre_shells();
        self.build_lists();
    }

    /// When the spheres were found to have flown apart, if they have.
    pub fn flown_apart(&self) -> Option<f64> {
        self.dispersal.parked.then_some(self.dispersal.since)
    }

    /// A parked engine asked to go on to `t`: refused if a sphere would then be beyond
    /// [`MAX_MAGNITUDE`] (at `1e308` one moving at 2 would be at infinity).
    pub(super) fn check_flight(&self, t: f64) -> Result<(), SimError> {
        if !self.dispersal.parked {
            return Ok(());
        }
        for (b, &id) in self.m.bodies.iter().zip(&self.id_of) {
            let r = b.r + b.v * (t - b.t);
            if !r.is_finite() || r.abs().max_element() > MAX_MAGNITUDE {
                return Err(SimError::Flown {
                    sphere: id as usize,
                    time: t,
                    since: self.dispersal.since,
                });
            }
        }
        Ok(())
    }

    /// Every shell centre moved to its sphere's position now, and the cells with it.
    fn recentre_shells(&mut self) {
        self.cells.clear();
        for (k, b) in self.m.bodies.iter().enumerate() {
            let r = b.r + b.v * (self.now - b.t);
            self.lists.centre[k].c = r;
            self.cells.insert(k as u32, self.cells.coords_of(r));
        }
    }

    /// Whether the spheres have flown apart: an open domain without gravity, no sphere with a
    /// pending pair or static-shape event, and no pair (by brute force, in the prediction's
    /// own kernel) that will ever meet; else why not.
    pub(super) fn never_meet(&self) -> Result<(), Meeting> {
        if PERIODIC || GRAVITY {
            return Err(Meeting::NotOpen);
        }
        for (i, b) in self.best.iter().enumerate() {
            if b.pairs[0].t.is_finite() || b.wall_t.is_finite() {
                return Err(Meeting::Event(i as u32));
            }
        }
        // Every sphere now; relative motions four at a time, the contact distance in the
        // fourth lane of `v` (as `arrivals` takes them).
        let now: Vec<(f64x4, f64x4)> = (self.m.bodies.iter())
            .map(|b| {
                let r = b.r + b.v * (self.now - b.t);
                let v = b.v;
                (
                    f64x4::new([r.x, r.y, r.z, 0.0]),
                    f64x4::new([v.x, v.y, v.z, b.radius]),
                )
            })
            .collect();
        let flip = f64x4::new([1.0, 1.0, 1.0, -1.0]);
        for (i, &(ri, vi)) in now.iter().enumerate() {
            let vi = vi * flip;
            for (at, four) in now[i + 1..].chunks(4).enumerate() {
                let mut r0 = [f64x4::ZERO; 4];
                let mut v = [f64x4::new([1.0, 0.0, 0.0, 0.0]); 4];
                for (k, &(rj, vj)) in four.iter().enumerate() {
                    r0[k] = rj - ri;
                    v[k] = vj - vi;
                }
                let (_, finite) = arrivals(r0, v);
                let finite = finite & ((1 << four.len()) - 1);
                if finite != 0 {
                    let j = i + 1 + 4 * at + finite.trailing_zeros() as usize;
                    return Err(Meeting::Pair(i as u32, j as u32));
                }
            }
        }
        Ok(())
    }
}
