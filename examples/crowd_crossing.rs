//! A crowd crossing: four groups of pedestrians, one at each side of a square, walk through each
//! other to the opposite side. Agents are spheres of radius 0.2 m on the plane `z = 0`; every
//! step, the time to collision of every pair of neighbours comes from the batch kernel
//! ([`batch::pair_times`]) and steers them with the anticipatory power law of Karamouzas,
//! Skinner & Guy (2014, Phys. Rev. Lett. 113, 238701).
//!
//! ```sh
//! cargo run --release --example crowd_crossing          # 4 × 49 agents, 20 m crossings
//! cargo run --example crowd_crossing -- --small         # 4 × 9 agents, 12 m crossings (CI)
//! cargo run --example crowd_crossing -- --out DIR       # where crowd_crossing.svg goes
//! ```
//!
//! The model (derivation of the force: docs/derivations/crowd.md): two agents whose current
//! velocities would bring their surfaces together in `τ` seconds have the interaction energy
//! `E(τ) = k τ⁻² e^{−τ/τ₀}` (`k = 1.5`, `τ₀ = 3 s`), and each feels `F = −∇ₓ E`, the gradient
//! taken with respect to their relative position. The kernel's time is exactly this `τ`: the
//! time until the surfaces touch, at the contact distance `r_a + r_b = 0.4 m`. Each agent is
//! also pulled towards its goal by `(v_goal − v)/ξ` (`ξ = 0.5 s`, preferred speed 1.3 m/s
//! towards the goal). The total force is capped at 20 m/s² and the speed at 2 m/s (the model
//! is used with both caps; the values are this example's choice); explicit Euler with `dt = 0.02 s`. Neighbours are the
//! agents within 10 m (a uniform grid of 10 m cells); an agent within 0.5 m of its goal has
//! arrived and leaves the crossing.
//!
//! It prints the agents and steps, the smallest distance between two agents relative to `2r`,
//! how many reached their goals, and the mean travel time against the straight-line time, and
//! draws every path, coloured by group, with start and goal marks, into `crowd_crossing.svg`.
//!
//! What it checks (exit code 1 with the reason on failure):
//!
//! - every agent reaches its goal before the end time (60 s; 40 s with `--small`);
//! - no two agents overlap by more than one step's travel at the speed cap: the smallest centre
//!   distance over every step stays above `2r − 2 v_max dt` = 0.32 m = 0.8 × 2r (see
//!   [`OVERLAP_BOUND`]). Measured: no overlap at all at either size (closest 1.001 × 2r);
//!   without the avoidance force the blocks walk through each other and the check fails;
//! - the kernel's times are those of the model: for every pair whose time is finite the
//!   closed form `τ = (−b − √(b² − a c))/a` in f64 agrees within the `stable` mode's bound
//!   (see [`kernel_bound`]).

mod common;

use std::fmt::Write as _;
use std::time::Instant;

use common::{Args, check, write_atomic};
use glam::DVec2;
use spheresweep::rng::Rng;
use spheresweep::{Accuracy, QueryOptions, Sphere, SphereStore, batch};

/// Agent radius (m).
const RADIUS: f64 = 0.2;
/// Energy scale `k` (m²/s², per unit mass) and the interaction horizon `τ₀` (s).
const K: f64 = 1.5;
const TAU0: f64 = 3.0;
/// Relaxation time towards the goal velocity (s) and preferred speed (m/s).
const XI: f64 = 0.5;
const PREFERRED_SPEED: f64 = 1.3;
/// Caps on the force per unit mass (m/s²) and on the speed (m/s).
const MAX_FORCE: f64 = 20.0;
const MAX_SPEED: f64 = 2.0;
/// Time step (s).
const DT: f64 = 0.02;
/// Neighbours are the agents within this distance (m).
const SENSING: f64 = 10.0;
/// Times of collision beyond this are not asked for: the force factor `E′(τ)` at 12 s is
/// `4·10⁻⁵` of its value at 1 s, nothing that steers.
const HORIZON: f32 = 12.0;
/// An agent within this distance of its goal has arrived (m).
const ARRIVED: f64 = 0.5;
/// The deepest overlap the check allows (m): one step's travel of two agents approaching each
/// other at the speed cap, `2 v_max dt`. An anticipating pair starts to repel while still
/// apart (τ > 0) and a touching pair is pushed apart at the full cap, so a pair can only go
/// from touching to this deep if the avoidance did not act within a step; the model gives no
/// tighter guarantee under explicit Euler with capped forces, and the run shows none.
const OVERLAP_BOUND: f64 = 2.0 * MAX_SPEED * DT;
/// Every how many steps a path point is kept for the picture.
const PATH_EVERY: usize = 25;

