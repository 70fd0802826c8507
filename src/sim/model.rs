//! What a simulation is made of: spheres in f64, static shapes with a material, the boundary,
//! and the effects the scene asks for. Plain data; [`World::validate`] is the boundary that
//! checks it once, naming the item and the field at fault.

use glam::DVec3;

use crate::Statics;
use crate::error::Problem;

/// One sphere of a simulation: centre and velocity at the start, radius, mass and material.
/// The engine keeps positions, velocities and times in f64.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereState {
    /// Centre.
    pub centre: DVec3,
    /// Velocity.
    pub velocity: DVec3,
    /// Radius (`> 0`).
    pub radius: f64,
    /// Mass (`> 0`).
    pub mass: f64,
    /// Index into [`World::materials`].
    pub material: u16,
}

/// A query's sphere as a simulation's: the same values in f64 (exact), material 0.
///
/// ```
/// use spheresweep::Sphere;
/// use spheresweep::sim::SphereState;
/// let s = SphereState::from(Sphere::new([1.0, 2.0, 3.0], [0.5, 0.0, 0.0], 0.25, 2.0)?);
/// assert_eq!((s.centre.x, s.velocity.x, s.radius, s.mass, s.material), (1.0, 0.5, 0.25, 2.0, 0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
impl From<crate::Sphere> for SphereState {
    fn from(s: crate::Sphere) -> Self {
        Self {
            centre: s.centre().as_dvec3(),
            velocity: s.velocity().as_dvec3(),
            radius: f64::from(s.radius()),
            mass: f64::from(s.mass()),
            material: 0,
        }
    }
}

/// A simulation's sphere as the queries take it: each value rounded to the nearest f32, its
/// centre taken as the query's centre at `t = 0` (the material is not kept). Every value a
/// simulation takes (`2⁻¹⁰⁰` to `2¹⁰⁰`, [`MAX_MAGNITUDE`]) is a normal f32, so the sphere of a
/// new [`Simulation`](super::Simulation) converts.
///
/// # Errors
/// The [`ShapeError`](crate::ShapeError) of [`Sphere::new`](crate::Sphere::new) for a value
/// no sphere may have, or one beyond f32's range (it rounds to infinite).
///
/// ```
/// # use glam::DVec3;
/// use spheresweep::Sphere;
/// use spheresweep::sim::SphereState;
/// let s = SphereState { centre: DVec3::new(0.1, 0.0, 0.0), velocity: DVec3::X, radius: 1.0, mass: 1.0, material: 3 };
/// let q = Sphere::try_from(&s)?;
/// assert_eq!((q.centre().x, q.radius()), (0.1f32, 1.0));
/// let far = SphereState { centre: DVec3::new(1e300, 0.0, 0.0), ..s };
/// assert!(Sphere::try_from(&far).is_err());
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
impl TryFrom<&SphereState> for crate::Sphere {
    type Error = crate::ShapeError;

    fn try_from(s: &SphereState) -> Result<Self, Self::Error> {
        crate::Sphere::new(
            s.centre.as_vec3().to_array(),
            s.velocity.as_vec3().to_array(),
            s.radius as f32,
            s.mass as f32,
        )
    }
}

/// What a collision does to the bodies that meet.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Response {
    /// Nothing: contacts are only reported, and the spheres pass through each other (`"none"`
    /// in scene files and Python). Applies to a whole scene, never to one pair of materials.
    ReportOnly,
    /// Elastic: the normal relative velocity is reversed.
    #[default]
    Elastic,
    /// Inelastic: the normal relative velocity is reversed and scaled by `restitution`.
    Inelastic {
        /// Coefficient of normal restitution, in `[0, 1]`.
        restitution: f64,
    },
    /// Perfectly inelastic: the bodies join into a cluster that moves as one (translation only,
    /// with the momentum-conserving common velocity); a cluster that meets a static shape stops.
    Sticky,
}

