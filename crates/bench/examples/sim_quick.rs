use spheresweep::sim::{Simulation, World, generate};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).map_or(4000, |s| s.parse().unwrap());
    let phi: f64 = args.get(2).map_or(0.25, |s| s.parse().unwrap());
    let t: f64 = args.get(3).map_or(20.0, |s| s.parse().unwrap());
    let mut w = World::default();
    generate::periodic_gas(&mut w, n, phi, 0.5, 1.0, 1).unwrap();
    let mut sim = Simulation::new(w).unwrap();
    let e0 = sim.kinetic_energy();
    let start = std::time::Instant::now();
    sim.advance_to(t).unwrap();
    let dt = start.elapsed().as_secs_f64();
    let s = sim.stats();
    println!(
        "{} coll={} cross={} stale={} pred={} lanes={} {:.0} coll/s dE/E={:e} maxov={:e} P={:?}",
        sim.engine_name(),
        s.pair_collisions,
        s.crossings,
        s.stale,
        s.predictions,
        s.kernels.sphere,
        s.pair_collisions as f64 / dt,
        (sim.kinetic_energy() - e0) / e0,
        s.max_overlap,
        sim.momentum()
    );
}
