//! The engine's rules for the static shapes its spheres meet, each shape with its material
//! ([`Statics<u16>`]): the earliest contact of a sphere with any of them in f64, the normal and
//! gap at a contact, and the floor angle at a concave wall. The geometry is each kind's own
//! (its kernel file); nothing here names a kind.

use glam::DVec3;

use super::KernelCounts;
use crate::contact::Body;
use crate::kernels::falling::earliest_rise;
use crate::kernels::{SettleSphere, settle_static, sphere_settle_lanes};
use crate::shape::ShapeKind;
use crate::statics::{OfKind, StaticShape, Statics, Visitor};

/// The shapes a prediction passes over: the last three a report-only sphere met (contacts
/// already reported, `ReportOnly::shape`; `NO_SHAPE` for none), and, with `through`
/// (report-only), a contact at once (`t = 0`) with a shape the sphere is through now. A
/// report-only sphere passes through the shapes, and a straight line meets each in one
/// interval, reported where it begins: through one, the sphere is in a contact already
/// reported (or started in). Without these a sphere that had left its vessel and met a plane,
/// or met two planes at a corner, was given the two in turn without end (a stall).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Skip {
    pub met: [Body; 3],
    pub through: bool,
}

impl Skip {
    /// Whether the contact `t` from now with shape `k` of kind `K` is passed over, the sphere
    /// at `r` now.
    #[inline]
    fn passes<K: StaticShape>(&self, shape: &K, k: usize, t: f64, r: DVec3, radius: f64) -> bool {
        self.met.contains(&Body::new(K::KIND, k as u32))
            || self.through && t == 0.0 && shape.normal_gap(r, radius).1 < -THROUGH * radius
    }
}

/// How far through a shape, in radii, a sphere is in the middle of its contact with it
/// (`Skip::through`): past the rounding of a contact's start (the engine's contact positions
/// round within about `10⁻¹⁵` of the scene's size), far below any depth a line reaches.
const THROUGH: f64 = 1e-9;

/// The earliest contact of one sphere with every shape but those `skip` passes over, kind by
/// kind.
struct Earliest<'a> {
    lanes: SettleSphere,
    r: DVec3,
    radius: f64,
    best: (f64, Body),
    skip: Skip,
    counts: &'a mut KernelCounts,
}

impl<P> Visitor<P> for Earliest<'_> {
    #[inline]
    fn visit<K: StaticShape>(&mut self, shapes: &OfKind<K, P>) {
        for (k, prepared) in shapes.settle().iter().enumerate() {
            let t = settle_static::<K>(&self.lanes, prepared);
            if t < self.best.0
                && !(self.skip).passes(&shapes.shapes()[k], k, t, self.r, self.radius)
            {
                self.best = (t, Body::new(K::KIND, k as u32));
            }
        }
        self.counts.add(K::KIND, shapes.len() as u64);
    }
}

/// The earliest contact of one falling sphere with every shape but those `skip` passes over,
/// kind by kind.
struct EarliestFalling<'a> {
    r: DVec3,
    v: DVec3,
    h: DVec3,
    radius: f64,
    best: (f64, Body),
    skip: Skip,
    counts: &'a mut KernelCounts,
}

impl<P> Visitor<P> for EarliestFalling<'_> {
    #[inline]
    fn visit<K: StaticShape>(&mut self, shapes: &OfKind<K, P>) {
        for (k, shape) in shapes.shapes().iter().enumerate() {
            let p = shape.falling_polynomial(self.r, self.v, self.h, self.radius);
            let t = earliest_rise(&p);
            if t < self.best.0 && !(self.skip).passes(shape, k, t, self.r, self.radius) {
                self.best = (t, Body::new(K::KIND, k as u32));
            }
        }
        self.counts.add(K::KIND, shapes.len() as u64);
    }
}

impl Statics<u16> {
    /// Earliest contact of a sphere (centre `r` now, velocity `v`, radius) with any shape
    /// but those `skip` passes over under the uniform acceleration `g`, each kind's polynomial answered by the
    /// certified root isolation of `kernels::falling`; ties go to the first in tie-break
    /// order.
    pub(crate) fn earliest_falling(
        &self,
        (r, v, radius): (DVec3, DVec3, f64),
        g: DVec3,
        skip: Skip,
        counts: &mut KernelCounts,
    ) -> (f64, Body) {
        let mut e = EarliestFalling {
            r,
            v,
            h: g * 0.5,
            radius,
            best: (f64::INFINITY, Body::new(ShapeKind::Plane, 0)),
            skip,
            counts,
        };
        self.visit(&mut e);
        e.best
    }

    /// Earliest contact of a sphere (centre `r` now, velocity `v`, radius) with any shape
    /// but those `skip` passes over, in f64 (the `Stable` kernels on `f64x4`, one lane used); ties go to the
    /// first in tie-break order.
    pub(crate) fn earliest(
        &self,
        (r, v, radius): (DVec3, DVec3, f64),
        skip: Skip,
        counts: &mut KernelCounts,
    ) -> (f64, Body) {
        let mut e = Earliest {
            lanes: sphere_settle_lanes(r, v, radius),
            r,
            radius,
            best: (f64::INFINITY, Body::new(ShapeKind::Plane, 0)),
            skip,
            counts,
        };
        self.visit(&mut e);
        e.best
    }

