//! One run of the hard-sphere gas from an FCC start, with the engine's counters: for profiling
//! (perf, callgrind) and quick checks.
//!
//! `cargo run --release -p spheresweep-bench --example sim_rate -- N PHI T` (defaults 4000,
//! 0.25, 20): prints the engine, collisions per second, counters per collision, bytes per
//! sphere, energy drift and the largest overlap seen.

use spheresweep::sim::{Simulation, World, generate};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |k: usize, default: f64| args.get(k).and_then(|s| s.parse().ok()).unwrap_or(default);
    let (n, phi, t) = (arg(1, 4000.0) as usize, arg(2, 0.25), arg(3, 20.0));
    let mut w = World::default();
    if let Err(e) = generate::periodic_gas(&mut w, n, phi, 0.5, 1.0, 1) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
    let mut sim = Simulation::new(w).expect("a generated gas is valid");
    let e0 = sim.kinetic_energy();
    let start = std::time::Instant::now();
    sim.advance_to(t).expect("an elastic gas never stalls");
    let seconds = start.elapsed().as_secs_f64();
    let s = sim.stats();
    let per = |x: u64| x as f64 / s.pair_collisions.max(1) as f64;
    println!(
        "{}: {} collisions, {:.0} per second; per collision {:.2} predictions, {:.2} shell events, {:.2} stale, {:.1} pairs answered; {} bytes per sphere; energy drift {:.1e}; largest overlap {:.1e}",
        sim.engine_name(),
        s.pair_collisions,
        s.pair_collisions as f64 / seconds,
        per(s.predictions),
        per(s.crossings),
        per(s.stale),
        per(s.kernels.sphere),
        sim.memory_bytes() / n.max(1),
        (sim.kinetic_energy() - e0) / e0,
        s.max_overlap
    );
}
