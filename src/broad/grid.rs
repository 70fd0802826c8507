//! Uniform-grid broad phase over the swept boxes of moving spheres.
//!
//! Sphere `i` moves as `c + v t` for `t` in `[0, t_max]`; its *swept box* is, per axis,
//! `lo = min(c, c + v t_max) - r`, `hi = max(c, c + v t_max) + r` (see [`swept_box`], the
//! exact definition). Two spheres are a *candidate pair* iff their swept boxes overlap as
//! closed intervals on all three axes. [`Grid::build`] finds every candidate pair exactly once.
//!
//! # Algorithm
//!
//! 1. **Statistics pass** (8 spheres per step with `f32x8`): a histogram of each box's largest
//!    extent over 512 buckets (the float's exponent and top mantissa bit). Each bucket keeps,
//!    in one `f32x8`, its count, its exact maximum extent and the bounding box of its spheres'
//!    `lo` corners.
//! 2. **Cell size** `s`, unless given in [`GridOptions::cell_size`]. The candidates are, for
//!    each bucket `b`, the largest extent among the spheres in buckets `<= b`. The rule picks
//!    the candidate minimising the estimated box tests per sphere,
//!    `13.5 * N / cells(s) + K(s)`: the half stencil scans 13.5 cells' worth of spheres, and
//!    each of the `K(s)` spheres with a larger extent is tested against all `N`. `cells(s)`
//!    is counted over the bounding box of the spheres that fit, capped as in step 3. So a few
//!    outliers (one giant, a fat tail) go to the oversize list instead of blowing up the
//!    cells, while a broad size distribution keeps cells big enough for almost all spheres.
//!    `s` gets a `2^-16` relative margin.
//! 3. **Grid bounds and cell cap**: the grid spans the bounding box of the `lo` corners of the
//!    spheres whose extent is `<= s` (known per bucket, so no extra pass for the automatic
//!    rule), plus one padding cell on every side. If that needs more than `2 N + 1024` cells
//!    (sparse, flat or elongated scenes, such as spheres in a line), `s` is grown until it
//!    fits. Memory is therefore `O(N)` whatever the coordinates. If that grew `s` more than
//!    twofold, a few far-away spheres may be the cause. An extra pass then finds, per axis,
//!    the bounds without the `64 + N/4096` most extreme `lo` corners on each side. With these
//!    bounds, the cell size is chosen again and fitted again, and kept if smaller. The
//!    spheres outside are clamped into the border cells, as the proof below allows.
//!    If `s` still grew more than twofold and the dense cell counts (step 5) then show
//!    crowded cells, with more than 32 spheres on average in a sphere's cell (dense clusters
//!    far apart), the build switches to the [`Layout::Sparse`] layout. That layout keeps the
//!    chosen `s` over the full bounds, with at most `2^21 - 2` cells per axis, and stores only
//!    occupied cells, so its memory is `O(N)` too. A line or a thin sheet of spheres stays
//!    dense: there, larger cells hold only a few more spheres.
//! 4. **Keys**: sphere `i` goes to the cell holding its box's `lo` corner, `f(lo)` per axis,
//!    where `f(x) = clamp(floor((x - origin) / s), 0, cells - 1)`. It is *oversize* iff its box
//!    touches more than two cells on some axis, `f(hi) > f(lo) + 1`: never for a box no wider
//!    than `s` (up to rounding), always for one wider than `2s` unless clamping into a border
//!    cell keeps it within two cells, and sometimes in between; the proof below rests on this
//!    definition alone. Oversize spheres get the key one past the
//!    last cell. Unless the store is in grid order (see below), the boxes are kept as 32-byte
//!    records.
//! 5. **Sort**, iterating the previous build's `order`. The keys are first gathered into that
//!    order. Dense layout: a counting sort (`O(N + cells)`): count, prefix sums, scatter the
//!    indices. For a scene that moved a little, every one of these steps is nearly
//!    sequential. Sparse layout: an LSD radix sort of the 64-bit keys on 11-bit digits (only
//!    the digits in use), then the list of occupied cells. For each cell, each neighbour
//!    row's cells have the cell's key plus a constant offset, so a merge of the sorted list
//!    with itself, one forward pointer per offset, finds each row's range. Finally the boxes
//!    are gathered by position into sorted SoA columns (`lo`/`hi` `x`/`y`/`z`), with
//!    independent loads, so an unsorted store keeps many cache misses in flight. If the
//!    previous build found at least half the positions in runs of 8 consecutive indices (the
//!    caller keeps its store in grid order), or after [`Grid::reset_order`], the boxes are
//!    instead recomputed from the columns, 8 at a time along such runs. This saves the records'
//!    memory traffic. Oversize spheres come last in `order`.
//! 6. **Pairs**: each sphere is tested against the rest of its cell and the 13 "forward"
//!    neighbours of the 26, 8 boxes at a time (`f32x8` compares to a bitmask). `x` is the
//!    fastest axis, so those are five contiguous position ranges: the own cell after the
//!    sphere plus the cell at `x+1`, and the three-cell rows `(y+1, z)`, `(y-1, z+1)`,
//!    `(y, z+1)` and `(y+1, z+1)`. The padding layer means these always exist, and the only
//!    branches are the range bounds. (The sparse layout reads them from its per-cell table.) Tests that the cell order already decides are dropped: a
//!    box in row `y+1` has `lo.y > a.lo.y`, so `a.lo.y <= hi.y` holds, and likewise for
//!    `y-1` and `z+1`. Hits are written branch-free: a 256-entry table turns the bitmask into
//!    up to four packed pairs, with one 32-byte store. Two consecutive spheres whose cells are
//!    equal or (dense layout) `x`-neighbours share their five ranges (each widened by that one cell, whose
//!    boxes cannot overlap the other sphere), so every window of 8 boxes is loaded once for
//!    both. Each range gets one straight-line batch; the rare longer ranges finish in a
//!    separate loop. Finally each oversize sphere is tested against every sphere before it in
//!    `order`.
//!
//! # Why the stencil is correct
//!
//! `f` is monotone (non-decreasing) whatever the rounding and clamping, and a non-oversize box
//! `b` has `f(hi_b) <= f(lo_b) + 1`. If boxes `a` and `b` overlap on an axis, then
//! `lo_a <= hi_b`, so `f(lo_a) <= f(hi_b) <= f(lo_b) + 1`, and symmetrically. Their cells
//! therefore differ by at most one on every axis. So every candidate pair lies within a cell
//! and its 26 neighbours. The half stencil (the neighbours with a larger linear cell index)
//! visits each such pair of cells once, and within a cell only later positions are tested.
//! Every pair is therefore reported exactly once, as positions `[p, q]` with `p < q`.
//!
//! # Parallelism and determinism
//!
//! From [`PAR_MIN`] spheres on, these parts run on rayon:
//! - the statistics pass, the key pass and the gathers, in fixed chunks of spheres;
//! - the pair phase, in fixed chunks of sorted positions. Each chunk writes its own pair
//!   buffer, and the buffers are concatenated in chunk order.
//!
//! `order()` and `pairs()` are therefore identical for any thread count, and identical to the
//! sequential path. The counting and the index scatter are sequential.
//!
//! # Cost
//!
//! A uniform gas at packing fraction 0.3 with a window of half a radius of travel has about
//! 1.1 spheres per cell. That is about 15 candidate boxes per sphere, in five 8-wide batches
//! (shared by two spheres when possible). The cost is per batch, not per candidate: a whole
//! build runs about 330 instructions per sphere, 260 of them in the pair phase. At
//! `N = 10^6` the build also streams about 300 bytes per sphere through memory.

use rayon::prelude::*;

use crate::store::{SphereBlock, SphereStore};
use wide::{f32x8, i32x8, u32x8};

/// From this many spheres on, [`Grid::build`] runs its passes on rayon (when its pool has more
/// than one thread).
pub const PAR_MIN: usize = 16384;

/// Spheres per chunk in the statistics and key passes.
const SPHERE_CHUNK: usize = 16384;
/// Sorted positions per chunk in the pair phase.
const PAIR_CHUNK: usize = 4096;
/// Positions per chunk when an oversize sphere is tested against all earlier ones.
const OVER_CHUNK: usize = 65536;
/// Buckets of the extent histogram: the float's bits shifted right by [`HSHIFT`] (exponent and
/// one mantissa bit).
const NB: usize = 512;
const HSHIFT: u32 = 22;
/// An empty histogram record: `[count, max extent, -lo_min xyz, lo_max xyz]`.
const EMPTY: [f32; 8] = [
    0.0,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
];
/// Adds one to a record's count lane.
const COUNT1: [f32; 8] = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
/// Smallest cell size; keeps `1 / s` finite.
const MIN_CELL: f32 = 1e-30;
/// Relative margin added to the automatic cell size so a box of exactly that extent does not
/// touch three cells through rounding.
const MARGIN: f32 = 1.0 + 1.0 / 65536.0;
/// Largest number of spheres (keys and positions must fit `u32`/`i32` with room for cells).
const MAX_N: usize = (1 << 30) - 1024;

/// The spheres as the grid reads them: the store's blocks of eight (AoSoA) and the count.
///
/// All values are finite and radii non-negative (the store validated them); sphere `i` is lane
/// `i % 8` of block `i / 8`.
#[derive(Clone, Copy, Debug)]
pub struct Columns<'a> {
    blocks: &'a [SphereBlock],
    n: usize,
}

