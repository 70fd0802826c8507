//! Gravity, checked from the outputs: the event log, the positions and the energies are read
//! here with this file's own arithmetic (closed forms of a ball in free fall, a barometric
//! profile), never by asking the engine whether it did right. Bounds:
//! docs/derivations/gravity.md.

use glam::DVec3;
use spheresweep::sim::{Boundary, Effects, EventRecord, Response, Simulation, SphereState, World};
use spheresweep::{Container, Cylinder, Plane, ShapeKind, Statics};

const G: f64 = 9.81;

fn ball(centre: DVec3, velocity: DVec3) -> SphereState {
    SphereState {
        centre,
        velocity,
        radius: 0.5,
        mass: 1.0,
        material: 0,
    }
}

fn down() -> DVec3 {
    DVec3::new(0.0, 0.0, -G)
}

fn floor() -> Plane {
    Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap()
}

/// One ball dropped from `height` (its bottom above the floor) onto the floor `z = 0`.
fn drop_world(height: f64, response: Response, tc: f64) -> World {
    World {
        spheres: vec![ball(DVec3::new(0.3, -0.2, 0.5 + height), DVec3::ZERO)],
        statics: Statics::new().with(floor(), 0),
        effects: Effects {
            response,
            tc,
            gravity: down(),
            record_events: true,
            ..Effects::default()
        },
        ..World::default()
    }
}

/// Wall events of the log, in order.
fn bounces(log: &[EventRecord]) -> Vec<&EventRecord> {
    log.iter()
        .filter(|e| e.other.kind == ShapeKind::Plane)
        .collect()
}

/// An elastic ball returns to its height at every one of 10⁴ bounces, each bounce at the
/// closed-form time `t_k = t₀ + 2k·u/g` with `u = √(2 g h)`; the bound on the drift is the
/// rounding of one flight per bounce, accumulated (docs/derivations/gravity.md, "Free
/// flight").
#[test]
fn an_elastic_ball_bounces_back_to_its_height_ten_thousand_times() {
    let h = 2.0;
    let mut sim = Simulation::new(drop_world(h, Response::Elastic, 0.0)).unwrap();
    let u = (2.0 * G * h).sqrt();
    let (t0, period) = (u / G, 2.0 * u / G);
    sim.advance_to(t0 + 10_000.0 * period - period / 2.0)
        .unwrap();
    let log = sim.take_events();
    let b = bounces(&log);
    assert_eq!(b.len(), 10_000);
    for (k, e) in b.iter().enumerate() {
        let expected = t0 + k as f64 * period;
        // Times: relative error of a few ulps per bounce, growing at most linearly.
        let bound = 1e-14 * expected * (k as f64 + 1.0).max(1.0);
        assert!(
            (e.time - expected).abs() <= bound.max(1e-12),
            "bounce {k}: {} vs {expected}",
            e.time
        );
        // The height reached is u²/2g: the approach speed stays u.
        assert!(
            (e.approach - u).abs() <= 1e-9 * u,
            "bounce {k}: {}",
            e.approach
        );
    }
    // Energy from the state: K + U is what it was.
    let e = sim.kinetic_energy() + sim.potential_energy();
    let e0 = G * (0.5 + h);
    assert!((e - e0).abs() <= 1e-9 * e0, "{e} vs {e0}");
}

/// An inelastic ball's approach speed falls by `e` at each bounce (its height by `e²`) and
/// the time between bounces is `2u/g` of the speed it left with.
#[test]
fn an_inelastic_ball_loses_e_squared_of_its_height_at_each_bounce() {
    let e = 0.8;
    let h = 3.0;
    let mut sim =
        Simulation::new(drop_world(h, Response::Inelastic { restitution: e }, 0.0)).unwrap();
    // The bounces accumulate at t = u₀/g (1 + 2e/(1 − e)) ≈ 7.04: stop just before.
    sim.advance_to(7.0).unwrap();
    let log = sim.take_events();
    let b = bounces(&log);
    assert!(b.len() >= 21, "{} bounces", b.len());
    let u0 = (2.0 * G * h).sqrt();
    for (k, w) in b.windows(2).enumerate().take(20) {
        let (a, c) = (w[0], w[1]);
        let expected = u0 * e.powi(k as i32);
        assert!((a.approach - expected).abs() <= 1e-9 * u0, "bounce {k}");
        assert!(
            (c.approach - e * a.approach).abs() <= 1e-9 * u0,
            "bounce {k}"
        );
        let flight = 2.0 * e * a.approach / G;
        assert!(
            ((c.time - a.time) - flight).abs() <= 1e-9 * flight.max(1e-3),
            "bounce {k}: {} vs {flight}",
            c.time - a.time
        );
        // The energy each bounce takes is ½(1 − e²)u².
        let lost = 0.5 * (1.0 - e * e) * a.approach * a.approach;
        assert!((a.energy_lost - lost).abs() <= 1e-9 * lost.max(1e-9));
    }
    // The ball never went through the floor.
    assert!(sim.spheres()[0].centre.z >= 0.5 * (1.0 - 1e-9));
}

