//! The engine's part of a checkpoint, listed once (`engine_state!`) and read by both `save`
//! and `load`; each value's own layout is its [`Persist`] description. `load` then checks what
//! depends on the world (indices, the grid, the radii) and rebuilds what is derived (the
//! cells' contents, the calendar). The layout is format version 6 (`sim::checkpoint`; 4 added
//! `Best::beyond`, 5 the dispersal state, 6 the event records not yet taken).

use super::dispersal::Meeting;
use super::{Best, Candidate, Engine};
use crate::contact::Body;
use crate::shape::ShapeKind;
use crate::sim::cells::NONE;
use crate::sim::checkpoint::{Decoder, Encoder};
use crate::sim::model::SimError;
use crate::sim::persist::{Persist, persist_fields};
use crate::sim::response::{NO_SHAPE, Responder, Trajectory};

persist_fields!(Trajectory { r, t, v, radius });
persist_fields!(Candidate { t, j, counter });
// The wall's kind and index in `Body`'s own order, as in format 3; `beyond` since format 4.
persist_fields!(Best {
    pairs,
    complete,
    wall_t,
    wall_kind,
    wall_index,
    shell_t,
    beyond
});

/// The engine's state in checkpoint order, for both directions: `$each!(place)` on every
/// value (`save` reads the place, `load` replaces it). Per sphere, in internal order, its
/// counter, public index, shell centre and pending event sit together; the response's state follows
/// (`Responder::save`). What is not listed is derived from it (the cells and neighbour lists
/// from the shell centres), or from the world.
macro_rules! engine_state {
    ($engine:ident, $each:ident) => {
        $each!($engine.now);
        $each!($engine.m.bodies);
        for k in 0..$engine.best.len() {
            $each!($engine.m.counter[k]);
            $each!($engine.id_of[k]);
            $each!($engine.lists.centre[k].c);
            $each!($engine.best[k]);
        }
        for k in 0..$engine.images.len() {
            $each!($engine.images[k]);
        }
        $each!($engine.since_reorder);
        $each!($engine.same_time);
        $each!($engine.stall_limit);
        $each!($engine.reorder_every);
        $each!($engine.window_start);
        $each!($engine.min_progress);
        $each!($engine.width);
        $each!($engine.stats);
        $each!($engine.dispersal);
        $each!($engine.log);
    };
}

fn bad(what: String) -> SimError {
    SimError::Checkpoint(what)
}

impl<
    R: Responder,
    const PERIODIC: bool,
    const WALLS: bool,
    const GEOMETRY: bool,
    const GRAVITY: bool,
