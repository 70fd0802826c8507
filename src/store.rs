//! Structure-of-arrays storage of spheres in blocks of eight (AoSoA): one f32 column per
//! coordinate inside each block, padded with NaN lanes, which no kernel can report as a hit
//! (every hit test is an ordered comparison, false for NaN).

use crate::Sphere;
use crate::error::ShapeError;
use crate::narrow::lanes::Lanes;
use crate::narrow::sphere_sphere::SphereLanes;

/// The lane count every column is padded to (an `f32x8`).
pub const PAD: usize = 8;

/// Eight spheres, one f32 column each for what the kernels read: a structure of arrays in
/// blocks (AoSoA). A lane group is one block, aligned for AVX loads; a batch over a store
/// streams one array instead of seven. Unused lanes are NaN.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(32))]
struct Block {
    cx: [f32; PAD],
    cy: [f32; PAD],
    cz: [f32; PAD],
    vx: [f32; PAD],
    vy: [f32; PAD],
    vz: [f32; PAD],
    r: [f32; PAD],
}

const EMPTY: Block = Block {
    cx: [f32::NAN; PAD],
    cy: [f32::NAN; PAD],
    cz: [f32::NAN; PAD],
    vx: [f32::NAN; PAD],
    vy: [f32::NAN; PAD],
    vz: [f32::NAN; PAD],
    r: [f32::NAN; PAD],
};

/// Spheres as f32 columns in blocks of eight ([`PAD`]), padded with NaN lanes.
///
/// ```
/// use spheresweep::{Sphere, SphereStore};
/// let spheres = [Sphere::new([1.0, 2.0, 3.0], [0.0; 3], 0.5, 1.0)?];
/// let store = SphereStore::from_spheres(&spheres);
/// assert_eq!((store.len(), store.padded_len()), (1, 8));
/// assert_eq!(store.to_spheres(), spheres);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SphereStore {
    len: usize,
    blocks: Vec<Block>,
    mass: Vec<f32>,
}

/// Building a store from plain arrays failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StoreError {
    /// An input array's length differs from the number of centres.
    #[error("{field} has {found} entries, expected {expected} (one per centre)")]
    LengthMismatch {
        /// The argument at fault.
        field: &'static str,
        /// The number of centres.
        expected: usize,
        /// Its length.
        found: usize,
    },
    /// A sphere failed validation.
    #[error("sphere {index}: {source}")]
    Invalid {
        /// Its index in the input.
        index: usize,
        /// What is wrong with it.
        source: ShapeError,
    },
}

impl SphereStore {
    /// An empty store.
    pub fn new() -> Self {
        Self::default()
    }

    /// A store holding `spheres`, in order.
    pub fn from_spheres(spheres: &[Sphere]) -> Self {
        let mut store = Self::default();
        spheres.iter().for_each(|s| store.push(s));
        store
    }

    /// A store from plain arrays (mass 1), validating every sphere.
    ///
    /// # Errors
    /// [`StoreError::LengthMismatch`] if the arrays differ in length;
    /// [`StoreError::Invalid`] naming the first invalid sphere and field.
    ///
    /// ```
    /// use spheresweep::{SphereStore, StoreError};
    /// let err = SphereStore::from_arrays(&[[0.0; 3], [1.0; 3]], &[[0.0; 3]; 2], &[1.0, -2.0]);
    /// assert_eq!(err.unwrap_err().to_string(), "sphere 1: sphere radius is negative");
    /// ```
    pub fn from_arrays(
        centres: &[[f32; 3]],
        velocities: &[[f32; 3]],
        radii: &[f32],
    ) -> Result<Self, StoreError> {
        let expected = centres.len();
        for (field, found) in [("velocities", velocities.len()), ("radii", radii.len())] {
            if found != expected {
                return Err(StoreError::LengthMismatch {
                    field,
                    expected,
                    found,
                });
            }
        }
        let mut store = Self::default();
        for (index, ((c, v), r)) in centres.iter().zip(velocities).zip(radii).enumerate() {
            let s = Sphere::new(*c, *v, *r, 1.0)
                .map_err(|source| StoreError::Invalid { index, source })?;
            store.push(&s);
        }
        Ok(store)
    }

