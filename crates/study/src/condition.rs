//! The condition number of a case's contact time, estimated with the exact oracle: how many
//! f32 ulps of the true time `t*` the true time moves when every f32 input moves by one ulp
//! (docs/derivations/condition.md).
//!
//! `κ = Σᵢ |t*(x + δᵢ eᵢ) − t*(x)| / ulp(t*)`, over every input `xᵢ` of the pair (each
//! coordinate of the centres, velocities, points, normals and axes, and each radius), where
//! `δᵢ` moves `xᵢ` to the next f32 up (or down, when moving up loses the contact). A first-order
//! estimate of `Σᵢ |∂t*/∂xᵢ| ulp(xᵢ) / ulp(t*)`: a backward-stable kernel whose answer is the
//! exact time of inputs each perturbed by `k` ulps has a time error up to about `k κ` ulps, so
//! the time error divided by `κ` tells an inaccurate kernel apart from an ill-conditioned case.

use super::oracle::{Exact, Inputs};
use super::pair::Pair;

/// The spacing of the f32 numbers just above `|t|` rounded to f32 (its ulp), in f64.
///
/// ```
/// use spheresweep_study::ulp32;
/// assert_eq!(ulp32(1.0), f64::from(f32::EPSILON)); // 2⁻²³
/// assert_eq!(ulp32(-4.0), 4.0 * f64::from(f32::EPSILON));
/// ```
pub fn ulp32(t: f64) -> f64 {
    let f = (t.abs() as f32).min(f32::MAX);
    f64::from(f.next_up()) - f64::from(f)
}

/// The condition number `κ` of `pair`'s contact time in the open window `[0, ∞)`, in ulps of
/// the time per ulp of every input (the sum over inputs).
///
/// `None` when the oracle finds no contact ahead (`t* = 0` or no contact: the time error is
/// not measured there). `Some(+∞)` when some input, moved by one ulp either way, loses the
/// contact: hit or miss itself is then decided by the last bit of an input.
///
/// ```
/// # use spheresweep::{Sphere, reference::Pair};
/// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
/// let pair = Pair {
///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
/// };
/// use spheresweep_study::condition;
/// let kappa = condition(&pair).unwrap();
/// assert!(kappa.is_finite() && kappa > 0.0); // a head-on contact is well-conditioned
/// let receding = Sphere::new([10.0, 0.0, 0.0], [2.0, 0.0, 0.0], 1.0, 1.0)?;
/// let apart = Pair { other: receding.into(), ..pair };
/// assert_eq!(condition(&apart), None); // no contact ahead
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn condition(pair: &Pair) -> Option<f64> {
    let inputs = Inputs::of(pair);
    let t = Exact::from_inputs(&inputs).time(f64::INFINITY)?;
    if t <= 0.0 {
        return None;
    }
    let mut sum = 0.0;
    for (i, &x) in inputs.values().iter().enumerate() {
        let moved = [x.next_up(), x.next_down()]
            .into_iter()
            .filter(|m| m.is_finite() && !(inputs.is_radius(i) && *m < 0.0))
            .find_map(|m| Exact::from_inputs(&inputs.with(i, m)).time(f64::INFINITY));
        match moved {
            Some(tm) => sum += (tm - t).abs(),
            None => return Some(f64::INFINITY),
        }
    }
    Some(sum / ulp32(t))
}
