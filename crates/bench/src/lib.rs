//! Helpers shared by spheresweep's criterion benchmarks (`cargo bench` at the repository
//! root) and `spheresweep bench`: the scenes and pairs both measure, and the peer's calls, so
//! that the two measure the same thing.

pub mod floor;
pub mod narrow;
pub mod peer;
pub mod scenes;
pub mod sim;
