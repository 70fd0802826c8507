//! The options of `spheresweep run`, and the settings that make a run what it is: the end
//! time, the snapshot spacing, the checkpoint spacing and what is recorded. A checkpoint records
//! them, and a resume must give the same ones (a resumed run continues the same run).

use std::path::PathBuf;

use spheresweep::io::scene_file::RunSettings;
use spheresweep::sim::Effects;

use crate::number::num;

/// Options of `spheresweep run`.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "Ctrl-C or SIGTERM stops the run between two events: earlier files are \
kept, temporary files removed, a last checkpoint written with --checkpoint-every; exit code 130. \
A scene too large for the memory available (MemAvailable, or SPHERESWEEP_MAX_MEMORY in bytes, \
e.g. 512M) is refused before it is built; so are outputs projected beyond --max-output."
)]
pub struct Args {
    /// The scene file: TOML, or JSON if its name ends in .json.
    pub scene: PathBuf,
    /// Directory for trajectory.xyz, events.csv and summary.json (default: `<stem>-run/`
    /// beside the scene; with --resume, the checkpoint's directory). One run a directory: a directory that holds another run's outputs,
    /// or a checkpoint, is refused without --force.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// End time, in the scene's time unit (its lengths over its speeds); finite and greater
    /// than 0. Default: the scene's `[run] t_end`.
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = number)]
    pub t_end: Option<f64>,
    /// Time between snapshots, in the scene's time unit; 0 for none, at most 10⁶ snapshots.
    /// Default: the scene's `[run] snapshot_every`.
    #[arg(long, value_name = "EVERY", allow_negative_numbers = true, value_parser = number)]
    pub snapshots: Option<f64>,
    /// No progress bar, nor progress lines.
    #[arg(long)]
    pub quiet: bool,
    /// Where stderr is not a terminal (a log file, a batch job), a progress line (simulated
    /// time, collisions, seconds so far) at most every SECONDS, in place of the bar; finite and
    /// greater than 0.
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = 60.0,
        allow_negative_numbers = true,
        value_parser = number
    )]
    pub progress_every: f64,
    /// Write `checkpoint.bin` in the output directory every T of simulated time (at the first
    /// snapshot or progress step past each T), atomically: a run killed at any moment resumes
    /// from the last one, and Ctrl-C or SIGTERM writes a last one before stopping. T is in the
    /// scene's time unit, finite and greater than 0. Default: no checkpoints.
    #[arg(long, value_name = "T", value_parser = number)]
    pub checkpoint_every: Option<f64>,
    /// Continue the run a checkpoint of this scene holds (`--checkpoint-every`): the outputs
    /// end exactly as those of a run never interrupted. Give the scene and options the run
    /// was started with (--out is the checkpoint's directory unless given): another end time, snapshot spacing, checkpoint spacing or scene
    /// is refused. Default: start from t = 0.
    #[arg(long, value_name = "CHECKPOINT")]
    pub resume: Option<PathBuf>,
    /// Replace the outputs of another run (or of this same run) in --out: its checkpoint and
    /// partial files are removed at the start, its outputs when this run completes (those
    /// this run does not write too), so that the directory never mixes two runs. Default:
    /// such a directory is refused.
    #[arg(long)]
    pub force: bool,
    /// Refuse a run whose outputs are projected to take more than this many bytes (suffixes
    /// K, M, G, T for powers of 1024), and stop one whose outputs pass it. Default: half the
    /// space free on the output directory's disk.
    #[arg(long, value_name = "BYTES")]
    pub max_output: Option<String>,
    /// Fault injection for the tests that show a broken engine is caught: the container-wall
    /// rules of before 2026-12-01 (`Simulation::break_walls_for_testing`).
    #[arg(long, hide = true)]
    pub break_walls_for_testing: bool,
}

/// What makes a run the run it is, beside its scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// The run ends at this time.
    pub t_end: f64,
    /// Time between snapshots, if any.
    pub snapshot_every: Option<f64>,
    /// Simulated time between checkpoints, if any.
    pub checkpoint_every: Option<f64>,
    /// Whether events.csv is written.
    pub record_events: bool,
    /// Whether its rows carry the contact point and normal.
    pub geometry: bool,
}

/// At most this many snapshots a run.
const MAX_SNAPSHOTS: f64 = 1e6;

/// Progress steps of a run without snapshots.
pub const STEPS: usize = 50;

