//! The exact oracle: the seed's quadratic in exact rational arithmetic on the f32 inputs
//! (every finite f32 is a dyadic rational), so every decision — hit or miss, root ahead or
//! behind, inside the window or not — is exact.
//!
//! The plane's normal and the cylinder's axis are the stored f32 vectors, not exactly unit:
//! distances are `(x·n)/‖n‖` and `‖x − (x·ŝ)ŝ/(ŝ·ŝ)‖`, which keep every coefficient rational.
//! Only the time itself is irrational; it is evaluated in f64 from the exact coefficients,
//! each correctly rounded, with the cancellation-free form (`C / (−b + √q)` and its interior
//! twin): relative error below `5·2⁻⁵³`, far below an f32 ulp (docs/derivations/oracle.md).

use dashu::rational::RBig;

use super::pair::Pair;
use spheresweep::Side;
use spheresweep::{Container, Cylinder, Plane, Shape, ShapeKind, Sphere};

/// The exact quadratic `dist² − D² = A t² + 2b t + C` of one pair, and `q = b² − AC`.
///
/// ```
/// # use spheresweep::{Sphere, reference::Pair};
/// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
/// let pair = Pair {
///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
/// };
/// use spheresweep_study::Exact;
/// let exact = Exact::of(&pair);
/// assert_eq!(exact.time(f64::INFINITY), Some(4.0));
/// assert_eq!(exact.contact_distance(), 2.0);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Exact {
    a: RBig,
    b: RBig,
    c: RBig,
    q: RBig,
    d: RBig,
    side: Side,
}

fn exact(x: f32) -> RBig {
    RBig::try_from(x).expect("validated shapes hold finite values")
}

fn exact64(x: f64) -> RBig {
    RBig::try_from(x).expect("a finite time")
}

type V = [RBig; 3];

fn sub(a: &V, b: &V) -> V {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}
fn dot(a: &V, b: &V) -> RBig {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}
fn to_f64(x: &RBig) -> f64 {
    x.to_f64().value()
}

/// The f32 numbers a pair is made of, flat, in a fixed order per kind: the sphere's centre,
/// velocity and radius (indices 0 – 6), then the other body's — a sphere's centre, velocity
/// and radius; a plane's point and normal; a cylinder's axis point, axis and radius; a
/// container's centre and radius. The oracle reads a pair only through them, so that one
/// input can be moved by an ulp without going through a constructor (which would normalise a
/// normal or an axis again): [`super::condition`](mod@super::condition).
///
/// ```
/// # use spheresweep::{Sphere, reference::Pair};
/// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
/// let pair = Pair {
///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
/// };
/// use spheresweep::ShapeKind;
/// use spheresweep_study::Inputs;
/// let inputs = Inputs::of(&pair);
/// assert_eq!((inputs.kind(), inputs.len()), (ShapeKind::Sphere, 14));
/// assert_eq!(inputs.values()[7], 10.0); // B's centre x, after A's 7 inputs
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inputs {
    kind: ShapeKind,
    values: [f32; 14],
}

