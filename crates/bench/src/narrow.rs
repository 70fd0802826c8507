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
///
/// ```
/// use spheresweep_bench::narrow::{T_MAX, cast_options};
/// let options = cast_options();
/// assert_eq!(options.max_time_of_impact, T_MAX);
/// assert!(options.stop_at_penetration);
/// ```
pub fn cast_options() -> ShapeCastOptions {
    ShapeCastOptions {
        max_time_of_impact: T_MAX,
        stop_at_penetration: true,
        ..Default::default()
    }
}

/// A random sphere in the cube `[−half, half]³` with velocity components up to `speed`.
///
/// ```
/// use spheresweep::rng::Rng;
/// use spheresweep_bench::narrow::random_sphere;
/// let s = random_sphere(&mut Rng::new(1), 10.0, 5.0);
/// assert!(s.centre().abs().max_element() <= 10.0 && s.velocity().abs().max_element() <= 5.0);
/// assert!((0.2..1.5).contains(&s.radius()));
/// ```
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
///
/// ```
/// use spheresweep::QueryOptions;
/// use spheresweep_bench::narrow::{SpherePairs, T_MAX};
/// let pairs = SpherePairs::new(256, 1);
/// let (mut ours, mut peer) = (vec![0.0; 256], vec![0.0; 256]);
/// pairs.ours(QueryOptions::new(T_MAX, Default::default()).unwrap(), &mut ours);
/// pairs.parry(&mut peer);
/// // Pairs that start apart: both find the same contacts, at nearly the same times (parry
/// // reports every overlap at the start as 0, ours only one that deepens).
/// let apart = pairs.a.iter().zip(pairs.b.iter());
/// let apart = apart.map(|(a, b)| a.centre().distance(b.centre()) > a.radius() + b.radius());
/// for ((o, p), _) in ours.iter().zip(&peer).zip(apart).filter(|(_, apart)| *apart) {
///     assert!(o.is_finite() == p.is_finite() && (!o.is_finite() || (o - p).abs() < 1e-3));
/// }
/// ```
pub struct SpherePairs {
    /// First spheres.
    pub a: SphereStore,
    /// Second spheres.
    pub b: SphereStore,
    parry: Vec<(BallAt, BallAt)>,
}

impl SpherePairs {
    /// `n` random pairs from `seed`.
    ///
    /// ```
    /// use spheresweep_bench::narrow::SpherePairs;
    /// let pairs = SpherePairs::new(100, 1);
    /// assert_eq!((pairs.a.len(), pairs.b.len()), (100, 100));
    /// assert_eq!(SpherePairs::new(100, 1).a, pairs.a); // deterministic in the seed
    /// ```
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
    ///
    /// ```
    /// use spheresweep::{QueryOptions, batch};
    /// use spheresweep_bench::narrow::SpherePairs;
    /// let pairs = SpherePairs::new(64, 1);
    /// let (mut out, mut want) = (vec![0.0; 64], vec![0.0; 64]);
    /// pairs.ours(QueryOptions::default(), &mut out);
    /// batch::zip_times(&pairs.a, &pairs.b, QueryOptions::default(), &mut want).unwrap();
    /// assert_eq!(out, want);
    /// ```
    pub fn ours(&self, options: QueryOptions, out: &mut [f32]) {
        batch::zip_times(&self.a, &self.b, options, out).expect("equal lengths");
    }

    /// parry3d: `query::cast_shapes` per pair.
    ///
    /// ```
    /// use spheresweep_bench::narrow::{SpherePairs, T_MAX};
    /// let mut out = vec![0.0; 64];
    /// SpherePairs::new(64, 1).parry(&mut out);
    /// assert!(out.iter().all(|&t| t == f32::INFINITY || (0.0..=T_MAX).contains(&t)));
    /// ```
    pub fn parry(&self, out: &mut [f32]) {
        for (((p1, v1, g1), (p2, v2, g2)), o) in self.parry.iter().zip(out.iter_mut()) {
            let hit = query::cast_shapes(p1, *v1, g1, p2, *v2, g2, cast_options())
                .expect("ball pairs are supported");
            *o = hit.map_or(f32::INFINITY, |h| h.time_of_impact);
        }
    }

