//! Nothing leaves its vessel, crosses a plane or enters a pillar, whatever the response: long
//! runs of one sphere and of many in a container at restitution 0.05 … 0.99, with and without
//! the TC model, sticky beads against a container, planes and pillars. Checked from the
//! trajectory alone: every snapshot is written as extended XYZ (`io::xyz::write_frame`, as
//! `spheresweep run` writes it) and read back by this file's own parser, and the positions are
//! checked against the shapes by this file's own geometry — never by the engine's bookkeeping.
//! The tolerance is the engine's stated one, `OVERLAP_TOLERANCE` of the radius (of the contact
//! distance for pairs); docs/derivations/simulation.md, "Concave walls", derives the engine's
//! bound, `2²⁵` times below it.

use glam::DVec3;
use spheresweep::sim::{
    Boundary, Effects, EventRecord, MaterialPair, OVERLAP_TOLERANCE, Response, SimError,
    Simulation, SphereState, Stats, World, generate,
};
use spheresweep::{Body, Container, Cylinder, Plane, ShapeKind, Statics};

/// One sphere of a snapshot, as parsed back here.
#[derive(Clone, Copy)]
struct Row {
    centre: DVec3,
    velocity: DVec3,
    radius: f64,
}

/// One snapshot as `spheresweep run` writes it, parsed back here: each sphere's centre,
/// velocity and radius, from the columns the `Properties` line names.
fn snapshot(sim: &Simulation) -> Vec<Row> {
    let mut text = Vec::new();
    spheresweep::io::xyz::write_frame(&mut text, &sim.spheres(), sim.time(), None).unwrap();
    let text = String::from_utf8(text).unwrap();
    let mut lines = text.lines();
    let n: usize = lines.next().unwrap().trim().parse().unwrap();
    let header = lines.next().unwrap();
    let properties = header
        .split_whitespace()
        .find_map(|w| w.strip_prefix("Properties="))
        .expect("a Properties key");
    // name:type:count triples; the column where each starts.
    let fields: Vec<&str> = properties.split(':').collect();
    let (mut column, mut pos, mut velo, mut radius) = (0, None, None, None);
    for f in fields.chunks(3) {
        let count: usize = f[2].parse().unwrap();
        match f[0] {
            "pos" => pos = Some(column),
            "velo" => velo = Some(column),
            "radius" => radius = Some(column),
            _ => {}
        }
        column += count;
    }
    let (pos, velo) = (pos.expect("pos column"), velo.expect("velo column"));
    let radius = radius.expect("radius column");
    let rows: Vec<Row> = lines
        .map(|l| {
            let w: Vec<f64> = l
                .split_whitespace()
                .skip(1)
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect();
            // The first word is the species; columns count from it.
            let at = |k: usize| w[k - 1];
            Row {
                centre: DVec3::new(at(pos), at(pos + 1), at(pos + 2)),
                velocity: DVec3::new(at(velo), at(velo + 1), at(velo + 2)),
                radius: at(radius),
            }
        })
        .collect();
    assert_eq!(rows.len(), n);
    rows
}

/// The shapes a world holds, for the checks.
struct Shapes {
    containers: Vec<(DVec3, f64)>,
    /// Point, unit normal.
    planes: Vec<(DVec3, DVec3)>,
    /// Point, unit axis, radius.
    pillars: Vec<(DVec3, DVec3, f64)>,
}

impl Shapes {
    fn of(w: &World) -> Self {
        Self {
            containers: (w.statics.of::<Container>().shapes().iter())
                .map(|c| (c.centre().as_dvec3(), f64::from(c.radius())))
                .collect(),
            planes: (w.statics.of::<Plane>().shapes().iter())
                .map(|p| (p.point().as_dvec3(), p.normal().as_dvec3().normalize()))
                .collect(),
            pillars: (w.statics.of::<Cylinder>().shapes().iter())
                .map(|c| {
                    let axis = c.axis().as_dvec3().normalize();
                    (c.point().as_dvec3(), axis, f64::from(c.radius()))
                })
                .collect(),
        }
    }
}

