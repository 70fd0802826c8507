//! `Run`: the engine as the public type sees it, one dynamic call per `advance_to` whatever
//! the monomorphisation, and the per-response hooks it needs.

use glam::DVec3;

use super::cells::Cells;
use super::checkpoint;
use super::engine::Engine;
use super::response::{self, Elastic, Materials, Motion, ReportOnly, Responder};
use super::{EventRecord, SimError, Stats};
use crate::statics::Statics;

/// The part of the engine the public type sees, whatever the monomorphisation.
pub(super) trait Run: Send {
    fn run_until(
        &mut self,
        t: f64,
        keep: &mut dyn FnMut(f64, &Stats) -> bool,
    ) -> Result<bool, SimError>;
    fn now(&self) -> f64;
    fn stats(&self) -> &Stats;
    /// When an open scene's spheres were found to have flown apart for good, if they have.
    fn flown_apart(&self) -> Option<f64>;
    fn motion(&self) -> &Motion;
    fn current(&self) -> Vec<response::Trajectory>;
    fn take_log(&mut self) -> Vec<EventRecord>;
    fn clusters(&self) -> Vec<Vec<u32>>;
    fn name(&self) -> String;
    fn bytes(&self) -> usize;
    fn save(&self, e: &mut checkpoint::Encoder);
    fn load(
        &mut self,
        d: &mut checkpoint::Decoder,
        masses: &[f64],
        materials: &[u16],
    ) -> Result<(), SimError>;
    /// The grid (its geometry: the invariant check sorts positions by it), the shapes, and
    /// whether the box is periodic and the response only reports.
    fn layout(&self) -> (&Cells, &Statics<u16>, bool, bool);
    fn break_walls(&mut self);
    fn set_velocities(&mut self, v: &[DVec3]) -> Result<(), SimError>;
    /// Periodic image counts in public order (empty outside a periodic box).
    fn images(&self) -> Vec<[i64; 3]>;
    /// Test-only: check the prediction invariant after every event.
    #[cfg(test)]
    fn set_checking(&mut self);
    /// Test-only: how many predictions left pairs out past their horizon.
    #[cfg(test)]
    fn left_out(&self) -> u64;
    /// Test-only fault injection: the horizon always used, and a quarter of the shell time.
    #[cfg(test)]
    fn break_horizon(&mut self);
    /// Test-only fault injection: sphere `k`'s velocity (engine order) made NaN.
    #[cfg(test)]
    fn poison(&mut self, k: usize);
    /// Test-only: the calendar's bucket width.
    #[cfg(test)]
    fn calendar_width(&self) -> f64;
}

/// Per-response hooks the public type needs.
pub(super) trait Clusters {
    fn clusters(&self) -> Vec<Vec<u32>> {
        Vec::new()
    }
}
impl Clusters for ReportOnly {}
impl Clusters for Elastic {}
impl Clusters for Materials {
    fn clusters(&self) -> Vec<Vec<u32>> {
        Materials::clusters(self).map(<[u32]>::to_vec).collect()
    }
}

impl<R: Responder + Clusters, const P: bool, const W: bool, const G: bool, const F: bool> Run
    for Engine<R, P, W, G, F>
{
    fn run_until(
        &mut self,
        t: f64,
        keep: &mut dyn FnMut(f64, &Stats) -> bool,
    ) -> Result<bool, SimError> {
        Engine::run_until(self, t, keep)
    }
    fn now(&self) -> f64 {
        self.now
    }
    fn flown_apart(&self) -> Option<f64> {
        Engine::flown_apart(self)
    }
    fn stats(&self) -> &Stats {
        &self.stats
    }
    fn motion(&self) -> &Motion {
        &self.m
    }
    fn current(&self) -> Vec<response::Trajectory> {
        Engine::current(self)
    }
    fn take_log(&mut self) -> Vec<EventRecord> {
        self.log.as_mut().map(std::mem::take).unwrap_or_default()
    }
    fn clusters(&self) -> Vec<Vec<u32>> {
        let mut c = self.responder.clusters();
        for members in &mut c {
            for s in members.iter_mut() {
                *s = self.id_of[*s as usize];
            }
            members.sort_unstable();
        }
        c.sort_unstable();
        c
    }
    fn save(&self, e: &mut checkpoint::Encoder) {
        Engine::save(self, e)
    }
    fn load(
        &mut self,
        d: &mut checkpoint::Decoder,
        masses: &[f64],
        materials: &[u16],
    ) -> Result<(), SimError> {
        Engine::load(self, d, masses, materials)
    }
    fn layout(&self) -> (&Cells, &Statics<u16>, bool, bool) {
        (&self.cells, &self.walls, P, R::REPORT_ONLY)
    }
    fn break_walls(&mut self) {
        self.broken_walls = true;
    }
    fn set_velocities(&mut self, v: &[DVec3]) -> Result<(), SimError> {
        Engine::set_velocities(self, v)
    }
    fn images(&self) -> Vec<[i64; 3]> {
        let mut out = vec![[0; 3]; self.images.len()];
        for (k, &id) in self.id_of.iter().enumerate().take(self.images.len()) {
            // A centre is counted across a face at its shell event but wrapped whenever it is
            // read (`current`): the box lengths that read takes off are crossings too.
            let r = self.centre_at(&self.m.bodies[k], self.now);
            let since = (r / self.cells.len).floor();
            out[id as usize] = std::array::from_fn(|a| self.images[k][a] + since[a] as i64);
        }
        out
    }
    fn bytes(&self) -> usize {
        Engine::bytes(self)
            + self
                .log
                .as_ref()
                .map_or(0, |l| l.capacity() * std::mem::size_of::<EventRecord>())
    }
    #[cfg(test)]
    fn set_checking(&mut self) {
        self.checking = true;
        // Renumber often, so that the check covers it.
        self.reorder_every = 97;
    }
    #[cfg(test)]
    fn left_out(&self) -> u64 {
        self.left_out
    }
    #[cfg(test)]
    fn break_horizon(&mut self) {
        self.broken_horizon = true;
    }
    #[cfg(test)]
    fn poison(&mut self, k: usize) {
        self.m.bodies[k].v.x = f64::NAN;
    }
    #[cfg(test)]
    fn calendar_width(&self) -> f64 {
        self.width
    }
    fn name(&self) -> String {
        format!(
            "{}{}{}{}{}",
            R::NAME,
            if P { ", periodic" } else { ", open" },
            if F { ", gravity" } else { "" },
            if W { ", static shapes" } else { "" },
            if G { ", contact geometry" } else { "" }
        )
    }
}
