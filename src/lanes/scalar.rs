//! One f64 lane: the kernels' formulas for a single pair, with the same roundings as a lane of
//! `f64x4` (the same IEEE operations, and `mul_add` a real fused multiply-add on x86-64-v3).
//! The event-driven engine answers its neighbours one at a time with it, where a group of four
//! cost more to fill than it saved (docs/derivations/simulation.md, "Prediction in f64"); the
//! kernels' test `one_pair_answers_as_each_lane_of_four` holds it to `f64x4` bit for bit.
//! A mask is a lane with all bits set or clear, as in the wide types.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Sub};
use wide::f64x4;

use super::Lanes;

/// A single f64 lane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct F64x1(pub f64);

/// A mask's set lane.
const SET: u64 = u64::MAX;

impl F64x1 {
    #[inline(always)]
    fn mask(set: bool) -> Self {
        Self(f64::from_bits(if set { SET } else { 0 }))
    }
}

macro_rules! binary {
    ($trait:ident, $fn:ident, $op:tt) => {
        impl $trait for F64x1 {
            type Output = Self;
            #[inline(always)]
            fn $fn(self, o: Self) -> Self {
                Self(self.0 $op o.0)
            }
        }
    };
}

binary!(Add, add, +);
binary!(Sub, sub, -);
binary!(Mul, mul, *);
binary!(Div, div, /);

impl Neg for F64x1 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self(-self.0)
    }
}

impl BitAnd for F64x1 {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        Self(f64::from_bits(self.0.to_bits() & o.0.to_bits()))
    }
}

impl BitOr for F64x1 {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, o: Self) -> Self {
        Self(f64::from_bits(self.0.to_bits() | o.0.to_bits()))
    }
}

impl Lanes for F64x1 {
    const WIDTH: usize = 1;
    const EXACT_DIFFERENCES: bool = true;
    type Index = u32;

    #[inline(always)]
    fn splat(x: f32) -> Self {
        Self(f64::from(x))
    }
    #[inline(always)]
    fn splat64(x: f64) -> Self {
        Self(x)
    }
    #[inline(always)]
    fn load8(col: &[f32; 8], lane: usize) -> Self {
        Self(f64::from(col[lane & 7]))
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        out[0] = self.0 as f32;
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Self(self.0.sqrt())
    }
    #[inline(always)]
    fn mul_add(self, m: Self, a: Self) -> Self {
        Self(self.0.mul_add(m.0, a.0))
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Self(self.0.abs())
    }
    /// The second operand where either is NaN, as `f64x4::fast_min` on x86.
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        if self.0 < o.0 { self } else { o }
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Self {
        Self::mask(self.0 < o.0)
    }
    #[inline(always)]
    fn le(self, o: Self) -> Self {
        Self::mask(self.0 <= o.0)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> Self {
        Self::mask(self.0 > o.0)
    }
    #[inline(always)]
    fn ge(self, o: Self) -> Self {
        Self::mask(self.0 >= o.0)
    }
    #[inline(always)]
    fn select(mask: Self, t: Self, f: Self) -> Self {
        if mask.any() { t } else { f }
    }
    #[inline(always)]
    fn eq(self, o: Self) -> Self {
        Self::mask(self.0 == o.0)
    }
    /// Whether the mask is set (its sign bit, as `movmskpd` reads a wide mask).
    #[inline(always)]
    fn any(self) -> bool {
        self.0.is_sign_negative()
    }
    #[inline(always)]
    fn bits(self) -> u32 {
        u32::from(self.any())
    }
    #[inline(always)]
    fn halves(self) -> [f64x4; 2] {
        [f64x4::splat(self.0); 2]
    }
    #[inline(always)]
    fn from_halves(h: [f64x4; 2]) -> Self {
        Self(h[0].to_array()[0])
    }
    #[inline(always)]
    fn index_splat(j: u32) -> u32 {
        j
    }
    #[inline(always)]
    fn index_select(mask: Self, t: u32, f: u32) -> u32 {
        if mask.any() { t } else { f }
    }
    #[inline(always)]
    fn index_store(i: u32, out: &mut [u32]) {
        out[0] = i;
    }
}
