//! Sphere `i`'s neighbour list, rebuilt from the cells around its shell centre at its shell
//! event (`rebuild_list`): the 27 cells' members copied out as entries (`cells_near`), then
//! those within reach kept, four at a time (`within_reach`). An entry of both the old and the
//! new list stays where it is in the other sphere's list. Both passes have no branch on what
//! they load, and load the shell centres through `passes::named` (every lane names a sphere:
//! `passes.rs`).

use wide::{f64x4, u32x4, u32x8};

use super::lists::{Before, CODE_BITS, NO_SHIFT, Shell, entry, mirror, split};
use super::passes::{KEPT_FIRST, named};
use super::*;
use crate::sim::cells::HEAD;

impl<
    R: Responder,
    const PERIODIC: bool,
    const WALLS: bool,
    const GEOMETRY: bool,
    const GRAVITY: bool,
> Engine<R, PERIODIC, WALLS, GEOMETRY, GRAVITY>
{
    /// Sphere `i`'s new list after its shell event (its centre already moved, into cell
    /// `ci`): every sphere whose centre is within reach. An entry of both the old and the new
    /// list stays where it is in the other sphere's list; a new one is added to it, and an old
    /// one not kept is removed from it. The entries naming a sphere that was not in the old
    /// list go into `fresh` when `track_fresh` (a box of fewer than three cells a side
    /// predicts the whole list and skips it).
    pub(super) fn rebuild_list(&mut self, i: u32, ci: [i32; 3], track_fresh: bool) {
        self.lists.next_epoch();
        let mut old = std::mem::take(&mut self.old);
        old.clear();
        old.extend_from_slice(self.lists.of(i));
        for &e in &old {
            self.lists.mark_old(e);
        }
        let count = self.within_reach(i, ci);
        // Taken out for the loops, which then read it as one slice (no bounds check or reload
        // of the vector an entry).
        let found = std::mem::take(&mut self.found);
        self.fresh.clear();
        for &e in &found[..count] {
            let before = self.lists.match_new(e);
            if before != Before::Same {
                let (j, code) = split(e);
                self.lists.push(j, entry(i, mirror(code)));
            }
            if track_fresh && before == Before::Absent {
                self.fresh.push(e);
            }
        }
        self.fresh_len = self.fresh.len();
        self.fresh.extend_from_slice(&[0; 3]);
        self.fresh.truncate(self.fresh_len.next_multiple_of(4));
        for &e in &old {
            if !self.lists.was_kept(e) {
                let (j, code) = split(e);
                self.lists.remove(j, entry(i, mirror(code)));
            }
        }
        self.old = old;
        self.lists.set(i, &found[..count]);
        self.found = found;
    }

    /// Builds every list from the centres alone (at the start and after loading a
    /// checkpoint): the same lists the shell events keep, since the test is symmetric.
    pub(super) fn build_lists(&mut self) {
        for i in 0..self.m.bodies.len() as u32 {
            self.lists.clear(i);
            let ci = self.cells.coords_of(self.lists.centre[i as usize].c);
            let found = self.within_reach(i, ci);
            for k in 0..found {
                self.lists.push(i, self.found[k]);
            }
        }
    }

    /// Every sphere `j ≠ i` (with its image's shift code) whose shell centre is within
    /// `dᵢⱼ + reach` of `i`'s, from the 27 cells around `i`'s, into the first entries of
    /// `found`; returns how many. The test
    /// computes `(cⱼ − cᵢ) + shift`, the exact negative of what `j` computes for `i`, so the
    /// lists are symmetric to the bit. Two passes with no branch on the data: the entries of
    /// the 27 cells are copied out (`cells_near`), then each is tested, in lanes of four.
    fn within_reach(&mut self, i: u32, ci: [i32; 3]) -> usize {
        let candidates = self.cells_near(i, ci);
        if self.fetch_neighbours {
            self.fetch_gathered_shells(candidates);
        }
        let centre = &self.lists.centre[..];
        let si = centre[i as usize];
        // Lane by lane the operations of `(cⱼ − cᵢ) + shift` on vectors, in the same order:
        // the fourth lane is `radiusⱼ − (−radiusᵢ)`, to the bit `radiusᵢ + radiusⱼ` (and the
        // shift's fourth lane is zero).
        let ci_lanes = f64x4::new([si.c.x, si.c.y, si.c.z, -si.radius]);
        let reach = f64x4::splat(self.lists.reach);
        let own = entry(i, NO_SHIFT);
        // Four candidates at a time: `gathered` has room past the last (`cells_near`); the
        // lanes past it are read and their spheres' centres loaded, so each names a sphere
        // (`cells_near`), but they are not counted.
        let rounded = candidates.next_multiple_of(4);
        let mut found = std::mem::take(&mut self.found);
        if found.len() < rounded {
            found.resize(rounded, 0);
        }
        // Sphere `i` is there once, under the code of no shift, and is not counted. Its
        // images are a box length away, and a periodic box is at least three largest
        // diameters (`assemble.rs`), more than `2rᵢ + reach` (at most 2.9 diameters, and the
        // margins: `PERIODIC_SHELL_CAP`); an open domain has no images.
        let mut len = 0;
        for (at, four) in self.gathered[..rounded]
            .as_chunks::<4>()
            .0
            .iter()
            .enumerate()
        {
            let relative = |k: usize| {
                let (j, code) = split(four[k]);
                // SAFETY: every lane of `gathered` names a sphere (`passes.rs`).
                let cj = unsafe { named(centre, j) };
                (shell_lanes(cj) - ci_lanes) + self.shift[usize::from(code)]
            };
            let dr = [relative(0), relative(1), relative(2), relative(3)];
            // The same sums as `DVec3::length_squared`, four pairs at once.
            let [x, y, z, sum] = f64x4::transpose(dr);
            let d = sum + reach;
            let within = (x * x + y * y + z * z).simd_le(d * d).to_bitmask();
            let own_lane = u32x4::new(*four).simd_eq(u32x4::splat(own)).to_bitmask();
            let within = within & !own_lane & ((1 << (candidates - 4 * at).min(4)) - 1);
            // The entries kept moved to the front, in order, and written at once.
            let packed = u32x4::new(*four).shuffle(KEPT_FIRST[within as usize & 15]);
            found[len..len + 4].copy_from_slice(packed.as_array());
            len += within.count_ones() as usize;
        }
        self.found = found;
        len
    }

    /// Copies the members of the 27 cells around sphere `i`'s shell centre (in cell `ci`)
    /// into `gathered` as list entries (with their image's shift code); returns how many. A cell
    /// that cannot hold a centre within reach is copied too, but not counted (the next copy
    /// overwrites it): a cell's whole record is copied whatever it holds, so the loop has no
    /// branch on the cells' contents. Every lane copied names a sphere (the count's lane is
    /// copied as sphere 0): the last copy stays past the entries counted, where `within_reach`
    /// reads it. The rare members past a record's seventh go after the rest.
    fn cells_near(&mut self, i: u32, ci: [i32; 3]) -> usize {
        if self.gathered.len() < GATHER_ROOM {
            self.gathered.resize(GATHER_ROOM, 0);
        }
        let si = self.lists.centre[i as usize];
        let far = self.lists.far * self.lists.far;
        let Stencil {
            axes: [ax, ay, az],
            gap,
        } = self.stencil.around(&self.cells, ci, si.c);
        let (cells, spilled) = (&self.cells, &mut self.spilled);
        let records = cells.records();
        spilled.clear();
        let head: &mut [u32; GATHER_ROOM] = (&mut self.gathered[..GATHER_ROOM])
            .try_into()
            .expect("the gathered entries have their room");
        let mut len = 0;
        for z in 0..3 {
            for y in 0..3 {
                // What a row's three cells share.
                let row = az.part[z] + ay.part[y];
                let row_code = az.code[z] + ay.code[y];
                let row_gap = gap[2][z] + gap[1][y];
                let row_inside = az.inside[z] & ay.inside[y];
                for (x, gap_x) in gap[0].into_iter().enumerate() {
                    // A cell beyond an open domain's edge, or farther than the widest reach,
                    // holds nobody within reach: its copy (of cell 0 instead, beyond an edge)
                    // is not counted.
                    let near = row_inside & ax.inside[x] & (row_gap + gap_x <= far);
                    let code = row_code + ax.code[x];
                    let cell = row + ax.part[x];
                    let record = &records[cell];
                    // The record's eight lanes as entries (`entry`, lane by lane), at once;
                    // `len` is at most 26 records' worth, so the mask changes nothing and
                    // spares a bounds check. The count's lane becomes sphere 0: lanes past
                    // `len` are read (and indexed by) `within_reach`, so every lane copied
                    // must name a sphere.
                    let members = u32x8::new(record.0) & MEMBER_LANES;
                    let lanes = (members << CODE_BITS) | u32x8::splat(u32::from(code));
                    let at = len & GATHER_MASK;
                    head[at..at + HEAD + 1].copy_from_slice(lanes.as_array());
                    let count = record.count();
                    if count > HEAD && near {
                        spilled.extend(cells.spill(cell).iter().map(|&j| entry(j, code)));
                    }
                    len += usize::from(near) * count.min(HEAD);
                }
            }
        }
        debug_assert!(len <= 27 * HEAD);
        if !spilled.is_empty() {
            let total = len + spilled.len();
            if self.gathered.len() < total + 4 {
                self.gathered.resize(total + 4, 0);
            }
            self.gathered[len..total].copy_from_slice(spilled);
            len = total;
        }
        len
    }
}

