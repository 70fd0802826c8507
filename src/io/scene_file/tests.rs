//! The scene file read and built end to end: a full scene, its JSON twin, and the errors
//! that name their item and line.

use super::*;
use crate::ShapeKind;
use crate::sim::{MaterialPair, Response};

const FULL: &str = r#"
[run]
t_end = 2.5
snapshot_every = 0.5
seed = 7

[boundary]
kind = "box"
lo = [-30.0, -30.0, -20.0]
hi = [30.0, 30.0, 40.0]

[[material]]
name = "glass"

[[material]]
name = "rubber"

[effects]
response = "inelastic"
restitution = 0.8
tc = 1e-4
record_events = true
geometry = true

[[effects.pair]]
a = "glass"
b = "rubber"
response = "sticky"

[[sphere]]
centre = [3.0, 3.0, 25.0]
velocity = [0.0, 0.0, -1.0]
radius = 0.5
mass = 2.0
material = "rubber"

[[generate]]
kind = "nozzle"
origin = [0.0, 0.0, 10.0]
direction = [0.0, 0.0, -1.0]
n = 50
radius = 0.2
speed = 3.0
spread = 0.05
material = "glass"

[[generate]]
kind = "random"
n = 100
radius = 0.3
speed = 1.0
inside = 0
seed = 3

[[generate]]
kind = "lattice"
lo = [10.0, 10.0, 1.0]
counts = [3, 4, 5]
spacing = 1.0
radius = 0.4

[[plane]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
material = "rubber"

[[cylinder]]
p1 = [5.0, 0.0, 0.0]
p2 = [5.0, 0.0, 1.0]
radius = 1.0

[[container]]
centre = [0.0, 0.0, 10.0]
radius = 30.0
"#;

#[test]
fn a_full_scene_builds() {
    let scene = SceneFile::from_toml_str(FULL).unwrap();
    let (world, run) = scene.build().unwrap();
    assert_eq!(
        run,
        RunSettings {
            t_end: 2.5,
            snapshot_every: Some(0.5),
            seed: 7
        }
    );
    assert_eq!(world.spheres.len(), 1 + 50 + 100 + 60);
    assert_eq!(world.materials, ["glass", "rubber"]);
    assert_eq!(world.spheres[0].material, 1);
    assert_eq!(world.spheres[0].mass, 2.0);
    assert!(world.spheres[1..].iter().all(|s| s.material == 0));
    assert_eq!(
        world.effects.response,
        Response::Inelastic { restitution: 0.8 }
    );
    assert_eq!(
        world.effects.pairs,
        [MaterialPair {
            a: 0,
            b: 1,
            response: Response::Sticky
        }]
    );
    let kinds: Vec<_> = world.statics.iter().map(|(b, _, &m)| (b.kind, m)).collect();
    assert_eq!(
        kinds,
        [
            (ShapeKind::Plane, 1),
            (ShapeKind::Cylinder, kinds[1].1),
            (ShapeKind::Container, kinds[2].1)
        ]
    );
    // The random block is inside its container.
    for s in &world.spheres[51..151] {
        assert!(s.centre.distance(DVec3::new(0.0, 0.0, 10.0)) <= 30.0 - 0.3);
    }
    let sim = Simulation::new(world).unwrap();
    assert!(sim.engine_name().contains("static shapes"));
    assert!(scene.start().is_ok());
}

#[test]
fn json_builds_the_same_world() {
    let json = r#"{
        "run": {"t_end": 2.5, "snapshot_every": 0.5, "seed": 7},
        "boundary": {"kind": "box", "lo": [-30, -30, -20], "hi": [30, 30, 40]},
        "material": [{"name": "glass"}, {"name": "rubber"}],
        "effects": {"response": "inelastic", "restitution": 0.8, "tc": 1e-4,
                    "record_events": true, "geometry": true,
                    "pair": [{"a": "glass", "b": "rubber", "response": "sticky"}]},
        "sphere": [{"centre": [3, 3, 25], "velocity": [0, 0, -1], "radius": 0.5,
                    "mass": 2, "material": "rubber"}],
        "generate": [
            {"kind": "nozzle", "origin": [0, 0, 10], "direction": [0, 0, -1], "n": 50,
             "radius": 0.2, "speed": 3, "spread": 0.05, "material": "glass"},
            {"kind": "random", "n": 100, "radius": 0.3, "speed": 1, "inside": 0, "seed": 3},
            {"kind": "lattice", "lo": [10, 10, 1], "counts": [3, 4, 5], "spacing": 1,
             "radius": 0.4}
        ],
        "plane": [{"point": [0, 0, 0], "normal": [0, 0, 1], "material": "rubber"}],
        "cylinder": [{"p1": [5, 0, 0], "p2": [5, 0, 1], "radius": 1}],
        "container": [{"centre": [0, 0, 10], "radius": 30}]
    }"#;
    let from_json = SceneFile::from_json_str(json).unwrap().build().unwrap();
    let from_toml = SceneFile::from_toml_str(FULL).unwrap().build().unwrap();
    assert_eq!(from_json, from_toml);
}