impl Shapes {
    /// The farthest a centre can get from the origin, the shapes confining it: a container's
    /// far side, or with planes only the farthest plane point or start, doubled for a fall
    /// and the walls between (every scene here keeps its spheres within it: `worst` checks).
    fn reach(&self, w: &World) -> f64 {
        let far = |p: DVec3| p.length();
        let vessel = self
            .containers
            .iter()
            .map(|&(c, r)| far(c) + r)
            .fold(0.0, f64::max);
        let walls = (self.planes.iter().map(|&(p, _)| far(p)))
            .chain(self.pillars.iter().map(|&(p, _, r)| far(p) + r))
            .chain(w.spheres.iter().map(|s| far(s.centre)))
            .fold(0.0, f64::max);
        if vessel > 0.0 { vessel } else { 2.0 * walls }
    }
}

/// Largest depth, over its tolerance, of any sphere through a shape, past a vessel's wall,
/// across a plane from `sides` (its side at the start), or of any pair's overlap.
fn worst(frame: &[Row], shapes: &Shapes, sides: &[Vec<bool>]) -> (f64, String) {
    let mut worst = (f64::NEG_INFINITY, String::new());
    let mut take = |depth: f64, tolerance: f64, what: &dyn Fn() -> String| {
        if depth / tolerance > worst.0 {
            worst = (depth / tolerance, what());
        }
    };
    for (
        i,
        &Row {
            centre: c,
            radius: r,
            ..
        },
    ) in frame.iter().enumerate()
    {
        let tol = OVERLAP_TOLERANCE * r;
        for (k, &(centre, radius)) in shapes.containers.iter().enumerate() {
            take((c - centre).length() + r - radius, tol, &|| {
                format!("sphere {i} outside container {k} at {c}")
            });
        }
        for (k, &(p, n)) in shapes.planes.iter().enumerate() {
            let d = (c - p).dot(n);
            let signed = if sides[i][k] { d } else { -d };
            take(r - signed, tol, &|| {
                format!("sphere {i} through plane {k} at {c}")
            });
        }
        for (k, &(p, axis, radius)) in shapes.pillars.iter().enumerate() {
            let x = c - p;
            let radial = (x - axis * x.dot(axis)).length();
            take(r + radius - radial, tol, &|| {
                format!("sphere {i} in pillar {k} at {c}")
            });
        }
        for (
            j,
            &Row {
                centre: cj,
                radius: rj,
                ..
            },
        ) in frame.iter().enumerate().skip(i + 1)
        {
            let d = r + rj;
            take(d - (cj - c).length(), OVERLAP_TOLERANCE * d, &|| {
                format!("spheres {i} and {j} overlap")
            });
        }
    }
    worst
}

/// Runs `world` to `t_end`, checking every snapshot `every` apart from the trajectory alone;
/// returns the statistics and the worst depth over its tolerance. A stall (the watchdog's
/// error) is returned as such: the caller says whether it may happen.
fn run(world: World, t_end: f64, every: f64) -> Result<(Stats, f64), (SimError, f64)> {
    run_balanced(world, t_end, every, None)
}

/// [`run`], checking each interval's energy balance too where a [`Balance`] is given.
fn run_balanced(
    world: World,
    t_end: f64,
    every: f64,
    mut balance: Option<&mut Balance>,
) -> Result<(Stats, f64), (SimError, f64)> {
    let shapes = Shapes::of(&world);
    let mut sim = Simulation::new(world).unwrap();
    let start = snapshot(&sim);
    let sides: Vec<Vec<bool>> = start
        .iter()
        .map(|&Row { centre: c, .. }| {
            shapes
                .planes
                .iter()
                .map(|&(p, n)| (c - p).dot(n) >= 0.0)
                .collect()
        })
        .collect();
    if let Some(b) = balance.as_deref_mut() {
        b.start(&start);
    }
    let mut deepest = f64::NEG_INFINITY;
    let mut t = 0.0;
    while t < t_end {
        t = (t + every).min(t_end);
        let result = sim.advance_to(t);
        let frame = snapshot(&sim);
        let (depth, what) = worst(&frame, &shapes, &sides);
        assert!(
            depth <= 1.0,
            "t = {}: {what}, {depth:e} tolerances deep",
            sim.time()
        );
        if let Some(b) = balance.as_deref_mut() {
            b.check(&frame, &sim.take_events(), sim.time());
        }
        deepest = deepest.max(depth);
        if let Err(e) = result {
            return Err((e, deepest));
        }
    }
    Ok((*sim.stats(), deepest))
}

