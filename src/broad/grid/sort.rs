//! Steps 4 and 5 of the build (module docs): the cell keys, the sort into cell order (a
//! counting sort for the dense layout, a radix sort for the sparse one), and the boxes gathered
//! into sorted columns.

use rayon::prelude::*;
use wide::{f32x8, i32x8, u32x8};

use super::spheres::{SphereBlocks, box_of, boxes_of8, spheres8};
use super::{BuildInput, CellChoice, Grid, Layout, SPHERE_CHUNK};
use crate::store::Packed;

/// One sphere as the key pass writes it and the gather reads it: centre, velocity, radius
/// (the store's packed record), from which the gather recomputes the box and which it copies
/// into cell order for the narrow phase.
pub(super) type Rec = Packed;

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

impl Grid {
    /// Steps 4 and 5 up to the sorted order: the layout, the keys (and box records unless the
    /// store is in grid order) and the sort into cell order, into `order_tmp` and `skey`.
    /// Settles the layout, cell size and dims; returns the number of grid (non-oversize)
    /// spheres.
    pub(super) fn sort_into_cells(
        &mut self,
        input: &BuildInput<'_>,
        layout: Layout,
        cells: CellChoice,
    ) -> usize {
        let n = input.n;
        let CellChoice {
            mut s,
            mut dims,
            mut origin,
            full,
            s_base,
        } = cells;
        // The dense layout unless asked otherwise, or (automatic) unless the cap grew the
        // cells more than twofold and the counts then show crowded cells.
        let maybe_sparse = layout == Layout::Auto && n >= 256 && s > 2.0 * s_base;
        // If the last build of this size went sparse for the same reason, go straight there.
        let mut sparse =
            layout == Layout::Sparse || (maybe_sparse && self.sparse && self.sparse_n == n);
        let coherent = self.coherent;
        self.size_sort_buffers(n, coherent);
        let mut ncells = 0;
        let dense_ran = !sparse;
        if !sparse {
            ncells = self.dense_keys(input, &Geom::new(origin, s, dims), coherent);
            if maybe_sparse {
                sparse = self.crowded(n);
            }
        }
        if sparse {
            (origin, s, dims) = sparse_cells(full, s_base);
        }
        self.sparse = sparse;
        self.sparse_n = n;
        self.cell_size = s;
        self.dims = dims;
        let (px, py) = (dims[0] as usize + 2, dims[1] as usize + 2);
        if sparse {
            let geom = Geom::new(origin, s, dims);
            self.vkeys.resize(n, 0);
            // The box records, if needed, are already written when the dense pass ran.
            let records_done = coherent || dense_ran;
            key_pass(
                &input.cols,
                input.t_max,
                &geom,
                records_done,
                input.par,
                &mut self.recs,
                &mut self.vkeys[..n],
            );
            self.sparse_sort(n, px as u64, (px * py) as u64)
        } else {
            self.dense_scatter(n, ncells)
        }
    }

    /// The sort's buffers for `n` spheres (the box records only when the store is not in grid
    /// order).
    fn size_sort_buffers(&mut self, n: usize, coherent: bool) {
        if !coherent {
            self.recs.resize(n, Packed::default());
        }
        self.order_tmp.resize(n, 0);
        self.skey.resize(n, 0);
        for b in self.boxes.iter_mut() {
            b.resize(n + 8, 0.0);
        }
    }

    /// Dense layout, step 4 and the counts of step 5: the keys, and box records unless the
    /// store is in (nearly) grid order (then the boxes are recomputed from the columns, read
    /// nearly sequentially, when gathered). Returns the size of the cell table.
    fn dense_keys(&mut self, input: &BuildInput<'_>, geom: &Geom, coherent: bool) -> usize {
        let n = input.n;
        let ncells = geom.over_key as usize;
        self.keys.resize(n, 0);
        key_pass(
            &input.cols,
            input.t_max,
            geom,
            coherent,
            input.par,
            &mut self.recs,
            &mut self.keys[..n],
        );
        self.dense_count(n, ncells, input.par);
        ncells
    }

    /// Whether the dense counts show crowded cells: the mean number of spheres sharing a
    /// sphere's cell above `CROWDED`, past which the extra passes of the sparse layout cost
    /// less than the crowded cells.
    fn crowded(&self, n: usize) -> bool {
        let load = self.cs.iter().map(|&c| c as f64 * c as f64).sum::<f64>() / n as f64;
        load > CROWDED
    }