/// One agent: where it is, how it moves, where it goes, and when it got there.
struct Agent {
    group: usize,
    position: DVec2,
    velocity: DVec2,
    start: DVec2,
    goal: DVec2,
    arrived: Option<f64>,
    path: Vec<DVec2>,
}

fn main() {
    if let Err(message) = run() {
        eprintln!("crowd_crossing: {message}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args = Args::parse("crowd_crossing")?;
    // Side of each group's square block, half the crossing distance, end time.
    let (side, half, t_end) = if args.small {
        (3, 6.0, 40.0)
    } else {
        (7, 10.0, 60.0)
    };
    let mut agents = four_groups(side, half);
    let n = agents.len();
    let straight_time = 2.0 * half / PREFERRED_SPEED;

    // The store the kernel reads: built once, updated in place every step (z = 0, vz = 0).
    let mut store = SphereStore::with_capacity(n);
    for a in &agents {
        let s = Sphere::new(planar(a.position), planar(a.velocity), RADIUS as f32, 1.0);
        store.push(&s.map_err(|e| e.to_string())?);
    }
    let options = QueryOptions::new(HORIZON, Accuracy::Stable).map_err(|e| e.to_string())?;

    let (mut pairs, mut times) = (Vec::<[u32; 2]>::new(), Vec::<f32>::new());
    let mut force = vec![DVec2::ZERO; n];
    let mut closest = f64::INFINITY; // smallest centre distance between two agents, any step
    let (mut steps, mut pairs_asked, mut kernel_seconds) = (0usize, 0usize, 0.0f64);
    let mut worst_kernel = 0.0f64; // largest |τ_kernel − τ_f64| / bound
    while steps as f64 * DT < t_end && agents.iter().any(|a| a.arrived.is_none()) {
        let now = steps as f64 * DT;
        for (i, a) in agents.iter().enumerate() {
            store
                .set_centre(i, planar(a.position))
                .and_then(|()| store.set_velocity(i, planar(a.velocity)))
                .map_err(|e| format!("agent {i} at t = {now:.2}: {e}"))?;
        }

        // Neighbour pairs of the agents still walking, and their times to collision.
        neighbour_pairs(&agents, &mut pairs);
        times.clear();
        times.resize(pairs.len(), 0.0);
        let clock = Instant::now();
        batch::pair_times(&store, &pairs, options, &mut times).map_err(|e| e.to_string())?;
        kernel_seconds += clock.elapsed().as_secs_f64();
        pairs_asked += pairs.len();

        // Goal forces, then every pair's avoidance force (equal and opposite).
        for (f, a) in force.iter_mut().zip(&agents) {
            let towards = (a.goal - a.position).normalize_or_zero();
            *f = (towards * PREFERRED_SPEED - a.velocity) / XI;
        }
        for (&[i, j], &tau) in pairs.iter().zip(&times) {
            let (i, j) = (i as usize, j as usize);
            let x = agents[i].position - agents[j].position;
            closest = closest.min(x.length());
            if !tau.is_finite() {
                continue;
            }
            let v = agents[i].velocity - agents[j].velocity;
            let closed = closed_form_tau(x, v);
            let (ai, aj) = (&agents[i], &agents[j]);
            let extent = ai.position.length() + aj.position.length();
            let speeds = ai.velocity.length() + aj.velocity.length();
            let bound = kernel_bound(x, v, extent, speeds, closed);
            worst_kernel = worst_kernel.max((f64::from(tau) - closed).abs() / bound);
            let f = avoidance(x, v, f64::from(tau));
            force[i] += f;
            force[j] -= f;
        }

        // Explicit Euler with the caps; arrivals leave the crossing.
        steps += 1;
        let later = steps as f64 * DT;
        for (a, f) in agents.iter_mut().zip(&force) {
            if a.arrived.is_some() {
                continue;
            }
            let old = a.velocity;
            a.velocity = (old + f.clamp_length_max(MAX_FORCE) * DT).clamp_length_max(MAX_SPEED);
            a.position += old * DT;
            if steps % PATH_EVERY == 0 {
                a.path.push(a.position);
            }
            if a.position.distance(a.goal) <= ARRIVED {
                a.arrived = Some(later);
                a.velocity = DVec2::ZERO;
                a.path.push(a.position);
            }
        }
    }

    // --- The summary. -----------------------------------------------------------------------
    let arrived: Vec<f64> = agents.iter().filter_map(|a| a.arrived).collect();
    let mean_travel = arrived.iter().sum::<f64>() / arrived.len().max(1) as f64;
    println!(
        "{n} agents in 4 groups, {steps} steps of {DT} s ({:.1} s simulated)",
        steps as f64 * DT
    );
    println!(
        "time to collision: {pairs_asked} neighbour pairs asked of the kernel in {:.1} ms",
        kernel_seconds * 1e3
    );
    println!(
        "closest two agents came: {:.4} m apart = {:.4} × 2r ({})",
        closest,
        closest / (2.0 * RADIUS),
        if closest >= 2.0 * RADIUS {
            "no overlap"
        } else {
            "overlapping"
        }
    );
    println!(
        "reached their goals: {} of {n}; mean travel time {mean_travel:.2} s against {straight_time:.2} s in a straight line at {PREFERRED_SPEED} m/s ({:.2}×)",
        arrived.len(),
        mean_travel / straight_time
    );
    println!("kernel times against the f64 closed form: worst {worst_kernel:.3} of the bound");

    check(arrived.len() == n, || {
        let late: Vec<usize> = (0..n).filter(|&i| agents[i].arrived.is_none()).collect();
        format!(
            "{} agents did not reach their goals by t = {t_end} s: {late:?}",
            late.len()
        )
    })?;
    check(closest >= 2.0 * RADIUS - OVERLAP_BOUND, || {
        format!(
            "two agents overlapped by {:.3} m: centres {closest:.3} m apart, 2r = {}, more than one step's travel at the speed cap ({OVERLAP_BOUND} m)",
            2.0 * RADIUS - closest,
            2.0 * RADIUS
        )
    })?;
    check(worst_kernel <= 1.0, || {
        format!("a kernel time differs from the closed form by {worst_kernel} of the stable bound")
    })?;

    let svg = picture(&agents, half + 0.6 * side as f64 + 1.0);
    let path = write_atomic(&args.out, "crowd_crossing.svg", &svg)?;
    println!("wrote {}", path.display());
    Ok(())
}

/// A 2-D vector as the store's 3-D one, on the plane z = 0.
fn planar(v: DVec2) -> [f32; 3] {
    [v.x as f32, v.y as f32, 0.0]
}

/// Four square blocks of `side × side` agents, 1.2 m apart with up to 0.2 m of jitter, centred
/// `half` from the centre on each side; each agent's goal is its start moved `2 half` straight
/// across, so the blocks cross through each other in the middle.
fn four_groups(side: usize, half: f64) -> Vec<Agent> {
    let mut rng = Rng::new(2014);
    let mut agents = Vec::new();
    for (group, towards) in [DVec2::X, DVec2::Y, DVec2::NEG_X, DVec2::NEG_Y]
        .into_iter()
        .enumerate()
    {
        let across = towards.perp();
        let centre = -towards * half;
        for k in 0..side * side {
            let (row, col) = ((k / side) as f64, (k % side) as f64);
            let mid = (side as f64 - 1.0) / 2.0;
            // Rows one behind the other along the walking direction, columns across it.
            let offset = (-towards * (row - mid) + across * (col - mid)) * 1.2;
            let jitter = DVec2::new(rng.range(-0.2, 0.2), rng.range(-0.2, 0.2));
            let start = centre + offset + jitter;
            agents.push(Agent {
                group,
                position: start,
                velocity: DVec2::ZERO,
                start,
                goal: start + towards * 2.0 * half,
                arrived: None,
                path: vec![start],
            });
        }
    }
    agents
}

/// The pairs of walking agents within [`SENSING`] of each other, from a uniform grid of cells
/// of that size: each agent is compared with the agents of its own and the eight surrounding
/// cells (each pair once).
fn neighbour_pairs(agents: &[Agent], pairs: &mut Vec<[u32; 2]>) {
    pairs.clear();
    let walking: Vec<usize> = (0..agents.len())
        .filter(|&i| agents[i].arrived.is_none())
        .collect();
    if walking.is_empty() {
        return;
    }
    let lo = walking
        .iter()
        .fold(DVec2::INFINITY, |m, &i| m.min(agents[i].position));
    let cell_of = |p: DVec2| ((p - lo) / SENSING).floor().as_ivec2();
    let cells = walking.iter().fold(glam::IVec2::ZERO, |m, &i| {
        m.max(cell_of(agents[i].position))
    }) + 1;
    let (cx, cy) = (cells.x as usize, cells.y as usize);
    // Counting sort of the agents by cell.
    let mut start = vec![0usize; cx * cy + 1];
    let index = |c: glam::IVec2| c.y as usize * cx + c.x as usize;
    for &i in &walking {
        start[index(cell_of(agents[i].position)) + 1] += 1;
    }
    for c in 0..cx * cy {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut sorted = vec![0usize; walking.len()];
    for &i in &walking {
        let c = index(cell_of(agents[i].position));
        sorted[fill[c]] = i;
        fill[c] += 1;
    }
    for &i in &walking {
        let c = cell_of(agents[i].position);
        for dy in -1..=1 {
            for dx in -1..=1 {
                let d = c + glam::IVec2::new(dx, dy);
                if d.x < 0 || d.y < 0 || d.x >= cells.x || d.y >= cells.y {
                    continue;
                }
                let k = index(d);
                for &j in &sorted[start[k]..start[k + 1]] {
                    if j > i && agents[i].position.distance(agents[j].position) <= SENSING {
                        pairs.push([i as u32, j as u32]);
                    }
                }
            }
        }
    }
}

/// The avoidance force on agent i (per unit mass) from agent j, with `x = x_i − x_j`,
/// `v = v_i − v_j` and `τ` their time to collision (surfaces touching):
///
/// `F = −(k e^{−τ/τ₀} / (a τ²)) (2/τ + 1/τ₀) [v − (a x − b v)/√(b² − a c)]`,
/// `a = |v|²`, `b = x·v`, `c = |x|² − (2r)²` (docs/derivations/crowd.md). Agent j feels `−F`.
/// Where the formula is singular — already touching (`τ = 0` or `c ≤ 0`) or grazing
/// (`b² − a c ≤ 0`) — the force takes its cap, pushing the two apart along `x`.
fn avoidance(x: DVec2, v: DVec2, tau: f64) -> DVec2 {
    let (a, b, c) = (
        v.length_squared(),
        x.dot(v),
        x.length_squared() - (2.0 * RADIUS).powi(2),
    );
    let disc = b * b - a * c;
    if tau <= 0.0 || c <= 0.0 {
        return x.normalize_or_zero() * MAX_FORCE;
    }
    if disc <= 0.0 || a == 0.0 {
        return DVec2::ZERO; // grazing: the gradient is unbounded but E's slope along it is not
    }
    let magnitude = K * (-tau / TAU0).exp() / (a * tau * tau) * (2.0 / tau + 1.0 / TAU0);
    let direction = v - (x * a - v * b) / disc.sqrt();
    let f = -direction * magnitude;
    if f.is_finite() {
        f
    } else {
        x.normalize_or_zero() * MAX_FORCE
    }
}

/// The time until the surfaces of two agents touch, in f64: the smaller root of
/// `|x + v t|² = (2r)²`, written `c / (−b + √(b² − a c))` so that it keeps its digits.
fn closed_form_tau(x: DVec2, v: DVec2) -> f64 {
    let (a, b, c) = (
        v.length_squared(),
        x.dot(v),
        x.length_squared() - (2.0 * RADIUS).powi(2),
    );
    let disc = (b * b - a * c).max(0.0);
    if c <= 0.0 {
        0.0
    } else {
        c / (-b + disc.sqrt())
    }
}

/// The bound on `|τ_kernel − τ|` for a pair with relative position `x` and velocity `v`, whose
/// centres lie `extent = |x_i| + |x_j|` from the origin together and whose speeds add to
/// `speeds`. The store holds the inputs rounded to f32 (relative `u = 2⁻²⁴`), which moves the
/// relative position by at most `√2 u·extent` and the relative velocity by `√2 u·speeds`; the
/// `stable` kernel is backward stable, its computed time the exact time of a pair moved by at
/// most `7u` of the coordinates and speeds it subtracts (docs/derivations/accuracy.md, "Where
/// the bodies are at the reported time"). So at the time `τ` the gap is off by at most
/// `δ = 9u (extent + speeds·τ)`, and the time by `δ` over the rate at which the gap closes at
/// contact, `√(b² − a c)/(2r)`; plus the final rounding of `τ` to f32, `u τ`. First order: it
/// grows without limit near grazing, where the time is ill conditioned for any method.
fn kernel_bound(x: DVec2, v: DVec2, extent: f64, speeds: f64, tau: f64) -> f64 {
    let u = f64::from(f32::EPSILON) / 2.0;
    let (a, b, c) = (
        v.length_squared(),
        x.dot(v),
        x.length_squared() - (2.0 * RADIUS).powi(2),
    );
    let closing = (b * b - a * c).max(0.0).sqrt() / (2.0 * RADIUS);
    let delta = 9.0 * u * (extent + speeds * tau);
    delta / closing.max(f64::MIN_POSITIVE) + u * tau
}

/// The crossing seen from above, `extent` metres each way from the centre: every path coloured
/// by group, a ring at each start and a cross at each goal.
fn picture(agents: &[Agent], extent: f64) -> String {
    let scale = 400.0 / extent; // pixels per metre
    let size = 2.0 * extent * scale;
    let p = |v: DVec2| ((v.x + extent) * scale, (extent - v.y) * scale + 30.0);
    let colours = ["#c0392b", "#2471a3", "#229954", "#b9770e"];
    let mut svg = String::new();
    let w = &mut svg;
    let _ = writeln!(
        w,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{size:.0}" height="{:.0}" viewBox="0 0 {size:.0} {:.0}" font-family="sans-serif" font-size="14">"#,
        size + 40.0,
        size + 40.0
    );
    let _ = writeln!(w, r##"<rect width="100%" height="100%" fill="#fdfdfb"/>"##);
    let _ = writeln!(
        w,
        r#"<text x="10" y="20">crowd crossing: {} agents (radius {RADIUS} m) in four groups, paths seen from above; ring: start, cross: goal</text>"#,
        agents.len()
    );
    for a in agents {
        let colour = colours[a.group % colours.len()];
        let points: Vec<String> = a
            .path
            .iter()
            .map(|&v| {
                let (x, y) = p(v);
                format!("{x:.0},{y:.0}")
            })
            .collect();
        let _ = writeln!(
            w,
            r#"<polyline points="{}" fill="none" stroke="{colour}" stroke-width="1.2" stroke-opacity="0.8"/>"#,
            points.join(" ")
        );
        let (sx, sy) = p(a.start);
        let _ = writeln!(
            w,
            r#"<circle cx="{sx:.1}" cy="{sy:.1}" r="{:.1}" fill="none" stroke="{colour}"/>"#,
            RADIUS * scale
        );
        let (gx, gy) = p(a.goal);
        let d = RADIUS * scale * 0.7;
        let _ = writeln!(
            w,
            r#"<path d="M{:.1},{:.1}L{:.1},{:.1}M{:.1},{:.1}L{:.1},{:.1}" stroke="{colour}" stroke-width="1.5"/>"#,
            gx - d,
            gy - d,
            gx + d,
            gy + d,
            gx - d,
            gy + d,
            gx + d,
            gy - d
        );
    }
    let _ = writeln!(
        w,
        r#"<text x="{:.1}" y="{:.1}">walking east: red, north: blue, west: green, south: orange</text>"#,
        size - 430.0,
        size + 25.0
    );
    // A 1-metre scale bar.
    let (bx, by) = (20.0, size + 20.0);
    let _ = writeln!(
        w,
        r#"<path d="M{bx:.1},{by:.1}h{scale:.1}" stroke="black" stroke-width="2"/><text x="{:.1}" y="{:.1}">1 m</text>"#,
        bx + scale + 6.0,
        by + 5.0
    );
    let _ = writeln!(w, "</svg>");
    svg
}
