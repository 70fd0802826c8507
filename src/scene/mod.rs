//! Scenes: a set of validated shapes. For now, the built-in demonstration scene; loading from
//! files comes with the scene-file issue.

mod demo;

pub use demo::demo;

use crate::{Container, Cylinder, Plane, Sphere};

/// Every shape of a scene, validated.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Scene {
    /// Moving spheres.
    pub spheres: Vec<Sphere>,
    /// Static infinite planes.
    pub planes: Vec<Plane>,
    /// Static infinite cylinders.
    pub cylinders: Vec<Cylinder>,
    /// Static spherical containers (every sphere is inside each of them).
    pub containers: Vec<Container>,
}
