//! The static shapes of a scene, by kind, in one registry.
//!
//! [`Statics<P>`] holds each static kind's shapes as an array of its own (structure of arrays,
//! so a kind's SIMD kernel reads them in a row), each shape with a payload `P`: `()` for a
//! query [`Scene`](crate::scene::Scene), a material for a simulation
//! [`World`](crate::sim::World). The kinds are listed once, in `static_kinds!` below, in the
//! order ties are broken (planes, then cylinders, then containers); everything that goes over
//! the kinds — the struct, [`Static`], [`Statics::visit`], [`Statics::get`] — is generated from
//! that one list, as box2d fills its `s_registers[type][type]` table in one place. A new kind
//! touches its own files (shape, kernel, reference, contact geometry), this list and the scene
//! file's schema.
//!
//! ```
//! use spheresweep::{Container, Plane, ShapeKind, statics::Statics};
//! let mut statics = Statics::new();
//! let floor = statics.push(Plane::new([0.0; 3], [0.0, 0.0, 1.0])?, "steel");
//! let vessel = statics.push(Container::new([0.0; 3], 10.0)?, "glass");
//! assert_eq!((floor.kind, vessel.kind), (ShapeKind::Plane, ShapeKind::Container));
//! assert_eq!(statics.get(vessel).map(|(_, m)| *m), Some("glass"));
//! assert_eq!(statics.of::<Plane>().len(), 1);
//! # Ok::<(), spheresweep::ShapeError>(())
//! ```

use std::fmt;

use glam::DVec3;

use crate::contact::Body;
use crate::kernels::{SettleLanes, StaticKernel};
use crate::shape::{Container, Cylinder, Plane, Shape, ShapeKind};

/// The registry: every static kind once, as `Type field`, in tie-break order (the order of
/// [`ShapeKind`]). Each entry's type implements the crate's `StaticKernel` in its kernel file.
macro_rules! static_kinds {
    ($then:ident) => {
        $then! {
            Plane planes,
            Cylinder cylinders,
            Container containers,
        }
    };
}

/// A static shape kind that spheres are tested against: [`Plane`], [`Cylinder`],
/// [`Container`]. Sealed: the kernels behind it are the crate's own.
///
/// ```
/// use spheresweep::{Cylinder, Plane, ShapeKind, batch::StaticShape};
/// assert_eq!(<Plane as StaticShape>::KIND, ShapeKind::Plane);
/// assert_eq!(Cylinder::KIND, ShapeKind::Cylinder);
/// ```
pub trait StaticShape:
    StaticKernel + Copy + Into<Shape> + Into<Static> + Sync + Send + fmt::Debug + PartialEq
{
    /// Which kind of body it is.
    const KIND: ShapeKind;
    /// This kind's shapes in `statics`.
    #[doc(hidden)]
    fn of<P>(statics: &Statics<P>) -> &OfKind<Self, P>;
    /// This kind's shapes in `statics`, to change.
    #[doc(hidden)]
    fn of_mut<P>(statics: &mut Statics<P>) -> &mut OfKind<Self, P>;
}

/// The shapes of one kind with their payloads, in index order (a [`Body`]'s `index`).
pub struct OfKind<K: StaticShape, P> {
    shapes: Vec<K>,
    payloads: Vec<P>,
    /// Each shape prepared once in f64 lanes, for the simulation's settle.
    settle: Vec<SettleLanes<K>>,
}

impl<K: StaticShape, P> OfKind<K, P> {
    /// The shapes.
    pub fn shapes(&self) -> &[K] {
        &self.shapes
    }

    /// The payloads, one per shape.
    pub fn payloads(&self) -> &[P] {
        &self.payloads
    }

    /// How many shapes of this kind.
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// Each shape with its body and payload, in index order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (Body, &K, &P)> + '_ {
        self.shapes
            .iter()
            .zip(&self.payloads)
            .enumerate()
            .map(|(i, (k, p))| (Body::new(K::KIND, i as u32), k, p))
    }

    /// The shapes prepared in f64 lanes, one per shape.
    pub(crate) fn settle(&self) -> &[SettleLanes<K>] {
        &self.settle
    }

    fn push(&mut self, shape: K, payload: P) -> Body {
        let index = u32::try_from(self.shapes.len()).expect("at most 2^32 shapes of one kind");
        self.settle.push(shape.prepare());
        self.shapes.push(shape);
        self.payloads.push(payload);
        Body::new(K::KIND, index)
    }
}

