//! The memory floor of the whole first-contact query on this machine: streaming bandwidth on
//! arrays of about 800 MB (sum of `u64`s, `copy_from_slice`) at one and two threads, the bytes
//! the query must move per sphere, and the nanoseconds per sphere those bytes take at least:
//! then the whole query (stable, uniform gas φ = 0.3, half a radius of travel) at N = 10⁶ on
//! the same thread counts, as a multiple of the floor:
//! `cargo run --release -p spheresweep-bench --example memory_floor [MB [N]]`.

use std::time::Instant;

use spheresweep::query::SceneQuery;
use spheresweep::scene::Scene;
use spheresweep::{Accuracy, QueryOptions};
use spheresweep_bench::floor::{self, ARRAY_BYTES};
use spheresweep_bench::scenes;

fn main() {
    let arg = |i: usize| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse::<usize>().ok())
    };
    let bytes = arg(1).map_or(ARRAY_BYTES, |mb| mb * 1_000_000);
    let n = arg(2).unwrap_or(1_000_000);
    print_traffic();
    println!(
        "\nbandwidth on {:.0} MB arrays (best of 5), the floor and the whole query at N = {n}:",
        bytes as f64 / 1e6
    );
    println!(
        "  {:>7} {:>10} {:>18} {:>18} {:>16} {:>12} {:>24}",
        "threads",
        "read GB/s",
        "copy GB/s (r + w)",
        "floor ns / sphere",
        "query ns/sphere",
        "× floor",
        "kept in cell order: ns"
    );
    let scene = Scene {
        spheres: scenes::uniform_gas(n, 0.3, 7),
        ..Scene::default()
    };
    for threads in [1, 2] {
        let b = floor::bandwidth(threads, bytes, 5);
        let f = floor::floor(b, &floor::query_streams());
        let kept = floor::floor(b, &floor::query_streams_kept_in_cell_order());
        let query = query_ns(&scene, threads);
        println!(
            "  {threads:>7} {:>10.1} {:>18.1} {:>18} {query:>16.1} {:>12} {:>24}",
            b.read / 1e9,
            b.copy / 1e9,
            format!("{:.1} – {:.1}", f.low_ns, f.high_ns),
            format!("{:.0} – {:.0}", query / f.high_ns, query / f.low_ns),
            format!("{:.1} – {:.1}", kept.low_ns, kept.high_ns)
        );
    }
    println!(
        "\nfloor: the low end is the minimum bytes at the faster rate; the high end adds a read\n\
         of every written line (write-allocate) at the slower rate."
    );
}

/// The query's minimum traffic, stream by stream, in both designs.
fn print_traffic() {
    println!("query's minimum traffic per sphere (bytes), sorted into cell order each call:");
    print_streams(&floor::query_streams());
    println!("\nand with the spheres kept in cell order across frames:");
    print_streams(&floor::query_streams_kept_in_cell_order());
}

/// A table of `streams` with its totals.
fn print_streams(streams: &[floor::Stream]) {
    println!("  {:<34} {:>6} {:>8}", "", "read", "written");
    let (mut read, mut written) = (0, 0);
    for s in streams {
        println!("  {:<34} {:>6} {:>8}", s.what, s.read, s.written);
        read += s.read;
        written += s.written;
    }
    println!(
        "  {:<34} {read:>6} {written:>8}   = {} bytes ({} with write-allocate)",
        "total",
        read + written,
        read + 2 * written
    );
}

/// The whole first-contact query's best time per sphere of three, in a pool of `threads`.
fn query_ns(scene: &Scene, threads: usize) -> f64 {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    let options = QueryOptions::new(scenes::window(0.5), Accuracy::Stable).expect("valid window");
    let (mut query, mut answers) = (SceneQuery::new(), Vec::new());
    pool.install(|| {
        query.first_contacts_into(scene, options, &mut answers);
        (0..3)
            .map(|_| {
                let start = Instant::now();
                query.first_contacts_into(scene, options, &mut answers);
                start.elapsed().as_secs_f64() * 1e9 / scene.spheres.len() as f64
            })
            .fold(f64::INFINITY, f64::min)
    })
}
