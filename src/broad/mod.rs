//! The broad phase: a uniform grid over the spheres' swept boxes that reports every candidate
//! sphere pair exactly once, in cell order (`grid/mod.rs` has the algorithm and why its stencil is
//! correct). Planes, cylinders and containers stay out of the grid: every sphere meets them in
//! the static-shape kernels directly.

mod grid;

pub use grid::{GridOptions, Layout};

use crate::store::SphereStore;

/// The uniform-grid broad phase over a store's spheres. It keeps its cell order and buffers
/// between builds, so a scene that moved a little re-sorts with coherent memory access.
///
/// ```
/// use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
/// let store = SphereStore::from_spheres(&[
///     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
///     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
///     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
/// ]);
/// let mut grid = Grid::new();
/// grid.build(&store, 4.0, GridOptions::default());
/// let pairs: Vec<[u32; 2]> = grid.pairs().iter().map(|&[p, q]| {
///     let (i, j) = (grid.order()[p as usize], grid.order()[q as usize]);
///     [i.min(j), i.max(j)]
/// }).collect();
/// assert_eq!(pairs, [[0, 1]]); // the far sphere's box overlaps nothing
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Default)]
pub struct Grid {
    inner: grid::Grid,
}

impl std::fmt::Debug for Grid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Grid")
            .field("spheres", &self.order().len())
            .field("pairs", &self.pairs().len())
            .field("cell_size", &self.cell_size())
            .field("oversize", &self.oversize())
            .finish()
    }
}

impl Grid {
    /// An empty grid.
    ///
    /// ```
    /// use spheresweep::broad::Grid;
    /// let grid = Grid::new();
    /// assert!(grid.order().is_empty() && grid.pairs().is_empty());
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// Rebuilds for the spheres of `store` over the window `[0, t_max]` (finite, `≥ 0`).
    ///
    /// # Panics
    /// If `t_max` is not finite and `≥ 0`, or `options.cell_size` is given and not finite and
    /// `> 0` (callers validate both; the scene query never passes an infinite window here).
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// let mut grid = Grid::new();
    /// grid.build(&store, 4.0, GridOptions { cell_size: Some(4.0), ..GridOptions::default() });
    /// assert_eq!(grid.cell_size(), 4.0);
    /// grid.build(&store, 0.0, GridOptions::default()); // sphere 0 no longer reaches sphere 1
    /// assert!(grid.pairs().is_empty());
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn build(&mut self, store: &SphereStore, t_max: f32, options: GridOptions) {
        self.inner
            .build(grid::SphereBlocks::of(store), t_max, options);
    }

    /// The cells and the cell order for the spheres of `store` over `[0, t_max]`, without the
    /// list of pairs: [`visit_pairs`](Self::visit_pairs) then hands the pairs on a few
    /// thousand at a time, so memory stays linear in the number of spheres however long the
    /// window. Same panics as [`build`](Self::build).
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// use std::sync::Mutex;
    /// let mut grid = Grid::new();
    /// grid.build_cells(&store, 4.0, GridOptions::default());
    /// let seen = Mutex::new(Vec::new());
    /// grid.visit_pairs(&|pairs| seen.lock().unwrap().extend_from_slice(pairs));
    /// grid.build(&store, 4.0, GridOptions::default());
    /// assert_eq!(seen.into_inner().unwrap(), grid.pairs()); // the same pairs
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn build_cells(&mut self, store: &SphereStore, t_max: f32, options: GridOptions) {
        self.inner
            .build_cells(grid::SphereBlocks::of(store), t_max, options);
    }

    /// Every candidate pair of the last [`build_cells`](Self::build_cells) (or
    /// [`build`](Self::build)) once, as positions in [`order`](Self::order), handed to
    /// `visit` in batches of a few thousand, from rayon's threads when the build ran there.
    /// The batches' order may depend on the thread count; the set of pairs does not.
    pub fn visit_pairs(&self, visit: &(dyn Fn(&[[u32; 2]]) + Sync)) {
        self.inner.visit_pairs(visit);
    }

    /// Sphere indices in cell order.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// let mut grid = Grid::new();
    /// grid.build(&store, 4.0, GridOptions::default());
    /// let mut order = grid.order().to_vec();
    /// order.sort();
    /// assert_eq!(order, [0, 1, 2]); // each sphere once
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn order(&self) -> &[u32] {
        self.inner.order()
    }

