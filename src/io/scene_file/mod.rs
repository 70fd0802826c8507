//! Scene files: a simulation described in TOML (for people) or JSON (for programs), read into
//! a [`World`] and the [`RunSettings`] of a run. The format, field by field with units, ranges
//! and defaults: docs/scene-format.md.
//!
//! ```
//! use spheresweep::io::scene_file::SceneFile;
//! let scene = SceneFile::from_toml_str(r#"
//!     [run]
//!     t_end = 2.0
//!
//!     [[material]]
//!     name = "steel"
//!
//!     [[sphere]]
//!     centre = [0.0, 0.0, 3.0]
//!     velocity = [0.0, 0.0, -1.0]
//!     radius = 1.0
//!
//!     [[plane]]
//!     point = [0.0, 0.0, 0.0]
//!     normal = [0.0, 0.0, 1.0]
//! "#)?;
//! let (world, run) = scene.build()?;
//! assert_eq!((world.spheres.len(), world.statics.len(), run.t_end), (1, 1, 2.0));
//!
//! // A typo is refused, naming the field and its line.
//! let err = SceneFile::from_toml_str("[run]\nt_end = 1\nsnapshot_evry = 0.1\n").unwrap_err();
//! assert!(err.to_string().contains("line 3") && err.to_string().contains("snapshot_evry"));
//! # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
//! ```
//!
//! Every table refuses unknown fields. Items are counted from 0 within their kind, in file
//! order (`sphere 3` is the fourth `[[sphere]]`), as the engine counts spheres and shapes; the
//! world's spheres are the listed `[[sphere]]`s first, then each `[[generate]]` block's in
//! order. Errors found after parsing (an undeclared material, a field that does not belong to
//! a generator, an invalid shape, spheres that overlap) name the item and, for TOML, its line.
//!
//! The module by concern: `schema.rs` (the serde tables, as parsed), `error.rs`
//! ([`SceneFileError`]), `locate.rs` (an item's line in the TOML text, and the errors that
//! name it), `assemble.rs` (the checks and the [`World`] built from the tables) and `place.rs`
//! (the spheres of the `[[generate]]` blocks).

use std::path::{Path, PathBuf};

use crate::Statics;
use crate::sim::{Boundary, Simulation, World};

use glam::DVec3;

mod assemble;
mod error;
mod locate;
mod place;
mod schema;
#[cfg(test)]
mod tests;
mod warnings;

pub use error::SceneFileError;
pub use schema::{
    BoundaryKind, BoundaryTable, ContainerTable, CylinderTable, EffectsTable, GenerateKind,
    GenerateTable, MaterialTable, PairTable, PlaneTable, RunTable, SceneFile, SphereTable,
};

use locate::Seg::Key;
use schema::{Origin, ShapesFile};

/// The most spheres a scene file may ask for (the generators' own limit).
pub const MAX_SPHERES: usize = 1 << 28;

/// The text format of a scene file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// TOML, for people: errors name the line of the item.
    Toml,
    /// JSON, for programs.
    Json,
}

impl Format {
    /// JSON if the file's name ends in `.json` (any case), TOML otherwise.
    ///
    /// ```
    /// use spheresweep::io::scene_file::Format;
    /// use std::path::Path;
    /// assert_eq!(Format::of(Path::new("jet.JSON")), Format::Json);
    /// assert_eq!(Format::of(Path::new("jet.toml")), Format::Toml);
    /// ```
    pub fn of(path: &Path) -> Self {
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        {
            Format::Json
        } else {
            Format::Toml
        }
    }
}

/// Parses `text` into the tables `T`, and where it came from (for TOML, the text itself, to
/// locate errors by line).
fn parse<T: serde::de::DeserializeOwned>(
    text: &str,
    format: Format,
    file: Option<PathBuf>,
) -> Result<(T, Origin), SceneFileError> {
    let parsed = match format {
        Format::Toml => toml::from_str(text).map_err(|e| e.to_string()),
        Format::Json => serde_json::from_str(text).map_err(|e| json_message(text, &e)),
    };
    let tables = parsed.map_err(|message| SceneFileError::Syntax {
        file: file.clone(),
        message,
    })?;
    let toml = (format == Format::Toml).then(|| text.into());
    Ok((tables, Origin { file, toml }))
}

/// serde_json's message, and where it stopped at a `NaN` or an infinity (which JSON does not
/// have, and JavaScript's `JSON.stringify` writes as `null`), what the scene asks instead.
fn json_message(text: &str, e: &serde_json::Error) -> String {
    let at = text
        .lines()
        .nth(e.line().saturating_sub(1))
        .and_then(|line| line.get(e.column().saturating_sub(1)..))
        .unwrap_or("");
    let word = at.trim_start_matches(['-', '+']);
    // A whole word: `infinite: 1` (an unquoted key) is another mistake.
    let nonfinite = ["NaN", "nan", "Infinity", "infinity", "inf"]
        .iter()
        .any(|w| {
            word.strip_prefix(w)
                .is_some_and(|rest| !rest.starts_with(|c: char| c.is_alphanumeric() || c == '_'))
        });
    if e.is_syntax() && nonfinite {
        format!("{e} (JSON has no NaN or infinity: every number in a scene must be finite)")
    } else {
        e.to_string()
    }
}

