//! What every example shares: its two flags and writing an output file safely.
//!
//! Kept small on purpose: the examples are meant to be read and copied, and this is the only
//! code they do not show inline.

use std::path::{Path, PathBuf};

/// The command line every example takes: `--small` (the size CI runs) and `--out DIR`.
pub struct Args {
    /// Run the small size (a few seconds in the dev profile) instead of the full one.
    pub small: bool,
    /// Where the example writes its files.
    pub out: PathBuf,
}

impl Args {
    /// Reads `--small` and `--out DIR` (default `target/examples-out/<name>`); anything else is
    /// an error naming the argument.
    pub fn parse(name: &str) -> Result<Self, String> {
        let mut args = Self {
            small: false,
            out: Path::new("target/examples-out").join(name),
        };
        let mut it = std::env::args().skip(1);
        while let Some(arg) = it.next() {
            match arg.as_str() {
                "--small" => args.small = true,
                "--out" => {
                    args.out = it.next().ok_or("--out needs a directory after it")?.into();
                }
                "-h" | "--help" => {
                    println!("usage: cargo run --example {name} -- [--small] [--out DIR]");
                    std::process::exit(0);
                }
                other => {
                    return Err(format!(
                        "unknown argument {other:?} (expected --small or --out DIR)"
                    ));
                }
            }
        }
        Ok(args)
    }
}

/// Writes `contents` to `dir/file` under a temporary name, then renames it into place, so a
/// reader never sees half a file and a failed run leaves the previous output whole.
pub fn write_atomic(dir: &Path, file: &str, contents: &str) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("cannot create the output directory {}: {e}", dir.display()))?;
    let path = dir.join(file);
    let staging = dir.join(format!(".{file}.partial"));
    std::fs::write(&staging, contents)
        .map_err(|e| format!("cannot write {}: {e}", staging.display()))?;
    std::fs::rename(&staging, &path).map_err(|e| {
        let _ = std::fs::remove_file(&staging);
        format!("cannot move {} into place: {e}", path.display())
    })?;
    Ok(path)
}

/// Turns a failed check into the example's error: `check(cond, || format!(..))?`.
pub fn check(ok: bool, message: impl FnOnce() -> String) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(format!("check failed: {}", message()))
    }
}
