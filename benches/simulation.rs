//! The event-driven engine on the hard-sphere gas of the peer's figures (FCC start, diameter,
//! mass and kT 1, no thermostat): time per collision at N = 4000, φ = 0.1 … 0.4 and at larger
//! N; and the same spheres with effects declared that they never use (the same engine must run
//! at the same cost). The peer (Smallenburg's EDMD, a C program) runs beside ours in
//! `spheresweep bench --sim --edmd DIR`, which reports the ratios; results: docs/benchmarks.md.

use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use spheresweep::sim::{Simulation, World};
use spheresweep_bench::sim;

/// Time for `collisions` collisions, run as `iters` back-to-back stretches of one simulation
/// (each sample a fresh gas; its set-up and its first two collisions per sphere, which leave the
/// lattice, not timed).
fn time_collisions(world: &World, n: usize, phi: f64, collisions: u64, iters: u64) -> Duration {
    let mut s = Simulation::new(world.clone()).expect("valid gas");
    let rate = sim::enskog_collision_rate(n, phi);
    let t0 = 2.0 * n as f64 / rate;
    s.advance_to(t0).expect("no stall");
    let dt = collisions as f64 / rate;
    let start = Instant::now();
    for k in 1..=iters {
        s.advance_to(t0 + dt * k as f64).expect("no stall");
    }
    start.elapsed()
}

fn gas(c: &mut Criterion) {
    let collisions = 20_000;
    let mut g = c.benchmark_group("sim_gas_per_20k_collisions");
    g.throughput(Throughput::Elements(collisions));
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(3));
    for (n, phi) in [
        (4000, 0.1),
        (4000, 0.25),
        (4000, 0.4),
        (32_000, 0.25),
        (108_000, 0.25),
    ] {
        let world = sim::gas(n, phi, 1);
        g.bench_function(format!("n{n}_phi{phi}"), |b| {
            b.iter_custom(|iters| time_collisions(&world, n, phi, collisions, iters))
        });
    }
    g.finish();
}

fn unused_effects(c: &mut Criterion) {
    let collisions = 20_000;
    let mut g = c.benchmark_group("sim_unused_effects_n4000_phi0.25");
    g.throughput(Throughput::Elements(collisions));
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(3));
    let plain = sim::gas(4000, 0.25, 1);
    let declared = sim::gas_with_unused_effects(4000, 0.25, 1);
    for (name, world) in [("plain", &plain), ("sticky_inelastic_declared", &declared)] {
        g.bench_function(name, |b| {
            b.iter_custom(|iters| time_collisions(world, 4000, 0.25, collisions, iters))
        });
    }
    g.finish();
}

/// Gravity's cost: one falling contact per shape kind (the certified root isolation of
/// docs/derivations/gravity.md) over 1024 spheres at random inside a vessel, around a pillar
/// and over a floor; and an elastic gas in a closed box with and without gravity, per event.
fn gravity(c: &mut Criterion) {
    use glam::DVec3;
    let mut g = c.benchmark_group("gravity_contact_per_1024");
    g.throughput(Throughput::Elements(1024));
    g.sample_size(20);
    g.warm_up_time(Duration::from_millis(300));
    g.measurement_time(Duration::from_secs(2));
    for (name, shape, cases) in sim::falling_cases(1024, 9) {
        g.bench_function(name, |b| {
            b.iter(|| {
                cases
                    .iter()
                    .map(|&(r, v, gr)| shape.time_of_impact_falling(r, v, 0.5, gr).unwrap_or(0.0))
                    .sum::<f64>()
            })
        });
    }
    g.finish();
    let mut g = c.benchmark_group("gravity_box_gas_per_20k_events");
    g.throughput(Throughput::Elements(20_000));
    g.sample_size(10);
    g.warm_up_time(Duration::from_millis(500));
    g.measurement_time(Duration::from_secs(3));
    for (name, gravity) in [
        ("without", DVec3::ZERO),
        ("with", DVec3::new(0.0, 0.0, -1.0)),
    ] {
        let world = sim::box_gas(400, gravity, 21);
        g.bench_function(name, |b| {
            b.iter_custom(|iters| sim::time_events(&world, 20_000 * iters))
        });
    }
    g.finish();
}

criterion_group!(benches, gas, unused_effects, gravity);
criterion_main!(benches);
