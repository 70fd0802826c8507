//! Hard-case families, one kind of numerical difficulty each, with a knob `k`: the larger,
//! the harder (typically a ratio of `10^k`). Each generates pairs in f64 and rounds them once
//! to the f32 shapes the kernels and the oracle both take as exact input.

use glam::DVec3;

use super::pair::Pair;
use spheresweep::Shape;
use spheresweep::rng::Rng;
use spheresweep::{Container, Cylinder, Plane, Sphere};

/// A family of hard cases.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Family {
    /// Well-conditioned sphere pairs: closest approach at least 10 % from grazing.
    Baseline,
    /// Sphere pairs whose closest approach is `D (1 ± 10⁻ᵏ)`.
    Grazing,
    /// Spheres of contact distance 1 that start `10ᵏ` apart, aimed within `2D`.
    FarSmall,
    /// Sphere pairs that start `D·10⁻ᵏ` apart and approach.
    AlmostTouching,
    /// Sphere pairs with a relative speed of `10⁻ᵏ`.
    SlowMotion,
    /// A sphere approaching a plane at an angle of `10⁻ᵏ` radians.
    ParallelToPlane,
    /// A sphere `10ᵏ` from a plane whose given point is `10ᵏ` away along the plane.
    FarFromPlane,
    /// A sphere near a plane near the origin whose given point is `10ᵏ` away along it.
    PlaneFarAnchor,
    /// A cylinder whose given axis point is `10ᵏ` along the axis from the sphere.
    CylinderFarAnchor,
    /// A sphere moving at an angle of `10⁻ᵏ` from a cylinder's axis, towards it.
    CylinderAlongAxis,
    /// A sphere inside a container, starting `D·10⁻ᵏ` from the wall.
    ContainerWall,
    /// Baseline sphere pairs with the whole scene `10ᵏ` from the origin.
    LargeOffset,
    /// Radii `10⁻ᵏ` next to `10ᵏ`.
    MixedScales,
}

impl Family {
    /// Every family, in report order.
    pub const ALL: [Family; 13] = [
        Family::Baseline,
        Family::Grazing,
        Family::FarSmall,
        Family::AlmostTouching,
        Family::SlowMotion,
        Family::ParallelToPlane,
        Family::FarFromPlane,
        Family::PlaneFarAnchor,
        Family::CylinderFarAnchor,
        Family::CylinderAlongAxis,
        Family::ContainerWall,
        Family::LargeOffset,
        Family::MixedScales,
    ];

