//! The narrow-phase workloads of the benchmarks and `spheresweep bench`: the same random pairs,
//! answered by our batch kernels and by parry3d's `cast_shapes` on shapes and poses built
//! beforehand.

use parry3d::math::{Pose, Vector};
use parry3d::query::{self, ShapeCastOptions};
use parry3d::shape::{Ball, Cylinder as ParryCylinder, HalfSpace, Shape as ParryShape};
use spheresweep::batch::{self, StaticShape};
use spheresweep::rng::Rng;
use spheresweep::{Container, Cylinder, Plane, QueryOptions, Sphere, SphereStore};

/// The window of every narrow-phase workload.
pub const T_MAX: f32 = 4.0;

/// parry's options for the same window, stopping at penetration (a contact at 0).
pub fn cast_options() -> ShapeCastOptions {
    ShapeCastOptions {
        max_time_of_impact: T_MAX,
        stop_at_penetration: true,
        ..Default::default()
    }
}

/// A random sphere in the cube `[−half, half]³` with velocity components up to `speed`.
pub fn random_sphere(rng: &mut Rng, half: f64, speed: f64) -> Sphere {
    let (c, v, r) = (rng.cube(half), rng.cube(speed), rng.range(0.2, 1.5));
    Sphere::new(c.as_vec3().into(), v.as_vec3().into(), r as f32, 1.0).expect("finite sphere")
}

type BallAt = (Pose, Vector, Ball);

fn ball_at(s: &Sphere) -> BallAt {
    (
        Pose::from_translation(s.centre()),
        s.velocity(),
        Ball::new(s.radius()),
    )
}

/// `n` sphere pairs, as two stores (ours) and as parry balls and poses.
pub struct SpherePairs {
    /// First spheres.
    pub a: SphereStore,
    /// Second spheres.
    pub b: SphereStore,
    parry: Vec<(BallAt, BallAt)>,
}

impl SpherePairs {
    /// `n` random pairs from `seed`.
    pub fn new(n: usize, seed: u64) -> Self {
        let mut rng = Rng::new(seed);
        let a: Vec<Sphere> = (0..n).map(|_| random_sphere(&mut rng, 10.0, 5.0)).collect();
        let b: Vec<Sphere> = (0..n).map(|_| random_sphere(&mut rng, 10.0, 5.0)).collect();
        let parry = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (ball_at(x), ball_at(y)))
            .collect();
        Self {
            a: SphereStore::from_spheres(&a),
            b: SphereStore::from_spheres(&b),
            parry,
        }
    }

    /// Ours: `batch::zip_times`.
    pub fn ours(&self, options: QueryOptions, out: &mut [f32]) {
        batch::zip_times(&self.a, &self.b, options, out).expect("equal lengths");
    }

    /// parry3d: `query::cast_shapes` per pair.
    pub fn parry(&self, out: &mut [f32]) {
        for (((p1, v1, g1), (p2, v2, g2)), o) in self.parry.iter().zip(out.iter_mut()) {
            let hit = query::cast_shapes(p1, *v1, g1, p2, *v2, g2, cast_options())
                .expect("ball pairs are supported");
            *o = hit.map_or(f32::INFINITY, |h| h.time_of_impact);
        }
    }

    /// parry3d's direct ball–ball path, `query::details::cast_shapes_ball_ball`.
    pub fn parry_ball_ball(&self, out: &mut [f32]) {
        for (((p1, v1, g1), (p2, v2, g2)), o) in self.parry.iter().zip(out.iter_mut()) {
            let hit = query::details::cast_shapes_ball_ball(
                &p1.inv_mul(p2),
                *v2 - *v1,
                g1,
                g2,
                cast_options(),
            );
            *o = hit.map_or(f32::INFINITY, |h| h.time_of_impact);
        }
    }
}

/// `n` spheres against one static shape, ours and (where parry has the shape) parry's.
pub struct AgainstStatic<K> {
    /// The spheres.
    pub spheres: SphereStore,
    /// The shape.
    pub shape: K,
    balls: Vec<BallAt>,
    peer: Option<(Pose, Box<dyn ParryShape>)>,
}

impl<K: StaticShape> AgainstStatic<K> {
    fn with(n: usize, seed: u64, shape: K, peer: Option<(Pose, Box<dyn ParryShape>)>) -> Self {
        let mut rng = Rng::new(seed);
        let spheres: Vec<Sphere> = (0..n)
            .map(|_| random_sphere(&mut rng, 20.0, 10.0))
            .collect();
        Self {
            balls: spheres.iter().map(ball_at).collect(),
            spheres: SphereStore::from_spheres(&spheres),
            shape,
            peer,
        }
    }

    /// Ours: `batch::static_times`.
    pub fn ours(&self, options: QueryOptions, out: &mut [f32]) {
        batch::static_times(&self.spheres, &self.shape, options, out).expect("one slot each");
    }

    /// Whether parry has this shape (it has no inside-of-a-ball cast).
    pub fn has_peer(&self) -> bool {
        self.peer.is_some()
    }

    /// parry3d: `query::cast_shapes` per sphere (no-op without a peer shape).
    pub fn parry(&self, out: &mut [f32]) {
        let Some((pose, shape)) = &self.peer else {
            return;
        };
        for ((p1, v1, g1), o) in self.balls.iter().zip(out.iter_mut()) {
            let hit = query::cast_shapes(p1, *v1, g1, pose, Vector::ZERO, &**shape, cast_options())
                .expect("supported shapes");
            *o = hit.map_or(f32::INFINITY, |h| h.time_of_impact);
        }
    }
}

/// The plane `z = 0` facing `+z`; parry's half-space is the solid `z ≤ 0` with that normal.
pub fn plane(n: usize, seed: u64) -> AgainstStatic<Plane> {
    let plane = Plane::new([0.0; 3], [0.0, 0.0, 1.0]).expect("valid plane");
    let peer: Box<dyn ParryShape> = Box::new(HalfSpace::new(Vector::Z));
    AgainstStatic::with(n, seed, plane, Some((Pose::identity(), peer)))
}

/// An infinite pillar along `(0.3, 1, 0.2)`; parry's finite cylinder is 2000 long (a hundred
/// times the scene), turned onto the same axis.
pub fn cylinder(n: usize, seed: u64) -> AgainstStatic<Cylinder> {
    let axis = glam::Vec3::new(0.3, 1.0, 0.2).normalize();
    let cylinder = Cylinder::from_axis([0.0; 3], axis.into(), 2.0).expect("valid cylinder");
    let pose = Pose::from_parts(
        glam::Vec3::ZERO,
        glam::Quat::from_rotation_arc(glam::Vec3::Y, axis),
    );
    let peer: Box<dyn ParryShape> = Box::new(ParryCylinder::new(1000.0, 2.0));
    AgainstStatic::with(n, seed, cylinder, Some((pose, peer)))
}

/// A vessel of radius 40 (parry has no inside-of-a-ball cast: no peer).
pub fn container(n: usize, seed: u64) -> AgainstStatic<Container> {
    let vessel = Container::new([0.0; 3], 40.0).expect("valid vessel");
    AgainstStatic::with(n, seed, vessel, None)
}
