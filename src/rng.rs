//! A small deterministic generator (splitmix64) for generated scenes, the accuracy study and
//! the benchmarks: the same seed gives the same inputs on every machine.

use glam::DVec3;

/// A deterministic pseudo-random generator (splitmix64).
///
/// ```
/// use spheresweep::rng::Rng;
/// let (mut a, mut b) = (Rng::new(7), Rng::new(7));
/// assert_eq!(a.unit(), b.unit()); // the same seed, the same sequence
/// ```
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    ///
    /// ```
    /// # use spheresweep::rng::Rng;
    /// assert_ne!(Rng::new(1).unit(), Rng::new(2).unit());
    /// ```
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    ///
    /// ```
    /// # use spheresweep::rng::Rng;
    /// let mut rng = Rng::new(3);
    /// assert!((0..1000).map(|_| rng.unit()).all(|u| (0.0..1.0).contains(&u)));
    /// ```
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in `[lo, hi)`.
    ///
    /// ```
    /// # use spheresweep::rng::Rng;
    /// let mut rng = Rng::new(3);
    /// assert!((0..1000).map(|_| rng.range(-2.0, 5.0)).all(|x| (-2.0..5.0).contains(&x)));
    /// ```
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// `true` with probability one half.
    ///
    /// ```
    /// # use spheresweep::rng::Rng;
    /// let mut rng = Rng::new(3);
    /// let heads = (0..10_000).filter(|_| rng.coin()).count();
    /// assert!((4_700..5_300).contains(&heads)); // 6 standard deviations (50) either side
    /// ```
    pub fn coin(&mut self) -> bool {
        self.next_u64() & 1 == 1
    }
    /// `±1`.
    ///
    /// ```
    /// # use spheresweep::rng::Rng;
    /// let mut rng = Rng::new(3);
    /// assert!((0..100).all(|_| rng.sign().abs() == 1.0));
    /// ```
    pub fn sign(&mut self) -> f64 {
        if self.coin() { 1.0 } else { -1.0 }
    }
    /// Uniform in the cube `[−lim, lim]³`.
    ///
    /// ```
    /// # use spheresweep::rng::Rng;
    /// let mut rng = Rng::new(3);
    /// assert!((0..100).all(|_| rng.cube(2.0).abs().max_element() <= 2.0));
    /// ```
    pub fn cube(&mut self, lim: f64) -> DVec3 {
        DVec3::new(
            self.range(-lim, lim),
            self.range(-lim, lim),
            self.range(-lim, lim),
        )
    }
    /// A standard normal deviate (Box–Muller).
    ///
    /// ```
    /// # use spheresweep::rng::Rng;
    /// let mut rng = Rng::new(3);
    /// let mean = (0..10_000).map(|_| rng.normal()).sum::<f64>() / 10_000.0;
    /// assert!(mean.abs() < 0.05); // 5 standard errors (1/√10⁴ = 0.01)
    /// ```
    pub fn normal(&mut self) -> f64 {
        let u = 1.0 - self.unit(); // (0, 1]
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
    /// A uniformly random unit vector.
    ///
    /// ```
    /// # use spheresweep::rng::Rng;
    /// let d = Rng::new(3).direction();
    /// assert!((d.length() - 1.0).abs() < 1e-12);
    /// ```
    pub fn direction(&mut self) -> DVec3 {
        loop {
            let v = self.cube(1.0);
            let l = v.length_squared();
            if l > 1e-4 && l <= 1.0 {
                return v / l.sqrt();
            }
        }
    }
    /// A random unit vector perpendicular to the unit vector `u`.
    ///
    /// ```
    /// # use spheresweep::rng::Rng;
    /// let u = glam::DVec3::Z;
    /// let p = Rng::new(3).perpendicular(u);
    /// assert!(p.dot(u).abs() < 1e-12 && (p.length() - 1.0).abs() < 1e-12);
    /// ```
    pub fn perpendicular(&mut self, u: DVec3) -> DVec3 {
        loop {
            let v = self.direction();
            let p = v - u * v.dot(u);
            if p.length_squared() > 1e-4 {
                return p.normalize();
            }
        }
    }
}
