//! Output limits in bytes. Before a run starts, the bytes its outputs will take (the frames
//! left, each at most [`frame_bound`] bytes, plus what a resumed run has written) are checked
//! against `--max-output` (default: half the space free on the output directory's disk) and
//! against the free space; during the run, the bytes written plus the events not yet written
//! (each at most [`event_bound`] bytes) are checked at every poll of the engine, and a run that
//! passes the limit stops with an error.
//!
//! (`crates/cli/src/memory.rs` has its own size parser and printer; these are private to `run`
//! until the two are merged.)

use std::path::Path;

use glam::DVec3;
use spheresweep::ShapeKind;
use spheresweep::contact::Body;
use spheresweep::io::xyz;
use spheresweep::sim::{EventGeometry, EventRecord, SphereState};

use super::events;
use crate::memory::{human, parse_bytes};
use crate::number::num;

/// The longest a float is written (`{:?}`, shortest round trip): sign, 17 digits, point,
/// exponent of three digits.
const WORST: f64 = -1.234_567_890_123_456_7e-300;

/// How many bytes the outputs may take, and where the figure comes from.
#[derive(Debug, Clone)]
pub struct Budget {
    pub max: u64,
    pub free: u64,
    pub source: String,
}

impl Budget {
    /// `--max-output`, or half the space free on the disk of `dir` (which exists).
    pub fn new(max_output: Option<&str>, dir: &Path) -> Result<Self, String> {
        let free = fs4::available_space(dir)
            .map_err(|e| format!("cannot read the free space of {}: {e}", dir.display()))?;
        Ok(match max_output {
            Some(text) => Self {
                max: parse_bytes(text).ok_or_else(|| {
                    format!("--max-output {text:?} is not a size in bytes (e.g. 500M, 2G)")
                })?,
                free,
                source: format!("--max-output {text}"),
            },
            None => Self {
                max: free / 2,
                free,
                source: format!(
                    "half of the {} free on the disk of {} (--max-output to change)",
                    human(free),
                    dir.display()
                ),
            },
        })
    }

    /// Refuses a run whose outputs would take more than the budget or the free space:
    /// `frames` more frames of at most `frame` bytes after `written` bytes.
    pub fn check_projection(&self, frames: u64, frame: u64, written: u64) -> Result<(), String> {
        let projected = frames.saturating_mul(frame).saturating_add(written);
        let (limit, what) = if self.max <= self.free {
            (self.max, self.source.clone())
        } else {
            (
                self.free,
                format!("the disk's free space ({})", human(self.free)),
            )
        };
        if projected <= limit {
            return Ok(());
        }
        Err(format!(
            "the outputs would take up to {}: {frames} frames of at most {} each{}; but {what} \
             allows {}: refused before the run; take snapshots less often or fewer spheres, or \
             raise --max-output",
            human(projected),
            human(frame),
            if written > 0 {
                format!(", after the {} written so far", human(written))
            } else {
                String::new()
            },
            human(limit)
        ))
    }

    /// The error of a run whose outputs passed the budget at time `t`.
    pub fn passed(&self, t: f64, written: u64) -> String {
        format!(
            "the outputs passed {} ({}) at t = {}, with {} written or due: stopped; their \
             partial files and the checkpoint removed",
            self.source,
            human(self.max),
            num(t),
            human(written)
        )
    }
}

/// At most this many bytes a frame of `n` spheres takes in `trajectory.xyz`.
pub fn frame_bound(n: usize, periodic: bool) -> u64 {
    let sphere = SphereState {
        centre: DVec3::splat(WORST),
        velocity: DVec3::splat(WORST),
        radius: WORST,
        mass: 1.0,
        material: u16::MAX,
    };
    let box_ = periodic.then_some(DVec3::splat(WORST));
    let bytes = |spheres: &[SphereState]| {
        let mut out = Vec::new();
        xyz::write_frame(&mut out, spheres, WORST, box_).expect("writes to memory");
        out.len() as u64
    };
    let (none, one) = (bytes(&[]), bytes(&[sphere]));
    // The count line of `none` says `0`: n has up to 20 digits.
    none + 19 + (one - none) * n as u64
}

/// At most this many bytes a row of `events.csv` takes.
pub fn event_bound(geometry: bool) -> u64 {
    let row = |kind| {
        let e = EventRecord {
            time: WORST,
            sphere: u32::MAX,
            other: Body::new(kind, u32::MAX),
            approach: WORST,
            restitution: WORST,
            energy_lost: WORST,
            geometry: Some(EventGeometry {
                point: DVec3::splat(WORST),
                normal: DVec3::splat(WORST),
            }),
        };
        let mut out = Vec::new();
        events::write(&mut out, &[e], geometry).expect("writes to memory");
        out.len() as u64
    };
    ShapeKind::ALL.map(row).into_iter().max().unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use spheresweep::sim::{Effects, Simulation, World, generate};

    /// The bounds hold for real frames and events, and are within a factor of two of them.
    #[test]
    fn the_bounds_hold_for_a_real_gas() {
        let mut world = World::default();
        generate::periodic_gas(&mut world, 500, 0.25, 0.5, 1.0, 1).unwrap();
        world.effects = Effects {
            record_events: true,
            geometry: true,
            ..Effects::default()
        };
        let size = match world.boundary {
            spheresweep::sim::Boundary::Periodic { size } => size,
            _ => unreachable!(),
        };
        let mut sim = Simulation::new(world).unwrap();
        sim.advance_to(3.0).unwrap();
        let mut frame = Vec::new();
        xyz::write_frame(&mut frame, &sim.spheres(), sim.time(), Some(size)).unwrap();
        let bound = frame_bound(500, true);
        assert!(frame.len() as u64 <= bound && bound < 2 * frame.len() as u64);
        let log = sim.take_events();
        let mut rows = Vec::new();
        events::write(&mut rows, &log, true).unwrap();
        let bound = event_bound(true) * log.len() as u64;
        assert!(!log.is_empty() && rows.len() as u64 <= bound && bound < 2 * rows.len() as u64);
        assert!(event_bound(false) < event_bound(true));
    }
}
