//! Up-front memory refusal for the commands: a scene or a chunk too large for the memory
//! available is refused before anything is allocated, with the count, the estimated bytes,
//! the memory available and the limit that set it (the library's `io::memory`, which says
//! how the figure is read).

pub use spheresweep::io::memory::{human, parse_bytes};

/// Refuses `bytes` (for `what`) above the memory available.
pub fn check(what: &str, bytes: u64) -> Result<(), String> {
    spheresweep::io::memory::check(what, bytes).map_err(|e| e.to_string())
}

/// The count of spheres a scene file gives, known before any is generated, to check memory
/// for: `None` if it is not known, or if it is more than a scene file may give (building it
/// then names the block and its limit, which says more than the bytes would).
pub fn scene_count(scene: &spheresweep::io::scene_file::SceneFile) -> Option<usize> {
    scene
        .sphere_count()
        .filter(|&n| n <= spheresweep::io::scene_file::MAX_SPHERES)
}

/// Refuses a scene file whose spheres (counted before any is generated) would not fit in the
/// memory available at `per_sphere` bytes each, naming the file and the count.
pub fn check_scene(
    path: &std::path::Path,
    scene: &spheresweep::io::scene_file::SceneFile,
    per_sphere: usize,
) -> Result<(), String> {
    match scene_count(scene) {
        Some(n) => check(
            &format!("{}: {n} spheres", path.display()),
            n.saturating_mul(per_sphere) as u64,
        ),
        None => Ok(()),
    }
}
