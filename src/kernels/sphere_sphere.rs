//! Sphere–sphere, eight (or four) pairs at once: `r0 = r_B0 − r_A0`, `v = v_B − v_A`,
//! `D = R_A + R_B`.

use super::quadratic::{Relative3, Solver};
use crate::contact::Side;
use crate::lanes::{Lanes, sub};
use crate::store::SphereLanes;

/// Earliest exterior contact time per lane in `[0, t_max]`, `+∞` for none; and the mask of
/// lanes outside the f32 kernels' safe range.
#[inline(always)]
pub fn time_of_impact<L: Lanes, S: Solver>(
    a: &SphereLanes<L>,
    b: &SphereLanes<L>,
    t_max: L,
) -> (L, L) {
    let rel = Relative3 {
        r0: sub(b.c, a.c),
        v: sub(b.v, a.v),
        d: a.r + b.r,
    };
    S::arrival(&rel, Side::Exterior, t_max)
}
