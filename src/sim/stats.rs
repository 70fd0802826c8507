//! What a run counts since its start: collisions, crossings, predictions, the kernels run,
//! and the observables accumulated at collisions (energy lost, the collision virial).

use super::persist::persist_fields;

/// Kernel evaluations by kind (sphere pairs count neighbours screened in f32 lanes; static
/// shapes count f64 kernel calls): which kernels a scene ran, and how often.
///
/// ```
/// # use glam::DVec3;
/// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
/// # let ball = |x: f64, vx: f64| SphereState {
/// #     centre: DVec3::new(x, 0.0, 0.0),
/// #     velocity: DVec3::new(vx, 0.0, 0.0),
/// #     radius: 0.5,
/// #     mass: 1.0,
/// #     material: 0,
/// # };
/// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
/// let world = World {
///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
///     ..World::default()
/// };
/// let mut sim = Simulation::new(world)?;
/// sim.advance_to(2.0)?;
/// let kernels = sim.stats().kernels;
/// assert!(kernels.sphere > 0);
/// assert_eq!((kernels.plane, kernels.cylinder, kernels.container), (0, 0, 0)); // no shapes
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KernelCounts {
    /// Sphere–sphere pairs answered: the approaching pairs of a list solved in f64 lanes
    /// (receding pairs are rejected before the kernel and not counted).
    pub sphere: u64,
    /// Sphere–plane evaluations.
    pub plane: u64,
    /// Sphere–cylinder evaluations.
    pub cylinder: u64,
    /// Sphere–container evaluations.
    pub container: u64,
}

/// Counters and accumulated observables since the start.
///
/// ```
/// # use glam::DVec3;
/// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
/// # let ball = |x: f64, vx: f64| SphereState {
/// #     centre: DVec3::new(x, 0.0, 0.0),
/// #     velocity: DVec3::new(vx, 0.0, 0.0),
/// #     radius: 0.5,
/// #     mass: 1.0,
/// #     material: 0,
/// # };
/// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
/// let world = World {
///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
///     ..World::default()
/// };
/// let mut sim = Simulation::new(world)?;
/// sim.advance_to(2.0)?;
/// let stats = sim.stats();
/// assert_eq!((stats.pair_collisions, stats.wall_collisions, stats.joins), (1, 0, 0));
/// assert_eq!(stats.energy_lost, 0.0); // elastic
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stats {
    /// Sphere–sphere collisions (or reported contacts).
    pub pair_collisions: u64,
    /// Sphere–static-shape collisions.
    pub wall_collisions: u64,
    /// Shell events: a sphere left its neighbour list's shell and rebuilt its list (the
    /// name is the format's; it counted cell crossings before the lists).
    pub crossings: u64,
    /// Pair events dropped because the partner had changed since the prediction.
    pub stale: u64,
    /// Full predictions of one sphere.
    pub predictions: u64,
    /// Kernels run.
    pub kernels: KernelCounts,
    /// Kinetic energy taken by inelastic and sticky collisions.
    pub energy_lost: f64,
    /// `Σ r_ij · Δp_j` over pair collisions (the collision virial).
    pub virial: f64,
    /// Largest overlap of two spheres seen at their collision, relative to their contact
    /// distance; 0 while none has overlapped.
    pub max_overlap: f64,
    /// Largest depth of a sphere through a static shape seen at their collision, relative to
    /// the sphere's radius; 0 while none has been through.
    pub max_wall_overlap: f64,
    /// Cluster joins (sticky collisions).
    pub joins: u64,
    /// Collisions whose impulse used the grazing floor.
    pub guarded: u64,
    /// Wall collisions a sphere left at a container's floor angle: sliding along the wall
    /// (docs/derivations/simulation.md, "Concave walls").
    pub slid: u64,
}

persist_fields!(KernelCounts {
    sphere,
    plane,
    cylinder,
    container
});

// In checkpoint order (format version 2): the counters, then the accumulated values.
persist_fields!(Stats {
    pair_collisions,
    wall_collisions,
    crossings,
    stale,
    predictions,
    kernels,
    joins,
    guarded,
    slid,
    energy_lost,
    virial,
    max_overlap,
    max_wall_overlap
});

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::persist::tests::{distinct, printed_numbers, round_trip};

    /// Every field of `Stats` survives a checkpoint: filled by its own description with a
    /// different non-zero value each, none may be left at its default (a field the description
    /// missed would be), and saving then loading gives the same struct and the same bytes.
    #[test]
    fn every_stat_is_in_the_checkpoint() {
        let stats: Stats = distinct();
        let numbers = printed_numbers(&stats);
        assert!(numbers.len() >= 16, "{stats:?}"); // 12 numbers and the 4 of `kernels` today
        for (k, x) in numbers.iter().enumerate() {
            assert!(
                x != "0" && x != "0.0" && !numbers[..k].contains(x),
                "a field missing from the checkpoint stays {x}: {stats:?}"
            );
        }
        round_trip(&stats);
    }
}