impl<'a> Columns<'a> {
    /// The spheres of `store`.
    pub fn of(store: &'a SphereStore) -> Self {
        Self {
            blocks: store.blocks(),
            n: store.len(),
        }
    }

    /// Number of spheres.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Centre, velocity and radius of sphere `i`.
    #[inline(always)]
    fn at(&self, i: usize) -> ([f32; 3], [f32; 3], f32) {
        let (b, l) = (&self.blocks[i / 8], i % 8);
        (
            [b.cx[l], b.cy[l], b.cz[l]],
            [b.vx[l], b.vy[l], b.vz[l]],
            b.r[l],
        )
    }
}

/// The swept box of sphere `i` over `[0, t_max]`, as `(lo, hi)`: per axis
/// `lo = min(c, c + v t_max) - r` and `hi = max(c, c + v t_max) + r`.
///
/// This is the exact float computation [`Grid::build`] uses (no fused multiply-add), so a
/// brute-force reference built on it finds exactly the same candidate pairs.
#[cfg(test)]
pub fn swept_box(cols: &Columns<'_>, i: usize, t_max: f32) -> ([f32; 3], [f32; 3]) {
    let (c, v, r) = cols.at(i);
    let mut lo = [0.0; 3];
    let mut hi = [0.0; 3];
    for a in 0..3 {
        let e = c[a] + v[a] * t_max;
        lo[a] = c[a].min(e) - r;
        hi[a] = c[a].max(e) + r;
    }
    (lo, hi)
}

/// Options for [`Grid::build`](crate::broad::Grid::build).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GridOptions {
    /// Cell edge length. `None` picks it automatically (see [`crate::broad`]: the
    /// largest box extent that minimises estimated box tests, with outliers going to the
    /// oversize list). `Some(s)` must be finite and `> 0`; spheres whose box is larger become
    /// oversize. Either way the cell cap (`2 N + 1024` cells) may grow it.
    pub cell_size: Option<f32>,
    /// Dense cell table or sparse cells; [`Layout::Auto`] picks (see [`Layout`]).
    pub layout: Layout,
}

/// How [`Grid::build`](crate::broad::Grid::build) indexes its cells.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Layout {
    /// Dense, except when the cell cap grew the cells more than twofold (even after trimming
    /// far-away spheres) *and* the dense counts then show crowded cells: on average more than
    /// 32 spheres share a sphere's cell. That happens with dense clusters far apart. A
    /// following build of the same size that still needs the cap goes sparse directly.
    #[default]
    Auto,
    /// A dense table over the bounding box, capped at `2 N + 1024` cells.
    Dense,
    /// Only the occupied cells: spheres are radix-sorted by a 64-bit cell key, and each
    /// occupied cell's neighbour rows are found by merging the sorted cell list with itself
    /// shifted by each row's key offset. The cell size is not capped (up to `2^21 - 2` cells
    /// per axis); there are at most `N` cells. Costs a few passes more than dense.
    Sparse,
}

/// One sphere's box and key, as written by the key pass and read by the scatter.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct Rec([f32; 8]);

/// Statistics of a chunk of spheres: for each extent bucket the record
/// `[count, max extent, -lo_min x y z, lo_max x y z]` of the spheres in it (so that merging is
/// a lane-wise max, plus a sum in the count lane).
#[derive(Clone)]
struct Stats {
    hist: Box<[f32x8; NB]>,
}

impl Stats {
    fn new() -> Self {
        Stats {
            hist: Box::new([f32x8::from(EMPTY); NB]),
        }
    }
}

/// Merge two histogram records.
#[inline(always)]
fn merge_rec(a: f32x8, b: f32x8) -> f32x8 {
    let c = a.as_array()[0] + b.as_array()[0];
    let mut m = a.fast_max(b).to_array();
    m[0] = c;
    f32x8::from(m)
}

fn merge_bbox(mn: &mut [f32; 3], mx: &mut [f32; 3], omn: &[f32; 3], omx: &[f32; 3]) {
    for a in 0..3 {
        mn[a] = mn[a].min(omn[a]);
        mx[a] = mx[a].max(omx[a]);
    }
}

/// A unit of pair-phase work: grid positions `start..end` (when `q == u32::MAX`), or
/// oversize position `q` against positions `start..end`.
#[derive(Clone, Copy)]
struct Item {
    q: u32,
    start: u32,
    end: u32,
}

/// The grid mapping used by the key pass.
#[derive(Clone, Copy)]
struct Geom {
    origin: [f32; 3],
    inv: f32,
    limf: [f32; 3],
    limi: [i32; 3],
    px: i32,
    pxy: i32,
    /// `px * py` for sparse keys.
    pxy_wide: u64,
    over_key: i32,
}

impl Geom {
    /// The mapping for a grid at `origin` with cells of size `s`, `dims` per axis (plus
    /// padding).
    fn new(origin: [f32; 3], s: f32, dims: [u32; 3]) -> Geom {
        let (px, py, pz) = (
            dims[0] as usize + 2,
            dims[1] as usize + 2,
            dims[2] as usize + 2,
        );
        Geom {
            origin,
            inv: 1.0 / s,
            limf: dims.map(|d| (d - 1) as f32),
            limi: dims.map(|d| (d - 1) as i32),
            px: px as i32,
            pxy: (px * py) as i32,
            pxy_wide: (px * py) as u64,
            // One past the last cell: the oversize bucket (dense layout only).
            over_key: px
                .saturating_mul(py)
                .saturating_mul(pz)
                .min(i32::MAX as usize) as i32,
        }
    }
}

/// Cell keys: `(x+1) + px ((y+1) + py (z+1))` over the padded grid, as dense table indices
/// (`u32`, oversize `over_key`) or sparse-layout keys (`u64`, oversize `u64::MAX`).
trait Key: Copy + Default + Send + Sync {
    fn make(gl: &[i32x8; 3], over: i32x8, g: &Geom) -> [Self; 8];
}

impl Key for u32 {
    #[inline(always)]
    fn make(gl: &[i32x8; 3], over: i32x8, g: &Geom) -> [u32; 8] {
        let one = i32x8::splat(1);
        let key = (gl[0] + one)
            + i32x8::splat(g.px) * (gl[1] + one)
            + i32x8::splat(g.pxy) * (gl[2] + one);
        over.select(i32x8::splat(g.over_key), key)
            .cast_unsigned()
            .to_array()
    }
}

impl Key for u64 {
    #[inline(always)]
    fn make(gl: &[i32x8; 3], over: i32x8, g: &Geom) -> [u64; 8] {
        let (x, y, z, o) = (
            gl[0].to_array(),
            gl[1].to_array(),
            gl[2].to_array(),
            over.to_array(),
        );
        let (px, pxy) = (g.px as u64, g.pxy_wide);
        std::array::from_fn(|l| {
            if o[l] != 0 {
                u64::MAX
            } else {
                (x[l] as u64 + 1) + px * (y[l] as u64 + 1) + pxy * (z[l] as u64 + 1)
            }
        })
    }
}

/// Largest cells per axis of the sparse layout (so that keys fit 63 bits).
const HMAX: u32 = (1 << 21) - 2;
/// Mean number of spheres sharing a sphere's cell past which [`Layout::Auto`] switches a
/// capped dense grid to the sparse layout.
const CROWDED: f64 = 32.0;
/// Bits per digit of the sparse layout's radix sort.
const RADIX_BITS: u32 = 11;

/// Reusable uniform-grid broad phase. See the [module docs](self) for the algorithm.
///
/// All buffers are kept between builds and only grow, so rebuilding a scene of the same size
/// does not allocate. The previous [`order`](Grid::order) is kept too and used to scatter the
/// next build coherently.
#[derive(Default)]
pub struct Grid {
    order: Vec<u32>,
    order_tmp: Vec<u32>,
    pairs: Vec<[u32; 2]>,
    npairs: usize,
    recs: Vec<Rec>,
    keys: Vec<u32>,
    kk: Vec<u32>,
    skey: Vec<u32>,
    boxes: [Vec<f32>; 6],
    cs: Vec<u32>,
    stats: Vec<Stats>,
    bbox_parts: Vec<([f32; 3], [f32; 3])>,
    items: Vec<Item>,
    outs: Vec<(Vec<[u32; 2]>, usize)>,
    cell_size: f32,
    dims: [u32; 3],
    n_grid: usize,
    /// Whether the last build found the store in (nearly) grid order; the next build then
    /// skips the box records.
    coherent: bool,
    /// Sparse layout: whether the last build used it, per-sphere keys, their sort buffers,
    /// occupied cells (keys, first positions), per-cell ranges, radix counts.
    sparse: bool,
    sparse_n: usize,
    vkeys: Vec<u64>,
    vkk: Vec<u64>,
    vtmp: Vec<u64>,
    itmp: Vec<u32>,
    ckey: Vec<u64>,
    cstart: Vec<u32>,
    hrows: Vec<[u32; 9]>,
    radix: Vec<u32>,
    /// Heaps for [`trimmed_bounds`](Grid::trimmed_bounds).
    trim_lo: [std::collections::BinaryHeap<u32>; 3],
    trim_hi: [std::collections::BinaryHeap<std::cmp::Reverse<u32>>; 3],
}

