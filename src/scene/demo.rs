//! The built-in scene of `spheresweep demo`: a vessel with a floor, a pillar and a few balls.

use super::Scene;
use crate::{Container, Cylinder, Plane, Sphere, SphereStore, Statics};

/// A small scene with every pair kind: nine spheres in a vessel of radius 10, a floor at
/// `z = −4` and a pillar of radius 1 along `z` through `(3, 0)`.
///
/// ```
/// let scene = spheresweep::scene::demo();
/// assert_eq!((scene.spheres.len(), scene.statics.len()), (9, 3));
/// ```
pub fn demo() -> Scene {
    let sphere = |c: [f32; 3], v: [f32; 3], r: f32| {
        Sphere::new(c, v, r, 1.0).expect("built-in demo sphere is valid")
    };
    Scene {
        spheres: SphereStore::from_spheres(&[
            // Two balls on a head-on course along x.
            sphere([-6.0, 2.0, 0.0], [2.0, 0.0, 0.0], 0.5),
            sphere([0.0, 2.0, 0.0], [-1.0, 0.0, 0.0], 0.5),
            // Falling onto the floor.
            sphere([-2.0, -3.0, 3.0], [0.0, 0.0, -3.0], 0.75),
            // Rolling into the pillar.
            sphere([8.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0),
            // Flying outwards to the vessel's wall.
            sphere([0.0, -5.0, 2.0], [0.0, -1.0, 0.5], 0.5),
            // Moving along the pillar's axis: never reaches it.
            sphere([5.0, 0.0, 4.0], [0.0, 0.0, 0.5], 0.5),
            // At rest, until the next ball grazes it.
            sphere([-5.0, 5.0, 1.0], [0.0, 0.0, 0.0], 0.5),
            // Grazes the ball at rest: offset 0.75 = D sideways, so B² − 4AC = 0 exactly, t = 3.
            sphere([-5.75, 8.0, 1.0], [0.0, -1.0, 0.0], 0.25),
            // Drifting slowly in open space: nothing within the window.
            sphere([0.0, 5.0, -2.0], [0.1, 0.0, 0.0], 0.5),
        ]),
        statics: Statics::new()
            .with(
                Plane::new([0.0, 0.0, -4.0], [0.0, 0.0, 1.0]).expect("valid floor"),
                (),
            )
            .with(
                Cylinder::new([3.0, 0.0, 0.0], [3.0, 0.0, 1.0], 1.0).expect("valid pillar"),
                (),
            )
            .with(Container::new([0.0; 3], 10.0).expect("valid vessel"), ()),
    }
}
