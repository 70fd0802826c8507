//! The sphere store: f32 columns in blocks of eight (AoSoA), padded with NaN lanes, which no
//! kernel can report as a hit (every hit test is an ordered comparison, false for NaN).
//!
//! Data enters through validating constructors ([`SphereStore::from_spheres`],
//! [`SphereStore::from_columns`], [`SphereStore::push`], the `set_*` updates) and is never
//! checked again: reads ([`SphereStore::get`], [`SphereStore::column`], the blocks) trust it.
//! The store owns its lane loads, so every consumer — kernels, swept boxes, the simulation —
//! reads the same blocks.

mod columns;
mod lanes;

use glam::Vec3;

use crate::error::{Problem, ShapeError};
use crate::lanes::Lanes;
use crate::shape::ShapeKind;
use crate::shape::Sphere;

pub use columns::{Column, Columns, Field};
pub(crate) use lanes::SphereLanes;

/// The lane count every column is padded to (an `f32x8`).
pub const PAD: usize = 8;

/// Eight spheres, one f32 column each for what the kernels read: a structure of arrays in
/// blocks (AoSoA). A lane group is one block, aligned for AVX loads; a batch over a store
/// streams one array instead of seven. Unused lanes are NaN.
///
/// ```
/// use spheresweep::{Sphere, SphereStore, store::Field};
/// let store = SphereStore::from_spheres(&[Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 1.0)?]);
/// let block = &store.blocks()[0];
/// assert_eq!(block.column(Field::Y).unwrap()[0], 2.0);
/// assert!(block.column(Field::Y).unwrap()[1].is_nan()); // lanes 1..8 are padding
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(32))]
pub struct SphereBlock {
    pub(crate) cx: [f32; PAD],
    pub(crate) cy: [f32; PAD],
    pub(crate) cz: [f32; PAD],
    pub(crate) vx: [f32; PAD],
    pub(crate) vy: [f32; PAD],
    pub(crate) vz: [f32; PAD],
    pub(crate) r: [f32; PAD],
}

impl SphereBlock {
    const EMPTY: SphereBlock = SphereBlock {
        cx: [f32::NAN; PAD],
        cy: [f32::NAN; PAD],
        cz: [f32::NAN; PAD],
        vx: [f32::NAN; PAD],
        vy: [f32::NAN; PAD],
        vz: [f32::NAN; PAD],
        r: [f32::NAN; PAD],
    };

    /// The block's column of `field` (NaN in unused lanes). [`Field::M`] is not held in
    /// blocks (the kernels never read it): it gives `None`.
    ///
    /// ```
    /// use spheresweep::{Sphere, SphereStore, store::Field};
    /// let store = SphereStore::from_spheres(&[Sphere::new([0.0; 3], [0.0; 3], 0.5, 1.0)?]);
    /// assert_eq!(store.blocks()[0].column(Field::R).unwrap()[0], 0.5);
    /// assert_eq!(store.blocks()[0].column(Field::M), None);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn column(&self, field: Field) -> Option<&[f32; PAD]> {
        Some(match field {
            Field::X => &self.cx,
            Field::Y => &self.cy,
            Field::Z => &self.cz,
            Field::Vx => &self.vx,
            Field::Vy => &self.vy,
            Field::Vz => &self.vz,
            Field::R => &self.r,
            Field::M => return None,
        })
    }

    #[inline]
    fn column_mut(&mut self, field: Field) -> Option<&mut [f32; PAD]> {
        Some(match field {
            Field::X => &mut self.cx,
            Field::Y => &mut self.cy,
            Field::Z => &mut self.cz,
            Field::Vx => &mut self.vx,
            Field::Vy => &mut self.vy,
            Field::Vz => &mut self.vz,
            Field::R => &mut self.r,
            Field::M => return None,
        })
    }
}

/// Spheres as f32 columns in blocks of eight ([`PAD`]), padded with NaN lanes, with a mass
/// column beside them.
///
/// ```
/// use spheresweep::{Sphere, SphereStore};
/// let spheres = [Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 1.0)?];
/// let store = SphereStore::from_spheres(&spheres);
/// assert_eq!((store.len(), store.padded_len()), (1, 8));
/// assert_eq!(store.to_spheres(), spheres);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Default)]
pub struct SphereStore {
    len: usize,
    blocks: Vec<SphereBlock>,
    mass: Vec<f32>,
}

