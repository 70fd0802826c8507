//! Output files that are never lost: checked before any work starts, written under a
//! temporary name in the same directory and renamed into place, so an existing file is either
//! kept whole or replaced whole — never truncated by a failure half-way.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Checks that `path` can be written (its directory exists or can be made, and a file can be
/// created there) without touching an existing file at `path`.
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

/// Two outputs must not be the same file (the second would overwrite the first).
pub fn distinct(a: &Path, b: &Path) -> Result<(), String> {
    let canon = |p: &Path| {
        let dir = std::fs::canonicalize(directory(p)).unwrap_or_else(|_| directory(p));
        dir.join(p.file_name().unwrap_or_default())
    };
    if canon(a) == canon(b) {
        Err(format!(
            "{} and {} are the same file: give each output its own path",
            a.display(),
            b.display()
        ))
    } else {
        Ok(())
    }
}

fn directory(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

fn temporary(path: &Path) -> PathBuf {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    directory(path).join(format!(".{name}.{}.tmp", std::process::id()))
}
