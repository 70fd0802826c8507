//! A small deterministic generator (splitmix64) for generated scenes, the accuracy study and
//! the benchmarks: the same seed gives the same inputs on every machine.

use glam::DVec3;

/// A deterministic pseudo-random generator (splitmix64).
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
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
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// `true` with probability one half.
    pub fn coin(&mut self) -> bool {
        self.next_u64() & 1 == 1
    }
    /// `±1`.
    pub fn sign(&mut self) -> f64 {
        if self.coin() { 1.0 } else { -1.0 }
    }
    /// Uniform in the cube `[−lim, lim]³`.
    pub fn cube(&mut self, lim: f64) -> DVec3 {
        DVec3::new(
            self.range(-lim, lim),
            self.range(-lim, lim),
            self.range(-lim, lim),
        )
    }
    /// A standard normal deviate (Box–Muller).
    pub fn normal(&mut self) -> f64 {
        let u = 1.0 - self.unit(); // (0, 1]
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
    /// A uniformly random unit vector.
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
