//! Uniform-grid broad phase over the swept boxes of moving spheres.
//!
//! Sphere `i` moves as `c + v t` for `t` in `[0, t_max]`; its *swept box* is, per axis,
//! `lo = min(c, c + v t_max) - r`, `hi = max(c, c + v t_max) + r` (`spheres::swept_box`,
//! a test build's, is the exact definition). Two spheres are a *candidate pair* iff their
//! swept boxes overlap as closed intervals on all three axes. [`Grid::build`] finds every
//! candidate pair exactly once.
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

mod cell_size;
mod pairs;
mod sort;
mod spheres;

use cell_size::{NB, Stats};
use pairs::Item;
use sort::Rec;
pub use spheres::SphereBlocks;
#[cfg(test)]
pub use spheres::swept_box;

use wide::f32x8;

/// From this many spheres on, [`Grid::build`] runs its passes on rayon (when its pool has more
/// than one thread).
pub const PAR_MIN: usize = 16384;

/// Spheres per chunk in the statistics and key passes.
const SPHERE_CHUNK: usize = 16384;
/// Sorted positions per chunk in the pair phase.
const PAIR_CHUNK: usize = 4096;
/// Positions per chunk when an oversize sphere is tested against all earlier ones.
const OVER_CHUNK: usize = 65536;
/// Smallest cell size; keeps `1 / s` finite.
const MIN_CELL: f32 = 1e-30;
/// Relative margin added to the automatic cell size so a box of exactly that extent does not
/// touch three cells through rounding.
const MARGIN: f32 = 1.0 + 1.0 / 65536.0;
/// Largest number of spheres (keys and positions must fit `u32`/`i32` with room for cells).
const MAX_N: usize = (1 << 30) - 1024;

/// What every stage of one build reads: the spheres, the window, their number, whether the
/// passes run on rayon, and the cell cap (`2 N + 1024` cells).
#[derive(Clone, Copy)]
struct BuildInput<'a> {
    cols: SphereBlocks<'a>,
    t_max: f32,
    n: usize,
    par: bool,
    cap: f64,
    /// Whether to copy the spheres' records into cell order too.
    records: bool,
}

/// The cells chosen before the layout is (module docs, steps 2 and 3).
#[derive(Clone, Copy)]
struct CellChoice {
    /// Cell edge length, after the cell cap.
    s: f32,
    /// Cells per axis, without the padding.
    dims: [u32; 3],
    /// The grid's smallest `lo` corner (over the trimmed bounds when those won).
    origin: [f32; 3],
    /// The bounds of the `lo` corners of the spheres that fit, untrimmed (for the sparse
    /// layout, which does not cap the cells).
    full: ([f32; 3], [f32; 3]),
    /// The cell size before the cap grew it (chosen again over the trimmed bounds, if tried).
    s_base: f32,
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
    /// The spheres' records in cell order (only for [`build_cells`](Grid::build_cells)).
    sorted: crate::store::PackedSpheres,
    keys: Vec<u32>,
    kk: Vec<u32>,
    skey: Vec<u32>,
    boxes: [Vec<f32>; 6],
    cs: Vec<u32>,
    stats: Vec<Stats>,
    bbox_parts: Vec<([f32; 3], [f32; 3])>,
    items: Vec<Item>,
    outs: Vec<(Vec<[u32; 2]>, usize)>,
    /// One pair buffer per worker for [`visit_pairs`](Grid::visit_pairs).
    scratch: Vec<std::sync::Mutex<Vec<[u32; 2]>>>,
    /// Whether the last build's passes ran on rayon.
    par: bool,
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
            + (self.recs.capacity() + self.sorted.0.capacity()) * size_of::<Rec>()
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
        b += self
            .scratch
            .iter()
            .map(|m| m.lock().unwrap_or_else(|e| e.into_inner()).capacity() * 8)
            .sum::<usize>();
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

