//! Outputs that appear whole or not at all, for every subcommand: a file or directory is
//! written under a temporary name beside its final path and renamed into place when complete,
//! so an existing output is either kept whole or replaced whole, never truncated by a failure
//! half-way; dropped before that, the temporary is removed (the `tempfile` crate's
//! [`TempPath`] and [`NamedTempFile`] do the removing and the renaming).
//!
//! The temporary of `NAME` is `.NAME.PID.tmp` (PID: the writing process), an earlier output
//! set aside while its replacement goes in is `.NAME.PID.old`, and the next command writing
//! `NAME` removes those a killed process left ([`remove_stale_temporaries`]). `run` keeps its
//! outputs under `.NAME.partial` instead, which a resume continues (`run/staged.rs`); it puts
//! them in place with [`persist`] too.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use tempfile::{NamedTempFile, TempDir, TempPath};

/// The directories this process made for its outputs, deepest first within each call
/// ([`make_dirs`]); those still empty when a command fails are removed ([`remove_made_dirs`]).
static MADE: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Makes `dir` and its missing parents, noting each one made.
pub fn make_dirs(dir: &Path) -> std::io::Result<()> {
    let mut missing = Vec::new();
    let mut at = Some(dir);
    while let Some(d) = at.filter(|d| !d.as_os_str().is_empty() && !d.exists()) {
        missing.push(d.to_path_buf());
        at = d.parent();
    }
    std::fs::create_dir_all(dir)?;
    MADE.lock()
        .unwrap_or_else(|e| e.into_inner())
        .extend(missing);
    Ok(())
}

/// After a failed or interrupted command: removes the directories [`make_dirs`] made that
/// are still empty (a failure before anything was written leaves no empty output directory;
/// one that holds a checkpoint or a kept partial output stays).
pub fn remove_made_dirs() {
    let made = std::mem::take(&mut *MADE.lock().unwrap_or_else(|e| e.into_inner()));
    // `remove_dir` removes only an empty directory; the deepest go first, then their parents.
    for dir in made.iter().rev().chain(made.iter()) {
        let _ = std::fs::remove_dir(dir);
    }
}

/// The message of a failure to write `path`.
fn fail(path: &Path) -> impl Fn(std::io::Error) -> String + '_ {
    move |e| format!("cannot write {}: {e}", path.display())
}

/// What becomes of a temporary that could not be put in place.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OnFailure {
    /// Removed: a temporary output.
    Remove,
    /// Kept: `run`'s partial output, which a resume from its last checkpoint continues.
    Keep,
}

/// Syncs `file`, the file at `tmp`, to disk and renames it to `path`: how every output is put
/// in place.
pub fn persist(
    file: &File,
    tmp: TempPath,
    path: &Path,
    on_failure: OnFailure,
) -> Result<(), String> {
    let kept = |tmp: TempPath| {
        if on_failure == OnFailure::Keep {
            let _ = tmp.keep();
        }
    };
    if let Err(e) = file.sync_all() {
        kept(tmp);
        return Err(fail(path)(e));
    }
    tmp.persist(path).map_err(|e| {
        kept(e.path);
        fail(path)(e.error)
    })
}

/// Writes `bytes` to `path` atomically: a temporary file beside it, synced, then renamed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let out = AtomicFile::create(path)?;
    let mut writer = out.writer()?;
    writer.write_all(bytes).map_err(fail(path))?;
    finish_writer(writer, fail(path))?;
    out.commit()
}

/// A file written under its temporary name ([`temporary`]), renamed to its path by
/// [`AtomicFile::commit`]; dropped before that, the temporary is removed.
#[derive(Debug)]
pub struct AtomicFile {
    path: PathBuf,
    file: NamedTempFile,
}

