//! The spheres as the grid reads them, and their swept boxes eight at a time.

use wide::{f32x8, u32x8};

use crate::store::{SphereBlock, SphereStore};

/// The spheres as the grid reads them: the store's blocks of eight (AoSoA) and the count.
///
/// All values are finite and radii non-negative (the store validated them); sphere `i` is lane
/// `i % 8` of block `i / 8`.
#[derive(Clone, Copy, Debug)]
pub struct SphereBlocks<'a> {
    blocks: &'a [SphereBlock],
    n: usize,
}

impl<'a> SphereBlocks<'a> {
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
    pub(super) fn at(&self, i: usize) -> ([f32; 3], [f32; 3], f32) {
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
pub fn swept_box(cols: &SphereBlocks<'_>, i: usize, t_max: f32) -> ([f32; 3], [f32; 3]) {
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

/// Swept boxes of spheres `i..i+8` (lanes past the end are zero spheres): one block's
/// columns when `i` starts a full block, else lane by lane.
#[inline(always)]
pub(super) fn boxes8(cols: &SphereBlocks<'_>, i: usize, t: f32x8) -> ([f32x8; 3], [f32x8; 3]) {
    let (c, v, r) = spheres8(cols, i);
    boxes_of8(&c, &v, r, t)
}

/// Centres, velocities and radii of spheres `i..i+8` as lanes (lanes past the end are zero
/// spheres).
#[inline(always)]
pub(super) fn spheres8(cols: &SphereBlocks<'_>, i: usize) -> ([f32x8; 3], [f32x8; 3], f32x8) {
    if i.is_multiple_of(8) && i + 8 <= cols.n {
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
    }
}

/// The swept boxes of lanes of spheres: the grid's one definition (module docs).
#[inline(always)]
pub(super) fn boxes_of8(
    c: &[f32x8; 3],
    v: &[f32x8; 3],
    r: f32x8,
    t: f32x8,
) -> ([f32x8; 3], [f32x8; 3]) {
    let mut lo = [f32x8::ZERO; 3];
    let mut hi = [f32x8::ZERO; 3];
    for a in 0..3 {
        let e = c[a] + v[a] * t;
        lo[a] = c[a].fast_min(e) - r;
        hi[a] = c[a].fast_max(e) + r;
    }
    (lo, hi)
}

/// One sphere's swept box with the same float operations as [`boxes_of8`] (`vminps(c, e)` /
/// `vmaxps(c, e)`, as `fast_min` / `fast_max` there).
#[inline(always)]
pub(super) fn box_of(c: [f32; 3], v: [f32; 3], r: f32, t_max: f32) -> [f32; 6] {
    let mut b = [0.0; 6];
    for a in 0..3 {
        let e = c[a] + v[a] * t_max;
        b[a] = (if c[a] < e { c[a] } else { e }) - r;
        b[3 + a] = (if c[a] > e { c[a] } else { e }) + r;
    }
    b
}

/// Largest extent of each box, as non-negative float bits.
#[inline(always)]
pub(super) fn max_extent(lo: &[f32x8; 3], hi: &[f32x8; 3]) -> u32x8 {
    let e = (hi[0] - lo[0])
        .fast_max(hi[1] - lo[1])
        .fast_max(hi[2] - lo[2]);
    e.to_bits() & u32x8::splat(0x7FFF_FFFF)
}
