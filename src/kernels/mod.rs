//! The 8-wide kernels: `A`, `B`, `C`, the discriminant and the earliest admissible root for
//! eight pairs at once (`wide::f32x8`, or four in `f64x4` for [`Accuracy::Double`]).
//!
//! Each pair kind is one kernel generic over the lane type and the [`quadratic::Solver`] of
//! the accuracy mode; the batch drivers (`crate::batch`) pick the monomorphised kernel once
//! per call. The SIMD stays in this folder and in the lane layer; nothing here is public.
//! The scalar f64 reference (`crate::reference`) is the specification these kernels are
//! tested against; they do not import it.
//!
//! [`Accuracy::Double`]: crate::Accuracy::Double

pub(crate) mod quadratic;
pub(crate) mod sphere_container;
pub(crate) mod sphere_cylinder;
pub(crate) mod sphere_plane;
pub(crate) mod sphere_sphere;