/// An inelastic ball on a floor would make infinitely many bounces in finite time. With TC it
/// ends hopping every `tc` or so, its bottom no higher than `g·tc²/8` (times the slack of the
/// first TC bounce, up to `tc/e` after the one before); without TC it ends hopping at the
/// least rise that rounding calls for, `2⁻³⁰(‖r‖ + R)` — finitely many events, never a
/// stall, never through the floor.
#[test]
fn a_ball_coming_to_rest_hops_no_higher_than_the_derived_bound() {
    let e = 0.5;
    for tc in [0.0, 1e-3] {
        let world = drop_world(1.0, Response::Inelastic { restitution: e }, tc);
        let mut sim = Simulation::new(world).unwrap();
        let mut highest_late: f64 = 0.0;
        for k in 1..=200 {
            sim.advance_to(0.05 * f64::from(k)).unwrap();
            if k > 100 {
                highest_late = highest_late.max(sim.spheres()[0].centre.z - 0.5);
            }
            sim.take_events();
        }
        let rounding_rise = (0.5f64.hypot(0.36) + 0.5) / (1u64 << 30) as f64;
        let bound = (G * (tc / e).powi(2) / 8.0).max(rounding_rise * 1.01);
        assert!(highest_late <= bound, "tc {tc}: {highest_late} vs {bound}");
        assert!(sim.spheres()[0].centre.z >= 0.5 * (1.0 - 1e-9));
        // Every hop raised the ball's speed back: what it added is in the balance.
        let balance = sim.kinetic_energy() + sim.potential_energy() + sim.stats().energy_lost;
        let e0 = G * 1.5;
        assert!(
            (balance - e0).abs() <= 1e-9 * e0,
            "tc {tc}: {balance} vs {e0}"
        );
    }
}

/// A ball placed exactly at rest on the floor is not a stall: it hops off.
#[test]
fn a_ball_resting_exactly_on_the_floor_does_not_stall() {
    for (response, tc) in [
        (Response::Elastic, 0.0),
        (Response::Inelastic { restitution: 0.5 }, 1e-3),
    ] {
        let mut w = drop_world(0.0, response, tc);
        w.effects.record_events = false;
        let mut sim = Simulation::new(w).unwrap();
        sim.advance_to(1.0).unwrap();
        let z = sim.spheres()[0].centre.z;
        assert!(
            (0.5 * (1.0 - 1e-9)..0.5 + 1e-3).contains(&z),
            "{response:?}: {z}"
        );
    }
}

