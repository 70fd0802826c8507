//! Contacts far from the origin: where a centre's coordinates round coarser than the contact
//! tolerance, `World::coarse_sphere` says so, and contacts there do overlap beyond it; just
//! inside that distance they do not (docs/derivations/simulation.md, "Contacts far from the
//! origin").

use glam::DVec3;
use spheresweep::sim::{OVERLAP_TOLERANCE, Simulation, SphereState, World};

/// 200 pairs of spheres of radius 0.5 around `origin`, 10 apart along `x` so that no pair
/// meets another, each pair closing along `y` at 2 with an impact parameter from head-on to
/// grazing (`0.005 k` for pair `k`, so the last at 0.995 of the contact distance).
fn pairs_at(origin: DVec3) -> World {
    let mut spheres = Vec::new();
    for k in 0..200 {
        let base = origin + DVec3::new(10.0 * k as f64, 0.0, 0.0);
        let offset = DVec3::new(0.0, 0.0, 0.005 * k as f64);
        for (at, v) in [
            (base, DVec3::Y),
            (base + DVec3::Y * 3.0 + offset, -DVec3::Y),
        ] {
            spheres.push(SphereState {
                centre: at,
                velocity: v,
                radius: 0.5,
                mass: 1.0,
                material: 0,
            });
        }
    }
    World {
        spheres,
        ..World::default()
    }
}

/// The largest overlap at the 200 collisions, over the contact distance.
fn overlap(world: World) -> f64 {
    let mut sim = Simulation::new(world).unwrap();
    sim.advance_to(3.0).unwrap();
    assert_eq!(sim.stats().pair_collisions, 200);
    sim.stats().max_overlap
}

#[test]
fn contacts_overlap_beyond_the_tolerance_only_where_the_scene_is_coarse() {
    // Within 2³⁶ radii (2³⁵ here) on every axis: not coarse, and no overlap past the tolerance.
    for near in [DVec3::splat(3e10), DVec3::new(-3.4e10, -3.4e10, 5.0)] {
        let world = pairs_at(near);
        assert_eq!(world.coarse_sphere(), None);
        let o = overlap(world);
        assert!(o <= OVERLAP_TOLERANCE, "at {near}: {o:e}");
    }
    // At 10¹² a coordinate's ulp is 2⁻¹³: coarse, and some contact overlaps past it.
    for far in [DVec3::splat(1e12), DVec3::new(0.0, -1e12, 0.0)] {
        let world = pairs_at(far);
        let coarse = world.coarse_sphere().expect("coarse");
        assert!(coarse.rounding > coarse.tolerance, "{coarse}");
        let o = overlap(world);
        assert!(o > OVERLAP_TOLERANCE, "at {far}: {o:e}");
    }
}