/// A shell centre and its radius as lanes of four, as they lie in memory.
#[inline(always)]
fn shell_lanes(s: &Shell) -> f64x4 {
    f64x4::new([s.c.x, s.c.y, s.c.z, s.radius])
}

/// The room `gathered` always has: the records of 27 cells and one more copy, below a power
/// of two (`GATHER_MASK`) and its copy.
const GATHER_ROOM: usize = GATHER_MASK + 1 + HEAD + 1;

/// Keeps a record's seven member lanes and zeroes its count's (`cells_near`).
const MEMBER_LANES: u32x8 = u32x8::new([!0, !0, !0, !0, !0, !0, !0, 0]);

/// One less than a power of two above every length the records of 26 cells can fill.
const GATHER_MASK: usize = 255;

/// The 3 × 3 × 3 cells around a shell centre, per axis and offset −1, 0, +1: a cell's index,
/// shift code, gap and whether it is inside the domain are sums (and) of its three axes' parts.
struct Stencil<'a> {
    /// Each axis' parts, borrowed from the table (a copy through the stack, stored and
    /// reloaded in pieces of other widths, stalled every rebuild on the store buffer).
    axes: [&'a AxisPart; 3],
    /// The squared distance from the centre to the neighbour cell's slab: a lower bound for
    /// any centre in it, or its image. A cell farther than the widest reach holds nobody within
    /// reach (`far` has a margin above the faces' rounding).
    gap: [[f64; 3]; 3],
}