impl<K: StaticShape, P> Default for OfKind<K, P> {
    fn default() -> Self {
        Self {
            shapes: Vec::new(),
            payloads: Vec::new(),
            settle: Vec::new(),
        }
    }
}

impl<K: StaticShape, P: Clone> Clone for OfKind<K, P> {
    fn clone(&self) -> Self {
        Self {
            shapes: self.shapes.clone(),
            payloads: self.payloads.clone(),
            settle: self.settle.clone(),
        }
    }
}

impl<K: StaticShape, P: PartialEq> PartialEq for OfKind<K, P> {
    fn eq(&self, other: &Self) -> bool {
        self.shapes == other.shapes && self.payloads == other.payloads
    }
}

impl<K: StaticShape, P: fmt::Debug> fmt::Debug for OfKind<K, P> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list()
            .entries(self.shapes.iter().zip(&self.payloads))
            .finish()
    }
}

/// Work done on each kind's shapes in turn ([`Statics::visit`]): one generic method, called
/// once per kind in tie-break order, monomorphised per kind (bepuphysics2's per-kind batches).
///
/// ```
/// use spheresweep::{Plane, batch::StaticShape, statics::{OfKind, Statics, Visitor}};
/// struct Count(usize);
/// impl<P> Visitor<P> for Count {
///     fn visit<K: StaticShape>(&mut self, shapes: &OfKind<K, P>) {
///         self.0 += shapes.len();
///     }
/// }
/// let statics = Statics::new().with(Plane::new([0.0; 3], [0.0, 0.0, 1.0])?, ());
/// let mut count = Count(0);
/// statics.visit(&mut count);
/// assert_eq!(count.0, 1);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub trait Visitor<P> {
    /// Called with one kind's shapes.
    fn visit<K: StaticShape>(&mut self, shapes: &OfKind<K, P>);
}

/// Work done on one static shape of a kind known only at run time ([`Static::apply`]): the
/// generic method is monomorphised per kind, so the work runs the kind's own kernel.
///
/// ```
/// use spheresweep::{Plane, QueryOptions, Sphere, SphereStore, Static, batch, statics::ShapeFn};
/// struct Times<'a>(&'a SphereStore, &'a mut [f32]);
/// impl ShapeFn for Times<'_> {
///     type Output = Result<(), spheresweep::BatchError>;
///     fn call<K: spheresweep::StaticShape>(self, shape: &K) -> Self::Output {
///         batch::static_times(self.0, shape, QueryOptions::default(), self.1)
///     }
/// }
/// let floor = Static::from(Plane::new([0.0; 3], [0.0, 0.0, 1.0])?);
/// let balls = SphereStore::from_spheres(&[Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0)?]);
/// let mut out = [0.0];
/// floor.apply(Times(&balls, &mut out))?;
/// assert_eq!(out, [2.0]);
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub trait ShapeFn {
    /// What the work returns.
    type Output;
    /// Does the work on `shape`.
    fn call<K: StaticShape>(self, shape: &K) -> Self::Output;
}

