//! Helpers shared by spheresweep's criterion benchmarks (`cargo bench` at the repository
//! root) and `spheresweep bench`: the scenes and pairs both measure, and the peer's calls, so
//! that the two measure the same thing.

pub mod floor;
pub mod narrow;
pub mod peer;
pub mod scenes;
pub mod sim;

/// A rayon pool of `threads` threads, for the one- and two-thread lines of the benchmarks.
///
/// ```
/// assert_eq!(spheresweep_bench::pool(2).current_num_threads(), 2);
/// ```
pub fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
}