impl Response {
    /// The responses' names, as scene files (`[effects] response`) and the Python binding
    /// spell them, in the order of the variants.
    pub const NAMES: [&'static str; 4] = ["none", "elastic", "inelastic", "sticky"];

    /// The response called `name` (one of [`NAMES`](Self::NAMES)); `"inelastic"` takes
    /// `restitution` as its coefficient, the others ignore it; `None` for any other name. The
    /// one reading of response names: which fields go with which name, and their ranges, are
    /// each caller's to check and word ([`World::validate`] checks the range too).
    ///
    /// ```
    /// use spheresweep::sim::Response;
    /// assert_eq!(Response::named("sticky", 0.5), Some(Response::Sticky));
    /// assert_eq!(Response::named("inelastic", 0.5), Some(Response::Inelastic { restitution: 0.5 }));
    /// assert_eq!(Response::named("bouncy", 0.5), None);
    /// for name in Response::NAMES {
    ///     assert_eq!(Response::named(name, 0.5).map(|r| r.name()), Some(name));
    /// }
    /// ```
    pub fn named(name: &str, restitution: f64) -> Option<Self> {
        match name {
            "none" => Some(Response::ReportOnly),
            "elastic" => Some(Response::Elastic),
            "inelastic" => Some(Response::Inelastic { restitution }),
            "sticky" => Some(Response::Sticky),
            _ => None,
        }
    }

    /// Its name (one of [`NAMES`](Self::NAMES)).
    pub fn name(&self) -> &'static str {
        match self {
            Response::ReportOnly => "none",
            Response::Elastic => "elastic",
            Response::Inelastic { .. } => "inelastic",
            Response::Sticky => "sticky",
        }
    }
}

/// A response for one pair of materials, overriding [`Effects::response`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialPair {
    /// One material.
    pub a: u16,
    /// The other (the order does not matter).
    pub b: u16,
    /// What their collisions do.
    pub response: Response,
}

/// The effects a scene calls for: the engine is assembled from these (and from the shapes the
/// scene has), so a scene pays only for what it uses.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Effects {
    /// Response for every pair of materials not listed in `pairs`.
    pub response: Response,
    /// Per-pair-of-materials overrides.
    pub pairs: Vec<MaterialPair>,
    /// The TC model's duration (Luding & McNamara 1998): a collision of a sphere whose previous
    /// collision was less than `tc` ago is elastic. `0` turns it off.
    ///
    /// It also sets what rest costs under gravity: a sphere resting on a wall hops off it
    /// about every `tc` (a settled pile of `N` makes a few `N/tc` events a unit of time, and
    /// some piles far more: docs/derivations/gravity.md, "Not every settled pile"); without
    /// it, every `2√(2ρ/γ)`, with `ρ = 2⁻³⁰` of the sphere's distance from the origin plus its
    /// radius, `γ` the gravity across the wall —
    /// thousands of hops a unit of time for a sphere resting 5 from the origin under `g = 1`
    /// (docs/derivations/gravity.md, "Resting contact").
    ///
    /// ```
    /// # use glam::DVec3;
    /// use spheresweep::sim::{Effects, Response, Simulation, SphereState, World};
    /// use spheresweep::{Plane, Statics};
    /// // One sphere dropped on a floor: its bounces die out, then it rests there, hopping.
    /// let hops_a_unit_of_time = |tc: f64| {
    ///     let world = World {
    ///         spheres: vec![SphereState {
    ///             centre: DVec3::new(0.0, 0.0, -3.0),
    ///             velocity: DVec3::ZERO,
    ///             radius: 1.0,
    ///             mass: 1.0,
    ///             material: 0,
    ///         }],
    ///         statics: Statics::new().with(Plane::new([0.0, 0.0, -5.0], [0.0, 0.0, 1.0])?, 0),
    ///         effects: Effects {
    ///             response: Response::Inelastic { restitution: 0.5 },
    ///             gravity: DVec3::new(0.0, 0.0, -1.0),
    ///             tc,
    ///             ..Effects::default()
    ///         },
    ///         ..World::default()
    ///     };
    ///     let mut sim = Simulation::new(world)?;
    ///     sim.advance_to(4.0)?; // its bounces end at t ≈ 4.24, then it hops
    ///     let before = sim.stats().wall_collisions;
    ///     sim.advance_to(6.0)?;
    ///     Ok::<_, spheresweep::Error>((sim.stats().wall_collisions - before) as f64 / 2.0)
    /// };
    /// let (with_tc, without) = (hops_a_unit_of_time(1e-3)?, hops_a_unit_of_time(0.0)?);
    /// // A hop off a level floor lasts tc (1 − 2⁻²⁰); without TC a flight lasts at least 2√(2ρ),
    /// // ρ = 5·2⁻³⁰ (|r| + radius).
    /// assert!((500.0..=1001.0).contains(&with_tc), "{with_tc}"); // measured 883.5 (from t ≈ 4.24)
    /// assert!((2000.0..=5200.0).contains(&without), "{without}"); // measured 4558
    /// # Ok::<(), spheresweep::Error>(())
    /// ```
    pub tc: f64,
    /// Whether each recorded event carries its contact point and normal.
    pub geometry: bool,
    /// Whether events are recorded (see `Simulation::take_events`).
    pub record_events: bool,
    /// A uniform acceleration every sphere feels (zero: none, and the engine has no gravity
    /// code at all). Static shapes stay put. Refused with a periodic box (it is periodic along
    /// every axis, so along `g`) and with sticky responses.
    pub gravity: DVec3,
}