/// One axis' part of the stencil around a cell coordinate, for offsets −1, 0, +1.
#[derive(Debug, Clone, Copy, Default)]
struct AxisPart {
    /// The axis' part of the cell index: the wrapped coordinate times the axis' stride (0
    /// outside an open domain: cell 0 stands in).
    part: [usize; 3],
    /// The axis' part of the shift code: its digit (0, 1, 2 for −1, 0, +1 box lengths) times
    /// 1, 3 or 9.
    code: [u8; 3],
    /// Whether the axis' coordinate is inside the domain (always, periodic).
    inside: [bool; 3],
}

/// Each axis' stencil parts, per cell coordinate, made once for the grid: a rebuild looks its
/// stencil up instead of wrapping nine coordinates.
#[derive(Debug, Clone, Default)]
pub(super) struct StencilTable {
    axes: [Vec<AxisPart>; 3],
}

impl StencilTable {
    /// The table of `cells`, wrapping (`periodic`) or marking the cells beyond an open domain's
    /// edge as outside.
    pub(super) fn new(cells: &Cells, periodic: bool) -> Self {
        let n = cells.n;
        let stride = [1, n[0] as usize, n[0] as usize * n[1] as usize];
        let axes = [0, 1, 2].map(|k| {
            (0..n[k])
                .map(|at| {
                    let mut axis = AxisPart::default();
                    for (o, d) in (-1..=1).enumerate() {
                        let (mut c, mut digit, mut inside) = (at + d, 1u8, true);
                        if c < 0 || c >= n[k] {
                            if periodic {
                                let wrap = if c < 0 { 1 } else { -1 };
                                c += wrap * n[k];
                                digit = (1 - wrap) as u8;
                            } else {
                                (c, inside) = (0, false);
                            }
                        }
                        axis.part[o] = c as usize * stride[k];
                        axis.code[o] = digit * [1, 3, 9][k];
                        axis.inside[o] = inside;
                    }
                    axis
                })
                .collect()
        });
        Self { axes }
    }

