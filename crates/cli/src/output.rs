//! Output files that are never lost: checked before any work starts, written under a
//! temporary name in the same directory and renamed into place, so an existing file is either
//! kept whole or replaced whole — never truncated by a failure half-way. An output is never an
//! input (the same file by device and inode, through any link), and the temporaries a killed
//! process left for an output are removed by the next command writing that output.

use std::io::Write;
use std::os::unix::fs::MetadataExt;
use std::path::{Component, Path, PathBuf};

/// Checks that `path` can be written (its directory exists or can be made, and a file can be
/// created there) without touching an existing file at `path`; removes the temporaries of
/// `path` that a killed process left ([`remove_stale_temporaries`]).
pub fn check_writable(path: &Path) -> Result<(), String> {
    let fail = |e: std::io::Error| format!("cannot write {}: {e}", path.display());
    if path.is_dir() {
        return Err(format!(
            "cannot write {}: it is a directory",
            path.display()
        ));
    }
    if path.file_name().is_none() {
        return Err(format!("cannot write {}: no file name", path.display()));
    }
    let dir = directory(path);
    std::fs::create_dir_all(&dir).map_err(fail)?;
    remove_stale_temporaries(std::slice::from_ref(&path.to_path_buf()));
    let probe = temporary(path);
    std::fs::File::create(&probe).map_err(fail)?;
    std::fs::remove_file(&probe).map_err(fail)?;
    Ok(())
}

/// Writes `bytes` to `path` atomically: a temporary file beside it, flushed, then renamed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let fail = |e: std::io::Error| format!("cannot write {}: {e}", path.display());
    let tmp = temporary(path);
    let result = (|| {
        let mut file = std::fs::File::create(&tmp)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(fail)
}

/// Two outputs must not be the same file (the second would overwrite the first), through a
/// link or not.
pub fn distinct(a: &Path, b: &Path) -> Result<(), String> {
    if same_file(a, b) {
        Err(format!(
            "{} and {} are the same file{}: give each output its own path",
            a.display(),
            b.display(),
            through_link(a, b)
        ))
    } else {
        Ok(())
    }
}

/// Refuses an output that is one of `inputs`: the same file by device and inode (links
/// followed, hard links included), or, when it does not exist yet, a path that leads to an
/// input once its directories are made. The message names both paths.
pub fn not_an_input(output: &Path, inputs: &[&Path]) -> Result<(), String> {
    match inputs.iter().find(|input| same_file(output, input)) {
        Some(input) => Err(format!(
            "the output {} and the input {} are the same file{}: writing it would destroy the \
             input; give the output another path",
            output.display(),
            input.display(),
            through_link(output, input)
        )),
        None => Ok(()),
    }
}

/// Refuses a directory output, replaced whole when written, that holds one of `inputs`.
pub fn no_input_inside(output_dir: &Path, inputs: &[&Path]) -> Result<(), String> {
    let dir = resolve(output_dir);
    match inputs.iter().find(|input| resolve(input).starts_with(&dir)) {
        Some(input) => Err(format!(
            "the input {} is inside the output directory {}, which is replaced whole: give \
             the output another path",
            input.display(),
            output_dir.display()
        )),
        None => Ok(()),
    }
}

/// Whether `a` and `b` are one file: by device and inode when both exist (links followed),
/// else by where their paths lead.
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        (Ok(x), Ok(y)) => (x.dev(), x.ino()) == (y.dev(), y.ino()),
        _ => resolve(a) == resolve(b),
    }
}

/// `" (through a link)"` when the two paths, taken as written, differ.
fn through_link(a: &Path, b: &Path) -> &'static str {
    if lexical(a) == lexical(b) {
        ""
    } else {
        " (through a link)"
    }
}

/// `path` made absolute with `.` and `..` taken as written, no link followed.
fn lexical(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut out = PathBuf::new();
    for part in absolute.components() {
        match part {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// Where `path` leads: its longest existing ancestor with every link resolved, then the rest
/// of the path with `.` and `..` taken as the directories they will be once made.
fn resolve(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let parts: Vec<Component> = absolute.components().collect();
    for keep in (1..=parts.len()).rev() {
        let head: PathBuf = parts[..keep].iter().collect();
        if let Ok(mut resolved) = std::fs::canonicalize(&head) {
            for part in &parts[keep..] {
                match part {
                    Component::ParentDir => {
                        resolved.pop();
                    }
                    Component::CurDir => {}
                    other => resolved.push(other),
                }
            }
            return resolved;
        }
    }
    absolute
}

fn directory(path: &Path) -> PathBuf {
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

fn beside(path: &Path, suffix: &str) -> PathBuf {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    directory(path).join(format!(".{name}.{}.{suffix}", std::process::id()))
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

    #[test]
    fn a_path_not_made_yet_resolves_through_its_parents() {
        let dir = std::env::temp_dir().join(format!("spheresweep-resolve-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let input = dir.join("in.csv");
        std::fs::write(&input, "x").unwrap();
        assert!(same_file(&dir.join("new/../in.csv"), &input));
        assert!(same_file(&dir.join("new/./../in.csv"), &input));
        assert!(!same_file(&dir.join("new/in.csv"), &input));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