/// A ball thrown across a sloped floor, a pillar, and a bowl: the brute-force check after
/// every event inside the engine's own tests covers this; here, from outside, it stays on
/// its side of everything and K + U + losses is conserved.
#[test]
fn a_ball_in_a_bowl_with_a_pillar_stays_inside_and_conserves_energy() {
    let world = World {
        spheres: vec![
            ball(DVec3::new(1.0, 0.0, 0.0), DVec3::new(0.3, 2.0, 1.0)),
            ball(DVec3::new(-2.0, 1.0, 1.0), DVec3::new(-1.0, 0.0, 0.5)),
        ],
        statics: Statics::new()
            .with(Container::new([0.0; 3], 5.0).unwrap(), 0)
            .with(
                Cylinder::new([0.0, 0.0, -2.0], [1.0, 0.0, -2.0], 0.4).unwrap(),
                0,
            ),
        effects: Effects {
            gravity: DVec3::new(0.3, 0.0, -G),
            ..Effects::default()
        },
        ..World::default()
    };
    let mut sim = Simulation::new(world).unwrap();
    let e0 = sim.kinetic_energy() + sim.potential_energy();
    for k in 1..=2000 {
        sim.advance_to(0.05 * f64::from(k)).unwrap();
        for s in sim.spheres() {
            assert!(s.centre.length() <= 4.5 * (1.0 + 1e-9), "{}", s.centre);
            let x = s.centre - DVec3::new(0.0, 0.0, -2.0);
            let across = (x.y * x.y + x.z * x.z).sqrt();
            assert!(across >= 0.9 * (1.0 - 1e-9), "{}", s.centre);
        }
        let e = sim.kinetic_energy() + sim.potential_energy();
        assert!(
            (e - e0).abs() <= 1e-8 * e0.abs().max(1.0),
            "t = {}: {e} vs {e0}",
            sim.time()
        );
    }
    let s = sim.stats();
    assert!(s.wall_collisions > 30 && s.pair_collisions > 0, "{s:?}");
}

/// Gravity is refused along a periodic axis, with sticky responses, not finite, or so strong
/// that a fall across the scene passes the speeds' range, naming the field.
#[test]
fn gravity_where_it_cannot_be_is_refused() {
    let mut w = drop_world(1.0, Response::Elastic, 0.0);
    w.boundary = Boundary::Periodic {
        size: DVec3::splat(10.0),
    };
    w.statics = Statics::new();
    let err = Simulation::new(w).unwrap_err().to_string();
    assert!(err.contains("gravity") && err.contains("periodic"), "{err}");
    let w = drop_world(1.0, Response::Sticky, 0.0);
    let err = Simulation::new(w).unwrap_err().to_string();
    assert!(err.contains("gravity") && err.contains("sticky"), "{err}");
    let mut w = drop_world(1.0, Response::Elastic, 0.0);
    w.effects.gravity = DVec3::new(0.0, f64::NAN, 0.0);
    let err = Simulation::new(w).unwrap_err().to_string();
    assert!(err.contains("gravity") && err.contains("finite"), "{err}");
    // So strong that a fall across the scene passes the speeds' range (1e200 stalled the
    // clock, blamed on a dense pile). The ball reaches 2 from the origin: √(2 g·2) ≤ 2¹⁰⁰
    // holds to g = 2¹⁹⁸ (about 4e59).
    let mut w = drop_world(1.0, Response::Elastic, 0.0);
    w.effects.gravity = DVec3::new(0.0, 0.0, -1e60);
    let err = Simulation::new(w.clone()).unwrap_err().to_string();
    assert!(
        err.contains("gravity") && err.contains("beyond 2¹⁰⁰"),
        "{err}"
    );
    w.effects.gravity.z = -1e59;
    assert!(Simulation::new(w.clone()).is_ok());
    // A fall to a floor far away counts too: 10²⁰ below, √(2·1e59·1e20) is past 2¹⁰⁰.
    w.statics = Statics::new().with(Plane::new([0.0, 0.0, -1e20], [0.0, 0.0, 1.0]).unwrap(), 0);
    let err = Simulation::new(w).unwrap_err().to_string();
    assert!(
        err.contains("gravity") && err.contains("beyond 2¹⁰⁰"),
        "{err}"
    );
}

/// This file's own Carnahan–Starling `Z(φ)` and `d(φZ)/dφ`.
fn cs(phi: f64) -> (f64, f64) {
    let z = (1.0 + phi + phi * phi - phi.powi(3)) / (1.0 - phi).powi(3);
    let h = 1e-7 * phi.max(1e-9);
    let pz = |p: f64| p * (1.0 + p + p * p - p.powi(3)) / (1.0 - p).powi(3);
    (z, (pz(phi + h) - pz(phi - h)) / (2.0 * h))
}

