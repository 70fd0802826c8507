//! The lane layer: the SIMD vector types the kernels are generic over, `f32x8` (eight pairs)
//! and `f64x4` (four), and 3-vector helpers on them. It knows no shape. Masks are lanes with
//! all bits set or clear, as `wide` produces them; integer index lanes ride beside the float
//! lanes (`u32x8`, `u64x4`), so an index is never rounded.

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Sub};
use wide::{f32x8, f64x4, u32x8, u64x4};

/// A SIMD vector of floats with the few operations the kernels use.
pub trait Lanes:
    Copy
    + Send
    + Sync
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
{
    /// How many pairs one vector holds.
    const WIDTH: usize;
    /// Whether differences of f32 inputs are exact in these lanes (f64).
    const EXACT_DIFFERENCES: bool;
    /// Every lane set to `x`.
    fn splat(x: f32) -> Self;
    /// Every lane set to `x`, rounded to the lane precision (for values prepared in f64).
    fn splat64(x: f64) -> Self;
    /// Lanes from a block column of eight, starting at `lane` (`0` for eight-wide lanes,
    /// `0` or `4` for four-wide): constant offsets, no bounds check.
    fn load8(col: &[f32; 8], lane: usize) -> Self;
    /// Writes the lanes, rounded to f32, to the first `WIDTH` slots of `out`.
    fn store(self, out: &mut [f32]);
    /// Square root.
    fn sqrt(self) -> Self;
    /// `self · m + a`, fused where the target has FMA (x86-64-v3 does).
    fn mul_add(self, m: Self, a: Self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Lane-wise minimum (x86 semantics: the second operand where either is NaN; callers
    /// catch NaN with an ordered compare).
    fn min(self, o: Self) -> Self;
    /// Mask of `self < o` (false for NaN).
    fn lt(self, o: Self) -> Self;
    /// Mask of `self ≤ o` (false for NaN).
    fn le(self, o: Self) -> Self;
    /// Mask of `self > o` (false for NaN).
    fn gt(self, o: Self) -> Self;
    /// Mask of `self ≥ o` (false for NaN).
    fn ge(self, o: Self) -> Self;
    /// `if mask { t } else { f }` lane by lane.
    fn select(mask: Self, t: Self, f: Self) -> Self;
    /// Mask of `self == o` (false for NaN).
    fn eq(self, o: Self) -> Self;
    /// Whether any lane of the mask is set.
    fn any(self) -> bool;
    /// The mask's lanes as bits, lane `k` in bit `k`.
    fn bits(self) -> u32;
    /// The lanes widened exactly to f64, four at a time (`[lo, hi]`; an `f64x4` gives itself
    /// twice).
    fn halves(self) -> [f64x4; 2];
    /// Lanes from f64 halves, rounded once to the lane precision (the inverse of
    /// [`halves`](Lanes::halves)).
    fn from_halves(h: [f64x4; 2]) -> Self;
    /// Integer lanes as wide as the float lanes, for indices.
    type Index: Copy + Send + Sync;
    /// Every index lane set to `j`.
    fn index_splat(j: u32) -> Self::Index;
    /// `if mask { t } else { f }` on index lanes, with a float-lane mask.
    fn index_select(mask: Self, t: Self::Index, f: Self::Index) -> Self::Index;
    /// The index lanes, to the first `WIDTH` slots of `out`.
    fn index_store(i: Self::Index, out: &mut [u32]);
}

macro_rules! impl_lanes {
    ($t:ty, $width:expr, $exact:expr, $scalar:ty, $index:ty, $iscalar:ty) => {
        impl Lanes for $t {
            type Index = $index;
            const WIDTH: usize = $width;
            const EXACT_DIFFERENCES: bool = $exact;
            #[inline(always)]
            fn splat(x: f32) -> Self {
                <$t>::splat(x as $scalar)
            }
            #[inline(always)]
            fn splat64(x: f64) -> Self {
                <$t>::splat(x as $scalar)
            }
            #[inline(always)]
            fn load8(col: &[f32; 8], lane: usize) -> Self {
                // `lane & (8 − WIDTH)` is 0 for eight lanes and 0 or 4 for four: in range.
                let start = lane & (8 - $width);
                <$t>::new(std::array::from_fn(|k| col[start + k] as $scalar))
            }
            #[inline(always)]
            fn store(self, out: &mut [f32]) {
                let lanes = self.to_array().map(|x| x as f32);
                out[..$width].copy_from_slice(&lanes);
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                <$t>::sqrt(self)
            }
            #[inline(always)]
            fn mul_add(self, m: Self, a: Self) -> Self {
                <$t>::mul_add(self, m, a)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn min(self, o: Self) -> Self {
                <$t>::fast_min(self, o)
            }
            #[inline(always)]
            fn lt(self, o: Self) -> Self {
                self.simd_lt(o)
            }
            #[inline(always)]
            fn le(self, o: Self) -> Self {
                self.simd_le(o)
            }
            #[inline(always)]
            fn gt(self, o: Self) -> Self {
                self.simd_gt(o)
            }
            #[inline(always)]
            fn ge(self, o: Self) -> Self {
                self.simd_ge(o)
            }
            #[inline(always)]
            fn select(mask: Self, t: Self, f: Self) -> Self {
                mask.select(t, f)
            }
            #[inline(always)]
            fn eq(self, o: Self) -> Self {
                self.simd_eq(o)
            }
            #[inline(always)]
            fn any(self) -> bool {
                <$t>::any(self)
            }
            #[inline(always)]
            fn bits(self) -> u32 {
                self.to_bitmask() as u32
            }
            #[inline(always)]
            fn halves(self) -> [f64x4; 2] {
                let x = self.to_array();
                let w = $width;
                [
                    f64x4::new(std::array::from_fn(|k| f64::from(x[k % w]))),
                    f64x4::new(std::array::from_fn(|k| f64::from(x[(4 + k) % w]))),
                ]
            }
            #[inline(always)]
            fn from_halves(h: [f64x4; 2]) -> Self {
                let (lo, hi) = (h[0].to_array(), h[1].to_array());
                <$t>::new(std::array::from_fn(|k| {
                    (if k < 4 { lo[k] } else { hi[k - 4] }) as $scalar
                }))
            }
            #[inline(always)]
            fn index_splat(j: u32) -> $index {
                <$index>::splat(j as $iscalar)
            }
            #[inline(always)]
            fn index_select(mask: Self, t: $index, f: $index) -> $index {
                mask.select(t, f)
            }
            #[inline(always)]
            fn index_store(i: $index, out: &mut [u32]) {
                for (slot, j) in out[..$width].iter_mut().zip(i.to_array()) {
                    // Indices are splatted from u32: the narrowing is exact.
                    *slot = j as u32;
                }
            }
        }
    };
}

impl_lanes!(f32x8, 8, false, f32, u32x8, u32);
impl_lanes!(f64x4, 4, true, f64, u64x4, u64);

/// A 3-vector of lanes: eight (or four) vectors at once.
pub type V3<L> = [L; 3];

/// `a · b`, literally: three products and two sums, each rounded.
#[inline(always)]
pub fn dot<L: Lanes>(a: V3<L>, b: V3<L>) -> L {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a · b` with fused multiply-adds: one rounding fewer per term.
#[inline(always)]
pub fn dot_fused<L: Lanes>(a: V3<L>, b: V3<L>) -> L {
    a[0].mul_add(b[0], a[1].mul_add(b[1], a[2] * b[2]))
}

/// `a − b` lane by lane.
#[inline(always)]
pub fn sub<L: Lanes>(a: V3<L>, b: V3<L>) -> V3<L> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a × b`, literally.
#[inline(always)]
pub fn cross<L: Lanes>(a: V3<L>, b: V3<L>) -> V3<L> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The part of `x` perpendicular to the unit vector `s`, `x − (x·s) s`, with fused
/// multiply-adds.
#[inline(always)]
pub fn reject_fused<L: Lanes>(x: V3<L>, s: V3<L>) -> V3<L> {
    let k = -dot_fused(x, s);
    [
        k.mul_add(s[0], x[0]),
        k.mul_add(s[1], x[1]),
        k.mul_add(s[2], x[2]),
    ]
}

/// `a × b` with one fused multiply-add per component.
#[inline(always)]
pub fn cross_fused<L: Lanes>(a: V3<L>, b: V3<L>) -> V3<L> {
    [
        a[1].mul_add(b[2], -(a[2] * b[1])),
        a[2].mul_add(b[0], -(a[0] * b[2])),
        a[0].mul_add(b[1], -(a[1] * b[0])),
    ]
}

/// `(p, e)` with `p = a·b` rounded and `a·b = p + e` exactly (one FMA; x86-64-v3 has it).
#[inline(always)]
fn two_product<L: Lanes>(a: L, b: L) -> (L, L) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `(s, e)` with `s = a + b` rounded and `a + b = s + e` exactly (Knuth's TwoSum: no
/// ordering of `|a|`, `|b|` needed).
#[inline(always)]
fn two_sum<L: Lanes>(a: L, b: L) -> (L, L) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `x·(n_hi + n_lo) − (d_hi + d_lo)` as if computed in twice the lane precision, then rounded
/// once more: Ogita, Rump & Oishi's Dot2 with FMA products. The error is at most about
/// `u |result| + 3u² (|x||n| + |d|)`, so a small distance measured from far-off coordinates
/// keeps its digits (docs/derivations/accuracy.md, "Compensated offsets").
#[inline(always)]
pub fn dot_minus_compensated<L: Lanes>(x: V3<L>, n_hi: V3<L>, n_lo: V3<L>, d_hi: L, d_lo: L) -> L {
    let (p0, e0) = two_product(x[0], n_hi[0]);
    let (p1, e1) = two_product(x[1], n_hi[1]);
    let (p2, e2) = two_product(x[2], n_hi[2]);
    let (s, t0) = two_sum(p0, p1);
    let (s, t1) = two_sum(s, p2);
    let (s, t2) = two_sum(s, -d_hi);
    let small = dot_fused(x, n_lo) - d_lo;
    s + (((e0 + e1) + (e2 + t0)) + ((t1 + t2) + small))
}