/// A number flag as `f64`, refusing a literal beyond the `f64` range (which parses as
/// infinity: `--t-end 1e309` was echoed as `--t-end inf`) in the user's own words; `inf` and
/// `nan` written as such pass, for `check_flags` to refuse.
fn number(text: &str) -> Result<f64, String> {
    let x: f64 = text.trim().parse().map_err(|e| format!("{e}"))?;
    let written = text.to_ascii_lowercase();
    if x.is_infinite() && !written.contains("inf") {
        return Err(format!(
            "{text} is beyond the largest number the run computes with (about 1.8e308)"
        ));
    }
    Ok(x)
}

/// Refuses flags out of range, before anything is read or written.
pub fn check_flags(args: &Args) -> Result<(), String> {
    if let Some(t) = args.t_end
        && !(t.is_finite() && t > 0.0)
    {
        return Err(format!(
            "--t-end {} must be finite and greater than 0",
            num(t)
        ));
    }
    if let Some(s) = args.snapshots
        && !(s.is_finite() && s >= 0.0)
    {
        return Err(format!(
            "--snapshots {} must be finite and 0 (none) or more",
            num(s)
        ));
    }
    if let Some(c) = args.checkpoint_every
        && !(c.is_finite() && c > 0.0)
    {
        return Err(format!(
            "--checkpoint-every {} must be finite and greater than 0",
            num(c)
        ));
    }
    let p = args.progress_every;
    // At most a year (`Duration` takes any such number of seconds).
    if !(p > 0.0 && p <= 3.2e7) {
        return Err(format!(
            "--progress-every {} must be greater than 0 and at most a year (3.2e7 seconds)",
            num(p)
        ));
    }
    Ok(())
}

impl Settings {
    /// The scene's `[run]` and `[effects]`, overridden by the flags.
    pub fn resolve(args: &Args, run: &RunSettings, effects: &Effects) -> Self {
        Self {
            t_end: args.t_end.unwrap_or(run.t_end),
            snapshot_every: match args.snapshots {
                Some(s) => (s > 0.0).then_some(s),
                None => run.snapshot_every,
            },
            checkpoint_every: args.checkpoint_every,
            record_events: effects.record_events,
            geometry: effects.record_events && effects.geometry,
        }
    }

    /// Frames written from stop `next_stop` on (and the first one, at t = 0, from the start).
    pub fn frames_from(&self, next_stop: u64) -> u64 {
        if self.snapshot_every.is_none() {
            return 0;
        }
        let later = self
            .stops()
            .iter()
            .skip(next_stop as usize)
            .filter(|s| s.1)
            .count();
        later as u64 + u64::from(next_stop == 0)
    }

    /// Refuses more than a million snapshots.
    pub fn check(&self) -> Result<(), String> {
        if let Some(dt) = self.snapshot_every
            && self.t_end / dt > MAX_SNAPSHOTS
        {
            return Err(format!(
                "{} snapshots (t_end {} every {}) is more than a million: take them less often",
                num((self.t_end / dt).floor()),
                num(self.t_end),
                num(dt)
            ));
        }
        Ok(())
    }

    /// Refuses to continue, with these settings, a run that `recorded` describes: each setting
    /// that differs is named with both values.
    pub fn same_run(&self, recorded: &Settings) -> Result<(), String> {
        let every = |x: Option<f64>| x.map_or_else(|| "none".to_string(), num);
        let yes_no = |b: bool| if b { "true" } else { "false" }.to_string();
        let differences: Vec<String> = [
            (
                "--t-end (or the scene's t_end)",
                num(self.t_end),
                num(recorded.t_end),
            ),
            (
                "--snapshots (or the scene's snapshot_every)",
                every(self.snapshot_every),
                every(recorded.snapshot_every),
            ),
            (
                "--checkpoint-every",
                every(self.checkpoint_every),
                every(recorded.checkpoint_every),
            ),
            (
                "the scene's record_events",
                yes_no(self.record_events),
                yes_no(recorded.record_events),
            ),
            (
                "the scene's geometry",
                yes_no(self.geometry),
                yes_no(recorded.geometry),
            ),
        ]
        .into_iter()
        .filter(|(_, here, there)| here != there)
        .map(|(what, here, there)| format!("{what} is {here} here but {there} in the checkpoint"))
        .collect();
        if differences.is_empty() {
            return Ok(());
        }
        Err(format!(
            "{}: a resume continues the run the checkpoint holds, whose outputs so far were \
             written with its settings (another spacing or end would leave a trajectory and \
             summary of two runs); give the options the run was started with, or start a new \
             run",
            differences.join("; ")
        ))
    }

