//! `spheresweep run --checkpoint-every` / `--resume`: a run killed with SIGKILL at a random
//! moment and resumed from its last checkpoint ends with outputs identical, byte for byte, to
//! those of a run never interrupted (the trajectory holds every snapshot up to the final state).

mod common;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use common::{fresh_dir, spawn_gas_run};

/// The gas run with a checkpoint every 2 time units.
fn run(out: &Path, extra: &[&str]) -> std::process::Child {
    let mut args = vec!["--checkpoint-every", "2"];
    args.extend_from_slice(extra);
    spawn_gas_run(out, &args)
}

#[test]
fn a_killed_run_resumes_to_the_same_bytes() {
    let dir = fresh_dir("resume");
    let (full, killed) = (dir.join("full"), dir.join("killed"));
    std::fs::create_dir_all(&killed).unwrap();

    let start = Instant::now();
    let out = run(&full, &[]).wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let whole = start.elapsed();

    // Kill at a pseudo-random point between 20 % and 80 % of the uninterrupted run's time,
    // once a checkpoint exists.
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .subsec_nanos();
    let fraction = 0.2 + 0.6 * f64::from(nanos % 1000) / 1000.0;
    let mut child = run(&killed, &[]);
    let deadline = Instant::now() + whole.mul_f64(fraction);
    while Instant::now() < deadline || !killed.join("checkpoint.bin").exists() {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let _ = child.kill(); // SIGKILL on Unix
    let _ = child.wait();
    assert!(
        killed.join("checkpoint.bin").exists(),
        "no checkpoint was written"
    );

    // SIGKILL can land while a checkpoint or the summary is being written, leaving its
    // temporary file: the resumed run removes those too (planted here, so that the check below
    // does not depend on where the kill landed).
    for name in [".checkpoint.bin.1.tmp", ".summary.json.1.tmp"] {
        std::fs::write(killed.join(name), b"left by a killed run").unwrap();
    }
    let ckpt = killed.join("checkpoint.bin");
    let resumed = run(&killed, &["--resume", ckpt.to_str().unwrap()])
        .wait_with_output()
        .unwrap();
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    let read = |p: PathBuf| std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    assert!(
        read(full.join("trajectory.xyz")) == read(killed.join("trajectory.xyz")),
        "trajectories differ after a kill at {:.0} % of the run",
        100.0 * fraction
    );
    // The summaries agree on every physical quantity (wall-clock fields aside).
    let physics = |p: PathBuf| {
        let text = String::from_utf8(read(p)).unwrap();
        text.lines()
            .filter(|l| !l.contains("wall_seconds") && !l.contains("per_second"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(
        physics(full.join("summary.json")),
        physics(killed.join("summary.json"))
    );
    // No temporary file of the killed run is left.
    let leftovers: Vec<_> = std::fs::read_dir(&killed)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_damaged_or_foreign_checkpoint_is_refused() {
    let dir = fresh_dir("resume-bad");
    let bogus = dir.join("bogus.bin");
    std::fs::write(&bogus, b"not a checkpoint").unwrap();
    let out = run(&dir.join("out"), &["--resume", bogus.to_str().unwrap()])
        .wait_with_output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bogus.bin") && err.contains("not a checkpoint"),
        "{err}"
    );
    assert!(
        !dir.join("out").exists(),
        "a refused resume must write nothing"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
