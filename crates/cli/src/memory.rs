//! Up-front memory refusal for the commands: a scene or a chunk too large for the memory
//! available is refused before anything is allocated, with the count, the estimated bytes,
//! the memory available and the limit that set it (the library's `io::memory`, which says
//! how the figure is read).

pub use spheresweep::io::memory::{human, parse_bytes};

/// Refuses `bytes` (for `what`) above the memory available.
pub fn check(what: &str, bytes: u64) -> Result<(), String> {
    spheresweep::io::memory::check(what, bytes).map_err(|e| e.to_string())
}

/// Refuses a scene file whose spheres (counted before any is generated) would not fit in the
/// memory available at `per_sphere` bytes each, naming the file and the count.
pub fn check_scene(
    path: &std::path::Path,
    scene: &spheresweep::io::scene_file::SceneFile,
    per_sphere: usize,
) -> Result<(), String> {
    match scene.sphere_count() {
        // More than a scene file may give: building it names the block and its limit, which
        // says more than the bytes would.
        Some(n) if n > spheresweep::io::scene_file::MAX_SPHERES => Ok(()),
        Some(n) => check(
            &format!("{}: {n} spheres", path.display()),
            n.saturating_mul(per_sphere) as u64,
        ),
        None => Ok(()),
    }
}