/// Where the spheres live.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Boundary {
    /// Open space; the cell grid covers the spheres' and shapes' extent at the start (spheres
    /// may leave it: edge cells reach to infinity).
    #[default]
    Open,
    /// Open space with the cell grid over the given box.
    OpenBox {
        /// Lower corner.
        lo: DVec3,
        /// Upper corner.
        hi: DVec3,
    },
    /// A periodic box `[0, size)` on every axis.
    Periodic {
        /// Box lengths.
        size: DVec3,
    },
}

/// A whole simulation's input.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct World {
    /// The spheres.
    pub spheres: Vec<SphereState>,
    /// The static shapes (planes, infinite cylinders, containers: every sphere starts inside
    /// each container), each with its material, an index into [`World::materials`].
    pub statics: Statics<u16>,
    /// Where the spheres live.
    pub boundary: Boundary,
    /// Material names (at least one; index 0 is the default).
    pub materials: Vec<String>,
    /// What collisions do and what is recorded.
    pub effects: Effects,
}

/// What lies outside the range the simulation computes in ([`SimError::Range`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum OutOfRange {
    /// A coordinate of the open box's corners.
    #[error("open box")]
    OpenBox,
    /// A length of the periodic box.
    #[error("periodic box")]
    PeriodicBox,
    /// The fastest sphere's speed (too slow, but moving).
    #[error("the fastest sphere")]
    FastestSphere,
}

impl OutOfRange {
    /// Whether the boundary (the scene file's `[boundary]`) is at fault.
    pub fn is_boundary(self) -> bool {
        matches!(self, Self::OpenBox | Self::PeriodicBox)
    }
}

