//! Contact times under a uniform acceleration: a sphere on the parabola
//! `x(t) = q + v t + h t²` (`h = g/2`) meets a static shape where a polynomial of degree at
//! most four, `p(t) = Σ a_k t^k` with `p < 0` on the allowed side, rises through zero. Each
//! shape kind writes its own `p` in its kernel file (`falling_polynomial`); this file finds its
//! earliest admissible root, never missing one (docs/derivations/gravity.md).
//!
//! The method isolates every real root by the roots of the derivatives: the roots of `p′`
//! (found the same way, one degree down) cut `[0, T]` into pieces on which `p` is monotone,
//! `T` being Fujiwara's bound on the roots; the first piece on which `p` rises from below zero
//! to at least zero holds the answer, narrowed to adjacent doubles (Newton's steps inside the
//! bracket, then halving). Every decision is a sign of `p` or of a derivative evaluated once,
//! so a root is missed only where `p` stays within its own rounding of zero: a graze no deeper
//! than that rounding.

/// The coefficients `a_0 … a_4` of a polynomial of degree at most four.
pub(crate) type Poly = [f64; 5];

/// The earliest `t ≥ 0` at which `p` rises through zero onto the forbidden side (`p ≥ 0`
/// with `p` increasing), or `0` when the sphere is on or past the wall moving out
/// (`p(0) ≥ 0` and `p′(0) ≥ 0`); `+∞` when it never does. A sphere past the wall moving back
/// in (`p(0) > 0`, `p′(0) < 0`) is answered at its next rise, the seed's rule that only an
/// approach is a contact. Coefficients beyond f64's range (a scene of size or gravity near
/// 10¹⁵⁰) give `+∞`: the engine's invariant check names any breach that follows.
pub(crate) fn earliest_rise(p: &Poly) -> f64 {
    if !p.iter().all(|a| a.is_finite()) {
        return f64::INFINITY;
    }
    if p[0] >= 0.0 && p[1] >= 0.0 {
        return 0.0;
    }
    let degree = degree(p);
    if degree == 0 {
        return f64::INFINITY;
    }
    let (knots, count) = monotone_pieces(p, degree, root_bound(p, degree));
    let mut lo = 0.0;
    let mut p_lo = eval(p, 0.0);
    for &hi in &knots[1..count] {
        let p_hi = eval(p, hi);
        if p_lo < 0.0 && p_hi >= 0.0 {
            return narrow(p, lo, hi, true).0;
        }
        (lo, p_lo) = (hi, p_hi);
    }
    f64::INFINITY
}

/// The ends of the pieces of `[0, end]` on which `q` (degree at most `n ≤ 4`) is monotone:
/// `0`, the roots of `q′` inside, then `end`; and how many of the five slots are used.
fn monotone_pieces(q: &Poly, n: usize, end: f64) -> ([f64; 5], usize) {
    let mut knots = [0.0; 5];
    let inner = if n >= 2 {
        roots_in(&derivative(q), n - 1, end, &mut knots[1..4])
    } else {
        0
    };
    knots[inner + 1] = end;
    (knots, inner + 2)
}

/// The index of the highest non-zero coefficient (`0` for a constant).
fn degree(p: &Poly) -> usize {
    (0..5).rev().find(|&k| p[k] != 0.0).unwrap_or(0)
}

/// `p′`.
fn derivative(p: &Poly) -> Poly {
    [p[1], 2.0 * p[2], 3.0 * p[3], 4.0 * p[4], 0.0]
}

/// `p(t)` by Horner's rule.
#[inline]
pub(crate) fn eval(p: &Poly, t: f64) -> f64 {
    (((p[4] * t + p[3]) * t + p[2]) * t + p[1]) * t + p[0]
}

/// Fujiwara's bound: every root of `p` (degree `n ≥ 1`) is at most
/// `2 max_k |a_{n−k}/a_n|^{1/k}` (the last term halved) in modulus. Slightly enlarged so that
/// rounding of the bound itself cannot put a root beyond it; `f64::MAX` if it overflows.
fn root_bound(p: &Poly, n: usize) -> f64 {
    let lead = p[n].abs();
    let mut m: f64 = 0.0;
    for k in 1..=n {
        let mut ratio = p[n - k].abs() / lead;
        if k == n {
            ratio /= 2.0;
        }
        m = m.max(ratio.powf(1.0 / k as f64));
    }
    let b = 2.0 * m * (1.0 + 1e-9) + f64::MIN_POSITIVE;
    if b.is_finite() { b } else { f64::MAX }
}

/// The roots of `q` (degree at most `n ≤ 3`) strictly inside `(0, end)`, in increasing order,
/// written to `out`; how many. On each of `q`'s monotone pieces at most one root lies, found
/// where `q` changes sign across the piece and narrowed to adjacent doubles.
fn roots_in(q: &Poly, n: usize, end: f64, out: &mut [f64]) -> usize {
    let n = n.min(degree(q));
    if n == 0 {
        return 0;
    }
    let (knots, count) = monotone_pieces(q, n, end);
    let mut found = 0;
    let mut lo = 0.0;
    let mut q_lo = eval(q, 0.0);
    for &hi in &knots[1..count] {
        let q_hi = eval(q, hi);
        if (q_lo < 0.0) != (q_hi < 0.0) && q_hi != 0.0 && found < out.len() {
            let (a, b) = narrow(q, lo, hi, q_lo < 0.0);
            let t = 0.5 * (a + b);
            if t > 0.0 && t < end {
                out[found] = t;
                found += 1;
            }
        }
        (lo, q_lo) = (hi, q_hi);
    }
    found
}

