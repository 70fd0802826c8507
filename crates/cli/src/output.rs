//! Output paths checked before any work starts: that they can be written, and that an output
//! is never an input (the same file by device and inode, through any link) nor another output.
//! The writing itself, under a temporary name renamed into place, is `atomic`'s.

use std::os::unix::fs::MetadataExt;
use std::path::{Component, Path, PathBuf};

use crate::atomic::{directory, make_dirs, remove_stale_temporaries, temporary};

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
    make_dirs(&dir).map_err(fail)?;
    remove_stale_temporaries(std::slice::from_ref(&path.to_path_buf()));
    let probe = temporary(path);
    std::fs::File::create(&probe).map_err(fail)?;
    std::fs::remove_file(&probe).map_err(fail)?;
    Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;

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
