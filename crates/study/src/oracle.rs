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
use spheresweep::Shape;
use spheresweep::Side;

/// The exact quadratic `dist² − D² = A t² + 2b t + C` of one pair, and `q = b² − AC`.
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

fn vector(v: glam::Vec3) -> V {
    [exact(v.x), exact(v.y), exact(v.z)]
}
fn sub(a: &V, b: &V) -> V {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}
fn dot(a: &V, b: &V) -> RBig {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}
fn to_f64(x: &RBig) -> f64 {
    x.to_f64().value()
}

impl Exact {
    /// The exact coefficients of `pair`.
    pub fn of(pair: &Pair) -> Self {
        let s = &pair.sphere;
        let (c, v, r) = (vector(s.centre()), vector(s.velocity()), exact(s.radius()));
        let (a, b, cc, d, side) = match &pair.other {
            Shape::Sphere(o) => {
                let r0 = sub(&vector(o.centre()), &c);
                let v = sub(&vector(o.velocity()), &v);
                let d = &r + exact(o.radius());
                (
                    dot(&v, &v),
                    dot(&r0, &v),
                    dot(&r0, &r0) - &d * &d,
                    d,
                    Side::Exterior,
                )
            }
            Shape::Container(k) => {
                let r0 = sub(&c, &vector(k.centre()));
                let d = exact(k.radius()) - &r;
                (
                    dot(&v, &v),
                    dot(&r0, &v),
                    dot(&r0, &r0) - &d * &d,
                    d,
                    Side::Interior,
                )
            }
            Shape::Plane(p) => {
                let n = vector(p.normal());
                let nn = dot(&n, &n);
                let r0 = dot(&sub(&c, &vector(p.point())), &n);
                let vn = dot(&v, &n);
                let a = &vn * &vn / &nn;
                let b = &r0 * &vn / &nn;
                let cc = &r0 * &r0 / &nn - &r * &r;
                (a, b, cc, r, Side::Exterior)
            }
            Shape::Cylinder(cy) => {
                let s_ = vector(cy.axis());
                let ss = dot(&s_, &s_);
                let x = sub(&c, &vector(cy.point()));
                let (xs, vs) = (dot(&x, &s_), dot(&v, &s_));
                let d = &r + exact(cy.radius());
                let a = dot(&v, &v) - &vs * &vs / &ss;
                let b = dot(&x, &v) - &xs * &vs / &ss;
                let cc = dot(&x, &x) - &xs * &xs / &ss - &d * &d;
                (a, b, cc, d, Side::Exterior)
            }
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
                } else if *c >= zero && *b > zero {
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
    pub fn contact_distance(&self) -> f64 {
        to_f64(&self.d)
    }

    /// Whether the pair grazes exactly (`q = b² − AC = 0`).
    pub fn is_exactly_grazing(&self) -> bool {
        self.q == RBig::ZERO
    }
}
