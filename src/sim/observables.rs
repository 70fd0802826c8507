//! Observables computed from what a run accumulates: the pressure of a periodic box from the
//! collision virial, and the hard-sphere equations of state to compare it with. One place for
//! the formulas the CLI's summary, the tests and the Python binding all report.

use super::{Boundary, Simulation};

/// The pressure of a periodic box since the start of the run, from the collision virial.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pressure {
    /// `P = (2 KE/3 + W/(3 t)) / V`: `KE` the kinetic energy now, `W` the collision virial
    /// ([`Stats::virial`](super::Stats::virial)) over the time `t` since the start, `V` the
    /// box's volume.
    pub p: f64,
    /// The compressibility factor `Z = PV/(NkT)`.
    pub z: f64,
    /// The packing fraction: the spheres' volume over the box's.
    pub phi: f64,
    /// `kT = 2 KE/(3N)`.
    pub kt: f64,
}

/// The compressibility factor `Z = PV/(NkT) = 1 + W/(2 KE t)` of a gas whose collisions
/// exchanged the virial `W = Σ r_ij · Δp_j` over the time `t` at the kinetic energy `KE`
/// (`NkT = 2 KE/3`). Over a window of a run, `W` is the change of
/// [`Stats::virial`](super::Stats::virial) across it and `t` its length.
///
/// ```
/// use spheresweep::sim::observables::compressibility;
/// assert_eq!(compressibility(0.0, 1.5, 2.0), 1.0); // no collisions: an ideal gas
/// assert_eq!(compressibility(6.0, 1.5, 2.0), 2.0);
/// ```
pub fn compressibility(virial: f64, kinetic_energy: f64, duration: f64) -> f64 {
    1.0 + virial / (2.0 * kinetic_energy * duration)
}

/// Carnahan–Starling's equation of state for hard spheres at packing fraction `phi`:
/// `Z = (1 + φ + φ² − φ³) / (1 − φ)³`.
///
/// ```
/// use spheresweep::sim::observables::carnahan_starling_z;
/// assert_eq!(carnahan_starling_z(0.0), 1.0);
/// assert!((carnahan_starling_z(0.3) - 1.363 / 0.343).abs() < 1e-12);
/// ```
pub fn carnahan_starling_z(phi: f64) -> f64 {
    (1.0 + phi + phi * phi - phi.powi(3)) / (1.0 - phi).powi(3)
}

/// Kolafa, Labík and Malijevský's (2004) equation of state for hard spheres, closer to
/// simulation than Carnahan–Starling's at the denser fluid states:
/// `Z = (1 + φ + φ² − ⅔(φ³ + φ⁴)) / (1 − φ)³`.
///
/// ```
/// use spheresweep::sim::observables::{carnahan_starling_z, kolafa_labik_malijevsky_z};
/// assert_eq!(kolafa_labik_malijevsky_z(0.0), 1.0);
/// let (klm, cs) = (kolafa_labik_malijevsky_z(0.3), carnahan_starling_z(0.3));
/// assert!(klm > cs && (klm - cs) / cs < 0.003); // 0.27 % apart at φ = 0.3
/// ```
pub fn kolafa_labik_malijevsky_z(phi: f64) -> f64 {
    (1.0 + phi + phi * phi - 2.0 / 3.0 * (phi.powi(3) + phi.powi(4))) / (1.0 - phi).powi(3)
}

impl Simulation {
    /// The pressure of a periodic box, from the collision virial since the start and the
    /// kinetic energy now (meaningful for an elastic gas, whose kinetic energy does not
    /// change); `None` outside a periodic box, before any time has passed, or without spheres.
    ///
    /// ```
    /// use spheresweep::sim::{Simulation, World, generate, observables::carnahan_starling_z};
    /// let mut world = World::default();
    /// generate::periodic_gas(&mut world, 500, 0.2, 0.5, 1.0, 7)?;
    /// let mut sim = Simulation::new(world)?;
    /// assert!(sim.pressure().is_none()); // no time yet
    /// sim.advance_to(20.0)?;
    /// let p = sim.pressure().unwrap();
    /// assert!((p.phi - 0.2).abs() < 1e-9);
    /// assert!((p.z - carnahan_starling_z(0.2)).abs() < 0.1 * p.z); // a short run, roughly
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn pressure(&self) -> Option<Pressure> {
        let Boundary::Periodic { size } = self.boundary else {
            return None;
        };
        let t = self.time();
        let bodies = self.engine.current();
        if t <= 0.0 || bodies.is_empty() {
            return None;
        }
        let n = bodies.len() as f64;
        let ke = self.kinetic_energy();
        let v = size.x * size.y * size.z;
        let p = (2.0 * ke / 3.0 + self.stats().virial / (3.0 * t)) / v;
        let kt = 2.0 * ke / (3.0 * n);
        let sphere_volume: f64 = bodies
            .iter()
            .map(|b| 4.0 / 3.0 * std::f64::consts::PI * b.radius.powi(3))
            .sum();
        Some(Pressure {
            p,
            z: p * v / (n * kt),
            phi: sphere_volume / v,
            kt,
        })
    }
}