/// The energy balance under gravity, from the outputs alone: between two snapshots, the drop
/// of `K + U` computed from the parsed rows (`Σ ½m|v|² − m g·r`) equals the sum of the event
/// log's `energy_lost` over the events between them (hops count negative), within the
/// rounding bound of docs/derivations/gravity.md, "The balance read from the outputs":
/// `64 u n e_s + (N + 16) u Σ_frames (½m|v|² + |m g·r|)` for `n` events and `N` spheres,
/// `e_s = K₀ + 3 M ‖g‖ L` the most energy one sphere can hold, `L` the farthest a centre gets
/// from the origin (`reach`, checked at every snapshot).
struct Balance {
    mass: Vec<f64>,
    g: DVec3,
    reach: f64,
    e_s: f64,
    /// `K + U` of the last snapshot, and the sum of its terms' sizes.
    last: (f64, f64),
    events: usize,
    /// Events whose separation speed a hop raised (restitution read above 1).
    hops: usize,
    /// The largest miss over its bound.
    worst: f64,
}

impl Balance {
    fn of(w: &World) -> Option<Self> {
        let g = w.effects.gravity;
        if g == DVec3::ZERO || !w.effects.record_events {
            return None;
        }
        let mass: Vec<f64> = w.spheres.iter().map(|s| s.mass).collect();
        let k0: f64 = (w.spheres.iter())
            .map(|s| 0.5 * s.mass * s.velocity.length_squared())
            .sum();
        let reach = Shapes::of(w).reach(w);
        let e_s = k0 + 3.0 * mass.iter().sum::<f64>() * g.length() * reach;
        Some(Self {
            mass,
            g,
            reach,
            e_s,
            last: (0.0, 0.0),
            events: 0,
            hops: 0,
            worst: 0.0,
        })
    }

    /// `K + U` of a frame and the sum of the sizes of its terms.
    fn energy(&self, frame: &[Row]) -> (f64, f64) {
        frame
            .iter()
            .zip(&self.mass)
            .fold((0.0, 0.0), |(e, size), (r, &m)| {
                let (k, u) = (
                    0.5 * m * r.velocity.length_squared(),
                    -m * self.g.dot(r.centre),
                );
                (e + k + u, size + k + u.abs())
            })
    }

    fn start(&mut self, frame: &[Row]) {
        self.last = self.energy(frame);
    }

    fn check(&mut self, frame: &[Row], log: &[EventRecord], now: f64) {
        let far = frame.iter().map(|r| r.centre.length()).fold(0.0, f64::max);
        assert!(
            far <= self.reach,
            "t = {now}: a centre {far} from the origin"
        );
        let (e, size) = self.energy(frame);
        let lost: f64 = log.iter().map(|r| r.energy_lost).sum();
        let sums = (frame.len() as f64 + 16.0) * U64 * (size + self.last.1);
        let bound = 64.0 * U64 * log.len() as f64 * self.e_s + sums;
        let miss = (self.last.0 - e - lost).abs();
        assert!(
            miss <= bound,
            "t = {now}: K + U fell by {:e}, the {} events logged {lost:e} lost: {miss:e} apart, \
             beyond the bound {bound:e}",
            self.last.0 - e,
            log.len()
        );
        self.worst = self.worst.max(miss / bound);
        self.events += log.len();
        self.hops += log.iter().filter(|r| r.restitution > 1.0 + 1e-6).count();
        self.last = (e, size);
    }
}

/// f64's unit roundoff.
const U64: f64 = f64::EPSILON / 2.0;

