//! The first-order rounding-error model of docs/derivations/accuracy.md, shared by the
//! narrow-phase tests: where hit/miss may differ from the f64 reference, and by how much
//! times may (pairs and their reference answers come from `spheresweep::reference::Pair`).

pub use spheresweep::reference::Pair;
use spheresweep::{Accuracy, QueryOptions, Side};

/// The 8-wide kernel's answer for a pair, through the public single-pair entry point (which
/// gives the batch entry points' bits: tests/narrow_batch.rs).
pub trait Kernel {
    /// Time of impact in `mode` over `[0, t_max]`.
    fn kernel(&self, mode: Accuracy, t_max: f32) -> Option<f32>;
}

impl Kernel for Pair {
    fn kernel(&self, mode: Accuracy, t_max: f32) -> Option<f32> {
        let options = QueryOptions::new(t_max, mode).expect("a valid window");
        spheresweep::time_of_impact(&self.sphere, &self.other, options)
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
    let t_ref = pair.time_of_impact(f64::INFINITY);
    let (r0, v, d, side) = pair.relative();
    let x = pair.operand_scale(mode);
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
    // Touching or overlapping at t = 0 with |b| within its rounding: the contact policy
    // decides hit (t = 0) or miss by the sign of b alone (found by the `kernels` fuzz target:
    // a sphere centred on a zero-radius cylinder's axis, moving across it).
    let in_contact = match side {
        Side::Exterior => c <= dc,
        Side::Interior => c >= -dc,
    };
    let ambiguous = q.abs() <= dq
        || a <= da
        || (b.abs() <= db && in_contact)
        // A root near the window's end; a contact now (t = 0) is in every window.
        || t_ref.is_some_and(|t| t > 0.0 && (t - t_max).abs() <= dt);
    Model {
        ambiguous,
        dt,
        q,
        dq,
    }
}