impl AtomicFile {
    /// Creates the temporary file of `path` (replacing one of this process, if any).
    pub fn create(path: &Path) -> Result<Self, String> {
        // The temporary's guard first: from here on, a failure removes the file.
        let tmp = TempPath::try_from_path(temporary(path)).map_err(fail(path))?;
        let file = File::create(&tmp).map_err(fail(path))?;
        Ok(Self {
            path: path.to_path_buf(),
            file: NamedTempFile::from_parts(file, tmp),
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// A buffered writer on the temporary file (a second handle on it).
    pub fn writer(&self) -> Result<BufWriter<File>, String> {
        let clone = self.file.as_file().try_clone().map_err(fail(&self.path))?;
        Ok(BufWriter::with_capacity(1 << 20, clone))
    }

    /// A message for an error while writing.
    pub fn error(&self, e: impl std::fmt::Display) -> String {
        format!("cannot write {}: {e}", self.path.display())
    }

    /// Syncs the file and renames it into place (every writer must have been flushed).
    pub fn commit(self) -> Result<(), String> {
        let (file, tmp) = self.file.into_parts();
        persist(&file, tmp, &self.path, OnFailure::Remove)
    }
}

/// A directory built under its temporary name ([`temporary`]) and swapped into place by
/// [`AtomicDir::commit`]; dropped before that, the temporary directory is removed.
#[derive(Debug)]
pub struct AtomicDir {
    path: PathBuf,
    tmp: TempDir,
}

impl AtomicDir {
    /// Creates the temporary directory of `path` (and `path`'s parents), removing the
    /// temporaries of `path` that a killed process left and an earlier one of this process.
    pub fn create(path: &Path) -> Result<Self, String> {
        if let Some(parent) = path.parent()
            && !parent.as_os_str().is_empty()
        {
            make_dirs(parent).map_err(fail(path))?;
        }
        remove_stale_temporaries(std::slice::from_ref(&path.to_path_buf()));
        let _ = std::fs::remove_dir_all(temporary(path));
        let tmp = tempfile::Builder::new()
            .prefix(&stem(path))
            .suffix(".tmp")
            .rand_bytes(0)
            .tempdir_in(directory(path))
            .map_err(fail(path))?;
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Creates file `name` in the temporary directory.
    pub fn create_file(&self, name: &str) -> Result<File, String> {
        File::create(self.tmp.path().join(name)).map_err(fail(&self.path))
    }

    /// A message for an error while writing.
    pub fn error(&self, e: impl std::fmt::Display) -> String {
        format!("cannot write {}: {e}", self.path.display())
    }

    /// Renames the finished directory into place (its files must have been synced). An
    /// earlier output at the path is moved aside first ([`set_aside`]) and removed after.
    pub fn commit(self) -> Result<(), String> {
        let old = set_aside(&self.path);
        let had_old = self.path.exists();
        if had_old {
            let _ = std::fs::remove_dir_all(&old);
            std::fs::rename(&self.path, &old).map_err(fail(&self.path))?;
        }
        if let Err(e) = std::fs::rename(self.tmp.path(), &self.path) {
            if had_old {
                let _ = std::fs::rename(&old, &self.path);
            }
            return Err(fail(&self.path)(e));
        }
        // Renamed: nothing is left at the temporary name to remove.
        let _ = self.tmp.keep();
        if had_old {
            let _ = std::fs::remove_dir_all(&old);
        }
        if let Ok(dir) = File::open(&self.path) {
            let _ = dir.sync_all();
        }
        Ok(())
    }
}

/// Flushes a buffered writer and syncs its file.
pub fn finish_writer(
    mut w: BufWriter<File>,
    error: impl Fn(std::io::Error) -> String,
) -> Result<(), String> {
    w.flush().map_err(&error)?;
    let file = w.into_inner().map_err(|e| error(e.into_error()))?;
    file.sync_all().map_err(error)
}

/// The directory `path` is in (`.` for a bare name).
pub fn directory(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The temporary name beside `path` that this process writes it under: `.NAME.PID.tmp`.
pub fn temporary(path: &Path) -> PathBuf {
    beside(path, "tmp")
}

/// The name beside `path` an earlier output is moved to while its replacement is renamed into
/// place: `.NAME.PID.old`.
pub fn set_aside(path: &Path) -> PathBuf {
    beside(path, "old")
}

/// `.NAME.PID`, the start of this process's leftover names of `path`.
fn stem(path: &Path) -> String {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    format!(".{name}.{}", std::process::id())
}

fn beside(path: &Path, suffix: &str) -> PathBuf {
    directory(path).join(format!("{}.{suffix}", stem(path)))
}

/// The process id in `file_name` if it is a temporary of `output` ([`temporary`]'s name for
/// it, written by any process).
pub fn is_temporary_of(file_name: &str, output: &Path) -> Option<u32> {
    leftover_of(file_name, output, "tmp")
}

/// The process id in `file_name` if it is an earlier output that process set aside
/// ([`set_aside`]'s name for it).
fn is_set_aside_of(file_name: &str, output: &Path) -> Option<u32> {
    leftover_of(file_name, output, "old")
}

fn leftover_of(file_name: &str, output: &Path, suffix: &str) -> Option<u32> {
    let name = output.file_name()?.to_str()?;
    let pid = file_name
        .strip_prefix('.')?
        .strip_prefix(name)?
        .strip_prefix('.')?
        .strip_suffix(suffix)?
        .strip_suffix('.')?;
    if pid.is_empty() || !pid.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    pid.parse().ok()
}

/// Whether process `pid` is running. Without /proc nothing can be told, and every process
/// counts as running (so no temporary is removed).
fn running(pid: u32) -> bool {
    !Path::new("/proc/self").exists() || Path::new("/proc").join(pid.to_string()).exists()
}

/// Removes the temporaries of `outputs` (files or directories) whose process is no longer
/// running: what a process killed while writing them (SIGKILL) left behind. An earlier output
/// set aside by such a process goes too once the output itself is in place (killed between
/// its two renames; without the output, the set-aside copy is the only one and is kept).
/// Temporaries of a running process, this one's included, and every other file are left alone.
pub fn remove_stale_temporaries(outputs: &[PathBuf]) {
    let mut dirs: Vec<PathBuf> = outputs.iter().map(|p| directory(p)).collect();
    dirs.sort();
    dirs.dedup();
    for dir in dirs {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let name = entry.file_name();
            let Some(name) = name.to_str() else { continue };
            let stale = outputs
                .iter()
                .filter(|o| directory(o) == dir)
                .find_map(|o| {
                    is_temporary_of(name, o)
                        .or_else(|| is_set_aside_of(name, o).filter(|_| o.exists()))
                })
                .is_some_and(|pid| !running(pid));
            if stale {
                let path = entry.path();
                let _ = match entry.file_type() {
                    Ok(t) if t.is_dir() => std::fs::remove_dir_all(&path),
                    _ => std::fs::remove_file(&path),
                };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporaries_are_told_by_name_and_process() {
        let out = Path::new("dir/pairs-toi.csv");
        let mine = temporary(out);
        let name = mine.file_name().unwrap().to_str().unwrap();
        assert_eq!(is_temporary_of(name, out), Some(std::process::id()));
        assert_eq!(is_temporary_of(".pairs-toi.csv.77.tmp", out), Some(77));
        assert_eq!(is_set_aside_of(".pairs-toi.csv.77.old", out), Some(77));
        assert_eq!(is_set_aside_of(".pairs-toi.csv.77.tmp", out), None);
        for other in [
            "pairs-toi.csv",
            ".pairs-toi.csv.tmp",
            ".pairs-toi.csv..tmp",
            ".pairs-toi.csv.7x.tmp",
            ".pairs-toi.csv.77.old",
            ".other.csv.77.tmp",
            ".pairs-toi.csv.x.77.tmp",
        ] {
            assert_eq!(is_temporary_of(other, out), None, "{other}");
        }
    }

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("spheresweep-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// The names in `dir`, sorted.
    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_file_is_written_under_its_temporary_name_and_removed_if_dropped() {
        let dir = scratch("file");
        let path = dir.join("out.csv");
        std::fs::write(&path, "old").unwrap();
        let a = AtomicFile::create(&path).unwrap();
        let mut w = a.writer().unwrap();
        w.write_all(b"new").unwrap();
        finish_writer(w, |e| a.error(e)).unwrap();
        assert!(temporary(&path).is_file());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        drop(a);
        assert_eq!(listing(&dir), ["out.csv"]);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
        write_atomic(&path, b"new").unwrap();
        assert_eq!(listing(&dir), ["out.csv"]);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "new");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_directory_replaces_an_earlier_one_whole_or_is_removed_if_dropped() {
        let dir = scratch("dir");
        let path = dir.join("toi");
        std::fs::create_dir(&path).unwrap();
        std::fs::write(path.join("time.npy"), "old").unwrap();
        let a = AtomicDir::create(&path).unwrap();
        assert_eq!(a.tmp.path(), temporary(&path));
        a.create_file("kind.npy").unwrap();
        drop(a);
        assert_eq!(listing(&dir), ["toi"]);
        assert_eq!(listing(&path), ["time.npy"]);
        let b = AtomicDir::create(&path).unwrap();
        b.create_file("kind.npy").unwrap();
        b.commit().unwrap();
        assert_eq!(listing(&dir), ["toi"]);
        assert_eq!(listing(&path), ["kind.npy"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
