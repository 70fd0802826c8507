//! Contact times under gravity against an exact oracle (docs/derivations/gravity.md, "Never
//! missing the earliest root"). The oracle forms each kind's polynomial from the f64 inputs and
//! f32 shapes as exact rationals (dashu), isolates its roots by the same derivative recursion
//! with every sign decided exactly, and checks the library's f64 answer `t_f` against the three
//! statements of the derivation, with `E(t) = 2⁻⁴⁷ M(t)` (`M` the magnitude bound of `p`'s terms):
//!
//! 1. at `t_f` the exact `p` is within `E` of zero;
//! 2. before `t_f` the exact `p` never rose above `E` (no deeper contact was missed);
//! 3. no answer (`None`) only if the exact `p` never rises above `E` at all; and on a simple
//!    root, `t_f` is within `2E/|p′|` (plus a few ulps) of the exact root.

use dashu::base::Approximation;
use dashu::rational::RBig;
use glam::DVec3;
use spheresweep::{Container, Cylinder, Plane, Static};

type P = Vec<RBig>;

fn q(x: f64) -> RBig {
    RBig::try_from(x).expect("finite")
}

fn f(x: &RBig) -> f64 {
    match x.to_f64() {
        Approximation::Exact(v) | Approximation::Inexact(v, _) => v,
    }
}

fn eval(p: &P, t: &RBig) -> RBig {
    let mut acc = RBig::ZERO;
    for a in p.iter().rev() {
        acc = acc * t + a;
    }
    acc
}

fn derivative(p: &P) -> P {
    p.iter()
        .enumerate()
        .skip(1)
        .map(|(k, a)| a * RBig::from(k as u32))
        .collect()
}

fn degree(p: &P) -> usize {
    (0..p.len())
        .rev()
        .find(|&k| p[k] != RBig::ZERO)
        .unwrap_or(0)
}