/// Building or updating a store failed: each variant names the sphere and the field.
///
/// ```
/// use spheresweep::{SphereStore, StoreError};
/// let mut store = SphereStore::new();
/// let err = store.set_velocity(0, [1.0; 3]).unwrap_err();
/// assert_eq!(err, StoreError::IndexOutOfRange { index: 0, len: 0 });
/// assert_eq!(err.to_string(), "sphere index 0 is out of range (the store holds 0)");
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StoreError {
    /// An input column's length differs from the first column's.
    #[error("column {field} has {found} entries, expected {expected} (one per sphere)")]
    LengthMismatch {
        /// The column at fault.
        field: Field,
        /// The length of the first column (`x`).
        expected: usize,
        /// Its length.
        found: usize,
    },
    /// A sphere failed validation: its index, then the field and what is wrong (the kind is
    /// the store's, not repeated).
    #[error("sphere {index}: {} {}", source.field, source.problem)]
    Invalid {
        /// Its index in the input.
        index: usize,
        /// What is wrong with it.
        source: ShapeError,
    },
    /// An update names a sphere the store does not hold.
    #[error("sphere index {index} is out of range (the store holds {len})")]
    IndexOutOfRange {
        /// The bad index.
        index: usize,
        /// Spheres in the store.
        len: usize,
    },
}

fn finite3(index: usize, field: &'static str, v: [f32; 3]) -> Result<(), StoreError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(StoreError::Invalid {
            index,
            source: ShapeError::new(ShapeKind::Sphere, field, Problem::NotFinite),
        })
    }
}

impl SphereStore {
    /// An empty store.
    ///
    /// ```
    /// use spheresweep::SphereStore;
    /// let store = SphereStore::new();
    /// assert_eq!((store.len(), store.padded_len(), store.blocks().len()), (0, 0, 0));
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty store with room for `n` spheres.
    ///
    /// ```
    /// use spheresweep::SphereStore;
    /// assert!(SphereStore::with_capacity(100).is_empty());
    /// ```
    pub fn with_capacity(n: usize) -> Self {
        Self {
            len: 0,
            blocks: Vec::with_capacity(n.div_ceil(PAD)),
            mass: Vec::with_capacity(n),
        }
    }

