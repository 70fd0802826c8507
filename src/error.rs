//! Errors at the validation boundary: each names the shape, the field and what is wrong; and
//! [`Error`], which wraps the errors of shapes, stores, batch calls and simulations so that a
//! caller can `?` across them.

use std::fmt;

use crate::shape::ShapeKind;

/// What is wrong with a field.
///
/// ```
/// use spheresweep::{Problem, Sphere};
/// let err = Sphere::new([0.0; 3], [0.0; 3], 1.0, 0.0).unwrap_err();
/// assert_eq!((err.field, err.problem), ("mass", Problem::NotPositive));
/// assert_eq!(Problem::NotPositive.to_string(), "must be greater than zero");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Problem {
    /// The value (or one of its components) is NaN or infinite.
    NotFinite,
    /// A radius below zero.
    Negative,
    /// A mass that is zero or below.
    NotPositive,
    /// A direction of length zero (a plane normal or a cylinder axis with `p1 == p2`).
    ZeroLength,
    /// A magnitude the simulation cannot compute with: a radius or mass outside
    /// `[2⁻¹⁰⁰, 2¹⁰⁰]`, or a coordinate or velocity component beyond `2¹⁰⁰`
    /// (`spheresweep::sim::MAX_MAGNITUDE`; docs/derivations/simulation.md, "The range of
    /// magnitudes").
    OutOfRange,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Problem::NotFinite => "is NaN or infinite",
            Problem::Negative => "is negative",
            Problem::NotPositive => "must be greater than zero",
            Problem::ZeroLength => "has zero length (degenerate direction)",
            Problem::OutOfRange => {
                "is outside the range the simulation computes in (radii and masses 2⁻¹⁰⁰ to \
                 2¹⁰⁰, about 7.9e-31 to 1.3e30; coordinates and velocities at most 2¹⁰⁰): \
                 choose units that bring the scene within it"
            }
        })
    }
}

/// A shape was rejected by its constructor; no shape value ever holds invalid data.
///
/// ```
/// use spheresweep::{Plane, Problem, ShapeKind};
/// let err = Plane::new([0.0; 3], [0.0; 3]).unwrap_err();
/// assert_eq!((err.kind, err.field, err.problem), (ShapeKind::Plane, "normal", Problem::ZeroLength));
/// assert_eq!(err.to_string(), "plane normal has zero length (degenerate direction)");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[error("{kind} {field} {problem}")]
pub struct ShapeError {
    /// The shape being built.
    pub kind: ShapeKind,
    /// The constructor argument at fault (`"centre"`, `"velocity"`, `"radius"`, `"mass"`,
    /// `"point"`, `"normal"`, `"axis"`).
    pub field: &'static str,
    /// What is wrong with it.
    pub problem: Problem,
}

impl ShapeError {
    pub(crate) const fn new(kind: ShapeKind, field: &'static str, problem: Problem) -> Self {
        Self {
            kind,
            field,
            problem,
        }
    }
}

/// An error of the library's shapes, stores, batch calls or simulations: one type to `?`
/// across them. The scene file's `io::scene_file::SceneFileError` (feature `scene-file`)
/// stays apart: it carries an I/O error (neither `Clone` nor `PartialEq`) and already holds
/// the shape or simulation error it stems from.
///
/// ```
/// use spheresweep::{Error, Sphere};
/// fn build() -> Result<Sphere, Error> {
///     Ok(Sphere::new([0.0; 3], [0.0; 3], -1.0, 1.0)?)
/// }
/// assert_eq!(build().unwrap_err().to_string(), "sphere radius is negative");
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A shape was rejected by its constructor.
    #[error(transparent)]
    Shape(#[from] ShapeError),
    /// A store could not be built or updated from columns.
    #[error(transparent)]
    Store(#[from] crate::store::StoreError),
    /// A batch call's arguments do not fit together.
    #[error(transparent)]
    Batch(#[from] crate::batch::BatchError),
    /// A simulation could not be built or advanced.
    #[error(transparent)]
    Sim(#[from] crate::sim::SimError),
}

/// A number as messages print it: plainly between `10⁻⁴` and `10⁶` (and `0`), in scientific
/// notation beyond, so that `1e300` reads as `1e300` and not as 301 digits.
///
/// ```
/// # use spheresweep::error::Num;
/// assert_eq!(Num(2.5).to_string(), "2.5");
/// assert_eq!(Num(1e300).to_string(), "1e300");
/// assert_eq!(Num(-3e-7).to_string(), "-3e-7");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

/// A vector as messages print it: `[x, y, z]`, each component a [`Num`].
///
/// ```
/// # use spheresweep::error::Nums;
/// assert_eq!(Nums([0.0, -9.81, 1e200]).to_string(), "[0, -9.81, 1e200]");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nums(pub [f64; 3]);

impl fmt::Display for Nums {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [x, y, z] = self.0.map(Num);
        write!(f, "[{x}, {y}, {z}]")
    }
}

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-4..1e6).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}
