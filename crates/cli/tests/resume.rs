//! `spheresweep run --checkpoint-every` / `--resume`: a run killed with SIGKILL after one of
//! its checkpoints and resumed from it ends with outputs identical, byte for byte, to those of a
//! run never interrupted (the trajectory holds every snapshot up to the final state, the event
//! log every event), written beside the checkpoint when no --out is given; a damaged checkpoint, one of another scene, and a changed partial output
//! are refused, saying why.

mod common;
mod run_support;

use std::os::unix::process::ExitStatusExt;
use std::process::Stdio;
use std::time::Duration;

use run_support::*;

/// The gas of 2000 spheres to t = 40, a snapshot every 4, every event with its geometry.
fn scene(dir: &std::path::Path) -> std::path::PathBuf {
    gas(
        dir,
        "gas",
        2000,
        1,
        "t_end = 40.0\nsnapshot_every = 4.0",
        true,
    )
}

const CHECKPOINTS: [&str; 2] = ["--checkpoint-every", "2"];

#[test]
fn a_killed_run_resumes_to_the_same_bytes() {
    let dir = scratch("resume");
    let scene = scene(&dir);
    let (full, killed) = (dir.join("full"), dir.join("killed"));
    success(&scene, &full, &CHECKPOINTS);

    // Kill once the run has written the checkpoint that continues with stop `target` (of the
    // ten; chosen from the clock), while it is still running: a run that ends first fails.
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .subsec_nanos();
    let target = 2 + u64::from(nanos % 7);
    let mut child = run(&scene, &killed, &CHECKPOINTS)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let checkpoint = killed.join("checkpoint.bin");
    loop {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its checkpoint of stop {target}"
        );
        if std::fs::read(&checkpoint).is_ok_and(|b| b.len() > 50 && next_stop(&b) >= target) {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap(); // SIGKILL
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(9), "the run was not killed: {status}");
    assert!(
        listing(&killed).contains(&".events.csv.partial".to_string()),
        "{:?}",
        listing(&killed)
    );

    // SIGKILL can land while a checkpoint or the summary is being written, leaving its
    // temporary file: the resumed run removes those too (planted here, so that the check below
    // does not depend on where the kill landed).
    for name in [".checkpoint.bin.1.tmp", ".summary.json.1.tmp"] {
        std::fs::write(killed.join(name), b"left by a killed run").unwrap();
    }
    let resume = [
        "--checkpoint-every",
        "2",
        "--resume",
        checkpoint.to_str().unwrap(),
    ];
    // No --out: a resume writes where its checkpoint is.
    let o = common::bin()
        .arg("run")
        .arg(&scene)
        .arg("--quiet")
        .args(resume)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        !dir.join("gas-run").exists(),
        "the resume wrote to the scene's default"
    );
    for name in ["trajectory.xyz", "events.csv"] {
        assert!(
            read(&full.join(name)) == read(&killed.join(name)),
            "{name} differs after a kill after the checkpoint of stop {target}"
        );
    }
    // The summaries agree on every physical quantity (wall-clock fields aside).
    assert_eq!(
        physics(&full.join("summary.json")),
        physics(&killed.join("summary.json"))
    );
    // Only the outputs are left: no temporary or partial file, and no checkpoint (its partial
    // files are the outputs now).
    assert_eq!(
        listing(&killed),
        ["events.csv", "summary.json", "trajectory.xyz"]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `run --resume` refuses a damaged checkpoint, one of another scene, and a partial output
/// that is not the one the checkpoint records; it writes nothing then.
#[test]
fn a_damaged_or_foreign_checkpoint_is_refused() {
    let dir = scratch("resume-bad");
    let scene = scene(&dir);
    let out = dir.join("out");
    let checkpoint = interrupted(&scene, &out, &CHECKPOINTS);
    let before = listing(&out);
    let resume = |path: &std::path::Path, scene: &std::path::Path| {
        let o = output(
            scene,
            &out,
            &[
                "--checkpoint-every",
                "2",
                "--resume",
                path.to_str().unwrap(),
            ],
        );
        assert!(!o.status.success(), "{} was accepted", path.display());
        assert_eq!(listing(&out), before, "a refused resume changed --out");
        stderr(&o)
    };

    let bogus = dir.join("bogus.bin");
    std::fs::write(&bogus, b"not a checkpoint").unwrap();
    let err = resume(&bogus, &scene);
    assert!(
        err.contains("bogus.bin: not a checkpoint of `spheresweep run`"),
        "{err}"
    );

    // Bits flipped in every section of a real checkpoint: its first, middle and last byte.
    let bytes = read(&checkpoint);
    let flipped = dir.join("flipped.bin");
    for (section, range) in sections(bytes.len()) {
        for at in [range.start, (range.start + range.end) / 2, range.end - 1] {
            let mut bad = bytes.clone();
            bad[at] ^= 1 << (at % 8);
            std::fs::write(&flipped, &bad).unwrap();
            let err = resume(&flipped, &scene);
            let why = match section {
                "header" if at == 7 => "flipped.bin: a checkpoint of format version",
                "header" => "flipped.bin: not a checkpoint of `spheresweep run`",
                _ => "flipped.bin: damaged: its checksum (CRC-64 over its",
            };
            assert!(err.contains(why), "{section}, byte {at}: {err}");
        }
    }
    let cut = dir.join("cut.bin");
    std::fs::write(&cut, &bytes[..bytes.len() - 1]).unwrap();
    assert!(resume(&cut, &scene).contains("damaged"));

    // The same run's checkpoint, given another scene (another seed: the same sizes, masses
    // and materials, another start).
    let other = gas(
        &dir,
        "other",
        2000,
        2,
        "t_end = 40.0\nsnapshot_every = 4.0",
        true,
    );
    let err = resume(&checkpoint, &other);
    assert!(
        err.contains("it was written for another scene") && err.contains("other.toml"),
        "{err}"
    );

    // A partial output changed since the checkpoint.
    let partial = out.join(".trajectory.xyz.partial");
    let mut text = read(&partial);
    text[100] ^= 1;
    std::fs::write(&partial, &text).unwrap();
    let err = resume(&checkpoint, &scene);
    assert!(
        err.contains(".trajectory.xyz.partial does not hold the bytes the checkpoint records"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
