//! The run's loop: the simulation advanced from stop to stop, each stop's events appended to
//! the event log, a snapshot appended to the trajectory where one is due, a checkpoint written
//! where one is due; an interruption ends it with a last checkpoint.

use std::error::Error;
use std::io::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use glam::DVec3;
use spheresweep::io::xyz;
use spheresweep::sim::{Boundary, SimError, Simulation, Stats};

use super::checkpoint::{Counters, Progress, RunCheckpoint};
use super::events;
use super::limits::{self, Budget};
use super::options::Settings;
use super::outputs::{self, OutDir};
use super::staged::Staged;
use crate::number::num;

/// A run that stopped short of its end, its outputs kept ([`Run::stop_short`]): an error, as
/// the end asked for was not reached.
#[derive(Debug)]
pub struct StoppedShort {
    reason: String,
    at: f64,
}

impl std::fmt::Display for StoppedShort {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}; the run went on to t = {} and stopped there, its outputs written",
            self.reason,
            num(self.at)
        )
    }
}

impl Error for StoppedShort {}

/// A run under way.
pub struct Run {
    pub sim: Simulation,
    pub settings: Settings,
    pub fingerprint: u64,
    pub counters: Counters,
    pub trajectory: Option<Staged>,
    pub events: Option<Staged>,
    pub place: Place,
    /// Checkpoints written by this process.
    pub checkpoints: usize,
    /// The bytes the outputs may take, and at most how many an event row takes.
    pub budget: Budget,
    event_bound: u64,
    /// Why the run stopped short of its end, if it did ([`Run::stop_short`]).
    pub stopped_short: Option<String>,
    /// Whether a sphere has been found where its coordinates round coarser than its contacts'
    /// tolerance (at the start, or at a stop since): warned of once a process (a resumed run
    /// says it again at its first stop if still so).
    coarse_warned: bool,
}

/// Where a run is: its scene file, its output directory, its periodic box (if any).
pub struct Place {
    pub scene: PathBuf,
    pub dir: OutDir,
    pub periodic_box: Option<DVec3>,
    pub budget: Budget,
    /// Held while the run writes to `dir` ([`OutDir::lock`]).
    pub _lock: std::fs::File,
}

impl Run {
    /// A run from t = 0: the outputs started, the first frame written.
    pub fn start(
        sim: Simulation,
        settings: Settings,
        fingerprint: u64,
        place: Place,
    ) -> Result<Self, String> {
        let dir = &place.dir;
        let start_coarse = sim.coarse_sphere().is_some();
        let counters = Counters {
            next_stop: 0,
            frames: 0,
            logged: 0,
            ke0: sim.kinetic_energy(),
            p0: sim.momentum(),
            momentum_scale: sim
                .spheres()
                .iter()
                .map(|s| s.mass * s.velocity.length())
                .sum(),
            simulated: 0.0,
        };
        let mut run = Self {
            trajectory: settings
                .snapshot_every
                .map(|_| Staged::create(dir.file(outputs::TRAJECTORY)))
                .transpose()?,
            events: if settings.record_events {
                Some(Staged::create(dir.file(outputs::EVENTS))?)
            } else {
                None
            },
            sim,
            settings,
            fingerprint,
            counters,
            budget: place.budget.clone(),
            event_bound: limits::event_bound(settings.geometry),
            place,
            checkpoints: 0,
            stopped_short: None,
            // The scene's own warning names a sphere coarse at the start.
            coarse_warned: start_coarse,
        };
        if let Some(f) = run.events.as_mut() {
            let header = events::header(settings.geometry);
            writeln!(f.writer(), "{header}").map_err(|e| f.fail(e))?;
        }
        run.snapshot()?;
        Ok(run)
    }

    /// The run a checkpoint holds, its partial outputs checked and continued.
    pub fn resume(sim: Simulation, c: RunCheckpoint, place: Place) -> Result<Self, String> {
        let dir = &place.dir;
        dir.remove_temporaries();
        let reopen = |on: bool, name: &str, p: Progress| {
            on.then(|| Staged::reopen(dir.file(name), p)).transpose()
        };
        Ok(Self {
            trajectory: reopen(
                c.settings.snapshot_every.is_some(),
                outputs::TRAJECTORY,
                c.trajectory,
            )?,
            events: reopen(c.settings.record_events, outputs::EVENTS, c.events)?,
            sim,
            settings: c.settings,
            fingerprint: c.fingerprint,
            counters: c.counters,
            budget: place.budget.clone(),
            event_bound: limits::event_bound(c.settings.geometry),
            place,
            checkpoints: 0,
            stopped_short: None,
            // Said again at the first stop if still so (the scene's warning names the start).
            coarse_warned: false,
        })
    }

