//! Open scenes whose spheres fly apart for good finish at once, whatever `t_end` (a lone sphere
//! with `t_end = 1e308` once left its shell for ever); pairs that meet late, or barely, are
//! still met. Positions are checked against straight lines computed here, not by the engine.

use glam::DVec3;
use spheresweep::sim::{SimError, Simulation, SphereState, Stats, World};
use spheresweep::{Plane, Statics};

fn ball(centre: DVec3, velocity: DVec3) -> SphereState {
    SphereState {
        centre,
        velocity,
        radius: 0.5,
        mass: 1.0,
        material: 0,
    }
}

/// Advances to `t` with at most `max_polls` × 4096 events; panics past the bound.
fn bounded(sim: &mut Simulation, t: f64, max_polls: u64) -> Result<(), SimError> {
    let mut polls = 0u64;
    let done = sim.advance_with(t, &mut |_, _: &Stats| {
        polls += 1;
        polls < max_polls
    })?;
    assert!(
        done,
        "not finished in {max_polls} × 4096 events: at t = {}",
        sim.time()
    );
    Ok(())
}

/// `a` within the rounding of a straight line to `b`: the last sums round at `|b|` (a few
/// `ε|b|`), the shell events before parking each rounded at the scene's scale (under 10³
/// here, a hundred events at most: under 10⁻¹⁰).
fn on_the_line(a: DVec3, b: DVec3) -> bool {
    (a - b).abs().max_element() <= 4.0 * f64::EPSILON * b.abs().max_element() + 1e-10
}

/// A lone sphere, and a cloud expanding from a point above a floor it rises from: both park
/// within a few dozen shell events and are then where straight lines put them at `t = 10²⁰`.
#[test]
fn spheres_that_fly_apart_finish_at_once_on_their_lines() {
    let lone = World {
        spheres: vec![ball(DVec3::ZERO, DVec3::new(1.0, -0.5, 0.25))],
        ..World::default()
    };
    let mut cloud = Vec::new();
    for k in 0..27 {
        let p = DVec3::new((k % 3) as f64, (k / 3 % 3) as f64, (k / 9) as f64) * 1.5;
        // Velocity `s (p − c) + w`: every pair recedes (`rᵢⱼ · vᵢⱼ = s |rᵢⱼ|²`), all rise.
        cloud.push(ball(p, (p - DVec3::splat(1.5)) * 0.3 + DVec3::Z));
    }
    let floor = Plane::new([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]).unwrap();
    let cloud = World {
        spheres: cloud,
        statics: Statics::new().with(floor, 0),
        ..World::default()
    };
    for world in [lone, cloud] {
        let n = world.spheres.len();
        let mut sim = Simulation::new(world.clone()).unwrap();
        let t = 1e20;
        bounded(&mut sim, t, 2).unwrap();
        let since = sim.flown_apart().expect("flown apart");
        assert!(since < 1e3, "{n} spheres: flown apart only at {since}");
        assert_eq!(sim.stats().pair_collisions + sim.stats().wall_collisions, 0);
        assert!(sim.stats().crossings < 200, "{:?}", sim.stats());
        for (s, w) in sim.spheres().iter().zip(&world.spheres) {
            let line = w.centre + w.velocity * t;
            assert!(
                on_the_line(s.centre, line),
                "{:?} against {line:?}",
                s.centre
            );
            assert_eq!(s.velocity, w.velocity);
        }
        // Twice as fast from t = 10²⁰: new velocities are an event; it parks again, nothing
        // having happened since then.
        let faster: Vec<DVec3> = world.spheres.iter().map(|s| s.velocity * 2.0).collect();
        sim.set_velocities(&faster).unwrap();
        assert_eq!(sim.flown_apart(), None);
        bounded(&mut sim, 2.0 * t, 2).unwrap();
        assert_eq!(sim.flown_apart(), Some(t));
    }
}