    /// Appends a sphere, keeping the columns padded.
    pub fn push(&mut self, s: &Sphere) {
        let (i, lane) = (self.len / PAD, self.len % PAD);
        if lane == 0 {
            self.blocks.push(EMPTY);
        }
        let (c, v, b) = (s.centre(), s.velocity(), &mut self.blocks[i]);
        (b.cx[lane], b.cy[lane], b.cz[lane]) = (c.x, c.y, c.z);
        (b.vx[lane], b.vy[lane], b.vz[lane]) = (v.x, v.y, v.z);
        b.r[lane] = s.radius();
        self.mass.push(s.mass());
        self.len += 1;
    }

    /// Number of spheres.
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the store holds no sphere.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Length of every column: `len()` rounded up to a multiple of [`PAD`].
    #[inline]
    pub fn padded_len(&self) -> usize {
        self.blocks.len() * PAD
    }

    /// Sphere `i`, if there is one.
    pub fn get(&self, i: usize) -> Option<Sphere> {
        (i < self.len).then(|| {
            let (b, lane) = (&self.blocks[i / PAD], i % PAD);
            Sphere::new(
                [b.cx[lane], b.cy[lane], b.cz[lane]],
                [b.vx[lane], b.vy[lane], b.vz[lane]],
                b.r[lane],
                self.mass[i],
            )
            .expect("the store holds only validated spheres")
        })
    }

    /// Every sphere, in order.
    pub fn to_spheres(&self) -> Vec<Sphere> {
        (0..self.len).filter_map(|i| self.get(i)).collect()
    }

    /// Spheres `i .. i + L::WIDTH` as lanes (padding lanes are NaN); `i` is a multiple of
    /// `L::WIDTH`.
    ///
    /// # Panics
    /// If `i ≥ padded_len()` (an internal invariant of the batch drivers).
    #[inline(always)]
    pub fn lanes<L: Lanes>(&self, i: usize) -> SphereLanes<L> {
        debug_assert_eq!(i % L::WIDTH, 0);
        // One bounds check: the block. Inside it every load is at a constant offset.
        let (b, lane) = (&self.blocks[i / PAD], i % PAD);
        SphereLanes {
            c: [
                L::load8(&b.cx, lane),
                L::load8(&b.cy, lane),
                L::load8(&b.cz, lane),
            ],
            v: [
                L::load8(&b.vx, lane),
                L::load8(&b.vy, lane),
                L::load8(&b.vz, lane),
            ],
            r: L::load8(&b.r, lane),
        }
    }

    /// The spheres at `indices` (at most `L::WIDTH`, each `< len()`) as lanes; missing lanes
    /// are NaN.
    #[inline(always)]
    pub fn gather<L: Lanes>(&self, indices: impl Iterator<Item = usize>) -> SphereLanes<L> {
        let mut g = EMPTY;
        for (k, i) in indices.take(L::WIDTH).enumerate() {
            debug_assert!(i < self.len);
            let (b, lane) = (&self.blocks[i / PAD], i % PAD);
            (g.cx[k], g.cy[k], g.cz[k]) = (b.cx[lane], b.cy[lane], b.cz[lane]);
            (g.vx[k], g.vy[k], g.vz[k]) = (b.vx[lane], b.vy[lane], b.vz[lane]);
            g.r[k] = b.r[lane];
        }
        SphereLanes {
            c: [L::load8(&g.cx, 0), L::load8(&g.cy, 0), L::load8(&g.cz, 0)],
            v: [L::load8(&g.vx, 0), L::load8(&g.vy, 0), L::load8(&g.vz, 0)],
            r: L::load8(&g.r, 0),
        }
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
