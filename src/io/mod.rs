//! Files in and out: extended XYZ snapshots, and scene files (with the `scene-file` feature).
//!
//! - [`xyz`]: extended XYZ frames of a simulation's spheres (OVITO, ASE), written and read
//!   back bit for bit; always compiled, no dependency.
//! - `scene_file` (feature `scene-file`): a scene described in TOML or JSON, read into a
//!   [`sim::World`](crate::sim::World) with errors that name the item, the field and the line
//!   (docs/scene-format.md).

#[cfg(feature = "scene-file")]
pub mod scene_file;
pub mod xyz;
