//! # spheresweep
//!
//! Continuous collision detection of moving spheres against each other, infinite planes,
//! infinite cylinders and the inside of spherical containers. Every contact time is the
//! earliest admissible root of `A t² + B t + C = 0` (docs/derivations/policies.md), found
//! eight pairs at a time by SIMD kernels in three [`Accuracy`] modes.
//!
//! ```
//! use spheresweep::{Plane, QueryOptions, Sphere, SphereStore, batch};
//! let floor = [Plane::new([0.0; 3], [0.0, 0.0, 1.0])?];
//! let balls = SphereStore::from_spheres(&[Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0)?]);
//! let hits = batch::earliest_static_contacts(&balls, &floor, QueryOptions::default());
//! assert_eq!(hits[0].unwrap().time, 2.0);
//! # Ok::<(), spheresweep::Error>(())
//! ```
//!
//! Layers import one way (docs/ARCHITECTURE.md): shapes and the lane layer ← [`store`] ←
//! kernels (private) ← [`batch`] ← [`query`]; [`contact`] holds the contact geometry both the
//! fast path and the [`reference`](mod@reference) use; the reference is the specification the fast path is
//! tested against and never imports.
#![warn(missing_docs)]

pub mod accuracy;
pub mod batch;
pub mod broad;
pub mod contact;
pub mod error;
pub mod io;
mod kernels;
mod lanes;
pub mod query;
pub mod reference;
pub mod rng;
pub mod scene;
pub mod shape;
pub mod sim;
pub mod statics;
pub mod store;

pub use accuracy::Accuracy;
pub use batch::{BatchError, FirstContact, QueryOptions, time_of_impact};
pub use contact::{Body, Contact, Side};
pub use error::{Error, Problem, ShapeError};
pub use shape::{Container, Cylinder, Plane, Shape, ShapeKind, Sphere};
pub use statics::{Static, StaticShape, Statics};
pub use store::{SphereStore, StoreError};

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
