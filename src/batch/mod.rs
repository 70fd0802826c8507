//! Batch drivers: the entry points that run the 8-wide kernels over stores, pair lists and
//! static shapes. Each returns the earliest contact per query item in `[0, t_max]`; above
//! [`PARALLEL_MIN`] items the work is split over rayon in fixed chunks, so results are
//! identical for any thread count.
//!
//! - [`options`]: what a query asks for ([`QueryOptions`]);
//! - `driver`: chunking, the accuracy-mode dispatch, parallelism;
//! - [`pairs`]: sphere pairs — [`zip_times`], [`pair_times`], [`one_against_times`],
//!   [`earliest_sphere_contact`], and the single-pair [`time_of_impact`];
//! - [`statics`]: spheres against planes, cylinders, containers — [`static_times`],
//!   [`earliest_static_contacts`].

mod driver;
pub mod options;
pub mod pairs;
pub mod statics;

pub use driver::PARALLEL_MIN;
pub use options::QueryOptions;
pub use pairs::{
    earliest_sphere_contact, one_against_times, pair_times, time_of_impact, zip_times,
};
pub use statics::{StaticShape, earliest_static_contacts, static_times, static_times_any};

use crate::contact::{Body, Contact};

/// The earliest contact of one sphere: when, with which body, and — only if the options asked
/// for it — the contact geometry (computed in f64 at `time`).
///
/// ```
/// use spheresweep::{Container, QueryOptions, ShapeKind, Sphere, SphereStore, batch};
/// let vessel = [Container::new([0.0; 3], 5.0)?];
/// let balls = SphereStore::from_spheres(&[Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?]);
/// let options = QueryOptions::default().with_geometry(true);
/// let hit = batch::earliest_static_contacts(&balls, &vessel, options)[0].unwrap();
/// assert_eq!((hit.time, hit.body.kind), (4.0, ShapeKind::Container));
/// assert_eq!(hit.geometry.unwrap().point.to_array(), [5.0, 0.0, 0.0]); // on the wall
/// # Ok::<(), spheresweep::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstContact {
    /// Time of impact in `[0, t_max]`.
    pub time: f32,
    /// The body touched.
    pub body: Body,
    /// Centres, contact point and normal at `time`, if asked for.
    pub geometry: Option<Contact>,
}

/// A batch call's arguments do not fit together.
///
/// ```
/// use spheresweep::{BatchError, QueryOptions, SphereStore, batch::pair_times};
/// let store = SphereStore::new();
/// let err = pair_times(&store, &[[0, 1]], QueryOptions::default(), &mut [0.0]).unwrap_err();
/// assert_eq!(err, BatchError::IndexOutOfRange { pair: 0, index: 0, len: 0 });
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BatchError {
    /// The window's end is NaN or negative.
    #[error("t_max must be zero or more (or +inf), got {0}")]
    Window(f32),
    /// The output slice has the wrong length.
    #[error("output has {found} slots, expected {expected} (one per query item)")]
    OutputLength {
        /// Query items.
        expected: usize,
        /// Output slots.
        found: usize,
    },
    /// Two stores meant to be paired element by element differ in length.
    #[error("the stores differ in length: {a} and {b} spheres")]
    StoreLengths {
        /// First store.
        a: usize,
        /// Second store.
        b: usize,
    },
    /// A pair names a sphere the store does not hold.
    #[error("pair {pair}: sphere index {index} is out of range (the store holds {len})")]
    IndexOutOfRange {
        /// Position of the pair in the list.
        pair: usize,
        /// The bad index.
        index: u32,
        /// Spheres in the store.
        len: usize,
    },
}

fn check_output(expected: usize, out: &[f32]) -> Result<(), BatchError> {
    if out.len() == expected {
        Ok(())
    } else {
        Err(BatchError::OutputLength {
            expected,
            found: out.len(),
        })
    }
}
