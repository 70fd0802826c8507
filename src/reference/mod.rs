//! The scalar reference path: the seed's formulas, literally, in f64, one file per pair kind.
//!
//! It is the specification the 8-wide kernels are tested against. Every function here takes
//! validated shapes, so no input can make it panic or divide by zero. Policies for the cases
//! the seed leaves open are in [`quadratic`] and in docs/derivations/policies.md.
//!
//! # Where its own accuracy ends
//!
//! The reference is the seed's formula *literally*, in f64: it shares `textbook`'s weakness at
//! f64's precision. Its hit/miss answer is exact only outside the band
//! `|q| ≲ 2·2⁻⁵³·A·X²` around grazing, a relative band of about `2⁻⁵³ (X/D)²` of `D²` in the
//! closest approach (`X` the distance the pair starts apart). For a pair `10⁷ D` apart that is
//! `10¹⁴ · 1.1·10⁻¹⁶ ≈ 1 %`: a distant pair grazing within `10⁻⁷ D` may be answered wrongly
//! here. Its times carry `2⁻⁵³ X²/(D·V·t)` relative error near grazing and near touching. The
//! f64 range holds every finite f32 input (docs/derivations/range.md). Beyond these limits the
//! accuracy study's exact rational oracle (`crates/study`, docs/derivations/oracle.md) is the
//! judge, and the tests that go there (`crates/study/tests/hard_cases.rs`) use it.

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
