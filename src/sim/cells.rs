//! The engine's cell list of shell centres: a uniform grid of cells at least one largest
//! diameter and the shell wide, each a fixed record of eight `u32` (seven members and the
//! count) with the rare members past the seventh in a side table, so a sphere moves between
//! cells at its shell event by a scan of its old cell's few members and a push, and a list
//! rebuild reads a cell as one 32-byte load at a fixed offset, with one bounds check (the
//! generator uses the grid for spacing too). A sphere's cell is not stored: it is `coords_of` its shell centre.
//! Periodic boxes wrap; an open domain clamps, so its outermost cells reach to infinity (a
//! sphere that leaves the domain stays in an edge cell and is still found by its neighbours).

use std::collections::HashMap;

use glam::DVec3;

/// "No sphere".
pub(crate) const NONE: u32 = u32::MAX;

/// Members a cell holds in its record; the rest go to the side table (`Cells::spill`).
pub(crate) const HEAD: usize = 7;

/// A cell's record: its first [`HEAD`] members, then its count in the last lane. Aligned so
/// that a rebuild reads it as one 32-byte load.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(32))]
pub(crate) struct Cell(pub [u32; HEAD + 1]);

impl Cell {
    /// How many spheres the cell holds (its record's and the side table's).
    #[inline(always)]
    pub fn count(&self) -> usize {
        self.0[HEAD] as usize
    }
}

/// The grid and its cell arrays.
#[derive(Debug, Clone)]
pub(crate) struct Cells {
    /// Cells per axis.
    pub n: [i32; 3],
    /// Lower corner of the domain.
    pub lo: DVec3,
    /// Cell width per axis.
    pub w: DVec3,
    /// Box lengths (periodic), `n · w`.
    pub len: DVec3,
    /// Their reciprocals, for the nearest image of a colliding pair (`Engine::collide_pair`).
    pub inv_len: DVec3,
    /// Each cell's record. A sphere's cell is not stored: it is `coords_of` its shell
    /// centre, which moves at each of its shell events (and the sphere with it, when the
    /// cell changes).
    cells: Vec<Cell>,
    /// The members past the [`HEAD`]th of the cells that have more, in order.
    spill: HashMap<usize, Vec<u32>>,
}

impl Cells {
    /// A grid over `[lo, lo + extent]` with cells no narrower than `min_width`, at most
    /// `max_cells` in all.
    pub fn new(lo: DVec3, extent: DVec3, min_width: f64, max_cells: usize) -> Self {
        let mut n = [0i32; 3];
        let budget = max_cells.max(1) as f64;
        // Largest per-axis counts with width ≥ min_width, shrunk evenly to fit the budget.
        let raw: [f64; 3] = [0, 1, 2].map(|k| (extent[k] / min_width).floor().clamp(1.0, 1e6));
        let total: f64 = raw.iter().product();
        let scale = if total > budget {
            (budget / total).cbrt()
        } else {
            1.0
        };
        for k in 0..3 {
            n[k] = ((raw[k] * scale).floor() as i32).max(1);
        }
        let w = DVec3::new(
            extent.x / f64::from(n[0]),
            extent.y / f64::from(n[1]),
            extent.z / f64::from(n[2]),
        );
        let cells = (n[0] as usize) * (n[1] as usize) * (n[2] as usize);
        Self {
            n,
            lo,
            w,
            len: extent,
            inv_len: 1.0 / extent,
            cells: super::pages::filled(Cell::default(), cells),
            spill: HashMap::new(),
        }
    }

    /// Point `p` taken into the periodic box `[0, len)` by whole box lengths (`x − L·floor(x/L)`,
    /// which can round up to `L` itself).
    #[inline]
    pub fn wrap(&self, p: DVec3) -> DVec3 {
        p - self.len * self.image(p)
    }

    /// Which periodic image of the box `p` lies in, in whole box lengths (`floor(x/L)`):
    /// [`wrap`](Self::wrap) takes it away.
    #[inline]
    pub fn image(&self, p: DVec3) -> DVec3 {
        (p / self.len).floor()
    }

    /// The (clamped) cell coordinates of a point.
    #[inline]
    pub fn coords_of(&self, p: DVec3) -> [i32; 3] {
        let q = (p - self.lo) / self.w;
        let axis = |k: usize| (q[k].floor().clamp(-1.0, 1e9) as i32).clamp(0, self.n[k] - 1);
        [axis(0), axis(1), axis(2)]
    }

    #[inline]
    pub fn index(&self, c: [i32; 3]) -> usize {
        ((c[2] as usize * self.n[1] as usize) + c[1] as usize) * self.n[0] as usize + c[0] as usize
    }