/// The user's report: one sphere in a vessel of radius 6.
fn one_in_a_vessel(restitution: f64, tc: f64) -> World {
    World {
        spheres: vec![SphereState {
            centre: DVec3::new(3.0, 0.0, 0.0),
            velocity: DVec3::new(0.3, 1.0, 0.2),
            radius: 0.5,
            mass: 1.0,
            material: 0,
        }],
        statics: Statics::new().with(Container::new([0.0; 3], 6.0).unwrap(), 0),
        effects: Effects {
            response: Response::Inelastic { restitution },
            tc,
            ..Effects::default()
        },
        ..World::default()
    }
}

/// One sphere, restitution 0.05 … 0.99, with and without `tc`, to t = 2500 (the report's
/// spheres left at t ≈ 15.5, 90, 195 and 2010 for 0.3, 0.8, 0.9, 0.99): it stays inside
/// and, its normal speed spent, slides along the wall — millions of wall collisions in all.
#[test]
fn one_inelastic_sphere_never_leaves_its_vessel() {
    let mut walls = 0;
    for e in [0.05, 0.3, 0.8, 0.9, 0.99] {
        for tc in [0.0, 1e-3] {
            let (stats, depth) = run(one_in_a_vessel(e, tc), 2500.0, 5.0)
                .unwrap_or_else(|(err, _)| panic!("e = {e}, tc = {tc}: {err}"));
            assert!(
                stats.slid > stats.wall_collisions / 2,
                "e = {e}, tc = {tc}: slid in {} of {} wall collisions",
                stats.slid,
                stats.wall_collisions
            );
            assert!(depth < 1e-3, "e = {e}, tc = {tc}: {depth:e}");
            walls += stats.wall_collisions;
        }
    }
    assert!(walls > 2_000_000, "{walls} wall collisions in all");
}

/// Spheres placed at random in a vessel, all moving at speed 1.
fn many_in_a_vessel(n: usize, restitution: f64, tc: f64, seed: u64) -> World {
    let inside = |p: DVec3| p.length() < 5.5;
    let spheres = generate::random_spheres(
        DVec3::splat(-5.5),
        DVec3::splat(5.5),
        &inside,
        n,
        0.3,
        1.0,
        0,
        seed,
    )
    .unwrap();
    World {
        spheres,
        ..one_in_a_vessel(restitution, tc)
    }
}

/// Many spheres in a vessel at low and high restitution, with and without `tc`: all stay
/// inside (their bounces against the wall collapse within a few time units, and they slide
/// along it in a shell), and no pair overlaps beyond the tolerance.
#[test]
fn many_inelastic_spheres_never_leave_their_vessel() {
    let mut walls = 0;
    for (n, e, tc) in [
        (20, 0.05, 0.0),
        (20, 0.3, 1e-3),
        (120, 0.05, 1e-3),
        (120, 0.5, 0.0),
        (120, 0.95, 1e-3),
    ] {
        let (stats, depth) = run(many_in_a_vessel(n, e, tc, n as u64), 400.0, 2.0)
            .unwrap_or_else(|(err, _)| panic!("{n} spheres, e = {e}, tc = {tc}: {err}"));
        assert!(
            stats.slid > 1000,
            "{n} spheres, e = {e}, tc = {tc}: {stats:?}"
        );
        assert!(depth < 1.0, "{depth:e}");
        walls += stats.wall_collisions;
    }
    assert!(walls > 500_000, "{walls} wall collisions in all");
}

