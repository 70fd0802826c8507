//! Limits: a scene or a chunk too large for the memory available is refused before anything
//! is built, naming the count, the estimated bytes and the memory available; a run whose
//! outputs are projected beyond `--max-output` (default half the free disk) is refused before
//! it starts, and one whose outputs pass it stops, removing its files; pathological
//! scenes finish with bounded work or stop with a clear error. Work is bounded by counting
//! events (the engine asks every 4096 events whether to go on), never by wall-clock time.

mod common;
mod run_support;

use common::{PAIR_HEADER, bin, repo, scratch, sparse_pairs_csv};

use glam::DVec3;
use spheresweep::Container;
use spheresweep::sim::{
    Effects, MaterialPair, Response, SimError, Simulation, SphereState, World, generate,
};

/// More spheres than a scene file may give (10¹⁵ from one lattice) are refused for the count,
/// naming the block's line and the limit, by `run` and `render` alike, not for the memory
/// they would take (which suggests more memory would do).
#[test]
fn a_block_of_more_spheres_than_a_scene_may_give_is_refused_for_its_count() {
    let dir = scratch("count-scene");
    let scene = dir.join("huge.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 1\n\n[[generate]]\nkind = \"lattice\"\nlo = [0, 0, 0]\n\
         counts = [100000, 100000, 100000]\nspacing = 2\nradius = 0.5\n",
    )
    .unwrap();
    for command in ["run", "render"] {
        let out = bin()
            .args([command, "--out"])
            .arg(dir.join(command))
            .arg(&scene)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{command}: {err}");
        assert!(
            err.contains("huge.toml:7: generate 0 (lattice): counts must give between 1 and")
                && !err.contains("GiB"),
            "{command}: {err}"
        );
    }
}

