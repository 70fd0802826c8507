//! Spheres placed where their coordinates round coarser than their contacts' tolerance: a
//! contact there can overlap by about the rounding, beyond [`OVERLAP_TOLERANCE`], though the
//! scene is within the engine's range (docs/derivations/simulation.md, "Contacts far from the
//! origin").

use super::{OVERLAP_TOLERANCE, World};

/// A sphere whose centre rounds by more than the tolerance of a contact with a sphere of its
/// own size ([`World::coarse_sphere`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoarseSphere {
    /// The sphere (its index in [`World::spheres`]).
    pub sphere: usize,
    /// Its largest coordinate in magnitude.
    pub coordinate: f64,
    /// How far apart two centres there may be computed from where they are: `√3` ulps of
    /// `coordinate` (half an ulp on each axis of each centre).
    pub rounding: f64,
    /// The overlap a contact with a sphere of its size may have: `2⁻¹⁶` of its diameter.
    pub tolerance: f64,
}

impl CoarseSphere {
    /// What is coarse and what follows, without the sphere's name (a scene file names its
    /// entry instead).
    pub fn problem(&self) -> String {
        format!(
            "its centre is {:e} from the origin on an axis, where two centres can be computed \
             {:.3e} off, beyond its contacts' tolerance {:.3e} (2⁻¹⁶ of its diameter): its \
             contacts may overlap by about that much (units or an origin nearer the scene \
             resolve them)",
            self.coordinate, self.rounding, self.tolerance
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
    /// The sphere whose centre rounds coarsest against its own contacts' tolerance, if that
    /// rounding is beyond it: `√3 ulp(max |xₖ|) > 2⁻¹⁶ · 2 radius`. `None` for every scene
    /// whose spheres start within `2³⁶` radii of the origin on every axis. Only the start is checked:
    /// a sphere that flies that far later is not (the run's largest overlap at collisions,
    /// [`Stats::max_overlap`](super::Stats::max_overlap), shows it).
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
        let each = self.spheres.iter().enumerate().filter_map(|(sphere, s)| {
            let coordinate = s.centre.abs().max_element();
            // An invalid sphere is `validate`'s to refuse.
            if !(coordinate.is_normal() && s.radius.is_finite() && s.radius > 0.0) {
                return None;
            }
            Some(CoarseSphere {
                sphere,
                coordinate,
                rounding: 3f64.sqrt() * ulp(coordinate),
                tolerance: OVERLAP_TOLERANCE * 2.0 * s.radius,
            })
        });
        each.filter(|c| c.rounding > c.tolerance)
            .max_by(|a, b| (a.rounding / a.tolerance).total_cmp(&(b.rounding / b.tolerance)))
    }
}

#[cfg(test)]
mod tests {
    use super::ulp;

    #[test]
    fn ulp_is_the_spacing_of_the_doubles_there() {
        for x in [1.0, 1.5, 1e12, 2f64.powi(37), 3e-300, 1.7e308] {
            assert_eq!(ulp(x), x.next_up() - x, "{x}");
        }
    }
}