    /// Unit normal from the shape `body` towards the sphere centre `r`, the signed gap
    /// (negative when the sphere is through the shape) and the shape's material.
    ///
    /// # Panics
    /// If `body` is not one of the shapes (the engine only names shapes it predicted).
    pub(crate) fn normal_gap(&self, body: Body, r: DVec3, radius: f64) -> (DVec3, f64, u16) {
        let (shape, &material) = self.get(body).expect("a shape of the scene");
        let (n, gap) = shape.normal_gap(r, radius);
        (n, gap, material)
    }

    /// Fault injection only: whether a sphere is at or past the concave wall `body` moving
    /// inwards (the case the old policy answered as no contact when it never got back in).
    pub(crate) fn past_and_inwards(&self, body: Body, r: DVec3, v: DVec3, radius: f64) -> bool {
        let Some((centre, big)) = self.get(body).and_then(|(s, _)| s.interior()) else {
            return false;
        };
        let x = r - centre;
        let d = big - radius;
        x.length_squared() >= d * d && x.dot(v) < 0.0
    }

    /// The least angle (its sine) at which a sphere of `radius`, `gap` from the wall `body`
    /// (negative when past it), moving at `speed`, may leave it at time `now`: `0` for a convex
    /// shape (a straight line that leaves one never meets it again). For a concave wall of
    /// radius `R`, with `D = R − radius`, `κ² = 2⁻²⁴ + 2⁻⁴⁴ (‖c‖ + D + speed·now) / D`, far above
    /// the rounding of the kernel's `C` at the wall, and at least `2 √(2 depth / D)` for a
    /// sphere `depth` past the wall, so that its line leads back inside
    /// (docs/derivations/simulation.md, "Concave walls").
    pub(crate) fn floor(&self, body: Body, radius: f64, gap: f64, speed: f64, now: f64) -> f64 {
        let Some((centre, big)) = self.get(body).and_then(|(s, _)| s.interior()) else {
            return 0.0;
        };
        let d = big - radius;
        if d <= 0.0 {
            // A sphere that fits exactly (or not at all) can only go straight back.
            return 1.0;
        }
        let scale = (centre.length() + d + speed * now.abs()) / d;
        let base = (WALL_FLOOR_SQUARED + WALL_FLOOR_ROUNDING * scale).sqrt();
        let depth = (-gap).max(0.0);
        base.max(2.0 * (2.0 * depth / d).sqrt()).min(1.0)
    }
}

/// The least rise of a hop at `r`, `ρ = 2⁻³⁰ (‖r‖ + radius)`: far above the rounding of a
/// gap there ([`hop_speed`], [`rounding_hop_time`]).
#[inline]
fn rounding_rise(r: DVec3, radius: f64) -> f64 {
    (r.length() + radius) / (1u64 << 30) as f64
}

/// The least normal speed at which a sphere leaves a wall under gravity where gravity itself
/// presses it on (`γ = −g·n̂ > 0`): enough to rise at least `2⁻³⁰ (‖r‖ + radius)`, far above
/// the rounding of the gap there, so that the contact it left and the one it returns to are
/// told apart; `0` elsewhere. The TC model raises it for a contact within `tc` of the sphere's
/// last (`Materials::rest_hop`; docs/derivations/gravity.md, "Resting contact").
pub(crate) fn hop_speed(g: DVec3, n: DVec3, r: DVec3, radius: f64) -> f64 {
    let gamma = -g.dot(n);
    if gamma > 0.0 {
        (2.0 * gamma * rounding_rise(r, radius)).sqrt()
    } else {
        0.0
    }
}

/// The flight of the hop at rounding height `ρ = 2⁻³⁰ (‖r‖ + radius)` off a floor, `2 √(2ρ/‖g‖)`
/// ([`hop_speed`] without TC, `γ = ‖g‖`): the least time a sphere resting on a floor there spends
/// off it. `0` without gravity.
pub(crate) fn rounding_hop_time(g: DVec3, r: DVec3, radius: f64) -> f64 {
    let g = g.length();
    if g == 0.0 {
        return 0.0;
    }
    2.0 * (2.0 * rounding_rise(r, radius) / g).sqrt()
}

/// `κ²` of a concave wall's floor angle where rounding does not matter: `2⁻²⁴` (the sphere
/// leaves at `2⁻¹²` rad, about 0.014°, or more).
const WALL_FLOOR_SQUARED: f64 = 1.0 / (1u64 << 24) as f64;
/// What rounding adds to `κ²`, per unit of `(‖c‖ + D + speed·now) / D`: `2⁻⁴⁴`, 2⁸ times the
/// bound on the kernel's relative error in `C` at the wall.
const WALL_FLOOR_ROUNDING: f64 = 1.0 / (1u64 << 44) as f64;

impl KernelCounts {
    /// Counts `n` evaluations of the kernel of `kind`.
    #[inline]
    pub(crate) fn add(&mut self, kind: ShapeKind, n: u64) {
        match kind {
            ShapeKind::Sphere => self.sphere += n,
            ShapeKind::Plane => self.plane += n,
            ShapeKind::Cylinder => self.cylinder += n,
            ShapeKind::Container => self.container += n,
        }
    }
}