/// The static shapes of a scene-file text alone: its `[[plane]]`, `[[cylinder]]` and
/// `[[container]]` tables (each kind in file order), and the `[[material]]` tables their
/// `material` fields name. Any other table is refused: a whole scene is a [`SceneFile`].
/// Every error names the item, the field and (TOML) the line, as a scene's do.
///
/// # Errors
/// [`SceneFileError::Syntax`] for text that does not parse or fit the tables (an unknown
/// table or field), [`SceneFileError::Item`] or [`SceneFileError::Shape`] for an item that
/// does not make sense (an undeclared material, a degenerate shape).
///
/// ```
/// use spheresweep::io::scene_file::{Format, read_statics};
/// let text = "[[plane]]\npoint = [0, 0, 0]\nnormal = [0, 0, 2]\n\n\
///     [[container]]\ncentre = [0, 0, 0]\nradius = 20\n";
/// let statics = read_statics(text, Format::Toml)?;
/// assert_eq!(statics.len(), 2);
/// assert_eq!(statics.of::<spheresweep::Plane>().shapes()[0].normal().z, 1.0); // normalised
/// let err = read_statics("[[cylinder]]\np1 = [1, 1, 1]\np2 = [1, 1, 1]\nradius = 1\n", Format::Toml);
/// assert_eq!(err.unwrap_err().to_string(), "line 3: cylinder 0: cylinder axis has zero length (degenerate direction)");
/// let err = read_statics("[run]\nt_end = 1\n", Format::Toml).unwrap_err(); // not a static shape
/// assert!(err.to_string().contains("unknown field `run`"));
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
pub fn read_statics(text: &str, format: Format) -> Result<Statics, SceneFileError> {
    let (tables, origin): (ShapesFile, Origin) = parse(text, format, None)?;
    let names = origin.material_names(&tables.material)?;
    let shapes =
        origin.static_shapes(&names, &tables.plane, &tables.cylinder, &tables.container)?;
    Ok(shapes.map(|_, _| ()))
}

/// How a run goes, from `[run]`.
///
/// ```
/// use spheresweep::io::scene_file::SceneFile;
/// let (_, run) = SceneFile::from_toml_str("[run]\nt_end = 3\nsnapshot_every = 0.5\n")?.build()?;
/// assert_eq!((run.t_end, run.snapshot_every, run.seed), (3.0, Some(0.5), 0));
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSettings {
    /// End time.
    pub t_end: f64,
    /// Time between snapshots, if any.
    pub snapshot_every: Option<f64>,
    /// Base seed.
    pub seed: u64,
}

impl SceneFile {
    /// Parses a TOML scene.
    ///
    /// # Errors
    /// [`SceneFileError::Syntax`] naming the line, column and key.
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// assert_eq!(SceneFile::from_toml_str("[run]\nt_end = 2\n")?.run.t_end, 2.0);
    /// let err = SceneFile::from_toml_str("[run]\n").unwrap_err(); // t_end is required
    /// assert!(err.to_string().contains("t_end"));
    /// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
    /// ```
    pub fn from_toml_str(text: &str) -> Result<Self, SceneFileError> {
        Self::parse(text, Format::Toml, None)
    }

    /// Parses a JSON scene (the same structure: `{"run": {"t_end": 1}, "sphere": [...]}`).
    ///
    /// # Errors
    /// [`SceneFileError::Syntax`] naming the line, column and key.
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// let json = r#"{"run": {"t_end": 1}, "sphere": [{"centre": [0, 0, 0], "radius": 1}]}"#;
    /// let scene = SceneFile::from_json_str(json)?;
    /// assert_eq!((scene.run.t_end, scene.sphere.len()), (1.0, 1));
    /// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
    /// ```
    pub fn from_json_str(text: &str) -> Result<Self, SceneFileError> {
        Self::parse(text, Format::Json, None)
    }