/// Why a simulation could not be built or advanced.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// A sphere's field is invalid.
    #[error("sphere {index}: {field} {problem}")]
    Sphere {
        /// Which sphere.
        index: usize,
        /// Which field.
        field: &'static str,
        /// What is wrong.
        problem: Problem,
    },
    /// A material index that names no material.
    #[error(
        "{item}: material {material} does not exist ({})",
        match count { 0 | 1 => "only material 0 exists".to_string(), n => format!("{n} materials, 0 to {}", n - 1) }
    )]
    Material {
        /// The item (`"sphere 3"`, `"plane 0"`, `"material pair 1"`).
        item: String,
        /// The index given.
        material: u16,
        /// How many materials there are.
        count: usize,
    },
    /// Two spheres overlap at the start by more than the engine's tolerance.
    #[error(
        "spheres {a} and {b} overlap by {} (a length in the scene's units; the tolerance is {} of their contact distance)",
        crate::error::Num(*depth),
        crate::error::Num(*tolerance)
    )]
    Overlap {
        /// One sphere.
        a: usize,
        /// The other.
        b: usize,
        /// Overlap depth.
        depth: f64,
        /// The tolerance, relative to the contact distance.
        tolerance: f64,
    },
    /// A sphere starts through a static shape (or outside a container).
    #[error(
        "sphere {sphere} starts through {shape} {index} (by {})",
        crate::error::Num(*depth)
    )]
    Penetrates {
        /// The sphere.
        sphere: usize,
        /// The shape's kind.
        shape: crate::ShapeKind,
        /// The shape's index.
        index: usize,
        /// Penetration depth.
        depth: f64,
    },
    /// A sphere fills a container (its radius at least the container's) and moves or falls:
    /// touching the wall all round, it would meet it again at once without end.
    #[error(
        "sphere {sphere} (radius {}) fills container {container} (radius {}): it has no room \
         to move, yet it moves or falls; give it no velocity (and the scene no gravity), or a \
         smaller radius",
        crate::error::Num(*radius),
        crate::error::Num(*container_radius)
    )]
    NoRoom {
        /// The sphere.
        sphere: usize,
        /// The container's index.
        container: usize,
        /// The sphere's radius.
        radius: f64,
        /// The container's radius.
        container_radius: f64,
    },
    /// A periodic box is too small for its spheres or not valid.
    #[error(
        "periodic box {axis}: length {} must be finite and at least three largest diameters ({})",
        crate::error::Num(*length),
        crate::error::Num(*needed)
    )]
    Box {
        /// `"x"`, `"y"` or `"z"`.
        axis: &'static str,
        /// The length given.
        length: f64,
        /// The smallest length accepted.
        needed: f64,
    },
    /// An open box that is not finite, or whose `hi` is not above its `lo` on every axis.
    #[error("open box [{lo}, {hi}]: its corners must be finite, with hi > lo on every axis")]
    OpenBox {
        /// The lower corner given.
        lo: DVec3,
        /// The upper corner given.
        hi: DVec3,
    },
    /// A static shape in a periodic box whose periodic images spheres could meet: the engine
    /// keeps none.
    #[error(
        "{shape} {index} in a periodic box: the engine keeps no periodic images of shapes, so \
         a plane's normal or a cylinder's axis must lie along a box axis, at least {} (two \
         largest diameters, and a cylinder's radius) from the faces it crosses, and a \
         container must lie inside the box",
        crate::error::Num(*margin)
    )]
    PeriodicShape {
        /// The shape's kind.
        shape: crate::ShapeKind,
        /// The shape's index.
        index: usize,
        /// How far from the faces it must be.
        margin: f64,
    },
    /// An effect's parameter is out of range.
    #[error("effects: {0}")]
    Effects(String),
    /// The boundary holds a coordinate or length beyond [`MAX_MAGNITUDE`], or the fastest
    /// sphere moves slower than [`MIN_MAGNITUDE`] (but moves).
    #[error(
        "{what}: outside the range the simulation computes in (lengths and speeds up to 2¹⁰⁰, \
         about 1.3e30; the fastest sphere at least 2⁻¹⁰⁰, about 7.9e-31, or at rest): choose \
         units that bring the scene within it"
    )]
    Range {
        /// What lies outside the range.
        what: OutOfRange,
    },
    /// A generator's parameter is out of range (`sim::generate`), or it could not place its
    /// spheres.
    #[error("{generator}: {problem}")]
    Generate {
        /// `"periodic gas"`, `"random spheres"`, `"nozzle"`, `"lattice"`.
        generator: &'static str,
        /// The parameter at fault, as the scene file names it (`"spacing"`, `"phi"`, …), or
        /// `""` when the failure is not one parameter's (no room left for a random sphere).
        field: &'static str,
        /// What is wrong, naming the value.
        problem: String,
    },
    /// Not enough memory for what was asked: refused before anything was allocated.
    #[error("{what} needs about {} MiB, which could not be allocated", bytes / (1 << 20))]
    Memory {
        /// What needed it.
        what: String,
        /// Bytes asked for.
        bytes: usize,
    },
    /// A new state given for the spheres does not fit them
    /// ([`Simulation::set_velocities`](super::Simulation::set_velocities)).
    #[error("{0}")]
    State(String),
    /// A time that is not finite or lies before the simulation's current time.
    #[error(
        "cannot advance to t = {}: {}",
        crate::error::Num(*to),
        if to.is_finite() {
            format!("the simulation is at t = {}", crate::error::Num(*now))
        } else {
            "a time must be finite".to_string()
        }
    )]
    Time {
        /// The current time.
        now: f64,
        /// The time asked for.
        to: f64,
    },
    /// A checkpoint could not be restored.
    #[error("checkpoint: {0}")]
    Checkpoint(String),
    /// The state broke the invariant every run keeps
    /// ([`Simulation::check_invariant`](super::Simulation::check_invariant)): a bug in the
    /// engine, never the scene's fault.
    #[error(
        "t = {}: sphere {sphere} is {} by {depth:.3e}, beyond the tolerance {tolerance:.3e}: the \
         simulation broke its invariant (a bug in spheresweep; please report it with the scene)",
        crate::error::Num(*time),
        breach_what(other)
    )]
    Breach {
        /// When.
        time: f64,
        /// The sphere (public index).
        sphere: usize,
        /// What it overlaps or is through (a sphere's index is public too).
        other: crate::contact::Body,
        /// How far (a length).
        depth: f64,
        /// The tolerance it exceeds (a length).
        tolerance: f64,
    },
    /// A sphere's centre or velocity is NaN or infinite: no valid state leads to one (the
    /// world's checks refuse every input that could), so this is a bug in the engine, caught
    /// before it reads as an overlap, a flight or nothing at all.
    #[error(
        "t = {}: sphere {sphere}'s centre or velocity is NaN or infinite: the simulation broke \
         its invariant (a bug in spheresweep; please report it with the scene)",
        crate::error::Num(*time)
    )]
    NotFinite {
        /// When it was found.
        time: f64,
        /// The sphere (public index).
        sphere: usize,
    },
    /// Inelastic collapse: a sphere's dissipating collisions came faster than one per window
    /// of the collapse watch, `collisions` more than the windows elapsed (the window `2⁻²⁰` of
    /// a sphere's mean time between events; under gravity at least an eighth of a hop at
    /// rounding height off a floor, wall contacts not counted) — infinitely many collisions in
    /// finite time, which hard inelastic spheres undergo without the TC model, or a pile held
    /// up by the rounding hop alone.
    #[error(
        "inelastic collapse at t = {}: sphere {sphere}'s dissipating collisions came faster \
         than one a window, {collisions} more than the windows elapsed (the window: 2⁻²⁰ of a \
         sphere's mean time between events; under gravity at least an eighth of a hop at \
         rounding height, and wall contacts not counted) — infinitely many collisions in \
         finite time, or a pile held up by rounding alone: give the scene the TC model, \
         `tc > 0`",
        crate::error::Num(*time)
    )]
    Collapse {
        /// When.
        time: f64,
        /// The sphere (public index).
        sphere: usize,
        /// Its count: rapid collisions less the windows elapsed.
        collisions: u64,
    },
    /// The engine processed more events than its limit without time advancing by 2⁻³⁰ of a
    /// sphere's mean time between events (an inelastic collapse, or a bug).
    #[error(
        "stalled at t = {}: {events} events without time advancing ({})",
        crate::error::Num(*time),
        if *inelastic {
            "a dense inelastic pile needs the TC model, `tc > 0`"
        } else {
            "events came faster than the clock's resolution, 2⁻³⁰ of a sphere's mean time between events: speeds or sizes spanning too many orders of magnitude"
        }
    )]
    Stalled {
        /// When.
        time: f64,
        /// How many events at that time.
        events: u64,
        /// Whether collisions can lose energy (the TC model's remedy applies).
        inelastic: bool,
    },
    /// An open scene's spheres have flown apart for good (nothing has met anything since
    /// `since`), and at `time` a sphere would be so far from the origin that its position
    /// rounds by more than the gap it keeps to its nearest sphere, or beyond
    /// [`MAX_MAGNITUDE`]; the run can go on to `reachable`.
    #[error(
        "t = {} is beyond what the simulation can reach: the spheres have flown apart (nothing has met anything since t = {}), and by then sphere {sphere} would be so far from the origin that its position rounds by more than the gap it keeps to its nearest sphere (or beyond 2¹⁰⁰): the run can go on to t = {}",
        crate::error::Num(*time),
        crate::error::Num(*since),
        crate::error::Num(*reachable)
    )]
    Flown {
        /// The sphere (the first found).
        sphere: usize,
        /// The time asked for.
        time: f64,
        /// The last event's time.
        since: f64,
        /// The latest time every sphere is within its reach.
        reachable: f64,
    },
}

