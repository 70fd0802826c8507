//! Hard-case families, one kind of numerical difficulty each, with a knob `k`: the larger,
//! the harder (typically a ratio of `10^k`). Each generates pairs in f64 and rounds them once
//! to the f32 shapes the kernels and the oracle both take as exact input. A family's [`Case`]
//! is a pair and its window: `[0, ∞)` but for the window-edge families, whose window ends
//! within a few ulps of the contact, and container-offset, whose window ends well before the
//! contact for some cases. [`scaled_case`] draws the well-conditioned cases of the scale sweep.

use glam::DVec3;

use super::oracle::{Exact, Inputs};
use super::pair::{Case, Pair};
use spheresweep::rng::Rng;
use spheresweep::{Container, Cylinder, Plane, Sphere};
use spheresweep::{Shape, ShapeKind};

/// A family of hard cases.
///
/// ```
/// use spheresweep::ShapeKind;
/// use spheresweep_study::Family;
/// assert_eq!((Family::Grazing.name(), Family::Grazing.kind()), ("grazing", ShapeKind::Sphere));
/// assert_eq!(Family::ALL.len(), 22);
/// ```
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
    /// A sphere and a plane with the whole scene `10ᵏ` from the origin, the plane given by a
    /// point within about 20 of the sphere: approaching, receding and shallow (0.01 – 0.1 rad).
    PlaneOffsetNear,
    /// As [`Family::PlaneOffsetNear`], the plane's given point moved `10ᵏ` along the plane.
    PlaneOffsetFar,
    /// A sphere aimed past a cylinder with the whole scene `10ᵏ` from the origin, the axis
    /// given by a point within about 20 of the sphere; 20 % within 1 – 10 % of grazing.
    CylinderOffsetNear,
    /// As [`Family::CylinderOffsetNear`], the given axis point moved `10ᵏ` along the axis.
    CylinderOffsetFar,
    /// A sphere inside a container `10ᵏ` from the origin, 20 % of them within 1 – 10 % of `D`
    /// from the wall; 30 % with a window that ends well before the contact (misses).
    ContainerOffset,
    /// Radii `10⁻ᵏ` next to `10ᵏ`.
    MixedScales,
    /// Well-conditioned sphere pairs that touch, the window ending within `k` ulps of the
    /// contact (either side).
    WindowEdgeSphere,
    /// A sphere approaching a plane, the window ending within `k` ulps of the contact.
    WindowEdgePlane,
    /// A sphere aimed at a cylinder (within 90 % of `D`), the window ending within `k` ulps of
    /// the contact.
    WindowEdgeCylinder,
    /// A sphere inside a container, the window ending within `k` ulps of the contact.
    WindowEdgeContainer,
}

impl Family {
    /// Every family, in report order.
    pub const ALL: [Family; 22] = [
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
        Family::PlaneOffsetNear,
        Family::PlaneOffsetFar,
        Family::CylinderOffsetNear,
        Family::CylinderOffsetFar,
        Family::ContainerOffset,
        Family::MixedScales,
        Family::WindowEdgeSphere,
        Family::WindowEdgePlane,
        Family::WindowEdgeCylinder,
        Family::WindowEdgeContainer,
    ];