    /// Short name for tables.
    pub fn name(self) -> &'static str {
        match self {
            Family::Baseline => "baseline",
            Family::Grazing => "grazing",
            Family::FarSmall => "far-small",
            Family::AlmostTouching => "almost-touching",
            Family::SlowMotion => "slow-motion",
            Family::ParallelToPlane => "parallel-to-plane",
            Family::FarFromPlane => "far-from-plane",
            Family::PlaneFarAnchor => "plane-far-anchor",
            Family::CylinderFarAnchor => "cylinder-far-anchor",
            Family::CylinderAlongAxis => "cylinder-along-axis",
            Family::ContainerWall => "container-wall",
            Family::LargeOffset => "large-offset",
            Family::MixedScales => "mixed-scales",
        }
    }

    /// The difficulty `k` the study and `tests/hard_cases.rs` state results at.
    pub fn stated_level(self) -> u32 {
        match self {
            Family::Baseline => 0,
            Family::FarSmall | Family::MixedScales => 3,
            Family::CylinderAlongAxis => 4,
            _ => 5,
        }
    }

    /// One pair of the family at difficulty `k`.
    pub fn generate(self, rng: &mut Rng, k: u32) -> Pair {
        let e = 10f64.powi(k as i32);
        match self {
            Family::Baseline => baseline(rng, DVec3::ZERO, 1.0, 1.0),
            Family::LargeOffset => {
                let offset = rng.direction() * e;
                baseline(rng, offset, 1.0, 1.0)
            }
            Family::MixedScales => baseline(rng, DVec3::ZERO, 1.0 / e, e),
            Family::Grazing => {
                let margin = 1.0 + rng.sign() * rng.range(0.5, 1.0) / e;
                let (ra, rb) = (rng_radius(rng), rng_radius(rng));
                aimed(rng, DVec3::ZERO, ra, rb, 10.0, margin, 1.0)
            }
            Family::FarSmall => {
                let margin = rng.range(0.0, 2.0);
                aimed(rng, DVec3::ZERO, 0.5, 0.5, e, margin, 1.0)
            }
            Family::SlowMotion => {
                let margin = well_separated(rng);
                let (ra, rb) = (rng_radius(rng), rng_radius(rng));
                aimed(rng, DVec3::ZERO, ra, rb, 3.0, margin, 1.0 / e)
            }
            Family::AlmostTouching => {
                let (ra, rb) = (rng_radius(rng), rng_radius(rng));
                let d = ra + rb;
                let u = rng.direction();
                let a = sphere(rng.cube(10.0), rng.cube(2.0), ra);
                let gap = d * rng.range(0.5, 1.0) / e;
                let centre = a.centre().as_dvec3() + u * (d + gap);
                // Approaching along −u, with a sideways part.
                let v = a.velocity().as_dvec3() - u * rng.range(0.5, 2.0) + rng.perpendicular(u);
                pair(a, Shape::Sphere(sphere(centre, v, rb)))
            }
            Family::ParallelToPlane => {
                let n = rng.direction();
                let point = rng.cube(10.0);
                let r = rng_radius(rng);
                let along = rng.perpendicular(n);
                let height = r + rng.range(1.0, 5.0);
                let c = point + n * height + along * rng.range(-10.0, 10.0);
                let angle = rng.range(0.5, 1.0) / e;
                let v = (along * angle.cos() - n * angle.sin()) * rng.range(0.5, 2.0);
                pair(sphere(c, v, r), Shape::Plane(plane(point, n)))
            }
            Family::FarFromPlane => {
                let n = rng.direction();
                let foot = rng.cube(10.0);
                let in_plane = rng.perpendicular(n) * e * rng.range(0.5, 1.0);
                let r = rng_radius(rng);
                let c = foot + n * e * rng.range(1.0, 2.0);
                let v = -n * rng.range(0.5, 2.0) + rng.perpendicular(n) * rng.range(0.0, 2.0);
                pair(sphere(c, v, r), Shape::Plane(plane(foot + in_plane, n)))
            }
            Family::PlaneFarAnchor => {
                let n = rng.direction();
                let foot = rng.cube(5.0);
                let along = rng.perpendicular(n);
                let anchor = foot + along * e * rng.sign();
                let r = rng_radius(rng);
                let c = foot + n * (r + rng.range(0.5, 5.0)) + along * rng.range(-5.0, 5.0);
                let v = -n * rng.range(0.5, 2.0) + rng.perpendicular(n) * rng.range(0.0, 2.0);
                pair(sphere(c, v, r), Shape::Plane(plane(anchor, n)))
            }
            Family::CylinderFarAnchor => {
                let s = rng.direction();
                let foot = rng.cube(5.0);
                let anchor = foot + s * e * rng.sign();
                let (r, rc) = (rng_radius(rng), rng_radius(rng));
                let out = rng.perpendicular(s);
                let c = foot + out * (r + rc + rng.range(1.0, 5.0)) + s * rng.range(-5.0, 5.0);
                // Aimed at the axis with a sideways miss distance around D.
                let side = s.cross(out) * (r + rc) * well_separated(rng);
                let v = (-out * rng.range(0.5, 2.0) + s * rng.range(-1.0, 1.0)) + side * 0.1;
                // The second axis point is the near foot: the direction is accurate, while the
                // anchor the kernels subtract is far.
                pair(sphere(c, v, r), Shape::Cylinder(cylinder(anchor, foot, rc)))
            }
            Family::CylinderAlongAxis => {
                let s = rng.direction();
                let foot = rng.cube(5.0);
                let (r, rc) = (rng_radius(rng), rng_radius(rng));
                let out = rng.perpendicular(s);
                let c = foot + out * (r + rc) * rng.range(1.5, 5.0);
                let angle = rng.range(0.5, 1.0) / e;
                let toward = -out + s.cross(out) * (well_separated(rng) - 1.0) * 0.5;
                let v = (s * angle.cos() + toward.normalize() * angle.sin()) * rng.range(0.5, 2.0);
                pair(
                    sphere(c, v, r),
                    Shape::Cylinder(cylinder(foot, foot + s, rc)),
                )
            }
            Family::ContainerWall => {
                let big = rng.range(10.0, 100.0);
                let r = rng_radius(rng);
                let d = big - r;
                let centre = rng.cube(10.0);
                let u = rng.direction();
                let c = centre + u * d * (1.0 - rng.range(0.5, 1.0) / e);
                let v = rng.direction() * rng.range(0.5, 2.0);
                let vessel = Container::new(centre.as_vec3().into(), big as f32).expect("valid");
                pair(sphere(c, v, r), Shape::Container(vessel))
            }
        }
    }
}

fn rng_radius(rng: &mut Rng) -> f64 {
    rng.range(0.25, 2.0)
}

/// A miss distance in units of `D` at least 10 % from grazing: hits and misses alike.
fn well_separated(rng: &mut Rng) -> f64 {
    if rng.coin() {
        rng.range(0.0, 0.9)
    } else {
        rng.range(1.1, 2.0)
    }
}

fn baseline(rng: &mut Rng, offset: DVec3, small: f64, large: f64) -> Pair {
    let margin = well_separated(rng);
    let (ra, rb) = (rng_radius(rng) * small, rng_radius(rng) * large);
    let distance = rng.range(3.0, 10.0);
    aimed(rng, offset, ra, rb, distance, margin, 1.0)
}

/// Sphere B sent past sphere A: start `distance · D` away, closest approach `margin · D`,
/// relative speed `speed` (around 1).
fn aimed(
    rng: &mut Rng,
    offset: DVec3,
    ra: f64,
    rb: f64,
    distance: f64,
    margin: f64,
    speed: f64,
) -> Pair {
    let d = ra + rb;
    let (u, w) = {
        let u = rng.direction();
        (u, rng.perpendicular(u))
    };
    let ca = offset + rng.cube(10.0 * d.max(1.0));
    let va = rng.cube(2.0) * speed;
    let cb = ca + w * (margin * d) - u * (distance * d);
    let vb = va + u * speed * rng.range(0.5, 2.0);
    pair(sphere(ca, va, ra), Shape::Sphere(sphere(cb, vb, rb)))
}

fn pair(sphere: Sphere, other: Shape) -> Pair {
    Pair { sphere, other }
}

fn sphere(c: DVec3, v: DVec3, r: f64) -> Sphere {
    Sphere::new(c.as_vec3().into(), v.as_vec3().into(), r as f32, 1.0).expect("finite")
}

fn plane(p: DVec3, n: DVec3) -> Plane {
    Plane::new(p.as_vec3().into(), n.as_vec3().into()).expect("unit normal")
}

fn cylinder(p1: DVec3, p2: DVec3, r: f64) -> Cylinder {
    Cylinder::new(p1.as_vec3().into(), p2.as_vec3().into(), r as f32).expect("distinct points")
}
