//! The shapes file of `--against`: the `[[plane]]`, `[[cylinder]]` and `[[container]]` tables
//! of the scene-file format (docs/scene-format.md), read by `io::scene_file::read_statics` so
//! that every field, unit and message is the scene file's. A whole scene file (one with a
//! `[run]` table) is accepted too: its other tables are checked as in `spheresweep run`, and
//! its spheres are not part of the query.

use std::path::Path;

use spheresweep::io::scene_file::{self, Format, SceneFile};

use super::compute::Shapes;

/// Reads the shapes of `path`: TOML, or JSON if its name ends in `.json`.
pub fn read(path: &Path) -> Result<Shapes, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let format = Format::of(path);
    let at = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let shapes = if has_run_table(&text, format).map_err(|e| at(&e))? {
        whole_scene(path, &text, format)?
    } else {
        scene_file::read_statics(&text, format).map_err(|e| at(&e))?
    };
    if shapes.is_empty() {
        return Err(format!(
            "{}: no [[plane]], [[cylinder]] or [[container]]: nothing to query against",
            path.display()
        ));
    }
    Ok(shapes)
}

/// Whether the text has a `[run]` table: a whole scene, not the static tables alone.
fn has_run_table(text: &str, format: Format) -> Result<bool, String> {
    Ok(match format {
        Format::Json => serde_json::from_str::<serde_json::Value>(text)
            .map_err(|e| e.to_string())?
            .get("run")
            .is_some(),
        Format::Toml => toml::from_str::<toml::Table>(text)
            .map_err(|e| e.to_string())?
            .contains_key("run"),
    })
}

/// The static shapes of a whole scene file, built as `spheresweep run` builds it.
fn whole_scene(path: &Path, text: &str, format: Format) -> Result<Shapes, String> {
    let at = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let scene = SceneFile::from_text(text, format).map_err(|e| at(&e))?;
    // Its spheres are built (and ignored): refuse a count too large for memory.
    crate::memory::check_scene(path, &scene, size_of::<spheresweep::sim::SphereState>())?;
    let (world, _) = scene.build().map_err(|e| at(&e))?;
    Ok(world.statics.map(|_, _| ()))
}
