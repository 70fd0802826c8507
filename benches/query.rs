//! The whole first-contact query (broad phase + narrow phase + reduction), ours against parry3d
//! (`Bvh` incremental for the candidates, `cast_shapes` on each, the earliest kept), one
//! thread; and ours in a two-thread rayon pool; each also with the compact answer
//! (`first_contacts_compact_into`, 8 bytes per sphere: `stable-compact`). Uniform gas at
//! φ = 0.3 and 0.05, half a radius of travel, N = 10³ … 10⁶. Results: docs/benchmarks.md.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use spheresweep::query::SceneQuery;
use spheresweep::scene::Scene;
use spheresweep::{Accuracy, QueryOptions};
use spheresweep_bench::peer::ParryQuery;
use spheresweep_bench::scenes;

fn query(c: &mut Criterion) {
    let (pool, pool2) = (spheresweep_bench::pool(1), spheresweep_bench::pool(2));
    let t_max = scenes::window(0.5);
    let options = QueryOptions::new(t_max, Accuracy::Stable).unwrap();
    for phi in [0.3, 0.05] {
        let mut g = c.benchmark_group(format!("query_gas_phi{phi}_travel0.5r"));
        for n in [1_000, 10_000, 100_000, 1_000_000] {
            let scene = Scene {
                spheres: scenes::uniform_gas(n, phi, 7),
                ..Scene::default()
            };
            g.throughput(Throughput::Elements(n as u64));
            g.sample_size(10);
            g.warm_up_time(Duration::from_millis(300));
            g.measurement_time(Duration::from_secs(if n >= 1_000_000 { 5 } else { 2 }));
            let (mut ours, mut out1) = (SceneQuery::new(), Vec::new());
            g.bench_function(format!("stable/{n}"), |b| {
                pool.install(|| {
                    b.iter(|| {
                        ours.first_contacts_into(&scene, options, &mut out1);
                        black_box(&out1);
                    })
                })
            });
            let (mut ours2, mut out2) = (SceneQuery::new(), Vec::new());
            g.bench_function(format!("stable-2-threads/{n}"), |b| {
                pool2.install(|| {
                    b.iter(|| {
                        ours2.first_contacts_into(&scene, options, &mut out2);
                        black_box(&out2);
                    })
                })
            });
            let (mut compact, mut hits) = (SceneQuery::new(), Vec::new());
            g.bench_function(format!("stable-compact/{n}"), |b| {
                pool.install(|| {
                    b.iter(|| {
                        compact.first_contacts_compact_into(&scene, options, &mut hits);
                        black_box(&hits);
                    })
                })
            });
            let (mut compact2, mut hits2) = (SceneQuery::new(), Vec::new());
            g.bench_function(format!("stable-compact-2-threads/{n}"), |b| {
                pool2.install(|| {
                    b.iter(|| {
                        compact2.first_contacts_compact_into(&scene, options, &mut hits2);
                        black_box(&hits2);
                    })
                })
            });
            let mut parry = ParryQuery::new();
            let mut out = vec![0.0f32; n];
            g.bench_function(format!("parry-bvh-cast_shapes/{n}"), |b| {
                b.iter(|| black_box(parry.first_contacts(&scene.spheres, t_max, &mut out)))
            });
        }
        g.finish();
    }
}

criterion_group!(benches, query);
criterion_main!(benches);