    /// Reads a scene file: JSON if its name ends in `.json`, TOML otherwise. Every message
    /// starts with the path.
    ///
    /// # Errors
    /// [`SceneFileError::Read`] naming the path, or a parse error prefixed with it.
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// let name = format!("spheresweep-doc-{}.json", std::process::id());
    /// let path = std::env::temp_dir().join(name);
    /// std::fs::write(&path, r#"{"run": {"t_end": 4}}"#).unwrap();
    /// let scene = SceneFile::from_path(&path); // read as JSON: the name ends in .json
    /// std::fs::remove_file(&path).unwrap();
    /// assert_eq!(scene?.run.t_end, 4.0);
    /// let missing = std::path::Path::new("/no/such/scene.toml");
    /// let missing = SceneFile::from_path(missing).unwrap_err();
    /// assert!(missing.to_string().starts_with("cannot read /no/such/scene.toml"));
    /// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
    /// ```
    pub fn from_path(path: &Path) -> Result<Self, SceneFileError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneFileError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text, Format::of(path), Some(path.to_path_buf()))
    }

    /// Parses a scene in either format (as [`from_toml_str`](Self::from_toml_str) or
    /// [`from_json_str`](Self::from_json_str)).
    ///
    /// # Errors
    /// [`SceneFileError::Syntax`] naming the line, column and key.
    ///
    /// ```
    /// use spheresweep::io::scene_file::{Format, SceneFile};
    /// let scene = SceneFile::from_text(r#"{"run": {"t_end": 3}}"#, Format::Json)?;
    /// assert_eq!(scene.run.t_end, 3.0);
    /// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
    /// ```
    pub fn from_text(text: &str, format: Format) -> Result<Self, SceneFileError> {
        Self::parse(text, format, None)
    }

    fn parse(text: &str, format: Format, file: Option<PathBuf>) -> Result<Self, SceneFileError> {
        let (mut scene, origin): (Self, Origin) = parse(text, format, file)?;
        scene.origin = origin;
        Ok(scene)
    }

    /// How many spheres [`build`](Self::build) would make: the `[[sphere]]` entries plus each
    /// `[[generate]]` block's count, read without generating anything, so that a caller can
    /// refuse a scene too large for memory before it is built. `None` if a block's count is
    /// missing or the total overflows (`build` then names the block).
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// let text = r#"
    ///     [run]
    ///     t_end = 1
    ///     [[sphere]]
    ///     centre = [0, 0, -5]
    ///     radius = 0.5
    ///     [[generate]]
    ///     kind = "lattice"
    ///     lo = [0, 0, 0]
    ///     counts = [10, 10, 10]
    ///     spacing = 1.5
    ///     radius = 0.5
    /// "#;
    /// assert_eq!(SceneFile::from_toml_str(text)?.sphere_count(), Some(1 + 1000)); // nothing generated yet
    /// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
    /// ```
    pub fn sphere_count(&self) -> Option<usize> {
        self.generate
            .iter()
            .try_fold(self.sphere.len(), |total, g| total.checked_add(g.count()?))
    }

    /// The file this scene was read from, if any.
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// assert_eq!(SceneFile::from_toml_str("[run]\nt_end = 1\n")?.path(), None); // not read from a file
    /// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
    /// ```
    pub fn path(&self) -> Option<&Path> {
        self.origin.file.as_deref()
    }

    /// Builds the world and the simulation in one step, naming the file's items in any error.
    ///
    /// # Errors
    /// As [`build`](Self::build), and [`Simulation::new`]'s errors through
    /// [`locate`](Self::locate).
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// let text = "[run]\nt_end = 2\n\
    ///     [[sphere]]\ncentre = [0, 0, 3]\nvelocity = [0, 0, -1]\nradius = 1\n\
    ///     [[plane]]\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n";
    /// let (mut sim, run) = SceneFile::from_toml_str(text)?.start()?;
    /// sim.advance_to(run.t_end)?;
    /// assert_eq!(sim.stats().wall_collisions, 1); // the floor at t = 2
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn start(&self) -> Result<(Simulation, RunSettings), SceneFileError> {
        let (world, run) = self.build()?;
        let sim = Simulation::new(world).map_err(|e| self.locate(e))?;
        Ok((sim, run))
    }

    /// Checks every item and builds the [`World`] (spheres, shapes, boundary, materials,
    /// effects) and the run's settings. Overlaps between spheres are checked by
    /// [`Simulation::new`] (see [`start`](Self::start) and [`locate`](Self::locate)).
    ///
    /// # Errors
    /// A [`SceneFileError`] naming the item, the field and (for TOML) the line.
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// use spheresweep::sim::Boundary;
    /// let text = "[run]\nt_end = 1\n[boundary]\nkind = \"periodic\"\n\
    ///     [[generate]]\nkind = \"periodic_gas\"\nn = 108\nphi = 0.2\nradius = 0.5\n";
    /// let (world, _) = SceneFile::from_toml_str(text)?.build()?;
    /// assert_eq!(world.spheres.len(), 108);
    /// assert!(matches!(world.boundary, Boundary::Periodic { size } if size.x > 0.0)); // set by the gas
    /// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
    /// ```
    pub fn build(&self) -> Result<(World, RunSettings), SceneFileError> {
        let run = self.run_settings()?;
        let materials = self.materials()?;
        let effects = self.effects(&materials)?;
        let mut world = World {
            materials,
            effects,
            ..World::default()
        };
        let periodic_size = self.boundary(&mut world)?;
        self.shapes(&mut world)?;
        for (i, s) in self.sphere.iter().enumerate() {
            world
                .spheres
                .push(self.listed_sphere(i, s, &world.materials)?);
        }
        self.generated(&mut world, periodic_size, run.seed)?;
        if let Boundary::Periodic { size } = world.boundary
            && size == DVec3::ZERO
        {
            return Err(self.item_error(
                "boundary",
                &[Key("boundary"), Key("kind")],
                "a periodic boundary needs `size`, or a `periodic_gas` generator to set it".into(),
            ));
        }
        world.validate().map_err(|e| self.locate(e))?;
        Ok((world, run))
    }
}
