//! Quick in-cache time ratios between the accuracy modes of every kernel, interleaved so
//! that a shared machine's drift hits every mode alike (best of many short timings):
//! `cargo run --release -p spheresweep-bench --example kernel_ratio`. The published figures
//! come from criterion (`cargo bench --bench narrow_phase`); this is the quick check.

use std::time::Instant;

use spheresweep::batch::{static_times, zip_times};
use spheresweep::rng::Rng;
use spheresweep::{Accuracy, Container, Cylinder, Plane, QueryOptions, SphereStore};
use spheresweep_bench::narrow::random_sphere;

fn main() {
    let n = 4096;
    let mut rng = Rng::new(1);
    let a: SphereStore = (0..n).map(|_| random_sphere(&mut rng, 40.0, 4.0)).collect();
    let b: SphereStore = (0..n).map(|_| random_sphere(&mut rng, 40.0, 4.0)).collect();
    let plane = Plane::new([1.0, 2.0, -30.0], [0.1, 0.2, 1.0]).unwrap();
    let cylinder = Cylinder::new([3.0, 0.0, 0.0], [3.5, 1.0, 1.0], 2.0).unwrap();
    let container = Container::new([0.0; 3], 80.0).unwrap();
    let mut out = vec![0.0f32; n];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    println!("kind       textbook ns  stable ns  double ns  stable/textbook  double/stable");
    for kind in ["sphere", "plane", "cylinder", "container"] {
        let mut best = [f64::INFINITY; 3];
        for _ in 0..200 {
            for (m, mode) in Accuracy::ALL.into_iter().enumerate() {
                let q = QueryOptions::new(4.0, mode).unwrap();
                let start = Instant::now();
                pool.install(|| {
                    for _ in 0..20 {
                        match kind {
                            "sphere" => zip_times(&a, &b, q, &mut out).unwrap(),
                            "plane" => static_times(&a, &plane, q, &mut out).unwrap(),
                            "cylinder" => static_times(&a, &cylinder, q, &mut out).unwrap(),
                            _ => static_times(&a, &container, q, &mut out).unwrap(),
                        }
                        std::hint::black_box(&mut out);
                    }
                });
                let ns = start.elapsed().as_secs_f64() * 1e9 / (20 * n) as f64;
                best[m] = best[m].min(ns);
            }
        }
        println!(
            "{kind:<10} {:>11.3}  {:>9.3}  {:>9.3}  {:>15.2}  {:>13.2}",
            best[0],
            best[1],
            best[2],
            best[1] / best[0],
            best[2] / best[1]
        );
    }
}