/// Piles settling under gravity with the TC model, at restitution near 0 and near 1: in a
/// bowl, and in a box of planes around a pillar. Nothing leaves or goes through, and between
/// snapshots the energy `K + U` read from them falls by what the event log says the events
/// took ([`Balance`]): hops included, over about 10⁶ events.
#[test]
fn piles_under_gravity_stay_inside_and_their_event_log_balances_their_energy() {
    let gravity = |w: World, e: f64| World {
        effects: Effects {
            response: Response::Inelastic { restitution: e },
            tc: 1e-3,
            gravity: DVec3::new(0.0, 0.0, -9.81),
            record_events: true,
            ..Effects::default()
        },
        ..w
    };
    let box_around_a_pillar = |seed: u64| {
        let spheres = generate::random_spheres(
            DVec3::new(-3.4, -3.4, 0.6),
            DVec3::new(3.4, 3.4, 8.0),
            &|p: DVec3| p.truncate().length() > 1.3,
            60,
            0.5,
            1.0,
            0,
            seed,
        )
        .unwrap();
        let statics = [
            ([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            ([-4.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            ([4.0, 0.0, 0.0], [-1.0, 0.0, 0.0]),
            ([0.0, -4.0, 0.0], [0.0, 1.0, 0.0]),
            ([0.0, 4.0, 0.0], [0.0, -1.0, 0.0]),
        ]
        .into_iter()
        .fold(Statics::new(), |s, (p, n)| {
            s.with(Plane::new(p, n).unwrap(), 0)
        })
        .with(Cylinder::new([0.0; 3], [0.0, 0.0, 1.0], 0.7).unwrap(), 0);
        World {
            spheres,
            statics,
            ..World::default()
        }
    };
    let (mut events, mut hops) = (0, 0);
    for e in [0.05, 0.95] {
        for (name, world) in [
            ("bowl", many_in_a_vessel(120, e, 0.0, 7)),
            ("box", box_around_a_pillar(7)),
        ] {
            let world = gravity(world, e);
            let mut balance = Balance::of(&world).unwrap();
            let (_, depth) = run_balanced(world, 10.0, 0.25, Some(&mut balance))
                .unwrap_or_else(|(err, _)| panic!("{name}, e = {e}: {err}"));
            assert!(depth < 1e-3, "{name}, e = {e}: {depth:e}");
            assert!(balance.worst < 1e-3, "{name}, e = {e}: {}", balance.worst);
            events += balance.events;
            hops += balance.hops;
            eprintln!(
                "{name}, e = {e}: {} events, {} hops, worst miss {:.2e} of its bound",
                balance.events, balance.hops, balance.worst
            );
        }
    }
    assert!(
        events > 1_000_000 && hops > 10_000,
        "{events} events, {hops} hops"
    );
}

/// Sticky beads: each bead that meets a glue wall stops there (infinite mass), and the free
/// beads bounce off each other, off the other walls and off the stuck beads. In a vessel of
/// glue, and between a glue floor, a ceiling and pillars of both kinds; nothing goes through.
#[test]
fn sticky_beads_stop_at_walls_and_nothing_goes_through() {
    let glue = |w: World| World {
        materials: vec!["bead".into(), "glue".into()],
        effects: Effects {
            response: Response::Inelastic { restitution: 0.5 },
            // Beads stick to glue walls (and stop there), bounce off each other and off the
            // other walls, and off the stuck beads (infinite mass).
            pairs: vec![MaterialPair {
                a: 0,
                b: 1,
                response: Response::Sticky,
            }],
            ..Effects::default()
        },
        ..w
    };
    let mut vessel = many_in_a_vessel(150, 0.5, 0.0, 3);
    *vessel
        .statics
        .payload_mut(Body::new(ShapeKind::Container, 0))
        .unwrap() = 1;
    let (stats, _) = run(glue(vessel), 200.0, 1.0).unwrap_or_else(|(e, _)| panic!("{e}"));
    assert!(stats.joins > 100, "{stats:?}");

    // A slab between two planes, crossed by pillars.
    let spheres = generate::random_spheres(
        DVec3::new(-6.0, -6.0, 0.5),
        DVec3::new(6.0, 6.0, 5.5),
        &|p: DVec3| {
            (-3..=3)
                .all(|k| (p.truncate() - glam::DVec2::new(2.0 * f64::from(k), 0.0)).length() > 1.0)
        },
        200,
        0.3,
        1.0,
        0,
        5,
    )
    .unwrap();
    let slab = World {
        spheres,
        statics: (-3..=3).fold(
            Statics::new()
                .with(Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap(), 1)
                .with(Plane::new([0.0, 0.0, 6.0], [0.0, 0.0, -1.0]).unwrap(), 0),
            |s, k| {
                let x = 2.0 * k as f32;
                let pillar = Cylinder::new([x, 0.0, 0.0], [x, 0.0, 1.0], 0.5).unwrap();
                s.with(pillar, if k % 2 == 0 { 1 } else { 0 })
            },
        ),
        ..World::default()
    };
    let (stats, _) = run(glue(slab), 200.0, 1.0).unwrap_or_else(|(e, _)| panic!("{e}"));
    assert!(stats.joins > 50 && stats.wall_collisions > 200, "{stats:?}");
}

/// In a periodic box a shape is met only as itself (the engine keeps no images of shapes):
/// a plane or a cylinder along a box axis, two largest diameters (and its radius) from the
/// faces it crosses, and a container inside the box, run; any other is refused, naming it.
/// A user's floor at z = 0 in a box of 6 let a sphere rising through the top face come back
/// through the floor. Here a sphere rises from z = 4 at speed 1 past the top face, wraps, and
/// meets a plane at z = 3 from below at t = 4.5, then from above and below every 5: 20 wall
/// collisions by t = 100, and never within its radius of the plane (checked every 0.1 from
/// its position alone).
#[test]
fn shapes_in_a_periodic_box_are_met_as_themselves_or_refused() {
    let at = |statics: Statics<u16>, x: f64| World {
        spheres: vec![SphereState {
            centre: DVec3::new(x, 3.0, 4.0),
            velocity: DVec3::new(0.0, 0.0, 1.0),
            radius: 0.5,
            mass: 1.0,
            material: 0,
        }],
        statics,
        boundary: Boundary::Periodic {
            size: DVec3::splat(6.0),
        },
        ..World::default()
    };
    let one = |statics: Statics<u16>| at(statics, 3.0);
    let plane = |z: f32, normal: [f32; 3]| Plane::new([0.0, 0.0, z], normal).unwrap();
    let mut sim =
        Simulation::new(one(Statics::new().with(plane(3.0, [0.0, 0.0, 1.0]), 0))).unwrap();
    for k in 1..=1000 {
        sim.advance_to(f64::from(k) * 0.1).unwrap();
        let z = sim.spheres()[0].centre.z;
        let gap = (z - 3.0).abs() - 0.5;
        assert!(
            gap >= -OVERLAP_TOLERANCE * 0.5,
            "t = {}: z = {z}",
            sim.time()
        );
    }
    assert_eq!(sim.stats().wall_collisions, 20, "{:?}", sim.stats());

    let fits = [
        Statics::new().with(
            Cylinder::new([3.0, 3.0, 0.0], [3.0, 3.0, 1.0], 0.5).unwrap(),
            0,
        ),
        Statics::new().with(Container::new([3.0; 3], 3.0).unwrap(), 0),
    ];
    for statics in fits {
        // The sphere rises beside the pillar (or inside the vessel), through the top face
        // and back.
        let mut sim = Simulation::new(at(statics, 1.5)).unwrap();
        sim.advance_to(50.0).unwrap();
        assert!(sim.check_invariant().unwrap().walls <= 0.0);
    }
    let refused = [
        (
            Statics::new().with(plane(0.0, [0.0, 0.0, 1.0]), 0),
            "plane 0",
        ),
        (
            Statics::new().with(plane(5.0, [0.0, 0.0, -1.0]), 0),
            "plane 0",
        ),
        (
            Statics::new().with(plane(3.0, [0.0, 0.1, 1.0]), 0),
            "plane 0",
        ),
        (
            Statics::new().with(
                Cylinder::new([0.6, 3.0, 0.0], [0.6, 3.0, 1.0], 0.5).unwrap(),
                0,
            ),
            "cylinder 0",
        ),
        (
            Statics::new().with(
                Cylinder::new([3.0, 3.0, 0.0], [3.0, 3.1, 1.0], 0.5).unwrap(),
                0,
            ),
            "cylinder 0",
        ),
        (
            Statics::new().with(Container::new([3.0; 3], 3.5).unwrap(), 0),
            "container 0",
        ),
    ];
    for (statics, name) in refused {
        let err = Simulation::new(one(statics)).unwrap_err().to_string();
        assert!(
            err.starts_with(&format!(
                "{name} in a periodic box: the engine keeps no periodic images"
            )),
            "{err}"
        );
    }
}

/// Report-only (`Response::ReportOnly`): each static shape a sphere meets is reported once, at
/// the time worked out here, and the sphere goes on through it (it stalled the clock at the
/// first contact, reporting it again and again). A straight line meets a plane, an infinite
/// cylinder or a container's wall in one interval; after new velocities a shape is met again.
#[test]
fn report_only_reports_each_shape_met_once() {
    let ball = |centre: DVec3, velocity: DVec3| SphereState {
        centre,
        velocity,
        radius: 0.5,
        mass: 1.0,
        material: 0,
    };
    let world = World {
        // A: along +x through a pillar at x = 5 (radius 1), then out of the vessel (radius
        // 20); B: down onto a floor at z = −10, then out of the vessel; C: out of the vessel.
        spheres: vec![
            ball(DVec3::ZERO, DVec3::X),
            ball(DVec3::new(0.0, 0.0, -5.0), -DVec3::Z),
            ball(DVec3::new(0.0, 10.0, 0.0), DVec3::Y),
        ],
        statics: Statics::new()
            .with(Plane::new([0.0, 0.0, -10.0], [0.0, 0.0, 1.0]).unwrap(), 0)
            .with(
                Cylinder::new([5.0, 0.0, 0.0], [5.0, 0.0, 1.0], 1.0).unwrap(),
                0,
            )
            .with(Container::new([0.0; 3], 20.0).unwrap(), 0),
        effects: Effects {
            response: Response::ReportOnly,
            record_events: true,
            ..Effects::default()
        },
        ..World::default()
    };
    let mut sim = Simulation::new(world).unwrap();
    sim.advance_to(100.0).unwrap();
    let met: Vec<(f64, u32, Body)> = (sim.take_events().iter())
        .map(|e| (e.time, e.sphere, e.other))
        .collect();
    let shape = |kind| Body::new(kind, 0);
    let want = [
        (3.5, 0, shape(ShapeKind::Cylinder)),
        (4.5, 1, shape(ShapeKind::Plane)),
        (9.5, 2, shape(ShapeKind::Container)),
        (14.5, 1, shape(ShapeKind::Container)),
        (19.5, 0, shape(ShapeKind::Container)),
    ];
    assert_eq!(met.len(), want.len(), "{met:?}");
    for (got, want) in met.iter().zip(want) {
        assert!((got.0 - want.0).abs() < 1e-12 && (got.1, got.2) == (want.1, want.2));
    }
    // Turned round at x = 100, A comes back into the vessel (a container's contact is its
    // wall from inside), meets the pillar at x = 6.5 (t = 193.5) and the vessel's far wall at
    // x = −19.5 (t = 219.5); C, whose last shape was the vessel, meets its far wall at
    // y = −19.5 (t = 229.5): a shape met before is met again after new velocities.
    let v = sim
        .spheres()
        .iter()
        .map(|s| -s.velocity)
        .collect::<Vec<_>>();
    sim.set_velocities(&v).unwrap();
    sim.advance_to(250.0).unwrap();
    let again: Vec<(f64, u32, Body)> = (sim.take_events().iter())
        .filter(|e| e.sphere != 1)
        .map(|e| (e.time, e.sphere, e.other))
        .collect();
    let want = [
        (193.5, 0, ShapeKind::Cylinder),
        (219.5, 0, ShapeKind::Container),
        (229.5, 2, ShapeKind::Container),
    ];
    assert_eq!(again.len(), want.len(), "{again:?}");
    for (got, (t, sphere, kind)) in again.iter().zip(want) {
        let same = (got.0 - t).abs() < 1e-9 && (got.1, got.2) == (sphere, shape(kind));
        assert!(same, "{again:?}");
    }
}