impl Grid {
    /// Sphere indices sorted by cell (cells in `x`-fastest order), oversize spheres last.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Every candidate pair exactly once, as positions `[p, q]` in [`order`](Grid::order) with
    /// `p < q`. The grid pairs come first, roughly in increasing `p`, then the oversize
    /// spheres' pairs. The order is deterministic and does not depend on the thread count.
    pub fn pairs(&self) -> &[[u32; 2]] {
        &self.pairs[..self.npairs]
    }

    /// The cell edge length used by the last build (`0` for an empty build).
    pub fn cell_size(&self) -> f32 {
        self.cell_size
    }

    /// Cells per axis of the last build, without the padding layer (for the sparse layout, of
    /// the virtual grid).
    pub fn dims(&self) -> [u32; 3] {
        self.dims
    }

    /// Number of cells: for the dense layout including the one-cell padding on every side
    /// (the size of the cell table, at most `2 N + 1024`); for the sparse layout the occupied
    /// cells (at most `N`).
    pub fn cells(&self) -> usize {
        if self.order.is_empty() {
            0
        } else if self.sparse {
            self.ckey.len()
        } else {
            self.dims.iter().map(|&d| d as usize + 2).product()
        }
    }

    /// Whether the last build used the sparse layout (see [`Layout`]).
    pub fn sparse(&self) -> bool {
        self.sparse
    }

    /// Number of oversize spheres in the last build; they are the last entries of `order()`.
    pub fn oversize(&self) -> usize {
        self.order.len() - self.n_grid
    }