/// Two spheres 10³ apart closing at 0.02 meet at `t = 49 950`, after thousands of quiet
/// shell events: the test for flying apart sees them approach and does not park. Two passing
/// at an impact parameter a hair (10⁻⁶ of the contact distance) inside contact meet; a hair
/// outside, they never do, and the scene parks.
#[test]
fn pairs_that_meet_late_or_barely_are_met() {
    let head_on = World {
        spheres: vec![
            ball(DVec3::ZERO, DVec3::X * 0.01),
            ball(DVec3::X * 1000.0, -DVec3::X * 0.01),
        ],
        ..World::default()
    };
    let mut sim = Simulation::new(head_on).unwrap();
    bounded(&mut sim, 49_949.0, 50).unwrap();
    assert_eq!(sim.stats().pair_collisions, 0);
    assert!(sim.flown_apart().is_none() && sim.stats().crossings > 1000);
    bounded(&mut sim, 1e9, 50).unwrap();
    assert_eq!(sim.stats().pair_collisions, 1);
    // Equal masses, head on: they swap velocities at t = 49 950, then fly apart.
    let s = sim.spheres();
    assert_eq!((s[0].velocity.x, s[1].velocity.x), (-0.01, 0.01));
    let since = sim.flown_apart().expect("flown apart after the collision");
    // Nothing has met anything since the collision.
    assert!((since - 49_950.0).abs() < 1e-6, "{since}");
    let meet = 49_950.0;
    let want = DVec3::X * (0.01 * meet - 0.01 * (1e9 - meet));
    assert!((s[0].centre - want).length() < 1e-6, "{:?}", s[0].centre);

    for (b, meets) in [(1.0 - 1e-6, true), (1.0 + 1e-6, false)] {
        let passing = World {
            spheres: vec![
                ball(DVec3::ZERO, DVec3::ZERO),
                ball(DVec3::new(-200.0, b, 0.0), DVec3::X),
            ],
            ..World::default()
        };
        let mut sim = Simulation::new(passing).unwrap();
        bounded(&mut sim, 1e6, 50).unwrap();
        assert_eq!(sim.stats().pair_collisions, u64::from(meets), "b = {b}");
        // Met, nothing has happened since the collision near t = 200; a hair apart, nothing
        // ever happened (the test for flying apart sees that they never meet before they pass).
        let since = sim.flown_apart().expect("flown apart");
        assert_eq!(since > 199.0, meets, "b = {b}: nothing since {since}");
    }
}

/// A parked run's checkpoint restores to the same bytes and the same positions later; new
/// velocities wake it, and a pair aimed at each other then meets when straight lines say. A
/// checkpoint that claims to be parked while its spheres still have events is refused.
#[test]
fn a_parked_run_checkpoints_and_wakes() {
    let world = World {
        spheres: vec![ball(DVec3::ZERO, -DVec3::X), ball(DVec3::X * 3.0, DVec3::X)],
        ..World::default()
    };
    let mut sim = Simulation::new(world.clone()).unwrap();
    bounded(&mut sim, 100.0, 2).unwrap();
    assert!(sim.flown_apart().is_some());
    let saved = sim.checkpoint();
    let mut back = Simulation::restore(world.clone(), &saved).unwrap();
    assert_eq!(back.checkpoint(), saved);
    bounded(&mut sim, 1e4, 2).unwrap();
    bounded(&mut back, 1e4, 2).unwrap();
    assert_eq!(sim.spheres(), back.spheres());
    // Turned round at t = 10⁴, at −10⁴ and 3 + 10⁴, closing at 2: they touch (1 apart) at
    // t = 10⁴ + (2·10⁴ + 2)/2 = 20 001.
    back.set_velocities(&[DVec3::X, -DVec3::X]).unwrap();
    assert!(back.flown_apart().is_none());
    bounded(&mut back, 20_000.9, 50).unwrap();
    assert_eq!(back.stats().pair_collisions, 0);
    bounded(&mut back, 20_001.1, 50).unwrap();
    assert_eq!(back.stats().pair_collisions, 1);

    // The parked flag forged into a checkpoint of a run that is not parked (its byte follows
    // the quiet count and the wait; the parking time, the event log's flag and the checksum
    // come after it).
    let mut early = Simulation::new(world.clone()).unwrap();
    early.advance_to(0.1).unwrap();
    let mut bytes = early.checkpoint();
    let body = bytes.len() - 8;
    bytes[body - 10] = 1;
    let sum = bytes[..body]
        .iter()
        .fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        });
    bytes[body..].copy_from_slice(&sum.to_le_bytes());
    let err = Simulation::restore(world, &bytes).unwrap_err().to_string();
    assert!(err.contains("parked, but"), "{err}");
}

