//! The four shapes of the seed, each built only through a validating constructor.
//!
//! Inputs are `f32` (the precision of the store and of the 8-wide kernels); the scalar
//! reference widens them to `f64`. Every finite value is accepted, at any scale: the kernels
//! answer pairs whose magnitudes leave f32's safe range in f64 (docs/derivations/range.md). Directions (plane normal, cylinder axis) are normalised in
//! `f64` and rounded once to `f32`.

use glam::{DVec3, Vec3};

use crate::error::{Problem, ShapeError};

/// The four kinds of body of the seed: the one enum that names them (errors, contacts, counters).
///
/// ```
/// use spheresweep::ShapeKind;
/// assert_eq!(ShapeKind::ALL[0], ShapeKind::Sphere); // spheres win ties
/// assert!(ShapeKind::Plane < ShapeKind::Container);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[non_exhaustive]
pub enum ShapeKind {
    /// A moving [`Sphere`].
    Sphere,
    /// A static infinite [`Plane`].
    Plane,
    /// A static infinite [`Cylinder`].
    Cylinder,
    /// A static spherical [`Container`].
    Container,
}

impl ShapeKind {
    /// Every kind, in the order ties are broken (spheres first).
    pub const ALL: [ShapeKind; 4] = [
        ShapeKind::Sphere,
        ShapeKind::Plane,
        ShapeKind::Cylinder,
        ShapeKind::Container,
    ];

    /// The code of "no body" beside [`ShapeKind::code`] in columns of kinds (a first contact
    /// that did not happen).
    pub const NONE_CODE: u8 = 255;

    /// The kind's code in columns of kinds (query files, Parquet, NumPy, Python, checkpoints):
    /// its place in the tie-break order, sphere `0`, plane `1`, cylinder `2`, container `3`;
    /// "none" is [`ShapeKind::NONE_CODE`].
    ///
    /// ```
    /// use spheresweep::ShapeKind;
    /// for kind in ShapeKind::ALL {
    ///     assert_eq!(ShapeKind::from_code(kind.code()), Some(kind));
    /// }
    /// assert_eq!(ShapeKind::Container.code(), 3);
    /// assert_eq!(ShapeKind::from_code(ShapeKind::NONE_CODE), None);
    /// ```
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The kind of a [`ShapeKind::code`], `None` for any other byte.
    pub fn from_code(code: u8) -> Option<ShapeKind> {
        ShapeKind::ALL.get(usize::from(code)).copied()
    }

    /// The lower-case name used in messages and reports.
    ///
    /// ```
    /// use spheresweep::ShapeKind;
    /// assert_eq!(ShapeKind::Cylinder.name(), "cylinder");
    /// assert_eq!(ShapeKind::Container.to_string(), "container");
    /// ```
    pub const fn name(self) -> &'static str {
        match self {
            ShapeKind::Sphere => "sphere",
            ShapeKind::Plane => "plane",
            ShapeKind::Cylinder => "cylinder",
            ShapeKind::Container => "container",
        }
    }
}

impl std::fmt::Display for ShapeKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Any one body a sphere can touch, by value: a single pair query names its other body with it.
///
/// ```
/// use spheresweep::{Plane, Shape, ShapeKind};
/// let floor = Shape::from(Plane::new([0.0; 3], [0.0, 0.0, 1.0])?);
/// assert_eq!(floor.kind(), ShapeKind::Plane);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Shape {
    /// A second moving sphere (exterior contact).
    Sphere(Sphere),
    /// A static plane.
    Plane(Plane),
    /// A static infinite cylinder.
    Cylinder(Cylinder),
    /// A container the sphere is inside.
    Container(Container),
}

impl Shape {
    /// Which kind of body this is.
    ///
    /// ```
    /// use spheresweep::{Container, Shape, ShapeKind};
    /// let vessel = Shape::Container(Container::new([0.0; 3], 10.0)?);
    /// assert_eq!(vessel.kind(), ShapeKind::Container);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub const fn kind(&self) -> ShapeKind {
        match self {
            Shape::Sphere(_) => ShapeKind::Sphere,
            Shape::Plane(_) => ShapeKind::Plane,
            Shape::Cylinder(_) => ShapeKind::Cylinder,
            Shape::Container(_) => ShapeKind::Container,
        }
    }
}

macro_rules! shape_from {
    ($($t:ident),*) => {$(
        impl From<$t> for Shape {
            fn from(s: $t) -> Self {
                Shape::$t(s)
            }
        }
    )*};
}
shape_from!(Sphere, Plane, Cylinder, Container);

