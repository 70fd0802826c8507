//! Steps 1 to 3 of the build (module docs): the histogram of box extents, the cell size it
//! picks, and the grid bounds under the cell cap (trimming far-away spheres when they grew it).

use rayon::prelude::*;
use wide::{f32x8, i32x8, u32x8};

use super::spheres::{SphereBlocks, boxes8, max_extent};
use super::{BuildInput, CellChoice, Grid, GridOptions, Layout, MARGIN, MIN_CELL, SPHERE_CHUNK};

/// Buckets of the extent histogram: the float's bits shifted right by [`HSHIFT`] (exponent and
/// one mantissa bit).
pub(super) const NB: usize = 512;
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

/// Statistics of a chunk of spheres: for each extent bucket the record
/// `[count, max extent, -lo_min x y z, lo_max x y z]` of the spheres in it (so that merging is
/// a lane-wise max, plus a sum in the count lane).
#[derive(Clone)]
pub(super) struct Stats {
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

/// The extent histogram over all spheres (module docs, step 1), merged over the chunks.
pub(super) struct ExtentHistogram {
    /// Spheres per bucket, in f64: a chunk's f32 count is exact, a total may not be.
    count: [f64; NB],
    /// Prefix maxima over the buckets: `prefix[b]` describes all spheres in buckets `<= b`,
    /// i.e. all spheres whose extent is at most `prefix[b]`'s max extent.
    prefix: [f32x8; NB],
}

impl Grid {
    /// Step 1: the extent histogram, per chunk of spheres (on rayon when the build is
    /// parallel), then merged.
    pub(super) fn extent_histogram(&mut self, input: &BuildInput<'_>) -> ExtentHistogram {
        let (cols, t_max, n) = (&input.cols, input.t_max, input.n);
        let nch = n.div_ceil(SPHERE_CHUNK);
        if self.stats.len() < nch {
            self.stats.resize_with(nch, Stats::new);
        }
        let work = |(ci, st): (usize, &mut Stats)| {
            stats_chunk(
                cols,
                t_max,
                ci * SPHERE_CHUNK,
                ((ci + 1) * SPHERE_CHUNK).min(n),
                st,
            )
        };
        if input.par {
            self.stats[..nch].par_iter_mut().enumerate().for_each(work);
        } else {
            self.stats[..nch].iter_mut().enumerate().for_each(work);
        }
        let mut count = [0f64; NB];
        let mut prefix = [f32x8::from(EMPTY); NB];
        for st in &self.stats[..nch] {
            for b in 0..NB {
                count[b] += st.hist[b].as_array()[0] as f64;
                prefix[b] = prefix[b].fast_max(st.hist[b]);
            }
        }
        for b in 1..NB {
            prefix[b] = prefix[b].fast_max(prefix[b - 1]);
        }
        ExtentHistogram { count, prefix }
    }

    /// Steps 2 and 3: the cell size and the bounds of the spheres that fit, then the cell cap.
    pub(super) fn choose_cells(
        &mut self,
        input: &BuildInput<'_>,
        opts: GridOptions,
        h: &ExtentHistogram,
    ) -> CellChoice {
        let (s, bounds) = self.fitted_bounds(input, opts.cell_size, h);
        self.cap_cells(input, opts, h, s, bounds)
    }

