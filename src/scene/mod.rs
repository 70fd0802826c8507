//! Scenes: a store of spheres and the static shapes around them, all validated, and the
//! built-in demonstration scene.

mod demo;

pub use demo::demo;

use crate::{Shape, SphereStore, Statics};

/// Every body of a scene, validated. The spheres live in a [`SphereStore`], so a query reads
/// them as they are and builds nothing per call.
///
/// ```
/// use spheresweep::{Plane, QueryOptions, Sphere, SphereStore, Statics, query, scene::Scene};
/// let scene = Scene {
///     spheres: SphereStore::from_spheres(&[
///         Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0)?,
///     ]),
///     statics: Statics::new().with(Plane::new([0.0; 3], [0.0, 0.0, 1.0])?, ()),
/// };
/// assert_eq!(query::first_contacts(&scene, QueryOptions::default())[0].unwrap().time, 2.0);
/// # Ok::<(), spheresweep::Error>(())
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Scene {
    /// Moving spheres.
    pub spheres: SphereStore,
    /// The static shapes: planes, infinite cylinders, containers (every sphere is inside
    /// each container).
    pub statics: Statics,
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
        match body.kind {
            crate::ShapeKind::Sphere => self.spheres.get(body.index as usize).map(Shape::Sphere),
            _ => self.statics.get(body).map(|(s, ())| s.into()),
        }
    }
}