    /// Short name for tables.
    ///
    /// ```
    /// use spheresweep_study::Family;
    /// assert_eq!(Family::WindowEdgePlane.name(), "window-edge-plane");
    /// ```
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
            Family::PlaneOffsetNear => "plane-offset-near",
            Family::PlaneOffsetFar => "plane-offset-far",
            Family::CylinderOffsetNear => "cylinder-offset-near",
            Family::CylinderOffsetFar => "cylinder-offset-far",
            Family::ContainerOffset => "container-offset",
            Family::MixedScales => "mixed-scales",
            Family::WindowEdgeSphere => "window-edge-sphere",
            Family::WindowEdgePlane => "window-edge-plane",
            Family::WindowEdgeCylinder => "window-edge-cylinder",
            Family::WindowEdgeContainer => "window-edge-container",
        }
    }

    /// The kind of body the sphere meets in this family.
    ///
    /// ```
    /// use spheresweep::ShapeKind;
    /// use spheresweep_study::Family;
    /// assert_eq!(Family::ContainerWall.kind(), ShapeKind::Container);
    /// assert_eq!(Family::CylinderAlongAxis.kind(), ShapeKind::Cylinder);
    /// ```
    pub fn kind(self) -> ShapeKind {
        match self {
            Family::Baseline
            | Family::Grazing
            | Family::FarSmall
            | Family::AlmostTouching
            | Family::SlowMotion
            | Family::LargeOffset
            | Family::MixedScales
            | Family::WindowEdgeSphere => ShapeKind::Sphere,
            Family::ParallelToPlane
            | Family::FarFromPlane
            | Family::PlaneFarAnchor
            | Family::PlaneOffsetNear
            | Family::PlaneOffsetFar
            | Family::WindowEdgePlane => ShapeKind::Plane,
            Family::CylinderFarAnchor
            | Family::CylinderAlongAxis
            | Family::CylinderOffsetNear
            | Family::CylinderOffsetFar
            | Family::WindowEdgeCylinder => ShapeKind::Cylinder,
            Family::ContainerWall | Family::ContainerOffset | Family::WindowEdgeContainer => {
                ShapeKind::Container
            }
        }
    }

    /// The difficulty `k` the study and `tests/hard_cases.rs` state results at.
    ///
    /// ```
    /// use spheresweep_study::Family;
    /// assert_eq!((Family::Baseline.stated_level(), Family::Grazing.stated_level()), (0, 5));
    /// ```
    pub fn stated_level(self) -> u32 {
        match self {
            Family::Baseline => 0,
            Family::FarSmall | Family::MixedScales => 3,
            Family::CylinderAlongAxis => 4,
            Family::WindowEdgeSphere
            | Family::WindowEdgePlane
            | Family::WindowEdgeCylinder
            | Family::WindowEdgeContainer => 4,
            _ => 5,
        }
    }

    /// One pair of the family at difficulty `k` (the pair of [`Family::case`]).
    ///
    /// ```
    /// use spheresweep::Shape;
    /// use spheresweep_study::{Family, Rng};
    /// let pair = Family::ParallelToPlane.generate(&mut Rng::new(1), 3);
    /// assert!(matches!(pair.other, Shape::Plane(_)));
    /// ```
    pub fn generate(self, rng: &mut Rng, k: u32) -> Pair {
        self.case(rng, k).pair
    }

    /// One case of the family at difficulty `k`: a pair and its window.
    ///
    /// ```
    /// use spheresweep_study::{Family, Rng};
    /// let mut rng = Rng::new(1);
    /// assert_eq!(Family::Baseline.case(&mut rng, 0).t_max, f32::INFINITY); // an open window
    /// // A window-edge case's window ends near its contact.
    /// assert!(Family::WindowEdgeSphere.case(&mut rng, 4).t_max.is_finite());
    /// ```
    pub fn case(self, rng: &mut Rng, k: u32) -> Case {
        let e = 10f64.powi(k as i32);
        let pair = match self {
            Family::PlaneOffsetNear | Family::PlaneOffsetFar => {
                let origin = rng.direction() * e;
                let far = if self == Family::PlaneOffsetFar {
                    e
                } else {
                    0.0
                };
                plane_scene(rng, origin, far, PlaneMotion::Mixed)
            }
            Family::CylinderOffsetNear | Family::CylinderOffsetFar => {
                let origin = rng.direction() * e;
                let far = if self == Family::CylinderOffsetFar {
                    e
                } else {
                    0.0
                };
                let margin = margin_mix(rng);
                cylinder_scene(rng, origin, far, margin)
            }
            Family::ContainerOffset => {
                let origin = rng.direction() * e;
                let frac = if rng.unit() < 0.2 {
                    1.0 - rng.range(0.01, 0.1)
                } else {
                    rng.range(0.0, 0.9)
                };
                let pair = container_scene(rng, origin, frac);
                // Misses: a window ending at 30 – 80 % of the contact time (the reference's:
                // far enough from it for every path to tell).
                let t_max = if rng.unit() < 0.3 {
                    pair.time_of_impact(f64::INFINITY)
                        .map_or(f32::INFINITY, |t| (t * rng.range(0.3, 0.8)) as f32)
                } else {
                    f32::INFINITY
                };
                return Case { pair, t_max };
            }
            Family::WindowEdgeSphere
            | Family::WindowEdgePlane
            | Family::WindowEdgeCylinder
            | Family::WindowEdgeContainer => return window_edge(rng, self.kind(), k),
            _ => self.classic(rng, e),
        };
        Case::open(pair)
    }

    /// The families of the first study, each a pair with the window `[0, ∞)`.
    fn classic(self, rng: &mut Rng, e: f64) -> Pair {
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
            _ => unreachable!("{} is generated by Family::case", self.name()),
        }
    }
}

