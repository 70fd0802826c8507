//! The scenes the benchmarks measure: a uniform hard-sphere gas at a packing fraction, and a
//! clustered one, with velocities of unit scale and a window given in radii of travel.

use spheresweep::rng::Rng;
use spheresweep::{Sphere, SphereStore};

/// A uniform gas of `n` spheres of radius 1 in a cube sized for packing fraction `phi`
/// (`n · 4π/3 / L³ = phi`), centres uniform (overlaps allowed: a broad-phase load, not an
/// equilibrium state), velocity components uniform in `[−1, 1]`. Deterministic in `seed`.
///
/// ```
/// let gas = spheresweep_bench::scenes::uniform_gas(1000, 0.3, 1);
/// assert_eq!(gas.len(), 1000);
/// ```
pub fn uniform_gas(n: usize, phi: f64, seed: u64) -> SphereStore {
    let side = box_side(n, phi);
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| {
            let c = (rng.cube(0.5) * side).as_vec3();
            let v = rng.cube(1.0).as_vec3();
            Sphere::new(c.into(), v.into(), 1.0, 1.0).expect("finite generated sphere")
        })
        .collect()
}

/// The side of the cube holding `n` unit spheres at packing fraction `phi`.
///
/// ```
/// use spheresweep_bench::scenes::box_side;
/// let side = box_side(1000, 0.3);
/// let phi = 1000.0 * 4.0 / 3.0 * std::f64::consts::PI / side.powi(3);
/// assert!((phi - 0.3).abs() < 1e-12);
/// ```
pub fn box_side(n: usize, phi: f64) -> f64 {
    (n as f64 * 4.0 / 3.0 * std::f64::consts::PI / phi).cbrt()
}

/// A clustered scene: `n` unit spheres in clumps of about a hundred, each clump a ball at
/// packing fraction about 0.3, the clumps spread over a cube at overall packing fraction
/// 0.01 — dense cells next to empty space.
///
/// ```
/// let scene = spheresweep_bench::scenes::clustered(1000, 1);
/// assert_eq!(scene.len(), 1000);
/// assert!(scene.iter().all(|s| s.radius() == 1.0));
/// ```
pub fn clustered(n: usize, seed: u64) -> SphereStore {
    let mut rng = Rng::new(seed);
    let clumps = n.div_ceil(100).max(1);
    let side = box_side(n, 0.01);
    let centres: Vec<_> = (0..clumps).map(|_| rng.cube(0.5) * side).collect();
    let clump_radius = (100.0f64 / 0.3).cbrt();
    (0..n)
        .map(|i| {
            let c = centres[i % clumps] + rng.direction() * clump_radius * rng.unit().cbrt();
            let v = rng.cube(1.0).as_vec3();
            Sphere::new(c.as_vec3().into(), v.into(), 1.0, 1.0).expect("finite generated sphere")
        })
        .collect()
}

/// The window in which a sphere of speed about 1 travels `radii` radii.
///
/// ```
/// assert_eq!(spheresweep_bench::scenes::window(2.0), 2.0); // speed 1, radius 1
/// ```
pub fn window(radii: f32) -> f32 {
    radii
}
