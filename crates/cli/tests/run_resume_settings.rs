//! A resume continues the same run: another end time, snapshot spacing (by flag or by an
//! edited scene file), checkpoint spacing or recording is refused, naming the setting and both
//! values, and nothing in the output directory changes. The same options resume.

mod common;
mod run_support;

use run_support::*;

const RUN: &str = "t_end = 100.0\nsnapshot_every = 2.0";

#[test]
fn a_resume_with_other_settings_is_refused_naming_them() {
    let dir = scratch("resume-settings");
    let scene = gas(&dir, "gas", 500, 1, RUN, false);
    let out = dir.join("out");
    let checkpoint = interrupted(&scene, &out, &["--checkpoint-every", "2"]);
    let before = listing(&out);
    let ckpt = checkpoint.to_str().unwrap();
    let refused = |scene: &std::path::Path, extra: &[&str], want: &[&str]| {
        let mut args = vec!["--resume", ckpt];
        args.extend_from_slice(extra);
        let o = output(scene, &out, &args);
        let err = stderr(&o);
        assert!(!o.status.success(), "{extra:?} was accepted");
        for w in want {
            assert!(err.contains(w), "{extra:?}: no {w:?} in {err}");
        }
        assert!(
            err.contains("a resume continues the run the checkpoint holds"),
            "{err}"
        );
        assert_eq!(listing(&out), before, "{extra:?} changed --out");
    };
    let snapshots = "--snapshots (or the scene's snapshot_every)";
    for every in ["4", "2.5", "1"] {
        refused(
            &scene,
            &["--checkpoint-every", "2", "--snapshots", every],
            &[&format!(
                "{snapshots} is {every} here but 2 in the checkpoint"
            )],
        );
    }
    for t in ["10", "1000", "1e300"] {
        refused(
            &scene,
            &["--checkpoint-every", "2", "--t-end", t],
            &[&format!(
                "--t-end (or the scene's t_end) is {t} here but 100 in the checkpoint"
            )],
        );
    }
    refused(
        &scene,
        &["--checkpoint-every", "3"],
        &["--checkpoint-every is 3 here but 2 in the checkpoint"],
    );
    refused(
        &scene,
        &[],
        &["--checkpoint-every is none here but 2 in the checkpoint"],
    );
    // The scene file edited: its snapshot spacing, or its recording.
    let edited = gas(
        &dir,
        "gas",
        500,
        1,
        "t_end = 100.0\nsnapshot_every = 4.0",
        false,
    );
    refused(
        &edited,
        &["--checkpoint-every", "2"],
        &[&format!("{snapshots} is 4 here but 2 in the checkpoint")],
    );
    let recording = gas(&dir, "gas", 500, 1, RUN, true);
    refused(
        &recording,
        &["--checkpoint-every", "2"],
        &[
            "the scene's record_events is true here but false in the checkpoint",
            "the scene's geometry is true here but false",
        ],
    );
    // The same scene and options resume (to the end; a shorter end would be refused).
    let scene = gas(&dir, "gas", 500, 1, RUN, false);
    let o = output(&scene, &out, &["--resume", ckpt, "--checkpoint-every", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let _ = std::fs::remove_dir_all(&dir);
}