    /// Rebuild for these spheres over the window `[0, t_max]`, in the stages of the module
    /// docs: the extent histogram, the cells, the sort into cell order, the pairs.
    ///
    /// Afterwards [`order`](Grid::order) holds the sphere indices sorted by cell and
    /// [`pairs`](Grid::pairs) every candidate pair exactly once as positions in `order()`.
    ///
    /// # Panics
    /// If the columns differ in length, `t_max` is not finite and `>= 0`, a given cell size is
    /// not finite and `> 0`, or there are more than about `2^30` spheres.
    pub fn build(&mut self, cols: SphereBlocks<'_>, t_max: f32, opts: GridOptions) {
        self.sorted.0.clear();
        if let Some(input) = self.cells_of(cols, t_max, opts, false) {
            self.find_pairs(&input);
        }
    }

    /// Steps 1–5 of [`build`](Grid::build): the cells and the cell order, no pairs. Then
    /// [`visit_pairs`](Grid::visit_pairs) hands the pairs on in small batches instead of a
    /// list, so memory stays linear in `N` whatever the window. Same panics as `build`.
    pub fn build_cells(&mut self, cols: SphereBlocks<'_>, t_max: f32, opts: GridOptions) {
        if let Some(input) = self.cells_of(cols, t_max, opts, true) {
            self.plan_pair_work(input.n, input.par);
        }
    }

    /// Every candidate pair of the last [`build_cells`](Grid::build_cells) exactly once, as
    /// positions in [`order`](Grid::order), a few thousand at a time (see the pair phase).
    pub fn visit_pairs(&self, visit: &(dyn Fn(&[[u32; 2]]) + Sync)) {
        let n = self.order.len();
        if n > 0 && !self.scratch.is_empty() {
            self.visit_pairs_of(n, self.par, visit);
        }
    }

    /// [`visit_pairs`](Grid::visit_pairs) on the calling thread, to a visitor with state of
    /// its own (no locks, no atomics).
    pub fn visit_pairs_mut(&self, visit: &mut dyn FnMut(&[[u32; 2]])) {
        let n = self.order.len();
        if n > 0 && !self.scratch.is_empty() {
            let mut buf = self.scratch[0].lock().unwrap_or_else(|e| e.into_inner());
            self.visit_pairs_in_order(n, &mut buf, visit);
        }
    }

    /// The spheres of the last [`build_cells`](Grid::build_cells) as records in
    /// [`order`](Grid::order) (empty after [`build`](Grid::build)).
    pub(crate) fn sorted_spheres(&self) -> &crate::store::PackedSpheres {
        &self.sorted
    }

    /// Whether the last build ran on rayon (enough spheres, more than one thread).
    pub fn parallel(&self) -> bool {
        self.par
    }

    fn cells_of<'a>(
        &mut self,
        cols: SphereBlocks<'a>,
        t_max: f32,
        opts: GridOptions,
        records: bool,
    ) -> Option<BuildInput<'a>> {
        if !self.start(&cols, t_max, opts) {
            return None;
        }
        let n = cols.len();
        let input = BuildInput {
            cols,
            t_max,
            n,
            // One thread: the sequential path, which gives the same result without the copies.
            par: n >= PAR_MIN && rayon::current_num_threads() > 1,
            cap: 2.0 * n as f64 + 1024.0,
            records,
        };
        let histogram = self.extent_histogram(&input);
        let cells = self.choose_cells(&input, opts, &histogram);
        let n_grid = self.sort_into_cells(&input, opts.layout, cells);
        self.gather_sorted_boxes(&input);
        std::mem::swap(&mut self.order, &mut self.order_tmp);
        self.n_grid = n_grid;
        self.par = input.par;
        Some(input)
    }

    /// Checks the arguments and forgets the last pairs; keeps the previous order when the
    /// number of spheres is the same, else starts from the identity. Returns whether there is
    /// anything to build (any sphere).
    fn start(&mut self, cols: &SphereBlocks<'_>, t_max: f32, opts: GridOptions) -> bool {
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
            return false;
        }
        true
    }
}
