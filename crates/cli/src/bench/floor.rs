//! The memory floor of the whole query (full run only): this machine's read and copy bandwidth
//! on arrays of about 800 MB at one and two threads, and the fewest nanoseconds per sphere the
//! query's minimum traffic takes at them (`spheresweep_bench::floor`; the example
//! `memory_floor` prints the traffic stream by stream).

use spheresweep_bench::floor::{self, ARRAY_BYTES};

use super::Line;

/// One line per thread count: the floor's low end as the time, the range and the rates noted.
pub fn lines(lines: &mut Vec<Line>) {
    for threads in [1, 2] {
        let bandwidth = floor::bandwidth(threads, ARRAY_BYTES, 5);
        let f = floor::floor(bandwidth);
        lines.push(Line {
            group: "memory floor of the whole query (minimum bytes per sphere at this machine's streaming bandwidth, 800 MB arrays)".into(),
            name: format!("floor, {threads} thread{}", if threads == 1 { "" } else { "s" }),
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
            ),
            threads,
            ..Line::default()
        });
    }
}