/// What a sphere near a plane does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PlaneMotion {
    /// 60 % approaching at 30° or more from the plane, 25 % receding, 15 % approaching at a
    /// shallow 0.01 – 0.1 rad.
    Mixed,
    /// Approaching at 30° or more, or receding, half each: well conditioned.
    Steep,
    /// Approaching at 30° or more.
    Approach,
}

/// A velocity for a sphere on the side `out` of a plane (`out`: unit normal towards the sphere).
fn plane_motion(rng: &mut Rng, out: DVec3, motion: PlaneMotion) -> DVec3 {
    let along = rng.perpendicular(out);
    let speed = rng.range(0.5, 2.0);
    let pick = rng.unit();
    let (approach, shallow) = match motion {
        PlaneMotion::Mixed => (!(0.6..0.85).contains(&pick), pick >= 0.85),
        PlaneMotion::Steep => (pick < 0.5, false),
        PlaneMotion::Approach => (true, false),
    };
    if shallow {
        let angle = rng.range(0.01, 0.1);
        (along * angle.cos() - out * angle.sin()) * speed
    } else {
        let toward = if approach { -out } else { out };
        (toward + along * rng.range(0.0, 1.5)).normalize() * speed
    }
}

/// A sphere within about 20 of a point `near` of a plane (`near` within 5 of `origin`), on
/// either side; the plane is given by `near` moved `far` along the plane.
fn plane_scene(rng: &mut Rng, origin: DVec3, far: f64, motion: PlaneMotion) -> Pair {
    let n = rng.direction();
    let near = origin + rng.cube(5.0);
    let r = rng_radius(rng);
    let out = n * rng.sign();
    let c = near + out * (r + rng.range(0.5, 10.0)) + rng.perpendicular(n) * rng.range(0.0, 10.0);
    let v = plane_motion(rng, out, motion);
    let anchor = near + rng.perpendicular(n) * far * rng.sign();
    pair(sphere(c, v, r), Shape::Plane(plane(anchor, n)))
}

/// A sphere whose motion across a cylinder's axis passes it at `margin · D` (the part of the
/// motion perpendicular to the axis is aimed; the axial part is up to the same speed), starting
/// 1.5 – 4 `D` from the axis near its point `near` (within 5 of `origin`); the cylinder is
/// given by `near` moved `far` along the axis, with `Cylinder::from_axis`.
fn cylinder_scene(rng: &mut Rng, origin: DVec3, far: f64, margin: f64) -> Pair {
    let s = rng.direction();
    let near = origin + rng.cube(5.0);
    let (r, rc) = (rng_radius(rng), rng_radius(rng));
    let d = r + rc;
    let u = rng.perpendicular(s);
    let w = s.cross(u);
    let across = w * (margin * d) - u * (d * rng.range(1.5, 4.0));
    let c = near + across + s * rng.range(-5.0, 5.0);
    let speed = rng.range(0.5, 2.0);
    let v = u * speed + s * (speed * rng.range(-1.0, 1.0));
    let anchor = near + s * (far * rng.sign());
    let axis = Cylinder::from_axis(anchor.as_vec3().into(), s.as_vec3().into(), rc as f32)
        .expect("a finite point and a unit axis");
    pair(sphere(c, v, r), Shape::Cylinder(axis))
}

