//! Columns in and out of the store: the eight fields as separate slices (what NumPy, Arrow and
//! Parquet hand over), and borrowed views of the store's columns.

use std::fmt;

use super::{PAD, SphereStore, StoreError};
use crate::error::ShapeError;
use crate::shape::Sphere;

/// One field of a sphere, as a column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Field {
    /// Centre x at `t = 0`.
    X,
    /// Centre y at `t = 0`.
    Y,
    /// Centre z at `t = 0`.
    Z,
    /// Velocity x.
    Vx,
    /// Velocity y.
    Vy,
    /// Velocity z.
    Vz,
    /// Radius.
    R,
    /// Mass.
    M,
}

impl Field {
    /// Every field, in the column order `x, y, z, vx, vy, vz, r, m`.
    pub const ALL: [Field; 8] = [
        Field::X,
        Field::Y,
        Field::Z,
        Field::Vx,
        Field::Vy,
        Field::Vz,
        Field::R,
        Field::M,
    ];

    /// The column's name: `x`, `y`, `z`, `vx`, `vy`, `vz`, `r`, `m`.
    pub const fn name(self) -> &'static str {
        match self {
            Field::X => "x",
            Field::Y => "y",
            Field::Z => "z",
            Field::Vx => "vx",
            Field::Vy => "vy",
            Field::Vz => "vz",
            Field::R => "r",
            Field::M => "m",
        }
    }
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Spheres as separate borrowed columns, one entry per sphere; `m: None` means mass 1.
#[derive(Debug, Clone, Copy)]
pub struct Columns<'a> {
    /// Centre x at `t = 0`.
    pub x: &'a [f32],
    /// Centre y at `t = 0`.
    pub y: &'a [f32],
    /// Centre z at `t = 0`.
    pub z: &'a [f32],
    /// Velocity x.
    pub vx: &'a [f32],
    /// Velocity y.
    pub vy: &'a [f32],
    /// Velocity z.
    pub vz: &'a [f32],
    /// Radius.
    pub r: &'a [f32],
    /// Mass (every mass 1 when absent).
    pub m: Option<&'a [f32]>,
}

impl Columns<'_> {
    /// The common length, or the first column that differs from `x`.
    pub(super) fn check_lengths(&self) -> Result<usize, StoreError> {
        let expected = self.x.len();
        let lengths = [
            (Field::Y, self.y.len()),
            (Field::Z, self.z.len()),
            (Field::Vx, self.vx.len()),
            (Field::Vy, self.vy.len()),
            (Field::Vz, self.vz.len()),
            (Field::R, self.r.len()),
            (Field::M, self.m.map_or(expected, <[f32]>::len)),
        ];
        match lengths.into_iter().find(|&(_, found)| found != expected) {
            Some((field, found)) => Err(StoreError::LengthMismatch {
                field,
                expected,
                found,
            }),
            None => Ok(expected),
        }
    }

    /// Sphere `i`, validated (`i` below the checked length).
    pub(super) fn sphere(&self, i: usize) -> Result<Sphere, ShapeError> {
        Sphere::new(
            [self.x[i], self.y[i], self.z[i]],
            [self.vx[i], self.vy[i], self.vz[i]],
            self.r[i],
            self.m.map_or(1.0, |m| m[i]),
        )
    }
}

/// A borrowed view of one column of a [`SphereStore`] (no copy): index it, iterate it, or
/// copy it out.
#[derive(Debug, Clone, Copy)]
pub struct Column<'a> {
    store: &'a SphereStore,
    field: Field,
}

impl<'a> Column<'a> {
    pub(super) fn new(store: &'a SphereStore, field: Field) -> Self {
        Self { store, field }
    }

    /// The field this column holds.
    pub fn field(&self) -> Field {
        self.field
    }

    /// Number of entries (the store's length).
    pub fn len(&self) -> usize {
        self.store.len()
    }

    /// Whether the column is empty.
    pub fn is_empty(&self) -> bool {
        self.store.is_empty()
    }

    /// Entry `i`, if the store holds sphere `i`.
    #[inline]
    pub fn get(&self, i: usize) -> Option<f32> {
        if i >= self.store.len() {
            return None;
        }
        Some(match self.store.blocks[i / PAD].column(self.field) {
            Some(col) => col[i % PAD],
            None => self.store.mass[i],
        })
    }

    /// The entries in order.
    pub fn iter(&self) -> impl Iterator<Item = f32> + 'a {
        let (store, field) = (self.store, self.field);
        (0..store.len()).map(move |i| match store.blocks[i / PAD].column(field) {
            Some(col) => col[i % PAD],
            None => store.mass[i],
        })
    }

    /// Copies the column into `out`, which must hold exactly [`len`](Self::len) entries.
    ///
    /// # Errors
    /// [`StoreError::LengthMismatch`] if `out` has another length.
    pub fn copy_to(&self, out: &mut [f32]) -> Result<(), StoreError> {
        if out.len() != self.len() {
            return Err(StoreError::LengthMismatch {
                field: self.field,
                expected: self.len(),
                found: out.len(),
            });
        }
        out.iter_mut().zip(self.iter()).for_each(|(o, x)| *o = x);
        Ok(())
    }

    /// The column as a new vector.
    pub fn to_vec(&self) -> Vec<f32> {
        self.iter().collect()
    }
}