/// Hydrostatic equilibrium with the hard-sphere equation of state: `dp/dz = −ρ m g` with
/// `p = ρ kT Z(φ)`, so `dφ/dz = −(m g / kT) φ / (d(φZ)/dφ)`; the profile of centres over
/// `[lo, hi]` holding `n` spheres over the area `area`, as the fraction in each of `bins`.
fn hydrostatic_fractions(
    n: f64,
    area: f64,
    lo: f64,
    hi: f64,
    r: f64,
    mg_kt: f64,
    bins: usize,
) -> Vec<f64> {
    let v = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let steps = 20_000;
    let dz = (hi - lo) / steps as f64;
    let profile = |phi0: f64| {
        let mut phi = phi0;
        let mut out = Vec::with_capacity(steps);
        for _ in 0..steps {
            out.push(phi);
            // Midpoint rule.
            let f = |p: f64| -mg_kt * p / cs(p).1;
            let mid = phi + 0.5 * dz * f(phi);
            phi += dz * f(mid);
        }
        out
    };
    let count = |phi0: f64| profile(phi0).iter().sum::<f64>() * dz * area / v;
    let (mut a, mut b) = (1e-12, 0.6);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if count(m) < n { a = m } else { b = m }
    }
    let p = profile(0.5 * (a + b));
    let total: f64 = p.iter().sum();
    let per = steps / bins;
    (0..bins)
        .map(|k| p[k * per..(k + 1) * per].iter().sum::<f64>() / total)
        .collect()
}

/// An elastic gas between a floor and a ceiling: `K + U` is conserved over 10⁶ collisions
/// within the derived bound, and the time-averaged profile of the centres matches hydrostatic
/// equilibrium with the hard-sphere equation of state (this file's own integration of
/// Carnahan–Starling, at the temperature the run's own kinetic energy gives) within 4σ of
/// the batch means, away from the layers a diameter from the floor and ceiling. The same
/// comparison rejects the profile of a gravity 10 % off, so it can fail.
#[test]
fn an_elastic_gas_under_gravity_conserves_energy_and_settles_into_hydrostatic_equilibrium() {
    // 400 spheres of radius 0.2 at kT = 1 in a box 10 × 10 × 8 of six planes (the bench's).
    let (half, height, r, n, g) = (5.0, 8.0, 0.2, 400, 1.0);
    let world = spheresweep_bench::sim::box_gas(n, DVec3::new(0.0, 0.0, -g), 21);
    let mut sim = Simulation::new(world).unwrap();
    let e0 = sim.kinetic_energy() + sim.potential_energy();
    sim.advance_to(200.0).unwrap();
    let (bins, batches, per_batch) = (16usize, 20usize, 100usize);
    let (lo, hi) = (r, height - r);
    let mut fractions = vec![vec![0.0; bins]; batches];
    let mut kinetic = 0.0;
    let mut t = 200.0;
    for batch in fractions.iter_mut() {
        for _ in 0..per_batch {
            t += 1.0;
            sim.advance_to(t).unwrap();
            for s in sim.spheres() {
                let k = (((s.centre.z - lo) / (hi - lo)) * bins as f64) as usize;
                batch[k.min(bins - 1)] += 1.0 / (n * per_batch) as f64;
            }
            kinetic += sim.kinetic_energy();
        }
    }
    let stats = *sim.stats();
    let collisions = stats.pair_collisions + stats.wall_collisions;
    assert!(
        collisions >= 1_000_000 && stats.pair_collisions > 100_000,
        "{stats:?}"
    );
    // K + U: each event rounds one or two spheres' coordinates and velocities by a few u; over
    // N events at most 8u N of the energies moved (K plus the potential over the box's height).
    let e = sim.kinetic_energy() + sim.potential_energy();
    let scale = e0.abs() + n as f64 * g * height;
    let bound = 8.0 * f64::EPSILON / 2.0 * collisions as f64 * scale;
    assert!(
        (e - e0).abs() <= bound,
        "K + U drifted {:e} (bound {bound:e})",
        e - e0
    );
    // Temperature from equipartition, then the profile.
    let kt = 2.0 / 3.0 * kinetic / (batches * per_batch) as f64 / n as f64;
    let area = (2.0 * (half - r)).powi(2);
    let z_scores = |mg_kt: f64| {
        let predicted = hydrostatic_fractions(n as f64, area, lo, hi, r, mg_kt, bins);
        // Bins two diameters clear of the floor and the ceiling (wall layering is not in a
        // bulk equation of state), both sides renormalised to them.
        let keep: Vec<usize> = (0..bins)
            .filter(|&k| {
                let (a, b) = (
                    lo + (hi - lo) * k as f64 / bins as f64,
                    lo + (hi - lo) * (k + 1) as f64 / bins as f64,
                );
                a >= 4.0 * r && b <= height - 4.0 * r
            })
            .collect();
        let norm_p: f64 = keep.iter().map(|&k| predicted[k]).sum();
        let mut worst: f64 = 0.0;
        for &k in &keep {
            let obs: Vec<f64> = fractions
                .iter()
                .map(|b| b[k] / keep.iter().map(|&j| b[j]).sum::<f64>())
                .collect();
            let mean = obs.iter().sum::<f64>() / batches as f64;
            let var = obs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (batches - 1) as f64;
            let sigma = (var / batches as f64).sqrt();
            worst = worst.max((mean - predicted[k] / norm_p).abs() / sigma);
        }
        worst
    };
    let right = z_scores(g / kt);
    println!(
        "{collisions} collisions; K + U drift {:.3e} (bound {bound:.3e}); kT {kt:.4}; worst bin \
         {right:.2}σ; 10 % off: {:.1}σ",
        e - e0,
        z_scores(1.1 * g / kt)
    );
    assert!(
        right <= 4.0,
        "the profile is {right:.1}σ from hydrostatic equilibrium (kT = {kt})"
    );
    let wrong = z_scores(1.1 * g / kt);
    assert!(
        wrong > 4.0,
        "a gravity 10 % off is not rejected ({wrong:.1}σ): the test has no power"
    );
}

