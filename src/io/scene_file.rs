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
//! assert_eq!((world.spheres.len(), world.planes.len(), run.t_end), (1, 1, 2.0));
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

use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;
use serde::Deserialize;

use crate::error::ShapeError;
use crate::sim::{
    Boundary, Effects, MaterialPair, Response, SimError, Simulation, SphereState, World, generate,
};
use crate::{Container, Cylinder, Plane, ShapeKind};

/// The most spheres a scene file may ask for (the generators' own limit).
pub const MAX_SPHERES: usize = 1 << 28;

/// A whole scene file, as parsed (nothing checked beyond the types yet; [`SceneFile::build`]
/// checks the rest).
///
/// ```
/// use spheresweep::io::scene_file::SceneFile;
/// let scene = SceneFile::from_toml_str("[run]\nt_end = 1\n[[sphere]]\ncentre = [0, 0, 0]\nradius = 1\n")?;
/// assert_eq!((scene.sphere.len(), scene.plane.len(), scene.boundary), (1, 0, None));
/// assert_eq!(scene.sphere[0].mass, 1.0); // the default, filled in when parsed
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// `[run]`: how long, how often to take a snapshot, the base seed.
    pub run: RunTable,
    /// `[boundary]`: open space (the default), an open box for the cell grid, or a periodic
    /// box.
    #[serde(default)]
    pub boundary: Option<BoundaryTable>,
    /// `[[material]]`: material names, in index order; the first is the default.
    #[serde(default)]
    pub material: Vec<MaterialTable>,
    /// `[effects]`: what collisions do and what is recorded.
    #[serde(default)]
    pub effects: EffectsTable,
    /// `[[sphere]]`: spheres listed one by one.
    #[serde(default)]
    pub sphere: Vec<SphereTable>,
    /// `[[generate]]`: generated blocks of spheres.
    #[serde(default)]
    pub generate: Vec<GenerateTable>,
    /// `[[plane]]`: static infinite planes.
    #[serde(default)]
    pub plane: Vec<PlaneTable>,
    /// `[[cylinder]]`: static infinite cylinders.
    #[serde(default)]
    pub cylinder: Vec<CylinderTable>,
    /// `[[container]]`: static spherical containers.
    #[serde(default)]
    pub container: Vec<ContainerTable>,
    #[serde(skip)]
    origin: Origin,
}

/// Where a scene came from, for messages: its path and, for TOML, its text (to find lines).
#[derive(Debug, Clone, Default)]
struct Origin {
    file: Option<PathBuf>,
    toml: Option<Arc<str>>,
}

/// `[run]`.
///
/// ```
/// use spheresweep::io::scene_file::{RunTable, SceneFile};
/// let scene = SceneFile::from_toml_str("[run]\nt_end = 5.0\nseed = 9\n")?;
/// assert_eq!(scene.run, RunTable { t_end: 5.0, snapshot_every: None, seed: 9 });
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunTable {
    /// End time of the run (`> 0`, finite).
    pub t_end: f64,
    /// Time between snapshots (`> 0`); none: no trajectory.
    #[serde(default)]
    pub snapshot_every: Option<f64>,
    /// Base seed: a generator without its own seed uses `seed + its block index`.
    #[serde(default)]
    pub seed: u64,
}

/// `[boundary] kind`.
///
/// ```
/// use spheresweep::io::scene_file::{BoundaryKind, SceneFile};
/// let scene = SceneFile::from_toml_str("[run]\nt_end = 1\n[boundary]\nkind = \"periodic\"\n")?;
/// assert_eq!(scene.boundary.unwrap().kind, BoundaryKind::Periodic);
/// assert_eq!(BoundaryKind::default(), BoundaryKind::Open);
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundaryKind {
    /// Open space; the cell grid covers the start.
    #[default]
    Open,
    /// Open space; the cell grid covers `[lo, hi]`.
    Box,
    /// Periodic box `[0, size)`.
    Periodic,
}

/// `[boundary]`.
///
/// ```
/// use spheresweep::io::scene_file::{BoundaryKind, SceneFile};
/// let text = "[run]\nt_end = 1\n[boundary]\nkind = \"box\"\nlo = [0, 0, 0]\nhi = [5, 5, 5]\n";
/// let boundary = SceneFile::from_toml_str(text)?.boundary.unwrap();
/// assert_eq!((boundary.kind, boundary.hi), (BoundaryKind::Box, Some([5.0; 3])));
/// assert_eq!(boundary.size, None); // for `periodic` only
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryTable {
    /// Which boundary.
    #[serde(default)]
    pub kind: BoundaryKind,
    /// Periodic box lengths (set by a `periodic_gas` generator when omitted).
    #[serde(default)]
    pub size: Option<[f64; 3]>,
    /// Lower corner of a `box`.
    #[serde(default)]
    pub lo: Option<[f64; 3]>,
    /// Upper corner of a `box`.
    #[serde(default)]
    pub hi: Option<[f64; 3]>,
}

/// `[[material]]`.
///
/// ```
/// use spheresweep::io::scene_file::SceneFile;
/// let text = "[run]\nt_end = 1\n[[material]]\nname = \"glass\"\n[[material]]\nname = \"glue\"\n";
/// let scene = SceneFile::from_toml_str(text)?;
/// let names: Vec<&str> = scene.material.iter().map(|m| m.name.as_str()).collect();
/// assert_eq!(names, ["glass", "glue"]); // material 0 is the default
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialTable {
    /// Its name (unique, not empty).
    pub name: String,
}

/// A response by name.
///
/// ```
/// use spheresweep::io::scene_file::{ResponseKind, SceneFile};
/// let scene = SceneFile::from_toml_str("[run]\nt_end = 1\n[effects]\nresponse = \"sticky\"\n")?;
/// assert_eq!(scene.effects.response, ResponseKind::Sticky);
/// assert_eq!(ResponseKind::default(), ResponseKind::Elastic);
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ResponseKind {
    /// Contacts are reported only; spheres pass through each other.
    None,
    /// Elastic collisions.
    #[default]
    Elastic,
    /// Inelastic collisions with a coefficient of restitution.
    Inelastic,
    /// Spheres that meet join into clusters.
    Sticky,
}

impl ResponseKind {
    fn name(self) -> &'static str {
        match self {
            ResponseKind::None => "none",
            ResponseKind::Elastic => "elastic",
            ResponseKind::Inelastic => "inelastic",
            ResponseKind::Sticky => "sticky",
        }
    }
}

/// `[effects]`.
///
/// ```
/// use spheresweep::io::scene_file::{ResponseKind, SceneFile};
/// let text = "[run]\nt_end = 1\n[effects]\nresponse = \"inelastic\"\nrestitution = 0.8\ntc = 1e-4\n";
/// let effects = SceneFile::from_toml_str(text)?.effects;
/// assert_eq!((effects.response, effects.restitution), (ResponseKind::Inelastic, Some(0.8)));
/// assert_eq!(effects.tc, 1e-4);
/// assert!(!effects.record_events && effects.pair.is_empty());
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectsTable {
    /// Response of every pair of materials not listed in `pair`.
    #[serde(default)]
    pub response: ResponseKind,
    /// Coefficient of restitution for `inelastic`, in `[0, 1]`.
    #[serde(default)]
    pub restitution: Option<f64>,
    /// The TC model's duration (`≥ 0`; 0 turns it off).
    #[serde(default)]
    pub tc: f64,
    /// Whether recorded events carry the contact point and normal.
    #[serde(default)]
    pub geometry: bool,
    /// Whether every collision is recorded.
    #[serde(default)]
    pub record_events: bool,
    /// `[[effects.pair]]`: per-pair-of-materials overrides.
    #[serde(default)]
    pub pair: Vec<PairTable>,
}

