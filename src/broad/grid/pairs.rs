//! Step 6 of the build (module docs): every sphere against its half stencil of cells, eight
//! boxes at a time, then the oversize spheres against all before them; in fixed chunks whose
//! outputs are concatenated in order, so the pairs do not depend on the thread count.

use rayon::prelude::*;
use wide::{f32x8, u32x8};

use super::{BuildInput, Grid, OVER_CHUNK, PAIR_CHUNK};

/// The sorted boxes, keys and cell tables of the last build of `$n` spheres, as a [`View`]
/// (a macro so that it borrows only those fields of the grid).
macro_rules! view {
    ($grid:expr, $n:expr) => {{
        let (px, py) = ($grid.dims[0] as usize + 2, $grid.dims[1] as usize + 2);
        View {
            b: [0, 1, 2, 3, 4, 5].map(|k| &$grid.boxes[k][..$n + 8]),
            skey: &$grid.skey[..$n],
            cs: &$grid.cs,
            px,
            pxy: px * py,
            sparse: $grid.sparse,
            hrows: &$grid.hrows,
        }
    }};
}

/// A unit of pair-phase work: grid positions `start..end` (when `q == u32::MAX`), or
/// oversize position `q` against positions `start..end`.
#[derive(Clone, Copy)]
pub(super) struct Item {
    q: u32,
    start: u32,
    end: u32,
}

impl Grid {
    /// Step 6: the pairs of the sorted boxes, in fixed chunks of work (on rayon when the build
    /// is parallel, each chunk into its own buffer, concatenated in chunk order).
    pub(super) fn find_pairs(&mut self, input: &BuildInput<'_>) {
        let n = input.n;
        self.plan_pair_work(n, input.par);
        let items = &self.items;
        let view = view!(self, n);
        if input.par {
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
                    view.item(*it, &mut out, &mut Flush::never());
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
                view.item(*it, &mut out, &mut Flush::never());
            }
            self.npairs = out.len;
        }
    }

    /// Step 6 without a list: the same pairs, handed to `visit` a few thousand at a time from
    /// per-thread buffers (each at most [`FLUSH_AT`] plus one sphere's pairs), so the memory
    /// does not grow with the number of pairs. On rayon when the build was parallel; every
    /// pair is visited exactly once, in an order that may depend on the thread count.
    pub(super) fn visit_pairs_of(&self, n: usize, par: bool, visit: &(dyn Fn(&[[u32; 2]]) + Sync)) {
        let view = view!(self, n);
        let run = |it: &Item, buf: &mut Vec<[u32; 2]>| {
            let mut sink = |pairs: &[[u32; 2]]| visit(pairs);
            let mut flush = Flush {
                at: FLUSH_AT,
                sink: Some(&mut sink),
            };
            let mut out = Out { buf, len: 0 };
            view.item(*it, &mut out, &mut flush);
            if out.len > 0 {
                visit(&out.buf[..out.len]);
            }
        };
        if par {
            let scratch = &self.scratch;
            self.items.par_iter().for_each(|it| {
                let worker = rayon::current_thread_index().unwrap_or(0) % scratch.len();
                let mut buf = scratch[worker].lock().unwrap_or_else(|e| e.into_inner());
                run(it, &mut buf);
            });
        } else {
            let mut buf = self.scratch[0].lock().unwrap_or_else(|e| e.into_inner());
            for it in &self.items {
                run(it, &mut buf);
            }
        }
    }

    /// The chunks of pair work and one pair buffer per worker (for
    /// [`visit_pairs_of`](Self::visit_pairs_of)).
    pub(super) fn plan_pair_work(&mut self, n: usize, par: bool) {
        self.pair_items(n);
        let workers = if par { rayon::current_num_threads() } else { 1 };
        if self.scratch.len() < workers {
            self.scratch.resize_with(workers, Default::default);
        }
    }

    /// The chunks of pair work: the grid positions in chunks of `PAIR_CHUNK`, then each
    /// oversize sphere against all positions before it in chunks of `OVER_CHUNK`.
    fn pair_items(&mut self, n: usize) {
        let n_grid = self.n_grid;
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
    }
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

/// Pairs a visiting pass buffers before handing them on (16 KB: they stay in L1/L2 for the
/// narrow phase that reads them).
pub(super) const FLUSH_AT: usize = 2048;

/// Where full buffers go: to `sink` once `at` pairs are buffered (checked after each sphere, so
/// a buffer holds at most `at` plus one or two spheres' pairs); never when listing.
struct Flush<'s> {
    at: usize,
    sink: Option<&'s mut dyn FnMut(&[[u32; 2]])>,
}

impl Flush<'_> {
    /// Listing: the buffer only grows.
    fn never() -> Self {
        Flush {
            at: usize::MAX,
            sink: None,
        }
    }

    /// Hands the first `len` pairs of `buf` on if that is a full buffer; the new length.
    #[inline(always)]
    fn check(&mut self, buf: &[[u32; 2]], len: usize) -> usize {
        if len < self.at {
            return len;
        }
        if let Some(sink) = self.sink.as_mut() {
            sink(&buf[..len]);
        }
        0
    }
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

    fn item(&self, it: Item, out: &mut Out<'_>, flush: &mut Flush<'_>) {
        let (start, end) = (it.start as usize, it.end as usize);
        if it.q == u32::MAX {
            out.len = if self.sparse {
                self.grid_range::<true>(start, end, out.buf, out.len, flush)
            } else {
                self.grid_range::<false>(start, end, out.buf, out.len, flush)
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
            out.len = flush.check(out.buf, out.len);
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
        flush: &mut Flush<'_>,
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
                len = flush.check(buf, len);
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
                len = flush.check(buf, len);
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