    /// Heap bytes held by the grid's buffers (capacities, not lengths).
    pub fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        let mut b = (self.order.capacity() + self.order_tmp.capacity()) * 4
            + self.pairs.capacity() * 8
            + self.recs.capacity() * size_of::<Rec>()
            + (self.keys.capacity()
                + self.kk.capacity()
                + self.skey.capacity()
                + self.cs.capacity())
                * 4
            + self.stats.capacity() * size_of::<Stats>()
            + self.stats.len() * size_of::<[f32x8; NB]>()
            + self.bbox_parts.capacity() * size_of::<([f32; 3], [f32; 3])>()
            + self.items.capacity() * size_of::<Item>()
            + self.outs.capacity() * size_of::<(Vec<[u32; 2]>, usize)>()
            + (self.vkeys.capacity()
                + self.vkk.capacity()
                + self.vtmp.capacity()
                + self.ckey.capacity())
                * 8
            + (self.itmp.capacity() + self.cstart.capacity() + self.radix.capacity()) * 4
            + self.hrows.capacity() * size_of::<[u32; 9]>()
            + self.trim_lo.iter().map(|h| h.capacity() * 4).sum::<usize>()
            + self.trim_hi.iter().map(|h| h.capacity() * 4).sum::<usize>();
        b += self.boxes.iter().map(|v| v.capacity() * 4).sum::<usize>();
        b += self.outs.iter().map(|o| o.0.capacity() * 8).sum::<usize>();
        b
    }

    /// Forget the previous order: the next build scatters in index order and takes the store
    /// to be in (nearly) grid order, so it recomputes the sorted boxes from the columns
    /// instead of writing box records. Call this after permuting your sphere store into
    /// [`order`](Grid::order). Results never depend on it, only speed.
    pub fn reset_order(&mut self) {
        self.order.clear();
        self.coherent = true;
    }

    /// Per axis, the `(trim + 1)`-th smallest and largest `lo` corner of the boxes.
    fn trimmed_bounds(
        &mut self,
        cols: &Columns<'_>,
        t_max: f32,
        trim: usize,
    ) -> ([f32; 3], [f32; 3]) {
        use std::cmp::Reverse;
        // Max-heaps of the smallest values (as ordered bits) and min-heaps of the largest.
        let (lows, highs) = (&mut self.trim_lo, &mut self.trim_hi);
        for h in lows.iter_mut() {
            h.clear();
        }
        for h in highs.iter_mut() {
            h.clear();
        }
        let n = cols.len();
        let t = f32x8::splat(t_max);
        let mut i = 0;
        while i < n {
            let (lo, _) = boxes8(cols, i, t);
            for a in 0..3 {
                let v = lo[a].to_array();
                for &x in &v[..(n - i).min(8)] {
                    let o = ord_bits(x);
                    if lows[a].len() <= trim {
                        lows[a].push(o);
                    } else if o < *lows[a].peek().unwrap() {
                        lows[a].pop();
                        lows[a].push(o);
                    }
                    if highs[a].len() <= trim {
                        highs[a].push(Reverse(o));
                    } else if o > highs[a].peek().unwrap().0 {
                        highs[a].pop();
                        highs[a].push(Reverse(o));
                    }
                }
            }
            i += 8;
        }
        let mut mn = [f32::INFINITY; 3];
        let mut mx = [f32::NEG_INFINITY; 3];
        for a in 0..3 {
            if let (Some(&l), Some(&Reverse(h))) = (lows[a].peek(), highs[a].peek()) {
                (mn[a], mx[a]) = (from_ord_bits(l), from_ord_bits(h));
            }
        }
        if mn.iter().zip(&mx).any(|(l, h)| l > h) {
            return ([f32::MIN; 3], [f32::MAX; 3]);
        }
        (
            mn.map(|x| x.clamp(-f32::MAX, f32::MAX)),
            mx.map(|x| x.clamp(-f32::MAX, f32::MAX)),
        )
    }

    /// Counting sort of the dense keys in the previous order (module docs, step 5), first part:
    /// the keys gathered into that order (`kk`) and counted (`cs`).
    fn dense_count(&mut self, n: usize, ncells: usize, par: bool) {
        // Counting sort, in the previous order. After it, cell k holds positions
        // cs[k]..cs[k+1]. The keys are first gathered into that order, so the counting and
        // the scatter of indices run on addresses known early (nearly sequential when the
        // scene moved little); the boxes are then gathered by position, with all loads
        // independent, which keeps many cache misses in flight for an unsorted store.
        self.kk.resize(n, 0);
        {
            let (keys, order) = (&self.keys[..n], &self.order[..n]);
            let work = |(kk, o): (&mut [u32], &[u32])| {
                for (k, &i) in kk.iter_mut().zip(o) {
                    *k = keys[i as usize];
                }
            };
            if par {
                self.kk[..n]
                    .par_chunks_mut(SPHERE_CHUNK)
                    .zip(order.par_chunks(SPHERE_CHUNK))
                    .for_each(work);
            } else {
                work((&mut self.kk[..n], order));
            }
        }
        let cs = &mut self.cs;
        cs.clear();
        cs.resize(ncells + 3, 0);
        for &k in &self.kk[..n] {
            cs[k as usize + 2] += 1;
        }
    }

    /// The rest of the counting sort after [`dense_count`](Self::dense_count): prefix sums
    /// and the scatter. Fills `order_tmp`, `skey` and `cs`; returns the number of grid
    /// (non-oversize) spheres.
    fn dense_scatter(&mut self, n: usize, ncells: usize) -> usize {
        let cs = &mut self.cs;
        let mut acc = 0u32;
        for c in cs.iter_mut() {
            acc += *c;
            *c = acc;
        }
        {
            let (ot, sk) = (&mut self.order_tmp[..n], &mut self.skey[..n]);
            for (&key, &i) in self.kk[..n].iter().zip(&self.order[..n]) {
                let slot = &mut cs[key as usize + 1];
                let pos = *slot as usize;
                *slot += 1;
                ot[pos] = i;
                sk[pos] = key;
            }
        }
        self.cs[ncells] as usize
    }

    /// Sort of the sparse-layout keys, in the previous order: LSD radix sort on 11-bit digits
    /// (only as many as the largest key needs, skipping digits all keys share). Then the list
    /// of occupied cells, and each cell's five position ranges. A neighbour row's key range is
    /// the cell's key plus a constant offset, so one forward-moving pointer per row offset
    /// finds them all. Fills `order_tmp`, `skey` (cell numbers) and `hrows`; returns the number
    /// of grid (non-oversize) spheres.
    fn sparse_sort(&mut self, n: usize, px: u64, pxy: u64) -> usize {
        let (vk, ix) = (&mut self.vkk, &mut self.order_tmp);
        vk.resize(n, 0);
        self.vtmp.resize(n, 0);
        self.itmp.resize(n, 0);
        for ((k, i), &o) in vk.iter_mut().zip(ix.iter_mut()).zip(&self.order[..n]) {
            *k = self.vkeys[o as usize];
            *i = o;
        }
        // Oversize keys (u64::MAX) sort last whatever the digits: map them to the largest
        // grid key + 1 for the sort.
        let (mut or, mut and, mut top) = (0u64, u64::MAX, 0u64);
        for &k in vk.iter() {
            if k != u64::MAX {
                top = top.max(k);
            }
        }
        let over = top + 1;
        for k in vk.iter_mut() {
            if *k == u64::MAX {
                *k = over;
            }
            or |= *k;
            and &= *k;
        }
        const NBK: usize = 1 << RADIX_BITS;
        self.radix.resize(NBK, 0);
        // Already sorted (a scene that did not change cells): nothing to do.
        let mut shift = if vk.windows(2).all(|w| w[0] <= w[1]) {
            64
        } else {
            0
        };
        while shift < 64 && (over >> shift) != 0 {
            if ((or ^ and) >> shift) & (NBK as u64 - 1) != 0 {
                let cnt = &mut self.radix;
                cnt.fill(0);
                for &k in vk.iter() {
                    cnt[(k >> shift) as usize & (NBK - 1)] += 1;
                }
                let mut acc = 0;
                for c in cnt.iter_mut() {
                    (*c, acc) = (acc, acc + *c);
                }
                let (vt, it) = (&mut self.vtmp[..n], &mut self.itmp[..n]);
                for (&k, &i) in vk.iter().zip(ix.iter()) {
                    let d = &mut cnt[(k >> shift) as usize & (NBK - 1)];
                    vt[*d as usize] = k;
                    it[*d as usize] = i;
                    *d += 1;
                }
                std::mem::swap(vk, &mut self.vtmp);
                std::mem::swap(ix, &mut self.itmp);
            }
            shift += RADIX_BITS;
        }
        // Occupied cells: keys and first positions (plus the end of the grid spheres).
        let (ckey, cstart) = (&mut self.ckey, &mut self.cstart);
        ckey.clear();
        cstart.clear();
        let mut n_grid = n;
        for (p, &k) in vk.iter().enumerate() {
            if k == over {
                n_grid = p;
                break;
            }
            if ckey.last() != Some(&k) {
                ckey.push(k);
                cstart.push(p as u32);
            }
            self.skey[p] = (ckey.len() - 1) as u32;
        }
        cstart.push(n_grid as u32);
        // Each cell's ranges: end of the own cell and of the cell at x+1, then the rows
        // (y+1, z), (y-1, z+1), (y, z+1), (y+1, z+1) over x-1..=x+1. Those are the cells with
        // keys in `key + d - 1 ..= key + d + 1` for the row's offset `d`: contiguous in the
        // sorted list, and moving forward as `key` does.
        let offsets = [px, pxy - px, pxy, pxy + px];
        let mut lo_ptr = [0usize; 4];
        let mut hi_ptr = [0usize; 4];
        let cells = ckey.len();
        let hrows = &mut self.hrows;
        hrows.clear();
        for (c, &k) in ckey.iter().enumerate() {
            let own_end = if ckey.get(c + 1) == Some(&(k + 1)) {
                cstart[c + 2]
            } else {
                cstart[c + 1]
            };
            let mut r = [own_end, 0, 0, 0, 0, 0, 0, 0, 0];
            for (j, &d) in offsets.iter().enumerate() {
                let (a, b) = (k + d - 1, k + d + 1);
                while lo_ptr[j] < cells && ckey[lo_ptr[j]] < a {
                    lo_ptr[j] += 1;
                }
                while hi_ptr[j] < cells && ckey[hi_ptr[j]] <= b {
                    hi_ptr[j] += 1;
                }
                // Cells lo_ptr..hi_ptr have keys in a..=b.
                if lo_ptr[j] < hi_ptr[j] {
                    r[1 + 2 * j] = cstart[lo_ptr[j]];
                    r[2 + 2 * j] = cstart[hi_ptr[j]];
                }
            }
            hrows.push(r);
        }
        n_grid
    }

    /// Rebuild for these spheres over the window `[0, t_max]`.
    ///
    /// Afterwards [`order`](Grid::order) holds the sphere indices sorted by cell and
    /// [`pairs`](Grid::pairs) every candidate pair exactly once as positions in `order()`.
    ///
    /// # Panics
    /// If the columns differ in length, `t_max` is not finite and `>= 0`, a given cell size is
    /// not finite and `> 0`, or there are more than about `2^30` spheres.
    pub fn build(&mut self, cols: Columns<'_>, t_max: f32, opts: GridOptions) {
        assert!(
            t_max.is_finite() && t_max >= 0.0,
            "t_max must be finite and >= 0, got {t_max}"
        );
        if let Some(s) = opts.cell_size {
            assert!(
                s.is_finite() && s > 0.0,
                "cell_size must be finite and > 0, got {s}"
            );
        }
        let n = cols.len();
        assert!(n <= MAX_N, "too many spheres: {n}");
        self.npairs = 0;
        if self.order.len() != n {
            if !self.order.is_empty() {
                self.coherent = false;
            }
            self.order.clear();
            self.order.extend(0..n as u32);
        }
        if n == 0 {
            self.n_grid = 0;
            self.cell_size = 0.0;
            self.dims = [0; 3];
            return;
        }
        // One thread: the sequential path, which gives the same result without the copies.
        let par = n >= PAR_MIN && rayon::current_num_threads() > 1;
        let cap = 2.0 * n as f64 + 1024.0;

        // 1. Statistics.
        let nch = n.div_ceil(SPHERE_CHUNK);
        if self.stats.len() < nch {
            self.stats.resize_with(nch, Stats::new);
        }
        let work = |(ci, st): (usize, &mut Stats)| {
            stats_chunk(
                &cols,
                t_max,
                ci * SPHERE_CHUNK,
                ((ci + 1) * SPHERE_CHUNK).min(n),
                st,
            )
        };
        if par {
            self.stats[..nch].par_iter_mut().enumerate().for_each(work);
        } else {
            self.stats[..nch].iter_mut().enumerate().for_each(work);
        }
        // Merge the chunks (counts in f64: a chunk's f32 count is exact, a total may not be),
        // and take prefix maxima over the buckets: `pre[b]` describes all spheres in buckets
        // `<= b`, i.e. all spheres whose extent is at most `pre[b]`'s max extent.
        let mut cnt = [0f64; NB];
        let mut pre = [f32x8::from(EMPTY); NB];
        for st in &self.stats[..nch] {
            for b in 0..NB {
                cnt[b] += st.hist[b].as_array()[0] as f64;
                pre[b] = pre[b].fast_max(st.hist[b]);
            }
        }
        for b in 1..NB {
            pre[b] = pre[b].fast_max(pre[b - 1]);
        }
        let bbox = |r: &f32x8| {
            let a = r.as_array();
            ([-a[2], -a[3], -a[4]], [a[5], a[6], a[7]])
        };

        // 2. Cell size, and 3. grid bounds: lo corners of the spheres that fit.
        let all = pre[NB - 1];
        let max_ext = all.as_array()[1];
        let (mut s, (mut lo_min, mut lo_max)) = match opts.cell_size {
            Some(s) => (s, bbox(&all)),
            None => {
                let b = auto_bucket(&cnt, &pre, n, cap, None);
                (pre[b].as_array()[1] * MARGIN, bbox(&pre[b]))
            }
        };
        if opts.cell_size.is_some() && max_ext > s {
            let parts = &mut self.bbox_parts;
            parts.clear();
            parts.resize(nch, ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]));
            let work = |(ci, p): (usize, &mut ([f32; 3], [f32; 3]))| {
                *p = bbox_chunk(
                    &cols,
                    t_max,
                    ci * SPHERE_CHUNK,
                    ((ci + 1) * SPHERE_CHUNK).min(n),
                    s,
                )
            };
            if par {
                parts.par_iter_mut().enumerate().for_each(work);
            } else {
                parts.iter_mut().enumerate().for_each(work);
            }
            let (mut mn, mut mx) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
            for p in parts.iter() {
                merge_bbox(&mut mn, &mut mx, &p.0, &p.1);
            }
            if mn[0] <= mx[0] {
                (lo_min, lo_max) = (mn, mx);
            }
        }
        // Then the cell cap.
        // Infinite boxes (finite inputs can overflow) must not make the grid infinite.
        lo_min = lo_min.map(|x| x.clamp(-f32::MAX, f32::MAX));
        lo_max = lo_max.map(|x| x.clamp(-f32::MAX, f32::MAX));
        s = s.clamp(MIN_CELL, f32::MAX);
        let s_fit = s;
        let mut s_base = s_fit;
        let (full_min, full_max) = (lo_min, lo_max);
        let (mut s, mut dims) = fit_cells(&lo_min, &lo_max, s_fit, cap);
        if s > 2.0 * s_fit && n >= 256 && opts.layout != Layout::Sparse {
            // The cap grew the cells: the scene is sparse for its bounding box, maybe because
            // of a few far-away spheres. Try the bounds without the `trim` most extreme `lo`
            // corners on each side of each axis; those spheres are clamped into the border
            // cells (correct, as `f` stays monotone).
            // The automatic cell size is chosen again with these bounds in its cell count.
            let trim = 64 + n / 4096;
            let (tmin, tmax) = self.trimmed_bounds(&cols, t_max, trim);
            let s_fit2 = match opts.cell_size {
                Some(_) => s_fit,
                None => {
                    let ext = [0, 1, 2].map(|a| tmax[a] as f64 - tmin[a] as f64);
                    let b = auto_bucket(&cnt, &pre, n, cap, Some(ext));
                    (pre[b].as_array()[1] * MARGIN).clamp(MIN_CELL, f32::MAX)
                }
            };
            let (s2, dims2) = fit_cells(&tmin, &tmax, s_fit2, cap);
            s_base = s_fit2;
            if s2 < s {
                (s, dims, lo_min) = (s2, dims2, tmin);
            }
        }
        // The dense layout unless asked otherwise, or (automatic) unless the cap grew the
        // cells more than twofold and the counts then show crowded cells.
        let maybe_sparse = opts.layout == Layout::Auto && n >= 256 && s > 2.0 * s_base;
        // If the last build of this size went sparse for the same reason, go straight there.
        let mut sparse =
            opts.layout == Layout::Sparse || (maybe_sparse && self.sparse && self.sparse_n == n);
        let coherent = self.coherent;
        if !coherent {
            self.recs.resize(n, Rec([0.0; 8]));
        }
        self.order_tmp.resize(n, 0);
        self.skey.resize(n, 0);
        for b in self.boxes.iter_mut() {
            b.resize(n + 8, 0.0);
        }
        let mut ncells = 0;
        let dense_ran = !sparse;
        if !sparse {
            let geom = Geom::new(lo_min, s, dims);
            ncells = geom.over_key as usize;
            // 4. Keys, and box records unless the store is in (nearly) grid order: then the
            // boxes are recomputed from the columns, read nearly sequentially, in step 5.
            self.keys.resize(n, 0);
            key_pass(
                &cols,
                t_max,
                &geom,
                coherent,
                par,
                &mut self.recs,
                &mut self.keys[..n],
            );
            // 5. Sort: counts first.
            self.dense_count(n, ncells, par);
            if maybe_sparse {
                // Mean number of spheres sharing a sphere's cell. Past `CROWDED`, the extra
                // passes of the sparse layout cost less than the crowded cells.
                let load = self.cs.iter().map(|&c| c as f64 * c as f64).sum::<f64>() / n as f64;
                sparse = load > CROWDED;
            }
        }
        if sparse {
            // Uncapped cells of the chosen size, at most `HMAX` per axis.
            lo_min = full_min;
            let ext = [0, 1, 2].map(|a| full_max[a] as f64 - full_min[a] as f64);
            s = s_base.max((ext.iter().cloned().fold(0.0, f64::max) / (HMAX - 1) as f64) as f32);
            dims = ext.map(|e| ((e / s as f64).floor() as u32 + 1).min(HMAX));
        }
        self.sparse = sparse;
        self.sparse_n = n;
        self.cell_size = s;
        self.dims = dims;
        let (px, py) = (dims[0] as usize + 2, dims[1] as usize + 2);
        let n_grid = if sparse {
            let geom = Geom::new(lo_min, s, dims);
            self.vkeys.resize(n, 0);
            // The box records, if needed, are already written when the dense pass ran.
            let records_done = coherent || dense_ran;
            key_pass(
                &cols,
                t_max,
                &geom,
                records_done,
                par,
                &mut self.recs,
                &mut self.vkeys[..n],
            );
            self.sparse_sort(n, px as u64, (px * py) as u64)
        } else {
            self.dense_scatter(n, ncells)
        };
        {
            // Gather the boxes by position (from the records, or recomputed from the columns),
            // counting the 8-blocks of positions whose indices are consecutive: if most are,
            // the store is in grid order and the next build skips the records.
            let [lx, ly, lz, hx, hy, hz] = &mut self.boxes;
            let recs = &self.recs[..];
            let ot = &self.order_tmp[..n];
            let work = |c: &[u32], out: [&mut [f32]; 6]| {
                if coherent {
                    gather_cols(&cols, t_max, c, out)
                } else {
                    gather_boxes(recs, c, out)
                }
            };
            let runs: usize = if par {
                ot.par_chunks(SPHERE_CHUNK)
                    .zip(
                        lx[..n]
                            .par_chunks_mut(SPHERE_CHUNK)
                            .zip(ly[..n].par_chunks_mut(SPHERE_CHUNK))
                            .zip(lz[..n].par_chunks_mut(SPHERE_CHUNK))
                            .zip(hx[..n].par_chunks_mut(SPHERE_CHUNK))
                            .zip(hy[..n].par_chunks_mut(SPHERE_CHUNK))
                            .zip(hz[..n].par_chunks_mut(SPHERE_CHUNK)),
                    )
                    .map(|(c, (((((lx, ly), lz), hx), hy), hz))| work(c, [lx, ly, lz, hx, hy, hz]))
                    .sum()
            } else {
                work(
                    ot,
                    [
                        &mut lx[..n],
                        &mut ly[..n],
                        &mut lz[..n],
                        &mut hx[..n],
                        &mut hy[..n],
                        &mut hz[..n],
                    ],
                )
            };
            self.coherent = runs * 8 * 2 >= n;
        }
        std::mem::swap(&mut self.order, &mut self.order_tmp);
        self.n_grid = n_grid;

        // 6. Pairs.
        let items = &mut self.items;
        items.clear();
        for start in (0..n_grid).step_by(PAIR_CHUNK) {
            items.push(Item {
                q: u32::MAX,
                start: start as u32,
                end: (start + PAIR_CHUNK).min(n_grid) as u32,
            });
        }
        for q in n_grid..n {
            for start in (0..q).step_by(OVER_CHUNK) {
                items.push(Item {
                    q: q as u32,
                    start: start as u32,
                    end: (start + OVER_CHUNK).min(q) as u32,
                });
            }
        }
        let view = View {
            b: [0, 1, 2, 3, 4, 5].map(|k| &self.boxes[k][..n + 8]),
            skey: &self.skey[..n],
            cs: &self.cs,
            px,
            pxy: px * py,
            sparse,
            hrows: &self.hrows,
        };
        if par {
            if self.outs.len() < items.len() {
                self.outs.resize_with(items.len(), Default::default);
            }
            self.outs[..items.len()]
                .par_iter_mut()
                .zip(items.par_iter())
                .for_each(|(o, it)| {
                    let mut out = Out {
                        buf: &mut o.0,
                        len: 0,
                    };
                    view.item(*it, &mut out);
                    o.1 = out.len;
                });
            let outs = &self.outs[..items.len()];
            let total: usize = outs.iter().map(|o| o.1).sum();
            if self.pairs.len() < total {
                self.pairs.resize(total, [0; 2]);
            }
            par_concat(&mut self.pairs[..total], outs);
            self.npairs = total;
        } else {
            let mut out = Out {
                buf: &mut self.pairs,
                len: 0,
            };
            for it in items.iter() {
                view.item(*it, &mut out);
            }
            self.npairs = out.len;
        }
    }
}

