//! The scalar reference path: the seed's formulas, literally, in f64, one file per pair kind.
//!
//! It is the specification the 8-wide kernels are tested against. Every function here takes
//! validated shapes, so no input can make it panic or divide by zero. Policies for the cases
//! the seed leaves open are in [`quadratic`] and in docs/derivations/policies.md.

pub mod quadratic;
pub mod scene;
pub mod sphere_container;
pub mod sphere_cylinder;
pub mod sphere_plane;
pub mod sphere_sphere;

use glam::DVec3;

pub use quadratic::{Quadratic, Roots, Side, earliest_contact};

/// A contact found by the reference path: when, where, and which way.
///
/// "A" is always the moving sphere of the query (for a container, the sphere inside it).
/// `normal` is the seed's summary-table normal on A: the unit vector that pushes A away from
/// the other body (for two spheres `(r_A − r_B)/‖r_A − r_B‖`, which the seed's text calls
/// `n̂_B`, the outward surface normal of B; A's own outward surface normal is `−normal`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Time of impact, in `[0, t_max]`.
    pub time: f64,
    /// Centre of sphere A at `time` (`r_A = r_A0 + v_A t`).
    pub centre: DVec3,
    /// The other body's reference point at `time`: B's centre, the container's centre, the
    /// foot of A's centre on the plane, or on the cylinder's axis.
    pub other: DVec3,
    /// The contact point, on the surface of both bodies.
    pub point: DVec3,
    /// Unit normal pushing A away from the other body.
    pub normal: DVec3,
}

/// `v` normalised, or `fallback` normalised when `v` is zero (a contact of two point-like
/// bodies, where the normal is the limit of the direction just before contact).
#[inline]
fn unit_or(v: DVec3, fallback: DVec3) -> DVec3 {
    v.try_normalize()
        .or_else(|| fallback.try_normalize())
        .unwrap_or(DVec3::ZERO)
}
