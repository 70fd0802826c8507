//! The `spheresweep` binary: the README's main command, bad input, and written reports.

mod common;

use common::{run, scratch, shipped, text};

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
        text(&out.stderr).contains("--t-max must be zero or more"),
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
        text(&out.stderr).contains("--t-max must be zero or more"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn every_shipped_scene_runs_and_writes_its_outputs() {
    for (name, n, events) in [
        ("hard_sphere_gas", 4000, false),
        ("granular_jet", 3600, true),
        ("sticky_aggregation", 2000, true),
        ("settling_pile", 600, false),
        ("galton_board", 250, false),
    ] {
        let dir = scratch(&format!("run-{name}"));
        let out = run(&[
            "run",
            &shipped(name),
            "--out",
            dir.to_str().unwrap(),
            "--t-end",
            "0.5",
            "--snapshots",
            "0.25",
            "--quiet",
        ]);
        assert!(out.status.success(), "{name}: {}", text(&out.stderr));
        let stdout = text(&out.stdout);
        for line in ["engine ", "collisions ", "kinetic ", "max overlap "] {
            assert!(stdout.contains(line), "{name}: no {line:?} in\n{stdout}");
        }
        let trajectory = std::fs::read_to_string(dir.join("trajectory.xyz")).unwrap();
        let frames = spheresweep::io::xyz::read_frames(&trajectory).unwrap();
        assert_eq!(frames.len(), 3, "{name}: frames at 0, 0.25 and 0.5");
        for (f, t) in frames.iter().zip([0.0, 0.25, 0.5]) {
            assert_eq!((f.spheres.len(), f.time), (n, t), "{name}");
        }
        assert_eq!(
            frames[0].periodic_box.is_some(),
            name == "hard_sphere_gas",
            "{name}"
        );
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(summary["spheres"], n, "{name}");
        assert_eq!(summary["t_end"], 0.5, "{name}");
        assert!(summary["collisions"]["pair"].as_u64().is_some(), "{name}");
        assert!(summary["kinetic_energy"]["relative_drift"].is_f64());
        let csv = dir.join("events.csv");
        assert_eq!(csv.exists(), events, "{name}");
        if events {
            let log = std::fs::read_to_string(&csv).unwrap();
            assert!(log.starts_with("time,sphere,other_kind,other_index,approach"));
            assert_eq!(
                log.lines().count() as u64 - 1,
                summary["events"].as_u64().unwrap()
            );
        }
        // Nothing but the outputs: no temporary file is left behind.
        let mut names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        let want: &[&str] = if events {
            &["events.csv", "summary.json", "trajectory.xyz"]
        } else {
            &["summary.json", "trajectory.xyz"]
        };
        assert_eq!(names, want, "{name}");
        std::fs::remove_dir_all(&dir).ok();
    }
}

#[test]
fn the_gas_pressure_is_printed_for_periodic_scenes() {
    let dir = scratch("run-pressure");
    let out = run(&[
        "run",
        &shipped("hard_sphere_gas"),
        "--out",
        dir.to_str().unwrap(),
        "--t-end",
        "1",
        "--snapshots",
        "0",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("Z = PV/(NkT) = ") && stdout.contains("Carnahan–Starling"),
        "{stdout}"
    );
    assert!(!dir.join("trajectory.xyz").exists(), "--snapshots 0: none");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_typo_in_a_scene_names_the_field_and_line_and_writes_nothing() {
    let dir = scratch("run-typo");
    let scene = dir.join("typo.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 1.0\n\n[[sphere]]\ncentre = [0.0, 0.0, 0.0]\nraduis = 0.5\n",
    )
    .unwrap();
    let outputs = dir.join("out");
    let out = run(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        outputs.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains(scene.to_str().unwrap())
            && stderr.contains("line 6")
            && stderr.contains("unknown field `raduis`"),
        "{stderr}"
    );
    assert!(!outputs.exists(), "no output directory for a bad scene");
    // The default directory beside the scene is not made either.
    let out = run(&["run", scene.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(!dir.join("typo-run").exists());
    // An undeclared material is named with its item and line.
    std::fs::write(
        &scene,
        "[run]\nt_end = 1.0\n\n[[sphere]]\ncentre = [0.0, 0.0, 0.0]\nradius = 0.5\nmaterial = \"rubber\"\n",
    )
    .unwrap();
    let out = run(&["run", scene.to_str().unwrap()]);
    let stderr = text(&out.stderr);
    assert!(
        stderr.contains(&format!(
            "{}:7: sphere 0: material \"rubber\" is not declared",
            scene.display()
        )),
        "{stderr}"
    );
    assert!(!dir.join("typo-run").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_missing_scene_names_its_path() {
    let out = run(&["run", "/no/such/dir/scene.toml"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("cannot read /no/such/dir/scene.toml"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn a_failed_run_leaves_earlier_outputs_whole() {
    let dir = scratch("run-keep");
    let scene = dir.join("pair.toml");
    let good = "[run]\nt_end = 2.0\nsnapshot_every = 1.0\n\n\
                [[sphere]]\ncentre = [0.0, 0.0, 0.0]\nvelocity = [1.0, 0.0, 0.0]\nradius = 0.5\n\n\
                [[sphere]]\ncentre = [3.0, 0.0, 0.0]\nradius = 0.5\n";
    std::fs::write(&scene, good).unwrap();
    let out = run(&["run", scene.to_str().unwrap(), "--quiet"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let outputs = dir.join("pair-run");
    let summary = std::fs::read_to_string(outputs.join("summary.json")).unwrap();
    assert!(summary.contains("\"pair\": 1"), "{summary}");
    let trajectory = std::fs::read_to_string(outputs.join("trajectory.xyz")).unwrap();
    // Overlapping spheres: refused when the simulation is built, before any output.
    std::fs::write(&scene, good.replace("[3.0, 0.0, 0.0]", "[0.5, 0.0, 0.0]")).unwrap();
    let out = run(&["run", scene.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("sphere 0 and sphere 1: spheres 0 and 1 overlap"),
        "{}",
        text(&out.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(outputs.join("summary.json")).unwrap(),
        summary
    );
    assert_eq!(
        std::fs::read_to_string(outputs.join("trajectory.xyz")).unwrap(),
        trajectory
    );
    // Bad overrides are refused before any work.
    for (flag, value, message) in [
        (
            "--t-end",
            "-1",
            "--t-end -1 must be finite and greater than 0",
        ),
        ("--snapshots", "nan", "--snapshots NaN must be finite"),
        (
            "--t-end",
            "1e309",
            "'1e309' for '--t-end <T>': 1e309 is beyond the largest number",
        ),
    ] {
        let out = run(&["run", scene.to_str().unwrap(), flag, value]);
        assert!(!out.status.success());
        assert!(text(&out.stderr).contains(message), "{}", text(&out.stderr));
    }
    std::fs::remove_dir_all(&dir).ok();
}

// ---- demo (the simulation) and render (issue 16) ----

/// Checks a PNG file: the signature, the IHDR size, and that it decodes whole.
fn png_size(path: &std::path::Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{}", path.display());
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |k: usize| u32::from_be_bytes([bytes[k], bytes[k + 1], bytes[k + 2], bytes[k + 3]]);
    let size = (be(16), be(20));
    let mut reader = png::Decoder::new(std::io::Cursor::new(&bytes))
        .read_info()
        .unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    assert_eq!((info.width, info.height), size);
    // Not blank: more than a handful of colours.
    let mut colours: Vec<&[u8]> = pixels.chunks(3).collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(
        colours.len() > 10,
        "{}: {} colours",
        path.display(),
        colours.len()
    );
    size
}

/// Parses an SVG file as XML: the root's size and how many circles it draws.
fn svg_size(path: &std::path::Path) -> ((u32, u32), usize) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let doc =
        roxmltree::Document::parse(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    assert_eq!(
        root.tag_name().namespace(),
        Some("http://www.w3.org/2000/svg")
    );
    let dim = |a: &str| root.attribute(a).unwrap().parse::<u32>().unwrap();
    let circles = root
        .descendants()
        .filter(|n| n.has_tag_name("circle"))
        .count();
    ((dim("width"), dim("height")), circles)
}

/// The names of the files in `dir`, sorted.
fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn demo_simulates_summarises_and_draws_into_its_default_directory() {
    let dir = scratch("demo-sim");
    let out = common::bin()
        .args(["demo", "--quick", "--size", "640x400"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    for line in [
        "4000 beads (3500 glass, 500 glue)",
        "engine       materials, open, static shapes",
        "simulated    t = 0 → 30 in ",
        "collisions   ",
        " per second",
        "glue clusters formed",
        "energy       ",
        "lost in sticky collisions",
        "kernels      sphere ",
        "all four ran",
        "picture      spheresweep-demo/demo.svg, spheresweep-demo/demo.png (640 × 400 px)",
    ] {
        assert!(stdout.contains(line), "no {line:?} in\n{stdout}");
    }
    // No progress bar when stderr is not a terminal.
    assert!(out.stderr.is_empty(), "{}", text(&out.stderr));
    let pictures = dir.join("spheresweep-demo");
    assert_eq!(listing(&pictures), ["demo.png", "demo.svg"]);
    let (size, circles) = svg_size(&pictures.join("demo.svg"));
    assert_eq!(size, (640, 400));
    assert!(circles > 500, "{circles} circles");
    assert_eq!(png_size(&pictures.join("demo.png")), (640, 400));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn demo_table_keeps_the_first_contact_table() {
    let out = run(&["demo", "--table"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("Built-in scene: 9 spheres") && stdout.contains("container 0"));
    let out = run(&["demo", "--table", "--accuracy", "double", "--t-max", "5"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("First contacts in [0, 5] (double mode"));
    // The simulation's options do not mix with the table's.
    let out = run(&["demo", "--table", "--out", "/tmp/never"]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("cannot be used with"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn demo_refuses_a_bad_size_or_output_before_running() {
    let dir = scratch("demo-bad");
    let file = dir.join("a-file");
    std::fs::write(&file, "kept\n").unwrap();
    let out = run(&["demo", "--out", file.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("not a directory"),
        "{}",
        text(&out.stderr)
    );
    assert!(out.stdout.is_empty(), "nothing printed before the error");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "kept\n");
    let pictures = dir.join("pictures");
    for size in ["0x400", "640", "640x-1", "9000x9000"] {
        let out = run(&[
            "demo",
            "--quick",
            "--size",
            size,
            "--out",
            pictures.to_str().unwrap(),
        ]);
        assert!(!out.status.success(), "{size}");
        assert!(
            text(&out.stderr).contains("is not a picture size"),
            "{size}: {}",
            text(&out.stderr)
        );
        assert!(!pictures.exists(), "{size}: nothing written");
    }
    let out = run(&["demo", "--quick", "--out", "/proc/no-such-dir/pictures"]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("cannot write /proc/no-such-dir/pictures/demo.svg"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn render_draws_a_scene_file_at_the_requested_size() {
    let dir = scratch("render-scene");
    let out = run(&[
        "render",
        &shipped("sticky_aggregation"),
        "--out",
        dir.to_str().unwrap(),
        "--size",
        "500x300",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(
        listing(&dir),
        ["sticky_aggregation.png", "sticky_aggregation.svg"]
    );
    let (size, circles) = svg_size(&dir.join("sticky_aggregation.svg"));
    // 2000 spheres in each of the two views, and the vessel.
    assert_eq!(size, (500, 300));
    assert!(circles >= 4000, "{circles}");
    assert_eq!(png_size(&dir.join("sticky_aggregation.png")), (500, 300));
    // One view, one format; the default size for one view is square.
    let top = dir.join("top");
    let out = run(&[
        "render",
        &shipped("granular_jet"),
        "--out",
        top.to_str().unwrap(),
        "--view",
        "top",
        "--format",
        "png",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(listing(&top), ["granular_jet.png"]);
    assert_eq!(png_size(&top.join("granular_jet.png")), (800, 800));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn render_draws_recorded_snapshots_one_frame_or_all() {
    let dir = scratch("render-frames");
    let scene = dir.join("balls.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 2.0\nsnapshot_every = 1.0\n\n\
         [[container]]\ncentre = [0.0, 0.0, 0.0]\nradius = 6.0\n\n\
         [[generate]]\nkind = \"random\"\ninside = 0\nn = 40\nradius = 0.5\nspeed = 1.0\n",
    )
    .unwrap();
    let out = run(&["run", scene.to_str().unwrap(), "--quiet"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let xyz = dir.join("balls-run/trajectory.xyz");
    // One frame.
    let one = dir.join("one");
    let out = run(&[
        "render",
        xyz.to_str().unwrap(),
        "--frame",
        "1",
        "--out",
        one.to_str().unwrap(),
        "--size",
        "320x240",
        "--format",
        "png",
        "--scene",
        scene.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(listing(&one), ["frame-0001.png"]);
    assert_eq!(png_size(&one.join("frame-0001.png")), (320, 240));
    // Every frame, by default beside the input.
    let out = run(&["render", xyz.to_str().unwrap(), "--view", "side"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let all = dir.join("balls-run/trajectory-render");
    assert_eq!(
        listing(&all),
        [
            "frame-0000.png",
            "frame-0000.svg",
            "frame-0001.png",
            "frame-0001.svg",
            "frame-0002.png",
            "frame-0002.svg"
        ]
    );
    for k in 0..3 {
        let (size, circles) = svg_size(&all.join(format!("frame-000{k}.svg")));
        assert_eq!(size, (800, 800));
        assert!(circles >= 40, "{circles}");
        assert_eq!(png_size(&all.join(format!("frame-000{k}.png"))), (800, 800));
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn render_errors_name_the_problem_and_write_nothing() {
    let dir = scratch("render-bad");
    let pictures = dir.join("pictures");
    let bad_xyz = dir.join("bad.xyz");
    std::fs::write(
        &bad_xyz,
        "2\nProperties=species:S:1:pos:R:3:radius:R:1 Time=0\nX 0 0 0 0.5\nX 2 oops 0 0.5\n",
    )
    .unwrap();
    let good_xyz = dir.join("good.xyz");
    std::fs::write(
        &good_xyz,
        "1\nProperties=species:S:1:pos:R:3:velo:R:3:radius:R:1:material:I:1 Time=0 pbc=\"F F F\"\n\
         X 0 0 0 0 0 0 0.5 0\n",
    )
    .unwrap();
    let notes = dir.join("notes.txt");
    std::fs::write(&notes, "not a scene\n").unwrap();
    let p = pictures.to_str().unwrap();
    for (args, message) in [
        (
            vec!["render", "/no/such/dir/t.xyz", "--out", p],
            "cannot read /no/such/dir/t.xyz".to_string(),
        ),
        (
            vec!["render", "/no/such/dir/s.toml", "--out", p],
            "cannot read /no/such/dir/s.toml".to_string(),
        ),
        (
            vec!["render", bad_xyz.to_str().unwrap(), "--out", p],
            format!("{}:4:", bad_xyz.display()),
        ),
        (
            vec![
                "render",
                good_xyz.to_str().unwrap(),
                "--frame",
                "3",
                "--out",
                p,
            ],
            "--frame 3:".to_string(),
        ),
        (
            vec![
                "render",
                good_xyz.to_str().unwrap(),
                "--size",
                "12x5000",
                "--out",
                p,
            ],
            "is not a picture size".to_string(),
        ),
        (
            vec!["render", notes.to_str().unwrap(), "--out", p],
            "cannot tell what to draw".to_string(),
        ),
        (
            vec![
                "render",
                &shipped("granular_jet"),
                "--frame",
                "0",
                "--out",
                p,
            ],
            "--frame applies to snapshots".to_string(),
        ),
        (
            vec![
                "render",
                good_xyz.to_str().unwrap(),
                "--out",
                notes.to_str().unwrap(),
            ],
            "not a directory".to_string(),
        ),
    ] {
        let out = run(&args);
        assert!(!out.status.success(), "{args:?}");
        assert!(
            text(&out.stderr).contains(&message),
            "{args:?}: no {message:?} in {}",
            text(&out.stderr)
        );
        assert!(!pictures.exists(), "{args:?}: nothing written");
    }
    assert_eq!(std::fs::read_to_string(&notes).unwrap(), "not a scene\n");
    std::fs::remove_dir_all(&dir).ok();
}

/// `bench`'s memory line comes from `bench --memory-probe N` run as a fresh process: it prints
/// the bytes per sphere a query held after its first call and the peak during it, both
/// measured (the query keeps its buffers, so it holds something) and the peak the larger.
#[cfg(target_os = "linux")]
#[test]
fn the_memory_probe_prints_held_and_peak_bytes_per_sphere() {
    let out = run(&[
        "bench",
        "--memory-probe",
        "20000",
        "--memory-probe-phi",
        "0.3",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    let figures: Vec<f64> = stdout
        .split_whitespace()
        .map(|f| f.parse().unwrap())
        .collect();
    let [held, peak] = figures[..] else {
        panic!("two figures expected: {stdout:?}");
    };
    assert!(held > 0.0 && held < 10_000.0, "{stdout:?}");
    assert!(peak >= held, "{stdout:?}");
}

/// Where stderr is not a terminal (here, a pipe) a run prints plain progress lines, at most one
/// every `--progress-every` seconds (a batch job saw nothing for minutes); `--quiet` prints
/// none, and a bad interval is refused naming the flag.
#[test]
fn a_run_without_a_terminal_prints_progress_lines() {
    let dir = scratch("run-progress-lines");
    let args = |extra: &[&str]| {
        let mut a = vec![
            "run".to_string(),
            shipped("hard_sphere_gas"),
            "--out".into(),
            dir.to_str().unwrap().into(),
            "--t-end".into(),
            "3".into(),
            "--snapshots".into(),
            "0".into(),
            "--force".into(),
        ];
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let call = |a: Vec<String>| run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    let out = call(args(&["--progress-every", "1e-6"]));
    assert!(out.status.success(), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("progress: t = "))
        .collect();
    assert!(lines.len() >= 2, "{err}");
    assert!(
        lines[0].contains("collisions") && lines[0].contains("% of t = 3"),
        "{err}"
    );
    let out = call(args(&["--progress-every", "1e-6", "--quiet"]));
    assert!(
        !text(&out.stderr).contains("progress:"),
        "{}",
        text(&out.stderr)
    );
    let out = call(args(&["--progress-every", "0"]));
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("--progress-every 0 must be greater than 0"));
    std::fs::remove_dir_all(&dir).ok();
}