/// Number of 8-blocks of `idx` (from its start) holding 8 consecutive indices.
fn runs8(idx: &[u32]) -> usize {
    let iota = u32x8::from([0, 1, 2, 3, 4, 5, 6, 7]);
    idx.chunks_exact(8)
        .filter(|c| {
            let v = u32x8::from(*c.first_chunk::<8>().unwrap());
            v.simd_eq(u32x8::splat(c[0]) + iota).all()
        })
        .count()
}

/// Write the boxes of spheres `idx` (records `recs`) into the six sorted columns; returns
/// [`runs8`] of `idx`.
fn gather_boxes(recs: &[Rec], idx: &[u32], cols: [&mut [f32]; 6]) -> usize {
    let [lx, ly, lz, hx, hy, hz] = cols;
    let m = idx.len();
    let (lx, ly, lz, hx, hy, hz) = (
        &mut lx[..m],
        &mut ly[..m],
        &mut lz[..m],
        &mut hx[..m],
        &mut hy[..m],
        &mut hz[..m],
    );
    for j in 0..m {
        let r = &recs[idx[j] as usize].0;
        lx[j] = r[0];
        ly[j] = r[1];
        lz[j] = r[2];
        hx[j] = r[3];
        hy[j] = r[4];
        hz[j] = r[5];
    }
    runs8(idx)
}

/// Write the boxes of spheres `idx`, recomputed from the columns, into the six sorted
/// columns: 8 at a time where `idx` holds 8 consecutive indices, else one by one (with the
/// same float operations as [`boxes8`]). Returns [`runs8`] of `idx`.
fn gather_cols(cols: &Columns<'_>, t_max: f32, idx: &[u32], out: [&mut [f32]; 6]) -> usize {
    let m = idx.len();
    let [lx, ly, lz, hx, hy, hz] = out;
    let o = [
        &mut lx[..m],
        &mut ly[..m],
        &mut lz[..m],
        &mut hx[..m],
        &mut hy[..m],
        &mut hz[..m],
    ];
    let iota = u32x8::from([0, 1, 2, 3, 4, 5, 6, 7]);
    let t = f32x8::splat(t_max);
    let mut runs = 0;
    let mut j = 0;
    while j < m {
        if let Some(c) = idx[j..].first_chunk::<8>()
            && u32x8::from(*c).simd_eq(u32x8::splat(c[0]) + iota).all()
        {
            runs += 1;
            let (lo, hi) = boxes8(cols, c[0] as usize, t);
            for a in 0..3 {
                *o[a][j..].first_chunk_mut::<8>().unwrap() = lo[a].to_array();
                *o[3 + a][j..].first_chunk_mut::<8>().unwrap() = hi[a].to_array();
            }
            j += 8;
            continue;
        }
        for l in j..(j + 8).min(m) {
            let i = idx[l] as usize;
            let (c, v, r) = cols.at(i);
            for a in 0..3 {
                let e = c[a] + v[a] * t_max;
                // `vminps(c, e)` / `vmaxps(c, e)`, as `fast_min` / `fast_max` in `boxes8`.
                o[a][l] = (if c[a] < e { c[a] } else { e }) - r;
                o[3 + a][l] = (if c[a] > e { c[a] } else { e }) + r;
            }
        }
        j += 8;
    }
    runs
}