    /// Advances through every stop left; an interruption returns
    /// [`crate::interrupt::Interrupted`] after a last checkpoint (when checkpoints are on).
    pub fn advance(&mut self, quiet: bool, every: Duration) -> Result<(), Box<dyn Error>> {
        let t_end = self.settings.t_end;
        let bar = crate::progress::SimProgress::new(t_end, quiet, 4, false, every)?;
        let mut next_checkpoint = self.settings.checkpoint_every.map(|c| self.sim.time() + c);
        let first = self.counters.next_stop as usize;
        for (k, (stop, snapshot)) in self.settings.stops().into_iter().enumerate().skip(first) {
            let start = Instant::now();
            // The bytes written, and at most those of the events not yet written, within the
            // budget (asked at every poll).
            let (written, max) = (self.written(), self.budget.max);
            let per_event = if self.events.is_some() {
                self.event_bound
            } else {
                0
            };
            let collisions = |s: &Stats| s.pair_collisions + s.wall_collisions;
            let before = collisions(self.sim.stats());
            let mut over = false;
            let advanced = self.sim.advance_with(stop, &mut |t, s| {
                over = written + (collisions(s) - before) * per_event > max;
                !over && bar.show(t, s) && !crate::interrupt::requested()
            });
            self.counters.simulated += start.elapsed().as_secs_f64();
            let finished = match advanced {
                Ok(done) => done && !crate::interrupt::requested(),
                Err(SimError::Flown {
                    sphere,
                    since,
                    reachable,
                    ..
                }) => {
                    bar.finish();
                    // Refused at a stop on the way (a snapshot's time): the end asked for is
                    // past the reach too, and it is what the user named.
                    let refused = SimError::Flown {
                        sphere,
                        time: t_end,
                        since,
                        reachable,
                    };
                    return Err(self.stop_short(reachable, refused)?.into());
                }
                Err(e) => return Err(e.into()),
            };
            bar.show(self.sim.time(), self.sim.stats());
            self.warn_if_coarse(&bar);
            self.log_events()?;
            self.within_budget(over)?;
            if !finished {
                bar.finish();
                return Err(self.interrupted()?.into());
            }
            if snapshot {
                self.snapshot()?;
                self.within_budget(false)?;
            }
            self.counters.next_stop = k as u64 + 1;
            if let (Some(at), Some(every)) = (next_checkpoint, self.settings.checkpoint_every)
                && self.sim.time() >= at
                && stop < t_end
            {
                self.checkpoint()?;
                next_checkpoint = Some(self.sim.time() + every);
            }
        }
        bar.finish();
        Ok(())
    }

    /// A parked run refused to fly past its spheres' reach (`SimError::Flown`): it goes on to
    /// `reachable`, writes its events and a last frame there, and is then finished short of
    /// `t_end` (the summary says so), so that nothing it computed is lost.
    fn stop_short(&mut self, reachable: f64, refused: SimError) -> Result<StoppedShort, String> {
        self.sim
            .advance_to(reachable)
            .map_err(|e| format!("{refused}; and then going on to t = {reachable}: {e}"))?;
        self.log_events()?;
        self.within_budget(false)?;
        self.snapshot()?;
        self.within_budget(false)?;
        let reason = refused.to_string();
        self.stopped_short = Some(reason.clone());
        Ok(StoppedShort {
            reason,
            at: reachable,
        })
    }

    /// Warns, once, of spheres that have flown where their coordinates round coarser than
    /// their contacts' tolerance (the start's spheres are the scene's warning): their
    /// collisions from now on may overlap by that much, which the summary's overlap measure
    /// then shows.
    fn warn_if_coarse(&mut self, bar: &crate::progress::SimProgress) {
        // In a periodic box the box's length counts, which the start's warning named.
        if self.coarse_warned || self.place.periodic_box.is_some() {
            return;
        }
        if let Some(c) = self.sim.coarse_sphere() {
            self.coarse_warned = true;
            bar.say(&format!("warning: at t = {}, {c}", num(self.sim.time())));
        }
    }

