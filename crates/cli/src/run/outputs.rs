//! The output directory of a run: the names of its files, the manifest that says which run
//! they belong to (the `run` field of `summary.json`), and the rule of one run a directory. A
//! new run refuses a directory that holds another run's files unless `--force`; a completing
//! run replaces the outputs in an order that never leaves a manifest beside another run's
//! files: the old manifest goes first, the new one comes last.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::options::Settings;
use super::staged::{Staged, partial_path};
use crate::number::num;

pub const TRAJECTORY: &str = "trajectory.xyz";
pub const EVENTS: &str = "events.csv";
pub const SUMMARY: &str = "summary.json";
pub const CHECKPOINT: &str = "checkpoint.bin";

/// Every file a run writes in its directory.
pub const ALL: [&str; 4] = [TRAJECTORY, EVENTS, SUMMARY, CHECKPOINT];

/// Which run the outputs in a directory belong to: the `run` field of `summary.json`. The
/// settings that shape the outputs, and no others (checkpoints do not change them).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// The fingerprint of the scene's world (16 hexadecimal digits).
    pub fingerprint: String,
    /// The end time asked for.
    pub t_end: f64,
    /// The snapshot spacing; `None`: no snapshots.
    pub snapshot_every: Option<f64>,
    /// Whether events are recorded.
    pub record_events: bool,
    /// Whether the event rows carry the contact point and normal.
    pub geometry: bool,
    /// The files of the run in the directory.
    pub outputs: Vec<String>,
}

impl Manifest {
    pub fn new(fingerprint: u64, s: &Settings) -> Self {
        let mut outputs = Vec::new();
        if s.snapshot_every.is_some() {
            outputs.push(TRAJECTORY.to_string());
        }
        if s.record_events {
            outputs.push(EVENTS.to_string());
        }
        outputs.push(SUMMARY.to_string());
        Self {
            fingerprint: super::hash::text(fingerprint),
            t_end: s.t_end,
            snapshot_every: s.snapshot_every,
            record_events: s.record_events,
            geometry: s.geometry,
            outputs,
        }
    }

    fn describe(&self) -> String {
        let every = |x: Option<f64>| x.map_or_else(|| "none".into(), num);
        format!(
            "scene fingerprint {}, t_end {}, snapshots every {}",
            self.fingerprint,
            num(self.t_end),
            every(self.snapshot_every)
        )
    }
}

/// A run's output directory.
#[derive(Debug, Clone)]
pub struct OutDir(pub PathBuf);

impl OutDir {
    /// `--out`, or `<stem>-run/` beside the scene; refused if it is a file, or cannot be
    /// written (made if it does not exist).
    pub fn new(out: Option<&Path>, scene: &Path) -> Result<Self, String> {
        let dir = out.map_or_else(|| default_out(scene), Path::to_path_buf);
        if dir.exists() && !dir.is_dir() {
            return Err(format!("--out {}: not a directory", dir.display()));
        }
        crate::output::check_writable(&dir.join(SUMMARY))?;
        // The scene is never one of the outputs (through a link or not).
        for name in ALL {
            crate::output::not_an_input(&dir.join(name), &[scene])?;
        }
        Ok(Self(dir))
    }

    /// Takes the directory for this process until it ends (an advisory lock on the directory
    /// itself, released by the system whatever way the process ends): a second run into it
    /// meanwhile is refused.
    pub fn lock(&self) -> Result<std::fs::File, String> {
        let dir = std::fs::File::open(&self.0)
            .map_err(|e| format!("cannot open {}: {e}", self.0.display()))?;
        match dir.try_lock() {
            Ok(()) => Ok(dir),
            Err(std::fs::TryLockError::WouldBlock) => Err(format!(
                "--out {}: another spheresweep run is writing to it; wait for it to end, or give \
                 another --out",
                self.0.display()
            )),
            Err(std::fs::TryLockError::Error(e)) => {
                Err(format!("cannot lock {}: {e}", self.0.display()))
            }
        }
    }

