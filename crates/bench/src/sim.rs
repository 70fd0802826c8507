//! Simulation workloads shared by the criterion bench (the root's `benches/simulation.rs`) and
//! `spheresweep bench --sim`: the hard-sphere gas of the peer's figures (FCC start, diameter 1,
//! mass 1, kT = 1, no thermostat), our rate measured over a set number of collisions, and the
//! peer (Smallenburg's EDMD "Single") run through `scripts/edmd_peer.sh` from a checkout the
//! user names (this project never downloads it).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use glam::DVec3;
use spheresweep::sim::{Effects, MaterialPair, Response, Simulation, Stats, World, generate};

/// The peer's gas: `n` spheres of diameter 1 on an FCC lattice at packing fraction `phi`.
///
/// ```
/// let world = spheresweep_bench::sim::gas(500, 0.25, 1);
/// assert_eq!(world.spheres.len(), 500);
/// assert!(world.spheres.iter().all(|s| s.radius == 0.5 && s.mass == 1.0));
/// ```
pub fn gas(n: usize, phi: f64, seed: u64) -> World {
    let mut w = World::default();
    generate::periodic_gas(&mut w, n, phi, 0.5, 1.0, seed).expect("valid gas");
    w
}

/// The same gas with effects declared that no sphere uses: a second material (no sphere has
/// it) that is sticky with itself and inelastic with the first, and a TC time. The engine
/// assembled for it must be the plain elastic one.
///
/// ```
/// use spheresweep::sim::Simulation;
/// use spheresweep_bench::sim::{gas, gas_with_unused_effects};
/// let plain = Simulation::new(gas(500, 0.25, 1)).unwrap();
/// let declared = Simulation::new(gas_with_unused_effects(500, 0.25, 1)).unwrap();
/// assert_eq!(declared.engine_name(), plain.engine_name()); // the elastic engine either way
/// ```
pub fn gas_with_unused_effects(n: usize, phi: f64, seed: u64) -> World {
    let mut w = gas(n, phi, seed);
    w.materials = vec!["gas".into(), "glue".into()];
    w.effects = Effects {
        pairs: vec![
            MaterialPair {
                a: 1,
                b: 1,
                response: Response::Sticky,
            },
            MaterialPair {
                a: 0,
                b: 1,
                response: Response::Inelastic { restitution: 0.5 },
            },
        ],
        tc: 1e-3,
        ..Effects::default()
    };
    w
}

/// Collisions per unit time of the gas from the Enskog theory with the Carnahan–Starling
/// contact value (diameter, mass and kT 1): `N/2 · 4 ρ g(σ) √π`.
///
/// ```
/// use spheresweep_bench::sim::enskog_collision_rate;
/// // Dilute limit: g → 1, so the rate per sphere is 2ρ√π with ρ = 6φ/π.
/// let phi: f64 = 1e-6;
/// let per_sphere = enskog_collision_rate(1, phi);
/// let dilute = 2.0 * 6.0 * phi / std::f64::consts::PI * std::f64::consts::PI.sqrt();
/// assert!((per_sphere / dilute - 1.0).abs() < 1e-5);
/// ```
pub fn enskog_collision_rate(n: usize, phi: f64) -> f64 {
    let rho = 6.0 * phi / std::f64::consts::PI;
    let g = (1.0 - phi / 2.0) / (1.0 - phi).powi(3);
    n as f64 / 2.0 * 4.0 * rho * g * std::f64::consts::PI.sqrt()
}

/// One measured run.
///
/// ```
/// use spheresweep_bench::sim::{gas, measure};
/// let rate = measure(gas(500, 0.25, 1), 5000);
/// assert!(rate.collisions > 2500 && rate.per_second() > 0.0 && rate.bytes > 0);
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Rate {
    /// Collisions processed.
    pub collisions: u64,
    /// Wall-clock seconds (setup excluded).
    pub seconds: f64,
    /// The engine's counters at the end.
    pub stats: Stats,
    /// Bytes the simulation held at the end (`Simulation::memory_bytes`).
    pub bytes: usize,
}

impl Rate {
    /// Collisions per second.
    ///
    /// ```
    /// use spheresweep_bench::sim::{gas, measure};
    /// let rate = measure(gas(256, 0.25, 1), 2000);
    /// assert_eq!(rate.per_second(), rate.collisions as f64 / rate.seconds);
    /// ```
    pub fn per_second(&self) -> f64 {
        self.collisions as f64 / self.seconds
    }
}