> Engine<R, PERIODIC, WALLS, GEOMETRY, GRAVITY>
{
    /// Writes the whole dynamic state (see `sim::checkpoint`), in internal order.
    pub fn save(&self, e: &mut Encoder) {
        let engine = self;
        macro_rules! each {
            ($place:expr) => {
                Persist::save(&$place, e)
            };
        }
        engine_state!(engine, each);
        self.responder.save(e);
    }

    /// Restores what [`save`](Self::save) wrote into an engine built from the same world;
    /// `masses` and `materials` are the world's, in public order. Every index is checked, so a
    /// damaged checkpoint is refused, never a panic.
    pub fn load(
        &mut self,
        d: &mut Decoder,
        masses: &[f64],
        materials: &[u16],
    ) -> Result<(), SimError> {
        let radii = self.public_radii();
        {
            let engine = &mut *self;
            macro_rules! each {
                ($place:expr) => {
                    Persist::load(&mut $place, d)?
                };
            }
            engine_state!(engine, each);
        }
        self.check_bodies(&radii)?;
        if let Some(log) = &self.log
            && let Some(r) = log.iter().find(|r| r.sphere as usize >= radii.len())
        {
            return Err(bad(format!(
                "an event of sphere {}, which does not exist",
                r.sphere
            )));
        }
        for k in 0..self.best.len() {
            self.check_sphere(k)?;
        }
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !(positive(self.width) && positive(self.min_progress) && self.now.is_finite()) {
            return Err(bad(format!(
                "time {}, calendar width {} or least progress {} invalid",
                self.now, self.width, self.min_progress
            )));
        }
        self.responder.load(d, self.m.bodies.len())?;
        // Report-only: the shape each sphere last met exists.
        for k in 0..self.best.len() {
            for shape in self.responder.shape_touched(k as u32) {
                if shape != NO_SHAPE {
                    self.check_wall(self.id_of[k], shape, 0.0)?;
                }
            }
        }
        if self.dispersal.parked {
            self.check_parked()?;
        }
        self.rebuild(masses, materials);
        Ok(())
    }

    /// The world's radii, in public order (read before a checkpoint replaces the state).
    fn public_radii(&self) -> Vec<f64> {
        let mut radii = vec![0.0; self.m.bodies.len()];
        for (b, &id) in self.m.bodies.iter().zip(&self.id_of) {
            radii[id as usize] = b.radius;
        }
        radii
    }

    /// Loaded bodies: finite, numbered by a permutation, each with its world's radius.
    fn check_bodies(&self, radii: &[f64]) -> Result<(), SimError> {
        let n = self.m.bodies.len();
        for b in &self.m.bodies {
            let x = [b.r.x, b.r.y, b.r.z, b.t, b.v.x, b.v.y, b.v.z, b.radius];
            if !x.iter().all(|v| v.is_finite()) {
                return Err(bad("a sphere's state is not finite".into()));
            }
        }
        let mut seen = vec![false; n];
        for (k, &id) in self.id_of.iter().enumerate() {
            if id as usize >= n || std::mem::replace(&mut seen[id as usize], true) {
                return Err(bad(format!(
                    "sphere numbering is not a permutation (entry {k})"
                )));
            }
        }
        for (b, &id) in self.m.bodies.iter().zip(&self.id_of) {
            if b.radius != radii[id as usize] {
                return Err(bad(format!(
                    "sphere {id}: radius {} is not the world's {}",
                    b.radius, radii[id as usize]
                )));
            }
        }
        Ok(())
    }

    /// One loaded sphere (internal index `k`): within its shell (so that its list holds every
    /// sphere it can meet before its shell event), its partners and static shape existing, no
    /// event time NaN.
    fn check_sphere(&mut self, k: usize) -> Result<(), SimError> {
        let n = self.m.bodies.len();
        let id = self.id_of[k];
        let (b, c) = (self.m.bodies[k], self.lists.centre[k].c);
        if b.t > self.now {
            return Err(bad(format!(
                "sphere {id}: its time {} is after the checkpoint's {}",
                b.t, self.now
            )));
        }
        // Where it was and where it is now: both within the shell (found by fuzzing: a
        // sphere at its own time 10¹³⁹ before now left the box and its shell); in an open
        // domain without gravity a body keeps its last velocity change's place (`keep_anchor`),
        // so only where it is now. Parked spheres have left their shells (`check_parked`
        // checks them instead).
        let limit = self.lists.delta * (1.0 + super::lists::REACH_MARGIN);
        let now = (self.centre_at(&b, self.now) - c).length();
        let was = if PERIODIC || GRAVITY {
            (b.r - c).length()
        } else {
            0.0
        };
        // Not `f64::max` alone, which drops a NaN.
        let away = if was.is_nan() || now.is_nan() {
            f64::NAN
        } else {
            was.max(now)
        };
        if away.is_nan() || (away > limit && !self.dispersal.parked) {
            return Err(bad(format!(
                "sphere {id}: {away} from its shell centre, beyond the shell's {}",
                self.lists.delta
            )));
        }
        let b = self.best[k];
        for &Candidate { t, j, .. } in &b.pairs {
            if j != NONE && j as usize >= n {
                return Err(bad(format!("sphere {id}: partner {j} does not exist")));
            }
            // An event without a partner never fires (found by fuzzing: it indexed
            // sphere 2³² − 1).
            if j == NONE && t != f64::INFINITY {
                return Err(bad(format!(
                    "sphere {id}: a pair event at t = {t} without a partner"
                )));
            }
        }
        self.check_wall(id, b.wall(), b.wall_t)?;
        if [b.pairs[0].t, b.pairs[1].t, b.wall_t, b.shell_t]
            .iter()
            .any(|t| t.is_nan())
        {
            return Err(bad(format!("sphere {id}: an event time is NaN")));
        }
        Ok(())
    }

    /// A parked engine's spheres: none with an event, no pair that meets (else the
    /// checkpoint is refused). Their shells stay as saved (a load then save gives the same
    /// bytes): nothing reads the lists until new velocities wake the engine (`dispersal.rs`).
    fn check_parked(&mut self) -> Result<(), SimError> {
        if let Some(b) = self.best.iter().find(|b| b.shell_t != f64::INFINITY) {
            return Err(bad(format!(
                "parked, but a shell event at t = {}",
                b.shell_t
            )));
        }
        let id = |k: u32| self.id_of[k as usize];
        match self.never_meet() {
            Ok(reach) => self.reach = reach,
            Err(Meeting::NotOpen) => return Err(bad("parked, but not an open scene".into())),
            Err(Meeting::Event(i)) => {
                return Err(bad(format!("parked, but sphere {} has an event", id(i))));
            }
            Err(Meeting::Pair(i, j)) => {
                let (i, j) = (id(i), id(j));
                return Err(bad(format!("parked, but spheres {i} and {j} meet")));
            }
        }
        Ok(())
    }

    /// A sphere's next static shape: of a static kind, and existing if its time is finite.
    fn check_wall(&self, id: u32, wall: Body, wall_t: f64) -> Result<(), SimError> {
        if wall.kind == ShapeKind::Sphere {
            let code = wall.kind.code();
            return Err(bad(format!("sphere {id}: static shape kind {code}")));
        }
        if wall_t != f64::INFINITY && self.walls.get(wall).is_none() {
            return Err(bad(format!("sphere {id}: {wall} does not exist")));
        }
        Ok(())
    }

    /// What a checkpoint does not hold, rebuilt from the loaded state and the world: masses and
    /// materials in internal order, the cells' contents, the neighbour lists and a fresh
    /// calendar (the log of events not yet taken is the checkpoint's).
    fn rebuild(&mut self, masses: &[f64], materials: &[u16]) {
        let n = self.m.bodies.len();
        self.m.mass = self.id_of.iter().map(|&id| masses[id as usize]).collect();
        self.m.material = self
            .id_of
            .iter()
            .map(|&id| materials[id as usize])
            .collect();
        self.cells.clear();
        for k in 0..n {
            self.lists.centre[k].radius = self.m.bodies[k].radius;
            let c = self.cells.coords_of(self.lists.centre[k].c);
            self.cells.insert(k as u32, c);
        }
        self.build_lists();
        // `size_calendar`'s time scale, 2²⁹ times the watchdog's least progress (exactly).
        self.responder
            .set_time_scale(self.min_progress * (1u64 << 29) as f64);
        self.reschedule();
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::sim::persist::tests::round_trip;

    /// A pending event with every field set: its description covers them all.
    #[test]
    fn a_pending_event_round_trips() {
        let best = Best {
            pairs: [
                Candidate {
                    t: 1.5,
                    j: 3,
                    counter: 7,
                },
                Candidate {
                    t: 2.5,
                    j: 4,
                    counter: 8,
                },
            ],
            complete: false,
            wall_t: 3.5,
            wall_kind: ShapeKind::Cylinder,
            wall_index: 9,
            shell_t: 4.5,
            beyond: true,
        };
        assert_ne!(best, Best::default());
        round_trip(&best);
        round_trip(&Trajectory {
            r: DVec3::new(1.0, 2.0, 3.0),
            t: 4.0,
            v: DVec3::new(5.0, 6.0, 7.0),
            radius: 8.0,
        });
    }
}