impl Inputs {
    /// The inputs of `pair`.
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// use spheresweep_study::Inputs;
    /// assert_eq!(&Inputs::of(&pair).values()[..7], &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn of(pair: &Pair) -> Self {
        let s = &pair.sphere;
        let mut values = [0.0f32; 14];
        values[..3].copy_from_slice(&s.centre().to_array());
        values[3..6].copy_from_slice(&s.velocity().to_array());
        values[6] = s.radius();
        let (a, b, r) = match &pair.other {
            Shape::Sphere(o) => (o.centre(), o.velocity(), o.radius()),
            Shape::Plane(p) => (p.point(), p.normal(), 0.0),
            Shape::Cylinder(c) => (c.point(), c.axis(), c.radius()),
            Shape::Container(k) => (k.centre(), glam::Vec3::ZERO, k.radius()),
            other => unimplemented!("no oracle for {} pairs yet", other.kind()),
        };
        values[7..10].copy_from_slice(&a.to_array());
        let kind = pair.other.kind();
        if kind == ShapeKind::Container {
            values[10] = r;
        } else {
            values[10..13].copy_from_slice(&b.to_array());
            values[13] = r;
        }
        Self { kind, values }
    }

    /// The kind of the other body.
    ///
    /// ```
    /// use spheresweep::{Plane, ShapeKind, Sphere, reference::Pair};
    /// use spheresweep_study::Inputs;
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0, 0.0, 3.0], [0.0; 3], 1.0, 1.0)?,
    ///     other: Plane::new([0.0; 3], [0.0, 0.0, 1.0])?.into(),
    /// };
    /// assert_eq!(Inputs::of(&pair).kind(), ShapeKind::Plane);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn kind(&self) -> ShapeKind {
        self.kind
    }

    /// How many inputs the pair has: 14 (sphere, cylinder), 13 (plane), 11 (container).
    ///
    /// ```
    /// use spheresweep::{Container, Sphere, reference::Pair};
    /// use spheresweep_study::Inputs;
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    ///     other: Container::new([0.0; 3], 5.0)?.into(),
    /// };
    /// // 7 for the sphere, then the vessel's centre and radius.
    /// assert_eq!(Inputs::of(&pair).len(), 11);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn len(&self) -> usize {
        match self.kind {
            ShapeKind::Sphere | ShapeKind::Cylinder => 14,
            ShapeKind::Plane => 13,
            ShapeKind::Container => 11,
            other => unimplemented!("no oracle for {other} pairs yet"),
        }
    }

    /// Never: every pair has inputs (for clippy's `len_without_is_empty`).
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// assert!(!spheresweep_study::Inputs::of(&pair).is_empty());
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The inputs in order.
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// let inputs = spheresweep_study::Inputs::of(&pair);
    /// assert_eq!(&inputs.values()[10..], &[-2.0, 0.0, 0.0, 1.0]); // B's velocity and radius
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn values(&self) -> &[f32] {
        &self.values[..self.len()]
    }

    /// Whether input `i` is a radius (which must stay at or above zero).
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// let inputs = spheresweep_study::Inputs::of(&pair);
    /// let radii: Vec<usize> = (0..inputs.len()).filter(|&i| inputs.is_radius(i)).collect();
    /// assert_eq!(radii, [6, 13]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn is_radius(&self, i: usize) -> bool {
        i == 6
            || (i == 13 && self.kind != ShapeKind::Plane)
            || (i == 10 && self.kind == ShapeKind::Container)
    }

    /// The same inputs with input `i` set to `x` (no validation: the caller keeps radii
    /// non-negative, values finite and normals and axes non-zero).
    ///
    /// # Panics
    /// If `i` is not below [`Self::len`].
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// use spheresweep_study::{Exact, Inputs};
    /// // B starts at x = 12: contact at (12 − 2)/2.
    /// let farther = Inputs::of(&pair).with(7, 12.0);
    /// assert_eq!(Exact::from_inputs(&farther).time(f64::INFINITY), Some(5.0));
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[must_use]
    pub fn with(mut self, i: usize, x: f32) -> Self {
        assert!(i < self.len(), "input {i} of {}", self.len());
        self.values[i] = x;
        self
    }

    /// The pair these inputs describe, through the validating constructors (which normalise
    /// a normal or an axis again); `None` if a constructor rejects a value (an infinity, a
    /// negative radius, a zero normal or axis).
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// let inputs = spheresweep_study::Inputs::of(&pair);
    /// assert_eq!(inputs.pair(), Some(pair));
    /// assert_eq!(inputs.with(6, -1.0).pair(), None); // a negative radius
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn pair(&self) -> Option<Pair> {
        let v = &self.values;
        let at = |i: usize| [v[i], v[i + 1], v[i + 2]];
        let sphere = Sphere::new(at(0), at(3), v[6], 1.0).ok()?;
        let other = match self.kind {
            ShapeKind::Sphere => Shape::Sphere(Sphere::new(at(7), at(10), v[13], 1.0).ok()?),
            ShapeKind::Plane => Shape::Plane(Plane::new(at(7), at(10)).ok()?),
            ShapeKind::Cylinder => Shape::Cylinder(Cylinder::from_axis(at(7), at(10), v[13]).ok()?),
            ShapeKind::Container => Shape::Container(Container::new(at(7), v[10]).ok()?),
            _ => return None,
        };
        Some(Pair { sphere, other })
    }

    fn vector(&self, i: usize) -> V {
        [
            exact(self.values[i]),
            exact(self.values[i + 1]),
            exact(self.values[i + 2]),
        ]
    }
}