/// Runs `world` for about `collisions` collisions (from the Enskog rate) and times it; setup
/// (building the engine, the first predictions) is not timed, as the peer's is not.
///
/// ```
/// use spheresweep_bench::sim::{gas, measure};
/// let rate = measure(gas(500, 0.25, 1), 5000);
/// assert_eq!(rate.stats.pair_collisions, rate.collisions);
/// assert!(rate.collisions > 2500); // about 5000, from the Enskog rate
/// ```
pub fn measure(world: World, collisions: u64) -> Rate {
    let n = world.spheres.len();
    let phi = match world.boundary {
        spheresweep::sim::Boundary::Periodic { size } => {
            world
                .spheres
                .iter()
                .map(|s| 4.0 / 3.0 * std::f64::consts::PI * s.radius.powi(3))
                .sum::<f64>()
                / (size.x * size.y * size.z)
        }
        _ => 0.25,
    };
    let t_end = collisions as f64 / enskog_collision_rate(n, phi);
    let mut sim = Simulation::new(world).expect("valid world");
    let start = Instant::now();
    sim.advance_to(t_end).expect("no stall");
    let seconds = start.elapsed().as_secs_f64();
    let stats = *sim.stats();
    Rate {
        collisions: stats.pair_collisions,
        seconds,
        stats,
        bytes: sim.memory_bytes(),
    }
}

/// The peer's collisions per second at `n`, `phi` for about `collisions` collisions: builds and
/// runs `scripts/edmd_peer.sh EDMD_DIR N PHI auto` (gcc `-Ofast -march=native`), pinned to the
/// core this thread last ran on, where our own measurement just ran (the two cores of a shared
/// host can differ by 5 % or more). An error says why (no checkout, no gcc, a failed build).
///
/// ```
/// use std::path::Path;
/// use spheresweep_bench::sim::peer_rate;
/// let err = peer_rate(Path::new("/no/such/edmd"), 4000, 0.25, 1000).unwrap_err();
/// assert!(err.contains("failed")); // no checkout there: the script says so
/// ```
pub fn peer_rate(edmd_dir: &Path, n: usize, phi: f64, collisions: u64) -> Result<f64, String> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/edmd_peer.sh");
    let out = Command::new("bash")
        .arg(&script)
        .arg(edmd_dir)
        .arg(n.to_string())
        .arg(phi.to_string())
        .arg("auto")
        .env("EDMD_COLLISIONS", collisions.to_string())
        .envs(current_cpu().map(|cpu| ("EDMD_CPU", cpu.to_string())))
        .output()
        .map_err(|e| format!("cannot run {}: {e}", script.display()))?;
    if !out.status.success() {
        return Err(format!(
            "{} failed: {}",
            script.display(),
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("")
        ));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    text.split_whitespace()
        .nth(2)
        .and_then(|r| r.parse().ok())
        .ok_or_else(|| format!("unexpected peer output: {text:?}"))
}

/// The core this thread last ran on (Linux: field 39 of `/proc/thread-self/stat`), if known.
///
/// ```
/// if let Some(cpu) = spheresweep_bench::sim::current_cpu() {
///     assert!(cpu < 4096); // one of this machine's cores
/// }
/// ```
pub fn current_cpu() -> Option<usize> {
    let stat = std::fs::read_to_string("/proc/thread-self/stat").ok()?;
    // The command name (field 2) is in parentheses and may hold spaces: count after it.
    let rest = &stat[stat.rfind(')')? + 1..];
    rest.split_whitespace().nth(39 - 3)?.parse().ok()
}

