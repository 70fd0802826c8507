//! The shapes file of `--against`: the `[[plane]]`, `[[cylinder]]` and `[[container]]` tables
//! of the scene-file format (docs/scene-format.md), read by `io::scene_file` so that every
//! field, unit and message is the scene file's. A whole scene file is accepted too: its other
//! tables are checked as in `spheresweep run`, and its spheres are not part of the query.

use std::path::Path;

use spheresweep::io::scene_file::SceneFile;

use super::compute::Shapes;

/// A `[run]` table for a shapes file that has none (the scene format requires one; a query
/// has no use for it). Appended at the end, so the lines of the file's own items stay put.
const RUN_TOML: &str = "\n[run]\nt_end = 1.0\n";

/// The same for a JSON shapes file, inserted as the first member of the top-level object.
const RUN_JSON: &str = r#""run": {"t_end": 1.0}, "#;

/// Reads the shapes of `path`: TOML, or JSON if its name ends in `.json`.
pub fn read(path: &Path) -> Result<Shapes, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let at = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let scene = if json {
        let value: serde_json::Value = serde_json::from_str(&text).map_err(|e| at(&e))?;
        if value.as_object().is_some_and(|o| o.is_empty()) {
            return Err(no_shapes(path));
        }
        let needs_run = value.as_object().is_some_and(|o| !o.contains_key("run"));
        match text.find('{') {
            // Inserted just inside the opening brace, on its line: every line keeps its number.
            Some(brace) if needs_run => {
                let (head, tail) = text.split_at(brace + 1);
                SceneFile::from_json_str(&format!("{head}{RUN_JSON}{tail}"))
            }
            _ => SceneFile::from_json_str(&text),
        }
        .map_err(|e| at(&e))?
    } else {
        let table: toml::Table = toml::from_str(&text).map_err(|e| at(&e))?;
        if table.contains_key("run") {
            SceneFile::from_toml_str(&text).map_err(|e| at(&e))?
        } else {
            SceneFile::from_toml_str(&format!("{text}{RUN_TOML}")).map_err(|e| at(&e))?
        }
    };
    // Spheres in a shapes file are built (and ignored): refuse a count too large for memory.
    crate::memory::check_scene(path, &scene, size_of::<spheresweep::sim::SphereState>())?;
    let (world, _) = scene.build().map_err(|e| at(&e))?;
    let shapes = world.statics.map(|_, _| ());
    if shapes.is_empty() {
        return Err(no_shapes(path));
    }
    Ok(shapes)
}

fn no_shapes(path: &Path) -> String {
    format!(
        "{}: no [[plane]], [[cylinder]] or [[container]]: nothing to query against",
        path.display()
    )
}