/// A sphere inside a container of radius 10 – 100 centred within 10 of `origin`, at `frac · D`
/// from the centre, moving in a random direction.
fn container_scene(rng: &mut Rng, origin: DVec3, frac: f64) -> Pair {
    let big = rng.range(10.0, 100.0);
    let r = rng_radius(rng);
    let d = big - r;
    let centre = origin + rng.cube(10.0);
    let c = centre + rng.direction() * (d * frac);
    let v = rng.direction() * rng.range(0.5, 2.0);
    let vessel = Container::new(centre.as_vec3().into(), big as f32).expect("valid");
    pair(sphere(c, v, r), Shape::Container(vessel))
}

/// A miss distance in units of `D`: 80 % at least 10 % from grazing, 20 % within 1 – 10 % of
/// it (either side).
fn margin_mix(rng: &mut Rng) -> f64 {
    if rng.unit() < 0.8 {
        well_separated(rng)
    } else {
        1.0 + rng.sign() * rng.range(0.01, 0.1)
    }
}

/// A well-conditioned pair of `kind` near the origin: one of the scale sweep's, before scaling.
fn well_conditioned(rng: &mut Rng, kind: ShapeKind) -> Pair {
    match kind {
        ShapeKind::Sphere => baseline(rng, DVec3::ZERO, 1.0, 1.0),
        ShapeKind::Plane => plane_scene(rng, DVec3::ZERO, 0.0, PlaneMotion::Steep),
        ShapeKind::Cylinder => {
            let margin = well_separated(rng);
            cylinder_scene(rng, DVec3::ZERO, 0.0, margin)
        }
        ShapeKind::Container => {
            let frac = rng.range(0.0, 0.9);
            container_scene(rng, DVec3::ZERO, frac)
        }
        other => unimplemented!("no family of {other} pairs yet"),
    }
}

/// A well-conditioned contact of `kind` near the origin, the window ending at the f32 nearest
/// the exact contact time moved by `j` ulps, `j` uniform in `−k ..= k`.
fn window_edge(rng: &mut Rng, kind: ShapeKind, k: u32) -> Case {
    loop {
        let pair = match kind {
            ShapeKind::Sphere => {
                let (ra, rb) = (rng_radius(rng), rng_radius(rng));
                let (distance, margin) = (rng.range(3.0, 10.0), rng.range(0.0, 0.9));
                aimed(rng, DVec3::ZERO, ra, rb, distance, margin, 1.0)
            }
            ShapeKind::Plane => plane_scene(rng, DVec3::ZERO, 0.0, PlaneMotion::Approach),
            ShapeKind::Cylinder => {
                let margin = rng.range(0.0, 0.9);
                cylinder_scene(rng, DVec3::ZERO, 0.0, margin)
            }
            ShapeKind::Container => {
                let frac = rng.range(0.0, 0.9);
                container_scene(rng, DVec3::ZERO, frac)
            }
            other => unimplemented!("no family of {other} pairs yet"),
        };
        let Some(t) = Exact::of(&pair).time(f64::INFINITY).filter(|t| *t > 0.0) else {
            continue;
        };
        let j = (rng.range(0.0, f64::from(2 * k + 1)).floor() as i64 - i64::from(k))
            .clamp(-i64::from(k), i64::from(k));
        let mut t_max = t as f32;
        for _ in 0..j.unsigned_abs() {
            t_max = if j > 0 {
                t_max.next_up()
            } else {
                t_max.next_down()
            };
        }
        return Case {
            pair,
            t_max: t_max.max(0.0),
        };
    }
}