/// `n` spheres of radius 0.5 placed at random (`seed`) within `within` of the centre of a cube
/// of half-side `half`, moving at speed 1, in a bowl of radius `bowl` centred there, under
/// gravity; restitution `e` and the TC model's `tc`.
fn bowl_pile(
    n: usize,
    (half, within): (f64, f64),
    bowl: f32,
    (e, tc): (f64, f64),
    seed: u64,
) -> Simulation {
    let inside = |p: DVec3| p.length() < within;
    let spheres = spheresweep::sim::generate::random_spheres(
        DVec3::splat(-half),
        DVec3::splat(half),
        &inside,
        n,
        0.5,
        1.0,
        0,
        seed,
    )
    .unwrap();
    let world = World {
        spheres,
        statics: Statics::new().with(Container::new([0.0; 3], bowl).unwrap(), 0),
        effects: Effects {
            response: Response::Inelastic { restitution: e },
            tc,
            gravity: down(),
            ..Effects::default()
        },
        ..World::default()
    };
    Simulation::new(world).unwrap()
}

/// A settling inelastic pile with TC, at restitution near 0, in the middle and near 1: no
/// sphere ever beyond the bowl or into another (this file's own distances, at 200 frames),
/// the balance of `K + U` and the losses closes, and — where the restitution lets it settle
/// within the run — the pile comes to rest but for a residue that sloshes: frictionless
/// spheres slide along the bowl and against each other with nothing but normal impulses to
/// take that motion, so their kinetic energy swings (with a period of about 2.35, half the
/// bowl's pendulum period) rather than decays. The test asks that from t = 8 to 16 it stay
/// below 3 · 10⁻³ of the energy lost (the largest measured: 1.85 · 10⁻³ at e = 0.02,
/// 1.46 · 10⁻³ at e = 0.6) and that its peak from t = 12 on be no higher than from 8 to 12
/// (nothing pumps it up: measured 1.81 against 1.85, 1.44 against 1.46);
/// docs/derivations/gravity.md, "What at rest means here".
#[test]
fn a_settling_pile_comes_to_rest_inside_its_bowl_at_every_restitution() {
    for (e, settles) in [(0.02, true), (0.6, true), (0.98, false)] {
        let mut sim = bowl_pile(120, (5.0, 4.3), 6.0, (e, 1e-3), 8);
        let e0 = sim.kinetic_energy() + sim.potential_energy();
        // The largest K / lost from t = 8 to 12, and after 12.
        let mut peaks = [0.0f64; 2];
        for k in 1..=200 {
            sim.advance_to(0.08 * f64::from(k)).unwrap();
            if k >= 100 {
                let share = sim.kinetic_energy() / sim.stats().energy_lost;
                let p = &mut peaks[usize::from(k > 150)];
                *p = p.max(share);
            }
            let s = sim.spheres();
            for (i, a) in s.iter().enumerate() {
                let out = a.centre.length() + a.radius - 6.0;
                assert!(
                    out <= 1e-5 * a.radius,
                    "e = {e}: sphere {i} is {out:e} beyond the bowl"
                );
                for b in &s[i + 1..] {
                    let overlap = a.radius + b.radius - (a.centre - b.centre).length();
                    assert!(
                        overlap <= 1e-5 * (a.radius + b.radius),
                        "e = {e}: overlap {overlap:e}"
                    );
                }
            }
        }
        let (k, u, lost) = (
            sim.kinetic_energy(),
            sim.potential_energy(),
            sim.stats().energy_lost,
        );
        assert!(
            (k + u + lost - e0).abs() <= 1e-9 * lost.abs().max(e0.abs()),
            "e = {e}: K + U + lost = {} vs {e0}",
            k + u + lost
        );
        if settles {
            assert!(
                peaks[0] < 3e-3 && peaks[1] < 3e-3 && peaks[1] <= peaks[0],
                "e = {e}: K / lost peaked at {peaks:?} from t = 8 to 12, and after"
            );
        }
    }
}

