//! Files in and out: extended XYZ snapshots, and scene files (with the `scene-file` feature).
//!
//! - [`xyz`]: extended XYZ frames of a simulation's spheres (OVITO, ASE), written and read
//!   back bit for bit; always compiled, no dependency.

pub mod xyz;