    /// parry3d's direct ball–ball path, `query::details::cast_shapes_ball_ball`.
    ///
    /// ```
    /// use spheresweep_bench::narrow::SpherePairs;
    /// let pairs = SpherePairs::new(64, 1);
    /// let (mut direct, mut generic) = (vec![0.0; 64], vec![0.0; 64]);
    /// pairs.parry_ball_ball(&mut direct);
    /// pairs.parry(&mut generic);
    /// assert!(direct.iter().zip(&generic).all(|(a, b)| a == b || (a - b).abs() < 1e-3));
    /// ```
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
///
/// ```
/// use spheresweep::QueryOptions;
/// use spheresweep_bench::narrow::{T_MAX, plane};
/// let floor = plane(256, 1);
/// let (mut ours, mut peer) = (vec![0.0; 256], vec![0.0; 256]);
/// floor.ours(QueryOptions::new(T_MAX, Default::default()).unwrap(), &mut ours);
/// floor.parry(&mut peer);
/// // Spheres below the plane are inside parry's half-space (a contact at 0): compare the others.
/// let above = floor.spheres.iter().map(|s| s.centre().z > s.radius());
/// for ((o, p), _) in ours.iter().zip(&peer).zip(above).filter(|(_, above)| *above) {
///     assert!(o.is_finite() == p.is_finite() && (!o.is_finite() || (o - p).abs() < 1e-3));
/// }
/// ```
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
    ///
    /// ```
    /// use spheresweep::{QueryOptions, batch};
    /// use spheresweep_bench::narrow::container;
    /// let vessel = container(64, 1);
    /// let (mut out, mut want) = (vec![0.0; 64], vec![0.0; 64]);
    /// vessel.ours(QueryOptions::default(), &mut out);
    /// let options = QueryOptions::default();
    /// batch::static_times(&vessel.spheres, &vessel.shape, options, &mut want).unwrap();
    /// assert_eq!(out, want);
    /// ```
    pub fn ours(&self, options: QueryOptions, out: &mut [f32]) {
        batch::static_times(&self.spheres, &self.shape, options, out).expect("one slot each");
    }

    /// Whether parry has this shape (it has no inside-of-a-ball cast).
    ///
    /// ```
    /// use spheresweep_bench::narrow::{container, cylinder};
    /// assert!(cylinder(8, 1).has_peer() && !container(8, 1).has_peer());
    /// ```
    pub fn has_peer(&self) -> bool {
        self.peer.is_some()
    }

    /// parry3d: `query::cast_shapes` per sphere (no-op without a peer shape).
    ///
    /// ```
    /// use spheresweep_bench::narrow::container;
    /// let mut out = vec![-1.0; 8];
    /// container(8, 1).parry(&mut out); // no peer: nothing written
    /// assert_eq!(out, [-1.0; 8]);
    /// ```
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
///
/// ```
/// let floor = spheresweep_bench::narrow::plane(10, 1);
/// assert_eq!((floor.spheres.len(), floor.shape.normal().z), (10, 1.0));
/// ```
pub fn plane(n: usize, seed: u64) -> AgainstStatic<Plane> {
    let plane = Plane::new([0.0; 3], [0.0, 0.0, 1.0]).expect("valid plane");
    let peer: Box<dyn ParryShape> = Box::new(HalfSpace::new(Vector::Z));
    AgainstStatic::with(n, seed, plane, Some((Pose::identity(), peer)))
}

/// An infinite pillar along `(0.3, 1, 0.2)`; parry's finite cylinder is 2000 long (a hundred
/// times the scene), turned onto the same axis.
///
/// ```
/// let pillar = spheresweep_bench::narrow::cylinder(10, 1);
/// assert_eq!(pillar.shape.radius(), 2.0);
/// assert!((pillar.shape.axis().length() - 1.0).abs() < 1e-6);
/// ```
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
///
/// ```
/// let vessel = spheresweep_bench::narrow::container(10, 1);
/// assert_eq!(vessel.shape.radius(), 40.0);
/// ```
pub fn container(n: usize, seed: u64) -> AgainstStatic<Container> {
    let vessel = Container::new([0.0; 3], 40.0).expect("valid vessel");
    AgainstStatic::with(n, seed, vessel, None)
}
