//! Spheres placed where their coordinates round coarser than their contacts' tolerance: a
//! contact there can overlap by about the rounding, beyond [`OVERLAP_TOLERANCE`], though the
//! scene is within the engine's range (docs/derivations/simulation.md, "Contacts far from the
//! origin").

use super::{Boundary, OVERLAP_TOLERANCE, Simulation, World};
use crate::error::Num;

/// A sphere whose centre rounds by more than the tolerance of a contact with a sphere of its
/// own size ([`World::coarse_sphere`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct CoarseSphere {
    /// The sphere (its index in [`World::spheres`]).
    pub sphere: usize,
    /// How many other spheres are coarse too.
    pub others: usize,
    /// The largest coordinate its centre has (in a periodic box: the box's largest length,
    /// which it roams).
    pub coordinate: f64,
    /// How far off the distance of two centres there may be: `√3` ulps of `coordinate` (half
    /// an ulp on each axis of each centre).
    pub rounding: f64,
    /// The overlap a contact with a sphere of its size may have: `2⁻¹⁶` of its diameter.
    pub tolerance: f64,
}

impl CoarseSphere {
    /// What is coarse and what follows, without the sphere's name (a scene file names its
    /// entry instead).
    pub fn problem(&self) -> String {
        let others = match self.others {
            0 => String::new(),
            1 => " (and 1 other sphere)".into(),
            n => format!(" (and {n} other spheres)"),
        };
        format!(
            "its coordinate {} rounds so that two centres' distance is off by up to {:.2e}, \
             more than the contact tolerance {:.2e} (2⁻¹⁶ of its diameter){others}: its \
             collisions may overlap by that much; move the scene nearer the origin or use \
             larger length units",
            Num(self.coordinate),
            self.rounding,
            self.tolerance
        )
    }
}

impl std::fmt::Display for CoarseSphere {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "sphere {}: {}", self.sphere, self.problem())
    }
}

/// One unit in the last place of `x` (positive, finite and normal): `2^(⌊log₂ x⌋ − 52)`.
fn ulp(x: f64) -> f64 {
    f64::from_bits(x.to_bits() & 0x7ff0_0000_0000_0000) * f64::EPSILON
}

impl World {
    /// The first sphere whose centre rounds coarsest against its contacts' tolerance, if that
    /// is beyond it: `√3 ulp(max |xₖ|) > 2⁻¹⁶ · 2 radius` (in a periodic box, the box's
    /// largest length for `max |xₖ|`). Never for a sphere within `2³⁶` radii of the origin on
    /// every axis. This is the start; [`Simulation::coarse_sphere`] checks where the spheres
    /// are later.
    ///
    /// ```
    /// use glam::DVec3;
    /// use spheresweep::sim::{SphereState, World};
    /// let at = |x: f64| World {
    ///     spheres: vec![SphereState {
    ///         centre: DVec3::new(x, 0.0, 0.0),
    ///         velocity: DVec3::ZERO,
    ///         radius: 0.5,
    ///         mass: 1.0,
    ///         material: 0,
    ///     }],
    ///     ..World::default()
    /// };
    /// assert!(at(1e10).coarse_sphere().is_none());
    /// let far = at(1e12).coarse_sphere().unwrap();
    /// assert!(far.sphere == 0 && far.rounding > far.tolerance);
    /// ```
    pub fn coarse_sphere(&self) -> Option<CoarseSphere> {
        let roams = match self.boundary {
            Boundary::Periodic { size } => Some(size.abs().max_element()),
            _ => None,
        };
        let each = self.spheres.iter().enumerate().filter_map(|(sphere, s)| {
            let coordinate = roams.unwrap_or(s.centre.abs().max_element());
            // An invalid sphere is `validate`'s to refuse.
            if !(coordinate.is_normal() && s.radius.is_finite() && s.radius > 0.0) {
                return None;
            }
            Some(CoarseSphere {
                sphere,
                others: 0,
                coordinate,
                rounding: 3f64.sqrt() * ulp(coordinate),
                tolerance: OVERLAP_TOLERANCE * 2.0 * s.radius,
            })
        });
        let mut worst: Option<CoarseSphere> = None;
        let mut count = 0;
        for c in each.filter(|c| c.rounding > c.tolerance) {
            count += 1;
            let ratio = |c: &CoarseSphere| c.rounding / c.tolerance;
            if worst.is_none_or(|w| ratio(&c) > ratio(&w)) {
                worst = Some(c);
            }
        }
        worst.map(|w| CoarseSphere {
            others: count - 1,
            ..w
        })
    }
}