/// How a breach of the invariant reads: "overlapping sphere 3", "past the wall of container 0".
fn breach_what(other: &crate::contact::Body) -> String {
    use crate::ShapeKind;
    match other.kind {
        ShapeKind::Sphere => format!("overlapping sphere {}", other.index),
        ShapeKind::Plane => format!("through plane {} (or across it)", other.index),
        ShapeKind::Cylinder => format!("through cylinder {}", other.index),
        ShapeKind::Container => format!("past the wall of container {}", other.index),
    }
}

fn finite3(v: DVec3) -> bool {
    v.is_finite()
}

/// The smallest radius and mass a simulation takes: `2⁻¹⁰⁰` (about 7.9·10⁻³¹).
pub const MIN_MAGNITUDE: f64 = 1.0 / (1u128 << 100) as f64;
/// The largest radius, mass, coordinate, box length or velocity component a simulation
/// takes: `2¹⁰⁰` (about 1.3·10³⁰). Within `[2⁻¹⁰⁰, 2¹⁰⁰]` every product of four lengths or
/// speeds the engine forms (`A C`, `A D²`, `‖r0 × v‖²`) is a normal `f64`, so a
/// scene computes alike at any units within it: scaled by powers of two, its events are the
/// same, at times scaled alike (docs/derivations/simulation.md, "The range of magnitudes").
pub const MAX_MAGNITUDE: f64 = (1u128 << 100) as f64;