/// `[[effects.pair]]`.
///
/// ```
/// use spheresweep::io::scene_file::{ResponseKind, SceneFile};
/// let text = r#"
///     [run]
///     t_end = 1
///     [[material]]
///     name = "glue"
///     [[material]]
///     name = "glass"
///     [[effects.pair]]
///     a = "glue"
///     b = "glue"
///     response = "sticky"
/// "#;
/// let pair = &SceneFile::from_toml_str(text)?.effects.pair[0];
/// assert_eq!((pair.a.as_str(), pair.b.as_str()), ("glue", "glue"));
/// assert_eq!(pair.response, ResponseKind::Sticky);
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairTable {
    /// One material's name.
    pub a: String,
    /// The other's (may equal `a`).
    pub b: String,
    /// What their collisions do (not `none`).
    pub response: ResponseKind,
    /// Coefficient of restitution for `inelastic`, in `[0, 1]`.
    #[serde(default)]
    pub restitution: Option<f64>,
}

fn zero3() -> [f64; 3] {
    [0.0; 3]
}
fn one() -> f64 {
    1.0
}

/// `[[sphere]]`.
///
/// ```
/// use spheresweep::io::scene_file::SceneFile;
/// let scene = SceneFile::from_toml_str("[run]\nt_end = 1\n[[sphere]]\ncentre = [1, 2, 3]\nradius = 0.5\n")?;
/// let s = &scene.sphere[0];
/// assert_eq!((s.centre, s.velocity, s.radius), ([1.0, 2.0, 3.0], [0.0; 3], 0.5));
/// assert_eq!((s.mass, s.material.as_deref()), (1.0, None)); // the defaults
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereTable {
    /// Centre at `t = 0`.
    pub centre: [f64; 3],
    /// Velocity (default at rest).
    #[serde(default = "zero3")]
    pub velocity: [f64; 3],
    /// Radius (`> 0`).
    pub radius: f64,
    /// Mass (`> 0`, default 1).
    #[serde(default = "one")]
    pub mass: f64,
    /// Material name (default the first declared).
    #[serde(default)]
    pub material: Option<String>,
}

/// `[[generate]] kind`.
///
/// ```
/// use spheresweep::io::scene_file::{GenerateKind, SceneFile};
/// let text = "[run]\nt_end = 1\n[[generate]]\nkind = \"periodic_gas\"\nn = 10\nphi = 0.1\nradius = 0.5\n";
/// assert_eq!(SceneFile::from_toml_str(text)?.generate[0].kind, GenerateKind::PeriodicGas);
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GenerateKind {
    /// A thermal gas on an FCC lattice filling a periodic box at a packing fraction.
    PeriodicGas,
    /// Non-overlapping spheres at random in a box or a container.
    Random,
    /// A stream fired from a nozzle.
    Nozzle,
    /// A simple cubic lattice.
    Lattice,
}

impl GenerateKind {
    fn name(self) -> &'static str {
        match self {
            GenerateKind::PeriodicGas => "periodic_gas",
            GenerateKind::Random => "random",
            GenerateKind::Nozzle => "nozzle",
            GenerateKind::Lattice => "lattice",
        }
    }
    /// The fields this kind takes beyond `kind`, `material`, `seed` and `mass`: (required,
    /// optional).
    fn fields(self) -> (&'static [&'static str], &'static [&'static str]) {
        match self {
            GenerateKind::PeriodicGas => (&["n", "phi", "radius"], &["temperature"]),
            GenerateKind::Random => (&["n", "radius"], &["speed", "lo", "hi", "inside"]),
            GenerateKind::Nozzle => (
                &["origin", "direction", "n", "radius", "speed"],
                &["spacing", "spread", "jitter"],
            ),
            GenerateKind::Lattice => (&["lo", "counts", "spacing", "radius"], &["speed"]),
        }
    }
}

/// `[[generate]]`: one block of generated spheres. Which fields apply depends on `kind`
/// (docs/scene-format.md); a field that does not apply is an error.
///
/// ```
/// use spheresweep::io::scene_file::{GenerateKind, SceneFile};
/// let text = r#"
///     [run]
///     t_end = 1
///     [[generate]]
///     kind = "lattice"
///     lo = [0, 0, 0]
///     counts = [2, 2, 2]
///     spacing = 1.5
///     radius = 0.5
/// "#;
/// let scene = SceneFile::from_toml_str(text)?;
/// let block = &scene.generate[0];
/// assert_eq!((block.kind, block.counts, block.n), (GenerateKind::Lattice, Some([2, 2, 2]), None));
/// assert_eq!(scene.build()?.0.spheres.len(), 8);
/// // A field of another kind is refused when built, naming it.
/// let wrong = SceneFile::from_toml_str(&format!("{text}    phi = 0.3\n"))?;
/// let message = wrong.build().unwrap_err().to_string();
/// assert!(message.contains("`phi` does not apply to kind = \"lattice\""));
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GenerateTable {
    /// The generator.
    pub kind: GenerateKind,
    /// Material of every sphere of the block (default the first declared).
    #[serde(default)]
    pub material: Option<String>,
    /// Seed (default `run.seed + the block's index`).
    #[serde(default)]
    pub seed: Option<u64>,
    /// Mass of every sphere (`> 0`, default 1).
    #[serde(default)]
    pub mass: Option<f64>,
    /// Number of spheres (`periodic_gas`, `random`, `nozzle`).
    #[serde(default)]
    pub n: Option<usize>,
    /// Packing fraction (`periodic_gas`).
    #[serde(default)]
    pub phi: Option<f64>,
    /// Sphere radius.
    #[serde(default)]
    pub radius: Option<f64>,
    /// `kT` (`periodic_gas`, default 1).
    #[serde(default)]
    pub temperature: Option<f64>,
    /// Speed (`random`, `lattice`: random directions, default 0; `nozzle`: along the stream).
    #[serde(default)]
    pub speed: Option<f64>,
    /// Lower corner (`random`: region; `lattice`: first site).
    #[serde(default)]
    pub lo: Option<[f64; 3]>,
    /// Upper corner of a `random` region.
    #[serde(default)]
    pub hi: Option<[f64; 3]>,
    /// Container index whose inside a `random` block fills.
    #[serde(default)]
    pub inside: Option<usize>,
    /// Nozzle exit (the first sphere's centre).
    #[serde(default)]
    pub origin: Option<[f64; 3]>,
    /// Nozzle direction (any non-zero length).
    #[serde(default)]
    pub direction: Option<[f64; 3]>,
    /// Distance between centres (`nozzle`: default 2.2 radii; `lattice`).
    #[serde(default)]
    pub spacing: Option<f64>,
    /// Largest tilt of a nozzle velocity from the direction, radians (default 0).
    #[serde(default)]
    pub spread: Option<f64>,
    /// Largest sideways offset at the nozzle (default 0).
    #[serde(default)]
    pub jitter: Option<f64>,
    /// Lattice sites per axis.
    #[serde(default)]
    pub counts: Option<[usize; 3]>,
}

impl GenerateTable {
    /// The kind-specific fields that are set.
    fn set_fields(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        let mut is = |name, set: bool| {
            if set {
                out.push(name);
            }
        };
        is("n", self.n.is_some());
        is("phi", self.phi.is_some());
        is("radius", self.radius.is_some());
        is("temperature", self.temperature.is_some());
        is("speed", self.speed.is_some());
        is("lo", self.lo.is_some());
        is("hi", self.hi.is_some());
        is("inside", self.inside.is_some());
        is("origin", self.origin.is_some());
        is("direction", self.direction.is_some());
        is("spacing", self.spacing.is_some());
        is("spread", self.spread.is_some());
        is("jitter", self.jitter.is_some());
        is("counts", self.counts.is_some());
        out
    }