    /// A store holding `spheres`, in order.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// assert_eq!(store.get(1).unwrap().radius(), 1.5);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn from_spheres(spheres: &[Sphere]) -> Self {
        let mut store = Self::with_capacity(spheres.len());
        spheres.iter().for_each(|s| store.push(s));
        store
    }

    /// A store from separate columns (what NumPy, Arrow and Parquet hand over), validating
    /// every sphere once. Without a mass column every mass is 1.
    ///
    /// # Errors
    /// [`StoreError::LengthMismatch`] naming the first column whose length differs from `x`;
    /// [`StoreError::Invalid`] naming the first invalid sphere and field.
    ///
    /// ```
    /// use spheresweep::{SphereStore, store::Columns};
    /// let (x, zero) = ([0.0, 3.0], [0.0; 2]);
    /// let columns = Columns { x: &x, y: &zero, z: &zero, vx: &zero, vy: &zero, vz: &zero, r: &[1.0, -2.0], m: None };
    /// let err = SphereStore::from_columns(&columns).unwrap_err();
    /// assert_eq!(err.to_string(), "sphere 1: radius is negative");
    /// ```
    pub fn from_columns(columns: &Columns<'_>) -> Result<Self, StoreError> {
        let n = columns.check_lengths()?;
        let mut store = Self::with_capacity(n);
        for index in 0..n {
            let s = columns
                .sphere(index)
                .map_err(|source| StoreError::Invalid { index, source })?;
            store.push(&s);
        }
        Ok(store)
    }

    /// Appends a sphere, keeping the columns padded.
    ///
    /// ```
    /// use spheresweep::{Sphere, SphereStore};
    /// let mut store = SphereStore::new();
    /// for i in 0..9 {
    ///     store.push(&Sphere::new([i as f32, 0.0, 0.0], [0.0; 3], 0.5, 1.0)?);
    /// }
    /// assert_eq!((store.len(), store.padded_len()), (9, 16)); // a second block of eight
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn push(&mut self, s: &Sphere) {
        let (i, lane) = (self.len / PAD, self.len % PAD);
        if lane == 0 {
            self.blocks.push(SphereBlock::EMPTY);
        }
        let (c, v, b) = (s.centre(), s.velocity(), &mut self.blocks[i]);
        (b.cx[lane], b.cy[lane], b.cz[lane]) = (c.x, c.y, c.z);
        (b.vx[lane], b.vy[lane], b.vz[lane]) = (v.x, v.y, v.z);
        b.r[lane] = s.radius();
        self.mass.push(s.mass());
        self.len += 1;
    }

    /// Number of spheres.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// assert_eq!(store.len(), 2);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the store holds no sphere.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// assert!(!store.is_empty() && SphereStore::new().is_empty());
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Length of every column: `len()` rounded up to a multiple of [`PAD`].
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// assert_eq!(store.padded_len(), spheresweep::store::PAD);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn padded_len(&self) -> usize {
        self.blocks.len() * PAD
    }

    /// Sphere `i`, if there is one (read back as stored: no validation again).
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// assert_eq!(store.get(0).unwrap().centre().to_array(), [1.0, 2.0, 3.0]);
    /// assert_eq!(store.get(2), None);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn get(&self, i: usize) -> Option<Sphere> {
        (i < self.len).then(|| {
            let (b, lane) = (&self.blocks[i / PAD], i % PAD);
            Sphere::from_validated(
                Vec3::new(b.cx[lane], b.cy[lane], b.cz[lane]),
                Vec3::new(b.vx[lane], b.vy[lane], b.vz[lane]),
                b.r[lane],
                self.mass[i],
            )
        })
    }

    /// Every sphere, in order, by value.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// let masses: Vec<f32> = store.iter().map(|s| s.mass()).collect();
    /// assert_eq!(masses, [2.0, 3.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn iter(&self) -> impl ExactSizeIterator<Item = Sphere> + '_ {
        (0..self.len).map(|i| self.get(i).expect("index below len"))
    }

    /// Every sphere, in order.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// assert_eq!(store.to_spheres()[1].velocity().x, 1.0);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    pub fn to_spheres(&self) -> Vec<Sphere> {
        self.iter().collect()
    }

    /// A borrowed view of one column (no copy).
    ///
    /// ```
    /// use spheresweep::{Sphere, SphereStore, store::Field};
    /// let store = SphereStore::from_spheres(&[Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 4.0)?]);
    /// assert_eq!(store.column(Field::Z).to_vec(), [3.0]);
    /// assert_eq!(store.column(Field::M).to_vec(), [4.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn column(&self, field: Field) -> Column<'_> {
        Column::new(self, field)
    }

    /// The blocks of eight, in order (the last one padded with NaN lanes): what the kernels,
    /// the swept boxes and the simulation read.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// use spheresweep::store::Field;
    /// assert_eq!(store.blocks().len(), 1);
    /// assert_eq!(&store.blocks()[0].column(Field::X).unwrap()[..2], &[1.0, 4.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn blocks(&self) -> &[SphereBlock] {
        &self.blocks
    }

    /// The mass column.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// assert_eq!(store.masses(), [2.0, 3.0]);
    /// # Ok::<(), spheresweep::ShapeError>(())
    /// ```
    #[inline]
    pub fn masses(&self) -> &[f32] {
        &self.mass
    }

    fn check_index(&self, index: usize) -> Result<(), StoreError> {
        if index < self.len {
            Ok(())
        } else {
            Err(StoreError::IndexOutOfRange {
                index,
                len: self.len,
            })
        }
    }

    fn write3(&mut self, i: usize, fields: [Field; 3], v: [f32; 3]) {
        let (b, lane) = (&mut self.blocks[i / PAD], i % PAD);
        for (field, x) in fields.into_iter().zip(v) {
            if let Some(col) = b.column_mut(field) {
                col[lane] = x;
            }
        }
    }

    /// A new store of the spheres at `indices`, in that order (`indices[k]` goes to position
    /// `k`): e.g. a store kept in a scene query's cell order
    /// ([`SceneQuery::cell_order`](crate::query::SceneQuery::cell_order)), which the next
    /// query then reads in sequence.
    ///
    /// # Errors
    /// [`StoreError::IndexOutOfRange`] naming the first index the store does not hold.
    ///
    /// ```
    /// use spheresweep::{Sphere, SphereStore};
    /// let store: SphereStore = (0..3)
    ///     .map(|k| Sphere::new([k as f32, 0.0, 0.0], [0.0; 3], 0.1, 1.0))
    ///     .collect::<Result<_, _>>()?;
    /// let reordered = store.gathered(&[2, 0, 1])?;
    /// assert_eq!(reordered.get(0), store.get(2));
    /// assert!(store.gathered(&[3]).is_err()); // names index 3 of a store of 3
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn gathered(&self, indices: &[u32]) -> Result<SphereStore, StoreError> {
        let mut out = SphereStore::with_capacity(indices.len());
        for &i in indices {
            let sphere = self.get(i as usize).ok_or(StoreError::IndexOutOfRange {
                index: i as usize,
                len: self.len,
            })?;
            out.push(&sphere);
        }
        Ok(out)
    }

    /// Moves sphere `i`'s centre at `t = 0` in place.
    ///
    /// # Errors
    /// If `i` is out of range or a coordinate is NaN or infinite.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let mut store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// store.set_centre(0, [7.0, 8.0, 9.0])?;
    /// assert_eq!(store.get(0).unwrap().centre().to_array(), [7.0, 8.0, 9.0]);
    /// let err = store.set_centre(1, [f32::INFINITY, 0.0, 0.0]).unwrap_err();
    /// assert_eq!(err.to_string(), "sphere 1: centre is NaN or infinite");
    /// # Ok::<(), spheresweep::Error>(())
    /// ```
    pub fn set_centre(&mut self, i: usize, centre: [f32; 3]) -> Result<(), StoreError> {
        self.check_index(i)?;
        finite3(i, "centre", centre)?;
        self.write3(i, [Field::X, Field::Y, Field::Z], centre);
        Ok(())
    }

    /// Sets sphere `i`'s velocity in place.
    ///
    /// # Errors
    /// If `i` is out of range or a component is NaN or infinite.
    ///
    /// ```
    /// # use spheresweep::{Sphere, SphereStore};
    /// let mut store = SphereStore::from_spheres(&[
    ///     Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 2.0)?,
    ///     Sphere::new([4.0, 5.0, 6.0], [1.0, 0.0, 0.0], 1.5, 3.0)?,
    /// ]);
    /// store.set_velocity(1, [0.0, -2.0, 0.0])?;
    /// assert_eq!(store.get(1).unwrap().centre_at(1.0).to_array(), [4.0, 3.0, 6.0]);
    /// assert!(store.set_velocity(2, [0.0; 3]).is_err()); // no sphere 2
    /// # Ok::<(), spheresweep::Error>(())
    /// ```
    pub fn set_velocity(&mut self, i: usize, velocity: [f32; 3]) -> Result<(), StoreError> {
        self.check_index(i)?;
        finite3(i, "velocity", velocity)?;
        self.write3(i, [Field::Vx, Field::Vy, Field::Vz], velocity);
        Ok(())
    }

    /// Spheres `8k .. 8k + L::WIDTH` of lane group `k` (a group is `L::WIDTH` spheres; there
    /// are `padded_len() / L::WIDTH` of them).
    ///
    /// # Panics
    /// If `k` is not a lane group of the store (an internal invariant of the batch drivers).
    #[inline(always)]
    pub(crate) fn lanes<L: Lanes>(&self, group: usize) -> SphereLanes<L> {
        let i = group * L::WIDTH;
        // One bounds check: the block. Inside it every load is at a constant offset.
        SphereLanes::load(&self.blocks[i / PAD], i % PAD)
    }

    /// The spheres at `indices` (at most `L::WIDTH`, each `< len()`, checked at the way in)
    /// as lanes; missing lanes are NaN.
    #[inline(always)]
    pub(crate) fn gather<L: Lanes>(&self, indices: impl Iterator<Item = usize>) -> SphereLanes<L> {
        let mut g = SphereBlock::EMPTY;
        for (k, i) in indices.take(L::WIDTH).enumerate() {
            let (b, lane) = (&self.blocks[i / PAD], i % PAD);
            (g.cx[k], g.cy[k], g.cz[k]) = (b.cx[lane], b.cy[lane], b.cz[lane]);
            (g.vx[k], g.vy[k], g.vz[k]) = (b.vx[lane], b.vy[lane], b.vz[lane]);
            g.r[k] = b.r[lane];
        }
        SphereLanes::load(&g, 0)
    }
}

