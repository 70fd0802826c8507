//! The memory floor of the whole first-contact query: this machine's streaming bandwidth on
//! arrays far larger than any cache (a sum of `u64`s, a `copy_from_slice`), one or more
//! threads, and the fewest bytes the query must move per sphere (sorted into cell order each
//! call, or kept in cell order across frames), turned into the fewest nanoseconds per sphere
//! any implementation could take at N = 10⁶.

use std::hint::black_box;
use std::time::Instant;

use rayon::prelude::*;
use spheresweep::store::{PAD, SphereBlock};

/// The size of the arrays the bandwidth is measured on: about 800 MB, far beyond any cache.
pub const ARRAY_BYTES: usize = 800_000_000;

/// One run's streaming bandwidth at a thread count, in bytes per second.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bandwidth {
    /// Threads sharing the work (each its contiguous part of the arrays).
    pub threads: usize,
    /// Bytes read per second summing a `u64` array.
    pub read: f64,
    /// Bytes moved (read and written) per second copying half the array onto the other half.
    pub copy: f64,
}

/// Measures [`Bandwidth`] on `threads` threads over an array of `bytes` bytes (its pages
/// touched first), best of `rounds` passes each.
///
/// ```
/// let b = spheresweep_bench::floor::bandwidth(2, 1 << 20, 2);
/// assert!(b.read > 0.0 && b.copy > 0.0);
/// ```
pub fn bandwidth(threads: usize, bytes: usize, rounds: usize) -> Bandwidth {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    let words = (bytes / 8).max(2 * threads);
    let mut data: Vec<u64> = (0..words as u64).collect();
    let read = pool.install(|| {
        let part = words.div_ceil(threads);
        best_seconds(rounds, || {
            let sum = data
                .par_chunks(part)
                .map(|c| c.iter().fold(0u64, |a, &x| a.wrapping_add(x)))
                .reduce(|| 0, u64::wrapping_add);
            black_box(sum);
        })
    });
    let copy = pool.install(|| {
        let (src, rest) = data.split_at_mut(words / 2);
        let dst = &mut rest[..src.len()];
        let part = src.len().div_ceil(threads);
        best_seconds(rounds, || {
            dst.par_chunks_mut(part)
                .zip(src.par_chunks(part))
                .for_each(|(d, s)| d.copy_from_slice(s));
            black_box(&dst[0]);
        })
    });
    let half = (words / 2 * 8) as f64;
    Bandwidth {
        threads,
        read: (words * 8) as f64 / read,
        copy: 2.0 * half / copy,
    }
}

/// The shortest of `rounds` timings of `f`, in seconds.
fn best_seconds(rounds: usize, mut f: impl FnMut()) -> f64 {
    (0..rounds.max(1))
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// One array the query must stream, per sphere: what it is, bytes read, bytes written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stream {
    /// What the bytes are.
    pub what: &'static str,
    /// Bytes read per sphere.
    pub read: usize,
    /// Bytes written per sphere.
    pub written: usize,
}

/// Bytes per sphere of the store's record as the kernels read it (its seven f32 columns:
/// centre, velocity, radius; the mass is not in the blocks).
pub fn store_record_bytes() -> usize {
    std::mem::size_of::<SphereBlock>() / PAD
}

/// Bytes of the record in cell order the fused pass reads (seven f32 padded to eight).
pub const REORDERED_RECORD_BYTES: usize = 32;

/// The fewest bytes per sphere a first-contact query moves through memory at a size no cache
/// holds: the store's record read, a 4-byte cell key and a 4-byte slot each written and read
/// back (the counting sort), the record written in cell order and read again by the pass, an
/// 8-byte answer (time and body) written.
///
/// ```
/// use spheresweep_bench::floor::{query_streams, store_record_bytes};
/// let read: usize = query_streams().iter().map(|s| s.read).sum();
/// assert_eq!(read, store_record_bytes() + 4 + 4 + 32);
/// ```
pub fn query_streams() -> [Stream; 5] {
    [
        Stream {
            what: "the store's record (7 f32)",
            read: store_record_bytes(),
            written: 0,
        },
        Stream {
            what: "cell key (u32)",
            read: 4,
            written: 4,
        },
        Stream {
            what: "slot of the permutation (u32)",
            read: 4,
            written: 4,
        },
        Stream {
            what: "record in cell order",
            read: REORDERED_RECORD_BYTES,
            written: REORDERED_RECORD_BYTES,
        },
        Stream {
            what: "answer (time, body)",
            read: 0,
            written: 8,
        },
    ]
}

/// The floor in nanoseconds per sphere at one [`Bandwidth`], as a range: from the bytes of the
/// streams at the faster of the two rates, to the same bytes plus one read of every written
/// line (write-allocate: ordinary stores fetch the line first) at the slower rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Floor {
    /// Bytes per sphere read and written, without write-allocate.
    pub bytes: usize,
    /// The same with every written byte read once first.
    pub bytes_with_write_allocate: usize,
    /// `bytes` at the faster rate (ns per sphere).
    pub low_ns: f64,
    /// `bytes_with_write_allocate` at the slower rate (ns per sphere).
    pub high_ns: f64,
}

/// The fewest bytes per sphere when the spheres are already kept in cell order across frames
/// (issue 26's store): the record in cell order read, the slot of the caller's id read, the
/// answer written in the caller's order.
///
/// ```
/// let bytes: usize = spheresweep_bench::floor::query_streams_kept_in_cell_order()
///     .iter()
///     .map(|s| s.read + s.written)
///     .sum();
/// assert_eq!(bytes, 44);
/// ```
pub fn query_streams_kept_in_cell_order() -> [Stream; 3] {
    [
        Stream {
            what: "record in cell order",
            read: REORDERED_RECORD_BYTES,
            written: 0,
        },
        Stream {
            what: "slot of the caller's id (u32)",
            read: 4,
            written: 0,
        },
        Stream {
            what: "answer (time, body)",
            read: 0,
            written: 8,
        },
    ]
}

/// The [`Floor`] of `streams` (e.g. [`query_streams`]) at `bandwidth`.
///
/// ```
/// use spheresweep_bench::floor::{Bandwidth, floor, query_streams};
/// let f = floor(Bandwidth { threads: 1, read: 1e10, copy: 2e10 }, &query_streams());
/// assert!(f.low_ns < f.high_ns);
/// assert_eq!(f.low_ns, f.bytes as f64 / 20.0); // bytes at 20 GB/s
/// ```
pub fn floor(bandwidth: Bandwidth, streams: &[Stream]) -> Floor {
    let read: usize = streams.iter().map(|s| s.read).sum();
    let written: usize = streams.iter().map(|s| s.written).sum();
    let (fast, slow) = (
        bandwidth.read.max(bandwidth.copy),
        bandwidth.read.min(bandwidth.copy),
    );
    Floor {
        bytes: read + written,
        bytes_with_write_allocate: read + 2 * written,
        low_ns: (read + written) as f64 / fast * 1e9,
        high_ns: (read + 2 * written) as f64 / slow * 1e9,
    }
}