impl Exact {
    /// The exact coefficients of `pair`.
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// assert_eq!(spheresweep_study::Exact::of(&pair).time(3.0), None); // the window ends first
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn of(pair: &Pair) -> Self {
        Self::from_inputs(&Inputs::of(pair))
    }

    /// The exact coefficients of the pair made of `inputs`.
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// use spheresweep_study::{Exact, Inputs};
    /// let exact = Exact::from_inputs(&Inputs::of(&pair));
    /// assert_eq!(exact.time(f64::INFINITY), Exact::of(&pair).time(f64::INFINITY));
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn from_inputs(inputs: &Inputs) -> Self {
        let (c, v, r) = (inputs.vector(0), inputs.vector(3), exact(inputs.values[6]));
        let (a, b, cc, d, side) = match inputs.kind {
            ShapeKind::Sphere => {
                let r0 = sub(&inputs.vector(7), &c);
                let v = sub(&inputs.vector(10), &v);
                let d = &r + exact(inputs.values[13]);
                (
                    dot(&v, &v),
                    dot(&r0, &v),
                    dot(&r0, &r0) - &d * &d,
                    d,
                    Side::Exterior,
                )
            }
            ShapeKind::Container => {
                let r0 = sub(&c, &inputs.vector(7));
                let d = exact(inputs.values[10]) - &r;
                (
                    dot(&v, &v),
                    dot(&r0, &v),
                    dot(&r0, &r0) - &d * &d,
                    d,
                    Side::Interior,
                )
            }
            ShapeKind::Plane => {
                let n = inputs.vector(10);
                let nn = dot(&n, &n);
                let r0 = dot(&sub(&c, &inputs.vector(7)), &n);
                let vn = dot(&v, &n);
                let a = &vn * &vn / &nn;
                let b = &r0 * &vn / &nn;
                let cc = &r0 * &r0 / &nn - &r * &r;
                (a, b, cc, r, Side::Exterior)
            }
            ShapeKind::Cylinder => {
                let s_ = inputs.vector(10);
                let ss = dot(&s_, &s_);
                let x = sub(&c, &inputs.vector(7));
                let (xs, vs) = (dot(&x, &s_), dot(&v, &s_));
                let d = &r + exact(inputs.values[13]);
                let a = dot(&v, &v) - &vs * &vs / &ss;
                let b = dot(&x, &v) - &xs * &vs / &ss;
                let cc = dot(&x, &x) - &xs * &xs / &ss - &d * &d;
                (a, b, cc, d, Side::Exterior)
            }
            other => unimplemented!("no oracle for {other} pairs yet"),
        };
        let q = &b * &b - &a * &cc;
        Self {
            a,
            b,
            c: cc,
            q,
            d,
            side,
        }
    }

