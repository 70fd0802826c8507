//! The engine's cell list of shell centres: a uniform grid of cells at least one largest
//! diameter and the shell wide, each a short contiguous array of sphere indices, so a sphere
//! moves between cells at its shell event by a scan of its old cell's few members and a push,
//! and a list rebuild reads its neighbours' indices without chasing pointers (the generator
//! uses it for spacing too). A sphere's cell is not stored: it is `coords_of` its shell centre.
//! Periodic boxes wrap; an open domain clamps, so its outermost cells reach to infinity (a
//! sphere that leaves the domain stays in an edge cell and is still found by its neighbours).

use glam::DVec3;

use super::runs::Runs;

/// "No sphere".
pub(crate) const NONE: u32 = u32::MAX;

/// Slots every cell has at least (the runs grow past it, never below): a rebuild copies this
/// many of a cell's slots at once.
pub(crate) const LEAST_CAPACITY: usize = 8;

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
    /// Each cell's spheres. A sphere's cell is not stored: it is `coords_of` its shell
    /// centre, which moves at each of its shell events (and the sphere with it, when the
    /// cell changes).
    runs: Runs,
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
            runs: Runs::new(cells, LEAST_CAPACITY),
        }
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

    /// The spheres in cell `cell` (an [`index`](Self::index)).
    #[inline(always)]
    pub fn members(&self, cell: usize) -> &[u32] {
        self.runs.of(cell)
    }

    /// Cell `cell`'s [`cell_capacity`](Self::cell_capacity) slots and how many of them hold
    /// its spheres (the rest are stale).
    #[inline(always)]
    pub fn slots(&self, cell: usize) -> (&[u32], usize) {
        self.runs.slots(cell)
    }

    /// The most spheres a cell holds now (the runs' capacity).
    #[inline]
    pub fn cell_capacity(&self) -> usize {
        self.runs.capacity()
    }

    /// Adds sphere `i` to cell `c`.
    #[inline]
    pub fn insert(&mut self, i: u32, c: [i32; 3]) {
        let cell = self.index(c);
        self.runs.push(cell, i);
    }

    /// Removes sphere `i` from cell `c`, where it is (the cell's last sphere takes its slot;
    /// a cell holds a few spheres, so finding it is a short scan).
    #[inline]
    pub fn remove(&mut self, i: u32, c: [i32; 3]) {
        let cell = self.index(c);
        debug_assert!(
            self.members(cell).contains(&i),
            "sphere {i} is not in cell {c:?}"
        );
        self.runs.remove_value(cell, i);
    }

    /// Cells in the grid.
    pub fn cell_count(&self) -> usize {
        self.runs.owners()
    }

    /// Bytes the grid holds.
    pub fn bytes(&self) -> usize {
        self.runs.bytes()
    }

    /// Empties every cell.
    pub fn clear(&mut self) {
        self.runs.clear_all();
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
        assert_eq!(c.members(cell), &[0, 2]);
        c.remove(2, [1, 1, 1]);
        c.remove(0, [1, 1, 1]);
        assert!(c.members(cell).is_empty());
        // A full cell grows and keeps its members.
        for i in 0..3 {
            c.insert(i, [0, 0, 0]);
        }
        let mut many = Cells::new(DVec3::ZERO, DVec3::splat(4.0), 1.0, 64);
        for i in 0..20 {
            many.insert(i, [2, 1, 0]);
        }
        many.remove(5, [2, 1, 0]);
        let mut m = many.members(many.index([2, 1, 0])).to_vec();
        m.sort();
        assert_eq!(m, (0..20).filter(|&i| i != 5).collect::<Vec<_>>());
        assert_eq!(c.coords_of(DVec3::new(-5.0, 3.99, 9.0)), [0, 3, 3]);
    }
}
