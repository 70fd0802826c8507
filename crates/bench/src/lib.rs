//! Helpers shared by spheresweep's criterion benchmarks (`cargo bench` at the repository
//! root): the peer's calls live here, so that the benchmarks and `spheresweep bench` measure
//! the same thing.
