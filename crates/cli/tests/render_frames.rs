//! `render`: snapshots with a NaN position or a negative radius are refused naming the frame,
//! the sphere and the line; pictures are framed by the scene's boundary or vessel, or else by a
//! robust extent that a far-flung sphere does not change (it is counted in the caption); a
//! run's snapshots are drawn with the shapes and material names of the scene its summary
//! names, only while that scene builds the world the run started from; the periodic box is
//! outlined over the spheres; a nanometre scene is framed as a metre one; a sequence is not
//! mixed with another's frames.

mod common;

use std::path::Path;
use std::process::Output;

use common::{bin, scratch};
use glam::DVec3;
use spheresweep::sim::SphereState;

fn spheresweep(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

const PROPERTIES: &str = "Properties=species:S:1:pos:R:3:radius:R:1 pbc=\"F F F\"";

#[test]
fn snapshots_with_a_nan_position_or_a_negative_radius_are_refused() {
    let dir = scratch("render-bad-xyz");
    for (name, bad, line, want) in [
        (
            "nan.xyz",
            "X 0 nan 0 0.5",
            8,
            "frame 1, sphere 1: pos = [0.0, NaN, 0.0] is not finite",
        ),
        (
            "negative.xyz",
            "X 0 3 0 -0.5",
            8,
            "frame 1, sphere 1: radius = -0.5 must be finite and at least 0",
        ),
    ] {
        let path = dir.join(name);
        std::fs::write(
            &path,
            format!("1\n{PROPERTIES}\nX 0 0 0 0.5\n\n2\n{PROPERTIES}\nX 0 0 0 0.5\n{bad}\n"),
        )
        .unwrap();
        let out_dir = dir.join("pictures");
        let out = spheresweep(&["render", s(&path), "--out", s(&out_dir)]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert!(
            err.contains(&format!("{}:{line}: {want}", path.display())),
            "{err}"
        );
        assert!(!out_dir.exists(), "a refused render made its output");
    }
    std::fs::remove_dir_all(&dir).ok();
}

fn ball(centre: DVec3) -> SphereState {
    SphereState {
        centre,
        velocity: DVec3::ZERO,
        radius: 0.4,
        mass: 1.0,
        material: 0,
    }
}

/// One frame of `spheres` in extended XYZ at `path`.
fn snapshot(path: &Path, spheres: &[SphereState]) {
    let mut text = Vec::new();
    spheresweep::io::xyz::write_frame(&mut text, spheres, 0.0, None).unwrap();
    std::fs::write(path, text).unwrap();
}

/// The top view of `path` as SVG: its text lines, its circles' radii and the whole document.
fn top_view(path: &Path, out: &Path) -> (Vec<String>, Vec<f64>, String) {
    ok(&spheresweep(&[
        "render",
        s(path),
        "--out",
        s(out),
        "--view",
        "top",
        "--format",
        "svg",
    ]));
    let stem = path.file_stem().unwrap().to_str().unwrap();
    let name = if path.extension().is_some_and(|e| e == "xyz") {
        "frame-0000.svg".to_string()
    } else {
        format!("{stem}.svg")
    };
    let svg = std::fs::read_to_string(out.join(name)).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let texts = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or_default().to_string())
        .collect();
    let radii = doc
        .descendants()
        .filter(|n| n.has_tag_name("circle"))
        .map(|n| n.attribute("r").unwrap().parse().unwrap())
        .collect();
    (texts, radii, svg)
}

#[test]
fn a_far_flung_sphere_does_not_change_the_scale_and_is_counted() {
    let dir = scratch("render-outlier");
    let cloud: Vec<SphereState> = (0..1000)
        .map(|k| {
            let (x, y, z) = (k % 10, k / 10 % 10, k / 100);
            ball(DVec3::new(f64::from(x), f64::from(y), f64::from(z)))
        })
        .collect();
    let mut with = cloud.clone();
    with.push(ball(DVec3::new(5000.0, 0.0, 0.0)));
    let (a, b) = (dir.join("cloud.xyz"), dir.join("outlier.xyz"));
    snapshot(&a, &cloud);
    snapshot(&b, &with);
    let (texts_a, radii_a, _) = top_view(&a, &dir.join("a"));
    let (texts_b, radii_b, _) = top_view(&b, &dir.join("b"));
    // The same size of sphere on screen, and the same scale bar.
    let largest = |r: &[f64]| r.iter().copied().fold(0.0, f64::max);
    assert!(largest(&radii_a) > 10.0, "{radii_a:?}");
    assert_eq!(largest(&radii_a), largest(&radii_b));
    let bar = |t: &[String]| t.iter().find(|t| t.parse::<f64>().is_ok()).cloned();
    assert_eq!(bar(&texts_a), bar(&texts_b));
    assert!(
        texts_b
            .iter()
            .any(|t| t.contains("1001 spheres (1 outside the frame)")),
        "{texts_b:?}"
    );
    assert!(
        texts_a
            .iter()
            .any(|t| t.contains("1000 spheres") && !t.contains("outside")),
        "{texts_a:?}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A scene of nine spheres of material "sand" around a vertical pillar of "steel" in an open
/// box, and two spheres outside the box.
const BOXED: &str = "[run]\nt_end = 1\nsnapshot_every = 1\n\n\
    [boundary]\nkind = \"box\"\nlo = [-10, -10, -10]\nhi = [10, 10, 10]\n\n\
    [[material]]\nname = \"sand\"\n\n[[material]]\nname = \"steel\"\n\n\
    [[generate]]\nkind = \"lattice\"\nlo = [-2, -2, 0]\ncounts = [3, 3, 1]\nspacing = 2\n\
    radius = 0.5\nmaterial = \"sand\"\n\n\
    [[sphere]]\ncentre = [60, 0, 0]\nradius = 0.5\nmaterial = \"sand\"\n\n\
    [[sphere]]\ncentre = [0, -80, 0]\nradius = 0.5\nmaterial = \"sand\"\n\n\
    [[cylinder]]\np1 = [6, 0, 0]\np2 = [6, 0, 1]\nradius = 1.5\nmaterial = \"steel\"\n";

#[test]
fn the_open_box_frames_the_scene_and_a_runs_pictures_have_its_shapes_and_names() {
    let dir = scratch("render-boxed");
    let scene = dir.join("boxed.toml");
    std::fs::write(&scene, BOXED).unwrap();
    for picture in [scene.clone(), dir.join("run/trajectory.xyz")] {
        if picture.extension().is_some_and(|e| e == "xyz") {
            ok(&spheresweep(&[
                "run",
                "--quiet",
                s(&scene),
                "--out",
                s(&dir.join("run")),
            ]));
        }
        let (texts, radii, svg) = top_view(&picture, &dir.join("pictures"));
        assert!(
            texts
                .iter()
                .any(|t| t.contains("11 spheres (2 outside the frame)")),
            "{picture:?}: {texts:?}"
        );
        for label in ["sand", "1 cylinder: steel", "open box (the frame)"] {
            assert!(
                texts.iter().any(|t| t == label),
                "{picture:?}: {label} in {texts:?}"
            );
        }
        // The box of side 20 fills the panel: a sphere of radius 0.5 is about 700 / 20.8 / 2
        // pixels, and the pillar (radius 1.5, seen along its axis) three times that.
        let sphere = radii.iter().copied().find(|&r| r > 10.0 && r < 25.0);
        assert!(sphere.is_some(), "{radii:?}");
        let pillar = svg
            .lines()
            .find(|l| l.contains("<circle") && l.contains("#8a939e"));
        let r: f64 = pillar
            .and_then(|l| l.split("r=\"").nth(1))
            .unwrap()
            .split('"')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert!((r / sphere.unwrap() - 3.0).abs() < 0.01, "{r} {sphere:?}");
    }
    // Another scene's shapes over these snapshots: drawn, with a warning naming both counts
    // (and none for the scene they came from).
    let other = dir.join("other.toml");
    let lone = "[run]\nt_end = 1\n\n[[sphere]]\ncentre = [0, 0, 0]\nradius = 0.5\n";
    std::fs::write(&other, lone).unwrap();
    let xyz = dir.join("run/trajectory.xyz");
    for (k, (scene, warned)) in [(&other, true), (&scene, false)].into_iter().enumerate() {
        let out = spheresweep(&[
            "render",
            s(&xyz),
            "--frame",
            "0",
            "--scene",
            s(scene),
            "--out",
            s(&dir.join(format!("pictures-{k}"))),
        ]);
        ok(&out);
        let err = String::from_utf8_lossy(&out.stderr);
        let want = format!(
            "warning: --scene {} has 1 sphere, the snapshots 11: its shapes",
            other.display()
        );
        assert_eq!(err.contains(&want), warned, "{scene:?}: {err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_periodic_box_is_outlined_over_the_spheres() {
    let dir = scratch("render-periodic");
    let scene = dir.join("gas.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 1\n\n[boundary]\nkind = \"periodic\"\n\n[[generate]]\n\
         kind = \"periodic_gas\"\nn = 500\nphi = 0.3\nradius = 0.5\n",
    )
    .unwrap();
    let (texts, _, svg) = top_view(&scene, &dir.join("pictures"));
    // In the panel (the clipped group), the outline comes after the last sphere.
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let panel = doc
        .descendants()
        .find(|n| n.has_tag_name("g") && n.children().any(|c| c.has_tag_name("circle")))
        .unwrap();
    let items: Vec<_> = panel.children().filter(|n| n.is_element()).collect();
    let last_sphere = items
        .iter()
        .rposition(|n| n.has_tag_name("circle"))
        .unwrap();
    let outline = items
        .iter()
        .position(|n| n.attribute("stroke") == Some("#d62728"))
        .expect("the box's outline");
    assert!(
        outline > last_sphere,
        "the outline is drawn under the spheres"
    );
    assert!(texts.iter().any(|t| t == "periodic box"), "{texts:?}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A scene `run` refuses (two spheres overlapping at the start) is drawn, with a warning that
/// says why and where; a scene it runs draws with none.
#[test]
fn a_scene_run_refuses_is_drawn_with_a_warning() {
    let dir = scratch("render-refused");
    let sphere = |x: f64| format!("[[sphere]]\ncentre = [{x}, 0, 0]\nradius = 1\n\n");
    for (name, second, warned) in [("overlap", 1.0, true), ("apart", 3.0, false)] {
        let scene = dir.join(format!("{name}.toml"));
        let text = format!("[run]\nt_end = 1\n\n{}{}", sphere(0.0), sphere(second));
        std::fs::write(&scene, text).unwrap();
        let out = spheresweep(&["render", s(&scene), "--out", s(&dir.join(name))]);
        ok(&out);
        let err = String::from_utf8_lossy(&out.stderr);
        let want = "drawn, but `run` refuses this scene: ";
        assert_eq!(err.contains(want), warned, "{name}: {err}");
        if warned {
            assert!(err.contains("spheres 0 and 1 overlap by 1 ("), "{err}");
        }
    }
}

/// A run's scene is found from wherever its pictures are drawn (its name is the run's working
/// directory's), and only if it still builds the world the run started from: a changed scene,
/// or another file of its name, is not drawn, and a warning says why.
#[test]
fn a_runs_scene_is_drawn_only_if_it_is_the_one_it_ran() {
    let dir = scratch("render-run-scene");
    std::fs::write(dir.join("boxed.toml"), BOXED).unwrap();
    let run = bin()
        .current_dir(&dir)
        .args(["run", "--quiet", "boxed.toml", "--out", "run"])
        .output()
        .unwrap();
    ok(&run);
    let sub = dir.join("sub");
    std::fs::create_dir(&sub).unwrap();
    let render = |out: &str| {
        let o = bin()
            .current_dir(&sub)
            .args(["render", "../run/trajectory.xyz", "--view", "top"])
            .args(["--format", "svg", "--out", out])
            .output()
            .unwrap();
        ok(&o);
        let svg = std::fs::read_to_string(sub.join(out).join("frame-0000.svg")).unwrap();
        let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
        (svg, text(&o.stdout), text(&o.stderr))
    };
    // From a directory of its own the scene is found beside the run: its pillar is drawn.
    let (svg, note, err) = render("found");
    assert!(svg.contains("1 cylinder: steel"), "{err}");
    assert!(
        note.contains("shapes and materials of ../boxed.toml"),
        "{note}"
    );
    assert!(err.is_empty(), "{err}");
    // Another file of the same name here is not the scene the run ran: the one in the run's
    // working directory, above the run's own, is drawn.
    let other = BOXED.replace("radius = 1.5", "radius = 3.5");
    std::fs::write(sub.join("boxed.toml"), &other).unwrap();
    let (_, note, err) = render("beside");
    assert!(
        note.contains("shapes and materials of ../boxed.toml"),
        "{note}"
    );
    assert!(err.is_empty(), "{err}");
    // From inside the run's directory, named as `trajectory.xyz`: found above it.
    std::fs::remove_file(sub.join("boxed.toml")).unwrap();
    let inside = bin()
        .current_dir(dir.join("run"))
        .args([
            "render",
            "trajectory.xyz",
            "--view",
            "top",
            "--format",
            "svg",
        ])
        .args(["--out", "inside"])
        .output()
        .unwrap();
    ok(&inside);
    let note = String::from_utf8_lossy(&inside.stdout);
    assert!(
        note.contains("shapes and materials of ../boxed.toml"),
        "{note}"
    );
    std::fs::write(sub.join("boxed.toml"), &other).unwrap();
    // The scene itself changed after the run: not drawn, and said.
    std::fs::remove_file(sub.join("boxed.toml")).unwrap();
    std::fs::write(dir.join("boxed.toml"), &other).unwrap();
    let (svg, _, err) = render("changed");
    assert!(!svg.contains("cylinder"), "{svg}");
    assert!(
        err.contains("builds the world the run started from"),
        "{err}"
    );
    // And gone: not drawn, and said.
    std::fs::remove_file(dir.join("boxed.toml")).unwrap();
    let (svg, _, err) = render("gone");
    assert!(!svg.contains("cylinder"), "{svg}");
    assert!(err.contains("no file of that name is found"), "{err}");
}

/// A scene a few nanometres across, in metres, is framed by its own extent: its spheres are
/// drawn at the same size in pixels as the same scene a billion times larger.
#[test]
fn a_nanometre_scene_is_framed_as_a_metre_one() {
    let dir = scratch("render-tiny");
    let scene = |scale: f64| {
        format!(
            "[run]\nt_end = 1\n[[sphere]]\ncentre = [{}, 0, 0]\nradius = {}\n\
             [[sphere]]\ncentre = [{}, 0, 0]\nradius = {}\n",
            1.0 * scale,
            0.5 * scale,
            4.0 * scale,
            0.5 * scale
        )
    };
    let mut radii = Vec::new();
    for (name, scale) in [("metre", 1.0), ("nano", 1e-9), ("tiny", 1e-21)] {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, scene(scale)).unwrap();
        let (_, r, _) = top_view(&path, &dir.join(name));
        radii.push(r.iter().copied().fold(0.0, f64::max));
    }
    assert!(radii[0] > 50.0, "{radii:?}");
    for r in &radii[1..] {
        assert!((r / radii[0] - 1.0).abs() < 1e-6, "{radii:?}");
    }
}

/// A render of every frame refuses a directory holding frame pictures it would not overwrite
/// (another sequence's, which would read as one with these) and writes nothing; one frame
/// asked for, or the same sequence again, is drawn.
#[test]
fn frames_of_another_render_are_not_mixed_with_these() {
    let dir = scratch("render-mixed");
    let (two, one) = (dir.join("two.xyz"), dir.join("one.xyz"));
    let mut text = Vec::new();
    for t in [0.0, 1.0] {
        let spheres = [
            ball(DVec3::new(t, 0.0, 0.0)),
            ball(DVec3::new(3.0, 0.0, 0.0)),
        ];
        spheresweep::io::xyz::write_frame(&mut text, &spheres, t, None).unwrap();
    }
    std::fs::write(&two, text).unwrap();
    snapshot(&one, &[ball(DVec3::ZERO)]);
    let out = dir.join("pictures");
    let render = |input: &Path, extra: &[&str]| {
        spheresweep(
            &[
                &["render", s(input), "--out", s(&out), "--format", "svg"],
                extra,
            ]
            .concat(),
        )
    };
    ok(&render(&two, &[]));
    let first = std::fs::read(out.join("frame-0000.svg")).unwrap();
    let refused = render(&one, &[]);
    assert!(!refused.status.success());
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(
        err.contains("holds 1 frame picture this render does not write")
            && err.contains("frame-0001.svg"),
        "{err}"
    );
    assert_eq!(std::fs::read(out.join("frame-0000.svg")).unwrap(), first);
    ok(&render(&two, &[]));
    ok(&render(&one, &["--frame", "0"]));
}

/// A plane tilted along the line of sight shades the band it sweeps over the panel's depths
/// (a sphere drawn on its line may be clear of it at its own depth); one seen edge on does not.
#[test]
fn a_plane_tilted_along_the_line_of_sight_shades_its_sweep() {
    let dir = scratch("render-tilted");
    let swept = |normal: &str| {
        let path = dir.join("plane.toml");
        let scene = format!(
            "[run]\nt_end = 1\n[[plane]]\npoint = [0, 0, 0]\nnormal = {normal}\n\
             [[sphere]]\ncentre = [3, -3, 1]\nradius = 0.5\n\
             [[sphere]]\ncentre = [2, 2, 2]\nradius = 0.5\n"
        );
        std::fs::write(&path, scene).unwrap();
        let (_, _, svg) = top_view(&path, &dir.join("pictures"));
        svg.lines()
            .filter(|l| l.contains("<polygon") && l.contains("#8c6d46"))
            .count()
    };
    assert_eq!(swept("[1, 1, 1]"), 1);
    assert_eq!(swept("[1, 1, 0]"), 0);
}