/// What the scale sweep multiplies by the scale `s`.
///
/// ```
/// use spheresweep_study::Scaling;
/// assert_eq!(Scaling::ALL.map(Scaling::name), ["lengths", "speeds", "all"]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scaling {
    /// Positions (centres, points on planes and axes) and radii: times scale by `s`.
    Lengths,
    /// Velocities: times scale by `1/s`.
    Speeds,
    /// Everything: times unchanged.
    All,
}

impl Scaling {
    /// Every scaling, in report order.
    pub const ALL: [Scaling; 3] = [Scaling::Lengths, Scaling::Speeds, Scaling::All];

    /// Short name for messages.
    ///
    /// ```
    /// assert_eq!(spheresweep_study::Scaling::Speeds.name(), "speeds");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Scaling::Lengths => "lengths",
            Scaling::Speeds => "speeds",
            Scaling::All => "all",
        }
    }
}

/// A well-conditioned case of `kind` (at least 10 % from grazing; a plane approached or left at
/// 30° or more; a sphere inside its container at most 90 % of the way to the wall) drawn near
/// the origin at scale 1, rounded to f32, then with the quantities `scaling` names multiplied
/// by `s` and rounded again. Half the cases that touch get a window ending at 0.3 – 0.7 or
/// 1.5 – 3 times the exact contact time (where that is a finite f32), the rest `[0, ∞)`.
///
/// `None` when a scaled input is not a finite f32 (the case is skipped). Normals and axes are
/// not scaled.
///
/// ```
/// use spheresweep::{Shape, ShapeKind};
/// use spheresweep_study::{Rng, Scaling, scaled_case};
/// let mut rng = Rng::new(1);
/// let case = scaled_case(ShapeKind::Plane, &mut rng, Scaling::Lengths, 1e6).unwrap();
/// assert!(matches!(case.pair.other, Shape::Plane(_)));
/// // Lengths of 10⁴⁰ are beyond f32: the case is skipped.
/// assert!(scaled_case(ShapeKind::Sphere, &mut rng, Scaling::Lengths, 1e40).is_none());
/// ```
pub fn scaled_case(kind: ShapeKind, rng: &mut Rng, scaling: Scaling, s: f64) -> Option<Case> {
    let base = Inputs::of(&well_conditioned(rng, kind));
    let (lengths, speeds) = match scaling {
        Scaling::Lengths => (s, 1.0),
        Scaling::Speeds => (1.0, s),
        Scaling::All => (s, s),
    };
    let speed_index =
        |i: usize| (3..6).contains(&i) || (kind == ShapeKind::Sphere && (10..13).contains(&i));
    let direction_index =
        |i: usize| matches!(kind, ShapeKind::Plane | ShapeKind::Cylinder) && (10..13).contains(&i);
    let mut inputs = base;
    for (i, &x) in base.values().iter().enumerate() {
        let factor = if direction_index(i) {
            1.0
        } else if speed_index(i) {
            speeds
        } else {
            lengths
        };
        let scaled = (f64::from(x) * factor) as f32;
        if !scaled.is_finite() {
            return None;
        }
        inputs = inputs.with(i, scaled);
    }
    let pair = inputs.pair()?;
    let windowed = rng.coin();
    let factor = if rng.coin() {
        rng.range(0.3, 0.7)
    } else {
        rng.range(1.5, 3.0)
    };
    let t_max = match Exact::of(&pair).time(f64::INFINITY) {
        Some(t) if windowed && t > 0.0 => {
            let end = (t * factor) as f32;
            if end.is_finite() { end } else { f32::INFINITY }
        }
        _ => f32::INFINITY,
    };
    Some(Case { pair, t_max })
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
