//! The 8-wide narrow phase: `A`, `B`, `C`, the discriminant and the earliest admissible root
//! for eight pairs at once (`wide::f32x8`, or four in `f64x4` for [`Accuracy::Double`]).
//!
//! Each pair kind is one kernel generic over the lane type and the [`quadratic::Solver`] of
//! the accuracy mode; the batch entry points in [`batch`] pick the monomorphised kernel once
//! per call. The scalar f64 reference (`crate::reference`) is the specification these kernels
//! are tested against.
//!
//! [`Accuracy::Double`]: crate::Accuracy::Double

pub mod batch;
pub mod lanes;
pub mod quadratic;
pub mod sphere_container;
pub mod sphere_cylinder;
pub mod sphere_plane;
pub mod sphere_sphere;

pub use batch::{
    BatchError, FirstContact, Query, StaticShape, first_contact_against, first_contacts,
    first_contacts_with_geometry, one_against_times, pair_times, static_times, zip_times,
};
