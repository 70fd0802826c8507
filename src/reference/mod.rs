//! The scalar reference path: the seed's formulas, literally, in f64, one file per pair kind.
//!
//! It is the specification the 8-wide kernels are tested against. Every function here takes
//! validated shapes, so no input can make it panic or divide by zero. Policies for the cases
//! the seed leaves open are in [`quadratic`] and in docs/derivations/policies.md.

pub mod quadratic;
pub mod scene;
pub mod sphere_container;
pub mod sphere_cylinder;
pub mod sphere_plane;
pub mod sphere_sphere;

pub mod pair;

pub use crate::contact::{Contact, Side};
pub use pair::Pair;
pub use quadratic::{Quadratic, Roots, earliest_contact};
