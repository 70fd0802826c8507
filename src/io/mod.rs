//! Files in and out: extended XYZ snapshots, and scene files (with the `scene-file` feature).
//!
//! - [`memory`]: the memory this process may still take (`SPHERESWEEP_MAX_MEMORY`,
//!   /proc/meminfo, `ulimit -v`, cgroups), so that a large input is refused, not aborted.
//! - [`xyz`]: extended XYZ frames of a simulation's spheres (OVITO, ASE), written and read
//!   back bit for bit; always compiled, no dependency.
//! - `scene_file` (feature `scene-file`): a scene described in TOML or JSON, read into a
//!   [`sim::World`](crate::sim::World) with errors that name the item, the field and the line
//!   (docs/scene-format.md).

pub mod memory;
#[cfg(feature = "scene-file")]
pub mod scene_file;
pub mod xyz;