macro_rules! define_statics {
    ($($kind:ident $field:ident,)*) => {
        /// The static shapes of a scene by kind, each with a payload `P`; see the
        /// [module](self) for the design.
        pub struct Statics<P = ()> {
            $($field: OfKind<$kind, P>,)*
        }

        /// One static shape by value, of any static kind (never a sphere).
        #[derive(Debug, Clone, Copy, PartialEq)]
        #[non_exhaustive]
        pub enum Static {
            $(
                #[doc = concat!("A [`", stringify!($kind), "`].")]
                $kind($kind),
            )*
        }

        $(
            impl StaticShape for $kind {
                const KIND: ShapeKind = ShapeKind::$kind;
                #[inline]
                fn of<P>(statics: &Statics<P>) -> &OfKind<Self, P> {
                    &statics.$field
                }
                #[inline]
                fn of_mut<P>(statics: &mut Statics<P>) -> &mut OfKind<Self, P> {
                    &mut statics.$field
                }
            }

            impl From<$kind> for Static {
                fn from(shape: $kind) -> Self {
                    Static::$kind(shape)
                }
            }
        )*

        impl Static {
            /// Which kind of body it is.
            pub fn kind(&self) -> ShapeKind {
                match self {
                    $(Static::$kind(_) => ShapeKind::$kind,)*
                }
            }

            /// Runs `f` on the shape, monomorphised for its kind.
            pub fn apply<F: ShapeFn>(&self, f: F) -> F::Output {
                match self {
                    $(Static::$kind(s) => f.call(s),)*
                }
            }

            /// When a sphere (centre `r`, velocity `v`, `radius`) falling under the uniform
            /// acceleration `g` first touches the shape, in f64: the earliest admissible root
            /// of the kind's polynomial (quadratic for a plane, quartic for a cylinder or a
            /// container), isolated so that it is never missed
            /// (docs/derivations/gravity.md); `None` if it never does.
            ///
            /// ```
            /// use glam::DVec3;
            /// use spheresweep::{Plane, Static};
            /// let floor = Static::Plane(Plane::new([0.0; 3], [0.0, 0.0, 1.0])?);
            /// // Dropped from rest with its bottom 4.905 above the floor: it lands at t = 1.
            /// let g = DVec3::new(0.0, 0.0, -9.81);
            /// let t = floor.time_of_impact_falling(DVec3::new(0.0, 0.0, 5.405), DVec3::ZERO, 0.5, g);
            /// assert!((t.unwrap() - 1.0).abs() < 1e-12);
            /// # Ok::<(), spheresweep::ShapeError>(())
            /// ```
            pub fn time_of_impact_falling(
                &self,
                r: DVec3,
                v: DVec3,
                radius: f64,
                g: DVec3,
            ) -> Option<f64> {
                let p = match self {
                    $(Static::$kind(s) => s.falling_polynomial(r, v, g * 0.5, radius),)*
                };
                let t = crate::kernels::falling::earliest_rise(&p);
                t.is_finite().then_some(t)
            }

            /// The unit normal from the shape towards a sphere centred at `r` and the signed
            /// gap between the sphere and the shape (negative when it is through).
            pub fn normal_gap(&self, r: DVec3, radius: f64) -> (DVec3, f64) {
                match self {
                    $(Static::$kind(s) => s.normal_gap(r, radius),)*
                }
            }

            /// Which side of the shape `r` is on, for a shape a sphere may be on either side
            /// of (a plane: `true` on the side its normal points to); `true` for the others.
            pub fn side(&self, r: DVec3) -> bool {
                match self {
                    $(Static::$kind(s) => s.side(r),)*
                }
            }

            /// The gap of a sphere at `r` that must stay on `side` ([`Static::side`]): across
            /// a plane, the whole way back.
            pub fn gap_on_side(&self, r: DVec3, radius: f64, side: bool) -> f64 {
                match self {
                    $(Static::$kind(s) => s.gap_on_side(r, radius, side),)*
                }
            }

            /// For a concave wall that keeps spheres inside (a container): its centre and
            /// radius.
            pub fn interior(&self) -> Option<(DVec3, f64)> {
                match self {
                    $(Static::$kind(s) => s.interior(),)*
                }
            }

            /// The least gap of a sphere moving from `r` at `v` for `horizon`, closed form.
            #[cfg(test)]
            pub(crate) fn least_gap_on_path(&self, r: DVec3, v: DVec3, horizon: f64, radius: f64) -> f64 {
                match self {
                    $(Static::$kind(s) => s.least_gap_on_path(r, v, horizon, radius),)*
                }
            }
        }

        impl From<Static> for Shape {
            fn from(shape: Static) -> Self {
                match shape {
                    $(Static::$kind(s) => Shape::$kind(s),)*
                }
            }
        }

        impl TryFrom<Shape> for Static {
            type Error = ShapeKind;
            /// A static shape, or the kind of a body that is not one (a sphere).
            fn try_from(shape: Shape) -> Result<Self, ShapeKind> {
                match shape {
                    $(Shape::$kind(s) => Ok(Static::$kind(s)),)*
                    other => Err(other.kind()),
                }
            }
        }

        impl<P> Statics<P> {
            /// Calls `visitor` with each kind's shapes, in tie-break order.
            pub fn visit<V: Visitor<P>>(&self, visitor: &mut V) {
                $(visitor.visit(&self.$field);)*
            }

            /// The static body `body`, by value, and its payload (`None` for a sphere or an
            /// index past the end).
            pub fn get(&self, body: Body) -> Option<(Static, &P)> {
                let i = body.index as usize;
                match body.kind {
                    $(ShapeKind::$kind => self.$field.shapes.get(i).map(|s| (Static::$kind(*s), &self.$field.payloads[i])),)*
                    _ => None,
                }
            }

            /// The payload of the static body `body`, to change.
            pub fn payload_mut(&mut self, body: Body) -> Option<&mut P> {
                match body.kind {
                    $(ShapeKind::$kind => self.$field.payloads.get_mut(body.index as usize),)*
                    _ => None,
                }
            }

            /// The same shapes with payloads `f(body, payload)`.
            pub fn map<Q>(&self, mut f: impl FnMut(Body, &P) -> Q) -> Statics<Q> {
                Statics {
                    $($field: OfKind {
                        shapes: self.$field.shapes.clone(),
                        payloads: self.$field.iter().map(|(b, _, p)| f(b, p)).collect(),
                        settle: self.$field.settle.clone(),
                    },)*
                }
            }

            /// Every shape with its body and payload, in tie-break order (kinds in the order of
            /// [`ShapeKind`], each by index).
            pub fn iter(&self) -> impl Iterator<Item = (Body, Static, &P)> + '_ {
                std::iter::empty()
                    $(.chain(self.$field.iter().map(|(b, s, p)| (b, Static::$kind(*s), p))))*
            }

            /// Adds a shape of any static kind with `payload`; its [`Body`].
            pub fn push_static(&mut self, shape: Static, payload: P) -> Body {
                match shape {
                    $(Static::$kind(k) => self.push(k, payload),)*
                }
            }

            /// Each static kind with how many shapes of it, in tie-break order (a kind with
            /// none included).
            pub fn counts(&self) -> Vec<(ShapeKind, usize)> {
                vec![$((ShapeKind::$kind, self.$field.len()),)*]
            }

            /// How many shapes of every kind.
            pub fn len(&self) -> usize {
                0 $(+ self.$field.len())*
            }
        }

        impl<P> Default for Statics<P> {
            fn default() -> Self {
                Self { $($field: OfKind::default(),)* }
            }
        }

        impl<P: Clone> Clone for Statics<P> {
            fn clone(&self) -> Self {
                Self { $($field: self.$field.clone(),)* }
            }
        }

        impl<P: PartialEq> PartialEq for Statics<P> {
            fn eq(&self, other: &Self) -> bool {
                true $(&& self.$field == other.$field)*
            }
        }

        impl<P: fmt::Debug> fmt::Debug for Statics<P> {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.debug_struct("Statics")
                    $(.field(stringify!($field), &self.$field))*
                    .finish()
            }
        }
    };
}

