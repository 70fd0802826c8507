//! Helpers of the `run` tests (resume.rs, run_*.rs): a small gas scene, the command, a run
//! stopped by SIGTERM once it has written a checkpoint, and the checkpoint's layout.
// Each test file uses a part of these.
#![allow(dead_code, unused_imports)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

pub use crate::common::{bin, scratch};

/// Byte ranges of the sections of a checkpoint of `len` bytes (the layout in
/// crates/cli/src/run/checkpoint.rs).
pub fn sections(len: usize) -> [(&'static str, std::ops::Range<usize>); 7] {
    [
        ("header", 0..8),
        ("settings", 8..42),
        ("counters", 42..114),
        ("trajectory", 114..130),
        ("events", 130..146),
        ("engine", 146..len - 8),
        ("checksum", len - 8..len),
    ]
}

/// The index of the stop a checkpoint continues with (its first counter).
pub fn next_stop(checkpoint: &[u8]) -> u64 {
    u64::from_le_bytes(checkpoint[42..50].try_into().unwrap())
}

/// A periodic gas of `n` spheres (seed `seed`) in `dir/name.toml`, recording events with
/// their geometry if `events`.
pub fn gas(dir: &Path, name: &str, n: usize, seed: u64, run: &str, events: bool) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    let effects = if events {
        "[effects]\nrecord_events = true\ngeometry = true\n\n"
    } else {
        ""
    };
    std::fs::write(
        &path,
        format!(
            "[run]\n{run}\nseed = {seed}\n\n[boundary]\nkind = \"periodic\"\n\n{effects}\
             [[generate]]\nkind = \"periodic_gas\"\nn = {n}\nphi = 0.25\nradius = 0.5\n\
             temperature = 1.0\n"
        ),
    )
    .unwrap();
    path
}

/// `spheresweep run SCENE --quiet --out OUT EXTRA…`.
pub fn run(scene: &Path, out: &Path, extra: &[&str]) -> Command {
    let mut c = bin();
    c.arg("run")
        .arg(scene)
        .args(["--quiet", "--out"])
        .arg(out)
        .args(extra);
    c
}

/// Runs it to the end.
pub fn output(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    run(scene, out, extra).output().expect("the binary runs")
}

/// Runs it to the end and asserts it succeeded.
pub fn success(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    let o = output(scene, out, extra);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

/// Standard error, as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Starts the run with `extra` (which must turn checkpoints on), waits until it has written
/// `checkpoint.bin`, and stops it with SIGTERM; returns the checkpoint's path. Fails if the
/// run ends first.
pub fn interrupted(scene: &Path, out: &Path, extra: &[&str]) -> PathBuf {
    let mut child = run(scene, out, extra)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let checkpoint = out.join("checkpoint.bin");
    while !checkpoint.exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before it wrote a checkpoint"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let ok = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok);
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    checkpoint
}

/// The names in `dir`, sorted.
pub fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

pub fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// A summary's lines but those of wall-clock time.
pub fn physics(p: &Path) -> String {
    String::from_utf8(read(p))
        .unwrap()
        .lines()
        .filter(|l| !l.contains("wall_seconds") && !l.contains("per_second"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The last frame of an extended-XYZ trajectory of `n` spheres, read here (not by the
/// library): its `Time=` and each sphere's centre.
pub fn last_frame(xyz: &str, n: usize) -> (f64, Vec<[f64; 3]>) {
    let lines: Vec<&str> = xyz.lines().collect();
    let frame = &lines[lines.len() - n - 2..];
    let time = frame[1].split("Time=").nth(1).expect("a Time= field");
    let time = time.split(' ').next().unwrap().parse().expect("a time");
    let centres = frame[2..]
        .iter()
        .map(|l| {
            let x: Vec<f64> = l
                .split_whitespace()
                .skip(1)
                .take(3)
                .map(|x| x.parse().expect("a coordinate"))
                .collect();
            [x[0], x[1], x[2]]
        })
        .collect();
    (time, centres)
}
