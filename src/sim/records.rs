//! The record of one processed collision, kept when the world asks for events.

use glam::DVec3;

use super::response::Outcome;
use crate::contact::Body;

/// Contact point and normal of an event.
///
/// ```
/// # use glam::DVec3;
/// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
/// # let ball = |x: f64, vx: f64| SphereState {
/// #     centre: DVec3::new(x, 0.0, 0.0),
/// #     velocity: DVec3::new(vx, 0.0, 0.0),
/// #     radius: 0.5,
/// #     mass: 1.0,
/// #     material: 0,
/// # };
/// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
/// let world = World {
///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
///     ..World::default()
/// };
/// let mut sim = Simulation::new(world)?;
/// sim.advance_to(2.0)?;
/// let g = sim.take_events()[0].geometry.unwrap(); // the scene asked for geometry
/// assert!((g.point - DVec3::new(1.5, 0.0, 0.0)).length() < 1e-12); // midway at t = 1
/// assert!((g.normal.x.abs() - 1.0).abs() < 1e-12);
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventGeometry {
    /// Where the bodies touch.
    pub point: DVec3,
    /// Unit normal pushing the sphere away from the other body.
    pub normal: DVec3,
}

/// One processed collision.
///
/// ```
/// # use glam::DVec3;
/// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
/// # let ball = |x: f64, vx: f64| SphereState {
/// #     centre: DVec3::new(x, 0.0, 0.0),
/// #     velocity: DVec3::new(vx, 0.0, 0.0),
/// #     radius: 0.5,
/// #     mass: 1.0,
/// #     material: 0,
/// # };
/// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
/// let world = World {
///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
///     ..World::default()
/// };
/// use spheresweep::ShapeKind;
/// let mut sim = Simulation::new(world)?;
/// sim.advance_to(2.0)?;
/// let events = sim.take_events();
/// assert_eq!(events.len(), 1);
/// let e = events[0];
/// assert!((e.time - 1.0).abs() < 1e-12 && (e.approach - 2.0).abs() < 1e-12);
/// assert_eq!((e.restitution, e.energy_lost), (1.0, 0.0));
/// // The event is the one sphere whose prediction found the contact; the other is its partner.
/// assert_eq!(e.other.kind, ShapeKind::Sphere);
/// let mut pair = [e.sphere, e.other.index];
/// pair.sort();
/// assert_eq!(pair, [0, 1]);
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventRecord {
    /// When.
    pub time: f64,
    /// The sphere.
    pub sphere: u32,
    /// What it met.
    pub other: Body,
    /// Normal approach speed before the collision.
    pub approach: f64,
    /// Restitution applied (`1` elastic, `0` sticky).
    pub restitution: f64,
    /// Kinetic energy the collision took.
    pub energy_lost: f64,
    /// Contact point and normal, when the scene asked for geometry.
    pub geometry: Option<EventGeometry>,
}

impl EventRecord {
    pub(super) fn new(
        time: f64,
        sphere: u32,
        other: Body,
        o: &Outcome,
        g: Option<(DVec3, DVec3)>,
    ) -> Self {
        Self {
            time,
            sphere,
            other,
            approach: o.approach,
            restitution: o.restitution,
            energy_lost: o.energy_lost,
            geometry: g.map(|(point, normal)| EventGeometry { point, normal }),
        }
    }
}