/// A sphere moving at constant velocity: `r(t) = centre + velocity · t`.
///
/// ```
/// use spheresweep::Sphere;
/// let s = Sphere::new([0.0, 1.0, 0.0], [1.0, 0.0, 0.0], 0.5, 2.0)?;
/// assert_eq!(s.centre_at(2.0), glam::Vec3::new(2.0, 1.0, 0.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    centre: Vec3,
    velocity: Vec3,
    radius: f32,
    mass: f32,
}

/// A static infinite plane through `point` with unit `normal` (two-sided: a sphere may hit
/// it from either side).
///
/// ```
/// use spheresweep::{Plane, QueryOptions, Shape, Sphere, time_of_impact};
/// let wall = Plane::new([0.0; 3], [1.0, 0.0, 0.0])?;
/// let ball = Sphere::new([-5.0, 0.0, 0.0], [2.0, 0.0, 0.0], 1.0, 1.0)?; // hits the back side
/// assert_eq!(time_of_impact(&ball, &Shape::Plane(wall), QueryOptions::default()), Some(2.0));
/// # Ok::<(), spheresweep::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    point: Vec3,
    normal: Vec3,
}

/// A static infinite cylinder: the axis through `point` along the unit `axis`, and a radius.
/// Spheres collide with it from outside.
///
/// ```
/// use spheresweep::{Cylinder, QueryOptions, Shape, Sphere, time_of_impact};
/// let pillar = Cylinder::new([0.0; 3], [0.0, 0.0, 1.0], 1.0)?; // the z axis, radius 1
/// let ball = Sphere::new([5.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 1.0, 1.0)?;
/// assert_eq!(time_of_impact(&ball, &Shape::Cylinder(pillar), QueryOptions::default()), Some(3.0));
/// # Ok::<(), spheresweep::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cylinder {
    point: Vec3,
    axis: Vec3,
    radius: f32,
}

/// A static spherical vessel; the spheres it holds move inside it and touch its wall from
/// within (contact distance `D = R_container − R_sphere`).
///
/// ```
/// use spheresweep::{Container, QueryOptions, Shape, Sphere, time_of_impact};
/// let vessel = Container::new([0.0; 3], 10.0)?;
/// let ball = Sphere::new([0.0; 3], [0.0, 3.0, 0.0], 1.0, 1.0)?; // wall reached at y = 9
/// assert_eq!(time_of_impact(&ball, &Shape::Container(vessel), QueryOptions::default()), Some(3.0));
/// # Ok::<(), spheresweep::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Container {
    centre: Vec3,
    radius: f32,
}

fn finite_vec(kind: ShapeKind, field: &'static str, v: [f32; 3]) -> Result<Vec3, ShapeError> {
    let v = Vec3::from_array(v);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ShapeError::new(kind, field, Problem::NotFinite))
    }
}

fn radius(kind: ShapeKind, r: f32) -> Result<f32, ShapeError> {
    if !r.is_finite() {
        Err(ShapeError::new(kind, "radius", Problem::NotFinite))
    } else if r < 0.0 {
        Err(ShapeError::new(kind, "radius", Problem::Negative))
    } else {
        Ok(r)
    }
}

/// Normalises in f64 (no overflow or underflow for any finite f32 input), rounds once to f32.
fn unit(kind: ShapeKind, field: &'static str, d: DVec3) -> Result<Vec3, ShapeError> {
    let len = d.length();
    if len == 0.0 {
        return Err(ShapeError::new(kind, field, Problem::ZeroLength));
    }
    Ok((d / len).as_vec3())
}

impl Sphere {
    /// A sphere with the given centre at `t = 0`, constant velocity, radius (`0` is a point
    /// sphere) and mass.
    ///
    /// # Errors
    /// A [`ShapeError`] naming the field if any value is NaN or infinite, the radius is
    /// negative or the mass is not above zero.
    ///
    /// ```
    /// use spheresweep::Sphere;
    /// assert!(Sphere::new([0.0; 3], [0.0; 3], 0.0, 1.0).is_ok()); // a point sphere
    /// let err = Sphere::new([0.0, f32::NAN, 0.0], [0.0; 3], 1.0, 1.0).unwrap_err();
    /// assert_eq!(err.to_string(), "sphere centre is NaN or infinite");
    /// ```
    pub fn new(
        centre: [f32; 3],
        velocity: [f32; 3],
        radius: f32,
        mass: f32,
    ) -> Result<Self, ShapeError> {
        const K: ShapeKind = ShapeKind::Sphere;
        let centre = finite_vec(K, "centre", centre)?;
        let velocity = finite_vec(K, "velocity", velocity)?;
        let radius = self::radius(K, radius)?;
        if !mass.is_finite() {
            return Err(ShapeError::new(K, "mass", Problem::NotFinite));
        }
        if mass <= 0.0 {
            return Err(ShapeError::new(K, "mass", Problem::NotPositive));
        }
        Ok(Self {
            centre,
            velocity,
            radius,
            mass,
        })
    }

