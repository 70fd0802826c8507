//! The scene file's tables as serde reads them: types and defaults only; every check beyond
//! the types is made when the world is assembled (`assemble.rs`, `place.rs`).

use std::path::PathBuf;
use std::sync::Arc;

use serde::de::Error as _;
use serde::{Deserialize, Deserializer};

use crate::sim::Response;

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
    pub(super) origin: Origin,
}

/// The static shapes of a scene and the materials they name, alone: the `[[material]]`,
/// `[[plane]]`, `[[cylinder]]` and `[[container]]` tables of [`SceneFile`], as
/// [`read_statics`](super::read_statics) parses them (any other table is refused).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ShapesFile {
    #[serde(default)]
    pub(super) material: Vec<MaterialTable>,
    #[serde(default)]
    pub(super) plane: Vec<PlaneTable>,
    #[serde(default)]
    pub(super) cylinder: Vec<CylinderTable>,
    #[serde(default)]
    pub(super) container: Vec<ContainerTable>,
}

/// Where a scene came from, for messages: its path and, for TOML, its text (to find lines).
#[derive(Debug, Clone, Default)]
pub(super) struct Origin {
    pub(super) file: Option<PathBuf>,
    pub(super) toml: Option<Arc<str>>,
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

/// A response's name as the file writes it, refused while parsing (naming the line) unless it
/// is one of [`Response::NAMES`]; assembly turns it into a [`Response`] with
/// [`Response::named`].
fn response_name<'de, D: Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    let name = String::deserialize(d)?;
    match Response::named(&name, f64::NAN) {
        Some(_) => Ok(name),
        None => Err(D::Error::unknown_variant(&name, &Response::NAMES)),
    }
}

fn elastic() -> String {
    Response::Elastic.name().into()
}

/// `[effects]`.
///
/// ```
/// use spheresweep::io::scene_file::{EffectsTable, SceneFile};
/// let text = "[run]\nt_end = 1\n[effects]\nresponse = \"inelastic\"\nrestitution = 0.8\ntc = 1e-4\n";
/// let effects = SceneFile::from_toml_str(text)?.effects;
/// assert_eq!((effects.response.as_str(), effects.restitution), ("inelastic", Some(0.8)));
/// assert_eq!(effects.tc, 1e-4);
/// assert!(!effects.record_events && effects.pair.is_empty());
/// assert_eq!(EffectsTable::default().response, "elastic"); // without [effects]
/// // A name that is not a response is refused as the file is parsed, naming its line.
/// let err = SceneFile::from_toml_str("[run]\nt_end = 1\n[effects]\nresponse = \"bouncy\"\n").unwrap_err();
/// assert!(err.to_string().contains("line 4") && err.to_string().contains("unknown variant `bouncy`"));
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectsTable {
    /// Response of every pair of materials not listed in `pair`: one of [`Response::NAMES`]
    /// (default `"elastic"`).
    #[serde(default = "elastic", deserialize_with = "response_name")]
    pub response: String,
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
    /// A uniform acceleration `[gx, gy, gz]` every sphere feels (default none). Refused with a
    /// periodic boundary and with sticky responses.
    #[serde(default)]
    pub gravity: Option<[f64; 3]>,
    /// `[[effects.pair]]`: per-pair-of-materials overrides.
    #[serde(default)]
    pub pair: Vec<PairTable>,
}

impl Default for EffectsTable {
    /// No `[effects]` table: elastic collisions, nothing recorded.
    fn default() -> Self {
        Self {
            response: elastic(),
            restitution: None,
            tc: 0.0,
            geometry: false,
            record_events: false,
            gravity: None,
            pair: Vec::new(),
        }
    }
}

/// `[[effects.pair]]`.
///
/// ```
/// use spheresweep::io::scene_file::SceneFile;
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
/// assert_eq!(pair.response, "sticky");
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairTable {
    /// One material's name.
    pub a: String,
    /// The other's (may equal `a`).
    pub b: String,
    /// What their collisions do: one of [`Response::NAMES`] but `"none"`.
    #[serde(deserialize_with = "response_name")]
    pub response: String,
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
    pub(super) fn name(self) -> &'static str {
        match self {
            GenerateKind::PeriodicGas => "periodic_gas",
            GenerateKind::Random => "random",
            GenerateKind::Nozzle => "nozzle",
            GenerateKind::Lattice => "lattice",
        }
    }
    /// The fields this kind takes beyond `kind`, `material`, `seed` and `mass`: (required,
    /// optional).
    pub(super) fn fields(self) -> (&'static [&'static str], &'static [&'static str]) {
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
    pub(super) fn set_fields(&self) -> Vec<&'static str> {
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
    pub(super) fn count(&self) -> Option<usize> {
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
/// assert_eq!(scene.build()?.0.statics.of::<spheresweep::Plane>().shapes()[0].normal().z, 1.0); // normalised
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
/// assert_eq!(world.statics.of::<spheresweep::Cylinder>().shapes()[0].axis().to_array(), [0.0, 0.0, 1.0]);
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
