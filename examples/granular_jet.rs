//! A granular jet: nine streams of grains fired straight down at a floor under gravity, with
//! four steel pillars around the point of impact, every collision inelastic, simulated event by
//! event with [`sim::Simulation`]. The same scene as `scenes/granular_jet.toml`, built in code.
//!
//! ```sh
//! cargo run --release --example granular_jet            # 9 × 400 grains for 10 s (as the scene file)
//! cargo run --example granular_jet -- --small           # 9 × 40 grains for 4 s (CI)
//! cargo run --example granular_jet -- --out DIR         # where granular_jet.svg goes
//! ```
//!
//! How the world is built: `generate::nozzle` for each stream (grains of radius 0.25, 0.6 apart,
//! speed 5, tilted at random by up to 0.05 rad), a [`Plane`] for the floor and four vertical
//! [`Cylinder`]s, three materials, and the effects: restitution 0.8 between grains, 0.6 against
//! the floor and 0.9 against the pillars, with the TC model (`tc = 10⁻³`) so that a dense pile
//! cannot collapse inelastically, and gravity `g = −9.81 ẑ`: grains bounce off the floor, splash
//! sideways into the pillars and fall back into a heap that settles. Events are recorded with
//! their contact geometry.
//!
//! It prints collisions by kind, the energy the collisions took and collisions per second of
//! wall-clock time, and draws the end state from the side with the paths of eight grains into
//! `granular_jet.svg`.
//!
//! What it checks (exit code 1 with the reason on failure):
//!
//! - **energy**: the initial kinetic plus potential energy (`Σ m g z`) minus the final one
//!   equals the energy the engine says its collisions took (`Stats::energy_lost`), within a
//!   rounding bound derived below;
//! - **momentum**: grain–grain collisions conserve it, so the total momentum changes by exactly
//!   gravity's `M g t` plus the wall impulses `m (u + w) n̂` of the recorded floor and pillar
//!   events (`u` the approach speed, `w` the speed it left with, from the energy the event took:
//!   `½ m (u² − w²)`), within a rounding bound derived below;
//! - **no grain passes through the floor or a pillar**: every grain's path, rebuilt piece by
//!   piece from its positions at each frame and at each of its recorded collisions, keeps its
//!   surface outside the floor and every pillar, to the engine's overlap tolerance. Between
//!   two points the path is a parabola that lies above the straight chord (gravity is
//!   downwards) and whose horizontal part is the chord's (the pillars are vertical), so the
//!   chord is checked: it goes at least as deep as the path.

mod common;

use std::fmt::Write as _;
use std::time::Instant;

use common::{Args, check, write_atomic};
use glam::DVec3;
use spheresweep::sim::{
    Boundary, Effects, EventRecord, MaterialPair, OVERLAP_TOLERANCE, Response, Simulation, World,
    generate,
};
use spheresweep::{Cylinder, Plane, ShapeKind, Statics};

const GRAIN_RADIUS: f64 = 0.25;
/// Gravity, down the z axis.
const GRAVITY: DVec3 = DVec3::new(0.0, 0.0, -9.81);
const SPACING: f64 = 0.6;
const SPEED: f64 = 5.0;
/// The nozzles' height above the floor (the floor is the plane z = 0).
const NOZZLE_HEIGHT: f64 = 10.0;
/// The pillars: vertical axes through these (x, y), radius 0.8.
const PILLARS: [(f64, f64); 4] = [(4.0, 0.0), (-4.0, 0.0), (0.0, 4.0), (0.0, -4.0)];
const PILLAR_RADIUS: f64 = 0.8;
/// Frames at which the positions are read and the paths checked.
const FRAME: f64 = 0.05;
/// Materials.
const GRAIN: u16 = 0;
const FLOOR: u16 = 1;
const STEEL: u16 = 2;