/// The smallest cell size `>= s` (and the cells per axis) for which the grid over the `lo`
/// corners `lo_min..=lo_max`, plus padding, has at most `cap` cells.
fn fit_cells(lo_min: &[f32; 3], lo_max: &[f32; 3], mut s: f32, cap: f64) -> (f32, [u32; 3]) {
    let ext = [0, 1, 2].map(|a| lo_max[a] as f64 - lo_min[a] as f64);
    loop {
        let d = ext.map(|e| (e / s as f64).floor() + 1.0);
        let t: f64 = d.iter().map(|x| x + 2.0).product();
        if t <= cap {
            return (s, d.map(|x| x as u32));
        }
        s = (s as f64 * (t / cap).cbrt().max(1.01)).min(f32::MAX as f64) as f32;
    }
}

/// Order-preserving map of floats to integers.
fn ord_bits(x: f32) -> u32 {
    let b = x.to_bits();
    if b >> 31 == 1 { !b } else { b | 0x8000_0000 }
}

fn from_ord_bits(o: u32) -> f32 {
    f32::from_bits(if o >> 31 == 1 { o & 0x7FFF_FFFF } else { !o })
}

/// Copy the chunk outputs, in order, into `dst` (whose length is their total).
fn par_concat(dst: &mut [[u32; 2]], outs: &[(Vec<[u32; 2]>, usize)]) {
    if outs.len() <= 8 {
        let mut at = 0;
        for o in outs {
            dst[at..at + o.1].copy_from_slice(&o.0[..o.1]);
            at += o.1;
        }
        return;
    }
    let (a, b) = outs.split_at(outs.len() / 2);
    let na: usize = a.iter().map(|o| o.1).sum();
    let (da, db) = dst.split_at_mut(na);
    rayon::join(|| par_concat(da, a), || par_concat(db, b));
}

/// Swept boxes of spheres `i..i+8` (lanes past the end are zero spheres): one block's
/// columns when `i` starts a full block, else lane by lane.
#[inline(always)]
fn boxes8(cols: &Columns<'_>, i: usize, t: f32x8) -> ([f32x8; 3], [f32x8; 3]) {
    let (c, v, r) = if i.is_multiple_of(8) && i + 8 <= cols.n {
        let b = &cols.blocks[i / 8];
        let f = f32x8::from;
        (
            [f(b.cx), f(b.cy), f(b.cz)],
            [f(b.vx), f(b.vy), f(b.vz)],
            f(b.r),
        )
    } else {
        let (mut c, mut v, mut r) = ([[0.0f32; 8]; 3], [[0.0f32; 8]; 3], [0.0f32; 8]);
        for l in 0..8.min(cols.n.saturating_sub(i)) {
            let (cc, vv, rr) = cols.at(i + l);
            for a in 0..3 {
                c[a][l] = cc[a];
                v[a][l] = vv[a];
            }
            r[l] = rr;
        }
        (c.map(f32x8::from), v.map(f32x8::from), f32x8::from(r))
    };
    let mut lo = [f32x8::ZERO; 3];
    let mut hi = [f32x8::ZERO; 3];
    for a in 0..3 {
        let e = c[a] + v[a] * t;
        lo[a] = c[a].fast_min(e) - r;
        hi[a] = c[a].fast_max(e) + r;
    }
    (lo, hi)
}

/// Largest extent of each box, as non-negative float bits.
#[inline(always)]
fn max_extent(lo: &[f32x8; 3], hi: &[f32x8; 3]) -> u32x8 {
    let e = (hi[0] - lo[0])
        .fast_max(hi[1] - lo[1])
        .fast_max(hi[2] - lo[2]);
    e.to_bits() & u32x8::splat(0x7FFF_FFFF)
}

fn hmin(v: f32x8) -> f32 {
    v.to_array().into_iter().fold(f32::INFINITY, f32::min)
}

fn hmax(v: f32x8) -> f32 {
    v.to_array().into_iter().fold(f32::NEG_INFINITY, f32::max)
}

/// Lanes `< m` set.
#[inline(always)]
fn lane_mask(m: usize) -> f32x8 {
    const IOTA: [i32; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    f32x8::from_bits(
        i32x8::from(IOTA)
            .simd_lt(i32x8::splat(m as i32))
            .cast_unsigned(),
    )
}

fn stats_chunk(cols: &Columns<'_>, t_max: f32, start: usize, end: usize, st: &mut Stats) {
    // Two sub-histograms, alternating by lane, halve the store-to-load chains when
    // consecutive spheres fall in the same bucket.
    let mut sub = [[f32x8::from(EMPTY); NB]; 2];
    let t = f32x8::splat(t_max);
    let one = f32x8::from(COUNT1);
    let mut i = start;
    while i < end {
        let m = (end - i).min(8);
        let (lo, hi) = boxes8(cols, i, t);
        let eb = max_extent(&lo, &hi);
        let e = f32x8::from_bits(eb);
        let rows = f32x8::transpose([f32x8::ZERO, e, -lo[0], -lo[1], -lo[2], lo[0], lo[1], lo[2]]);
        let bv = eb >> HSHIFT;
        let bk = bv.to_array();
        if m == 8 && bv.simd_eq(u32x8::splat(bk[0])).all() {
            // All eight in one bucket (the common case for narrow size distributions): one
            // update instead of eight dependent ones.
            let r01 = rows[0]
                .fast_max(rows[1])
                .fast_max(rows[2].fast_max(rows[3]));
            let r = r01.fast_max(
                rows[4]
                    .fast_max(rows[5])
                    .fast_max(rows[6].fast_max(rows[7])),
            );
            let h = &mut sub[0][bk[0] as usize];
            *h = h.fast_max(r) + one * f32x8::splat(8.0);
        } else {
            for l in 0..m {
                let h = &mut sub[l & 1][bk[l] as usize];
                *h = h.fast_max(rows[l]) + one;
            }
        }
        i += 8;
    }
    for (h, (a, b)) in st.hist.iter_mut().zip(sub[0].iter().zip(sub[1].iter())) {
        *h = merge_rec(*a, *b);
    }
}

/// Bounding box of the `lo` corners of the spheres whose largest extent is `<= s`.
fn bbox_chunk(
    cols: &Columns<'_>,
    t_max: f32,
    start: usize,
    end: usize,
    s: f32,
) -> ([f32; 3], [f32; 3]) {
    let t = f32x8::splat(t_max);
    let mut mn = [f32x8::splat(f32::INFINITY); 3];
    let mut mx = [f32x8::splat(f32::NEG_INFINITY); 3];
    let sb = u32x8::splat(s.to_bits());
    let mut i = start;
    while i < end {
        let (lo, hi) = boxes8(cols, i, t);
        let eb = max_extent(&lo, &hi);
        let fits = f32x8::from_bits(eb.simd_le(sb)) & lane_mask(end - i);
        for a in 0..3 {
            mn[a] = mn[a].fast_min(fits.select(lo[a], f32x8::splat(f32::INFINITY)));
            mx[a] = mx[a].fast_max(fits.select(lo[a], f32x8::splat(f32::NEG_INFINITY)));
        }
        i += 8;
    }
    (
        [0, 1, 2].map(|a| hmin(mn[a])),
        [0, 1, 2].map(|a| hmax(mx[a])),
    )
}

/// The automatic cell size (module docs, step 2): the bucket `b` whose prefix record gives
/// the cell size (its max extent) and grid bounds.
///
/// `ext`, if given, replaces the buckets' bounding boxes in the cell count.
fn auto_bucket(
    cnt: &[f64; NB],
    pre: &[f32x8; NB],
    n: usize,
    cap: f64,
    ext: Option<[f64; 3]>,
) -> usize {
    let mut best = (f64::INFINITY, NB - 1);
    let mut above = 0.0f64;
    for b in (0..NB).rev() {
        if cnt[b] == 0.0 {
            continue;
        }
        let a = pre[b].as_array();
        let s = a[1] as f64;
        let cells: f64 = (0..3)
            .map(|k| {
                (ext.map_or(a[5 + k] as f64 + a[2 + k] as f64, |e| e[k])
                    .clamp(0.0, f32::MAX as f64)
                    / s)
                    .floor()
                    + 1.0
            })
            .product::<f64>()
            .min(cap);
        let cost = 13.5 * n as f64 / cells + above;
        if cost < best.0 {
            best = (cost, b);
        }
        above += cnt[b];
        if above >= best.0 {
            break;
        }
    }
    best.1
}

/// The key pass over all spheres: keys, and box records unless `coherent`.
fn key_pass<K: Key>(
    cols: &Columns<'_>,
    t_max: f32,
    g: &Geom,
    coherent: bool,
    par: bool,
    recs: &mut [Rec],
    keys: &mut [K],
) {
    let n = keys.len();
    if coherent {
        let work =
            |(ci, k): (usize, &mut [K])| keys_chunk(cols, t_max, ci * SPHERE_CHUNK, g, &mut [], k);
        if par {
            keys.par_chunks_mut(SPHERE_CHUNK).enumerate().for_each(work);
        } else {
            keys.chunks_mut(SPHERE_CHUNK).enumerate().for_each(work);
        }
    } else {
        let work = |(ci, (r, k)): (usize, (&mut [Rec], &mut [K]))| {
            keys_chunk(cols, t_max, ci * SPHERE_CHUNK, g, r, k)
        };
        if par {
            recs[..n]
                .par_chunks_mut(SPHERE_CHUNK)
                .zip(keys.par_chunks_mut(SPHERE_CHUNK))
                .enumerate()
                .for_each(work);
        } else {
            recs[..n]
                .chunks_mut(SPHERE_CHUNK)
                .zip(keys.chunks_mut(SPHERE_CHUNK))
                .enumerate()
                .for_each(work);
        }
    }
}

/// Keys of spheres `start..start + keys.len()`, and their box records unless `recs` is empty.
fn keys_chunk<K: Key>(
    cols: &Columns<'_>,
    t_max: f32,
    start: usize,
    g: &Geom,
    recs: &mut [Rec],
    keys: &mut [K],
) {
    let write = !recs.is_empty();
    let t = f32x8::splat(t_max);
    let inv = f32x8::splat(g.inv);
    let zero = f32x8::ZERO;
    let one = i32x8::splat(1);
    let cell = |x: f32x8, a: usize| -> i32x8 {
        ((x - f32x8::splat(g.origin[a])) * inv)
            .floor()
            .fast_max(zero)
            .fast_min(f32x8::splat(g.limf[a]))
            .fast_trunc_int()
            .min(i32x8::splat(g.limi[a]))
    };
    let len = keys.len();
    let mut j = 0;
    while j < len {
        let (lo, hi) = boxes8(cols, start + j, t);
        let gl = [cell(lo[0], 0), cell(lo[1], 1), cell(lo[2], 2)];
        let gh = [cell(hi[0], 0), cell(hi[1], 1), cell(hi[2], 2)];
        let over = (gh[0] - gl[0]).simd_gt(one)
            | (gh[1] - gl[1]).simd_gt(one)
            | (gh[2] - gl[2]).simd_gt(one);
        let ka = K::make(&gl, over, g);
        let m = (len - j).min(8);
        keys[j..j + m].copy_from_slice(&ka[..m]);
        if write {
            let rows = f32x8::transpose([lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], zero, zero]);
            for l in 0..m {
                recs[j + l] = Rec(rows[l].to_array());
            }
        }
        j += 8;
    }
}

