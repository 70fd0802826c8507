//! Time per sphere of the whole query's stages on a uniform gas (one thread), to see where a
//! query's time goes: `cargo run --release -p spheresweep-bench --example query_stages [N]`.

use std::time::Instant;

use spheresweep::broad::{Grid, GridOptions};
use spheresweep::query::SceneQuery;
use spheresweep::scene::Scene;
use spheresweep::{Accuracy, QueryOptions, batch};
use spheresweep_bench::scenes;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100_000);
    // `query_stages N only [K]`: the compact query alone, K times (default 20; for callgrind,
    // the difference of two K).
    if std::env::args().nth(2).as_deref() == Some("only") {
        let scene = Scene {
            spheres: scenes::uniform_gas(n, 0.3, 7),
            ..Scene::default()
        };
        let options = QueryOptions::new(0.5, Accuracy::Stable).unwrap();
        let (mut query, mut out) = (SceneQuery::new(), Vec::new());
        let k: usize = std::env::args()
            .nth(3)
            .and_then(|a| a.parse().ok())
            .unwrap_or(20);
        let mut best = f64::INFINITY;
        for _ in 0..k {
            let start = Instant::now();
            query.first_contacts_compact_into(&scene, options, &mut out);
            std::hint::black_box(&out);
            best = best.min(start.elapsed().as_secs_f64() * 1e9 / n as f64);
        }
        println!("N = {n}: compact query best of {k}: {best:.1} ns/sphere");
        return;
    }
    // `query_stages N frames`: a gas moving frame by frame (each sphere by its velocity times
    // the window), the query reused (the grid re-sorts from the last frame's cell order)
    // against a new query each frame (sorted from scratch).
    if std::env::args().nth(2).as_deref() == Some("frames") {
        frames(n);
        return;
    }
    output_cost(n);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    pool.install(|| {
        let store = scenes::uniform_gas(n, 0.3, 7);
        let t_max = 0.5;
        let best = |f: &mut dyn FnMut()| {
            (0..7)
                .map(|_| {
                    let s = Instant::now();
                    f();
                    s.elapsed().as_secs_f64() * 1e9 / n as f64
                })
                .fold(f64::INFINITY, f64::min)
        };
        let mut grid = Grid::new();
        let g = best(&mut || grid.build(&store, t_max, GridOptions::default()));
        let pairs = grid.pairs().to_vec();
        let mut times = vec![0.0; pairs.len()];
        let options = QueryOptions::new(t_max, Accuracy::Stable).unwrap();
        let p = best(&mut || batch::pair_times(&store, &pairs, options, &mut times).unwrap());
        let scene = Scene {
            spheres: store,
            ..Scene::default()
        };
        let mut query = SceneQuery::new();
        let mut cells = Grid::new();
        let c = best(&mut || cells.build_cells(&scene.spheres, t_max, GridOptions::default()));
        let mut compact = Vec::new();
        let k = best(&mut || {
            query.first_contacts_compact_into(&scene, options, &mut compact);
            std::hint::black_box(&compact);
        });
        let mut out = Vec::new();
        let q = best(&mut || {
            query.first_contacts_into(&scene, options, &mut out);
            std::hint::black_box(&out);
        });
        println!(
            "N = {n}: grid with its pair list {g:.1} ns/sphere, cells only {c:.1}, listed pair_times {p:.1} ({:.2} pairs/sphere); whole query: compact {k:.1}, as Option<FirstContact> {q:.1} ns/sphere; held {:.0} B/sphere",
            pairs.len() as f64 / n as f64,
            query.heap_bytes() as f64 / n as f64
        );
    });
}

fn output_cost(n: usize) {
    let s = Instant::now();
    let v: Vec<Option<spheresweep::FirstContact>> = vec![None; n];
    std::hint::black_box(&v);
    println!(
        "output Vec<Option<FirstContact>>: {} B per sphere, {:.1} ns/sphere to allocate and fill",
        std::mem::size_of::<Option<spheresweep::FirstContact>>(),
        s.elapsed().as_secs_f64() * 1e9 / n as f64
    );
}

fn frames(n: usize) {
    let mut spheres = scenes::uniform_gas(n, 0.3, 7);
    let t_max = scenes::window(0.5);
    let options = QueryOptions::new(t_max, Accuracy::Stable).unwrap();
    let (mut reused, mut out) = (SceneQuery::new(), Vec::new());
    // The same gas, its store kept in the query's cell order (gathered once after the first
    // frame, then moving with the other).
    let (mut kept_query, mut kept_out) = (SceneQuery::new(), Vec::new());
    let mut kept: Option<(spheresweep::SphereStore, Vec<u32>)> = None;
    let (mut warm, mut cold, mut sorted) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let per = |start: Instant| start.elapsed().as_secs_f64() * 1e9 / n as f64;
    for _ in 0..8 {
        let scene = Scene {
            spheres: spheres.clone(),
            ..Scene::default()
        };
        let start = Instant::now();
        reused.first_contacts_compact_into(&scene, options, &mut out);
        warm = warm.min(per(start));
        let mut fresh = SceneQuery::new();
        let mut fresh_out = Vec::with_capacity(n);
        let start = Instant::now();
        fresh.first_contacts_compact_into(&scene, options, &mut fresh_out);
        cold = cold.min(per(start));
        assert_eq!(out, fresh_out);
        if let Some((store, order)) = &kept {
            let scene = Scene {
                spheres: store.clone(),
                ..Scene::default()
            };
            let start = Instant::now();
            kept_query.first_contacts_compact_into(&scene, options, &mut kept_out);
            sorted = sorted.min(per(start));
            for (k, &i) in order.iter().enumerate() {
                assert_eq!(kept_out[k].time(), out[i as usize].time());
            }
        } else {
            let order = reused.cell_order().to_vec();
            kept = Some((spheres.gathered(&order).unwrap(), order));
        }
        for i in 0..n {
            let s = spheres.get(i).unwrap();
            spheres
                .set_centre(i, s.centre_at(t_max).to_array())
                .unwrap();
        }
        if let Some((store, _)) = &mut kept {
            for i in 0..n {
                let s = store.get(i).unwrap();
                store.set_centre(i, s.centre_at(t_max).to_array()).unwrap();
            }
        }
    }
    println!(
        "N = {n}, frames moving half a radius: reused query (re-sorted from the last order) {warm:.1} ns/sphere, new query each frame {cold:.1}, store kept in cell order {sorted:.1}"
    );
}
