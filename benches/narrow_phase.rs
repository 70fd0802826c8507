//! Narrow-phase throughput: every pair kind × accuracy mode, the scalar f64 reference, and
//! parry3d's `cast_shapes` on the same pairs in the same group, in cache and streaming.
//! Our kernels run in a one-thread rayon pool (the targets are per core); one extra line
//! shows the two-thread parallel batch. The workloads are `spheresweep_bench::narrow`, the
//! same `spheresweep bench` measures. Results: docs/benchmarks.md.

use std::hint::black_box;

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use spheresweep::batch::StaticShape;
use spheresweep::{Accuracy, QueryOptions, Sphere, reference};
use spheresweep_bench::narrow::{self, AgainstStatic, SpherePairs, T_MAX};

/// In cache (about 250 KiB of blocks for sphere pairs) and streaming (far beyond L3).
const SIZES: [usize; 2] = [4096, 1 << 22];

fn one_thread() -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
}

fn our_modes<F: Fn(QueryOptions, &mut [f32]) + Copy + Sync>(
    g: &mut BenchmarkGroup<WallTime>,
    n: usize,
    f: F,
) {
    let pool = one_thread();
    let mut out = vec![0.0f32; n];
    for mode in Accuracy::ALL {
        let q = QueryOptions::new(T_MAX, mode).unwrap();
        g.bench_function(format!("{mode}/{n}"), |b| {
            pool.install(|| b.iter(|| f(q, black_box(&mut out))))
        });
    }
}

fn configure(g: &mut BenchmarkGroup<WallTime>, n: usize) {
    g.throughput(Throughput::Elements(n as u64));
    g.sample_size(if n > 100_000 { 10 } else { 30 });
    g.warm_up_time(std::time::Duration::from_millis(500));
    g.measurement_time(std::time::Duration::from_secs(if n > 100_000 {
        3
    } else {
        2
    }));
}

fn sphere_sphere(c: &mut Criterion) {
    let mut g = c.benchmark_group("sphere_sphere");
    for n in SIZES {
        configure(&mut g, n);
        let pairs = SpherePairs::new(n, 1);
        our_modes(&mut g, n, |q, out| pairs.ours(q, out));
        let mut out = vec![0.0f32; n];
        if n > 100_000 {
            let q = QueryOptions::new(T_MAX, Accuracy::Stable).unwrap();
            g.bench_function(format!("stable-2-threads/{n}"), |bch| {
                bch.iter(|| pairs.ours(q, black_box(&mut out)))
            });
        }
        let (a, b) = (pairs.a.to_spheres(), pairs.b.to_spheres());
        g.bench_function(format!("reference-f64/{n}"), |bch| {
            bch.iter(|| {
                for ((x, y), o) in a.iter().zip(&b).zip(out.iter_mut()) {
                    *o = reference::sphere_sphere::time_of_impact(x, y, T_MAX.into())
                        .map_or(f32::INFINITY, |t| t as f32);
                }
                black_box(&mut out);
            })
        });
        g.bench_function(format!("parry-cast_shapes/{n}"), |bch| {
            bch.iter(|| pairs.parry(black_box(&mut out)))
        });
        g.bench_function(format!("parry-cast_shapes_ball_ball/{n}"), |bch| {
            bch.iter(|| pairs.parry_ball_ball(black_box(&mut out)))
        });
    }
    g.finish();
}

/// Every sphere against one static shape: ours, the reference, and parry's where it has one.
fn against_static<K: StaticShape>(
    c: &mut Criterion,
    name: &str,
    make: fn(usize, u64) -> AgainstStatic<K>,
    reference: fn(&Sphere, &K, f64) -> Option<f64>,
) {
    let mut g = c.benchmark_group(name);
    for n in SIZES {
        configure(&mut g, n);
        let set = make(n, 2);
        our_modes(&mut g, n, |q, out| set.ours(q, out));
        let spheres = set.spheres.to_spheres();
        let mut out = vec![0.0f32; n];
        g.bench_function(format!("reference-f64/{n}"), |b| {
            b.iter(|| {
                for (s, o) in spheres.iter().zip(out.iter_mut()) {
                    *o = reference(s, &set.shape, T_MAX.into()).map_or(f32::INFINITY, |t| t as f32);
                }
                black_box(&mut out);
            })
        });
        if set.has_peer() {
            g.bench_function(format!("parry-cast_shapes/{n}"), |b| {
                b.iter(|| set.parry(black_box(&mut out)))
            });
        }
    }
    g.finish();
}

fn sphere_plane(c: &mut Criterion) {
    against_static(
        c,
        "sphere_plane",
        narrow::plane,
        reference::sphere_plane::time_of_impact,
    );
}

fn sphere_cylinder(c: &mut Criterion) {
    against_static(
        c,
        "sphere_cylinder",
        narrow::cylinder,
        reference::sphere_cylinder::time_of_impact,
    );
}

fn sphere_container(c: &mut Criterion) {
    against_static(
        c,
        "sphere_container",
        narrow::container,
        reference::sphere_container::time_of_impact,
    );
}

criterion_group!(
    benches,
    sphere_sphere,
    sphere_plane,
    sphere_cylinder,
    sphere_container
);
criterion_main!(benches);
