//! Scenes: a store of spheres and the static shapes around them, all validated. For now, the
//! built-in demonstration scene; loading from files comes with the scene-file issue.

mod demo;

pub use demo::demo;

use crate::{Container, Cylinder, Plane, Shape, SphereStore};

/// Every body of a scene, validated. The spheres live in a [`SphereStore`], so a query reads
/// them as they are and builds nothing per call.
///
/// ```
/// use spheresweep::{Plane, QueryOptions, Sphere, SphereStore, query, scene::Scene};
/// let scene = Scene {
///     spheres: SphereStore::from_spheres(&[
///         Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0)?,
///     ]),
///     planes: vec![Plane::new([0.0; 3], [0.0, 0.0, 1.0])?],
///     ..Scene::default()
/// };
/// assert_eq!(query::first_contacts(&scene, QueryOptions::default())[0].unwrap().time, 2.0);
/// # Ok::<(), spheresweep::Error>(())
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Scene {
    /// Moving spheres.
    pub spheres: SphereStore,
    /// Static infinite planes.
    pub planes: Vec<Plane>,
    /// Static infinite cylinders.
    pub cylinders: Vec<Cylinder>,
    /// Static spherical containers (every sphere is inside each of them).
    pub containers: Vec<Container>,
}

impl Scene {
    /// The body `body` of the scene, by value (`None` if there is no such body).
    ///
    /// ```
    /// use spheresweep::{Body, Shape, ShapeKind};
    /// let scene = spheresweep::scene::demo();
    /// assert!(matches!(scene.body(Body::new(ShapeKind::Plane, 0)), Some(Shape::Plane(_))));
    /// ```
    pub fn body(&self, body: crate::Body) -> Option<Shape> {
        use crate::ShapeKind;
        let i = body.index as usize;
        match body.kind {
            ShapeKind::Sphere => self.spheres.get(i).map(Shape::Sphere),
            ShapeKind::Plane => self.planes.get(i).copied().map(Shape::Plane),
            ShapeKind::Cylinder => self.cylinders.get(i).copied().map(Shape::Cylinder),
            ShapeKind::Container => self.containers.get(i).copied().map(Shape::Container),
        }
    }
}