/// Asked to go on until a parked sphere would be past its reach, the run refuses, naming the
/// sphere, the time, when the last event was and how far it can go (and goes there), and stays
/// where it was: two spheres side by side moving together (a gap of 0.5 they keep) reach
/// `2⁵⁰ (0.5 + 2⁻¹⁶)` (about 5.6·10¹⁴), where their positions would round by a good part of
/// the gap; a lone sphere goes to `2¹⁰⁰` (about 1.27·10³⁰).
#[test]
fn a_parked_run_refuses_to_fly_past_its_reach() {
    let side_by_side = World {
        spheres: vec![ball(DVec3::ZERO, DVec3::X), ball(DVec3::Y * 1.5, DVec3::X)],
        ..World::default()
    };
    let lone = World {
        spheres: vec![ball(DVec3::ZERO, DVec3::X)],
        ..World::default()
    };
    let margin = 0.5 + 1.0 / 65536.0;
    for (world, reach) in [
        (side_by_side, 2f64.powi(50) * margin),
        (lone, 2f64.powi(100)),
    ] {
        let mut sim = Simulation::new(world).unwrap();
        bounded(&mut sim, reach / 2.0, 2).unwrap();
        let err = sim.advance_to(reach * 2.0).unwrap_err();
        let SimError::Flown {
            sphere,
            time,
            since,
            reachable,
        } = err
        else {
            panic!("{err}");
        };
        assert!(sphere <= 1 && time == reach * 2.0 && since == 0.0, "{err}");
        assert!(
            reachable <= reach && reachable > reach * (1.0 - 1e-12),
            "{err}"
        );
        assert_eq!(sim.time(), reach / 2.0);
        let text = err.to_string();
        assert!(text.contains("the run can go on to t = "), "{text}");
        sim.advance_to(reachable).unwrap();
    }
}

/// A free flight `10⁸` from the origin, with the engine kept awake by a pair that meets only at
/// `t ≈ 10⁹`: after `3.5·10⁵` shell events its centre is still its straight line from the
/// start, to a few ulps of `10⁸` (each shell event moved the body to its time, rounding at
/// `10⁸`, and it drifted by `2.7·10⁻³`, 10⁵ ulps).
#[test]
fn a_free_flight_far_from_the_origin_stays_on_its_line() {
    let start = DVec3::new(1e8, 0.0, 0.0);
    let v = DVec3::new(1e-3, 1e-3, 0.0);
    let world = World {
        spheres: vec![
            ball(start, v),
            ball(DVec3::new(0.0, -2000.0, 0.0), DVec3::ZERO),
            ball(DVec3::new(0.0, -3000.0, 0.0), DVec3::Y * 1e-6),
        ],
        ..World::default()
    };
    let mut sim = Simulation::new(world).unwrap();
    let t = 5e8;
    bounded(&mut sim, t, 400).unwrap();
    assert!(sim.flown_apart().is_none() && sim.stats().crossings > 100_000);
    let line = start + v * t;
    let got = sim.spheres()[0].centre;
    let ulp = 1e8 * f64::EPSILON;
    assert!(
        (got - line).abs().max_element() <= 4.0 * ulp,
        "{got:?} against {line:?}"
    );
}

/// A parked scene at rest checkpointed at `t = 10²⁰⁰` restores and goes on: its spheres are
/// where they started. The checkpoint's shell check moved them with the parabola's `g Δt²/2`,
/// which is `0 · ∞ = NaN` once `Δt²` overflows, and `f64::max` then dropped the NaN, so the
/// check checked nothing; with the NaN kept, the parabola refuses this checkpoint.
#[test]
fn a_scene_at_rest_checkpoints_at_any_time() {
    let world = World {
        spheres: vec![
            ball(DVec3::ZERO, DVec3::ZERO),
            ball(DVec3::X * 3.0, DVec3::ZERO),
        ],
        ..World::default()
    };
    let mut sim = Simulation::new(world.clone()).unwrap();
    bounded(&mut sim, 1e200, 2).unwrap();
    let saved = sim.checkpoint();
    let mut back = Simulation::restore(world, &saved).unwrap();
    assert_eq!(back.checkpoint(), saved);
    bounded(&mut back, 1e300, 2).unwrap();
    let centres: Vec<DVec3> = back.spheres().iter().map(|s| s.centre).collect();
    assert_eq!(centres, [DVec3::ZERO, DVec3::X * 3.0]);
}
