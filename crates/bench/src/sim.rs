//! Simulation workloads shared by the criterion bench (`benches/simulation.rs`) and
//! `spheresweep bench --sim`: the hard-sphere gas of the peer's figures (FCC start, diameter 1,
//! mass 1, kT = 1, no thermostat), our rate measured over a set number of collisions, and the
//! peer (Smallenburg's EDMD "Single") run through `scripts/edmd_peer.sh` from a checkout the
//! user names (this project never downloads it).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use spheresweep::sim::{Effects, MaterialPair, Response, Simulation, Stats, World, generate};

/// The peer's gas: `n` spheres of diameter 1 on an FCC lattice at packing fraction `phi`.
pub fn gas(n: usize, phi: f64, seed: u64) -> World {
    let mut w = World::default();
    generate::periodic_gas(&mut w, n, phi, 0.5, 1.0, seed).expect("valid gas");
    w
}

/// The same gas with effects declared that no sphere uses: a second material (no sphere has
/// it) that is sticky with itself and inelastic with the first, and a TC time. The engine
/// assembled for it must be the plain elastic one.
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
pub fn enskog_collision_rate(n: usize, phi: f64) -> f64 {
    let rho = 6.0 * phi / std::f64::consts::PI;
    let g = (1.0 - phi / 2.0) / (1.0 - phi).powi(3);
    n as f64 / 2.0 * 4.0 * rho * g * std::f64::consts::PI.sqrt()
}

/// One measured run.
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
    pub fn per_second(&self) -> f64 {
        self.collisions as f64 / self.seconds
    }
}

/// Runs `world` for about `collisions` collisions (from the Enskog rate) and times it; setup
/// (building the engine, the first predictions) is not timed, as the peer's is not.
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
/// runs `scripts/edmd_peer.sh EDMD_DIR N PHI auto` (gcc `-Ofast -march=native`, pinned to one
/// core). An error says why (no checkout, no gcc, a failed build).
pub fn peer_rate(edmd_dir: &Path, n: usize, phi: f64, collisions: u64) -> Result<f64, String> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/edmd_peer.sh");
    let out = Command::new("bash")
        .arg(&script)
        .arg(edmd_dir)
        .arg(n.to_string())
        .arg(phi.to_string())
        .arg("auto")
        .env("EDMD_COLLISIONS", collisions.to_string())
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

/// Peak resident memory of this process in bytes (Linux `VmHWM`), if known.
pub fn peak_resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
