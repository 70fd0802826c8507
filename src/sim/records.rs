//! The record of one processed collision, kept when the world asks for events.

use glam::DVec3;

use super::checkpoint::{Decoder, Encoder};
use super::model::SimError;
use super::persist::{Persist, persist_fields};
use super::response::Outcome;
use crate::ShapeKind;
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
    /// Restitution applied (`1` elastic, `0` sticky), or where a hop under gravity raised the
    /// separation speed, that speed over the approach (above 1, with a negative
    /// `energy_lost`, where the hop added energy: docs/derivations/gravity.md, "Resting piles").
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

persist_fields!(EventGeometry { point, normal });
persist_fields!(EventRecord {
    time,
    sphere,
    other,
    approach,
    restitution,
    energy_lost,
    geometry,
});

/// Whether there is one, then it.
impl Persist for Option<EventGeometry> {
    fn save(&self, e: &mut Encoder) {
        e.u8(u8::from(self.is_some()));
        if let Some(g) = self {
            g.save(e);
        }
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        *self = match d.u8()? {
            0 => None,
            _ => {
                let mut g = EventGeometry {
                    point: DVec3::ZERO,
                    normal: DVec3::ZERO,
                };
                g.load(d)?;
                Some(g)
            }
        };
        Ok(())
    }
}

/// The events recorded and not yet taken: whether there is a log, their count, then each, so
/// that a restored simulation gives them to `take_events` as the saved one would have. What is
/// recorded is not the world (its fingerprint): restored into a world that records no events,
/// they are dropped; a world that records them from a checkpoint without starts with none.
impl Persist for Option<Vec<EventRecord>> {
    fn save(&self, e: &mut Encoder) {
        e.u8(u8::from(self.is_some()));
        if let Some(log) = self {
            e.len(log.len());
            for r in log {
                r.save(e);
            }
        }
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        let mut events = Vec::new();
        if d.u8()? != 0 {
            // Time, sphere, body (kind and index), three figures and the geometry's flag: 42
            // bytes at least.
            let n = d.len(42, "event log")?;
            events.reserve(n);
            for _ in 0..n {
                let mut r = EventRecord {
                    time: 0.0,
                    sphere: 0,
                    other: Body::new(ShapeKind::Sphere, 0),
                    approach: 0.0,
                    restitution: 0.0,
                    energy_lost: 0.0,
                    geometry: None,
                };
                r.load(d)?;
                events.push(r);
            }
        }
        if let Some(log) = self {
            *log = events;
        }
        Ok(())
    }
}
