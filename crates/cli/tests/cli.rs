//! The `spheresweep` binary: the README's main command, bad input, and written reports.

use std::process::{Command, Output};

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spheresweep"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn demo_prints_one_row_per_sphere_in_every_mode() {
    for mode in ["textbook", "stable", "double"] {
        let out = run(&["demo", "--accuracy", mode]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let stdout = text(&out.stdout);
        let rows: Vec<&str> = stdout
            .lines()
            .filter(|l| {
                l.trim_start()
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_ascii_digit())
            })
            .collect();
        assert_eq!(rows.len(), 9, "{stdout}");
        for body in [
            "sphere 1",
            "plane 0",
            "cylinder 0",
            "container 0",
            "nothing",
        ] {
            assert!(stdout.contains(body), "{mode}: no {body} in\n{stdout}");
        }
    }
}

#[test]
fn demo_draws_the_scene_when_asked() {
    let path = std::env::temp_dir().join(format!("spheresweep-demo-{}.svg", std::process::id()));
    let out = run(&["demo", "--svg", path.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let svg = std::fs::read_to_string(&path).unwrap();
    assert!(svg.contains("<svg") && svg.contains("paths to the first contact"));
    std::fs::remove_file(&path).ok();
    let out = run(&["demo", "--svg", "/proc/no-such-dir/demo.svg"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("cannot write /proc/no-such-dir/demo.svg"));
}

#[test]
fn bad_arguments_fail_with_a_message_naming_them() {
    let out = run(&["demo", "--t-max=-1"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("t_max must be zero or more"),
        "{}",
        text(&out.stderr)
    );
    let out = run(&["demo", "--accuracy", "fast"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("unknown accuracy mode \"fast\""));
    let out = run(&["accuracy", "--cases", "0"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("--cases must be between 1 and"));
}

#[test]
fn accuracy_writes_the_report_and_its_plot() {
    let dir = std::env::temp_dir().join(format!("spheresweep-cli-{}", std::process::id()));
    let (md, svg) = (dir.join("nested/report.md"), dir.join("nested/plot.svg"));
    let out = run(&[
        "accuracy",
        "--cases",
        "40",
        "--out",
        md.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report = std::fs::read_to_string(&md).unwrap();
    assert!(report.contains("![error against throughput](plot.svg)"));
    for row in [
        "| stable |",
        "| parry3d |",
        "grazing (5)",
        "container-wall (5)",
    ] {
        assert!(report.contains(row), "no {row}");
    }
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn an_unwritable_report_is_an_error_not_lost_output() {
    let out = run(&[
        "accuracy",
        "--cases",
        "5",
        "--out",
        "/proc/no-such-dir/report.md",
    ]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("cannot write /proc/no-such-dir/report.md"),
        "{}",
        text(&out.stderr)
    );
}

/// A scratch directory of this test process.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("spheresweep-cli-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn an_unwritable_plot_leaves_an_existing_report_whole() {
    let dir = scratch("keep");
    let md = dir.join("report.md");
    std::fs::write(&md, "the old report\n").unwrap();
    let out = run(&[
        "accuracy",
        "--cases",
        "10",
        "--out",
        md.to_str().unwrap(),
        "--svg",
        "/proc/no-such-dir/plot.svg",
    ]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("cannot write /proc/no-such-dir/plot.svg"));
    assert_eq!(std::fs::read_to_string(&md).unwrap(), "the old report\n");
}

#[test]
fn one_path_for_both_outputs_is_refused() {
    let dir = scratch("same");
    let md = dir.join("x.md");
    std::fs::write(&md, "kept\n").unwrap();
    let p = md.to_str().unwrap();
    let out = run(&["accuracy", "--cases", "10", "--out", p, "--svg", p]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("are the same file"),
        "{}",
        text(&out.stderr)
    );
    assert_eq!(std::fs::read_to_string(&md).unwrap(), "kept\n");
}

#[test]
fn huge_case_counts_are_refused_before_any_work() {
    for cases in ["999999999", "18446744073709551615", "0"] {
        let out = run(&["accuracy", "--cases", cases, "--out", "/tmp/never.md"]);
        assert!(!out.status.success(), "{cases}");
        assert!(
            text(&out.stderr).contains("--cases must be between 1 and"),
            "{cases}: {}",
            text(&out.stderr)
        );
    }
}

#[test]
fn the_plot_goes_beside_the_report_by_default() {
    let dir = scratch("beside");
    let md = dir.join("sub/r.md");
    let out = run(&["accuracy", "--cases", "20", "--out", md.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(dir.join("sub/r.svg").exists());
}

#[test]
fn demo_checks_its_picture_path_before_printing() {
    let dir = scratch("demo-dir");
    let out = run(&["demo", "--svg", dir.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("is a directory"));
    assert!(out.stdout.is_empty(), "nothing printed before the error");
}

#[test]
fn a_negative_window_is_a_clear_error() {
    let out = run(&["demo", "--t-max", "-1"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("t_max must be zero or more"),
        "{}",
        text(&out.stderr)
    );
}
