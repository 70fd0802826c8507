//! What a query asks for: the window `[0, t_max]`, the accuracy mode, and whether contact
//! geometry is wanted.

use super::BatchError;
use crate::Accuracy;

/// The options of every query: the time window `[0, t_max]`, the accuracy mode, and whether
/// the contact point and normal are computed for each contact found (off by default: the
/// kernels find times only).
///
/// ```
/// use spheresweep::{Accuracy, QueryOptions};
/// let options = QueryOptions::new(10.0, Accuracy::Stable)?.with_geometry(true);
/// assert_eq!((options.t_max(), options.geometry()), (10.0, true));
/// assert!(QueryOptions::new(-1.0, Accuracy::Stable).is_err());
/// # Ok::<(), spheresweep::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QueryOptions {
    t_max: f32,
    accuracy: Accuracy,
    geometry: bool,
}

impl QueryOptions {
    /// A query over `[0, t_max]` in `accuracy` mode, without geometry.
    ///
    /// # Errors
    /// [`BatchError::Window`] if `t_max` is NaN or negative (`+∞` is allowed).
    ///
    /// ```
    /// use spheresweep::{Accuracy, BatchError, QueryOptions};
    /// assert!(QueryOptions::new(f32::INFINITY, Accuracy::Double).is_ok());
    /// assert!(matches!(QueryOptions::new(f32::NAN, Accuracy::Double), Err(BatchError::Window(_))));
    /// ```
    pub fn new(t_max: f32, accuracy: Accuracy) -> Result<Self, BatchError> {
        if t_max.is_nan() || t_max < 0.0 {
            return Err(BatchError::Window(t_max));
        }
        Ok(Self {
            t_max,
            accuracy,
            geometry: false,
        })
    }

    /// The same query, with or without contact geometry.
    ///
    /// ```
    /// use spheresweep::QueryOptions;
    /// assert!(QueryOptions::default().with_geometry(true).geometry());
    /// ```
    #[must_use]
    pub fn with_geometry(self, geometry: bool) -> Self {
        Self { geometry, ..self }
    }

    /// End of the window.
    ///
    /// ```
    /// use spheresweep::{Accuracy, QueryOptions};
    /// assert_eq!(QueryOptions::new(2.5, Accuracy::Stable)?.t_max(), 2.5);
    /// assert_eq!(QueryOptions::default().t_max(), f32::INFINITY);
    /// # Ok::<(), spheresweep::BatchError>(())
    /// ```
    #[inline]
    pub fn t_max(&self) -> f32 {
        self.t_max
    }

    /// Accuracy mode.
    ///
    /// ```
    /// use spheresweep::{Accuracy, QueryOptions};
    /// assert_eq!(QueryOptions::new(1.0, Accuracy::Textbook)?.accuracy(), Accuracy::Textbook);
    /// # Ok::<(), spheresweep::BatchError>(())
    /// ```
    #[inline]
    pub fn accuracy(&self) -> Accuracy {
        self.accuracy
    }

    /// Whether contact geometry is computed.
    ///
    /// ```
    /// use spheresweep::QueryOptions;
    /// assert!(!QueryOptions::default().geometry()); // times only, unless asked
    /// ```
    #[inline]
    pub fn geometry(&self) -> bool {
        self.geometry
    }
}

impl Default for QueryOptions {
    /// `[0, +∞)`, [`Accuracy::Stable`], no geometry.
    fn default() -> Self {
        Self {
            t_max: f32::INFINITY,
            accuracy: Accuracy::Stable,
            geometry: false,
        }
    }
}