    /// How many spheres the block makes (before it is built; `None` if the count is missing
    /// or overflows).
    fn count(&self) -> Option<usize> {
        match self.kind {
            GenerateKind::Lattice => {
                let c = self.counts?;
                c[0].checked_mul(c[1])?.checked_mul(c[2])
            }
            _ => self.n,
        }
    }
}

/// `[[plane]]`.
///
/// ```
/// use spheresweep::io::scene_file::SceneFile;
/// let text = "[run]\nt_end = 1\n[[plane]]\npoint = [0, 0, 0]\nnormal = [0, 0, 2]\n";
/// let scene = SceneFile::from_toml_str(text)?;
/// assert_eq!(scene.plane[0].normal, [0.0, 0.0, 2.0]); // as written
/// assert_eq!(scene.build()?.0.planes[0].shape.normal().z, 1.0); // normalised when built
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaneTable {
    /// A point on the plane.
    pub point: [f64; 3],
    /// Its normal (any non-zero length).
    pub normal: [f64; 3],
    /// Material name (default the first declared).
    #[serde(default)]
    pub material: Option<String>,
}

/// `[[cylinder]]`.
///
/// ```
/// use spheresweep::io::scene_file::SceneFile;
/// let text = "[run]\nt_end = 1\n[[cylinder]]\np1 = [3, 0, 0]\np2 = [3, 0, 1]\nradius = 1\n";
/// let (world, _) = SceneFile::from_toml_str(text)?.build()?;
/// assert_eq!(world.cylinders[0].shape.axis().to_array(), [0.0, 0.0, 1.0]);
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CylinderTable {
    /// A point on the axis.
    pub p1: [f64; 3],
    /// Another point on the axis.
    pub p2: [f64; 3],
    /// Radius (`≥ 0`).
    pub radius: f64,
    /// Material name (default the first declared).
    #[serde(default)]
    pub material: Option<String>,
}

/// `[[container]]`.
///
/// ```
/// use spheresweep::io::scene_file::SceneFile;
/// let text = "[run]\nt_end = 1\n[[container]]\ncentre = [0, 0, 0]\nradius = -1\n";
/// let err = SceneFile::from_toml_str(text)?.build().unwrap_err();
/// assert_eq!(err.to_string(), "line 5: container 0: container radius is negative");
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContainerTable {
    /// Centre.
    pub centre: [f64; 3],
    /// Inner radius (`≥ 0`).
    pub radius: f64,
    /// Material name (default the first declared).
    #[serde(default)]
    pub material: Option<String>,
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

/// Why a scene file could not be read or built. Its message starts with the file (when read
/// from one) and the line (when known), then names the item and the field.
///
/// ```
/// use spheresweep::io::scene_file::{SceneFile, SceneFileError};
/// let text = "[run]\nt_end = 1\n[[sphere]]\ncentre = [0, 0, 0]\nradius = 1\nmaterial = \"rubber\"\n";
/// let err = SceneFile::from_toml_str(text)?.build().unwrap_err();
/// assert!(matches!(&err, SceneFileError::Item { line: Some(6), item, .. } if item == "sphere 0"));
/// let message = r#"line 6: sphere 0: material "rubber" is not declared (declared: "default")"#;
/// assert_eq!(err.to_string(), message);
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug)]
#[non_exhaustive]
pub enum SceneFileError {
    /// The file could not be read.
    Read {
        /// The path.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The text is not valid TOML or JSON, or does not fit the format (a typo'd field, a
    /// wrong type, a missing required field). The message is the parser's: it names the line,
    /// the column and the key.
    Syntax {
        /// The file, if read from one.
        file: Option<PathBuf>,
        /// The parser's message.
        message: String,
    },
    /// An item that parsed but does not make sense (an undeclared material, a field that does
    /// not belong to its generator, a value out of range).
    Item {
        /// The file, if read from one.
        file: Option<PathBuf>,
        /// The line of the item or field (TOML only).
        line: Option<usize>,
        /// The item (`"sphere 3"`, `"generate 1 (nozzle)"`, `"boundary"`).
        item: String,
        /// What is wrong.
        problem: String,
    },
    /// The simulation refused an item (overlapping spheres, a generator's parameters).
    Sim {
        /// The file, if read from one.
        file: Option<PathBuf>,
        /// The line of the (first) item named.
        line: Option<usize>,
        /// The item or items.
        item: String,
        /// The simulation's error.
        source: SimError,
    },
    /// A shape's constructor refused an item.
    Shape {
        /// The file, if read from one.
        file: Option<PathBuf>,
        /// The line of the item or field.
        line: Option<usize>,
        /// The item (`"plane 0"`).
        item: String,
        /// The constructor's error.
        source: ShapeError,
    },
}

impl fmt::Display for SceneFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = |f: &mut fmt::Formatter<'_>, file: &Option<PathBuf>, line: &Option<usize>| match (
            file, line,
        ) {
            (Some(p), Some(l)) => write!(f, "{}:{l}: ", p.display()),
            (Some(p), None) => write!(f, "{}: ", p.display()),
            (None, Some(l)) => write!(f, "line {l}: "),
            (None, None) => Ok(()),
        };
        match self {
            SceneFileError::Read { path, source } => {
                write!(f, "cannot read {}: {source}", path.display())
            }
            SceneFileError::Syntax { file, message } => {
                at(f, file, &None)?;
                f.write_str(message.trim_end())
            }
            SceneFileError::Item {
                file,
                line,
                item,
                problem,
            } => {
                at(f, file, line)?;
                write!(f, "{item}: {problem}")
            }
            SceneFileError::Sim {
                file,
                line,
                item,
                source,
            } => {
                at(f, file, line)?;
                write!(f, "{item}: {source}")
            }
            SceneFileError::Shape {
                file,
                line,
                item,
                source,
            } => {
                at(f, file, line)?;
                write!(f, "{item}: {source}")
            }
        }
    }
}

