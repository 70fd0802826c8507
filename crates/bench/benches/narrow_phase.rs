//! Narrow-phase throughput: every pair kind × accuracy mode, the scalar f64 reference, and
//! parry3d's `cast_shapes` on the same pairs in the same group, in cache and streaming.
//! Our kernels run in a one-thread rayon pool (the targets are per core); one extra line
//! shows the two-thread parallel batch. Results: docs/benchmarks.md.

use std::hint::black_box;

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use parry3d::math::{Pose, Vector};
use parry3d::query::{self, ShapeCastOptions};
use parry3d::shape::{Ball, Cylinder as ParryCylinder, HalfSpace};
use spheresweep::QueryOptions;
use spheresweep::batch::{self, StaticShape};
use spheresweep::rng::Rng;
use spheresweep::{Accuracy, Container, Cylinder, Plane, Sphere, SphereStore, reference};

const T_MAX: f32 = 4.0;
/// In cache (about 250 KiB of columns for sphere pairs) and streaming (far beyond L3).
const SIZES: [usize; 2] = [4096, 1 << 22];

/// A random sphere in the cube `[−box_, box_]³` with speed components up to `speed`.
fn random_sphere(rng: &mut Rng, box_: f64, speed: f64) -> Sphere {
    let (c, v, r) = (rng.cube(box_), rng.cube(speed), rng.range(0.2, 1.5));
    Sphere::new(c.as_vec3().into(), v.as_vec3().into(), r as f32, 1.0).unwrap()
}

fn options() -> ShapeCastOptions {
    ShapeCastOptions {
        max_time_of_impact: T_MAX,
        stop_at_penetration: true,
        ..Default::default()
    }
}

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
        let mut rng = Rng::new(1);
        let a: Vec<Sphere> = (0..n).map(|_| random_sphere(&mut rng, 10.0, 5.0)).collect();
        let b: Vec<Sphere> = (0..n).map(|_| random_sphere(&mut rng, 10.0, 5.0)).collect();
        let (sa, sb) = (SphereStore::from_spheres(&a), SphereStore::from_spheres(&b));
        our_modes(&mut g, n, |q, out| {
            batch::zip_times(&sa, &sb, q, out).unwrap()
        });
        if n > 100_000 {
            let q = QueryOptions::new(T_MAX, Accuracy::Stable).unwrap();
            let mut out = vec![0.0f32; n];
            g.bench_function(format!("stable-2-threads/{n}"), |bch| {
                bch.iter(|| batch::zip_times(&sa, &sb, q, black_box(&mut out)).unwrap())
            });
        }
        let mut out = vec![0.0f32; n];
        g.bench_function(format!("reference-f64/{n}"), |bch| {
            bch.iter(|| {
                for ((x, y), o) in a.iter().zip(&b).zip(out.iter_mut()) {
                    *o = reference::sphere_sphere::time_of_impact(x, y, T_MAX.into())
                        .map_or(f32::INFINITY, |t| t as f32);
                }
                black_box(&mut out);
            })
        });
        let parry: Vec<_> = a
            .iter()
            .zip(&b)
            .map(|(x, y)| {
                (
                    Pose::from_translation(x.centre()),
                    x.velocity(),
                    Ball::new(x.radius()),
                    Pose::from_translation(y.centre()),
                    y.velocity(),
                    Ball::new(y.radius()),
                )
            })
            .collect();
        g.bench_function(format!("parry-cast_shapes/{n}"), |bch| {
            bch.iter(|| {
                for ((p1, v1, g1, p2, v2, g2), o) in parry.iter().zip(out.iter_mut()) {
                    let hit = query::cast_shapes(p1, *v1, g1, p2, *v2, g2, options()).unwrap();
                    *o = hit.map_or(f32::INFINITY, |h| h.time_of_impact);
                }
                black_box(&mut out);
            })
        });
        g.bench_function(format!("parry-cast_shapes_ball_ball/{n}"), |bch| {
            bch.iter(|| {
                for ((p1, v1, g1, p2, v2, g2), o) in parry.iter().zip(out.iter_mut()) {
                    let pos12 = p1.inv_mul(p2);
                    let hit =
                        query::details::cast_shapes_ball_ball(&pos12, *v2 - *v1, g1, g2, options());
                    *o = hit.map_or(f32::INFINITY, |h| h.time_of_impact);
                }
                black_box(&mut out);
            })
        });
    }
    g.finish();
}