    pub fn file(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// The run's files present in the directory: outputs, checkpoint, partial files.
    fn present(&self) -> Vec<PathBuf> {
        ALL.iter()
            .map(|name| self.file(name))
            .chain([TRAJECTORY, EVENTS].map(|name| partial_path(&self.file(name))))
            .filter(|p| p.exists())
            .collect()
    }

    /// The manifest of the run whose summary is in the directory, if it has one.
    fn manifest(&self) -> Option<Manifest> {
        let text = std::fs::read_to_string(self.file(SUMMARY)).ok()?;
        let value: serde_json::Value = serde_json::from_str(&text).ok()?;
        serde_json::from_value(value.get("run")?.clone()).ok()
    }

    /// A new run (not a resume) takes the directory: refused if it holds the files of another
    /// run, or of this same one, unless `force`; with `force` the other run's checkpoint and
    /// partial files are removed now (its outputs when this run completes).
    pub fn claim(&self, ours: &Manifest, force: bool) -> Result<(), String> {
        let present = self.present();
        if present.is_empty() {
            return Ok(());
        }
        if force {
            let other = [
                self.file(CHECKPOINT),
                partial_path(&self.file(TRAJECTORY)),
                partial_path(&self.file(EVENTS)),
            ];
            return other.into_iter().try_for_each(remove);
        }
        let whose = if self.file(CHECKPOINT).exists() {
            format!(
                "the checkpoint of an interrupted run: resume it with --resume {}",
                self.file(CHECKPOINT).display()
            )
        } else {
            match self.manifest() {
                Some(m) if &m == ours => {
                    "the outputs of this same scene and options, complete: nothing to do".into()
                }
                Some(m) => format!("the outputs of another run ({})", m.describe()),
                None if self.file(SUMMARY).exists() => "the files of another run, its \
                    summary.json naming no run this version reads (one of an earlier version, \
                    or another program's)"
                    .into(),
                None => "the files of another run, and no summary.json naming it (an \
                         unfinished run, or one of an earlier version)"
                    .into(),
            }
        };
        let names: Vec<String> = present
            .iter()
            .map(|p| {
                p.file_name()
                    .unwrap_or_default()
                    .to_string_lossy()
                    .into_owned()
            })
            .collect();
        Err(format!(
            "--out {} holds {whose} ({}); give another --out, or --force to replace them",
            self.0.display(),
            names.join(", ")
        ))
    }

    /// The end of a run: the old manifest removed, the staged outputs renamed into place, the
    /// outputs this run does not write (another run's) and the checkpoint removed. The caller then
    /// writes the summary with the new manifest, last.
    pub fn replace_outputs(&self, staged: Vec<Staged>, ours: &Manifest) -> Result<(), String> {
        remove(self.file(SUMMARY))?;
        for s in staged {
            s.commit()?;
        }
        for name in [TRAJECTORY, EVENTS] {
            if !ours.outputs.iter().any(|o| o == name) {
                remove(self.file(name))?;
            }
        }
        remove(self.file(CHECKPOINT))
    }

    /// Removes the temporary files (`.NAME.PID.tmp`) that a run killed while it wrote a
    /// checkpoint or its summary left behind, whatever their process.
    pub fn remove_temporaries(&self) {
        for entry in std::fs::read_dir(&self.0).into_iter().flatten().flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if ALL
                .iter()
                .any(|o| crate::atomic::is_temporary_of(&name, Path::new(o)).is_some())
            {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// Removes a file, if it is there.
fn remove(p: PathBuf) -> Result<(), String> {
    match std::fs::remove_file(&p) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(format!("cannot remove {}: {e}", p.display()))
        }
        _ => Ok(()),
    }
}

/// The default output directory: `<stem>-run/` beside the scene.
fn default_out(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let dir = match scene.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    dir.join(format!("{stem}-run"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_output_is_beside_the_scene() {
        assert_eq!(
            default_out(Path::new("scenes/gas.toml")),
            Path::new("scenes/gas-run")
        );
        assert_eq!(default_out(Path::new("gas.toml")), Path::new("./gas-run"));
    }
}
