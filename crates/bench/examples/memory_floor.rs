//! The memory floor of the whole first-contact query on this machine: streaming bandwidth on
//! arrays of about 800 MB (sum of `u64`s, `copy_from_slice`) at one and two threads, the bytes
//! the query must move per sphere, and the nanoseconds per sphere those bytes take at least:
//! `cargo run --release -p spheresweep-bench --example memory_floor [MB]`.

use spheresweep_bench::floor::{self, ARRAY_BYTES};

fn main() {
    let bytes = std::env::args()
        .nth(1)
        .and_then(|a| a.parse::<usize>().ok())
        .map_or(ARRAY_BYTES, |mb| mb * 1_000_000);
    println!("query's minimum traffic per sphere (bytes):");
    println!("  {:<34} {:>6} {:>8}", "", "read", "written");
    let (mut read, mut written) = (0, 0);
    for s in floor::query_streams() {
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
    println!(
        "\nbandwidth on {:.0} MB arrays (best of 5) and the floor in ns per sphere:",
        bytes as f64 / 1e6
    );
    println!(
        "  {:>7} {:>10} {:>22} {:>22}",
        "threads", "read GB/s", "copy GB/s (r + w)", "floor ns / sphere"
    );
    for threads in [1, 2] {
        let b = floor::bandwidth(threads, bytes, 5);
        let f = floor::floor(b);
        println!(
            "  {threads:>7} {:>10.1} {:>22.1} {:>22}",
            b.read / 1e9,
            b.copy / 1e9,
            format!("{:.1} – {:.1}", f.low_ns, f.high_ns)
        );
    }
    println!(
        "\nfloor: the low end is the minimum bytes at the faster rate; the high end adds a read\n\
         of every written line (write-allocate) at the slower rate."
    );
}