    /// End of step 5: the boxes gathered by position into the sorted columns (from the
    /// records, or recomputed from the columns when the store is in grid order), counting the
    /// 8-blocks of positions whose indices are consecutive: if most are, the store is in grid
    /// order and the next build skips the records.
    pub(super) fn gather_sorted_boxes(&mut self, input: &BuildInput<'_>) {
        let (cols, t_max, n) = (&input.cols, input.t_max, input.n);
        let coherent = self.coherent;
        // The records in cell order too, when the caller asked for them (the query's narrow
        // phase reads them); else an empty column.
        let records = if input.records { n } else { 0 };
        self.sorted.0.resize(records, Packed::default());
        let [lx, ly, lz, hx, hy, hz] = &mut self.boxes;
        let recs = &self.recs[..];
        let ot = &self.order_tmp[..n];
        let work = |c: &[u32], out: [&mut [f32]; 6], sorted: &mut [Packed]| {
            if coherent {
                gather_cols(cols, t_max, c, out, sorted)
            } else {
                gather_boxes(recs, t_max, c, out, sorted)
            }
        };
        let sorted = &mut self.sorted.0[..];
        let runs: usize = if input.par {
            let sorted = if records > 0 {
                rayon::iter::Either::Left(sorted.par_chunks_mut(SPHERE_CHUNK))
            } else {
                let chunks = n.div_ceil(SPHERE_CHUNK);
                let none = |_| -> &mut [Packed] { &mut [] };
                rayon::iter::Either::Right((0..chunks).into_par_iter().map(none))
            };
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
                .zip(sorted)
                .map(|((c, (((((lx, ly), lz), hx), hy), hz)), s)| {
                    work(c, [lx, ly, lz, hx, hy, hz], s)
                })
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
                sorted,
            )
        };
        self.coherent = runs * 8 * 2 >= n;
    }
}

/// The sparse layout's cells: the cell size chosen before the cap (`s_base`) over the full
/// bounds of the fitting `lo` corners, grown only so that no axis has more than `HMAX` cells.
/// Returns the origin, the cell size and the cells per axis.
fn sparse_cells(
    (full_min, full_max): ([f32; 3], [f32; 3]),
    s_base: f32,
) -> ([f32; 3], f32, [u32; 3]) {
    let ext = [0, 1, 2].map(|a| full_max[a] as f64 - full_min[a] as f64);
    let s = s_base.max((ext.iter().cloned().fold(0.0, f64::max) / (HMAX - 1) as f64) as f32);
    let dims = ext.map(|e| ((e / s as f64).floor() as u32 + 1).min(HMAX));
    (full_min, s, dims)
}

impl Grid {
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

/// Write the boxes of spheres `idx`, recomputed from their records `recs`, into the six
/// sorted columns, and the records themselves into `sorted` unless it is empty; returns
/// [`runs8`] of `idx`.
fn gather_boxes(
    recs: &[Rec],
    t_max: f32,
    idx: &[u32],
    cols: [&mut [f32]; 6],
    sorted: &mut [Packed],
) -> usize {
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
    let copy = !sorted.is_empty();
    for j in 0..m {
        let rec = recs[idx[j] as usize];
        let [cx, cy, cz, vx, vy, vz, r, _] = rec.0;
        let b = box_of([cx, cy, cz], [vx, vy, vz], r, t_max);
        lx[j] = b[0];
        ly[j] = b[1];
        lz[j] = b[2];
        hx[j] = b[3];
        hy[j] = b[4];
        hz[j] = b[5];
        if copy {
            sorted[j] = rec;
        }
    }
    runs8(idx)
}

/// Write the boxes of spheres `idx`, recomputed from the columns, into the six sorted
/// columns: 8 at a time where `idx` holds 8 consecutive indices, else one by one (with the
/// same float operations as [`boxes_of8`]); and the spheres' records into `sorted` unless it
/// is empty. Returns [`runs8`] of `idx`.
fn gather_cols(
    cols: &SphereBlocks<'_>,
    t_max: f32,
    idx: &[u32],
    out: [&mut [f32]; 6],
    sorted: &mut [Packed],
) -> usize {
    if !sorted.is_empty() {
        for (slot, &i) in sorted.iter_mut().zip(idx) {
            let (c, v, r) = cols.at(i as usize);
            *slot = Packed([c[0], c[1], c[2], v[0], v[1], v[2], r, 0.0]);
        }
    }
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
            let (cc, vv, rr) = spheres8(cols, c[0] as usize);
            let (lo, hi) = boxes_of8(&cc, &vv, rr, t);
            for a in 0..3 {
                *o[a][j..].first_chunk_mut::<8>().unwrap() = lo[a].to_array();
                *o[3 + a][j..].first_chunk_mut::<8>().unwrap() = hi[a].to_array();
            }
            j += 8;
            continue;
        }
        for l in j..(j + 8).min(m) {
            let (c, v, r) = cols.at(idx[l] as usize);
            let b = box_of(c, v, r, t_max);
            for a in 0..6 {
                o[a][l] = b[a];
            }
        }
        j += 8;
    }
    runs
}

/// The key pass over all spheres: keys, and box records unless `coherent`.
fn key_pass<K: Key>(
    cols: &SphereBlocks<'_>,
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
    cols: &SphereBlocks<'_>,
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
        let (c, v, r) = spheres8(cols, start + j);
        let (lo, hi) = boxes_of8(&c, &v, r, t);
        let gl = [cell(lo[0], 0), cell(lo[1], 1), cell(lo[2], 2)];
        let gh = [cell(hi[0], 0), cell(hi[1], 1), cell(hi[2], 2)];
        let over = (gh[0] - gl[0]).simd_gt(one)
            | (gh[1] - gl[1]).simd_gt(one)
            | (gh[2] - gl[2]).simd_gt(one);
        let ka = K::make(&gl, over, g);
        let m = (len - j).min(8);
        keys[j..j + m].copy_from_slice(&ka[..m]);
        if write {
            let rows = f32x8::transpose([c[0], c[1], c[2], v[0], v[1], v[2], r, zero]);
            for l in 0..m {
                recs[j + l] = Packed(rows[l].to_array());
            }
        }
        j += 8;
    }
}