impl std::error::Error for SceneFileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SceneFileError::Read { source, .. } => Some(source),
            SceneFileError::Sim { source, .. } => Some(source),
            SceneFileError::Shape { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// One step of a path into the file: a key or an array index.
#[derive(Debug, Clone, Copy)]
enum Seg {
    Key(&'static str),
    At(usize),
}
use Seg::{At, Key};

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
        Self::toml(text, None)
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
        Self::json(text, None)
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
        let file = Some(path.to_path_buf());
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        {
            Self::json(&text, file)
        } else {
            Self::toml(&text, file)
        }
    }

    fn toml(text: &str, file: Option<PathBuf>) -> Result<Self, SceneFileError> {
        let mut scene: Self = toml::from_str(text).map_err(|e| SceneFileError::Syntax {
            file: file.clone(),
            message: e.to_string(),
        })?;
        scene.origin = Origin {
            file,
            toml: Some(text.into()),
        };
        Ok(scene)
    }

    fn json(text: &str, file: Option<PathBuf>) -> Result<Self, SceneFileError> {
        let mut scene: Self = serde_json::from_str(text).map_err(|e| SceneFileError::Syntax {
            file: file.clone(),
            message: e.to_string(),
        })?;
        scene.origin = Origin { file, toml: None };
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

    /// The line of the value at `path` in the TOML text (the key's line for a field, the
    /// header's for an array element); the nearest enclosing item's when the field is absent.
    fn line(&self, path: &[Seg]) -> Option<usize> {
        let text = self.origin.toml.as_deref()?;
        let root = toml::de::DeTable::parse(text).ok()?;
        let mut offset = None;
        let mut table = Some(root.get_ref());
        let mut value: Option<&toml::de::DeValue<'_>> = None;
        for seg in path {
            match *seg {
                Key(name) => {
                    let t = table.take().or_else(|| value.and_then(|v| v.as_table()))?;
                    let Some((k, v)) = t.iter().find(|(k, _)| k.get_ref().as_ref() == name) else {
                        break;
                    };
                    offset = Some(k.span().start);
                    value = Some(v.get_ref());
                }
                At(i) => {
                    let Some(e) = value.and_then(|v| v.as_array()).and_then(|a| a.get(i)) else {
                        break;
                    };
                    offset = Some(e.span().start);
                    value = Some(e.get_ref());
                }
            }
        }
        let offset = offset?;
        Some(text.get(..offset)?.matches('\n').count() + 1)
    }

    fn item_error(&self, item: impl Into<String>, path: &[Seg], problem: String) -> SceneFileError {
        SceneFileError::Item {
            file: self.origin.file.clone(),
            line: self.line(path),
            item: item.into(),
            problem,
        }
    }

    fn sim_error(&self, item: impl Into<String>, path: &[Seg], source: SimError) -> SceneFileError {
        SceneFileError::Sim {
            file: self.origin.file.clone(),
            line: self.line(path),
            item: item.into(),
            source,
        }
    }

    fn shape_error(
        &self,
        item: impl Into<String>,
        path: &[Seg],
        source: ShapeError,
    ) -> SceneFileError {
        SceneFileError::Shape {
            file: self.origin.file.clone(),
            line: self.line(path),
            item: item.into(),
            source,
        }
    }

    /// The item a sphere of the world came from, and its path in the file.
    fn sphere_item(&self, index: usize) -> (String, Vec<Seg>) {
        if index < self.sphere.len() {
            return (format!("sphere {index}"), vec![Key("sphere"), At(index)]);
        }
        let mut start = self.sphere.len();
        for (b, g) in self.generate.iter().enumerate() {
            let n = g.count().unwrap_or(0);
            if index < start + n {
                return (
                    format!(
                        "generate {b} ({}), its sphere {}",
                        g.kind.name(),
                        index - start
                    ),
                    vec![Key("generate"), At(b)],
                );
            }
            start += n;
        }
        (format!("sphere {index}"), Vec::new())
    }

    /// Names the items of the file behind an error of [`Simulation::new`] or
    /// [`World::validate`] on the world [`build`](Self::build) made (overlapping spheres are
    /// named by their `[[sphere]]` or `[[generate]]` entry).
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// use spheresweep::sim::Simulation;
    /// let text = "[run]\nt_end = 1\n\
    ///     [[sphere]]\ncentre = [0, 0, 0]\nradius = 1\n\
    ///     [[sphere]]\ncentre = [1, 0, 0]\nradius = 1\n";
    /// let scene = SceneFile::from_toml_str(text)?;
    /// let (world, _) = scene.build()?; // overlaps are the engine's to find
    /// let err = scene.locate(Simulation::new(world).unwrap_err());
    /// assert!(err.to_string().starts_with("line 3: sphere 0 and sphere 1: spheres 0 and 1 overlap"));
    /// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
    /// ```
    pub fn locate(&self, err: SimError) -> SceneFileError {
        match &err {
            SimError::Overlap { a, b, .. } => {
                let (ia, pa) = self.sphere_item(*a);
                let (ib, _) = self.sphere_item(*b);
                self.sim_error(format!("{ia} and {ib}"), &pa, err)
            }
            SimError::Sphere { index, .. } => {
                let (item, path) = self.sphere_item(*index);
                self.sim_error(item, &path, err)
            }
            SimError::Penetrates {
                sphere,
                shape,
                index,
                ..
            } => {
                let (item, path) = self.sphere_item(*sphere);
                let key = match shape {
                    ShapeKind::Plane => "plane",
                    ShapeKind::Cylinder => "cylinder",
                    _ => "container",
                };
                self.sim_error(format!("{item} and {key} {index}"), &path, err)
            }
            SimError::Box { .. } => self.sim_error("boundary", &[Key("boundary")], err),
            _ => self.sim_error("scene", &[], err),
        }
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

    fn run_settings(&self) -> Result<RunSettings, SceneFileError> {
        let r = &self.run;
        if !(r.t_end.is_finite() && r.t_end > 0.0) {
            return Err(self.item_error(
                "run",
                &[Key("run"), Key("t_end")],
                format!("t_end = {:?} must be finite and greater than 0", r.t_end),
            ));
        }
        if let Some(every) = r.snapshot_every
            && !(every.is_finite() && every > 0.0)
        {
            return Err(self.item_error(
                "run",
                &[Key("run"), Key("snapshot_every")],
                format!("snapshot_every = {every:?} must be finite and greater than 0"),
            ));
        }
        Ok(RunSettings {
            t_end: r.t_end,
            snapshot_every: r.snapshot_every,
            seed: r.seed,
        })
    }

    fn materials(&self) -> Result<Vec<String>, SceneFileError> {
        if self.material.is_empty() {
            return Ok(vec!["default".into()]);
        }
        if self.material.len() > crate::sim::MAX_MATERIALS {
            let max = crate::sim::MAX_MATERIALS;
            return Err(self.item_error(
                format!("material {max}"),
                &[Key("material"), At(max)],
                format!("at most {max} materials"),
            ));
        }
        let mut names: Vec<String> = Vec::with_capacity(self.material.len());
        for (i, m) in self.material.iter().enumerate() {
            let path = [Key("material"), At(i), Key("name")];
            if m.name.trim().is_empty() {
                return Err(self.item_error(
                    format!("material {i}"),
                    &path,
                    "name is empty".into(),
                ));
            }
            if let Some(j) = names.iter().position(|n| *n == m.name) {
                return Err(self.item_error(
                    format!("material {i}"),
                    &path,
                    format!("name {:?} is already material {j}", m.name),
                ));
            }
            names.push(m.name.clone());
        }
        Ok(names)
    }

    /// The index of a material named by `item` (the first when `name` is `None`).
    fn material_index(
        &self,
        names: &[String],
        name: Option<&str>,
        item: &str,
        path: &[Seg],
    ) -> Result<u16, SceneFileError> {
        let Some(name) = name else { return Ok(0) };
        match names.iter().position(|n| n == name) {
            // At most MAX_MATERIALS names (checked in `materials`).
            Some(i) => Ok(i as u16),
            None => Err(self.item_error(
                item,
                path,
                format!(
                    "material {name:?} is not declared (declared: {})",
                    names
                        .iter()
                        .map(|n| format!("{n:?}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )),
        }
    }

    fn response(
        &self,
        kind: ResponseKind,
        restitution: Option<f64>,
        item: &str,
        path: &[Seg],
    ) -> Result<Response, SceneFileError> {
        let mut at: Vec<Seg> = path.to_vec();
        at.push(Key("restitution"));
        match (kind, restitution) {
            (ResponseKind::Inelastic, Some(e)) if (0.0..=1.0).contains(&e) => {
                Ok(Response::Inelastic { restitution: e })
            }
            (ResponseKind::Inelastic, Some(e)) => {
                Err(self.item_error(item, &at, format!("restitution = {e:?} must be in [0, 1]")))
            }
            (ResponseKind::Inelastic, None) => Err(self.item_error(
                item,
                path,
                "response = \"inelastic\" needs `restitution` (in [0, 1])".into(),
            )),
            (k, Some(_)) => Err(self.item_error(
                item,
                &at,
                format!(
                    "restitution applies only to response = \"inelastic\", not {:?}",
                    k.name()
                ),
            )),
            (ResponseKind::None, None) => Ok(Response::None),
            (ResponseKind::Elastic, None) => Ok(Response::Elastic),
            (ResponseKind::Sticky, None) => Ok(Response::Sticky),
        }
    }

    fn effects(&self, names: &[String]) -> Result<Effects, SceneFileError> {
        let e = &self.effects;
        let response = self.response(e.response, e.restitution, "effects", &[Key("effects")])?;
        if !(e.tc.is_finite() && e.tc >= 0.0) {
            return Err(self.item_error(
                "effects",
                &[Key("effects"), Key("tc")],
                format!("tc = {:?} must be finite and at least 0", e.tc),
            ));
        }
        let mut pairs = Vec::with_capacity(e.pair.len());
        for (i, p) in e.pair.iter().enumerate() {
            let item = format!("effects.pair {i}");
            let path = [Key("effects"), Key("pair"), At(i)];
            let at = |k| [Key("effects"), Key("pair"), At(i), Key(k)];
            let a = self.material_index(names, Some(&p.a), &item, &at("a"))?;
            let b = self.material_index(names, Some(&p.b), &item, &at("b"))?;
            let r = self.response(p.response, p.restitution, &item, &path)?;
            if r == Response::None {
                return Err(self.item_error(
                    item,
                    &at("response"),
                    "response = \"none\" applies to a whole scene ([effects] response), not to one pair".into(),
                ));
            }
            if response == Response::None {
                return Err(self.item_error(
                    item,
                    &path,
                    "[effects] response = \"none\" reports contacts only: a pair cannot change that".into(),
                ));
            }
            pairs.push(MaterialPair { a, b, response: r });
        }
        Ok(Effects {
            response,
            pairs,
            tc: e.tc,
            geometry: e.geometry,
            record_events: e.record_events,
        })
    }

    /// Sets the world's boundary; returns the periodic size if one was given.
    fn boundary(&self, world: &mut World) -> Result<Option<DVec3>, SceneFileError> {
        let Some(b) = &self.boundary else {
            return Ok(None);
        };
        let at = |k| [Key("boundary"), Key(k)];
        let not_for = |field: &'static str, set: bool| {
            if set {
                Err(self.item_error(
                    "boundary",
                    &at(field),
                    format!(
                        "`{field}` does not apply to kind = {:?}",
                        match b.kind {
                            BoundaryKind::Open => "open",
                            BoundaryKind::Box => "box",
                            BoundaryKind::Periodic => "periodic",
                        }
                    ),
                ))
            } else {
                Ok(())
            }
        };
        let finite = |field: &'static str, v: [f64; 3]| {
            let v = DVec3::from_array(v);
            if v.is_finite() {
                Ok(v)
            } else {
                Err(self.item_error(
                    "boundary",
                    &at(field),
                    format!("{field} = {} must be finite", show(v)),
                ))
            }
        };
        match b.kind {
            BoundaryKind::Open => {
                not_for("size", b.size.is_some())?;
                not_for("lo", b.lo.is_some())?;
                not_for("hi", b.hi.is_some())?;
                world.boundary = Boundary::Open;
                Ok(None)
            }
            BoundaryKind::Box => {
                not_for("size", b.size.is_some())?;
                let (Some(lo), Some(hi)) = (b.lo, b.hi) else {
                    return Err(self.item_error(
                        "boundary",
                        &at("kind"),
                        "kind = \"box\" needs `lo` and `hi`".into(),
                    ));
                };
                let (lo, hi) = (finite("lo", lo)?, finite("hi", hi)?);
                if !hi.cmpgt(lo).all() {
                    return Err(self.item_error(
                        "boundary",
                        &at("hi"),
                        format!(
                            "hi = {} must exceed lo = {} on every axis",
                            show(hi),
                            show(lo)
                        ),
                    ));
                }
                world.boundary = Boundary::OpenBox { lo, hi };
                Ok(None)
            }
            BoundaryKind::Periodic => {
                not_for("lo", b.lo.is_some())?;
                not_for("hi", b.hi.is_some())?;
                let size = match b.size {
                    Some(s) => {
                        let s = finite("size", s)?;
                        if !s.cmpgt(DVec3::ZERO).all() {
                            return Err(self.item_error(
                                "boundary",
                                &at("size"),
                                format!("size = {} must be greater than 0 on every axis", show(s)),
                            ));
                        }
                        Some(s)
                    }
                    None => None,
                };
                world.boundary = Boundary::Periodic {
                    size: size.unwrap_or(DVec3::ZERO),
                };
                Ok(size)
            }
        }
    }

    fn shapes(&self, world: &mut World) -> Result<(), SceneFileError> {
        let f32s = |v: [f64; 3]| v.map(|x| x as f32);
        for (i, p) in self.plane.iter().enumerate() {
            let item = format!("plane {i}");
            let path = |k| [Key("plane"), At(i), Key(k)];
            let material = self.material_index(
                &world.materials,
                p.material.as_deref(),
                &item,
                &path("material"),
            )?;
            let shape = Plane::new(f32s(p.point), f32s(p.normal))
                .map_err(|e| self.shape_error(&item, &path(e.field), e))?;
            world.statics.push(shape, material);
        }
        for (i, c) in self.cylinder.iter().enumerate() {
            let item = format!("cylinder {i}");
            let path = |k| [Key("cylinder"), At(i), Key(k)];
            let material = self.material_index(
                &world.materials,
                c.material.as_deref(),
                &item,
                &path("material"),
            )?;
            let shape = Cylinder::new(f32s(c.p1), f32s(c.p2), c.radius as f32).map_err(|e| {
                let field = if e.field == "axis" { "p2" } else { e.field };
                self.shape_error(&item, &path(field), e)
            })?;
            world.statics.push(shape, material);
        }
        for (i, c) in self.container.iter().enumerate() {
            let item = format!("container {i}");
            let path = |k| [Key("container"), At(i), Key(k)];
            let material = self.material_index(
                &world.materials,
                c.material.as_deref(),
                &item,
                &path("material"),
            )?;
            let shape = Container::new(f32s(c.centre), c.radius as f32)
                .map_err(|e| self.shape_error(&item, &path(e.field), e))?;
            world.statics.push(shape, material);
        }
        Ok(())
    }

    fn listed_sphere(
        &self,
        i: usize,
        s: &SphereTable,
        names: &[String],
    ) -> Result<SphereState, SceneFileError> {
        let item = format!("sphere {i}");
        let path = |k| [Key("sphere"), At(i), Key(k)];
        let material =
            self.material_index(names, s.material.as_deref(), &item, &path("material"))?;
        let bad = |field: &'static str, problem: String| {
            Err(self.item_error(&item, &path(field), format!("{field} {problem}")))
        };
        let (centre, velocity) = (DVec3::from_array(s.centre), DVec3::from_array(s.velocity));
        if !centre.is_finite() {
            return bad("centre", format!("= {} must be finite", show(centre)));
        }
        if !velocity.is_finite() {
            return bad("velocity", format!("= {} must be finite", show(velocity)));
        }
        if !(s.radius.is_finite() && s.radius > 0.0) {
            return bad(
                "radius",
                format!("= {:?} must be finite and greater than 0", s.radius),
            );
        }
        if !(s.mass.is_finite() && s.mass > 0.0) {
            return bad(
                "mass",
                format!("= {:?} must be finite and greater than 0", s.mass),
            );
        }
        Ok(SphereState {
            centre,
            velocity,
            radius: s.radius,
            mass: s.mass,
            material,
        })
    }

    fn generated(
        &self,
        world: &mut World,
        mut periodic_size: Option<DVec3>,
        base_seed: u64,
    ) -> Result<(), SceneFileError> {
        let mut total = world.spheres.len();
        for (b, g) in self.generate.iter().enumerate() {
            let item = format!("generate {b} ({})", g.kind.name());
            let block = [Key("generate"), At(b)];
            let path = |k| [Key("generate"), At(b), Key(k)];
            // Fields that do not belong to the kind, then the ones it needs.
            let (required, optional) = g.kind.fields();
            for f in g.set_fields() {
                if !required.contains(&f) && !optional.contains(&f) {
                    return Err(self.item_error(
                        &item,
                        &path(f),
                        format!(
                            "`{f}` does not apply to kind = {:?} (it takes {}; and material, seed, mass)",
                            g.kind.name(),
                            required
                                .iter()
                                .chain(optional)
                                .copied()
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ));
                }
            }
            let set = g.set_fields();
            if let Some(missing) = required.iter().find(|f| !set.contains(f)) {
                return Err(self.item_error(
                    &item,
                    &path("kind"),
                    format!(
                        "kind = {:?} needs `{missing}` (it needs {})",
                        g.kind.name(),
                        required.join(", ")
                    ),
                ));
            }
            let count = g.count().unwrap_or(usize::MAX);
            if count == 0 || count > MAX_SPHERES - total.min(MAX_SPHERES) {
                let field = if g.kind == GenerateKind::Lattice {
                    "counts"
                } else {
                    "n"
                };
                return Err(self.item_error(
                    &item,
                    &path(field),
                    format!(
                        "{field} must give between 1 and {} spheres in all (this block: {})",
                        MAX_SPHERES,
                        g.count()
                            .map_or("more than 2^64".to_string(), |c| c.to_string())
                    ),
                ));
            }
            total += count;
            let material = self.material_index(
                &world.materials,
                g.material.as_deref(),
                &item,
                &path("material"),
            )?;
            let mass = g.mass.unwrap_or(1.0);
            if !(mass.is_finite() && mass > 0.0) {
                return Err(self.item_error(
                    &item,
                    &path("mass"),
                    format!("mass = {mass:?} must be finite and greater than 0"),
                ));
            }
            let seed = g.seed.unwrap_or(base_seed.wrapping_add(b as u64));
            let sim = |e: SimError| self.generator_error(&item, &block, e);
            // Every required field is set (checked above); `req` reads one.
            let req = |v: Option<f64>| v.unwrap_or(f64::NAN);
            let req3 = |v: Option<[f64; 3]>| DVec3::from_array(v.unwrap_or([f64::NAN; 3]));
            let radius = req(g.radius);
            let mut spheres = match g.kind {
                GenerateKind::PeriodicGas => {
                    if world.boundary != (Boundary::Periodic { size: DVec3::ZERO })
                        || periodic_size.is_some()
                    {
                        let problem = if matches!(world.boundary, Boundary::Periodic { .. }) {
                            "the periodic box is already set (by [boundary] size or an earlier periodic_gas): a periodic_gas sets it from n and phi"
                        } else {
                            "periodic_gas needs [boundary] kind = \"periodic\" (without size: the gas sets it)"
                        };
                        return Err(self.item_error(&item, &block, problem.into()));
                    }
                    let mut tmp = World::default();
                    let kt = g.temperature.unwrap_or(1.0);
                    generate::periodic_gas(&mut tmp, count, req(g.phi), radius, kt, seed)
                        .map_err(sim)?;
                    world.boundary = tmp.boundary;
                    if let Boundary::Periodic { size } = tmp.boundary {
                        periodic_size = Some(size);
                    }
                    // The generator's masses are 1: keep kT for the mass asked for.
                    let scale = 1.0 / mass.sqrt();
                    for s in &mut tmp.spheres {
                        s.velocity *= scale;
                    }
                    tmp.spheres
                }
                GenerateKind::Random => {
                    self.random_block(g, b, &item, world, periodic_size, material, seed)?
                }
                GenerateKind::Nozzle => {
                    let spacing = g.spacing.unwrap_or(2.2 * radius);
                    generate::nozzle(
                        req3(g.origin),
                        req3(g.direction),
                        count,
                        radius,
                        req(g.speed),
                        spacing,
                        g.spread.unwrap_or(0.0),
                        g.jitter.unwrap_or(0.0),
                        material,
                        seed,
                    )
                    .map_err(sim)?
                }
                GenerateKind::Lattice => generate::cubic_lattice(
                    req3(g.lo),
                    g.counts.unwrap_or([0; 3]),
                    req(g.spacing),
                    radius,
                    g.speed.unwrap_or(0.0),
                    material,
                    seed,
                )
                .map_err(sim)?,
            };
            for s in &mut spheres {
                s.material = material;
                s.mass = mass;
            }
            // Generators check their own parameters; anything they pass through unchecked
            // (a NaN speed, say) is named here rather than as a global sphere index.
            if let Some(k) = spheres.iter().position(|s| {
                !(s.centre.is_finite()
                    && s.velocity.is_finite()
                    && s.radius > 0.0
                    && s.radius.is_finite())
            }) {
                return Err(self.item_error(
                    &item,
                    &block,
                    format!("its sphere {k} is not finite (check radius, speed and positions)"),
                ));
            }
            world.spheres.extend(spheres);
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn random_block(
        &self,
        g: &GenerateTable,
        b: usize,
        item: &str,
        world: &World,
        periodic_size: Option<DVec3>,
        material: u16,
        seed: u64,
    ) -> Result<Vec<SphereState>, SceneFileError> {
        let path = |k| [Key("generate"), At(b), Key(k)];
        // A radius that is not finite and positive is refused by the generator, naming it.
        let radius = g.radius.unwrap_or(f64::NAN);
        let (mut lo, mut hi) = match (g.lo, g.hi) {
            (Some(lo), Some(hi)) => (DVec3::from_array(lo), DVec3::from_array(hi)),
            (None, None) => (DVec3::NEG_INFINITY, DVec3::INFINITY),
            (Some(_), None) => {
                return Err(self.item_error(item, &path("lo"), "`lo` needs `hi`".into()));
            }
            (None, Some(_)) => {
                return Err(self.item_error(item, &path("hi"), "`hi` needs `lo`".into()));
            }
        };
        let vessel = match g.inside {
            Some(k) => match world.statics.of::<Container>().shapes().get(k) {
                Some(c) => {
                    let (centre, r) = (c.centre().as_dvec3(), f64::from(c.radius()));
                    lo = lo.max(centre - r);
                    hi = hi.min(centre + r);
                    Some((centre, r))
                }
                None => {
                    return Err(self.item_error(
                        item,
                        &path("inside"),
                        format!(
                            "inside = {k}: there are {} containers (counted from 0)",
                            world.statics.of::<Container>().len()
                        ),
                    ));
                }
            },
            None => None,
        };
        if let Some(size) = periodic_size {
            // Keep every sphere whole inside the box, so none overlaps its neighbour's image.
            lo = lo.max(DVec3::splat(radius));
            hi = hi.min(size - radius);
        }
        if g.lo.is_none() && vessel.is_none() && periodic_size.is_none() {
            return Err(self.item_error(
                item,
                &path("kind"),
                "kind = \"random\" needs a region: `lo` and `hi`, or `inside` (a container index)"
                    .into(),
            ));
        }
        if !(lo.is_finite() && hi.is_finite() && (hi - lo).is_finite() && hi.cmpgt(lo).all()) {
            return Err(self.item_error(
                item,
                &path(if g.lo.is_some() { "hi" } else { "inside" }),
                format!(
                    "the region from {} to {} is empty or not finite",
                    show(lo),
                    show(hi)
                ),
            ));
        }
        // Room beside every sphere already placed, and clear of every static shape.
        let occupied = Occupied::new(&world.spheres);
        let margin = 1e-9 * radius;
        let inside = |p: DVec3| {
            occupied.is_free(p, radius)
                && (world.statics.iter()).all(|(_, s, _)| s.normal_gap(p, radius).1 >= margin)
        };
        generate::random_spheres(
            lo,
            hi,
            &inside,
            g.n.unwrap_or(0),
            radius,
            g.speed.unwrap_or(0.0),
            material,
            seed,
        )
        .map_err(|e| self.generator_error(item, &[Key("generate"), At(b)], e))
    }

    /// A generator's refusal ([`SimError::Generate`]) in its own words, at the line of the
    /// field it names (the block's line when it names none); any other error as it is.
    fn generator_error(&self, item: &str, path: &[Seg], e: SimError) -> SceneFileError {
        match e {
            SimError::Generate { field, problem, .. } => {
                let mut path = path.to_vec();
                if !field.is_empty() {
                    path.push(Key(field));
                }
                self.item_error(item, &path, problem)
            }
            other => self.sim_error(item, path, other),
        }
    }
}

/// A vector in messages: each component as the shortest decimal that reads back (exponent
/// form for very large and small magnitudes).
fn show(v: DVec3) -> String {
    format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)
}

/// Spheres already placed, hashed on a grid, to keep a random block clear of them.
struct Occupied<'a> {
    spheres: &'a [SphereState],
    cell: f64,
    reach: f64,
    grid: std::collections::HashMap<[i64; 3], Vec<u32>>,
}

impl<'a> Occupied<'a> {
    fn new(spheres: &'a [SphereState]) -> Self {
        let reach = spheres.iter().map(|s| s.radius).fold(0.0, f64::max);
        let cell = (2.0 * reach).max(f64::MIN_POSITIVE);
        let mut grid: std::collections::HashMap<[i64; 3], Vec<u32>> = Default::default();
        for (i, s) in spheres.iter().enumerate() {
            grid.entry(Self::key(s.centre, cell))
                .or_default()
                .push(i as u32);
        }
        Self {
            spheres,
            cell,
            reach,
            grid,
        }
    }

    fn key(p: DVec3, cell: f64) -> [i64; 3] {
        // Saturating casts: far-away points share the edge cells.
        (p / cell).floor().to_array().map(|x| x as i64)
    }

    fn is_free(&self, p: DVec3, radius: f64) -> bool {
        if self.spheres.is_empty() {
            return true;
        }
        let span = ((radius + self.reach) / self.cell).ceil().min(64.0) as i64;
        let c = Self::key(p, self.cell);
        if span >= 64 {
            return self
                .spheres
                .iter()
                .all(|s| s.centre.distance(p) >= s.radius + radius);
        }
        for dx in -span..=span {
            for dy in -span..=span {
                for dz in -span..=span {
                    let k = [
                        c[0].saturating_add(dx),
                        c[1].saturating_add(dy),
                        c[2].saturating_add(dz),
                    ];
                    if let Some(members) = self.grid.get(&k)
                        && members.iter().any(|&j| {
                            let s = &self.spheres[j as usize];
                            s.centre.distance(p) < (s.radius + radius) * (1.0 + 1e-9)
                        })
                    {
                        return false;
                    }
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FULL: &str = r#"
[run]
t_end = 2.5
snapshot_every = 0.5
seed = 7

[boundary]
kind = "box"
lo = [-30.0, -30.0, -20.0]
hi = [30.0, 30.0, 40.0]

[[material]]
name = "glass"

[[material]]
name = "rubber"

[effects]
response = "inelastic"
restitution = 0.8
tc = 1e-4
record_events = true
geometry = true

[[effects.pair]]
a = "glass"
b = "rubber"
response = "sticky"

[[sphere]]
centre = [3.0, 3.0, 25.0]
velocity = [0.0, 0.0, -1.0]
radius = 0.5
mass = 2.0
material = "rubber"

[[generate]]
kind = "nozzle"
origin = [0.0, 0.0, 10.0]
direction = [0.0, 0.0, -1.0]
n = 50
radius = 0.2
speed = 3.0
spread = 0.05
material = "glass"

[[generate]]
kind = "random"
n = 100
radius = 0.3
speed = 1.0
inside = 0
seed = 3

[[generate]]
kind = "lattice"
lo = [10.0, 10.0, 1.0]
counts = [3, 4, 5]
spacing = 1.0
radius = 0.4

[[plane]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
material = "rubber"

[[cylinder]]
p1 = [5.0, 0.0, 0.0]
p2 = [5.0, 0.0, 1.0]
radius = 1.0

[[container]]
centre = [0.0, 0.0, 10.0]
radius = 30.0
"#;

    #[test]
    fn a_full_scene_builds() {
        let scene = SceneFile::from_toml_str(FULL).unwrap();
        let (world, run) = scene.build().unwrap();
        assert_eq!(
            run,
            RunSettings {
                t_end: 2.5,
                snapshot_every: Some(0.5),
                seed: 7
            }
        );
        assert_eq!(world.spheres.len(), 1 + 50 + 100 + 60);
        assert_eq!(world.materials, ["glass", "rubber"]);
        assert_eq!(world.spheres[0].material, 1);
        assert_eq!(world.spheres[0].mass, 2.0);
        assert!(world.spheres[1..].iter().all(|s| s.material == 0));
        assert_eq!(
            world.effects.response,
            Response::Inelastic { restitution: 0.8 }
        );
        assert_eq!(
            world.effects.pairs,
            [MaterialPair {
                a: 0,
                b: 1,
                response: Response::Sticky
            }]
        );
        let kinds: Vec<_> = world.statics.iter().map(|(b, _, &m)| (b.kind, m)).collect();
        assert_eq!(
            kinds,
            [
                (ShapeKind::Plane, 1),
                (ShapeKind::Cylinder, kinds[1].1),
                (ShapeKind::Container, kinds[2].1)
            ]
        );
        // The random block is inside its container.
        for s in &world.spheres[51..151] {
            assert!(s.centre.distance(DVec3::new(0.0, 0.0, 10.0)) <= 30.0 - 0.3);
        }
        let sim = Simulation::new(world).unwrap();
        assert!(sim.engine_name().contains("static shapes"));
        assert!(scene.start().is_ok());
    }

    #[test]
    fn json_builds_the_same_world() {
        let json = r#"{
            "run": {"t_end": 2.5, "snapshot_every": 0.5, "seed": 7},
            "boundary": {"kind": "box", "lo": [-30, -30, -20], "hi": [30, 30, 40]},
            "material": [{"name": "glass"}, {"name": "rubber"}],
            "effects": {"response": "inelastic", "restitution": 0.8, "tc": 1e-4,
                        "record_events": true, "geometry": true,
                        "pair": [{"a": "glass", "b": "rubber", "response": "sticky"}]},
            "sphere": [{"centre": [3, 3, 25], "velocity": [0, 0, -1], "radius": 0.5,
                        "mass": 2, "material": "rubber"}],
            "generate": [
                {"kind": "nozzle", "origin": [0, 0, 10], "direction": [0, 0, -1], "n": 50,
                 "radius": 0.2, "speed": 3, "spread": 0.05, "material": "glass"},
                {"kind": "random", "n": 100, "radius": 0.3, "speed": 1, "inside": 0, "seed": 3},
                {"kind": "lattice", "lo": [10, 10, 1], "counts": [3, 4, 5], "spacing": 1,
                 "radius": 0.4}
            ],
            "plane": [{"point": [0, 0, 0], "normal": [0, 0, 1], "material": "rubber"}],
            "cylinder": [{"p1": [5, 0, 0], "p2": [5, 0, 1], "radius": 1}],
            "container": [{"centre": [0, 0, 10], "radius": 30}]
        }"#;
        let from_json = SceneFile::from_json_str(json).unwrap().build().unwrap();
        let from_toml = SceneFile::from_toml_str(FULL).unwrap().build().unwrap();
        assert_eq!(from_json, from_toml);
    }

    fn toml_error(text: &str) -> String {
        match SceneFile::from_toml_str(text) {
            Err(e) => e.to_string(),
            Ok(s) => s.build().unwrap_err().to_string(),
        }
    }

    #[test]
    fn a_typo_is_refused_naming_the_field_and_its_line() {
        let text = FULL.replace("restitution = 0.8", "restitusion = 0.8");
        let line = text
            .lines()
            .position(|l| l.starts_with("restitusion"))
            .unwrap()
            + 1;
        let err = toml_error(&text);
        assert!(err.contains(&format!("line {line}")), "{err}");
        assert!(err.contains("unknown field `restitusion`"), "{err}");
        // In a generator block too (not the first one), and in JSON.
        let text = FULL.replace("inside = 0", "insde = 0");
        let line = text.lines().position(|l| l.starts_with("insde")).unwrap() + 1;
        let err = toml_error(&text);
        assert!(
            err.contains(&format!("line {line}")) && err.contains("`insde`"),
            "{err}"
        );
        let err = SceneFile::from_json_str("{\"run\": {\n\"t_end\": 1,\n\"sede\": 2}}")
            .unwrap_err()
            .to_string();
        assert!(err.contains("`sede`") && err.contains("line 3"), "{err}");
    }

    #[test]
    fn undeclared_materials_name_the_item_and_line() {
        let text = FULL.replace(
            "material = \"rubber\"\n\n[[generate]]",
            "material = \"steel\"\n\n[[generate]]",
        );
        let err = toml_error(&text);
        assert!(
            err.starts_with("line 35: sphere 0: material \"steel\" is not declared"),
            "{err}"
        );
        let err = toml_error(
            "[run]\nt_end = 1\n[[plane]]\npoint = [0,0,0]\nnormal = [0,0,1]\nmaterial = \"x\"\n",
        );
        assert!(
            err.starts_with("line 6: plane 0: material \"x\" is not declared"),
            "{err}"
        );
    }

    /// More materials than the engine's response table holds are refused, naming the first
    /// one too many; the most accepted build.
    #[test]
    fn at_most_max_materials_are_declared() {
        let declare = |n: usize| {
            let mut text = String::from("[run]\nt_end = 1\n");
            for k in 0..n {
                text += &format!("[[material]]\nname = \"m{k}\"\n");
            }
            text
        };
        let max = crate::sim::MAX_MATERIALS;
        let err = toml_error(&declare(max + 1));
        assert!(err.contains(&format!("at most {max} materials")), "{err}");
        let file = SceneFile::from_toml_str(&declare(max)).unwrap();
        let (world, _) = file.build().unwrap();
        assert_eq!(world.materials.len(), max);
    }

    #[test]
    fn fields_that_do_not_fit_their_item_are_named() {
        let cases = [
            (
                FULL.replace("spread = 0.05", "phi = 0.05"),
                "generate 0 (nozzle): `phi` does not apply",
            ),
            (
                FULL.replace("counts = [3, 4, 5]\n", ""),
                "generate 2 (lattice): kind = \"lattice\" needs `counts`",
            ),
            (
                FULL.replace("inside = 0", "inside = 4"),
                "inside = 4: there are 1 containers",
            ),
            (
                FULL.replace("normal = [0.0, 0.0, 1.0]", "normal = [0.0, 0.0, 0.0]"),
                "plane 0: plane normal has zero length",
            ),
            (
                FULL.replace("restitution = 0.8", "restitution = 1.5"),
                "effects: restitution = 1.5 must be in [0, 1]",
            ),
            (
                FULL.replace(
                    "response = \"sticky\"",
                    "response = \"sticky\"\nrestitution = 0.5",
                ),
                "effects.pair 0: restitution applies only to response = \"inelastic\"",
            ),
            (
                FULL.replace("t_end = 2.5", "t_end = -1"),
                "run: t_end = -1.0 must be finite",
            ),
            (
                FULL.replace("mass = 2.0", "mass = 0.0"),
                "sphere 0: mass = 0.0 must be finite and greater than 0",
            ),
            (
                FULL.replace("kind = \"box\"", "kind = \"periodic\""),
                "boundary: `lo` does not apply to kind = \"periodic\"",
            ),
            (
                FULL.replace("name = \"rubber\"", "name = \"glass\""),
                "material 1: name \"glass\" is already material 0",
            ),
        ];
        for (text, want) in cases {
            let err = toml_error(&text);
            assert!(err.contains(want), "want {want:?} in {err}");
            assert!(err.starts_with("line "), "{err}");
        }
    }

    #[test]
    fn overlapping_spheres_are_named_by_their_entries() {
        let text = "[run]\nt_end = 1\n\n[[sphere]]\ncentre = [0, 0, 0]\nradius = 1\n\n[[generate]]\nkind = \"lattice\"\nlo = [1, 0, 0]\ncounts = [2, 1, 1]\nspacing = 3\nradius = 0.5\n";
        let scene = SceneFile::from_toml_str(text).unwrap();
        let err = scene.start().unwrap_err().to_string();
        assert!(
            err.starts_with(
                "line 4: sphere 0 and generate 0 (lattice), its sphere 0: spheres 0 and 1 overlap"
            ),
            "{err}"
        );
    }

    #[test]
    fn a_periodic_gas_sets_its_box() {
        let text = "[run]\nt_end = 1\n[boundary]\nkind = \"periodic\"\n[[generate]]\nkind = \"periodic_gas\"\nn = 500\nphi = 0.2\nradius = 0.5\ntemperature = 2.0\nmass = 4.0\n";
        let (world, _) = SceneFile::from_toml_str(text).unwrap().build().unwrap();
        let Boundary::Periodic { size } = world.boundary else {
            panic!("not periodic")
        };
        let volume = 500.0 * 4.0 / 3.0 * std::f64::consts::PI * 0.125 / 0.2;
        assert!((size.x.powi(3) - volume).abs() < 1e-9 * volume);
        let ke: f64 = world
            .spheres
            .iter()
            .map(|s| 0.5 * s.mass * s.velocity.length_squared())
            .sum();
        assert!((ke - 1.5 * 500.0 * 2.0).abs() < 1e-9 * ke);
        let err = toml_error(&text.replace("kind = \"periodic\"", "kind = \"open\""));
        assert!(
            err.contains("periodic_gas needs [boundary] kind = \"periodic\""),
            "{err}"
        );
        let err = toml_error("[run]\nt_end = 1\n[boundary]\nkind = \"periodic\"\n");
        assert!(err.contains("a periodic boundary needs `size`"), "{err}");
    }

    #[test]
    fn the_documented_example_builds_and_runs() {
        let doc = include_str!("../../docs/scene-format.md");
        let example = doc
            .split("```toml\n")
            .nth(1)
            .and_then(|s| s.split("```").next())
            .expect("docs/scene-format.md has a TOML example");
        let scene = SceneFile::from_toml_str(example).unwrap();
        let (mut sim, run) = scene.start().unwrap();
        assert_eq!(sim.spheres().len(), 101);
        sim.advance_to(run.t_end).unwrap();
        assert!(sim.stats().pair_collisions > 0 && sim.stats().wall_collisions > 0);
    }

    #[test]
    fn files_are_named_in_messages() {
        let missing = Path::new("/no/such/scene.toml");
        let err = SceneFile::from_path(missing).unwrap_err().to_string();
        assert!(
            err.starts_with("cannot read /no/such/scene.toml: "),
            "{err}"
        );
        let dir = std::env::temp_dir().join(format!("spheresweep-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("typo.toml");
        std::fs::write(&path, "[run]\nt_ned = 1\n").unwrap();
        let err = SceneFile::from_path(&path).unwrap_err().to_string();
        assert!(
            err.starts_with(&format!("{}: TOML parse error at line 2", path.display())),
            "{err}"
        );
        std::fs::write(
            &path,
            "[run]\nt_end = 1\n[[sphere]]\ncentre = [0,0,0]\nradius = 1\nmaterial = \"rubber\"\n",
        )
        .unwrap();
        let err = SceneFile::from_path(&path)
            .unwrap()
            .build()
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with(&format!(
                "{}:6: sphere 0: material \"rubber\" is not declared",
                path.display()
            )),
            "{err}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}
