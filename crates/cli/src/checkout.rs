//! Files a git checkout tracks are not replaced without `--force`: a report written into a
//! checkout (docs/accuracy.md at its root, say) would otherwise replace the committed one
//! without a word.
//!
//! Whether a file is tracked is git's answer (`git ls-files --error-unmatch`, run in the
//! file's directory). Without a git to ask, an existing file with a `.git` in one of its
//! directories' ancestors counts as tracked: it cannot be told apart, and the safe side is to
//! ask for `--force`.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// How `path` stands with git.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Tracked {
    /// It does not exist, or no checkout tracks it.
    No,
    /// A checkout tracks it (git said so).
    Yes,
    /// There is no git to ask, and `.git` is in this ancestor directory.
    InCheckout(PathBuf),
}

/// Whether replacing `path` would replace a file a checkout tracks.
pub fn tracked(path: &Path) -> Tracked {
    if !path.is_file() {
        return Tracked::No;
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path.file_name().unwrap_or_default();
    let asked = Command::new("git")
        .arg("-C")
        .arg(dir)
        .args(["ls-files", "--error-unmatch", "--"])
        .arg(name)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    match asked {
        Ok(status) if status.success() => Tracked::Yes,
        // Not tracked (1), or not in a repository (128).
        Ok(_) => Tracked::No,
        Err(_) => match std::fs::canonicalize(dir).ok().and_then(|d| {
            d.ancestors()
                .find(|a| a.join(".git").exists())
                .map(Path::to_path_buf)
        }) {
            Some(root) => Tracked::InCheckout(root),
            None => Tracked::No,
        },
    }
}

/// Refuses to replace `path` when a checkout tracks it, unless `force`; `flag` is the option
/// that named it (for the message).
pub fn refuse_tracked(path: &Path, flag: &str, force: bool) -> Result<(), String> {
    let why = match tracked(path) {
        Tracked::No => return Ok(()),
        _ if force => return Ok(()),
        Tracked::Yes => "git tracks it".to_string(),
        Tracked::InCheckout(root) => format!(
            "it is in the git checkout at {} (no git to ask whether it is tracked)",
            root.display()
        ),
    };
    Err(format!(
        "{flag} {}: {why}, and writing it would replace the committed file: give --force to \
         replace it, or another {flag}",
        path.display()
    ))
}