/// Every sphere against one static shape: ours, the reference, and parry's pairs if given.
fn against_static<K: StaticShape + Copy>(
    c: &mut Criterion,
    name: &str,
    shape: K,
    reference: fn(&Sphere, &K, f64) -> Option<f64>,
    parry: Option<(Pose, &dyn parry3d::shape::Shape)>,
) {
    let mut g = c.benchmark_group(name);
    for n in SIZES {
        configure(&mut g, n);
        let mut rng = Rng::new(2);
        let spheres: Vec<Sphere> = (0..n)
            .map(|_| random_sphere(&mut rng, 20.0, 10.0))
            .collect();
        let store = SphereStore::from_spheres(&spheres);
        our_modes(&mut g, n, |q, out| {
            batch::static_times(&store, &shape, q, out).unwrap()
        });
        let mut out = vec![0.0f32; n];
        g.bench_function(format!("reference-f64/{n}"), |b| {
            b.iter(|| {
                for (s, o) in spheres.iter().zip(out.iter_mut()) {
                    *o = reference(s, &shape, T_MAX.into()).map_or(f32::INFINITY, |t| t as f32);
                }
                black_box(&mut out);
            })
        });
        if let Some((pose, g2)) = parry {
            let balls: Vec<_> = spheres
                .iter()
                .map(|s| {
                    (
                        Pose::from_translation(s.centre()),
                        s.velocity(),
                        Ball::new(s.radius()),
                    )
                })
                .collect();
            g.bench_function(format!("parry-cast_shapes/{n}"), |b| {
                b.iter(|| {
                    for ((p1, v1, g1), o) in balls.iter().zip(out.iter_mut()) {
                        let hit =
                            query::cast_shapes(p1, *v1, g1, &pose, Vector::ZERO, g2, options())
                                .unwrap();
                        *o = hit.map_or(f32::INFINITY, |h| h.time_of_impact);
                    }
                    black_box(&mut out);
                })
            });
        }
    }
    g.finish();
}

fn sphere_plane(c: &mut Criterion) {
    // The plane z = 0 facing +z; parry's half-space is the solid z ≤ 0 with the same normal.
    let plane = Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap();
    let half_space = HalfSpace::new(Vector::Z);
    against_static(
        c,
        "sphere_plane",
        plane,
        reference::sphere_plane::time_of_impact,
        Some((Pose::identity(), &half_space)),
    );
}

fn sphere_cylinder(c: &mut Criterion) {
    // An infinite pillar along (0.3, 1, 0.2); parry's finite cylinder (along its local y) is
    // 2000 long, a hundred times the scene, turned onto the same axis.
    let axis = glam::Vec3::new(0.3, 1.0, 0.2).normalize();
    let cylinder = Cylinder::new([0.0; 3], axis.into(), 2.0).unwrap();
    let long = ParryCylinder::new(1000.0, 2.0);
    let pose = Pose::from_parts(
        glam::Vec3::ZERO,
        glam::Quat::from_rotation_arc(glam::Vec3::Y, axis),
    );
    against_static(
        c,
        "sphere_cylinder",
        cylinder,
        reference::sphere_cylinder::time_of_impact,
        Some((pose, &long)),
    );
}

fn sphere_container(c: &mut Criterion) {
    // parry has no "inside of a ball" cast: ours and the reference only.
    let vessel = Container::new([0.0; 3], 40.0).unwrap();
    against_static(
        c,
        "sphere_container",
        vessel,
        reference::sphere_container::time_of_impact,
        None,
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
