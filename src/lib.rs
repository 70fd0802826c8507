//! # spheresweep
//!
//! Continuous collision detection of moving spheres against each other, infinite planes,
//! infinite cylinders and the inside of spherical containers. Every contact time is the
//! earliest admissible root of `A t² + B t + C = 0` (docs/derivations/policies.md).
//!
//! ```
//! use spheresweep::{Sphere, Plane, reference};
//! let floor = Plane::new([0.0; 3], [0.0, 0.0, 1.0])?;
//! let ball = Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0)?;
//! assert_eq!(reference::sphere_plane::time_of_impact(&ball, &floor, 10.0), Some(2.0));
//! # Ok::<(), spheresweep::ShapeError>(())
//! ```
#![warn(missing_docs)]

pub mod accuracy;
pub mod error;
pub mod narrow;
pub mod query;
pub mod reference;
pub mod scene;
pub mod shape;
pub mod store;
#[cfg(feature = "study")]
pub mod study;

pub use accuracy::Accuracy;
pub use error::{Problem, ShapeError, ShapeKind};
pub use shape::{Container, Cylinder, Plane, Sphere};
pub use store::{SphereStore, StoreError};

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
