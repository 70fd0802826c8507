//! The first contact of every sphere with no time limit (`t_max = ∞`), where no broad phase can
//! cull: time, pairs tested and peak memory, on a dilute gas (1 % volume fraction) of `N`
//! spheres. `cargo run --release -p spheresweep-bench --example unbounded_window [N]`.

use std::time::Instant;

use spheresweep::query::SceneQuery;
use spheresweep::scene::Scene;
use spheresweep::{Accuracy, QueryOptions, Sphere, SphereStore};

/// Peak resident memory of this process so far (VmHWM), in bytes.
fn peak_rss() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        .map_or(0, |kb| kb * 1024)
}

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100_000);
    let mut rng = spheresweep::rng::Rng::new(1);
    let r = 0.3f64;
    let side = (n as f64 * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) / 0.01).cbrt();
    let spheres: Vec<Sphere> = (0..n)
        .map(|_| {
            let c = [0; 3].map(|_| rng.range(0.0, side) as f32);
            let v = [0; 3].map(|_| rng.range(-1.0, 1.0) as f32);
            Sphere::new(c, v, r as f32, 1.0).expect("valid")
        })
        .collect();
    let scene = Scene {
        spheres: SphereStore::from_spheres(&spheres),
        ..Scene::default()
    };
    let before = peak_rss();
    let options = QueryOptions::new(f32::INFINITY, Accuracy::Stable).expect("valid");
    let (mut query, mut out) = (SceneQuery::new(), Vec::new());
    let start = Instant::now();
    query.first_contacts_compact_into(&scene, options, &mut out);
    let secs = start.elapsed().as_secs_f64();
    let touching = out.iter().filter(|c| !c.is_none()).count();
    println!(
        "N = {n}, 1 % volume fraction, t_max = inf: {secs:.2} s, {} pairs tested ({:.1} per sphere), {touching} spheres touch one, peak memory {:.0} MB ({:.0} MB before the query), query holds {:.0} B/sphere",
        query.stats().candidate_pairs,
        query.stats().candidate_pairs as f64 / n as f64,
        peak_rss() as f64 / 1e6,
        before as f64 / 1e6,
        query.heap_bytes() as f64 / n as f64
    );
}
