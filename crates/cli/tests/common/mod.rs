//! Helpers shared by the binary's integration tests: the binary, paths in the repository, a
//! fresh scratch directory, and a `run` of the hard-sphere gas started in the background.
// Each test file uses a part of these.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

/// The `spheresweep` binary this test build made.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_spheresweep"))
}

/// A path inside the repository, given from its root.
pub fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

/// The binary run with `args` to its end.
pub fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

/// Bytes of the binary's output as text.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A scratch directory for one test: empty, under the system's temporary directory, named
/// after the test, and removed with everything in it when the value is dropped (also when the
/// test fails), so that test runs leave nothing behind. Reads as a `&Path`.
pub struct Scratch(tempfile::TempDir);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<std::ffi::OsStr> for Scratch {
    fn as_ref(&self) -> &std::ffi::OsStr {
        self.0.path().as_os_str()
    }
}

/// A new scratch directory named `spheresweep-cli-NAME-…`.
pub fn scratch(name: &str) -> Scratch {
    let dir = tempfile::Builder::new()
        .prefix(&format!("spheresweep-cli-{name}-"))
        .tempdir()
        .expect("a scratch directory");
    Scratch(dir)
}

/// A shipped scene file's path, `scenes/NAME.toml`.
pub fn shipped(name: &str) -> String {
    format!("{}/../../scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"))
}

/// `spheresweep run` of scenes/hard_sphere_gas.toml to t = 40 with four snapshots into `out`,
/// plus `extra` arguments, started in the background with its standard error piped.
pub fn spawn_gas_run(out: &Path, extra: &[&str]) -> Child {
    bin()
        .arg("run")
        .arg(repo("scenes/hard_sphere_gas.toml"))
        .args(["--t-end", "40", "--snapshots", "4", "--quiet", "--out"])
        .arg(out)
        .args(extra)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs")
}

/// The header of a pairs CSV file.
pub const PAIR_HEADER: &str = "ax,ay,az,avx,avy,avz,ar,bx,by,bz,bvx,bvy,bvz,br\n";

/// A pairs CSV file of `len` bytes with room for many rows and none written: its header, then
/// zeros the file system need not store (sparse), for checks made before any row is read.
pub fn sparse_pairs_csv(path: &Path, len: u64) {
    std::fs::write(path, PAIR_HEADER).unwrap();
    let file = std::fs::OpenOptions::new().write(true).open(path).unwrap();
    file.set_len(len).unwrap();
}