    /// Every candidate pair once, as positions `[p, q]` (`p < q`) in [`order`](Self::order).
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// let mut grid = Grid::new();
    /// grid.build(&store, 4.0, GridOptions::default());
    /// let [p, q] = grid.pairs()[0];
    /// assert!(p < q && grid.pairs().len() == 1);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn pairs(&self) -> &[[u32; 2]] {
        self.inner.pairs()
    }

    /// Edge of a cell in the last build.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// let mut grid = Grid::new();
    /// grid.build(&store, 4.0, GridOptions { cell_size: Some(8.0), ..GridOptions::default() });
    /// assert_eq!(grid.cell_size(), 8.0);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn cell_size(&self) -> f32 {
        self.inner.cell_size()
    }

    /// Spheres on the oversize list in the last build (tested against all).
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// let mut grid = Grid::new();
    /// // Over [0, 10] sphere 0's swept box is 12 wide: it spans more than two cells of 3.
    /// grid.build(&store, 10.0, GridOptions { cell_size: Some(3.0), ..GridOptions::default() });
    /// assert_eq!(grid.oversize(), 1);
    /// assert_eq!(grid.order().last(), Some(&0)); // oversize spheres come last
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn oversize(&self) -> usize {
        self.inner.oversize()
    }

    /// Cells per axis of the last build (without the padding layer).
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// let mut grid = Grid::new();
    /// grid.build(&store, 4.0, GridOptions { cell_size: Some(8.0), ..GridOptions::default() });
    /// let [nx, ny, nz] = grid.dims();
    /// assert!(nx * 8 >= 52 && ny == 1 && nz == 1); // the boxes span 52 along x, 2 across
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn dims(&self) -> [u32; 3] {
        self.inner.dims()
    }

    /// Cells in the last build's table (dense layout, padding included) or occupied cells
    /// (sparse layout, for scenes too spread out for a dense table).
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// use spheresweep::broad::Layout;
    /// let mut grid = Grid::new();
    /// grid.build(&store, 4.0, GridOptions { cell_size: Some(8.0), layout: Layout::Sparse });
    /// assert_eq!(grid.cells(), 2); // spheres 0 and 1 (boxes from x = −1 and 4) share a cell
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn cells(&self) -> usize {
        self.inner.cells()
    }

    /// Whether the last build used the sparse layout.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// use spheresweep::broad::Layout;
    /// let mut grid = Grid::new();
    /// grid.build(&store, 4.0, GridOptions { layout: Layout::Dense, ..GridOptions::default() });
    /// assert!(!grid.sparse());
    /// grid.build(&store, 4.0, GridOptions { layout: Layout::Sparse, ..GridOptions::default() });
    /// assert!(grid.sparse());
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn sparse(&self) -> bool {
        self.inner.sparse()
    }

    /// Forgets the kept cell order (the next build sorts from the identity order).
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// let mut grid = Grid::new();
    /// grid.build(&store, 4.0, GridOptions::default());
    /// let pairs = grid.pairs().len();
    /// grid.reset_order();
    /// grid.build(&store, 4.0, GridOptions::default());
    /// assert_eq!(grid.pairs().len(), pairs); // the same candidates
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn reset_order(&mut self) {
        self.inner.reset_order();
    }

    /// Bytes the grid holds on the heap (its buffers, grown to the largest scene so far).
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore, broad::{Grid, GridOptions}};
    /// # let store = SphereStore::from_spheres(&[
    /// #     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
    /// #     Sphere::new([5.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// #     Sphere::new([50.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
    /// # ]);
    /// let mut grid = Grid::new();
    /// grid.build(&store, 4.0, GridOptions::default());
    /// assert!(grid.heap_bytes() >= 3 * 4); // at least the order, one u32 per sphere
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn heap_bytes(&self) -> usize {
        self.inner.heap_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Sphere;
    use crate::rng::Rng;

    /// Every pair `i < j` whose swept boxes overlap, from the same float operations.
    fn brute(store: &SphereStore, t_max: f32) -> Vec<[u32; 2]> {
        let cols = grid::SphereBlocks::of(store);
        let boxes: Vec<_> = (0..store.len())
            .map(|i| grid::swept_box(&cols, i, t_max))
            .collect();
        let mut pairs = Vec::new();
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                let ((la, ha), (lb, hb)) = (boxes[i], boxes[j]);
                if (0..3).all(|a| la[a] <= hb[a] && lb[a] <= ha[a]) {
                    pairs.push([i as u32, j as u32]);
                }
            }
        }
        pairs
    }

    fn grid_pairs(store: &SphereStore, t_max: f32, options: GridOptions) -> Vec<[u32; 2]> {
        let mut grid = Grid::new();
        grid.build(store, t_max, options);
        let mut pairs: Vec<[u32; 2]> = grid
            .pairs()
            .iter()
            .map(|&[p, q]| {
                let (i, j) = (grid.order()[p as usize], grid.order()[q as usize]);
                [i.min(j), i.max(j)]
            })
            .collect();
        let n = pairs.len();
        pairs.sort_unstable();
        pairs.dedup();
        assert_eq!(pairs.len(), n, "a pair reported twice");
        pairs
    }

    #[test]
    fn grid_pairs_are_the_overlapping_boxes_exactly_once() {
        let mut rng = Rng::new(1);
        for (n, spread, speed, radii) in [
            (0, 1.0, 1.0, (1.0, 1.0)),
            (1, 1.0, 1.0, (1.0, 1.0)),
            (700, 20.0, 1.0, (1.0, 1.0)),
            (700, 20.0, 1.0, (0.01, 10.0)),
            (700, 0.01, 1.0, (1.0, 1.0)),
            (500, 1e4, 0.0, (1.0, 1.0)),
            (600, 30.0, 50.0, (0.5, 0.5)),
        ] {
            let store: SphereStore = (0..n)
                .map(|_| {
                    let c = rng.cube(spread).as_vec3();
                    let v = (rng.cube(1.0) * speed).as_vec3();
                    let (lo, hi): (f64, f64) = radii;
                    let r = lo * (hi / lo).powf(rng.unit());
                    Sphere::new(c.into(), v.into(), r as f32, 1.0).unwrap()
                })
                .collect();
            for t_max in [0.0, 0.5, 10.0] {
                let expected = brute(&store, t_max);
                assert_eq!(grid_pairs(&store, t_max, GridOptions::default()), expected);
                // A forced small cell puts most spheres on the oversize list; each layout.
                for layout in [Layout::Dense, Layout::Sparse] {
                    let forced = GridOptions {
                        cell_size: Some(0.3),
                        layout,
                    };
                    assert_eq!(
                        grid_pairs(&store, t_max, forced),
                        expected,
                        "n {n} t {t_max}"
                    );
                    let auto = GridOptions {
                        cell_size: None,
                        layout,
                    };
                    assert_eq!(grid_pairs(&store, t_max, auto), expected, "n {n} t {t_max}");
                }
            }
        }
    }
}
