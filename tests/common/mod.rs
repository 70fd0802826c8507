//! Shared by the narrow-phase tests: one pair of any kind, its reference answer, its kernel
//! answer in every mode, and the first-order rounding-error model of
//! docs/derivations/accuracy.md that says where hit/miss may differ and by how much times may.
#![allow(dead_code)]

use glam::DVec3;
use spheresweep::narrow::{self, Query};
use spheresweep::reference::{self, Side};
use spheresweep::{Accuracy, Container, Cylinder, Plane, Sphere, SphereStore};

/// The other body of a pair.
#[derive(Debug, Clone, Copy)]
pub enum Other {
    Sphere(Sphere),
    Plane(Plane),
    Cylinder(Cylinder),
    Container(Container),
}

/// A moving sphere and what it may hit.
#[derive(Debug, Clone, Copy)]
pub struct Pair {
    pub sphere: Sphere,
    pub other: Other,
}

impl Pair {
    pub fn reference(&self, t_max: f64) -> Option<f64> {
        let s = &self.sphere;
        match &self.other {
            Other::Sphere(b) => reference::sphere_sphere::time_of_impact(s, b, t_max),
            Other::Plane(p) => reference::sphere_plane::time_of_impact(s, p, t_max),
            Other::Cylinder(c) => reference::sphere_cylinder::time_of_impact(s, c, t_max),
            Other::Container(k) => reference::sphere_container::time_of_impact(s, k, t_max),
        }
    }

    /// The kernel's answer through the public batch API, one item.
    pub fn kernel(&self, mode: Accuracy, t_max: f32) -> Option<f32> {
        let q = Query::new(t_max, mode).unwrap();
        let one = SphereStore::from_spheres(&[self.sphere]);
        let first = |r: Result<Vec<Option<narrow::FirstContact>>, _>| r.unwrap()[0].map(|f| f.time);
        match &self.other {
            Other::Sphere(b) => {
                let mut out = [0.0];
                let two = SphereStore::from_spheres(&[*b]);
                narrow::zip_times(&one, &two, q, &mut out).unwrap();
                out[0].is_finite().then_some(out[0])
            }
            Other::Plane(p) => first(narrow::first_contacts(&one, &[*p], q)),
            Other::Cylinder(c) => first(narrow::first_contacts(&one, &[*c], q)),
            Other::Container(k) => first(narrow::first_contacts(&one, &[*k], q)),
        }
    }

    /// `(r0, v, D, side)` in f64, the plane's embedded along x; and `X`, the size of the
    /// position-like operands the mode's kernel subtracts (its absolute rounding scale).
    pub fn geometry(&self, mode: Accuracy) -> (DVec3, DVec3, f64, Side, f64) {
        let s = &self.sphere;
        let (c, v, r) = (
            s.centre().as_dvec3(),
            s.velocity().as_dvec3(),
            f64::from(s.radius()),
        );
        let f32_anchor = mode == Accuracy::Stable;
        match &self.other {
            Other::Sphere(b) => {
                let r0 = b.centre().as_dvec3() - c;
                let rel_v = b.velocity().as_dvec3() - v;
                (
                    r0,
                    rel_v,
                    r + f64::from(b.radius()),
                    Side::Exterior,
                    r0.length(),
                )
            }
            Other::Container(k) => {
                let r0 = c - k.centre().as_dvec3();
                (
                    r0,
                    v,
                    f64::from(k.radius()) - r,
                    Side::Interior,
                    r0.length(),
                )
            }
            Other::Plane(p) => {
                let n = p.normal().as_dvec3();
                let point = p.point().as_dvec3();
                let foot = n * point.dot(n);
                let x = if f32_anchor {
                    (c - foot).length() + foot.length()
                } else {
                    (c - point).length()
                };
                let r0 = DVec3::new((c - point).dot(n), 0.0, 0.0);
                // |v| (not |v·n|): the kernel's v·n carries rounding of the whole velocity.
                (r0, DVec3::new(v.dot(n), 0.0, 0.0), r, Side::Exterior, x)
            }
            Other::Cylinder(cy) => {
                let s_ = cy.axis().as_dvec3().normalize();
                let point = cy.point().as_dvec3();
                let foot = point - s_ * point.dot(s_);
                let x = if f32_anchor {
                    (c - foot).length() + foot.length()
                } else {
                    (c - point).length()
                };
                let perp = |w: DVec3| w - s_ * w.dot(s_);
                (
                    perp(c - point),
                    perp(v),
                    r + f64::from(cy.radius()),
                    Side::Exterior,
                    x,
                )
            }
        }
    }