/// JSON has no NaN or infinity: where serde_json stops at one, the message says so (and only
/// there: another syntax error keeps serde_json's own words).
#[test]
fn json_names_a_nan_or_an_infinity_it_cannot_read() {
    let error = |value: &str| {
        let text = format!(
            r#"{{"run": {{"t_end": 1}}, "sphere": [{{"centre": [5, 0, {value}], "radius": 1}}]}}"#
        );
        SceneFile::from_json_str(&text).unwrap_err().to_string()
    };
    for value in ["NaN", "Infinity", "-Infinity"] {
        let message = error(value);
        assert!(
            message.contains("JSON has no NaN or infinity"),
            "{value}: {message}"
        );
    }
    let message = error("[1]");
    assert!(!message.contains("NaN"), "{message}");
    let unquoted = SceneFile::from_json_str(r#"{"run": {"t_end": 1}, infinite: 1}"#);
    let message = unquoted.unwrap_err().to_string();
    assert!(
        message.contains("key must be a string") && !message.contains("NaN"),
        "{message}"
    );
}

/// Shapes are stored in f32: a finite value beyond its range is named as such, at its line
/// (a new user's trial: `radius = 1e39` read "container radius is NaN or infinite").
#[test]
fn a_shape_value_beyond_f32_is_named_as_such() {
    let text = "[run]\nt_end = 1\n\n[[container]]\ncentre = [0, 0, 0]\nradius = 1e39\n";
    let message = toml_error(text);
    assert!(
        message.contains("line 6")
            && message.contains("container 0")
            && message.contains("radius holds 1e39, beyond the range of f32"),
        "{message}"
    );
    let text = "[run]\nt_end = 1\n\n[[plane]]\npoint = [0, -4e38, 0]\nnormal = [0, 0, 1]\n";
    let message = toml_error(text);
    assert!(message.contains("point holds -4e38, beyond"), "{message}");
}

fn toml_error(text: &str) -> String {
    match SceneFile::from_toml_str(text) {
        Err(e) => e.to_string(),
        Ok(s) => s.build().unwrap_err().to_string(),
    }
}

#[test]
fn a_typo_is_refused_naming_the_field_and_its_line() {
    let text = FULL.replace("restitution = 0.8", "restitusion = 0.8");
    let line = text
        .lines()
        .position(|l| l.starts_with("restitusion"))
        .unwrap()
        + 1;
    let err = toml_error(&text);
    assert!(err.contains(&format!("line {line}")), "{err}");
    assert!(err.contains("unknown field `restitusion`"), "{err}");
    // In a generator block too (not the first one), and in JSON.
    let text = FULL.replace("inside = 0", "insde = 0");
    let line = text.lines().position(|l| l.starts_with("insde")).unwrap() + 1;
    let err = toml_error(&text);
    assert!(
        err.contains(&format!("line {line}")) && err.contains("`insde`"),
        "{err}"
    );
    let err = SceneFile::from_json_str("{\"run\": {\n\"t_end\": 1,\n\"sede\": 2}}")
        .unwrap_err()
        .to_string();
    assert!(err.contains("`sede`") && err.contains("line 3"), "{err}");
}

#[test]
fn undeclared_materials_name_the_item_and_line() {
    let text = FULL.replace(
        "material = \"rubber\"\n\n[[generate]]",
        "material = \"steel\"\n\n[[generate]]",
    );
    let err = toml_error(&text);
    assert!(
        err.starts_with("line 35: sphere 0: material \"steel\" is not declared"),
        "{err}"
    );
    let err = toml_error(
        "[run]\nt_end = 1\n[[plane]]\npoint = [0,0,0]\nnormal = [0,0,1]\nmaterial = \"x\"\n",
    );
    assert!(
        err.starts_with("line 6: plane 0: material \"x\" is not declared"),
        "{err}"
    );
}

/// More materials than the engine's response table holds are refused, naming the first
/// one too many; the most accepted build.
#[test]
fn at_most_max_materials_are_declared() {
    let declare = |n: usize| {
        let mut text = String::from("[run]\nt_end = 1\n");
        for k in 0..n {
            text += &format!("[[material]]\nname = \"m{k}\"\n");
        }
        text
    };
    let max = crate::sim::MAX_MATERIALS;
    let err = toml_error(&declare(max + 1));
    assert!(err.contains(&format!("at most {max} materials")), "{err}");
    let file = SceneFile::from_toml_str(&declare(max)).unwrap();
    let (world, _) = file.build().unwrap();
    assert_eq!(world.materials.len(), max);
}

#[test]
fn fields_that_do_not_fit_their_item_are_named() {
    let cases = [
        (
            FULL.replace("spread = 0.05", "phi = 0.05"),
            "generate 0 (nozzle): `phi` does not apply",
        ),
        (
            FULL.replace("counts = [3, 4, 5]\n", ""),
            "generate 2 (lattice): kind = \"lattice\" needs `counts`",
        ),
        (
            FULL.replace("inside = 0", "inside = 4"),
            "inside = 4: the scene has one container, 0",
        ),
        (
            FULL.replace("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, 0.0]"),
            "plane 0: plane normal has zero length",
        ),
        (
            FULL.replace("restitution = 0.8", "restitution = 1.5"),
            "effects: restitution = 1.5 must be in [0, 1]",
        ),
        (
            FULL.replace(
                "response = \"sticky\"",
                "response = \"sticky\"\nrestitution = 0.5",
            ),
            "effects.pair 0: restitution applies only to response = \"inelastic\"",
        ),
        (
            FULL.replace("t_end = 2.5", "t_end = -1"),
            "run: t_end = -1.0 must be finite",
        ),
        (
            FULL.replace("mass = 2.0", "mass = 0.0"),
            "sphere 0: mass = 0.0 must be finite and greater than 0",
        ),
        (
            FULL.replace("mass = 2.0", "mass = 1e-40"),
            "sphere 0: mass = 1e-40 is outside 2⁻¹⁰⁰ to 2¹⁰⁰",
        ),
        (
            FULL.replace(
                "velocity = [0.0, 0.0, -1.0]",
                "velocity = [0.0, 0.0, -1e100]",
            ),
            "sphere 0: velocity = [0.0, 0.0, -1e100] is beyond 2¹⁰⁰",
        ),
        (
            FULL.replace("radius = 0.5", "radius = 1e160"),
            "sphere 0: radius = 1e160 is outside 2⁻¹⁰⁰ to 2¹⁰⁰",
        ),
        (
            FULL.replace("kind = \"box\"", "kind = \"periodic\""),
            "boundary: `lo` does not apply to kind = \"periodic\"",
        ),
        (
            FULL.replace("name = \"rubber\"", "name = \"glass\""),
            "material 1: name \"glass\" is already material 0",
        ),
    ];
    for (text, want) in cases {
        let err = toml_error(&text);
        assert!(err.contains(want), "want {want:?} in {err}");
        assert!(err.starts_with("line "), "{err}");
    }
}

/// A boundary beyond the engine's range is refused at the `[boundary]` table's line, naming
/// the kind of box (the engine's `SimError::Range`, located by what it names).
#[test]
fn a_boundary_beyond_the_range_is_refused_at_its_table() {
    let huge = FULL.replace("hi = [30.0, 30.0, 40.0]", "hi = [30.0, 30.0, 1e31]");
    let err = toml_error(&huge);
    let line = FULL.lines().position(|l| l == "[boundary]").unwrap() + 1;
    let want = format!("line {line}: boundary: open box: outside the range");
    assert!(
        err.starts_with(&want),
        "want {want:?} at the start of {err}"
    );
}

#[test]
fn overlapping_spheres_are_named_by_their_entries() {
    let text = "[run]\nt_end = 1\n\n[[sphere]]\ncentre = [0, 0, 0]\nradius = 1\n\n[[generate]]\nkind = \"lattice\"\nlo = [1, 0, 0]\ncounts = [2, 1, 1]\nspacing = 3\nradius = 0.5\n";
    let scene = SceneFile::from_toml_str(text).unwrap();
    let err = scene.start().unwrap_err().to_string();
    assert!(
        err.starts_with(
            "line 4: sphere 0 and generate 0 (lattice), its sphere 0: spheres 0 and 1 overlap"
        ),
        "{err}"
    );
}

#[test]
fn a_periodic_gas_sets_its_box() {
    let text = "[run]\nt_end = 1\n[boundary]\nkind = \"periodic\"\n[[generate]]\nkind = \"periodic_gas\"\nn = 500\nphi = 0.2\nradius = 0.5\ntemperature = 2.0\nmass = 4.0\n";
    let (world, _) = SceneFile::from_toml_str(text).unwrap().build().unwrap();
    let Boundary::Periodic { size } = world.boundary else {
        panic!("not periodic")
    };
    let volume = 500.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.125 / 0.2;
    assert!((size.x.powi(3) - volume).abs() < 1e-9 * volume);
    let ke: f64 = world
        .spheres
        .iter()
        .map(|s| 0.5 * s.mass * s.velocity.length_squared())
        .sum();
    assert!((ke - 1.5 * 500.0 * 2.0).abs() < 1e-9 * ke);
    let err = toml_error(&text.replace("kind = \"periodic\"", "kind = \"open\""));
    assert!(
        err.contains("periodic_gas needs [boundary] kind = \"periodic\""),
        "{err}"
    );
    let err = toml_error("[run]\nt_end = 1\n[boundary]\nkind = \"periodic\"\n");
    assert!(err.contains("a periodic boundary needs `size`"), "{err}");
}

#[test]
fn the_documented_example_builds_and_runs() {
    let doc = include_str!("../../../docs/scene-format.md");
    let example = doc
        .split("```toml\n")
        .nth(1)
        .and_then(|s| s.split("```").next())
        .expect("docs/scene-format.md has a TOML example");
    let scene = SceneFile::from_toml_str(example).unwrap();
    let (mut sim, run) = scene.start().unwrap();
    assert_eq!(sim.spheres().len(), 101);
    sim.advance_to(run.t_end).unwrap();
    assert!(sim.stats().pair_collisions > 0 && sim.stats().wall_collisions > 0);
}

#[test]
fn files_are_named_in_messages() {
    let missing = Path::new("/no/such/scene.toml");
    let err = SceneFile::from_path(missing).unwrap_err().to_string();
    assert!(
        err.starts_with("cannot read /no/such/scene.toml: "),
        "{err}"
    );
    let dir = std::env::temp_dir().join(format!("spheresweep-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("typo.toml");
    std::fs::write(&path, "[run]\nt_ned = 1\n").unwrap();
    let err = SceneFile::from_path(&path).unwrap_err().to_string();
    assert!(
        err.starts_with(&format!("{}: TOML parse error at line 2", path.display())),
        "{err}"
    );
    std::fs::write(
        &path,
        "[run]\nt_end = 1\n[[sphere]]\ncentre = [0,0,0]\nradius = 1\nmaterial = \"rubber\"\n",
    )
    .unwrap();
    let err = SceneFile::from_path(&path)
        .unwrap()
        .build()
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with(&format!(
            "{}:6: sphere 0: material \"rubber\" is not declared",
            path.display()
        )),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The warnings of the world the scene `text` builds.
fn warnings(text: &str) -> Vec<String> {
    let file = SceneFile::from_toml_str(text).unwrap();
    let (world, _) = file.build().unwrap();
    file.warnings(&world)
}

/// A shape moved by its `f32` rounding by more than `2⁻¹⁰` of the smallest radius where the
/// scene is, named at its entry's line; a move along a plane or along a cylinder's axis is not
/// one, a tilt is (it grows with the scene's extent).
#[test]
fn shapes_that_rounding_moves_are_warned_of_at_their_line() {
    let scene = |radius: f64| {
        warnings(&format!(
            "[run]\nt_end = 1\n\
             [[sphere]]\ncentre = [0, 0, 5]\nradius = {radius}\n\
             [[plane]]\npoint = [100000000.3, 0, -100000000.3]\nnormal = [0, 0, 1]\n\
             [[cylinder]]\np1 = [100000000.3, 3, 0]\np2 = [0, 3, 0]\nradius = 0.5\n\
             [[container]]\ncentre = [0, 0, 0]\nradius = 1000.1\n"
        ))
    };
    // The plane's point moves 0.3 along its normal (z); the cylinder's p1 only along its axis
    // (x); the container's radius by 2.4e-5, under 2⁻¹⁰ · 0.5.
    let w = scene(0.5);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("line 6: plane 0: stored in f32") && w[0].contains("3.00e-1"),
        "{w:?}"
    );
    // With a smaller sphere the container's radius moves by more than 2⁻¹⁰ of it.
    let w = scene(0.01);
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(w[1].starts_with("line 13: container 0: stored"), "{w:?}");
    // A pillar moved across its axis.
    let pillar = "[[cylinder]]\np1 = [0, 100000000.3, 0]\np2 = [0, 100000000.3, 1]\nradius = 0.5\n";
    let w = warnings(&format!(
        "[run]\nt_end = 1\n[[sphere]]\ncentre = [0, 0, 0]\nradius = 0.5\n{pillar}"
    ));
    assert!(
        w.len() == 1 && w[0].starts_with("line 6: cylinder 0: stored"),
        "{w:?}"
    );
    // A tilted axis whose ends round by 1.2e-5 and 2.4e-5 (under 2⁻¹⁰ · 0.5 = 4.9e-4): its
    // tilt moves it 3.4e-4 at 10 along it, 7e-3 at 200: said when the scene reaches 200.
    let tilted = "[[cylinder]]\np1 = [1000.1, 0, 0]\np2 = [1000.2, 0, 1]\nradius = 0.5\n";
    for (far, said) in [(5.0, false), (200.0, true)] {
        let w = warnings(&format!(
            "[run]\nt_end = 1\n[[sphere]]\ncentre = [1000, 0, {far}]\nradius = 0.5\n{tilted}"
        ));
        assert_eq!(w.len(), usize::from(said), "{far}: {w:?}");
    }
}

/// A sphere far from the origin is named at its entry's line; a generated one by its block
/// and its index in it.
#[test]
fn spheres_far_from_the_origin_are_warned_of_at_their_entry() {
    let w = warnings("[run]\nt_end = 1\n[[sphere]]\ncentre = [0, -1e12, 0]\nradius = 0.5\n");
    assert!(
        w.len() == 1 && w[0].starts_with("line 3: sphere 0: its coordinate 1e12 rounds"),
        "{w:?}"
    );
    let w = warnings(
        "[run]\nt_end = 1\n[[sphere]]\ncentre = [0, 0, 0]\nradius = 0.5\n\
         [[generate]]\nkind = \"nozzle\"\norigin = [1e12, 0, 0]\ndirection = [0, 0, -1]\n\
         n = 5\nradius = 0.2\nspeed = 4.0\n",
    );
    assert!(
        w.len() == 1
            && w[0].starts_with("line 6: generate 0 (nozzle), its sphere 0: its coordinate")
            && w[0].contains("(and 4 other spheres)"),
        "{w:?}"
    );
}