    /// Step 2: the cell size (given, or the automatic rule over the histogram) and the
    /// bounding box of the `lo` corners of the spheres whose box fits in a cell.
    fn fitted_bounds(
        &mut self,
        input: &BuildInput<'_>,
        cell_size: Option<f32>,
        h: &ExtentHistogram,
    ) -> (f32, ([f32; 3], [f32; 3])) {
        let (cols, t_max, n) = (&input.cols, input.t_max, input.n);
        let pre = &h.prefix;
        let bbox = |r: &f32x8| {
            let a = r.as_array();
            ([-a[2], -a[3], -a[4]], [a[5], a[6], a[7]])
        };
        let all = pre[NB - 1];
        let max_ext = all.as_array()[1];
        let (s, (mut lo_min, mut lo_max)) = match cell_size {
            Some(s) => (s, bbox(&all)),
            None => {
                let b = auto_bucket(&h.count, pre, n, input.cap, None);
                (pre[b].as_array()[1] * MARGIN, bbox(&pre[b]))
            }
        };
        if cell_size.is_some() && max_ext > s {
            // A given size that some boxes exceed: the bounds of those that fit need a pass.
            let parts = &mut self.bbox_parts;
            parts.clear();
            parts.resize(
                n.div_ceil(SPHERE_CHUNK),
                ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
            );
            let work = |(ci, p): (usize, &mut ([f32; 3], [f32; 3]))| {
                *p = bbox_chunk(
                    cols,
                    t_max,
                    ci * SPHERE_CHUNK,
                    ((ci + 1) * SPHERE_CHUNK).min(n),
                    s,
                )
            };
            if input.par {
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
        (s, (lo_min, lo_max))
    }

    /// Step 3: the cell cap. The cells grow until the grid over `bounds` has at most `cap`
    /// cells; if that grew them more than twofold, the bounds without the most extreme `lo`
    /// corners are tried (with the automatic size chosen again over them) and kept if they
    /// give smaller cells.
    fn cap_cells(
        &mut self,
        input: &BuildInput<'_>,
        opts: GridOptions,
        h: &ExtentHistogram,
        s: f32,
        (lo_min, lo_max): ([f32; 3], [f32; 3]),
    ) -> CellChoice {
        let (n, cap) = (input.n, input.cap);
        // Infinite boxes (finite inputs can overflow) must not make the grid infinite.
        let lo_min = lo_min.map(|x| x.clamp(-f32::MAX, f32::MAX));
        let lo_max = lo_max.map(|x| x.clamp(-f32::MAX, f32::MAX));
        let s_fit = s.clamp(MIN_CELL, f32::MAX);
        let mut s_base = s_fit;
        let (mut s, mut dims) = fit_cells(&lo_min, &lo_max, s_fit, cap);
        let mut origin = lo_min;
        if s > 2.0 * s_fit && n >= 256 && opts.layout != Layout::Sparse {
            // The cap grew the cells: the scene is sparse for its bounding box, maybe because
            // of a few far-away spheres. Try the bounds without the `trim` most extreme `lo`
            // corners on each side of each axis; those spheres are clamped into the border
            // cells (correct, as `f` stays monotone).
            // The automatic cell size is chosen again with these bounds in its cell count.
            let trim = 64 + n / 4096;
            let (tmin, tmax) = self.trimmed_bounds(&input.cols, input.t_max, trim);
            let s_fit2 = match opts.cell_size {
                Some(_) => s_fit,
                None => {
                    let ext = [0, 1, 2].map(|a| tmax[a] as f64 - tmin[a] as f64);
                    let b = auto_bucket(&h.count, &h.prefix, n, cap, Some(ext));
                    (h.prefix[b].as_array()[1] * MARGIN).clamp(MIN_CELL, f32::MAX)
                }
            };
            let (s2, dims2) = fit_cells(&tmin, &tmax, s_fit2, cap);
            s_base = s_fit2;
            if s2 < s {
                (s, dims, origin) = (s2, dims2, tmin);
            }
        }
        CellChoice {
            s,
            dims,
            origin,
            full: (lo_min, lo_max),
            s_base,
        }
    }
}

impl Grid {
    /// Per axis, the `(trim + 1)`-th smallest and largest `lo` corner of the boxes.
    fn trimmed_bounds(
        &mut self,
        cols: &SphereBlocks<'_>,
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

fn stats_chunk(cols: &SphereBlocks<'_>, t_max: f32, start: usize, end: usize, st: &mut Stats) {
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
    cols: &SphereBlocks<'_>,
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