    /// The true earliest admissible time in `[0, t_max]` (`t_max` may be `+∞`), by the policy
    /// of docs/derivations/policies.md, every decision exact.
    ///
    /// A sphere inside a container is at a contact at `t = 0` when it is at or beyond the
    /// wall (`C ≥ 0`) and moving outwards (`b > 0`) or tangentially (`b = 0`, `A > 0`): touching
    /// the wall and sliding along it, and an exact fit (`D = 0`) that moves at all, are contacts
    /// at 0 (the container policy of the compensated kernels).
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// use spheresweep_study::Exact;
    /// assert_eq!(Exact::of(&pair).time(10.0), Some(4.0));
    /// assert_eq!(Exact::of(&pair).time(4.0), Some(4.0)); // the window is closed
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn time(&self, t_max: f64) -> Option<f64> {
        let zero = RBig::ZERO;
        let Exact {
            a,
            b,
            c,
            q,
            d,
            side,
        } = self;
        if *side == Side::Interior && *d < zero {
            return Some(0.0); // a sphere larger than its vessel
        }
        if *a == zero {
            return None;
        }
        let finite_t = t_max.is_finite().then(|| exact64(t_max));
        match side {
            Side::Exterior => {
                if *b < zero && *c > zero && *q >= zero {
                    // t1 = (−b − √q)/A ≤ T ⟺ −b − AT ≤ √q.
                    if let Some(t) = &finite_t {
                        let lhs = -b - a * t;
                        if lhs > zero && &lhs * &lhs > *q {
                            return None;
                        }
                    }
                    let (cf, bf, qf) = (to_f64(c), to_f64(b), to_f64(q));
                    // The exact check passed: clamp the f64 rounding to the window.
                    Some((cf / (qf.sqrt() - bf)).min(t_max))
                } else if *c <= zero && *b < zero {
                    Some(0.0)
                } else {
                    None
                }
            }
            Side::Interior => {
                let ahead = *q >= zero && (*b < zero || *q > b * b);
                if ahead {
                    // t2 = (−b + √q)/A ≤ T ⟺ √q ≤ AT + b.
                    if let Some(t) = &finite_t {
                        let rhs = a * t + b;
                        if rhs < zero || *q > &rhs * &rhs {
                            return None;
                        }
                    }
                    let (af, bf, cf, qf) = (to_f64(a), to_f64(b), to_f64(c), to_f64(q));
                    let t = if bf <= 0.0 {
                        (qf.sqrt() - bf) / af
                    } else {
                        cf / (-bf - qf.sqrt())
                    };
                    Some(t.min(t_max))
                } else if *c >= zero {
                    // At or beyond the wall (`A > 0` here) with no way back inside: moving
                    // outwards, or tangentially (`b = 0`: touching and sliding along the wall,
                    // or an exact fit `D = 0` that moves at all), or inwards too slowly ever to
                    // get back (`b < 0` with `q < 0`).
                    Some(0.0)
                } else {
                    None
                }
            }
        }
    }

    /// `dist(t) − D` at the time `t` (an f32 or f64 value, taken exactly): how far from
    /// touching the bodies are at a reported time (positive: apart for an exterior pair,
    /// negative: inside the wall for a container).
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// let exact = spheresweep_study::Exact::of(&pair);
    /// assert_eq!(exact.gap(2.0), 4.0); // centres 6 apart, D = 2
    /// assert_eq!(exact.gap(4.0), 0.0);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn gap(&self, t: f64) -> f64 {
        let t = exact64(t);
        let f = &self.a * &t * &t + RBig::from(2) * &self.b * &t + &self.c;
        let (f, d) = (to_f64(&f), to_f64(&self.d));
        // dist − D = f / (dist + D), no cancellation.
        let dist = (f + d * d).max(0.0).sqrt();
        if dist + d.abs() == 0.0 {
            0.0
        } else {
            f / (dist + d.abs())
        }
    }

    /// `|D − d_min|`, how far the closest approach is from grazing (`d_min² = D² − q/A`);
    /// `+∞` without relative motion.
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// // Head-on: the closest approach is 0, two units inside the contact distance.
    /// assert_eq!(spheresweep_study::Exact::of(&pair).grazing_margin(), 2.0);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn grazing_margin(&self) -> f64 {
        if self.a == RBig::ZERO {
            return f64::INFINITY;
        }
        let qa = to_f64(&(&self.q / &self.a));
        let d = to_f64(&self.d).abs();
        let d_min = (d * d - qa).max(0.0).sqrt();
        qa.abs() / (d + d_min)
    }

    /// The contact distance `D`.
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// assert_eq!(spheresweep_study::Exact::of(&pair).contact_distance(), 1.0 + 1.0);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn contact_distance(&self) -> f64 {
        to_f64(&self.d)
    }

    /// Whether the pair grazes exactly (`q = b² − AC = 0`).
    ///
    /// ```
    /// # use spheresweep::{Sphere, reference::Pair};
    /// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
    /// let pair = Pair {
    ///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
    ///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
    /// };
    /// use spheresweep_study::Exact;
    /// assert!(!Exact::of(&pair).is_exactly_grazing());
    /// // Aimed 2 = D off-centre: the spheres just touch, at t = 5.
    /// let aside = Sphere::new([10.0, 2.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?;
    /// let grazing = Pair { other: aside.into(), ..pair };
    /// assert!(Exact::of(&grazing).is_exactly_grazing());
    /// assert_eq!(Exact::of(&grazing).time(f64::INFINITY), Some(5.0));
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn is_exactly_grazing(&self) -> bool {
        self.q == RBig::ZERO
    }
}