#[test]
fn a_scene_too_large_for_memory_is_refused_before_it_is_built() {
    let dir = scratch("memory-scene");
    // 4000 spheres need about 1.4 MiB; say 1 MiB is available.
    let out = bin()
        .args(["run", "--quiet", "--out"])
        .arg(dir.join("out"))
        .arg(repo("scenes/hard_sphere_gas.toml"))
        .env("SPHERESWEEP_MAX_MEMORY", "1M")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("hard_sphere_gas.toml")
            && err.contains("4000 spheres")
            && err.contains("needs about")
            && err.contains("1.0 MiB (1048576 B) is available")
            && err.contains("SPHERESWEEP_MAX_MEMORY"),
        "{err}"
    );
    assert!(
        !dir.join("out").exists(),
        "a refused scene wrote its output directory"
    );

    // A billion spheres are refused against the machine's own memory, before a sphere is
    // generated (the estimate is 10⁹ × about 360 B).
    let huge = dir.join("huge.toml");
    std::fs::write(
        &huge,
        "[run]\nt_end = 1\n\n[boundary]\nkind = \"periodic\"\n\n[[generate]]\nkind = \"periodic_gas\"\nn = 250000000\nphi = 0.1\nradius = 0.5\ntemperature = 1.0\n",
    )
    .unwrap();
    let out = bin()
        .args(["run", "--quiet"])
        .arg(&huge)
        .env("SPHERESWEEP_MAX_MEMORY", "8G")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("250000000 spheres") && err.contains("GiB"),
        "{err}"
    );

    // A bad override is named.
    let out = bin()
        .args(["run", "--quiet"])
        .arg(repo("scenes/hard_sphere_gas.toml"))
        .env("SPHERESWEEP_MAX_MEMORY", "lots")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("SPHERESWEEP_MAX_MEMORY=\"lots\""),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_query_chunk_too_large_for_memory_is_refused() {
    let dir = scratch("memory-query");
    let input = dir.join("pairs.csv");
    std::fs::write(
        &input,
        format!("{PAIR_HEADER}0,0,0,1,0,0,1,5,0,0,0,0,0,1\n"),
    )
    .unwrap();
    // A file with room for a million rows (a header, then sparse to 64 MiB: no row is read
    // before the check).
    let large = dir.join("large.csv");
    sparse_pairs_csv(&large, 64 << 20);
    let out = bin()
        .args(["query", "--chunk-rows", "1000000"])
        .arg(&large)
        .env("SPHERESWEEP_MAX_MEMORY", "64M")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("--chunk-rows 1000000 (1000000 rows at most in this input)")
            && err.contains("needs about")
            && err.contains("64.0 MiB"),
        "{err}"
    );
    assert!(!dir.join("large-toi.csv").exists());
    // The same chunk fits in 4 GiB, and a small one in 64 MiB; and a file of one row is not
    // refused for a chunk of a million (it holds at most a few rows: a new user's trial had
    // a 16-row file refused under 700 MiB).
    for (rows, limit) in [("1000000", "4G"), ("1000", "64M"), ("1000000", "64M")] {
        let out = bin()
            .args(["query", "--chunk-rows", rows])
            .arg(&input)
            .env("SPHERESWEEP_MAX_MEMORY", limit)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Advances to `t`, at most `max_polls` × 4096 events; returns the events processed, or the
/// engine's error. Panics if the bound is reached.
fn run_bounded(sim: &mut Simulation, t: f64, max_polls: u64) -> Result<u64, SimError> {
    let mut polls = 0u64;
    let finished = sim.advance_with(t, &mut |_, _| {
        polls += 1;
        polls < max_polls
    })?;
    let s = sim.stats();
    assert!(
        finished,
        "not finished after {polls} × 4096 events (t = {} of {t})",
        sim.time()
    );
    Ok(s.pair_collisions + s.wall_collisions + s.crossings + s.stale)
}

fn sphere(centre: DVec3, velocity: DVec3, radius: f64, material: u16) -> SphereState {
    SphereState {
        centre,
        velocity,
        radius,
        mass: radius.powi(3),
        material,
    }
}

/// One huge sphere sets the grid's cell size, so that every sphere shares a cell or two with
/// every other: each prediction looks at all of them, but the run still ends, with work that
/// grows with the collisions, not without bound.
#[test]
fn every_sphere_in_one_cell_finishes() {
    let vessel = |p: DVec3| p.length() < 9.0 && p.length() > 6.4;
    let mut spheres = generate::random_spheres(
        DVec3::splat(-9.5),
        DVec3::splat(9.5),
        &vessel,
        300,
        0.3,
        1.0,
        0,
        4,
    )
    .unwrap();
    spheres.push(sphere(DVec3::ZERO, DVec3::ZERO, 6.0, 0));
    let world = World {
        spheres,
        statics: spheresweep::Statics::new().with(Container::new([0.0; 3], 10.0).unwrap(), 0),
        ..World::default()
    };
    let mut sim = Simulation::new(world).unwrap();
    // 300 spheres at speed 1 in a shell of volume ~2600: some thousands of collisions by
    // t = 20; 250 polls (10⁶ events) is a bound two orders of magnitude above.
    let events = run_bounded(&mut sim, 20.0, 250).unwrap();
    assert!(sim.stats().pair_collisions > 0 && events > 0);
}

/// Every sphere sticks to every other, in a small elastic container: they gather into
/// clusters and finally one, which moves as a rigid body; the run ends.
#[test]
fn everything_stuck_in_one_cluster_finishes() {
    let inside = |p: DVec3| p.length() < 3.4;
    let spheres = generate::random_spheres(
        DVec3::splat(-3.5),
        DVec3::splat(3.5),
        &inside,
        60,
        0.4,
        2.0,
        1,
        9,
    )
    .unwrap();
    let world = World {
        spheres,
        statics: spheresweep::Statics::new().with(Container::new([0.0; 3], 4.0).unwrap(), 0),
        // Glue (material 1) sticks to glue; the vessel (material 0) is elastic, so that the
        // clusters keep moving and meet.
        materials: vec!["vessel".into(), "glue".into()],
        effects: Effects {
            pairs: vec![MaterialPair {
                a: 1,
                b: 1,
                response: Response::Sticky,
            }],
            ..Effects::default()
        },
        ..World::default()
    };
    let mut sim = Simulation::new(world).unwrap();
    run_bounded(&mut sim, 200.0, 250).unwrap();
    let clusters = sim.clusters();
    let largest = clusters.iter().map(Vec::len).max().unwrap_or(0);
    assert!(
        largest >= 30,
        "largest cluster {largest} of 60 spheres after t = 200"
    );
}

/// A dense inelastic pile without the TC model collapses (infinitely many collisions in finite
/// time): the engine stops with `SimError::Collapse`, naming the sphere, the time and the
/// remedy, well within the bound (a local collapse never stalls the clock the global watchdog
/// reads: other spheres' events keep it moving); with the TC model the same pile runs to the
/// end and keeps the invariant.
#[test]
fn a_dense_inelastic_pile_collapses_with_a_clear_error_or_runs_with_tc() {
    let pile = |tc: f64| {
        let mut world = World::default();
        generate::periodic_gas(&mut world, 500, 0.45, 0.5, 1.0, 2).unwrap();
        world.effects = Effects {
            response: Response::Inelastic { restitution: 0.05 },
            pairs: Vec::<MaterialPair>::new(),
            tc,
            ..Effects::default()
        };
        Simulation::new(world).unwrap()
    };
    // The collapse is seen after 10⁵ rapid collisions of one sphere; allow ten times the
    // global watchdog's 10⁶ + 1000 × 500 events in all.
    let bound = 10 * (1_000_000 + 1000 * 500) / 4096 + 1;
    match run_bounded(&mut pile(0.0), 50.0, bound) {
        Err(e @ SimError::Collapse { time, .. }) => {
            let text = e.to_string();
            assert!(time < 50.0 && text.contains("tc > 0"), "{text}");
        }
        other => panic!("expected the collapse to be named, got {other:?}"),
    }
    let mut with_tc = pile(1e-3);
    run_bounded(&mut with_tc, 50.0, bound).unwrap();
    assert_eq!(with_tc.time(), 50.0);
    let state = with_tc.check_invariant().unwrap();
    assert!(state.pairs <= 1.0, "{state:?}");
}

/// `render` of a scene and `query --against` a shapes file build the scene's spheres too:
/// a count too large for memory is refused before any is generated.
#[test]
fn render_and_shapes_files_refuse_scenes_too_large_for_memory() {
    let dir = scratch("memory-render");
    let huge = dir.join("huge.toml");
    std::fs::write(
        &huge,
        "[run]\nt_end = 1\n\n[[plane]]\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n\n[[generate]]\nkind = \"lattice\"\nlo = [0, 0, 1]\ncounts = [600, 600, 600]\nspacing = 1.0\nradius = 0.4\n",
    )
    .unwrap();
    let out = bin()
        .args(["render", "--out"])
        .arg(dir.join("pictures"))
        .arg(&huge)
        .env("SPHERESWEEP_MAX_MEMORY", "1G")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("216000000 spheres") && err.contains("needs about"),
        "{err}"
    );
    assert!(!dir.join("pictures").exists());

    let spheres = dir.join("spheres.csv");
    std::fs::write(&spheres, "x,y,z,vx,vy,vz,r\n0,0,5,0,0,-1,1\n").unwrap();
    let out = bin()
        .args(["query", "--against"])
        .arg(&huge)
        .arg(&spheres)
        .env("SPHERESWEEP_MAX_MEMORY", "1G")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        err.contains("216000000 spheres") && err.contains("huge.toml"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Snapshots so frequent that the trajectory would pass the limit: refused before the run,
/// with the projected bytes, nothing written.
#[test]
fn outputs_projected_beyond_the_limit_are_refused_before_the_run() {
    let dir = scratch("max-output");
    let scene = run_support::gas(&dir, "gas", 200, 1, "t_end = 10.0", false);
    let out = dir.join("out");
    // 1001 frames of 200 spheres: about 24 MiB.
    let o = run_support::output(&scene, &out, &["--snapshots", "0.01", "--max-output", "1M"]);
    let err = run_support::stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("the outputs would take up to")
            && err.contains("1001 frames of at most")
            && err.contains("--max-output 1M allows 1.0 MiB (1048576 B)")
            && err.contains("refused before the run"),
        "{err}"
    );
    assert!(!out.exists(), "the output directory made for the run stays");
    // Within the limit it runs.
    run_support::success(&scene, &out, &["--snapshots", "0.5", "--max-output", "1M"]);

    // The shipped gas with a snapshot every 5·10⁻⁵ (a million frames of 4000 spheres, over
    // 700 GB), against the default limit: half the disk's free space.
    let gas = repo("scenes/hard_sphere_gas.toml");
    let o = run_support::output(&gas, &dir.join("big"), &["--snapshots", "5e-5"]);
    let err = run_support::stderr(&o);
    assert!(
        !o.status.success()
            && err.contains("1000001 frames")
            && err.contains("free on the disk of")
            && err.contains("GiB"),
        "{err}"
    );
    assert!(!dir.join("big").exists());

    let o = run_support::output(&scene, &out, &["--max-output", "lots", "--force"]);
    assert!(
        run_support::stderr(&o).contains("--max-output \"lots\" is not a size in bytes"),
        "{}",
        run_support::stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// An event log that passes the limit during the run (events cannot be projected): the run
/// stops with an error, and removes its partial files and its checkpoint.
#[test]
fn a_run_whose_outputs_pass_the_limit_stops_and_removes_its_files() {
    let dir = scratch("max-output-events");
    let scene = run_support::gas(&dir, "gas", 200, 1, "t_end = 50.0", true);
    let out = dir.join("out");
    let o = run_support::output(
        &scene,
        &out,
        &["--max-output", "100K", "--checkpoint-every", "1"],
    );
    let err = run_support::stderr(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("the outputs passed --max-output 100K (100.0 KiB (102400 B)) at t = ")
            && err.contains("partial files and the checkpoint removed"),
        "{err}"
    );
    assert!(!out.exists(), "the output directory made for the run stays");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Numbers in messages beyond 10⁶ are in exponent form: `--t-end 1e300` is not printed as a
/// 301-digit number.
#[test]
fn huge_numbers_in_messages_are_in_exponent_form() {
    let dir = scratch("huge-numbers");
    let scene = run_support::gas(
        &dir,
        "gas",
        100,
        1,
        "t_end = 1.0\nsnapshot_every = 1.0",
        false,
    );
    let o = run_support::output(&scene, &dir.join("out"), &["--t-end", "1e300"]);
    let err = run_support::stderr(&o);
    assert!(
        !o.status.success() && err.contains("1e300 snapshots (t_end 1e300 every 1)"),
        "{err}"
    );
    assert!(!err.contains("00000000000000"), "{err}");
    // It says where each figure came from: the scene file's spacing, the flag's end.
    assert!(err.contains("gas.toml's snapshot_every, --t-end)"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// An open scene whose spheres fly apart runs to `t_end = 1e25` at once (a lone sphere once
/// left its shell for ever): the summary says when they flew apart and prints the end in
/// exponent form; the last frame of the trajectory, read here, has each sphere on its line.
#[test]
fn a_scene_that_flies_apart_runs_to_a_huge_t_end_at_once() {
    let dir = scratch("flying-apart");
    let scene = dir.join("apart.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 1e25\nsnapshot_every = 1e24\n\n\
         [[sphere]]\ncentre = [0, 0, 0]\nradius = 0.5\nvelocity = [-1, 0.5, 0]\n\n\
         [[sphere]]\ncentre = [3, 0, 0]\nradius = 0.5\nvelocity = [1, 0, -0.25]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = run_support::success(&scene, &out, &[]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("run          t = 0 → 1e25 in "), "{text}");
    assert!(
        text.contains("flown apart  nothing has met anything since t = 0,"),
        "{text}"
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        summary["flown_apart"].as_f64(),
        Some(0.0),
        "nothing ever happened"
    );
    let xyz = std::fs::read_to_string(out.join("trajectory.xyz")).unwrap();
    let (time, last) = run_support::last_frame(&xyz, 2);
    assert_eq!(time, 1e25);
    let want = [[-1e25, 0.5e25, 0.0], [3.0 + 1e25, 0.0, -0.25e25]];
    for (got, want) in last.iter().zip(want) {
        for (g, w) in got.iter().zip(want) {
            assert!(
                (g - w).abs() <= 4.0 * f64::EPSILON * w.abs(),
                "{got:?} against {want:?}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A pair meeting `10¹²` from the origin: the run warns at the first sphere's line before it starts
/// and its summary marks the overlap at the collision as beyond the tolerance; the same pair
/// near the origin has neither.
#[test]
fn a_scene_far_from_the_origin_is_warned_of_and_its_overlap_marked() {
    let dir = scratch("far-from-origin");
    for (name, x, far) in [("far", 1e12, true), ("near", 0.0, false)] {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(
            &scene,
            format!(
                "[run]\nt_end = 2\nsnapshot_every = 1\n\n\
                 [[sphere]]\ncentre = [{x:e}, 0.3, 0]\nradius = 0.5\nvelocity = [1, 0, 0]\n\n\
                 [[sphere]]\ncentre = [{:e}, 0, 0]\nradius = 0.5\nvelocity = [-1, 0, 0]\n",
                x + 3.0
            ),
        )
        .unwrap();
        let o = run_support::output(&scene, &dir.join(name), &[]);
        let (text, err) = (String::from_utf8_lossy(&o.stdout), run_support::stderr(&o));
        assert!(o.status.success(), "{err}");
        let warning = format!(
            "warning: {}:5: sphere 0: its coordinate 1e12 ",
            scene.display()
        );
        assert_eq!(err.contains(&warning), far, "{err}");
        assert_eq!(text.contains(": beyond the tolerance 2⁻¹⁶"), far, "{text}");
        assert!(text.contains("collisions   1 pair"), "{text}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A pair flying along x from 10 short of `2³⁶` while it closes in y: at `2³⁶` (t = 10) its
/// coordinates round coarser than its contacts' tolerance, so the run warns once, at the first
/// stop past it (t = 12), naming the sphere; the same pair from the origin never is, and
/// neither is warned of at the start. (Carried there from the origin instead, a sphere would
/// leave its shell some `2³⁶` times on the way.)
#[test]
fn spheres_carried_far_during_a_run_are_warned_of_once() {
    let dir = scratch("carried-far");
    let edge = 2f64.powi(36) - 10.0;
    for (name, x, far) in [("far", edge, true), ("near", 0.0, false)] {
        let scene = dir.join(format!("{name}.toml"));
        std::fs::write(
            &scene,
            format!(
                "[run]\nt_end = 20\nsnapshot_every = 4\n\n\
                 [[sphere]]\ncentre = [{x:?}, 0, 0]\nradius = 0.5\nvelocity = [1, 0.5, 0]\n\n\
                 [[sphere]]\ncentre = [{x:?}, 3, 0]\nradius = 0.5\nvelocity = [1, -0.5, 0]\n"
            ),
        )
        .unwrap();
        let o = run_support::output(&scene, &dir.join(name), &[]);
        let (text, err) = (String::from_utf8_lossy(&o.stdout), run_support::stderr(&o));
        assert!(o.status.success(), "{err}");
        let warning = "warning: at t = 12, sphere 0: its coordinate ";
        assert_eq!(err.contains(warning), far, "{err}");
        assert_eq!(err.matches("warning").count(), usize::from(far), "{err}");
        assert!(text.contains("collisions   1 pair"), "{text}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two spheres side by side flying together, asked to go to `10²⁰`: past their reach (about
/// `5.6·10¹⁴`, where their positions would round by a good part of their gap) the run stops
/// short, but keeps what it computed: a last frame at the reach, with the spheres on their
/// lines and still apart, the summary saying why, and an error exit naming the end asked for
/// and the reach.
#[test]
fn a_parked_run_stopped_at_its_reach_keeps_its_outputs() {
    let dir = scratch("stopped-short");
    let scene = dir.join("together.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 1e20\nsnapshot_every = 1e19\n\n[effects]\nrecord_events = true\n\n\
         [[sphere]]\ncentre = [0, 0, 0]\nradius = 0.5\nvelocity = [1, 0, 0]\n\n\
         [[sphere]]\ncentre = [0, 1.5, 0]\nradius = 0.5\nvelocity = [1, 0, 0]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = run_support::output(&scene, &out, &[]);
    let (text, err) = (String::from_utf8_lossy(&o.stdout), run_support::stderr(&o));
    assert!(!o.status.success(), "{text}");
    // The end asked for is named, not the first snapshot past the reach (10¹⁹) where the
    // run found it could not go on.
    assert!(
        err.contains("error: t = 1e20 is beyond what the simulation can reach")
            && err.contains("the run went on to t = ")
            && err.contains("and stopped there"),
        "{err}"
    );
    assert!(
        text.contains("stopped      short of the end asked for: t = 1e20 is beyond"),
        "{text}"
    );
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let reach = summary["t_end"].as_f64().unwrap();
    let margin = 0.5 + 1.0 / 65536.0;
    assert!(
        reach <= 2f64.powi(50) * margin && reach > 2f64.powi(50) * margin * (1.0 - 1e-12),
        "{reach}"
    );
    assert!(summary["stopped_short"].as_str().is_some(), "{summary}");
    assert!(out.join("events.csv").exists() && !out.join("checkpoint.bin").exists());
    // Two frames, t = 0 and the reach, the last with both spheres on their lines.
    let xyz = std::fs::read_to_string(out.join("trajectory.xyz")).unwrap();
    assert_eq!(xyz.lines().count(), 8, "two frames of two spheres");
    let (time, centres) = run_support::last_frame(&xyz, 2);
    assert_eq!(time, reach);
    assert_eq!(centres, [[reach, 0.0, 0.0], [reach, 1.5, 0.0]]);
    let _ = std::fs::remove_dir_all(&dir);
}