/// 40 inelastic spheres settle in a box (a floor and four walls) with TC. Once at rest they
/// simmer: the hops of walls and pairs keep each pressed contact from recurring much sooner
/// than `tc`, so the events per unit time stay bounded — under `7N/tc` (at most twelve
/// contacts a sphere, each pair counted once, and a wall: seven contacts per sphere, each
/// recurring about every `tc` at most) in each of ten seconds at rest, measured at a steady
/// `2.4 N/tc` — and the kinetic energy stays small. Without the pair hop the rate grows
/// (8 · 10⁴ to 3.9 · 10⁵ from the first second to the seventh), and with hops only where
/// gravity presses on a wall it explodes (6.7 × 10⁷ events by t = 8.25):
/// docs/derivations/gravity.md, "Resting piles". A run past its event budget stops and
/// fails, never hangs.
#[test]
fn a_resting_stack_simmers_at_a_bounded_rate() {
    let (n, tc) = (40usize, 1e-3);
    let mut rng = spheresweep::rng::Rng::new(3);
    let g = [-1.8, -0.6, 0.6, 1.8];
    let mut spheres = Vec::new();
    for z in g {
        for y in g {
            for x in g {
                let centre = DVec3::new(x, y, z + 2.5);
                spheres.push(ball(centre, rng.direction() * 1.5));
            }
        }
    }
    spheres.truncate(n);
    let mut statics = Statics::new();
    for (p, normal) in [
        ([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        ([-3.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ([3.0, 0.0, 0.0], [-1.0, 0.0, 0.0]),
        ([0.0, -3.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 3.0, 0.0], [0.0, -1.0, 0.0]),
    ] {
        statics.push(Plane::new(p, normal).unwrap(), 0);
    }
    let world = World {
        spheres,
        statics,
        effects: Effects {
            response: Response::Inelastic { restitution: 0.5 },
            tc,
            gravity: down(),
            ..Effects::default()
        },
        ..World::default()
    };
    let mut sim = Simulation::new(world).unwrap();
    let e0 = sim.kinetic_energy() + sim.potential_energy();
    let events = |s: &Simulation| s.stats().pair_collisions + s.stats().wall_collisions;
    let bound = 7.0 * n as f64 / tc;
    sim.advance_to(8.0).unwrap();
    let mut energies = Vec::new();
    for k in 1..=10 {
        let (t0, before) = (sim.time(), events(&sim));
        let budget = before + (2.0 * bound) as u64;
        let done = sim
            .advance_with(t0 + 1.0, &mut |_, s| {
                s.pair_collisions + s.wall_collisions < budget
            })
            .unwrap();
        let rate = (events(&sim) - before) as f64 / (sim.time() - t0);
        println!(
            "t = {}: {rate:.3e} events per unit time, K = {:.3e}",
            sim.time(),
            sim.kinetic_energy()
        );
        assert!(
            done && rate <= bound,
            "second {k} at rest: {rate:.3e} events per unit time (bound {bound:.3e})"
        );
        energies.push(sim.kinetic_energy());
        for s in sim.spheres() {
            assert!(s.centre.z >= 0.5 * (1.0 - 1e-9) && s.centre.x.abs() <= 2.5 * (1.0 + 1e-9));
        }
    }
    // At rest: what moves is the simmer, a thousandth of the energy the pile lost or less.
    let lost = sim.stats().energy_lost;
    assert!(
        energies.iter().all(|&k| k < 1e-3 * lost),
        "{energies:?} of {lost}"
    );
    let balance = sim.kinetic_energy() + sim.potential_energy() + lost - e0;
    assert!(
        balance.abs() <= 1e-9 * lost,
        "K + U + lost drifted {balance:e}"
    );
}

/// The event log's `restitution` is what each collision did: the normal separation speed over
/// the approach, read back here through the energy each row says it took, `½ μ u² (1 − r²)`
/// (`μ` the pair's reduced mass, a wall's sphere's mass; every mass here 1). Two grains
/// meeting gently in free fall keep their coefficient (gravity presses nothing together: no
/// hop); a settling stack's resting contacts (within `tc` of a sphere's last) are elastic and
/// hop at `‖g‖·tc/2`, reading above 1 with a negative loss where the hop added energy
/// (docs/derivations/gravity.md, "Resting piles"). Rounding: `energy_lost` is formed from
/// velocities of at most `v_max` (the speed the whole of the scene's energy would give one
/// sphere), each term to a few ulps of `½ v_max²`; the bound allows 64 of them.
#[test]
fn the_event_log_reads_what_each_collision_did() {
    let (e, tc) = (0.5, 1e-3);
    let effects = Effects {
        response: Response::Inelastic { restitution: e },
        tc,
        gravity: down(),
        record_events: true,
        ..Effects::default()
    };
    let (u, z) = (0.002, 10.0);
    let pair = World {
        spheres: vec![
            ball(DVec3::new(-0.5005, 0.0, z), DVec3::new(0.5 * u, 0.0, 0.0)),
            ball(DVec3::new(0.5005, 0.0, z), DVec3::new(-0.5 * u, 0.0, 0.0)),
        ],
        effects: effects.clone(),
        ..World::default()
    };
    let mut sim = Simulation::new(pair).unwrap();
    sim.advance_to(1.0).unwrap();
    let log = sim.take_events();
    assert_eq!(log.len(), 1, "{log:?}");
    let (approach, r, lost) = (log[0].approach, log[0].restitution, log[0].energy_lost);
    let expected = 0.5 * 0.5 * u * u * (1.0 - e * e);
    assert!(
        (approach - u).abs() <= 1e-12 && r == e && (lost - expected).abs() <= 1e-12 * expected,
        "grains meeting in free fall: approach {approach}, restitution {r}, lost {lost:e} (expected {u}, {e}, {expected:e})"
    );

    // A stack of 27 settling on a floor between four walls.
    let mut rng = spheresweep::rng::Rng::new(5);
    let g = [-1.2, 0.0, 1.2];
    let mut spheres = Vec::new();
    for z in g {
        for y in g {
            for x in g {
                spheres.push(ball(DVec3::new(x, y, z + 2.0), rng.direction()));
            }
        }
    }
    let mut statics = Statics::new().with(floor(), 0);
    for (p, normal) in [
        ([-2.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ([2.0, 0.0, 0.0], [-1.0, 0.0, 0.0]),
        ([0.0, -2.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 2.0, 0.0], [0.0, -1.0, 0.0]),
    ] {
        statics.push(Plane::new(p, normal).unwrap(), 0);
    }
    let world = World {
        spheres,
        statics,
        effects,
        ..World::default()
    };
    let mut sim = Simulation::new(world).unwrap();
    // Energy above the lowest the spheres can sit (centres at z = 0.5), all in one sphere.
    let floor_u = 27.0 * G * 0.5;
    let v_max_sq = 2.0 * (sim.kinetic_energy() + sim.potential_energy() - floor_u);
    sim.advance_to(4.0).unwrap();
    let log = sim.take_events();
    let (mut hops, mut kept) = (0, 0);
    for ev in &log {
        let mu = if ev.other.kind == ShapeKind::Sphere {
            0.5
        } else {
            1.0
        };
        let (u, r) = (ev.approach, ev.restitution);
        let said = 0.5 * mu * u * u * (1.0 - r * r);
        let tolerance = 64.0 * f64::EPSILON * (0.5 * v_max_sq + 0.5 * mu * u * u * (1.0 + r * r));
        assert!(
            (ev.energy_lost - said).abs() <= tolerance,
            "t = {}: sphere {} and {:?}: approach {u:e}, restitution {r}, but lost {:e} (½μu²(1 − r²) = {said:e})",
            ev.time,
            ev.sphere,
            ev.other,
            ev.energy_lost
        );
        if r > 1.0 + 1e-6 {
            hops += 1;
        } else if r == e {
            kept += 1;
        }
    }
    // Both kinds occur, so both readings were checked.
    assert!(
        hops > 100 && kept > 100,
        "{hops} hops, {kept} at e, of {}",
        log.len()
    );
}

/// Without TC an inelastic pile in a bowl has no floor but the rounding hop on its walls
/// (`2⁻³⁰` of the scene's size), which feeds it as fast as its collisions drain it: 30 spheres
/// at restitution 0.5 ground on at a steady 8.5 · 10⁶ collisions per unit time, each sphere's
/// some 10⁻⁶ apart (an eighth of the rounding hop's flight is 6 · 10⁻⁶), never converging and
/// never named. The collapse watch names it, within a bounded number of collisions; with TC the
/// same pile runs on (by construction for the watch: with TC its window is at most `tc`, and a
/// dissipating collision comes at least `tc` after the sphere's last, so none adds to the
/// count — this half guards the run, not the watch).
#[test]
fn an_inelastic_pile_in_a_bowl_without_tc_is_named_a_collapse() {
    let pile = |tc: f64| bowl_pile(30, (3.0, 2.5), 3.0, (0.5, tc), 5);
    let mut without = pile(0.0);
    let mut polls = 0u64;
    match without.advance_with(6.0, &mut |_, _| {
        polls += 1;
        polls < 5_000
    }) {
        Err(e @ spheresweep::sim::SimError::Collapse { .. }) => {
            assert!(e.to_string().contains("tc > 0"), "{e}");
        }
        other => panic!(
            "expected the collapse named, got {other:?} at t = {}",
            without.time()
        ),
    }
    pile(1e-3).advance_to(6.0).unwrap();
}

/// One sphere sliding round a bowl without TC meets the wall many times a window of the
/// collapse watch (a chord of angle `2κ`, `κ = 2⁻¹²`, lasts `2κD/v`), fast or under weak
/// gravity or far from the origin (where the rounding hop's flight, the window's floor, is
/// long): it is sliding, not collapsing, and runs on. Wall collisions under gravity are not
/// counted; counting them named these three a collapse at t = 19.6, 0.49 and 19.5 (a review).
#[test]
fn a_sphere_sliding_round_a_bowl_without_tc_is_no_collapse() {
    for (g, v, centre, t_end) in [
        (1e-4, 10.0, [0.0; 3], 25.0),
        (9.81, 400.0, [0.0; 3], 1.0),
        (1.0, 10.0, [1e4, 0.0, 0.0], 25.0),
    ] {
        let c = DVec3::from_array(centre);
        let world = World {
            spheres: vec![ball(c - DVec3::Z * 3.9999, DVec3::X * v)],
            statics: Statics::new().with(Container::new(c.as_vec3().to_array(), 4.5).unwrap(), 0),
            effects: Effects {
                response: Response::Inelastic { restitution: 0.5 },
                gravity: DVec3::new(0.0, 0.0, -g),
                ..Effects::default()
            },
            ..World::default()
        };
        let mut sim = Simulation::new(world).unwrap();
        if let Err(e) = sim.advance_to(t_end) {
            panic!("g = {g}, v = {v}, bowl at {centre:?}: {e}");
        }
        assert!(
            sim.stats().wall_collisions > 1000,
            "it slid: {:?}",
            sim.stats()
        );
    }
}
