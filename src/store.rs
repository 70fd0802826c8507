//! Structure-of-arrays storage of spheres: one f32 column per coordinate, padded to a multiple
//! of eight with NaN lanes, which no kernel can report as a hit (every hit test is an ordered
//! comparison, false for NaN).

use crate::Sphere;
use crate::error::ShapeError;
use crate::narrow::lanes::Lanes;
use crate::narrow::sphere_sphere::SphereLanes;

/// The lane count every column is padded to (an `f32x8`).
pub const PAD: usize = 8;

/// Spheres as f32 columns, padded to a multiple of [`PAD`].
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
    cx: Vec<f32>,
    cy: Vec<f32>,
    cz: Vec<f32>,
    vx: Vec<f32>,
    vy: Vec<f32>,
    vz: Vec<f32>,
    r: Vec<f32>,
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
        if self.len == self.cx.len() {
            for col in self.columns_mut() {
                col.resize(col.len() + PAD, f32::NAN);
            }
        }
        let (c, v, i) = (s.centre(), s.velocity(), self.len);
        let values = [c.x, c.y, c.z, v.x, v.y, v.z, s.radius(), s.mass()];
        for (col, value) in self.columns_mut().into_iter().zip(values) {
            col[i] = value;
        }
        self.len += 1;
    }

    fn columns_mut(&mut self) -> [&mut Vec<f32>; 8] {
        [
            &mut self.cx,
            &mut self.cy,
            &mut self.cz,
            &mut self.vx,
            &mut self.vy,
            &mut self.vz,
            &mut self.r,
            &mut self.mass,
        ]
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
        self.cx.len()
    }

    /// Sphere `i`, if there is one.
    pub fn get(&self, i: usize) -> Option<Sphere> {
        (i < self.len).then(|| {
            Sphere::new(
                [self.cx[i], self.cy[i], self.cz[i]],
                [self.vx[i], self.vy[i], self.vz[i]],
                self.r[i],
                self.mass[i],
            )
            .expect("the store holds only validated spheres")
        })
    }

    /// Every sphere, in order.
    pub fn to_spheres(&self) -> Vec<Sphere> {
        (0..self.len).filter_map(|i| self.get(i)).collect()
    }

    /// Spheres `i .. i + L::WIDTH` as lanes (padding lanes are NaN).
    ///
    /// # Panics
    /// If `i + L::WIDTH > padded_len()` (an internal invariant of the batch drivers).
    #[inline(always)]
    pub fn lanes<L: Lanes>(&self, i: usize) -> SphereLanes<L> {
        // One check for all seven columns: re-sliced to the same length `n`, and with
        // `i + WIDTH ≤ n` asserted, every column access below is provably in bounds.
        let n = self.padded_len();
        assert!(
            i + L::WIDTH <= n,
            "lane group {i} beyond the padded columns ({n})"
        );
        let col = |c: &[f32]| L::load(&c[..n][i..i + L::WIDTH]);
        SphereLanes {
            c: [col(&self.cx), col(&self.cy), col(&self.cz)],
            v: [col(&self.vx), col(&self.vy), col(&self.vz)],
            r: col(&self.r),
        }
    }

    /// The spheres at `indices` (at most `L::WIDTH`, each `< len()`) as lanes; missing lanes
    /// are NaN.
    #[inline(always)]
    pub fn gather<L: Lanes>(&self, indices: impl Iterator<Item = usize>) -> SphereLanes<L> {
        let mut cols = [[f32::NAN; PAD]; 7];
        for (lane, i) in indices.take(L::WIDTH).enumerate() {
            debug_assert!(i < self.len);
            let values = [
                self.cx[i], self.cy[i], self.cz[i], self.vx[i], self.vy[i], self.vz[i], self.r[i],
            ];
            for (col, value) in cols.iter_mut().zip(values) {
                col[lane] = value;
            }
        }
        let [cx, cy, cz, vx, vy, vz, r] = cols.map(|col| L::load(&col));
        SphereLanes {
            c: [cx, cy, cz],
            v: [vx, vy, vz],
            r,
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