/// Whether a positive magnitude is within `[MIN_MAGNITUDE, MAX_MAGNITUDE]`.
pub(crate) fn in_range(x: f64) -> bool {
    (MIN_MAGNITUDE..=MAX_MAGNITUDE).contains(&x)
}

/// Refuses velocities whose fastest component is below [`MIN_MAGNITUDE`] but not zero: slower
/// spheres are fine (their speeds only round away against the others'), but a scene moving
/// only that slowly would square its speeds to nothing.
pub(crate) fn fastest_in_range(velocities: impl Iterator<Item = DVec3>) -> Result<(), SimError> {
    let fastest = velocities.fold(0.0, |m: f64, v| m.max(v.abs().max_element()));
    if fastest > 0.0 && fastest < MIN_MAGNITUDE {
        return Err(SimError::Range {
            what: OutOfRange::FastestSphere,
        });
    }
    Ok(())
}

/// Whether every component is at most `MAX_MAGNITUDE` in magnitude.
pub(crate) fn bounded3(v: DVec3) -> bool {
    v.abs().max_element() <= MAX_MAGNITUDE
}

/// How a radius or mass outside [`in_range`] is refused where its value is quoted (a scene
/// file's sphere, a generator's radius).
pub(crate) const OUTSIDE_RANGE: &str = "is outside 2⁻¹⁰⁰ to 2¹⁰⁰ (about 7.9e-31 to 1.3e30), the \
     range the simulation computes in: choose units that bring the scene within it";

/// How a coordinate or velocity beyond [`bounded3`] is refused where its value is quoted (a
/// scene file's sphere).
#[cfg(feature = "scene-file")]
pub(crate) const BEYOND_RANGE: &str = "is beyond 2¹⁰⁰ (about 1.3e30), the largest the \
     simulation computes with: choose units that bring the scene within it";

/// The most materials a world may have: the engine keeps a response for every ordered pair of
/// materials (16 MiB at this count), so a larger table is refused rather than allocated.
pub const MAX_MATERIALS: usize = 1024;