/// The sign change of `p` in `[lo, hi]`, bracketed to a width of `2⁻⁸⁰ max(1, hi)`.
fn bracket(p: &P, mut lo: RBig, mut hi: RBig) -> (RBig, RBig) {
    let rising = eval(p, &lo) < RBig::ZERO;
    let width = (if hi > RBig::ONE {
        hi.clone()
    } else {
        RBig::ONE
    }) / RBig::from(1u128 << 80);
    let two = RBig::from(2);
    while &hi - &lo > width {
        let mid = (&lo + &hi) / &two;
        if (eval(p, &mid) < RBig::ZERO) == rising {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo, hi)
}

/// The roots of `p` in `(0, end)`, each as a narrow bracket's midpoint, by the roots of `p′`.
fn roots(p: &P, end: &RBig) -> Vec<RBig> {
    let n = degree(p);
    if n == 0 {
        return Vec::new();
    }
    let mut cuts = vec![RBig::ZERO];
    if n >= 2 {
        cuts.extend(roots(&derivative(p), end));
    }
    cuts.push(end.clone());
    let mut out = Vec::new();
    for w in cuts.windows(2) {
        let (a, b) = (eval(p, &w[0]), eval(p, &w[1]));
        if (a < RBig::ZERO) != (b < RBig::ZERO) && b != RBig::ZERO {
            let (lo, hi) = bracket(p, w[0].clone(), w[1].clone());
            out.push((lo + hi) / RBig::from(2));
        }
    }
    out
}

/// Exact: the earliest rise of `p` through zero (the derivation's rule), searched up to `end`.
fn earliest_rise(p: &P, end: &RBig) -> Option<RBig> {
    let (p0, p1) = (&p[0], &p[1]);
    if *p0 >= RBig::ZERO && *p1 >= RBig::ZERO {
        return Some(RBig::ZERO);
    }
    let mut knots = vec![RBig::ZERO];
    knots.extend(roots(&derivative(p), end));
    knots.push(end.clone());
    for w in knots.windows(2) {
        if eval(p, &w[0]) < RBig::ZERO && eval(p, &w[1]) >= RBig::ZERO {
            let (lo, hi) = bracket(p, w[0].clone(), w[1].clone());
            return Some((lo + hi) / RBig::from(2));
        }
    }
    None
}

/// The largest value of `p` over `[0, end]`: at an end or a critical point.
fn max_on(p: &P, end: &RBig) -> RBig {
    let mut best = eval(p, &RBig::ZERO).max(eval(p, end));
    for c in roots(&derivative(p), end) {
        best = best.max(eval(p, &c));
    }
    best
}

/// The largest value of `p` over `[from, end]`.
fn max_between(p: &P, from: &RBig, end: &RBig) -> RBig {
    let mut best = eval(p, from).max(eval(p, end));
    for c in roots(&derivative(p), end) {
        if c > *from {
            best = best.max(eval(p, &c));
        }
    }
    best
}

/// `‖a + b t + c t²‖² − L²` (sign `s`), exactly.
fn norm_poly(a: [RBig; 3], b: [RBig; 3], c: [RBig; 3], l: RBig, s: i32) -> P {
    let dot = |x: &[RBig; 3], y: &[RBig; 3]| &x[0] * &y[0] + &x[1] * &y[1] + &x[2] * &y[2];
    let two = RBig::from(2);
    let p = vec![
        dot(&a, &a) - &l * &l,
        &two * dot(&a, &b),
        dot(&b, &b) + &two * dot(&a, &c),
        &two * dot(&b, &c),
        dot(&c, &c),
    ];
    p.into_iter().map(|x| x * RBig::from(s)).collect()
}

fn v3(v: DVec3) -> [RBig; 3] {
    [q(v.x), q(v.y), q(v.z)]
}

/// One case: the shape, the sphere, `g`; the oracle's polynomial for it (axis-aligned normals
/// and axes only, so that the unit vectors are exact), and the magnitudes' bound.
struct Case {
    shape: Static,
    r: DVec3,
    v: DVec3,
    radius: f64,
    g: DVec3,
}

impl Case {
    fn poly(&self) -> (P, Box<dyn Fn(f64) -> f64>) {
        let h = self.g * 0.5;
        let (r, v, radius) = (self.r, self.v, self.radius);
        match self.shape {
            Static::Container(k) => {
                let x = r - k.centre().as_dvec3();
                let d = f64::from(k.radius());
                let xe = [0, 1, 2].map(|i| q(r[i]) - q(f64::from(k.centre()[i])));
                let p = norm_poly(xe, v3(v), v3(h), q(d) - q(radius), 1);
                let m = move |t: f64| {
                    (x.length() + v.length() * t + h.length() * t * t).powi(2) + d * d
                };
                (p, Box::new(m))
            }
            Static::Cylinder(c) => {
                let axis = c.axis().as_dvec3();
                let k = (0..3)
                    .find(|&i| axis[i].abs() == 1.0)
                    .expect("an axis-aligned cylinder");
                let perp = |u: [RBig; 3]| {
                    let mut u = u;
                    u[k] = RBig::ZERO;
                    u
                };
                let xe = [0, 1, 2].map(|i| q(r[i]) - q(f64::from(c.point()[i])));
                let l = q(f64::from(c.radius())) + q(radius);
                let p = norm_poly(perp(xe), perp(v3(v)), perp(v3(h)), l, -1);
                let x = r - c.point().as_dvec3();
                let reach = f64::from(c.radius()) + radius;
                let m = move |t: f64| {
                    (x.length() + v.length() * t + h.length() * t * t).powi(2) + reach * reach
                };
                (p, Box::new(m))
            }
            Static::Plane(pl) => {
                let n = pl.normal().as_dvec3();
                let k = (0..3)
                    .find(|&i| n[i].abs() == 1.0)
                    .expect("an axis-aligned plane");
                let sign = n[k];
                let xe = q(r[k]) - q(f64::from(pl.point()[k]));
                let d = f(&xe) * sign;
                let s = if d >= 0.0 { 1 } else { -1 };
                let ss = RBig::from(s) * q(sign);
                // R − s n̂·(x + v t + h t²)
                let p = vec![
                    q(radius) - &ss * xe,
                    -(&ss * q(v[k])),
                    -(&ss * q(h[k])),
                    RBig::ZERO,
                    RBig::ZERO,
                ];
                let x = (r - pl.point().as_dvec3()).length();
                let m = move |t: f64| x + v.length() * t + h.length() * t * t + radius;
                (p, Box::new(m))
            }
            other => panic!("no oracle for {other:?}"),
        }
    }

    /// Checks the library's answer against the oracle; returns whether a contact was found.
    fn check(&self, name: &str) -> bool {
        let tf = self
            .shape
            .time_of_impact_falling(self.r, self.v, self.radius, self.g);
        let (p, m) = self.poly();
        let bound = |t: f64| m(t) / (1u64 << 47) as f64;
        // The search window: a time by which the exact answer is known to have come.
        let horizon = q(1e6);
        let exact = earliest_rise(&p, &horizon);
        match tf {
            Some(0.0) => {
                // A contact now: on or past the wall (moving out, by the rule).
                let at = f(&eval(&p, &RBig::ZERO));
                assert!(
                    at >= -bound(0.0),
                    "{name}: a contact now, {at:e} inside the wall"
                );
                true
            }
            Some(t) => {
                let te = q(t);
                let at = f(&eval(&p, &te));
                assert!(
                    at.abs() <= bound(t),
                    "{name}: p(t_f = {t}) = {at:e} beyond {:e}",
                    bound(t)
                );
                // From the first time it is inside (a sphere past the wall moving back in
                // starts with p > 0): no rise above E before t_f.
                let inside = if eval(&p, &RBig::ZERO) > RBig::ZERO {
                    roots(&p, &te).into_iter().next().unwrap_or(RBig::ZERO)
                } else {
                    RBig::ZERO
                };
                let before = f(&max_between(&p, &inside, &te));
                assert!(
                    before <= bound(t),
                    "{name}: p rose to {before:e} before t_f = {t} (bound {:e}); exact root {:?}",
                    bound(t),
                    exact.as_ref().map(f)
                );
                if let Some(e) = &exact {
                    let slope = f(&eval(&derivative(&p), e)).abs();
                    let te = f(e);
                    if slope > 0.0 && te > 0.0 {
                        let allowed = 2.0 * bound(te) / slope + 4.0 * te * f64::EPSILON;
                        // A graze may be answered anywhere its p stays within E.
                        if allowed < te {
                            assert!(
                                (t - te).abs() <= allowed,
                                "{name}: t_f = {t} vs exact {te} (allowed {allowed:e})"
                            );
                        }
                    }
                }
                true
            }
            None => {
                let peak = f(&max_on(&p, &horizon));
                assert!(
                    peak <= bound(1e6),
                    "{name}: no contact found, yet p rises to {peak:e} (exact root {:?})",
                    exact.as_ref().map(f)
                );
                false
            }
        }
    }
}

fn container(c: [f32; 3], r: f32) -> Static {
    Static::Container(Container::new(c, r).unwrap())
}

/// Hard cases by name, in a vessel of radius 5 (and one far from the origin).
#[test]
fn hard_cases_in_a_vessel_match_the_oracle() {
    let g = DVec3::new(0.0, 0.0, -9.81);
    let d = 4.5; // R_K − R
    let cases = [
        // Resting in the bottom: on the wall, not moving: a contact now.
        (
            "resting at the bottom",
            DVec3::new(0.0, 0.0, -d),
            DVec3::ZERO,
        ),
        // Hopping off the bottom at the least speeds the engine uses.
        (
            "hop 1e-4",
            DVec3::new(0.0, 0.0, -d),
            DVec3::new(0.0, 0.0, 1e-4),
        ),
        (
            "hop 1e-7",
            DVec3::new(0.0, 0.0, -d),
            DVec3::new(0.0, 0.0, 1e-7),
        ),
        // Tangential rolling: along the bottom at speed 3, leaving at 2⁻¹² rad.
        (
            "rolling",
            DVec3::new(0.0, 0.0, -d),
            DVec3::new(3.0, 0.0, 3.0 / 4096.0),
        ),
        (
            "rolling fast",
            DVec3::new(0.0, 0.0, -d),
            DVec3::new(30.0, 1.0, 30.0 / 4096.0),
        ),
        // Sliding along the wall at the equator, faster than gravity can pull it off.
        (
            "equator",
            DVec3::new(d, 0.0, 0.0),
            DVec3::new(-1e-3, 20.0, 0.0),
        ),
        // Thrown horizontally from near the top: falls the whole way.
        (
            "from the top",
            DVec3::new(0.0, 0.0, d - 1e-9),
            DVec3::new(1.0, 0.0, 0.0),
        ),
        // A parabola whose apex grazes the wall from inside: apex at height d on the axis.
        (
            "apex graze",
            DVec3::new(0.0, 0.0, d - 0.5 * 9.0 / 9.81),
            DVec3::new(0.0, 0.0, 3.0),
        ),
        // Past the wall moving in.
        (
            "past, moving in",
            DVec3::new(0.0, 0.0, -d - 1e-9),
            DVec3::new(0.0, 0.0, 1.0),
        ),
    ];
    for (name, r, v) in cases {
        let case = Case {
            shape: container([0.0; 3], 5.0),
            r,
            v,
            radius: 0.5,
            g,
        };
        assert!(
            case.check(name),
            "{name}: a sphere in a vessel always meets it"
        );
    }
    // The same far from the origin, and with a tilted gravity.
    let far = [1000.0f32, -2000.0, 500.0];
    let c = DVec3::new(1000.0, -2000.0, 500.0);
    for (name, r, v) in [
        ("far resting", c + DVec3::new(0.0, 0.0, -d), DVec3::ZERO),
        (
            "far rolling",
            c + DVec3::new(0.0, 0.0, -d),
            DVec3::new(3.0, 0.0, 1e-3),
        ),
    ] {
        let case = Case {
            shape: container(far, 5.0),
            r,
            v,
            radius: 0.5,
            g: DVec3::new(0.3, -0.2, -9.81),
        };
        assert!(case.check(name));
    }
}

/// Pillars and floors: grazes, hops, a sphere skimming along a pillar, and `g` along the axis.
#[test]
fn hard_cases_on_pillars_and_floors_match_the_oracle() {
    let g = DVec3::new(0.0, 0.0, -9.81);
    let pillar = Static::Cylinder(Cylinder::new([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0).unwrap());
    let floor = Static::Plane(Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap());
    let cases: Vec<(&str, Static, DVec3, DVec3, bool)> = vec![
        // Dropped onto the top of a horizontal pillar.
        (
            "onto a pillar",
            pillar,
            DVec3::new(0.3, 0.0, 3.0),
            DVec3::ZERO,
            true,
        ),
        // Falling past the pillar's side, missing it by 10⁻⁹.
        (
            "skims the side",
            pillar,
            DVec3::new(0.0, 1.5 + 1e-9, 3.0),
            DVec3::ZERO,
            false,
        ),
        // Resting on top, and hopping off it.
        (
            "resting on top",
            pillar,
            DVec3::new(0.0, 0.0, 1.5),
            DVec3::ZERO,
            true,
        ),
        (
            "hop off the top",
            pillar,
            DVec3::new(0.0, 0.0, 1.5),
            DVec3::new(0.0, 0.0, 1e-5),
            true,
        ),
        // Moving sideways over the top: slower than √(gL) gravity holds it to the curve (a
        // contact at once), faster it flies off, never back.
        (
            "rolls over",
            pillar,
            DVec3::new(0.0, 0.0, 1.5),
            DVec3::new(0.0, 2.0, 1e-6),
            true,
        ),
        (
            "flies off",
            pillar,
            DVec3::new(0.0, 0.0, 1.5),
            DVec3::new(0.0, 5.0, 1e-6),
            false,
        ),
        // Floor: resting, hopping, thrown up.
        (
            "resting on the floor",
            floor,
            DVec3::new(0.0, 0.0, 0.5),
            DVec3::ZERO,
            true,
        ),
        (
            "hop",
            floor,
            DVec3::new(0.0, 0.0, 0.5),
            DVec3::new(1.0, 0.0, 1e-7),
            true,
        ),
        (
            "thrown up",
            floor,
            DVec3::new(5.0, 0.0, 2.0),
            DVec3::new(0.0, 1.0, 7.0),
            true,
        ),
    ];
    for (name, shape, r, v, hits) in cases {
        let case = Case {
            shape,
            r,
            v,
            radius: 0.5,
            g,
        };
        assert_eq!(case.check(name), hits, "{name}");
    }
    // Gravity along the pillar's axis: a quadratic; a sphere thrown at it sideways.
    let case = Case {
        shape: pillar,
        r: DVec3::new(0.0, 3.0, 0.0),
        v: DVec3::new(1.0, -1.0, 0.0),
        radius: 0.5,
        g: DVec3::new(-9.81, 0.0, 0.0),
    };
    assert!(case.check("g along the axis"));
}

/// Random spheres in a vessel, on a pillar's scale and a floor's, across six decades of speed
/// and gravity.
#[test]
fn random_cases_match_the_oracle() {
    let mut rng = spheresweep::rng::Rng::new(17);
    let vessel = container([0.5, -0.25, 2.0], 5.0);
    let pillar = Static::Cylinder(Cylinder::new([0.0, 0.0, 0.0], [0.0, 1.0, 0.0], 0.7).unwrap());
    let mut found = 0;
    for k in 0..300 {
        let speed = 10f64.powf(6.0 * rng.unit() - 3.0);
        let gravity = 10f64.powf(4.0 * rng.unit() - 2.0);
        let g = rng.direction() * gravity;
        let v = rng.direction() * speed;
        let (shape, r) = if k % 2 == 0 {
            let r = DVec3::new(0.5, -0.25, 2.0) + rng.direction() * 4.4 * rng.unit();
            (vessel, r)
        } else {
            let mut r = rng.direction() * (1.25 + 3.0 * rng.unit());
            if (r.x * r.x + r.z * r.z).sqrt() < 1.25 {
                r.x = r.x.abs() + 1.25;
            }
            (pillar, r)
        };
        let case = Case {
            shape,
            r,
            v,
            radius: 0.5,
            g,
        };
        found += usize::from(case.check(&format!("random {k}")));
    }
    assert!(found > 150, "{found} contacts");
}