    /// A sphere from values already validated at the way in (the store's columns): no check.
    #[inline]
    pub(crate) const fn from_validated(
        centre: Vec3,
        velocity: Vec3,
        radius: f32,
        mass: f32,
    ) -> Self {
        Self {
            centre,
            velocity,
            radius,
            mass,
        }
    }

    /// Centre at `t = 0`.
    ///
    /// ```
    /// use spheresweep::Sphere;
    /// let s = Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 1.0)?;
    /// assert_eq!(s.centre().to_array(), [1.0, 2.0, 3.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn centre(&self) -> Vec3 {
        self.centre
    }
    /// Constant velocity.
    ///
    /// ```
    /// use spheresweep::Sphere;
    /// let s = Sphere::new([0.0; 3], [4.0, 0.0, -1.0], 0.5, 1.0)?;
    /// assert_eq!(s.velocity().to_array(), [4.0, 0.0, -1.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn velocity(&self) -> Vec3 {
        self.velocity
    }
    /// Radius (zero for a point sphere).
    ///
    /// ```
    /// use spheresweep::Sphere;
    /// assert_eq!(Sphere::new([0.0; 3], [0.0; 3], 0.25, 1.0)?.radius(), 0.25);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn radius(&self) -> f32 {
        self.radius
    }
    /// Mass (finite, above zero).
    ///
    /// ```
    /// use spheresweep::Sphere;
    /// assert_eq!(Sphere::new([0.0; 3], [0.0; 3], 0.25, 3.0)?.mass(), 3.0);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn mass(&self) -> f32 {
        self.mass
    }
    /// Centre at time `t`, `centre + velocity · t`, in f32.
    ///
    /// ```
    /// use spheresweep::Sphere;
    /// let s = Sphere::new([1.0, 0.0, 0.0], [0.0, 2.0, 0.0], 0.5, 1.0)?;
    /// assert_eq!(s.centre_at(1.5).to_array(), [1.0, 3.0, 0.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn centre_at(&self, t: f32) -> Vec3 {
        self.centre + self.velocity * t
    }
}

impl Plane {
    /// The plane through `point` with normal `normal` (any non-zero length; normalised here).
    ///
    /// # Errors
    /// A [`ShapeError`] if a value is NaN or infinite or the normal is zero.
    ///
    /// ```
    /// use spheresweep::Plane;
    /// let floor = Plane::new([0.0; 3], [0.0, 0.0, 5.0])?;
    /// assert_eq!(floor.normal().to_array(), [0.0, 0.0, 1.0]); // normalised
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn new(point: [f32; 3], normal: [f32; 3]) -> Result<Self, ShapeError> {
        const K: ShapeKind = ShapeKind::Plane;
        let point = finite_vec(K, "point", point)?;
        let normal = unit(K, "normal", finite_vec(K, "normal", normal)?.as_dvec3())?;
        Ok(Self { point, normal })
    }
    /// A point on the plane (`r_P0`).
    ///
    /// ```
    /// use spheresweep::Plane;
    /// assert_eq!(Plane::new([0.0, 0.0, 2.0], [0.0, 0.0, 1.0])?.point().z, 2.0);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn point(&self) -> Vec3 {
        self.point
    }
    /// The unit normal (`n̂_P`).
    ///
    /// ```
    /// use spheresweep::Plane;
    /// let n = Plane::new([0.0; 3], [3.0, 4.0, 0.0])?.normal();
    /// assert_eq!(n.to_array(), [0.6, 0.8, 0.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn normal(&self) -> Vec3 {
        self.normal
    }
}