    /// Bytes the outputs have taken so far.
    fn written(&self) -> u64 {
        [&self.trajectory, &self.events]
            .into_iter()
            .flatten()
            .map(Staged::written)
            .sum()
    }

    /// Refuses to go on once the outputs have passed the budget (or were about to: `over`).
    fn within_budget(&self, over: bool) -> Result<(), String> {
        let written = self.written();
        if over || written > self.budget.max {
            return Err(self.budget.passed(self.sim.time(), written));
        }
        Ok(())
    }

    /// A run that failed: its partial outputs and its checkpoint are removed (an interrupted
    /// run keeps them instead).
    pub fn abandon(mut self) {
        self.trajectory = None;
        self.events = None;
        let _ = std::fs::remove_file(self.checkpoint_path());
    }

    /// The stop's events, appended to the log.
    fn log_events(&mut self) -> Result<(), String> {
        if let Some(f) = self.events.as_mut() {
            let batch = self.sim.take_events();
            self.counters.logged += batch.len() as u64;
            events::write(f.writer(), &batch, self.settings.geometry).map_err(|e| f.fail(e))?;
        }
        Ok(())
    }

    /// A frame of the current state, appended to the trajectory (when snapshots are on), once
    /// the state is checked against the invariant every run keeps: a breach ends the run with
    /// the error, naming the sphere, the other body and the time.
    fn snapshot(&mut self) -> Result<(), String> {
        if let Some(t) = self.trajectory.as_mut() {
            self.sim.check_invariant().map_err(|e| e.to_string())?;
            let (spheres, time) = (self.sim.spheres(), self.sim.time());
            xyz::write_frame(t.writer(), &spheres, time, self.place.periodic_box)
                .map_err(|e| t.fail(e))?;
            self.counters.frames += 1;
        }
        Ok(())
    }

    /// Writes `checkpoint.bin`: the counters, how far each partial output has got (flushed and
    /// synced first), and the engine.
    fn checkpoint(&mut self) -> Result<(), String> {
        let progress =
            |f: &mut Option<Staged>| f.as_mut().map_or(Ok(Progress::default()), Staged::progress);
        let c = RunCheckpoint {
            fingerprint: self.fingerprint,
            settings: self.settings,
            counters: self.counters,
            trajectory: progress(&mut self.trajectory)?,
            events: progress(&mut self.events)?,
            engine: self.sim.checkpoint(),
        };
        crate::atomic::write_atomic(&self.checkpoint_path(), &c.to_bytes())?;
        self.checkpoints += 1;
        Ok(())
    }

    pub fn checkpoint_path(&self) -> PathBuf {
        self.place.dir.file(outputs::CHECKPOINT)
    }

    /// Ctrl-C or SIGTERM: stopped between two events, or at this stop before its snapshot (a
    /// stop of fewer than 4096 events is never polled inside). A last checkpoint (if they are
    /// on) continues with this same stop, and the partial outputs are kept for it; without
    /// checkpoints they are removed.
    fn interrupted(&mut self) -> Result<crate::interrupt::Interrupted, String> {
        let stats = *self.sim.stats();
        let done = format!(
            "at t = {} of {} after {} collisions",
            self.sim.time(),
            num(self.settings.t_end),
            stats.pair_collisions + stats.wall_collisions
        );
        if self.settings.checkpoint_every.is_none() {
            return Ok(crate::interrupt::Interrupted(format!(
                "{done}; nothing written, earlier files in {} kept (with --checkpoint-every T \
                 an interrupted run can be resumed)",
                self.place.dir.0.display()
            )));
        }
        self.checkpoint()?;
        for f in [self.trajectory.take(), self.events.take()]
            .into_iter()
            .flatten()
        {
            f.keep()?;
        }
        let path = self.checkpoint_path();
        Ok(crate::interrupt::Interrupted(format!(
            "{done}; wrote {} ({} frames and {} events so far, in the partial files beside it); \
             resume with `spheresweep run {} --resume {}` and the same options",
            path.display(),
            self.counters.frames,
            self.counters.logged,
            self.place.scene.display(),
            path.display()
        )))
    }
}

/// The box of a periodic scene.
pub fn periodic_box(boundary: Boundary) -> Option<DVec3> {
    match boundary {
        Boundary::Periodic { size } => Some(size),
        _ => None,
    }
}