/// One sphere as one aligned 32-byte record (`c`, `v`, `r`, padding): what a gather of
/// scattered spheres reads — one cache line per sphere, where the blocks spread a sphere over
/// seven.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(C, align(32))]
pub(crate) struct Packed(pub(crate) [f32; 8]);

/// Spheres as packed records, for the gathers of a broad phase's candidate pairs (the grid
/// writes them in cell order).
#[derive(Debug, Clone, Default)]
pub(crate) struct PackedSpheres(pub(crate) Vec<Packed>);

/// Where a batch driver gathers the spheres of listed pairs from.
pub(crate) trait Gather: Sync {
    /// Number of spheres.
    fn count(&self) -> usize;
    /// The spheres at `indices` (at most `L::WIDTH`, each below [`count`](Gather::count)) as
    /// lanes; missing lanes are NaN.
    fn gather<L: Lanes>(&self, indices: impl Iterator<Item = usize>) -> SphereLanes<L>;

    /// Eight spheres into eight lanes (`L::WIDTH == 8`): the same lanes as
    /// [`gather`](Gather::gather), by a faster path where the source has one.
    #[inline(always)]
    fn gather8<L: Lanes>(&self, indices: [usize; 8]) -> SphereLanes<L> {
        self.gather(indices.into_iter())
    }
}