impl World {
    /// Checks every item once: finite values, positive radii and masses, existing materials
    /// (at most [`MAX_MATERIALS`]), effect parameters in range. Overlaps and the box size are
    /// checked when the engine is built.
    pub fn validate(&self) -> Result<(), SimError> {
        if self.materials.len() > MAX_MATERIALS {
            return Err(SimError::Effects(format!(
                "{} materials: at most {MAX_MATERIALS} (the engine keeps a response for every \
                 pair of materials)",
                self.materials.len()
            )));
        }
        let count = self.materials.len().max(1);
        let material = |item: String, m: u16| {
            if usize::from(m) < count {
                Ok(())
            } else {
                Err(SimError::Material {
                    item,
                    material: m,
                    count,
                })
            }
        };
        for (index, s) in self.spheres.iter().enumerate() {
            let bad = |field, problem| {
                Err(SimError::Sphere {
                    index,
                    field,
                    problem,
                })
            };
            if !finite3(s.centre) {
                return bad("centre", Problem::NotFinite);
            }
            if !finite3(s.velocity) {
                return bad("velocity", Problem::NotFinite);
            }
            if !s.radius.is_finite() {
                return bad("radius", Problem::NotFinite);
            }
            if s.radius < 0.0 {
                return bad("radius", Problem::Negative);
            }
            if s.radius == 0.0 {
                // A point has no contact distance with another point: the simulation keeps
                // radii within its range (`in_range`), where the queries take points.
                return bad("radius", Problem::NotPositive);
            }
            if !s.mass.is_finite() {
                return bad("mass", Problem::NotFinite);
            }
            if s.mass <= 0.0 {
                return bad("mass", Problem::NotPositive);
            }
            for (field, ok) in [
                ("centre", bounded3(s.centre)),
                ("velocity", bounded3(s.velocity)),
                ("radius", in_range(s.radius)),
                ("mass", in_range(s.mass)),
            ] {
                if !ok {
                    return bad(field, Problem::OutOfRange);
                }
            }
            material(format!("sphere {index}"), s.material)?;
        }
        for (body, _, &m) in self.statics.iter() {
            material(body.to_string(), m)?;
        }
        let fx = &self.effects;
        let check = |r: &Response, what: String| match r {
            Response::Inelastic { restitution: e } if !(0.0..=1.0).contains(e) => Err(
                SimError::Effects(format!("{what}: restitution {e} is not in [0, 1]")),
            ),
            _ => Ok(()),
        };
        check(&fx.response, "response".into())?;
        for (i, p) in fx.pairs.iter().enumerate() {
            material(format!("material pair {i}"), p.a)?;
            material(format!("material pair {i}"), p.b)?;
            check(&p.response, format!("material pair {i}"))?;
            if p.response == Response::ReportOnly && fx.response != Response::ReportOnly {
                return Err(SimError::Effects(format!(
                    "material pair {i}: response `none` applies to a whole scene, not one pair"
                )));
            }
            if fx.response == Response::ReportOnly {
                return Err(SimError::Effects(format!(
                    "material pair {i}: the scene's response is `none` (contacts reported \
                     only), which a pair cannot change"
                )));
            }
        }
        if !(fx.tc.is_finite() && fx.tc >= 0.0) {
            return Err(SimError::Effects(format!(
                "tc = {} must be finite and ≥ 0",
                fx.tc
            )));
        }
        self.validate_gravity()?;
        if let Boundary::OpenBox { lo, hi } = self.boundary
            && !(finite3(lo) && finite3(hi) && hi.cmpgt(lo).all())
        {
            return Err(SimError::OpenBox { lo, hi });
        }
        self.validate_magnitudes()
    }

    /// The boundary's magnitudes within the engine's range (`MAX_MAGNITUDE`; the spheres' are
    /// checked with their other fields).
    fn validate_magnitudes(&self) -> Result<(), SimError> {
        let (what, ok) = match self.boundary {
            Boundary::Open => (OutOfRange::OpenBox, true),
            Boundary::OpenBox { lo, hi } => (OutOfRange::OpenBox, bounded3(lo) && bounded3(hi)),
            // A length that is not finite is the box check's to name, with its axis.
            Boundary::Periodic { size } => {
                (OutOfRange::PeriodicBox, !finite3(size) || bounded3(size))
            }
        };
        if !ok {
            return Err(SimError::Range { what });
        }
        fastest_in_range(self.spheres.iter().map(|s| s.velocity))
    }
}

