//! The lane-group driver every batch entry point runs through: one mode dispatch per call,
//! lane groups in order, fixed parallel chunks above [`PARALLEL_MIN`] items so that results
//! do not depend on the thread count.

use rayon::prelude::*;

use crate::lanes::Lanes;

/// Query items per batch from which the work runs in parallel.
pub const PARALLEL_MIN: usize = 1 << 15;
/// Query items per parallel task (a multiple of eight).
const CHUNK: usize = 1 << 12;

/// Runs `$f::<Lanes, Solver>(args)` for the accuracy mode: one dispatch per batch.
macro_rules! with_mode {
    ($accuracy:expr, $f:ident$(::<$($g:ty),*>)?($($arg:expr),* $(,)?)) => {
        match $accuracy {
            $crate::Accuracy::Textbook => {
                $f::<wide::f32x8, $crate::kernels::quadratic::Textbook $($(, $g)*)?>($($arg),*)
            }
            $crate::Accuracy::Stable => {
                $f::<wide::f32x8, $crate::kernels::quadratic::Stable $($(, $g)*)?>($($arg),*)
            }
            $crate::Accuracy::Double => {
                $f::<wide::f64x4, $crate::kernels::quadratic::Stable $($(, $g)*)?>($($arg),*)
            }
        }
    };
}
pub(crate) use with_mode;

/// One lane group of a batch: it writes the results for items `i .. i + out.len()`
/// (`i` a multiple of `WIDTH`, `out.len() ≤ WIDTH`, shorter only at the tail). A trait rather
/// than a closure so that `#[inline(always)]` puts the whole kernel inside the driver's loop.
pub(crate) trait LaneKernel: Sync {
    /// One result per query item.
    type Item: Copy + Send;
    /// Items per lane group.
    const WIDTH: usize;
    fn write(&self, i: usize, out: &mut [Self::Item]);
}

/// Stores the first `out.len()` lanes of `t` (all of them but at the tail).
#[inline(always)]
pub(crate) fn store_lanes<L: Lanes>(t: L, out: &mut [f32]) {
    if out.len() == L::WIDTH {
        t.store(out);
    } else {
        let mut tail = [0.0f32; 8];
        t.store(&mut tail);
        out.copy_from_slice(&tail[..out.len()]);
    }
}

/// Fills `out` lane group by lane group, in parallel chunks above [`PARALLEL_MIN`].
#[inline(always)]
pub(crate) fn fill<K: LaneKernel>(out: &mut [K::Item], kernel: &K) {
    if out.len() >= PARALLEL_MIN {
        out.par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(k, chunk)| fill_range(k * CHUNK, chunk, kernel));
    } else {
        fill_range(0, out, kernel);
    }
}

#[inline(always)]
fn fill_range<K: LaneKernel>(offset: usize, out: &mut [K::Item], kernel: &K) {
    // Exact chunks: full groups have a length known at compile time, so `store_lanes`'
    // tail check folds away in the hot loop; only the remainder takes the tail path.
    let mut parts = out.chunks_exact_mut(K::WIDTH);
    let mut i = offset;
    for part in &mut parts {
        kernel.write(i, part);
        i += K::WIDTH;
    }
    let rest = parts.into_remainder();
    if !rest.is_empty() {
        kernel.write(i, rest);
    }
}