    /// The spheres in cell `cell` (an [`index`](Self::index)), in their order.
    pub fn members(&self, cell: usize) -> impl Iterator<Item = u32> + '_ {
        let c = &self.cells[cell];
        c.0[..c.count().min(HEAD)]
            .iter()
            .chain(self.spill(cell))
            .copied()
    }

    /// Every cell's record (its first [`HEAD`] members and its count), by
    /// [`index`](Self::index).
    #[inline(always)]
    pub fn records(&self) -> &[Cell] {
        &self.cells
    }

    /// Cell `cell`'s members past the [`HEAD`]th (none, nearly always).
    #[inline]
    pub fn spill(&self, cell: usize) -> &[u32] {
        self.spill.get(&cell).map_or(&[], |v| &v[..])
    }

    /// Adds sphere `i` to cell `c`.
    #[inline]
    pub fn insert(&mut self, i: u32, c: [i32; 3]) {
        let cell = self.index(c);
        let record = &mut self.cells[cell].0;
        let k = record[HEAD] as usize;
        if k < HEAD {
            record[k] = i;
        } else {
            self.spill.entry(cell).or_default().push(i);
        }
        record[HEAD] += 1;
    }

    /// Removes sphere `i` from cell `c`, where it is (the cell's last member, in its record
    /// or its spill, takes its place; a cell holds a few spheres, so finding it is a short
    /// scan).
    #[inline]
    pub fn remove(&mut self, i: u32, c: [i32; 3]) {
        let cell = self.index(c);
        let record = &mut self.cells[cell].0;
        let count = record[HEAD] as usize;
        let last = if count > HEAD {
            let spill = self
                .spill
                .get_mut(&cell)
                .expect("a cell past its record spills");
            let last = spill.pop().expect("a cell past its record spills");
            if spill.is_empty() {
                self.spill.remove(&cell);
            }
            last
        } else if count > 0 {
            record[count - 1]
        } else {
            debug_assert!(false, "sphere {i} is not in empty cell {c:?}");
            return;
        };
        record[HEAD] -= 1;
        if last == i {
            return;
        }
        // `i` is in the record or the spill; the last member takes its place.
        if let Some(k) = record[..(count - 1).min(HEAD)].iter().position(|&x| x == i) {
            record[k] = last;
        } else if let Some(x) = self
            .spill
            .get_mut(&cell)
            .and_then(|s| s.iter_mut().find(|x| **x == i))
        {
            *x = last;
        } else {
            // Not there: put the last member back.
            debug_assert!(false, "sphere {i} is not in cell {c:?}");
            record[HEAD] += 1;
            if count > HEAD {
                self.spill.entry(cell).or_default().push(last);
            }
        }
    }

    /// Cells in the grid.
    pub fn cell_count(&self) -> usize {
        self.cells.len()
    }

    /// Bytes the grid holds.
    pub fn bytes(&self) -> usize {
        let spilled: usize = self.spill.values().map(|v| v.capacity() * 4 + 40).sum();
        self.cells.capacity() * size_of::<Cell>() + spilled
    }

    /// Empties every cell.
    pub fn clear(&mut self) {
        self.cells.fill(Cell::default());
        self.spill.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn width_never_below_the_minimum_and_budget_holds() {
        let c = Cells::new(DVec3::ZERO, DVec3::new(10.0, 3.5, 100.0), 1.0, 1000);
        assert!(c.w.min_element() >= 1.0);
        assert!(c.cell_count() <= 1000, "{:?}", c.n);
        let c = Cells::new(DVec3::ZERO, DVec3::splat(10.0), 1.0, 1 << 20);
        assert_eq!(c.n, [10, 10, 10]);
    }

    #[test]
    fn lists_insert_and_remove() {
        let mut c = Cells::new(DVec3::ZERO, DVec3::splat(4.0), 1.0, 64);
        for i in 0..3 {
            c.insert(i, [1, 1, 1]);
        }
        c.remove(1, [1, 1, 1]);
        let cell = c.index([1, 1, 1]);
        assert_eq!(c.members(cell).collect::<Vec<_>>(), [0, 2]);
        c.remove(2, [1, 1, 1]);
        c.remove(0, [1, 1, 1]);
        assert_eq!(c.members(cell).count(), 0);
        // A cell past its record spills, and keeps its members in the order of a vector's
        // `swap_remove` through removals from the record, the spill and the end.
        let mut many = Cells::new(DVec3::ZERO, DVec3::splat(4.0), 1.0, 64);
        let mut model: Vec<u32> = (0..20).collect();
        for i in 0..20 {
            many.insert(i, [2, 1, 0]);
        }
        let cell = many.index([2, 1, 0]);
        for i in [
            5, 19, 12, 0, 17, 3, 8, 1, 2, 4, 6, 7, 9, 10, 11, 13, 14, 15, 16, 18,
        ] {
            many.remove(i, [2, 1, 0]);
            let at = model.iter().position(|&x| x == i).unwrap();
            model.swap_remove(at);
            assert_eq!(
                many.members(cell).collect::<Vec<_>>(),
                model,
                "after removing {i}"
            );
            assert_eq!(many.records()[cell].count(), model.len());
        }
        assert_eq!(many.spill.len(), 0);
        assert_eq!(c.coords_of(DVec3::new(-5.0, 3.99, 9.0)), [0, 3, 3]);
    }
}
