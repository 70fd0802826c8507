//! Runs one kernel × mode over 4096 in-cache pairs `REPS` times, for instruction counting under
//! `valgrind --tool=callgrind` (deterministic, unlike wall time on a shared machine):
//!
//! ```sh
//! cargo build --release -p spheresweep-bench --example kernel_cost
//! for reps in 1 101; do valgrind --tool=callgrind --callgrind-out-file=/dev/null \
//!     target/release/examples/kernel_cost sphere stable $reps 2>&1 | grep refs; done
//! ```
//!
//! (instructions at 101 − at 1) / (100 · 4096) is the cost per pair.

use spheresweep::batch::{static_times, zip_times};
use spheresweep::rng::Rng;
use spheresweep::{Accuracy, Container, Cylinder, Plane, QueryOptions, SphereStore};
use spheresweep_bench::narrow::random_sphere;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: kernel_cost sphere|plane|cylinder|container textbook|stable|double REPS";
    let (kind, mode, reps) = match args.as_slice() {
        [_, k, m, r] => (k.as_str(), m.parse::<Accuracy>(), r.parse::<usize>()),
        _ => {
            eprintln!("{usage}");
            std::process::exit(2);
        }
    };
    let (Ok(mode), Ok(reps)) = (mode, reps) else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    let n = 4096;
    let mut rng = Rng::new(1);
    let a: SphereStore = (0..n).map(|_| random_sphere(&mut rng, 40.0, 4.0)).collect();
    let b: SphereStore = (0..n).map(|_| random_sphere(&mut rng, 40.0, 4.0)).collect();
    let q = QueryOptions::new(4.0, mode).unwrap();
    let mut out = vec![0.0f32; n];
    let plane = Plane::new([1.0, 2.0, -30.0], [0.1, 0.2, 1.0]).unwrap();
    let cylinder = Cylinder::new([3.0, 0.0, 0.0], [3.5, 1.0, 1.0], 2.0).unwrap();
    let container = Container::new([0.0; 3], 80.0).unwrap();
    for _ in 0..reps {
        match kind {
            "sphere" => zip_times(&a, &b, q, &mut out).unwrap(),
            "plane" => static_times(&a, &plane, q, &mut out).unwrap(),
            "cylinder" => static_times(&a, &cylinder, q, &mut out).unwrap(),
            "container" => static_times(&a, &container, q, &mut out).unwrap(),
            _ => {
                eprintln!("{usage}");
                std::process::exit(2);
            }
        }
        std::hint::black_box(&mut out);
    }
    println!("{}", out.iter().filter(|t| t.is_finite()).count());
}