/// For each 8-bit hit mask, the pairs `[0, lane]` of its first four set lanes, packed to the
/// front (as 8 `u32`: four `[p, q]` pairs once the base `[p, s]` is added).
static EMIT: [[u32; 8]; 256] = {
    let mut t = [[0u32; 8]; 256];
    let mut m = 0;
    while m < 256 {
        let (mut k, mut j) = (0, 0);
        while j < 8 {
            if (m >> j) & 1 == 1 && k < 4 {
                t[m][2 * k + 1] = j as u32;
                k += 1;
            }
            j += 1;
        }
        m += 1;
    }
    t
};

/// Output window of the first batches of one or two spheres: five batches write at most 8
/// pairs per sphere each, and each write is 8 entries wide.
const WIN2: usize = 88;

/// Lanes holding the second element of each pair.
const ODD: [u32; 8] = [0, !0, 0, !0, 0, !0, 0, !0];

/// A pair buffer whose first `len` entries are valid; `buf` is longer and grown ahead of the
/// writes (its tail is scratch).
struct Out<'a> {
    buf: &'a mut Vec<[u32; 2]>,
    len: usize,
}

/// Grow `buf` to at least `need` entries.
#[cold]
#[inline(never)]
fn grow(buf: &mut Vec<[u32; 2]>, need: usize) {
    let n = (buf.len() * 2).max(need + 1024);
    buf.resize(n, [0; 2]);
}

/// The sorted boxes (each column padded by 8), sorted keys and cell starts.
#[derive(Clone, Copy)]
struct View<'a> {
    b: [&'a [f32]; 6],
    skey: &'a [u32],
    cs: &'a [u32],
    px: usize,
    pxy: usize,
    /// Sparse layout: `skey` holds cell numbers and `hrows` their ranges.
    sparse: bool,
    hrows: &'a [[u32; 9]],
}