impl World {
    /// Gravity: finite, no faster a fall across the scene than [`MAX_MAGNITUDE`], never along a
    /// periodic axis (a periodic box wraps every axis), and not with sticky responses (a
    /// cluster stuck to a shape would have to be held against it).
    fn validate_gravity(&self) -> Result<(), SimError> {
        let fx = &self.effects;
        let g = fx.gravity;
        let shown = crate::error::Nums(g.to_array());
        if !finite3(g) {
            return Err(SimError::Effects(format!("gravity {shown} must be finite")));
        }
        if g == DVec3::ZERO {
            return Ok(());
        }
        // A sphere falling across the scene, a distance `L` (at most its farthest sphere's
        // distance from the origin and the farthest shape's), reaches `√(2 g L)`: at most
        // 2¹⁰⁰ as every speed, with `g L ≤ 2¹⁹⁹`. (Not `g` alone: in units of tiny lengths
        // and tinier times, g is huge and the scene fine.)
        let sphere = (self.spheres.iter())
            .map(|s| s.centre.length() + s.radius)
            .fold(MIN_MAGNITUDE, f64::max);
        let shape = (self.statics.iter())
            .map(|(_, s, _)| {
                let wall = s.normal_gap(DVec3::ZERO, 0.0).1.abs();
                wall + s.interior().map_or(0.0, |(_, radius)| radius)
            })
            .fold(0.0, f64::max);
        let reach = sphere + shape;
        if g.length() * reach > MAX_MAGNITUDE * MAX_MAGNITUDE / 2.0 {
            return Err(SimError::Effects(format!(
                "gravity {shown}: a sphere falling across the scene (up to {}) would \
                 reach speeds beyond 2¹⁰⁰ (about 1.3e30; √(2 g L)), outside the range the \
                 simulation computes in: choose units that bring it within",
                crate::error::Num(reach)
            )));
        }
        if let Boundary::Periodic { .. } = self.boundary {
            return Err(SimError::Effects(format!(
                "gravity {shown} with a periodic box: the box wraps every axis, so spheres would \
                 fall for ever along g; use an open box with a floor (planes) instead"
            )));
        }
        let sticky = std::iter::once(&fx.response)
            .chain(fx.pairs.iter().map(|p| &p.response))
            .any(|r| *r == Response::Sticky);
        if sticky {
            return Err(SimError::Effects(format!(
                "gravity {shown} with a sticky response: not supported (a cluster stuck to a \
                 shape would have to be held against gravity)"
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world(response: Response, pairs: Vec<MaterialPair>, tc: f64) -> World {
        World {
            spheres: vec![SphereState {
                centre: DVec3::ZERO,
                velocity: DVec3::X,
                radius: 1.0,
                mass: 1.0,
                material: 0,
            }],
            materials: vec!["a".into(), "b".into()],
            effects: Effects {
                response,
                pairs,
                tc,
                ..Effects::default()
            },
            ..World::default()
        }
    }

    /// Effects out of range are refused naming what is wrong; `none` is a whole scene's only.
    #[test]
    fn effects_are_checked_once() {
        let pair = |response| MaterialPair {
            a: 0,
            b: 1,
            response,
        };
        let sticky = pair(Response::Sticky);
        assert!(
            world(Response::Elastic, vec![sticky], 0.0)
                .validate()
                .is_ok()
        );
        for (w, message) in [
            (
                world(Response::Elastic, vec![pair(Response::ReportOnly)], 0.0),
                "material pair 0: response `none` applies to a whole scene",
            ),
            (
                world(Response::ReportOnly, vec![sticky], 0.0),
                "material pair 0: the scene's response is `none`",
            ),
            (
                world(Response::Inelastic { restitution: 1.5 }, vec![], 0.0),
                "response: restitution 1.5 is not in [0, 1]",
            ),
            (
                world(
                    Response::Elastic,
                    vec![MaterialPair { b: 2, ..sticky }],
                    0.0,
                ),
                "material pair 0: material 2 does not exist (2 materials, 0 to 1)",
            ),
            (world(Response::Elastic, vec![], -1.0), "tc = -1 must be"),
            (
                World {
                    materials: (0..=MAX_MATERIALS).map(|i| i.to_string()).collect(),
                    ..world(Response::Elastic, vec![], 0.0)
                },
                "1025 materials: at most 1024",
            ),
        ] {
            let e = w.validate().unwrap_err().to_string();
            assert!(e.contains(message), "{e}");
        }
    }

    /// A boundary's fault is named as the boundary's, with the axis where there is one; a
    /// material past an empty list names the one material there is.
    #[test]
    fn a_boundary_or_material_fault_names_what_was_given() {
        let with = |boundary| World {
            boundary,
            ..world(Response::Elastic, vec![], 0.0)
        };
        let flat = Boundary::OpenBox {
            lo: DVec3::ZERO,
            hi: DVec3::new(1.0, 0.0, 1.0),
        };
        let e = with(flat).validate().unwrap_err();
        assert!(matches!(e, SimError::OpenBox { .. }), "{e}");
        assert!(
            e.to_string()
                .starts_with("open box [[0, 0, 0], [1, 0, 1]]: its corners")
        );
        let nan = Boundary::Periodic {
            size: DVec3::new(10.0, f64::NAN, 10.0),
        };
        let e = crate::sim::Simulation::new(with(nan))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("periodic box y: length NaN must be finite"),
            "{e}"
        );
        let none = World {
            materials: Vec::new(),
            ..world(Response::Elastic, vec![], 0.0)
        };
        let mut one = none.clone();
        one.spheres[0].material = 1;
        let e = one.validate().unwrap_err().to_string();
        assert_eq!(
            e,
            "sphere 0: material 1 does not exist (only material 0 exists)"
        );
    }
}