impl Gather for SphereStore {
    #[inline]
    fn count(&self) -> usize {
        self.len
    }
    #[inline(always)]
    fn gather<L: Lanes>(&self, indices: impl Iterator<Item = usize>) -> SphereLanes<L> {
        SphereStore::gather(self, indices)
    }
}

impl Gather for PackedSpheres {
    #[inline]
    fn count(&self) -> usize {
        self.0.len()
    }
    #[inline(always)]
    fn gather<L: Lanes>(&self, indices: impl Iterator<Item = usize>) -> SphereLanes<L> {
        let mut g = SphereBlock::EMPTY;
        for (k, i) in indices.take(L::WIDTH).enumerate() {
            let [cx, cy, cz, vx, vy, vz, r, _] = self.0[i].0;
            (g.cx[k], g.cy[k], g.cz[k]) = (cx, cy, cz);
            (g.vx[k], g.vy[k], g.vz[k]) = (vx, vy, vz);
            g.r[k] = r;
        }
        SphereLanes::load(&g, 0)
    }

    /// Each record loaded whole (one 32-byte load) and the eight transposed into columns:
    /// eight loads and a few shuffles where the lane-by-lane gather makes 56 of each.
    #[inline(always)]
    fn gather8<L: Lanes>(&self, indices: [usize; 8]) -> SphereLanes<L> {
        let rows = indices.map(|i| wide::f32x8::from(self.0[i].0));
        let [cx, cy, cz, vx, vy, vz, r, _] = wide::f32x8::transpose(rows).map(|c| c.to_array());
        SphereLanes::load(
            &SphereBlock {
                cx,
                cy,
                cz,
                vx,
                vy,
                vz,
                r,
            },
            0,
        )
    }
}

/// Two stores are equal when they hold equal spheres in the same order (the NaN padding
/// lanes, which would make every padded store unequal to itself, are not compared).
impl PartialEq for SphereStore {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl From<&[Sphere]> for SphereStore {
    fn from(spheres: &[Sphere]) -> Self {
        Self::from_spheres(spheres)
    }
}

impl FromIterator<Sphere> for SphereStore {
    fn from_iter<I: IntoIterator<Item = Sphere>>(iter: I) -> Self {
        let mut store = Self::default();
        iter.into_iter().for_each(|s| store.push(&s));
        store
    }
}
