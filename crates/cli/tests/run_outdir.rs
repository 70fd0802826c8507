//! One run an output directory: a run refuses a directory that holds another run's outputs,
//! this same run's, a checkpoint, or outputs without a manifest, naming what it found, and
//! changes nothing; with --force it replaces them whole, removing the other run's outputs it
//! does not write itself.

mod common;
mod run_support;

use run_support::*;

fn manifest(out: &std::path::Path) -> serde_json::Value {
    let text = String::from_utf8(read(&out.join("summary.json"))).unwrap();
    serde_json::from_str::<serde_json::Value>(&text).unwrap()["run"].clone()
}

#[test]
fn a_run_refuses_another_runs_directory_unless_forced_and_never_mixes_them() {
    let dir = scratch("outdir");
    let a = gas(&dir, "a", 200, 1, "t_end = 2.0\nsnapshot_every = 1.0", true);
    let b = gas(
        &dir,
        "b",
        300,
        2,
        "t_end = 1.0\nsnapshot_every = 0.5",
        false,
    );
    let out = dir.join("out");
    success(&a, &out, &[]);
    let before: Vec<_> = ["events.csv", "summary.json", "trajectory.xyz"]
        .map(|n| read(&out.join(n)))
        .into();
    assert_eq!(
        manifest(&out)["outputs"],
        serde_json::json!(["trajectory.xyz", "events.csv", "summary.json"])
    );
    let unchanged = || {
        let now: Vec<_> = ["events.csv", "summary.json", "trajectory.xyz"]
            .map(|n| read(&out.join(n)))
            .into();
        assert!(now == before, "a refused run changed --out");
        assert_eq!(
            listing(&out),
            ["events.csv", "summary.json", "trajectory.xyz"]
        );
    };

    // Another scene, without snapshots: refused, naming the other run.
    let o = output(&b, &out, &["--snapshots", "0"]);
    let err = stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("holds the outputs of another run (scene fingerprint")
            && err.contains("t_end 2, snapshots every 1")
            && err.contains("events.csv, summary.json")
            && err.contains("--force"),
        "{err}"
    );
    unchanged();
    // The same scene and options again: refused too.
    let o = output(&a, &out, &[]);
    assert!(
        stderr(&o).contains("the outputs of this same scene and options, complete"),
        "{}",
        stderr(&o)
    );
    unchanged();

    // Forced: B's summary alone, no trajectory or event log of A beside it.
    success(&b, &out, &["--snapshots", "0", "--force"]);
    assert_eq!(listing(&out), ["summary.json"]);
    let m = manifest(&out);
    assert_eq!(
        (m["t_end"].as_f64(), m["snapshot_every"].is_null()),
        (Some(1.0), true)
    );
    assert_eq!(m["outputs"], serde_json::json!(["summary.json"]));

    // Outputs without a manifest (an earlier version, or an unfinished run) are refused.
    std::fs::write(out.join("trajectory.xyz"), b"1\nan unknown run\n").unwrap();
    std::fs::write(out.join("summary.json"), b"{}").unwrap();
    let o = output(&b, &out, &[]);
    assert!(
        stderr(&o).contains("its summary.json naming no run this version reads"),
        "{}",
        stderr(&o)
    );
    std::fs::remove_file(out.join("summary.json")).unwrap();
    let o = output(&b, &out, &[]);
    assert!(
        stderr(&o).contains("and no summary.json naming it"),
        "{}",
        stderr(&o)
    );
    assert_eq!(read(&out.join("trajectory.xyz")), b"1\nan unknown run\n");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_directory_with_a_checkpoint_is_resumed_or_forced() {
    let dir = scratch("outdir-checkpoint");
    let a = gas(
        &dir,
        "a",
        300,
        1,
        "t_end = 200.0\nsnapshot_every = 1.0",
        true,
    );
    let out = dir.join("out");
    interrupted(&a, &out, &["--checkpoint-every", "1"]);
    let before = listing(&out);
    assert_eq!(
        before,
        [
            ".events.csv.partial",
            ".trajectory.xyz.partial",
            "checkpoint.bin"
        ]
    );
    let o = output(&a, &out, &["--t-end", "1", "--checkpoint-every", "1"]);
    let err = stderr(&o);
    assert!(
        !o.status.success()
            && err.contains("the checkpoint of an interrupted run: resume it with --resume")
            && err.contains("checkpoint.bin"),
        "{err}"
    );
    assert_eq!(listing(&out), before);
    // Forced, a new run removes the checkpoint and its partial files.
    success(&a, &out, &["--t-end", "1", "--force"]);
    assert_eq!(
        listing(&out),
        ["events.csv", "summary.json", "trajectory.xyz"]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two runs at once in one directory: the second is refused while the first writes there,
/// even with --force, and runs once the first has ended.
#[test]
fn a_second_run_into_a_directory_in_use_is_refused() {
    let dir = scratch("outdir-busy");
    let a = gas(
        &dir,
        "a",
        300,
        1,
        "t_end = 100000.0\nsnapshot_every = 1.0",
        false,
    );
    let b = gas(&dir, "b", 100, 2, "t_end = 1.0", false);
    let out = dir.join("out");
    let mut first = run(&a, &out, &[])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // The directory is taken before the partial trajectory is made.
    while !out.join(".trajectory.xyz.partial").exists() {
        assert!(first.try_wait().unwrap().is_none(), "the first run ended");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let o = output(&b, &out, &["--force"]);
    let disturbed = first.try_wait().unwrap().is_some();
    // The first run is stopped before any assertion, so that none leaves it running.
    let ok = std::process::Command::new("kill")
        .args(["-TERM", &first.id().to_string()])
        .status()
        .unwrap()
        .success();
    let code = first.wait().unwrap().code();
    let err = stderr(&o);
    assert!(
        !o.status.success() && err.contains("another spheresweep run is writing to it"),
        "{err}"
    );
    assert!(
        !disturbed && ok && code == Some(130),
        "the first run was disturbed"
    );
    success(&b, &out, &["--force"]);
    assert_eq!(listing(&out), ["summary.json"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A scene named as one of the run's outputs (through a link or not) is refused before any
/// work: the run would overwrite its own input.
#[test]
fn a_scene_that_is_one_of_the_outputs_is_refused() {
    let dir = scratch("outdir-scene");
    let scene = gas(&dir, "gas", 50, 1, "t_end = 1.0", false);
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::os::unix::fs::symlink(&scene, out.join("summary.json")).unwrap();
    let before = read(&scene);
    let run = common::bin()
        .args(["run", "--quiet", "--force"])
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("are the same file"), "{stderr}");
    assert_eq!(read(&scene), before);
    std::fs::remove_dir_all(&dir).ok();
}

/// A run that fails after its output directory was made (here an inelastic collapse, found
/// mid-run) leaves no empty directory behind, nor the parents it made for it; a directory that
/// existed before stays.
#[test]
fn a_failed_run_leaves_no_empty_output_directory() {
    let dir = scratch("outdir-failed");
    let scene = dir.join("collapse.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 50.0\nsnapshot_every = 5.0\nseed = 2\n\n[boundary]\nkind = \"periodic\"\n\n\
         [effects]\nresponse = \"inelastic\"\nrestitution = 0.05\n\n[[generate]]\n\
         kind = \"periodic_gas\"\nn = 500\nphi = 0.45\nradius = 0.5\ntemperature = 1.0\n",
    )
    .unwrap();
    let o = output(&scene, &dir.join("made/out"), &[]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("inelastic collapse"), "{}", stderr(&o));
    assert!(
        !dir.join("made").exists(),
        "the directories made for the run stay"
    );
    std::fs::create_dir(dir.join("there")).unwrap();
    let o = output(&scene, &dir.join("there"), &[]);
    assert!(!o.status.success());
    assert!(
        dir.join("there").is_dir(),
        "a directory that existed before is removed"
    );
}