/// Peak resident memory of this process in bytes (Linux `VmHWM`), if known.
///
/// ```
/// if let Some(bytes) = spheresweep_bench::sim::peak_resident_bytes() {
///     assert!(bytes > 0); // Linux: this process's VmHWM
/// }
/// ```
pub fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Random falling spheres (centre, velocity, gravity) against one shape of each kind, for the
/// cost of a contact under gravity: inside a vessel of radius 5, around a horizontal pillar of
/// radius 0.7, over a floor; speeds 10⁻²–10², gravity 10⁻¹–10¹ in random directions.
///
/// ```
/// let cases = spheresweep_bench::sim::falling_cases(16, 1);
/// assert_eq!(cases.len(), 3);
/// for (_, shape, spheres) in &cases {
///     assert_eq!(spheres.len(), 16);
///     assert!(spheres.iter().all(|&(r, _, _)| shape.normal_gap(r, 0.5).1 >= 0.0));
/// }
/// ```
#[allow(clippy::type_complexity)]
pub fn falling_cases(
    n: usize,
    seed: u64,
) -> Vec<(
    &'static str,
    spheresweep::Static,
    Vec<(DVec3, DVec3, DVec3)>,
)> {
    use spheresweep::{Container, Cylinder, Plane, Static};
    let mut rng = spheresweep::rng::Rng::new(seed);
    let shapes = [
        (
            "container",
            Static::Container(Container::new([0.0; 3], 5.0).expect("valid")),
        ),
        (
            "cylinder",
            Static::Cylinder(Cylinder::new([0.0; 3], [0.0, 1.0, 0.0], 0.7).expect("valid")),
        ),
        (
            "plane",
            Static::Plane(Plane::new([0.0; 3], [0.0, 0.0, 1.0]).expect("valid")),
        ),
    ];
    shapes
        .into_iter()
        .map(|(name, shape)| {
            let mut cases = Vec::with_capacity(n);
            while cases.len() < n {
                let r = rng.direction() * 4.4 * rng.unit() + DVec3::new(0.0, 0.0, 0.5);
                if shape.normal_gap(r, 0.5).1 < 0.0 {
                    continue;
                }
                let v = rng.direction() * 10f64.powf(4.0 * rng.unit() - 2.0);
                let g = rng.direction() * 10f64.powf(2.0 * rng.unit() - 1.0);
                cases.push((r, v, g));
            }
            (name, shape, cases)
        })
        .collect()
}

/// An elastic gas of `n` spheres of radius 0.2 in a closed box of six planes (10 × 10 × 8),
/// under `gravity` (zero: none): the same scene with and without gravity.
///
/// ```
/// use glam::DVec3;
/// let world = spheresweep_bench::sim::box_gas(50, DVec3::new(0.0, 0.0, -1.0), 1);
/// assert_eq!((world.spheres.len(), world.statics.len()), (50, 6));
/// ```
pub fn box_gas(n: usize, gravity: DVec3, seed: u64) -> World {
    use spheresweep::{Plane, Statics};
    let (half, height, r) = (5.0f32, 8.0f32, 0.2);
    let inside = |p: DVec3| {
        p.x.abs() < f64::from(half) - r
            && p.y.abs() < f64::from(half) - r
            && p.z > r
            && p.z < f64::from(height) - r
    };
    let mut spheres = generate::random_spheres(
        DVec3::new(-f64::from(half), -f64::from(half), 0.0),
        DVec3::new(f64::from(half), f64::from(half), f64::from(height)),
        &inside,
        n,
        r,
        1.0,
        0,
        seed,
    )
    .expect("room for the gas");
    generate::thermal_velocities(&mut spheres, 1.0, seed + 1);
    let mut statics = Statics::new();
    for (p, normal) in [
        ([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        ([0.0, 0.0, height], [0.0, 0.0, -1.0]),
        ([-half, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ([half, 0.0, 0.0], [-1.0, 0.0, 0.0]),
        ([0.0, -half, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, half, 0.0], [0.0, -1.0, 0.0]),
    ] {
        statics.push(Plane::new(p, normal).expect("valid"), 0);
    }
    World {
        spheres,
        statics,
        effects: Effects {
            gravity,
            ..Effects::default()
        },
        ..World::default()
    }
}

/// Wall-clock time for `events` events (pair and wall collisions) of a fresh simulation of
/// `world`, after a first stretch of as many events that is not timed.
pub fn time_events(world: &World, events: u64) -> std::time::Duration {
    let mut s = Simulation::new(world.clone()).expect("valid world");
    let count = |s: &Simulation| s.stats().pair_collisions + s.stats().wall_collisions;
    let mut t = 0.0;
    while count(&s) < events {
        t += 1.0;
        s.advance_to(t).expect("no stall");
    }
    let (start, first) = (Instant::now(), count(&s));
    while count(&s) < first + events {
        t += 1.0;
        s.advance_to(t).expect("no stall");
    }
    start
        .elapsed()
        .mul_f64(events as f64 / (count(&s) - first) as f64)
}