impl Simulation {
    /// [`World::coarse_sphere`] of the spheres where they are now: spheres that have flown far
    /// from the origin since the start (a cluster carried off at speed) may meet where their
    /// coordinates round coarser than their contacts' tolerance.
    ///
    /// ```
    /// use glam::DVec3;
    /// use spheresweep::sim::{Simulation, SphereState, World};
    /// let ball = SphereState {
    ///     centre: DVec3::ZERO,
    ///     velocity: DVec3::new(1e11, 0.0, 0.0),
    ///     radius: 0.5,
    ///     mass: 1.0,
    ///     material: 0,
    /// };
    /// let mut sim = Simulation::new(World { spheres: vec![ball], ..World::default() })?;
    /// assert!(sim.coarse_sphere().is_none());
    /// sim.advance_to(10.0)?; // at 1e12
    /// assert_eq!(sim.coarse_sphere().map(|c| c.sphere), Some(0));
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn coarse_sphere(&self) -> Option<CoarseSphere> {
        let now = World {
            spheres: self.spheres(),
            boundary: self.boundary,
            ..World::default()
        };
        now.coarse_sphere()
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::ulp;
    use crate::sim::{Boundary, SphereState, World};

    #[test]
    fn ulp_is_the_spacing_of_the_doubles_there() {
        for x in [1.0, 1.5, 1e12, 2f64.powi(37), 3e-300, 1.7e308] {
            assert_eq!(ulp(x), x.next_up() - x, "{x}");
        }
    }

    fn spheres(at: &[(f64, f64)]) -> World {
        World {
            spheres: at
                .iter()
                .map(|&(x, radius)| SphereState {
                    centre: DVec3::new(0.0, -x, 0.0),
                    velocity: DVec3::ZERO,
                    radius,
                    mass: 1.0,
                    material: 0,
                })
                .collect(),
            ..World::default()
        }
    }

    /// The threshold to the bit: coarse from the first power of two above `2³⁷ ρ / √3`
    /// (`2³⁶` at `ρ = 1/2`, `2³⁸` at `ρ = √3`), not an ulp below it.
    #[test]
    fn coarse_from_the_power_of_two_where_root_three_ulps_pass_the_tolerance() {
        for (radius, first) in [(0.5, 2f64.powi(36)), (3f64.sqrt(), 2f64.powi(38))] {
            assert!(spheres(&[(first, radius)]).coarse_sphere().is_some());
            assert!(
                spheres(&[(first.next_down(), radius)])
                    .coarse_sphere()
                    .is_none()
            );
        }
    }

    /// The coarsest is named, the first of equals, with how many others are coarse; in a
    /// periodic box the box's length counts, not where a sphere starts.
    #[test]
    fn the_coarsest_first_and_the_others_counted() {
        let w = spheres(&[
            (1.0, 0.5),
            (1e12, 0.5),
            (1e12, 0.25),
            (1e12, 0.25),
            (1e13, 1e3),
        ]);
        let c = w.coarse_sphere().unwrap();
        assert_eq!((c.sphere, c.others), (2, 2));
        let mut boxed = spheres(&[(1.0, 0.5), (2.0, 0.25)]);
        boxed.boundary = Boundary::Periodic {
            size: DVec3::splat(1e12),
        };
        assert_eq!(boxed.coarse_sphere().map(|c| c.sphere), Some(1));
        let mut small = spheres(&[(1e12, 0.5)]);
        small.boundary = Boundary::Periodic {
            size: DVec3::splat(10.0),
        };
        assert_eq!(small.coarse_sphere(), None);
    }
}