impl View<'_> {
    /// The half-stencil ranges of sphere `p` (cell `ka`), united with those of `p + 1` (cell
    /// `kb`) when [`pairable`](Self::pairable).
    #[inline(always)]
    fn rows<const SPARSE: bool>(&self, p: usize, ka: usize, kb: usize) -> [(usize, usize); 5] {
        if SPARSE {
            let r = self.hrows[ka].map(|x| x as usize);
            [
                (p + 1, r[0]),
                (r[1], r[2]),
                (r[3], r[4]),
                (r[5], r[6]),
                (r[7], r[8]),
            ]
        } else {
            row_ranges(self.cs, ka, kb, self.px, self.pxy, p)
        }
    }

    /// Whether consecutive spheres in cells `ka` and `kb` can share their rows: same cell, or
    /// (dense layout) the next cell in `x`.
    #[inline(always)]
    fn pairable<const SPARSE: bool>(ka: usize, kb: usize) -> bool {
        if SPARSE {
            kb == ka
        } else {
            kb.wrapping_sub(ka) <= 1
        }
    }

    fn item(&self, it: Item, out: &mut Out<'_>) {
        let (start, end) = (it.start as usize, it.end as usize);
        if it.q == u32::MAX {
            out.len = if self.sparse {
                self.grid_range::<true>(start, end, out.buf, out.len)
            } else {
                self.grid_range::<false>(start, end, out.buf, out.len)
            };
            return;
        }
        // Oversize sphere q against positions start..end (all before q).
        let n8 = self.b[0].len();
        let (lx, ly, lz) = (&self.b[0][..n8], &self.b[1][..n8], &self.b[2][..n8]);
        let (hx, hy, hz) = (&self.b[3][..n8], &self.b[4][..n8], &self.b[5][..n8]);
        let q = it.q as usize;
        let al = [
            f32x8::splat(lx[q]),
            f32x8::splat(ly[q]),
            f32x8::splat(lz[q]),
        ];
        let ah = [
            f32x8::splat(hx[q]),
            f32x8::splat(hy[q]),
            f32x8::splat(hz[q]),
        ];
        let mut s = start;
        while s < end {
            let mut m = test8!(s, al, ah, lx, ly, lz, hx, hy, hz, false, false, false)
                & ((1u32 << (end - s).min(8)) - 1);
            while m != 0 {
                if out.len >= out.buf.len() {
                    grow(out.buf, out.len + 1);
                }
                out.buf[out.len] = [(s + m.trailing_zeros() as usize) as u32, it.q];
                out.len += 1;
                m &= m - 1;
            }
            s += 8;
        }
    }

    /// Pairs of the grid spheres at positions `start..end` with their half stencil, written
    /// from `buf[len]` on; returns the new length.
    ///
    /// Two consecutive spheres `p`, `p+1` whose cells are equal or `x`-neighbours share their
    /// rows: each row is the union of their two rows (one more cell at most), loaded once and
    /// tested against both. The extra cell holds only boxes that cannot overlap the other
    /// sphere (its cell differs by two in `x`), so it adds no pair; in the own row, `p+1`
    /// skips the positions up to itself. Each row gets one 8-wide batch here, straight-line;
    /// the rest of the rows longer than 8 is done by [`long_rows`](Self::long_rows) right
    /// after.
    fn grid_range<const SPARSE: bool>(
        &self,
        start: usize,
        end: usize,
        buf: &mut Vec<[u32; 2]>,
        mut len: usize,
    ) -> usize {
        let skey = self.skey;
        // All columns have length `n + 8`; clamping window starts to `n` (a no-op: positions
        // never exceed `n`) lets the compiler drop the per-column bounds checks.
        let n8 = self.b[0].len();
        let lim = n8 - 8;
        let (lx, ly, lz) = (&self.b[0][..n8], &self.b[1][..n8], &self.b[2][..n8]);
        let (hx, hy, hz) = (&self.b[3][..n8], &self.b[4][..n8], &self.b[5][..n8]);
        let odd = u32x8::from(ODD);
        let skey = &skey[..end];
        let mut p = start;
        while p < end {
            let ka = skey[p] as usize;
            let kb = skey.get(p + 1).map_or(usize::MAX, |&k| k as usize);
            // Five batches write at most 8 pairs per sphere each, plus 8 entries of scratch.
            if len + WIN2 > buf.len() {
                grow(buf, len + WIN2);
            }
            let w: &mut [[u32; 2]; WIN2] = (&mut buf[len..len + WIN2]).try_into().unwrap();
            let mut k = 0;
            let mut long = false;
            let pu = p as u32;
            let splat = |q: usize| {
                (
                    u32x8::from([q as u32, 0, q as u32, 0, q as u32, 0, q as u32, 0]),
                    [
                        f32x8::splat(lx[q]),
                        f32x8::splat(ly[q]),
                        f32x8::splat(lz[q]),
                    ],
                    [
                        f32x8::splat(hx[q]),
                        f32x8::splat(hy[q]),
                        f32x8::splat(hz[q]),
                    ],
                )
            };
            // Write pairs `[q, t + j]` for the set bits `j` of `m` at `w[k]`.
            macro_rules! emit {
                ($m:expr, $pv:expr, $q:expr, $t:expr) => {{
                    let (m, t) = ($m, $t);
                    let base = $pv + (u32x8::splat(t as u32) & odd);
                    let q = (base + u32x8::from(EMIT[m as usize])).to_array();
                    let at = k.min(WIN2 - 8);
                    w[at..at + 4].copy_from_slice(q.as_chunks::<2>().0);
                    let c = m.count_ones() as usize;
                    if c > 4 {
                        emit_rest(w, at, $q, m, t);
                    }
                    k = at + c;
                }};
            }
            if Self::pairable::<SPARSE>(ka, kb) {
                // Spheres p and p+1 together.
                let rows = self.rows::<SPARSE>(p, ka, kb);
                let (pva, ala, aha) = splat(p);
                let (pvb, alb, ahb) = splat(p + 1);
                macro_rules! row2 {
                    ($i:expr, $ly:expr, $hy:expr, $lz:expr) => {{
                        let (s, e) = rows[$i];
                        let t = s.min(lim);
                        let lanes = (1u32 << (e - t).min(8)) - 1;
                        let ma = test8!(t, ala, aha, lx, ly, lz, hx, hy, hz, $ly, $hy, $lz) & lanes;
                        // In the own row (`t == p + 1`), lane 0 is p+1 itself.
                        let mb = test8!(t, alb, ahb, lx, ly, lz, hx, hy, hz, $ly, $hy, $lz)
                            & lanes
                            & !u32::from($i == 0);
                        emit!(ma, pva, pu, t);
                        emit!(mb, pvb, pu + 1, t);
                        long |= e > t + 8;
                    }};
                }
                row2!(0, false, false, false);
                row2!(1, true, false, false);
                row2!(2, false, true, true);
                row2!(3, false, false, true);
                row2!(4, true, false, true);
                len += k;
                if long {
                    len = self.long_rows::<SPARSE, 2>(p, ka, kb, buf, len);
                }
                p += 2;
            } else {
                let rows = self.rows::<SPARSE>(p, ka, ka);
                let (pva, ala, aha) = splat(p);
                macro_rules! row1 {
                    ($i:expr, $ly:expr, $hy:expr, $lz:expr) => {{
                        let (s, e) = rows[$i];
                        let t = s.min(lim);
                        let m = test8!(t, ala, aha, lx, ly, lz, hx, hy, hz, $ly, $hy, $lz)
                            & ((1u32 << (e - t).min(8)) - 1);
                        emit!(m, pva, pu, t);
                        long |= e > t + 8;
                    }};
                }
                // Own cell after p and cell x+1; row (y+1, z); rows (y-1, y, y+1) at z+1.
                row1!(0, false, false, false);
                row1!(1, true, false, false);
                row1!(2, false, true, true);
                row1!(3, false, false, true);
                row1!(4, true, false, true);
                len += k;
                if long {
                    len = self.long_rows::<SPARSE, 1>(p, ka, ka, buf, len);
                }
                p += 1;
            }
        }
        len
    }

    /// The batches after the first of the rows longer than 8 (see
    /// [`grid_range`](Self::grid_range)), for the `SPHERES` (1 or 2) spheres from position
    /// `p` on, in cells `ka` and `kb`.
    #[inline(never)]
    fn long_rows<const SPARSE: bool, const SPHERES: usize>(
        &self,
        p: usize,
        ka: usize,
        kb: usize,
        buf: &mut Vec<[u32; 2]>,
        mut len: usize,
    ) -> usize {
        let rows = self.rows::<SPARSE>(p, ka, kb);
        let n8 = self.b[0].len();
        let lim = n8 - 8;
        let (lx, ly, lz) = (&self.b[0][..n8], &self.b[1][..n8], &self.b[2][..n8]);
        let (hx, hy, hz) = (&self.b[3][..n8], &self.b[4][..n8], &self.b[5][..n8]);
        let odd = u32x8::from(ODD);
        let splat = |q: usize| {
            (
                u32x8::from([q as u32, 0, q as u32, 0, q as u32, 0, q as u32, 0]),
                [
                    f32x8::splat(lx[q]),
                    f32x8::splat(ly[q]),
                    f32x8::splat(lz[q]),
                ],
                [
                    f32x8::splat(hx[q]),
                    f32x8::splat(hy[q]),
                    f32x8::splat(hz[q]),
                ],
            )
        };
        let sp: [_; SPHERES] = std::array::from_fn(|d| splat(p + d));
        let spheres = SPHERES;
        macro_rules! row {
            ($i:expr, $ly:expr, $hy:expr, $lz:expr) => {{
                let (s0, e) = rows[$i];
                let mut s = s0 + 8;
                if s < e {
                    // At most one pair per candidate and sphere, plus 8 entries of scratch.
                    let need = len + spheres * (e - s) + 8;
                    if need > buf.len() {
                        grow(buf, need);
                    }
                    let out = &mut buf[..];
                    let olim = out.len() - 8;
                    while s < e {
                        let t = s.min(lim);
                        let lanes = (1u32 << (e - t).min(8)) - 1;
                        for (d, (pv, al, ah)) in sp.iter().enumerate() {
                            let m =
                                test8!(t, al, ah, lx, ly, lz, hx, hy, hz, $ly, $hy, $lz) & lanes;
                            let base = *pv + (u32x8::splat(t as u32) & odd);
                            let q = (base + u32x8::from(EMIT[m as usize])).to_array();
                            let at = len.min(olim);
                            out[at..at + 4].copy_from_slice(q.as_chunks::<2>().0);
                            let c = m.count_ones() as usize;
                            if c > 4 {
                                emit_rest(out, at, (p + d) as u32, m, t);
                            }
                            len = at + c;
                        }
                        s = t + 8;
                    }
                }
            }};
        }
        row!(0, false, false, false);
        row!(1, true, false, false);
        row!(2, false, true, true);
        row!(3, false, false, true);
        row!(4, true, false, true);
        len
    }
}

/// Mask of the boxes at positions `t..t+8` (columns `lx..hz`) overlapping the splatted box
/// `(al, ah)`. The flags drop tests that the cell order already implies (module docs): `sly`
/// drops `a.lo.y <= b.hi.y` (rows y+1), `shy` drops `b.lo.y <= a.hi.y` (row y-1), `slz`
/// drops `a.lo.z <= b.hi.z` (rows z+1). All columns must have the same length, at least
/// `t + 8`.
macro_rules! test8 {
    ($t:expr, $al:expr, $ah:expr, $lx:ident, $ly:ident, $lz:ident, $hx:ident, $hy:ident, $hz:ident, $sly:expr, $shy:expr, $slz:expr) => {{
        let t = $t;
        let ld = |c: &[f32]| f32x8::from(*c[t..t + 8].first_chunk::<8>().unwrap());
        let mut m = $al[0].simd_le(ld($hx)) & ld($lx).simd_le($ah[0]) & ld($lz).simd_le($ah[2]);
        if !$sly {
            m &= $al[1].simd_le(ld($hy));
        }
        if !$shy {
            m &= ld($ly).simd_le($ah[1]);
        }
        if !$slz {
            m &= $al[2].simd_le(ld($hz));
        }
        m.to_bitmask()
    }};
}
use test8;

/// The five position ranges of the half stencil of the sphere at position `p` in cell `ka`,
/// united with those of the sphere at `p + 1` in cell `kb` (`kb` is `ka` or `ka + 1`): the
/// rest of the own cell through the cell at `x+1` of `kb`, then the rows `(y+1, z)`,
/// `(y-1, z+1)`, `(y, z+1)` and `(y+1, z+1)`, from `x-1` of `ka` to `x+1` of `kb`. Cell `k`
/// holds positions `cs[k]..cs[k+1]`.
#[inline(always)]
fn row_ranges(
    cs: &[u32],
    ka: usize,
    kb: usize,
    px: usize,
    pxy: usize,
    p: usize,
) -> [(usize, usize); 5] {
    let d = kb - ka;
    // One bounds check per row: its cells `b-1..=b+1+d` span `cs[b-1..b+3+d]`.
    let row = |b: usize| {
        let w = cs[b - 1..].first_chunk::<5>().unwrap();
        (w[0] as usize, w[3 + d] as usize)
    };
    [
        (p + 1, cs[kb + 2] as usize),
        row(ka + px),
        row(ka + pxy - px),
        row(ka + pxy),
        row(ka + pxy + px),
    ]
}

/// Hits past the fourth (rare): pairs `[p, s + j]` for the set bits `j` of `m` after its first
/// four, written from `out[at + 4]` on.
#[cold]
#[inline(never)]
fn emit_rest(out: &mut [[u32; 2]], at: usize, p: u32, m: u32, s: usize) {
    let mut rest = m;
    for _ in 0..4 {
        rest &= rest - 1;
    }
    let mut k = at + 4;
    while rest != 0 {
        out[k] = [p, (s + rest.trailing_zeros() as usize) as u32];
        k += 1;
        rest &= rest - 1;
    }
}