    /// Full speed, for the rounding of velocity projections.
    pub fn speed(&self) -> f64 {
        let v = self.sphere.velocity().as_dvec3();
        match &self.other {
            Other::Sphere(b) => (b.velocity().as_dvec3() - v).length(),
            _ => v.length(),
        }
    }
}

/// Unit roundoff of f32 and f64.
pub const U32: f64 = 1.0 / (1u64 << 24) as f64;
pub const U64: f64 = 1.0 / (1u64 << 53) as f64;
/// Worst-case roundings (in units of `u` times the operand scale) a kernel spends on each of
/// `A`, `b`, `C`, operands included: the largest count over kinds and modes is the textbook
/// cylinder's `C`, 23 (docs/derivations/accuracy.md, "Rounding counts").
pub const K: f64 = 24.0;

/// Where the mode's answer may differ from the reference, and by how much.
#[derive(Debug, Clone, Copy)]
pub struct Model {
    /// Hit/miss may differ (inside a band of ill-conditioning).
    pub ambiguous: bool,
    /// Bound on |t_kernel − t_reference| when both hit.
    pub dt: f64,
    /// The quantities, for messages.
    pub q: f64,
    pub dq: f64,
}

/// The model for `pair` in `mode` with the window `[0, t_max]`.
pub fn model(pair: &Pair, mode: Accuracy, t_max: f64) -> Model {
    // The reference's root without the window: is it near the window's end?
    let t_ref = pair.reference(f64::INFINITY);
    let (r0, v, d, side, x) = pair.geometry(mode);
    let speed = pair.speed();
    let u = if mode == Accuracy::Double { U64 } else { U32 };
    let a = v.dot(v);
    let b = r0.dot(v);
    let c = r0.dot(r0) - d * d;
    let w = r0.cross(v);
    let q = a * d * d - w.dot(w);
    let (da, db, dc) = (
        K * u * speed * speed,
        K * u * x * speed,
        K * u * (x * x + d * d),
    );
    // The f64 reference evaluates B² − 4AC literally: its own error in q units.
    let dq_ref = 4.0 * U64 * (b * b + a * c.abs()) + 2.0 * K * U64 * x * speed * b.abs();
    let dq_mode = match mode {
        // disc = B² − 4AC = 4q: δdisc/4 = |B|δB/2 + δA|C| + AδC + u(B² + 4A|C|).
        Accuracy::Textbook => {
            2.0 * b.abs() * db + da * c.abs() + a * dc + 4.0 * u * (b * b + a * c.abs())
        }
        // Stable: δq ≤ 7u A D² + 11u X V ‖w‖ + δA D² (counts in the derivation) ≤ K u (…).
        _ => K * u * (a * d * d + x * speed * w.length()) + da * d * d,
    };
    let dq = dq_mode + dq_ref;
    let t = t_ref.unwrap_or(0.0);
    let sq = q.max(0.0).sqrt();
    let root_dt = |u: f64, dq: f64, db: f64, da: f64, dc: f64| -> f64 {
        let tb = (2.0 * db + 2.0 * dq.sqrt() + 2.0 * t * da) / (2.0 * a);
        let dt = match (mode, side) {
            (Accuracy::Textbook, _) => tb,
            (_, Side::Exterior) => (dc + t * (dq.sqrt() + db)) / (sq + b.abs()),
            (_, Side::Interior) if b <= 0.0 => (dq.sqrt() + db + t * da) / a,
            (_, Side::Interior) => (dc + t * (dq.sqrt() + db)) / (b + sq),
        };
        dt + 3.0 * u * t
    };
    let dt_ref =
        (2.0 * K * U64 * x * speed + 2.0 * dq_ref.sqrt() + 2.0 * t * K * U64 * a) / (2.0 * a);
    let dt = root_dt(u, dq_mode, db, da, dc) + dt_ref + U32 * t;
    let ambiguous = q.abs() <= dq
        || a <= da
        || (b.abs() <= db && c.abs() <= dc)
        || t_ref.is_some_and(|t| (t - t_max).abs() <= dt);
    Model {
        ambiguous,
        dt,
        q,
        dq,
    }
}
