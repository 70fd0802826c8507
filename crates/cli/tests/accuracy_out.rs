//! `accuracy` writes to spheresweep-accuracy/ in the current directory by default, and never
//! replaces a file a git checkout tracks without `--force` (run at the root of a checkout, it
//! used to replace the committed docs/accuracy.md without a word).

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::{bin, scratch};

/// `spheresweep accuracy --cases 10 ARGS` run in `dir`, with `path` as PATH if given.
fn accuracy(dir: &Path, args: &[&str], path: Option<&Path>) -> Output {
    let mut command = bin();
    command
        .current_dir(dir)
        .args(["accuracy", "--cases", "10"])
        .args(args);
    if let Some(p) = path {
        command.env("PATH", p);
    }
    command.output().expect("the binary runs")
}

fn git(dir: &Path, args: &[&str]) {
    let ok = Command::new("git")
        .current_dir(dir)
        .args(args)
        .output()
        .expect("git runs")
        .status
        .success();
    assert!(ok, "git {args:?}");
}

/// A checkout in `dir` tracking docs/accuracy.md and docs/accuracy.svg ("committed"), with an
/// untracked notes.md beside them.
fn checkout(dir: &Path) {
    git(dir, &["init", "-q"]);
    std::fs::create_dir_all(dir.join("docs")).unwrap();
    for name in ["accuracy.md", "accuracy.svg", "notes.md"] {
        std::fs::write(dir.join("docs").join(name), "committed").unwrap();
    }
    git(dir, &["add", "docs/accuracy.md", "docs/accuracy.svg"]);
}

fn read(path: impl AsRef<Path>) -> String {
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn by_default_the_report_goes_to_its_own_directory_never_docs() {
    let dir = scratch("accuracy-default");
    checkout(&dir);
    let out = accuracy(&dir, &[], None);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(read(dir.join("spheresweep-accuracy/accuracy.md")).contains("accuracy.svg"));
    assert!(read(dir.join("spheresweep-accuracy/accuracy.svg")).contains("<svg"));
    assert_eq!(read(dir.join("docs/accuracy.md")), "committed");
    assert_eq!(read(dir.join("docs/accuracy.svg")), "committed");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_tracked_file_is_replaced_only_with_force() {
    let dir = scratch("accuracy-tracked");
    checkout(&dir);
    let out = accuracy(&dir, &["--out", "docs/accuracy.md"], None);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--out docs/accuracy.md: git tracks it") && err.contains("--force"),
        "{err}"
    );
    assert!(!err.contains("accuracy: the study"), "the study ran: {err}");
    assert_eq!(read(dir.join("docs/accuracy.md")), "committed");
    // The plot beside an untracked report is tracked: refused too.
    let out = accuracy(
        &dir,
        &["--out", "docs/notes.md", "--svg", "docs/accuracy.svg"],
        None,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--svg docs/accuracy.svg: git tracks it"),
        "{err}"
    );
    assert_eq!(read(dir.join("docs/notes.md")), "committed");
    // An untracked file in the checkout is an ordinary output.
    let out = accuracy(
        &dir,
        &["--out", "docs/notes.md", "--svg", "docs/notes.svg"],
        None,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_ne!(read(dir.join("docs/notes.md")), "committed");
    // --force replaces the tracked ones.
    let out = accuracy(&dir, &["--out", "docs/accuracy.md", "--force"], None);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(read(dir.join("docs/accuracy.md")).contains("accuracy.svg"));
    assert!(read(dir.join("docs/accuracy.svg")).contains("<svg"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn without_git_an_existing_file_in_a_checkout_needs_force() {
    let dir = scratch("accuracy-no-git");
    checkout(&dir);
    let empty = dir.join("no-programs");
    std::fs::create_dir(&empty).unwrap();
    let out = accuracy(&dir, &["--out", "docs/notes.md"], Some(&empty));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--out docs/notes.md: it is in the git checkout at")
            && err.contains("no git to ask"),
        "{err}"
    );
    assert_eq!(read(dir.join("docs/notes.md")), "committed");
    let out = accuracy(&dir, &["--out", "docs/notes.md", "--force"], Some(&empty));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::fs::remove_dir_all(&dir).ok();
}
