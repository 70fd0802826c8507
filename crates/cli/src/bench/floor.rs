//! The memory floor of the whole query (full run only): this machine's read and copy bandwidth
//! on arrays of about 800 MB at one and two threads, and the fewest nanoseconds per sphere the
//! query's minimum traffic takes at them (`spheresweep_bench::floor`; the example
//! `memory_floor` prints the traffic stream by stream).

use spheresweep_bench::floor::{self, ARRAY_BYTES};

use super::Line;
use crate::number::counted;

/// One line per thread count: the floor's low end as the time, the range and the rates noted,
/// and how many times the low end the whole query measured earlier in the run took at N = 10⁶.
pub fn lines(lines: &mut Vec<Line>) {
    for threads in [1, 2] {
        let bandwidth = floor::bandwidth(threads, ARRAY_BYTES, 5);
        let f = floor::floor(bandwidth, &floor::query_streams());
        let kept = floor::floor(bandwidth, &floor::query_streams_kept_in_cell_order());
        let query: Vec<String> = lines
            .iter()
            .filter(|l| l.group.starts_with("whole query") && l.n == 1_000_000)
            .filter(|l| l.threads == threads)
            .map(|l| {
                let form = if l.name.contains("compact") {
                    ", compact"
                } else {
                    ""
                };
                format!("{:.0}× ({}{form})", l.ns / f.low_ns, phi_of(&l.group))
            })
            .collect();
        let query = if query.is_empty() {
            String::new()
        } else {
            format!("; the query at N = 10⁶: {} the low end", query.join(", "))
        };
        lines.push(Line {
            group: "memory floor of the whole query (minimum bytes per sphere at this machine's streaming bandwidth, 800 MB arrays)".into(),
            name: format!("floor, {}", counted(threads as u64, "thread", "threads")),
            n: 1,
            ns: f.low_ns,
            peer_ns: None,
            note: format!(
                "to {:.1} ns; {} B/sphere ({} with write-allocate); read {:.1} GB/s, copy {:.1} GB/s (read + written)",
                f.high_ns,
                f.bytes,
                f.bytes_with_write_allocate,
                bandwidth.read / 1e9,
                bandwidth.copy / 1e9
            ) + &query
                + &format!(
                    "; kept in cell order across frames: {} B/sphere, {:.1} – {:.1} ns",
                    kept.bytes, kept.low_ns, kept.high_ns
                ),
            threads,
            ..Line::default()
        });
    }
}

/// The `phi …` part of a group's name ("phi 0.3"), or the name itself.
fn phi_of(group: &str) -> &str {
    group
        .find("phi ")
        .and_then(|at| group[at..].split(',').next())
        .unwrap_or(group)
}