static_kinds!(define_statics);

impl<P> Statics<P> {
    /// No shapes.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `shape` with `payload`; its [`Body`] (the next index of its kind).
    ///
    /// # Panics
    /// Above 2³² shapes of one kind (a [`Body`] index is a `u32`).
    pub fn push<K: StaticShape>(&mut self, shape: K, payload: P) -> Body {
        K::of_mut(self).push(shape, payload)
    }

    /// `self` with `shape` added (a builder for scenes written by hand).
    pub fn with<K: StaticShape>(mut self, shape: K, payload: P) -> Self {
        self.push(shape, payload);
        self
    }

    /// The shapes of kind `K`.
    pub fn of<K: StaticShape>(&self) -> &OfKind<K, P> {
        K::of(self)
    }

    /// Whether there are no static shapes at all.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl FromIterator<Static> for Statics<()> {
    /// Shapes of any kinds, each with no payload, in the order given within each kind.
    fn from_iter<I: IntoIterator<Item = Static>>(shapes: I) -> Self {
        let mut statics = Statics::new();
        for s in shapes {
            statics.push_static(s, ());
        }
        statics
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Statics<u16> {
        let mut s = Statics::new();
        s.push(Container::new([0.0; 3], 9.0).unwrap(), 3);
        s.push(Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap(), 1);
        s.push(
            Cylinder::new([1.0, 0.0, 0.0], [1.0, 0.0, 1.0], 0.5).unwrap(),
            2,
        );
        s.push(Plane::new([0.0, 0.0, 5.0], [0.0, 0.0, -1.0]).unwrap(), 4);
        s
    }

    /// The registry's order is the tie-break order of `ShapeKind`, whatever order shapes were
    /// added in, and `get` finds each shape under the body `push` gave it.
    #[test]
    fn iteration_follows_the_kind_order_and_get_finds_every_body() {
        let s = sample();
        let bodies: Vec<Body> = s.iter().map(|(b, _, _)| b).collect();
        let mut sorted = bodies.clone();
        sorted.sort();
        assert_eq!(bodies, sorted);
        assert_eq!(bodies.len(), s.len());
        for (b, shape, p) in s.iter() {
            assert_eq!(s.get(b), Some((shape, p)));
            assert_eq!(shape.kind(), b.kind);
        }
        assert_eq!(s.get(Body::new(ShapeKind::Sphere, 0)), None);
        assert_eq!(s.get(Body::new(ShapeKind::Plane, 2)), None);
        let payloads: Vec<u16> = s.iter().map(|(_, _, p)| *p).collect();
        assert_eq!(payloads, [1, 4, 2, 3]);
    }

    /// A visitor meets every kind once, in order, and `map` keeps the shapes.
    #[test]
    fn visit_meets_each_kind_in_order_and_map_keeps_shapes() {
        struct Kinds(Vec<(ShapeKind, usize)>);
        impl<P> Visitor<P> for Kinds {
            fn visit<K: StaticShape>(&mut self, shapes: &OfKind<K, P>) {
                self.0.push((K::KIND, shapes.len()));
            }
        }
        let s = sample();
        let mut k = Kinds(Vec::new());
        s.visit(&mut k);
        let order: Vec<ShapeKind> = k.0.iter().map(|x| x.0).collect();
        assert_eq!(&order[..], &ShapeKind::ALL[1..]);
        assert_eq!(k.0.iter().map(|x| x.1).sum::<usize>(), 4);
        let plain = s.map(|_, _| ());
        assert_eq!(plain.of::<Plane>().shapes(), s.of::<Plane>().shapes());
        let back: Statics<()> = s.iter().map(|(_, shape, _)| shape).collect();
        assert_eq!(back, plain);
    }

    /// Each kind's gap: a plane two-sided, a cylinder from its axis, a container inwards.
    #[test]
    fn gaps_point_from_the_shape_to_the_sphere() {
        let s = sample();
        let r = DVec3::new(3.0, 0.0, 2.0);
        let gap = |b| s.get(b).unwrap().0.normal_gap(r, 0.5);
        let (n, g) = gap(Body::new(ShapeKind::Plane, 0));
        assert_eq!((n, g), (DVec3::Z, 1.5));
        let (n, g) = gap(Body::new(ShapeKind::Plane, 1));
        assert_eq!((n, g), (DVec3::NEG_Z, 2.5));
        let (n, g) = gap(Body::new(ShapeKind::Cylinder, 0));
        assert_eq!((n, g), (DVec3::X, 1.0));
        let (n, g) = gap(Body::new(ShapeKind::Container, 0));
        assert!((g - (9.0 - 0.5 - 13f64.sqrt())).abs() < 1e-12);
        assert!((n + r / 13f64.sqrt()).length() < 1e-12);
        let floor = s.get(Body::new(ShapeKind::Plane, 0)).unwrap().0;
        assert!(!floor.side(DVec3::new(0.0, 0.0, -1.0)));
        assert_eq!(
            floor.gap_on_side(DVec3::new(0.0, 0.0, -1.0), 0.5, true),
            -1.5
        );
        assert_eq!(
            s.get(Body::new(ShapeKind::Container, 0))
                .unwrap()
                .0
                .interior(),
            Some((DVec3::ZERO, 9.0))
        );
    }
}