fn main() {
    if let Err(message) = run() {
        eprintln!("granular_jet: {message}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args = Args::parse("granular_jet")?;
    let (per_nozzle, t_end) = if args.small { (40, 4.0) } else { (400, 10.0) };
    let world = jet_world(per_nozzle)?;
    let n = world.spheres.len();
    let masses: Vec<f64> = world.spheres.iter().map(|s| s.mass).collect();
    let radii: Vec<f64> = world.spheres.iter().map(|s| s.radius).collect();

    let mut sim = Simulation::new(world).map_err(|e| e.to_string())?;
    println!("{n} grains in 9 streams, engine: {}", sim.engine_name());
    let (e0, p0) = (
        sim.kinetic_energy() + sim.potential_energy(),
        sim.momentum(),
    );
    let total_mass: f64 = masses.iter().sum();

    // Eight grains whose paths are drawn: the first, middle and last of a few streams.
    let tracked: Vec<usize> = [
        (4, 0),
        (4, per_nozzle / 2),
        (4, per_nozzle - 1),
        (0, 0),
        (8, 3),
        (2, per_nozzle / 3),
        (6, per_nozzle / 4),
        (1, 1),
    ]
    .iter()
    .map(|&(nozzle, k)| nozzle * per_nozzle + k)
    .collect();
    let mut paths: Vec<Vec<DVec3>> = tracked.iter().map(|_| Vec::new()).collect();

    let mut wall_impulse = DVec3::ZERO;
    let (mut grain_grain, mut grain_floor, mut grain_pillar) = (0u64, 0u64, 0u64);
    let mut deepest = 0.0f64; // deepest penetration of a path into the floor or a pillar
    let mut before = sim.spheres();
    for (i, &k) in tracked.iter().enumerate() {
        paths[i].push(before[k].centre);
    }
    // Each grain's known points in the current frame: (time, centre).
    let mut points: Vec<Vec<(f64, DVec3)>> = vec![Vec::new(); n];
    let clock = Instant::now();
    let frames = (t_end / FRAME).round() as usize;
    for f in 1..=frames {
        let (t0, t1) = (sim.time(), f as f64 * FRAME);
        sim.advance_to(t1).map_err(|e| e.to_string())?;
        let after = sim.spheres();
        let events = sim.take_events();
        for (s, list) in points.iter_mut().enumerate() {
            list.clear();
            list.push((t0, before[s].centre));
        }
        for e in &events {
            let (a, centre_a, normal) = event_centre(e, &radii)?;
            points[a].push((e.time, centre_a));
            match e.other.kind {
                ShapeKind::Sphere => {
                    grain_grain += 1;
                    // The partner's centre: a contact distance from a's, along the normal.
                    let b = e.other.index as usize;
                    points[b].push((e.time, centre_a - normal * (radii[a] + radii[b])));
                }
                kind => {
                    if kind == ShapeKind::Plane {
                        grain_floor += 1;
                    } else {
                        grain_pillar += 1;
                    }
                    check(e.approach > 0.0, || {
                        format!(
                            "grain {a} at t = {}: a wall event that was not approaching ({})",
                            e.time, e.approach
                        )
                    })?;
                    // The speed it left with, from the energy the event took (a rest hop
                    // gives some back: `energy_lost` is then below ½ m u² (1 − e²)).
                    let (m, u) = (masses[a], e.approach);
                    let w = (u * u - 2.0 * e.energy_lost / m).max(0.0).sqrt();
                    wall_impulse += normal * (m * (u + w));
                }
            }
        }
        for (s, list) in points.iter_mut().enumerate() {
            list.push((t1, after[s].centre));
            for w in list.windows(2) {
                deepest = deepest.max(penetration(w[0].1, w[1].1, radii[s]));
            }
        }
        for (i, &k) in tracked.iter().enumerate() {
            paths[i].extend(points[k].iter().skip(1).map(|p| p.1));
        }
        before = after;
    }
    let seconds = clock.elapsed().as_secs_f64();
    let stats = *sim.stats();
    let (e1, p1) = (
        sim.kinetic_energy() + sim.potential_energy(),
        sim.momentum(),
    );
    let gravity_impulse = GRAVITY * (total_mass * sim.time());

    // --- The summary. ---------------------------------------------------------------------
    let collisions = stats.pair_collisions + stats.wall_collisions;
    println!(
        "t = {t_end} s: {collisions} collisions ({grain_grain} grain–grain, {grain_floor} grain–floor, {grain_pillar} grain–pillar) in {seconds:.2} s of wall-clock time (with this example's checks), {:.0} collisions/s",
        collisions as f64 / seconds
    );
    println!(
        "energy: {e0:.3} at the start, {e1:.3} at the end; the collisions took {:.3} ({:.1} %)",
        stats.energy_lost,
        100.0 * stats.energy_lost / e0
    );
    println!(
        "momentum: {:.3} → {:.3}; the floor and pillars gave {:.3}, gravity {:.3}",
        p0, p1, wall_impulse, gravity_impulse
    );
    println!(
        "kernels run: {} sphere lanes, {} plane, {} cylinder; deepest overlap at a collision {:.1e} of the contact distance",
        stats.kernels.sphere, stats.kernels.plane, stats.kernels.cylinder, stats.max_overlap
    );
    check(
        grain_grain == stats.pair_collisions && grain_floor + grain_pillar == stats.wall_collisions,
        || {
            format!(
                "the event log ({grain_grain} pair, {} wall) and the stats ({stats:?}) differ",
                grain_floor + grain_pillar
            )
        },
    )?;
    check(
        grain_floor > 0 && grain_pillar > 0 && grain_grain > 0,
        || "the jet should hit the floor, the pillars and itself".into(),
    )?;

    // --- Energy: e0 − e1 = energy_lost (E = K + U, U = Σ m g z ≥ 0 above the floor). ----------
    // Each collision updates one or two velocities v' = v + Δv in f64, and each shell event
    // moves a grain along its parabola; each component of v', of Δv = n̂ (1 + e) u / m and of the
    // moved centre is rounded a few times (n̂ is unit to a few u), so each update changes
    // ½ m |v|² + m g z by its exact amount within 32 u E₀ (no grain ever holds more than the
    // total energy E₀: collisions only take energy but for rest hops, which the balance counts,
    // and the grazing guard adds at most 2⁻⁴⁰ of a pair's energy, only in guarded collisions).
    // The sums over n grains add n u E₀. u = 2⁻⁵³.
    let u = f64::EPSILON / 2.0;
    let updates = (2 * stats.pair_collisions + stats.wall_collisions + stats.crossings) as f64;
    let energy_bound =
        u * e0 * (32.0 * updates + 2.0 * n as f64) + stats.guarded as f64 * e0 / 2f64.powi(40);
    let energy_gap = (e0 - e1 - stats.energy_lost).abs();
    println!("energy balance: |E0 − E1 − lost| = {energy_gap:.2e} (bound {energy_bound:.2e})");
    check(energy_gap <= energy_bound, || {
        format!(
            "E0 − E1 = {} but the collisions took {}: off by {energy_gap:e}, more than the bound {energy_bound:e}",
            e0 - e1,
            stats.energy_lost
        )
    })?;
    check(stats.energy_lost > 0.0, || {
        "inelastic collisions took no energy".into()
    })?;

    // --- Momentum: p1 − p0 = M g t + Σ wall impulses. ---------------------------------------
    // Each velocity update moves m v by its exact impulse within 8 u m (|v'| + |Δv|) ≤
    // 24 u √(2 m E₀) per component (|v| ≤ √(2 E₀/m)); the wall impulses summed here add as much
    // again (their `w` from a difference of squares: within 4 u u²/w of it, and w ≥ e u), and
    // the sums over n grains n u √(2 m E₀).
    let m_max = masses.iter().copied().fold(0.0, f64::max);
    let scale = (2.0 * m_max * e0).sqrt();
    let momentum_bound = u * scale * (48.0 * updates + 2.0 * n as f64);
    let momentum_gap = (p1 - p0 - wall_impulse - gravity_impulse)
        .abs()
        .max_element();
    println!(
        "momentum balance: |P1 − P0 − M g t − Σ wall impulses| = {momentum_gap:.2e} (bound {momentum_bound:.2e})"
    );
    check(momentum_gap <= momentum_bound, || {
        format!(
            "the momentum changed by {:?} but the walls gave {wall_impulse:?}: off by {momentum_gap:e}, bound {momentum_bound:e}",
            p1 - p0
        )
    })?;

    // --- No grain through the floor or a pillar. ------------------------------------------------
    // The engine resolves a wall contact before the overlap exceeds OVERLAP_TOLERANCE of the
    // radius; a partner's centre at a pair event is placed a contact distance away, which is
    // right to OVERLAP_TOLERANCE of that distance; f64 positions of size 50 round by 10⁻¹³.
    let path_bound = OVERLAP_TOLERANCE * 3.0 * GRAIN_RADIUS + 1e-12;
    println!(
        "deepest any grain's path goes into the floor or a pillar: {deepest:.2e} (bound {path_bound:.2e})"
    );
    check(deepest <= path_bound, || {
        format!("a grain's path goes {deepest:e} into the floor or a pillar (bound {path_bound:e})")
    })?;

    let svg = side_view(&sim, &paths, t_end);
    let path = write_atomic(&args.out, "granular_jet.svg", &svg)?;
    println!("wrote {}", path.display());
    Ok(())
}

/// The scene: nine nozzles on a 3 × 3 grid 0.6 apart, `per_nozzle` grains each, above a floor
/// with four pillars.
fn jet_world(per_nozzle: usize) -> Result<World, String> {
    let inelastic = |restitution| Response::Inelastic { restitution };
    let mut world = World {
        materials: ["grain", "floor", "steel"].map(String::from).to_vec(),
        statics: Statics::new().with(
            Plane::new([0.0; 3], [0.0, 0.0, 1.0]).map_err(|e| e.to_string())?,
            FLOOR,
        ),
        effects: Effects {
            response: inelastic(0.8),
            pairs: vec![
                MaterialPair {
                    a: GRAIN,
                    b: FLOOR,
                    response: inelastic(0.6),
                },
                MaterialPair {
                    a: GRAIN,
                    b: STEEL,
                    response: inelastic(0.9),
                },
            ],
            tc: 1e-3,
            geometry: true,
            record_events: true,
            gravity: GRAVITY,
        },
        ..World::default()
    };
    for &(x, y) in &PILLARS {
        let (x, y, r) = (x as f32, y as f32, PILLAR_RADIUS as f32);
        let shape = Cylinder::new([x, y, 0.0], [x, y, 1.0], r).map_err(|e| e.to_string())?;
        world.statics.push(shape, STEEL);
    }
    let mut seed = 11;
    for i in -1..=1 {
        for j in -1..=1 {
            let origin = DVec3::new(
                SPACING * f64::from(i),
                SPACING * f64::from(j),
                NOZZLE_HEIGHT,
            );
            let stream = generate::nozzle(
                origin,
                DVec3::NEG_Z,
                per_nozzle,
                GRAIN_RADIUS,
                SPEED,
                SPACING,
                0.05,
                0.0,
                GRAIN,
                seed,
            )
            .map_err(|e| e.to_string())?;
            world.spheres.extend(stream);
            seed += 1;
        }
    }
    // The cell grid covers the region the jet and its splash reach.
    let top = NOZZLE_HEIGHT + SPACING * per_nozzle as f64 + 1.0;
    world.boundary = Boundary::OpenBox {
        lo: DVec3::new(-40.0, -40.0, -1.0),
        hi: DVec3::new(40.0, 40.0, top),
    };
    Ok(world)
}

/// The sphere of an event, its centre at the event and the event's normal (pushing it away from
/// the other body): the contact point is a radius from the centre, against the normal.
fn event_centre(e: &EventRecord, radii: &[f64]) -> Result<(usize, DVec3, DVec3), String> {
    let g = e
        .geometry
        .ok_or_else(|| format!("event at t = {}: no contact geometry recorded", e.time))?;
    let a = e.sphere as usize;
    Ok((a, g.point + g.normal * radii[a], g.normal))
}

/// How deep a grain of radius `r` moving straight from `a` to `b` goes into the floor (z = 0)
/// or a pillar at its deepest (zero or negative if it stays clear).
fn penetration(a: DVec3, b: DVec3, r: f64) -> f64 {
    // The height is linear along the segment: its lowest point is an end.
    let mut deepest = r - a.z.min(b.z);
    for &(x, y) in &PILLARS {
        // The distance from the vertical axis is the length of a 2-D point moving linearly:
        // smallest where d/ds |p + s d|² = 0, clamped to the segment.
        let p = a.truncate() - glam::DVec2::new(x, y);
        let d = (b - a).truncate();
        let s = if d.length_squared() > 0.0 {
            (-p.dot(d) / d.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        deepest = deepest.max(PILLAR_RADIUS + r - (p + d * s).length());
    }
    deepest
}

/// The end state seen from the side (x across, z up): the floor, the pillars as bands, every
/// grain in the view as a disc, and the tracked grains' paths.
fn side_view(sim: &Simulation, paths: &[Vec<DVec3>], t_end: f64) -> String {
    let (x_lo, x_hi, z_lo, z_hi) = (-14.0, 14.0, -1.0, 16.0);
    let scale = 32.0; // pixels per unit
    let (width, height) = ((x_hi - x_lo) * scale, (z_hi - z_lo) * scale + 40.0);
    let px = |x: f64| (x - x_lo) * scale;
    let pz = |z: f64| (z_hi - z) * scale + 30.0;
    let mut svg = String::new();
    let w = &mut svg;
    let _ = writeln!(
        w,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="sans-serif" font-size="14">"#
    );
    let _ = writeln!(w, r##"<rect width="100%" height="100%" fill="#fbfbf8"/>"##);
    let _ = writeln!(
        w,
        r#"<text x="10" y="20">granular jet at t = {t_end} s, seen from the side (x across, z up); pillars grey, paths of eight grains</text>"#
    );
    // Pillars: those at y = 0 as bands at their x; those at x = 0 as one band at x = 0.
    for &(x, _) in &PILLARS {
        let _ = writeln!(
            w,
            r##"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" fill="#9aa7b1" fill-opacity="0.45"/>"##,
            px(x - PILLAR_RADIUS),
            pz(z_hi),
            2.0 * PILLAR_RADIUS * scale,
            pz(0.0) - pz(z_hi)
        );
    }
    let _ = writeln!(
        w,
        r##"<rect x="0" y="{:.1}" width="{width:.0}" height="{:.1}" fill="#6b5b4b"/>"##,
        pz(0.0),
        pz(z_lo) - pz(0.0)
    );
    for s in sim.spheres() {
        let (x, z) = (s.centre.x, s.centre.z);
        if (x_lo..=x_hi).contains(&x) && (z_lo..=z_hi).contains(&z) {
            let _ = writeln!(
                w,
                r##"<circle cx="{:.1}" cy="{:.1}" r="{:.1}" fill="#d9a441" fill-opacity="0.7" stroke="#8a6420" stroke-width="0.5"/>"##,
                px(x),
                pz(z),
                s.radius * scale
            );
        }
    }
    let colours = [
        "#c0392b", "#2471a3", "#229954", "#7d3c98", "#d35400", "#17a589", "#b7950b", "#34495e",
    ];
    for (path, colour) in paths.iter().zip(colours.iter().cycle()) {
        let points: Vec<String> = path
            .iter()
            .map(|p| format!("{:.1},{:.1}", px(p.x), pz(p.z)))
            .collect();
        let _ = writeln!(
            w,
            r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="1.6"/>"#,
            points.join(" ")
        );
        if let Some(end) = path.last() {
            let _ = writeln!(
                w,
                r#"<circle cx="{:.1}" cy="{:.1}" r="4" fill="{colour}"/>"#,
                px(end.x),
                pz(end.z)
            );
        }
    }
    let _ = writeln!(w, "</svg>");
    svg
}