    /// The times a run stops at: every snapshot time, or [`STEPS`] even steps, ending at
    /// `t_end`. The flag says whether a snapshot is taken there.
    pub fn stops(&self) -> Vec<(f64, bool)> {
        let t_end = self.t_end;
        match self.snapshot_every {
            Some(dt) => {
                // Snapshots at k·dt (k ≥ 1) up to t_end, within rounding (a k·dt that rounds
                // just below t_end is t_end: 10 · 1e24 is 9.999999999999999e24, and the last
                // frame was there, the run ending after it); t_end itself if it falls between
                // two.
                let last = ((t_end / dt) * (1.0 + 1e-12)).floor() as u64;
                let near_end = t_end * (1.0 - 1e-12);
                let mut out: Vec<(f64, bool)> = (1..=last)
                    .map(|k| k as f64 * dt)
                    .map(|t| (if t >= near_end { t_end } else { t }, true))
                    .collect();
                if out.last().is_none_or(|&(t, _)| t < t_end) {
                    out.push((t_end, false));
                }
                out
            }
            // Fractions of `t_end` (`t_end · k` overflowed from 5e306), the last `t_end` itself
            // (`t_end · k / STEPS` rounded off it: 1e21 ended at 9.999999999999999e20).
            None => (1..=STEPS)
                .map(|k| match k {
                    STEPS => (t_end, false),
                    _ => (t_end * (k as f64 / STEPS as f64), false),
                })
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn every(t_end: f64, dt: Option<f64>) -> Settings {
        Settings {
            t_end,
            snapshot_every: dt,
            checkpoint_every: None,
            record_events: false,
            geometry: false,
        }
    }

    #[test]
    fn stops_end_at_t_end_and_mark_snapshots() {
        assert_eq!(
            every(1.0, Some(0.25)).stops(),
            [(0.25, true), (0.5, true), (0.75, true), (1.0, true)]
        );
        assert_eq!(
            every(1.0, Some(0.4)).stops(),
            [(0.4, true), (0.8, true), (1.0, false)]
        );
        // 0.1 · 3 rounds above 0.3: the last snapshot is still taken, at t_end.
        assert_eq!(every(0.3, Some(0.1)).stops().len(), 3);
        assert_eq!(every(0.3, Some(0.1)).stops().last(), Some(&(0.3, true)));
        // 10 · 1e24 rounds below 1e25: the tenth snapshot is still at t_end, and the last.
        let s = every(1e25, Some(1e24)).stops();
        assert_eq!((s.len(), s.last()), (10, Some(&(1e25, true))));
        assert_eq!(every(1.0, Some(0.4)).frames_from(0), 3);
        assert_eq!(every(1.0, Some(0.4)).frames_from(1), 1);
        assert_eq!(every(1.0, None).frames_from(0), 0);
        let s = every(2.0, None).stops();
        assert_eq!((s.len(), s[STEPS - 1]), (STEPS, (2.0, false)));
        // Huge ends: every stop finite and rising, the last the end itself.
        for t_end in [1e21, 5e20, 1e27, 1e304, 5e306, f64::MAX] {
            let s = every(t_end, None).stops();
            assert_eq!(s.last(), Some(&(t_end, false)));
            assert!(s.windows(2).all(|w| w[0].0 <= w[1].0 && w[1].0.is_finite()));
        }
    }

    #[test]
    fn a_resume_names_every_setting_that_differs_with_both_values() {
        let a = every(40.0, Some(2.0));
        assert!(a.same_run(&a).is_ok());
        let b = Settings {
            t_end: 1e300,
            snapshot_every: Some(4.0),
            ..a
        };
        let err = b.same_run(&a).unwrap_err();
        assert!(
            err.contains("--t-end (or the scene's t_end) is 1e300 here but 40 in the checkpoint")
                && err.contains("snapshot_every) is 4 here but 2 in the checkpoint"),
            "{err}"
        );
        let c = Settings {
            checkpoint_every: Some(2.0),
            record_events: true,
            ..a
        };
        let err = c.same_run(&a).unwrap_err();
        assert!(
            err.contains("--checkpoint-every is 2 here but none")
                && err.contains("record_events is true here but false"),
            "{err}"
        );
    }
}
