//! Broad-phase throughput: the uniform grid against parry3d's `Bvh` — rebuilt every step, and
//! updated incrementally (`insert_or_update_partially`, `refit`, then
//! `traverse_bvtt_single_tree::<false>`) — on the same swept boxes, one thread, in the same
//! group; and the grid in a two-thread rayon pool (`grid-2-threads`). Uniform gas at packing fractions 0.05 and 0.3 with windows of half a radius and of
//! ten radii of travel, and a clustered scene; N = 10³ … 10⁶ (10⁷ with
//! `SPHERESWEEP_BENCH_HUGE=1`). Candidate pairs per sphere are printed for both. Results:
//! docs/benchmarks.md.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use spheresweep::SphereStore;
use spheresweep::broad::{Grid, GridOptions};
use spheresweep_bench::peer::{ParryIncremental, ParryRebuild, swept_boxes_into};
use spheresweep_bench::scenes;

fn sizes() -> Vec<usize> {
    let mut sizes = vec![1_000, 10_000, 100_000, 1_000_000];
    if std::env::var_os("SPHERESWEEP_BENCH_HUGE").is_some() {
        sizes.push(10_000_000);
    }
    sizes
}

fn group(c: &mut Criterion, name: &str, make: &dyn Fn(usize) -> SphereStore, t_max: f32) {
    let (pool, pool2) = (spheresweep_bench::pool(1), spheresweep_bench::pool(2));
    let mut g = c.benchmark_group(name);
    for n in sizes() {
        let store = make(n);
        g.throughput(Throughput::Elements(n as u64));
        g.sample_size(10);
        g.warm_up_time(Duration::from_millis(300));
        g.measurement_time(Duration::from_secs(if n >= 1_000_000 { 4 } else { 2 }));
        let mut grid = Grid::new();
        pool.install(|| grid.build(&store, t_max, GridOptions::default()));
        let ours = grid.pairs().len();
        g.bench_function(format!("grid/{n}"), |b| {
            pool.install(|| {
                b.iter(|| {
                    grid.build(&store, t_max, GridOptions::default());
                    black_box(grid.pairs().len())
                })
            })
        });
        if n <= 2_000_000 {
            let mut grid2 = Grid::new();
            grid2.build(&store, t_max, GridOptions::default());
            g.bench_function(format!("grid-2-threads/{n}"), |b| {
                pool2.install(|| {
                    b.iter(|| {
                        grid2.build(&store, t_max, GridOptions::default());
                        black_box(grid2.pairs().len())
                    })
                })
            });
        }
        let (mut lo, mut hi) = (Vec::new(), Vec::new());
        swept_boxes_into(&store, t_max, &mut lo, &mut hi);
        let mut incremental = ParryIncremental::new();
        let theirs = incremental.count(&lo, &hi);
        g.bench_function(format!("parry-bvh-incremental/{n}"), |b| {
            b.iter(|| black_box(incremental.count(&lo, &hi)))
        });
        if n <= 1_000_000 {
            let mut rebuild = ParryRebuild::new();
            g.bench_function(format!("parry-bvh-rebuild/{n}"), |b| {
                b.iter(|| black_box(rebuild.count(&lo, &hi)))
            });
        }
        eprintln!(
            "{name}/{n}: candidate pairs per sphere: grid {:.3}, parry {:.3}; grid bytes per sphere {:.0}",
            ours as f64 / n as f64,
            theirs as f64 / n as f64,
            grid.heap_bytes() as f64 / n as f64
        );
    }
    g.finish();
}

fn gas(c: &mut Criterion) {
    for phi in [0.05, 0.3] {
        for radii in [0.5f32, 10.0] {
            let name = format!("broad_gas_phi{phi}_travel{radii}r");
            group(
                c,
                &name,
                &|n| scenes::uniform_gas(n, phi, 7),
                scenes::window(radii),
            );
        }
    }
}

fn clustered(c: &mut Criterion) {
    group(
        c,
        "broad_clustered_travel0.5r",
        &|n| scenes::clustered(n, 7),
        scenes::window(0.5),
    );
}

criterion_group!(benches, gas, clustered);
criterion_main!(benches);
