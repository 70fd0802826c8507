//! The output directory of a run: the names of its files, and the temporaries a killed run
//! leaves in it.

use std::path::{Path, PathBuf};

pub const TRAJECTORY: &str = "trajectory.xyz";
pub const EVENTS: &str = "events.csv";
pub const SUMMARY: &str = "summary.json";
pub const CHECKPOINT: &str = "checkpoint.bin";

/// Every file a run writes in its directory.
pub const ALL: [&str; 4] = [TRAJECTORY, EVENTS, SUMMARY, CHECKPOINT];

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
        Ok(Self(dir))
    }

    pub fn file(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// Removes the temporary files (`.NAME.PID.tmp`) that a run killed while it wrote a
    /// checkpoint or its summary left behind, whatever their process.
    pub fn remove_temporaries(&self) {
        for entry in std::fs::read_dir(&self.0).into_iter().flatten().flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if ALL
                .iter()
                .any(|o| name.starts_with(&format!(".{o}.")) && name.ends_with(".tmp"))
            {
                let _ = std::fs::remove_file(entry.path());
            }
        }
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