impl Cylinder {
    /// The infinite cylinder whose axis passes through `p1` and `p2` (`r_C1`, `r_C2`).
    ///
    /// # Errors
    /// A [`ShapeError`] if a value is NaN or infinite, the radius is negative, or
    /// `p1 == p2` (field `"axis"`).
    ///
    /// ```
    /// use spheresweep::{Cylinder, Problem};
    /// let pillar = Cylinder::new([2.0, 0.0, 0.0], [2.0, 0.0, 7.0], 0.5)?;
    /// assert_eq!(pillar.axis().to_array(), [0.0, 0.0, 1.0]);
    /// let err = Cylinder::new([1.0; 3], [1.0; 3], 0.5).unwrap_err();
    /// assert_eq!((err.field, err.problem), ("axis", Problem::ZeroLength));
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn new(p1: [f32; 3], p2: [f32; 3], radius: f32) -> Result<Self, ShapeError> {
        const K: ShapeKind = ShapeKind::Cylinder;
        let p1 = finite_vec(K, "p1", p1)?;
        let p2 = finite_vec(K, "p2", p2)?;
        let radius = self::radius(K, radius)?;
        let axis = unit(K, "axis", p2.as_dvec3() - p1.as_dvec3())?;
        Ok(Self {
            point: p1,
            axis,
            radius,
        })
    }
    /// The infinite cylinder whose axis passes through `point` along `direction` (any non-zero
    /// length; normalised here in f64, then rounded once to f32).
    ///
    /// Prefer this form far from the origin: `Cylinder::new(p, p + s, r)` rounds `p + s` to f32
    /// first, and near `|p| = 10⁵` that alone tilts a unit axis by up to `|p|·2⁻²⁴ ≈ 6·10⁻³`.
    ///
    /// # Errors
    /// A [`ShapeError`] if a value is NaN or infinite, the radius is negative, or `direction`
    /// is zero (field `"axis"`).
    ///
    /// ```
    /// use spheresweep::Cylinder;
    /// let pillar = Cylinder::from_axis([1e5, 0.0, 0.0], [0.0, 0.0, 2.0], 1.0)?;
    /// assert_eq!(pillar.axis().to_array(), [0.0, 0.0, 1.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn from_axis(
        point: [f32; 3],
        direction: [f32; 3],
        radius: f32,
    ) -> Result<Self, ShapeError> {
        const K: ShapeKind = ShapeKind::Cylinder;
        let point = finite_vec(K, "point", point)?;
        let direction = finite_vec(K, "axis", direction)?;
        let radius = self::radius(K, radius)?;
        let axis = unit(K, "axis", direction.as_dvec3())?;
        Ok(Self {
            point,
            axis,
            radius,
        })
    }
    /// A point on the axis (`r_C1`).
    ///
    /// ```
    /// use spheresweep::Cylinder;
    /// let pillar = Cylinder::new([2.0, 0.0, 0.0], [2.0, 0.0, 7.0], 0.5)?;
    /// assert_eq!(pillar.point().to_array(), [2.0, 0.0, 0.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn point(&self) -> Vec3 {
        self.point
    }
    /// The unit axis direction (`ŝ`).
    ///
    /// ```
    /// use spheresweep::Cylinder;
    /// let pillar = Cylinder::new([0.0; 3], [0.0, -3.0, 0.0], 0.5)?;
    /// assert_eq!(pillar.axis().to_array(), [0.0, -1.0, 0.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn axis(&self) -> Vec3 {
        self.axis
    }
    /// Radius (`R_C`).
    ///
    /// ```
    /// use spheresweep::Cylinder;
    /// assert_eq!(Cylinder::new([0.0; 3], [0.0, 0.0, 1.0], 0.5)?.radius(), 0.5);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn radius(&self) -> f32 {
        self.radius
    }
}

impl Container {
    /// A static spherical vessel with the given centre and inner radius.
    ///
    /// # Errors
    /// A [`ShapeError`] if a value is NaN or infinite or the radius is negative.
    ///
    /// ```
    /// use spheresweep::Container;
    /// assert!(Container::new([0.0; 3], 10.0).is_ok());
    /// let err = Container::new([0.0; 3], -1.0).unwrap_err();
    /// assert_eq!(err.to_string(), "container radius is negative");
    /// ```
    pub fn new(centre: [f32; 3], radius: f32) -> Result<Self, ShapeError> {
        const K: ShapeKind = ShapeKind::Container;
        Ok(Self {
            centre: finite_vec(K, "centre", centre)?,
            radius: self::radius(K, radius)?,
        })
    }
    /// Centre of the vessel.
    ///
    /// ```
    /// use spheresweep::Container;
    /// assert_eq!(Container::new([1.0, 2.0, 3.0], 10.0)?.centre().to_array(), [1.0, 2.0, 3.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn centre(&self) -> Vec3 {
        self.centre
    }
    /// Inner radius of the vessel.
    ///
    /// ```
    /// use spheresweep::Container;
    /// assert_eq!(Container::new([0.0; 3], 10.0)?.radius(), 10.0);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn radius(&self) -> f32 {
        self.radius
    }
}
