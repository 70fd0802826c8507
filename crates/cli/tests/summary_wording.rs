//! The run summary's wording: a count of one is singular (`1 sphere`, `1 frame`), an empty
//! scene's kinetic energy prints as `0`, never `-0`, the kinetic energy's change is a "drift"
//! only where it is conserved (elastic, without gravity), and the sphere kernel counter is
//! named for what it counts (approaching pairs solved in f64, docs/run-summary.md).

mod common;

use common::{run, scratch, text};

/// `spheresweep run` of the scene `toml` (written to a scratch directory): its stdout.
fn summary(name: &str, toml: &str) -> String {
    let dir = scratch(name);
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, toml).unwrap();
    let out_dir = dir.join("out");
    let out = run(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(out.status.success(), "{name}: {}", text(&out.stderr));
    text(&out.stdout)
}

#[test]
fn an_empty_scene_prints_an_unsigned_zero() {
    let stdout = summary("empty", "[run]\nt_end = 1.0\n");
    assert!(stdout.contains(": 0 spheres, "), "{stdout}");
    assert!(
        stdout.contains("kinetic      0.000000000e0 → 0.000000000e0 ("),
        "{stdout}"
    );
    assert!(!stdout.contains("-0.0"), "{stdout}");
}

#[test]
fn a_count_of_one_is_singular() {
    let stdout = summary(
        "one",
        "[run]\nt_end = 1.0\nsnapshot_every = 5.0\n[effects]\nrecord_events = true\n\
         [[sphere]]\ncentre = [0.0, 0.0, 0.0]\nvelocity = [1.0, 0.0, 0.0]\nradius = 0.5\n\
         [[plane]]\npoint = [1.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n",
    );
    for want in [": 1 sphere, ", "(1 frame)", "(1 event)"] {
        assert!(stdout.contains(want), "no {want:?} in\n{stdout}");
    }
    // Elastic, without gravity: the kinetic energy is conserved, its change a drift.
    assert!(stdout.contains("(relative drift "), "{stdout}");
    assert!(
        stdout.contains("kernels      sphere 0 (approaching pairs solved in f64, four at a time)"),
        "{stdout}"
    );
}

#[test]
fn under_gravity_the_kinetic_energy_change_is_no_drift() {
    let stdout = summary(
        "fall",
        "[run]\nt_end = 1.0\n[effects]\ngravity = [0.0, 0.0, -1.0]\n\
         [[sphere]]\ncentre = [0.0, 0.0, 0.0]\nvelocity = [1.0, 0.0, 0.0]\nradius = 0.5\n",
    );
    assert!(!stdout.contains("drift +"), "{stdout}");
    assert!(
        stdout.contains("(relative change +1.000e0; under gravity K alone is not conserved"),
        "{stdout}"
    );
    assert!(stdout.contains("potential    0.000000000e0 → "), "{stdout}");
}