/// Narrows `[lo, hi]` around the sign change of `q` (`rising`: `q(lo) < 0 ≤ q(hi)`, else the
/// reverse) until its ends are adjacent doubles; for a rise its lower end is a time at which
/// the sphere is still on the allowed side by `q`'s own evaluation. How:
/// Newton's steps from the middle while they stay inside the bracket (each evaluation moves
/// one end), a few single-ulp steps to close it around where they converged, then halving
/// whatever is left. Every end is set by the sign of `q` evaluated there, as with halving
/// alone, so the answer carries the same guarantee; Newton only makes it quicker.
fn narrow(q: &Poly, mut lo: f64, mut hi: f64, rising: bool) -> (f64, f64) {
    let below = |t: f64| (eval(q, t) < 0.0) == rising;
    let dq = derivative(q);
    let mut x = 0.5 * (lo + hi);
    for _ in 0..16 {
        let fx = eval(q, x);
        if (fx < 0.0) == rising {
            lo = x;
        } else {
            hi = x;
        }
        let next = x - fx / eval(&dq, x);
        if !(next > lo && next < hi) || next == x {
            break;
        }
        x = next;
    }
    for _ in 0..4 {
        if lo.next_up() >= hi {
            return (lo, hi);
        }
        if x == lo {
            let up = lo.next_up();
            if below(up) {
                (lo, x) = (up, up);
            } else {
                hi = up;
            }
        } else {
            let down = hi.next_down();
            if below(down) {
                lo = down;
            } else {
                (hi, x) = (down, down);
            }
        }
    }
    loop {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            return (lo, hi);
        }
        if below(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `(t − r₁)(t − r₂)…` times `lead`, expanded.
    fn from_roots(lead: f64, roots: &[f64]) -> Poly {
        let mut p = [0.0; 5];
        p[0] = lead;
        for (deg, &r) in roots.iter().enumerate() {
            for k in (0..=deg + 1).rev() {
                let below = if k > 0 { p[k - 1] } else { 0.0 };
                p[k] = below - r * p[k];
            }
        }
        p
    }

    #[test]
    fn the_first_rising_root_is_found_among_four() {
        // Roots 1, 2, 3, 4 with a positive lead: p < 0 on (1, 2) and (3, 4), rising at 2 and 4;
        // from t = 0 (p(0) > 0, falling) the first rise is at 2.
        let p = from_roots(1.0, &[1.0, 2.0, 3.0, 4.0]);
        let t = earliest_rise(&p);
        assert!((t - 2.0).abs() < 1e-14, "{t}");
        // Negated: p < 0 before 1, rises at 1.
        let q = p.map(|a| -a);
        assert!((earliest_rise(&q) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn a_rise_between_close_roots_is_not_missed() {
        // Two roots 10⁻⁶ apart far out: a dip of depth ~10⁻¹² between them. −p < 0 before 5
        // and rises there, with slope |p′(5)| = 10⁻⁶·2·4; the time is good to the evaluation
        // bound over the slope, `16u Σ|a_k| 5^k / |p′(5)|` (docs/derivations/gravity.md).
        let p = from_roots(1.0, &[5.0, 5.000001, 7.0, 9.0]).map(|a| -a);
        let t = earliest_rise(&p);
        let magnitude: f64 = (0..5).map(|k| p[k].abs() * 5f64.powi(k as i32)).sum();
        let bound = 16.0 * f64::EPSILON / 2.0 * magnitude / 8e-6;
        assert!((t - 5.0).abs() <= bound, "{t} (bound {bound:e})");
        assert!(bound < 1e-5, "the test tells the two roots apart");
    }

    #[test]
    fn on_the_wall_moving_out_is_a_contact_now_and_moving_in_is_not() {
        assert_eq!(earliest_rise(&[0.0, 1.0, -1.0, 0.0, 0.0]), 0.0);
        // Past the wall, moving back in, then out again at t = 2 (p = 2 − 3t + t²).
        let t = earliest_rise(&[2.0, -3.0, 1.0, 0.0, 0.0]);
        assert!((t - 2.0).abs() < 1e-15, "{t}");
        // Never: a constant inside, or a parabola that stays below.
        assert_eq!(earliest_rise(&[-1.0, 0.0, 0.0, 0.0, 0.0]), f64::INFINITY);
        assert_eq!(earliest_rise(&[-1.0, 1.0, -1.0, 0.0, 0.0]), f64::INFINITY);
    }

    #[test]
    fn the_answer_is_never_past_the_root() {
        // At the returned time p is still below zero (by its own evaluation), one step later
        // it is not.
        for &(a, b) in &[(0.3, 0.7), (1e-8, 2.0), (0.5, 1e6)] {
            let p = from_roots(-1.0, &[a, b]);
            let t = earliest_rise(&p.map(|x| -x));
            let q = p.map(|x| -x);
            assert!(
                eval(&q, t) < 0.0 && eval(&q, t.next_up()) >= 0.0,
                "{a} {b}: {t}"
            );
        }
    }
}