    /// Bytes the table holds (a few per cell along each axis).
    pub(super) fn bytes(&self) -> usize {
        self.axes
            .iter()
            .map(|a| a.capacity() * std::mem::size_of::<AxisPart>())
            .sum()
    }

    /// The indices of the 27 cells around cell `ci` (each axis' three parts, summed as in
    /// `cells_near`): for fetching ahead.
    #[inline]
    pub(super) fn cell_parts(&self, ci: [i32; 3]) -> [[usize; 3]; 3] {
        self.axes_at(ci).map(|axis| axis.part)
    }

    /// Each axis' parts at cell `ci`.
    #[inline]
    fn axes_at(&self, ci: [i32; 3]) -> [&AxisPart; 3] {
        let axis = |k: usize| &self.axes[k][ci[k] as usize];
        [axis(0), axis(1), axis(2)]
    }

    /// The stencil around centre `c`, in cell `ci`.
    #[inline]
    fn around(&self, cells: &Cells, ci: [i32; 3], c: DVec3) -> Stencil<'_> {
        let gap = |k: usize| {
            let below = c[k] - (cells.lo[k] + f64::from(ci[k]) * cells.w[k]);
            let above = cells.w[k] - below;
            [below * below, 0.0, above * above]
        };
        Stencil {
            axes: self.axes_at(ci),
            gap: [gap(0), gap(1), gap(2)],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cells fetched ahead of a rebuild (`cell_parts`) are the 27 around the cell,
    /// wrapped, in a periodic grid: each index is that of the neighbour cell's coordinates.
    #[test]
    fn the_cells_fetched_ahead_are_the_27_around() {
        let cells = Cells::new(DVec3::ZERO, DVec3::new(5.0, 4.0, 3.0), 1.0, 1000);
        assert_eq!(cells.n, [5, 4, 3]);
        let table = StencilTable::new(&cells, true);
        for ci in [[0, 0, 0], [4, 3, 2], [2, 1, 1]] {
            let [x, y, z] = table.cell_parts(ci);
            for (dz, pz) in (-1..=1).zip(z) {
                for (dy, py) in (-1..=1).zip(y) {
                    for (dx, px) in (-1..=1).zip(x) {
                        let wrap = |k: usize, d: i32| (ci[k] + d).rem_euclid(cells.n[k]);
                        let c = [wrap(0, dx), wrap(1, dy), wrap(2, dz)];
                        assert_eq!(pz + py + px, cells.index(c), "{ci:?} + {dx},{dy},{dz}");
                    }
                }
            }
        }
    }
}
