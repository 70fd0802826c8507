//! The end of a run: the observables computed into a [`Summary`], the outputs committed,
//! `summary.json` written (last: its `run` field is the directory's manifest) and the summary
//! printed. The fields of `summary.json` are documented once, in docs/run-summary.md; a test
//! checks that its table lists exactly the fields written.

use std::error::Error;
use std::io::Write;
use std::path::Path;

use glam::DVec3;
use serde::Serialize;
use spheresweep::sim::{Boundary, OVERLAP_TOLERANCE, Response, World, observables};

use super::outputs::{self, Manifest};
use super::simulate::Run;
use crate::number::{counted, num};

/// What the summary says of the scene, taken from its world before the simulation is built.
pub struct About {
    pub scene: String,
    pub describe: String,
    pub spheres: usize,
    pub walls: usize,
    pub elastic: bool,
    pub equal_radii: bool,
    /// The gravity and the potential energy `Σ −m g·r` at t = 0 (zero without gravity).
    pub gravity: DVec3,
    pub potential_start: f64,
}

impl About {
    pub fn of(scene: &Path, world: &World) -> Self {
        let describe = format!(
            "{}: {}, {} material(s), {}, {}",
            scene.display(),
            counted(world.spheres.len() as u64, "sphere", "spheres"),
            world.materials.len(),
            crate::statics_text(&world.statics),
            match world.boundary {
                Boundary::Open => "open".to_string(),
                Boundary::OpenBox { lo, hi } => format!(
                    "open (cell grid from [{:?}, {:?}, {:?}] to [{:?}, {:?}, {:?}])",
                    lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
                ),
                Boundary::Periodic { size } => {
                    format!("periodic box {:.4} × {:.4} × {:.4}", size.x, size.y, size.z)
                }
            }
        );
        Self {
            scene: scene.display().to_string(),
            describe,
            spheres: world.spheres.len(),
            walls: world.statics.len(),
            elastic: world.effects.response == Response::Elastic && world.effects.pairs.is_empty(),
            equal_radii: world.spheres.windows(2).all(|w| w[0].radius == w[1].radius),
            gravity: world.effects.gravity,
            potential_start: unsigned_zero(
                world
                    .spheres
                    .iter()
                    .map(|s| -s.mass * world.effects.gravity.dot(s.centre))
                    .sum(),
            ),
        }
    }
}

/// `(K₀ + U₀ − K₁ − U₁ − lost)` relative to `K₀` (to the same bits as before gravity when
/// `U` is zero), or under gravity to the largest energy moved.
fn balance(k0: f64, k1: f64, u0: f64, u1: f64, lost: f64) -> f64 {
    if u0 == 0.0 && u1 == 0.0 {
        return relative(k0 - k1 - lost, k0);
    }
    let scale = k0.max(k1).max((u1 - u0).abs()).max(lost.abs());
    relative(k0 + u0 - k1 - u1 - lost, scale)
}

fn relative(change: f64, scale: f64) -> f64 {
    if scale > 0.0 { change / scale } else { change }
}

/// `x`, with a zero of either sign as `+0` (an empty sum is `-0.0`, which would print and
/// serialise as `-0`).
fn unsigned_zero(x: f64) -> f64 {
    if x == 0.0 { 0.0 } else { x }
}

/// `summary.json`, the figures of a completed run (docs/run-summary.md documents each field).
#[derive(Debug, Serialize)]
pub struct Summary {
    /// The scene file, as given.
    scene: String,
    /// The engine the world was assembled into (response, boundary, shapes, geometry).
    engine: String,
    /// The number of spheres.
    spheres: usize,
    /// Planes, cylinders and containers.
    static_shapes: usize,
    /// The time the run ended at.
    t_end: f64,
    /// Why the run stopped at `t_end` short of the end it was asked for (a parked run refused to
    /// fly its spheres past their reach); `null` when it reached it.
    stopped_short: Option<String>,
    /// In an open scene whose spheres have flown apart for good, the time of the last thing
    /// that happened (a collision, or the start).
    flown_apart: Option<f64>,
    /// Wall-clock seconds spent simulating, over every resumed part.
    wall_seconds: f64,
    /// Collisions by kind, and their rate.
    collisions: Collisions,
    /// Kinetic energy at the start and the end.
    kinetic_energy: Energy,
    /// Potential energy `Σ −m g·r` at the start and the end (all zero without gravity).
    potential_energy: Energy,
    /// Kinetic energy taken by inelastic and sticky collisions (less what rest hops gave
    /// under gravity).
    energy_lost: f64,
    /// (start − end − lost) of `K + U`, over the start's kinetic energy (under gravity: over
    /// the largest of the energies moved, `K` at either end, `|ΔU|` and the loss).
    energy_balance: f64,
    /// Total momentum at the start and the end.
    momentum: Momentum,
    /// Clusters of stuck spheres at the end.
    clusters: Clusters,
    /// Kernel evaluations by kind.
    kernels: Kernels,
    /// The largest overlap of two spheres at their collision, over their contact distance.
    max_overlap: f64,
    /// The largest depth of a sphere through a static shape at their collision, over its radius.
    max_wall_overlap: f64,
    /// Wall collisions a sphere left at a container's floor angle.
    slid: u64,
    /// The deepest overlaps in the state at the end.
    state_overlap: StateOverlap,
    /// Shell events processed (a sphere rebuilt its neighbour list).
    crossings: u64,
    /// Calendar entries found stale.
    stale: u64,
    /// Full predictions of one sphere.
    predictions: u64,
    /// Collisions whose impulse used the grazing floor.
    guarded: u64,
    /// `Σ r_ij · Δp_j` over pair collisions.
    virial: f64,
    pressure: Option<Pressure>,
    /// Frames in `trajectory.xyz` (0 without snapshots).
    frames: u64,
    /// Rows in `events.csv`; `None` when events are not recorded.
    events: Option<u64>,
    /// The directory's manifest: which run its files belong to.
    run: Manifest,
}

/// Collisions of a run.
#[derive(Debug, Serialize)]
struct Collisions {
    /// Sphere–sphere collisions.
    pair: u64,
    /// Sphere–shape collisions.
    wall: u64,
    /// Collisions per second of wall time.
    per_second: f64,
}

/// The kinetic energy at the start and the end of a run.
#[derive(Debug, Serialize)]
struct Energy {
    /// At t = 0.
    start: f64,
    /// At the end.
    end: f64,
    /// (end − start) / start.
    relative_drift: f64,
}

/// The total momentum at the start and the end of a run.
#[derive(Debug, Serialize)]
struct Momentum {
    /// At t = 0, `[x, y, z]`.
    start: [f64; 3],
    /// At the end.
    end: [f64; 3],
    /// |end − start| (static shapes exchange momentum).
    drift: f64,
}

/// The clusters of stuck spheres at the end of a run (sticky responses).
#[derive(Debug, Serialize)]
struct Clusters {
    /// Clusters of two or more spheres.
    count: usize,
    /// Spheres in them.
    spheres: usize,
    /// Spheres in the largest.
    largest: usize,
    /// Sticky joins.
    joins: u64,
}

/// Kernel evaluations by kind of the other body.
#[derive(Debug, Serialize)]
struct Kernels {
    /// Sphere–sphere pairs answered: the approaching pairs of the neighbour lists, solved in
    /// f64 four at a time (`KernelCounts::sphere`).
    sphere: u64,
    /// Sphere–plane kernel evaluations.
    plane: u64,
    /// Sphere–cylinder kernel evaluations.
    cylinder: u64,
    /// Sphere–container kernel evaluations.
    container: u64,
}

/// The largest overlaps in the state at the end (`Simulation::check_invariant`), sphere pairs
/// and spheres against static shapes, each over its tolerance (`1` is the limit; `null` in a
/// report-only scene, where spheres pass through each other).
#[derive(Debug, Serialize)]
struct StateOverlap {
    /// Of two spheres, over `2⁻¹⁶` of their contact distance.
    pairs: Option<f64>,
    /// Of a sphere through a static shape, over `2⁻¹⁶` of its radius.
    shapes: Option<f64>,
}

#[derive(Debug, Serialize)]
struct Pressure {
    p: f64,
    z: f64,
    phi: f64,
    kt: f64,
    carnahan_starling: Option<f64>,
}

impl Summary {
    /// The observables of a run at its end, its state checked against the invariant first
    /// (a breach is the run's error).
    pub fn of(run: &Run, about: &About) -> Result<Self, String> {
        let (sim, c) = (&run.sim, &run.counters);
        let state = sim.check_invariant().map_err(|e| e.to_string())?;
        // NaN: a report-only world; −∞: nothing to compare (no shapes, or one sphere).
        let finite = |x: f64| (!x.is_nan()).then_some(x.max(0.0));
        let stats = *sim.stats();
        let v3 = |v: DVec3| [v.x, v.y, v.z];
        let (ke0, ke1) = (unsigned_zero(c.ke0), unsigned_zero(sim.kinetic_energy()));
        let pe1 = unsigned_zero(sim.potential_energy());
        let clusters = sim.clusters();
        let collisions = stats.pair_collisions + stats.wall_collisions;
        Ok(Self {
            scene: about.scene.clone(),
            engine: sim.engine_name(),
            spheres: about.spheres,
            static_shapes: about.walls,
            t_end: sim.time(),
            stopped_short: run.stopped_short.clone(),
            flown_apart: sim.flown_apart(),
            wall_seconds: c.simulated,
            collisions: Collisions {
                pair: stats.pair_collisions,
                wall: stats.wall_collisions,
                per_second: collisions as f64 / c.simulated.max(1e-9),
            },
            kinetic_energy: Energy {
                start: ke0,
                end: ke1,
                relative_drift: relative(ke1 - ke0, ke0),
            },
            potential_energy: Energy {
                start: about.potential_start,
                end: pe1,
                relative_drift: relative(pe1 - about.potential_start, about.potential_start.abs()),
            },
            energy_lost: stats.energy_lost,
            energy_balance: balance(ke0, ke1, about.potential_start, pe1, stats.energy_lost),
            momentum: Momentum {
                start: v3(c.p0),
                end: v3(sim.momentum()),
                drift: (sim.momentum() - c.p0).length(),
            },
            clusters: Clusters {
                count: clusters.len(),
                spheres: clusters.iter().map(Vec::len).sum(),
                largest: clusters.iter().map(Vec::len).max().unwrap_or(0),
                joins: stats.joins,
            },
            kernels: Kernels {
                sphere: stats.kernels.sphere,
                plane: stats.kernels.plane,
                cylinder: stats.kernels.cylinder,
                container: stats.kernels.container,
            },
            max_overlap: stats.max_overlap,
            max_wall_overlap: stats.max_wall_overlap,
            slid: stats.slid,
            state_overlap: StateOverlap {
                pairs: finite(state.pairs),
                shapes: finite(state.walls),
            },
            crossings: stats.crossings,
            stale: stats.stale,
            predictions: stats.predictions,
            guarded: stats.guarded,
            virial: stats.virial,
            pressure: sim.pressure().map(|p| Pressure::of(p, about)),
            frames: c.frames,
            events: run.settings.record_events.then_some(c.logged),
            run: Manifest::new(run.fingerprint, &run.settings),
        })
    }
}

impl Pressure {
    /// The library's pressure of a periodic box (`Simulation::pressure`), with
    /// Carnahan–Starling's `Z` beside it for an elastic gas of equal spheres.
    fn of(p: observables::Pressure, about: &About) -> Self {
        Self {
            p: p.p,
            z: p.z,
            phi: p.phi,
            kt: p.kt,
            carnahan_starling: (about.elastic && about.equal_radii)
                .then(|| observables::carnahan_starling_z(p.phi)),
        }
    }
}

/// Commits the outputs, writes the summary (last) and prints it.
pub fn finish(mut run: Run, about: &About) -> Result<(), Box<dyn Error>> {
    let summary = match Summary::of(&run, about) {
        Ok(s) => s,
        Err(e) => {
            run.abandon();
            return Err(e.into());
        }
    };
    let dir = run.place.dir.clone();
    let mut wrote = Vec::new();
    if run.trajectory.is_some() {
        let path = dir.file(outputs::TRAJECTORY);
        let frames = counted(summary.frames, "frame", "frames");
        wrote.push(format!("{} ({frames})", path.display()));
    }
    if run.events.is_some() {
        let path = dir.file(outputs::EVENTS);
        let events = counted(run.counters.logged, "event", "events");
        wrote.push(format!("{} ({events})", path.display()));
    }
    let staged = [run.trajectory.take(), run.events.take()];
    dir.replace_outputs(staged.into_iter().flatten().collect(), &summary.run)?;
    let json_path = dir.file(outputs::SUMMARY);
    let text = serde_json::to_string_pretty(&summary)?;
    crate::atomic::write_atomic(&json_path, format!("{text}\n").as_bytes())?;
    wrote.push(json_path.display().to_string());
    let mut out = std::io::stdout().lock();
    summary.print(&mut out, about, run.counters.momentum_scale)?;
    writeln!(out, "wrote        {}", wrote.join(", "))?;
    Ok(())
}

impl Summary {
    /// The summary as printed.
    fn print(
        &self,
        out: &mut impl Write,
        about: &About,
        momentum_scale: f64,
    ) -> std::io::Result<()> {
        let (c, e) = (&self.collisions, &self.kinetic_energy);
        writeln!(out, "scene        {}", about.describe)?;
        writeln!(out, "engine       {}", self.engine)?;
        writeln!(
            out,
            "run          t = 0 → {} in {:.3} s of wall time",
            num(self.t_end),
            self.wall_seconds
        )?;
        if let Some(why) = &self.stopped_short {
            writeln!(out, "stopped      short of the end asked for: {why}")?;
        }
        if let Some(t) = self.flown_apart {
            writeln!(
                out,
                "flown apart  nothing has met anything since t = {}, and nothing can: no pair \
                 meets again and no sphere is headed for a shape",
                num(t)
            )?;
        }
        writeln!(
            out,
            "collisions   {} pair, {} wall: {} per second of wall time",
            c.pair,
            c.wall,
            si(c.per_second)
        )?;
        writeln!(
            out,
            "kinetic      {:.9e} → {:.9e} ({})",
            e.start,
            e.end,
            kinetic_change(e, about)
        )?;
        if about.gravity != DVec3::ZERO {
            let u = &self.potential_energy;
            writeln!(out, "potential    {:.9e} → {:.9e}", u.start, u.end)?;
            writeln!(
                out,
                "energy lost  {:.6e} (balance of K + U, start − end − lost: {:+.3e} of the energy moved)",
                self.energy_lost, self.energy_balance
            )?;
        } else {
            writeln!(
                out,
                "energy lost  {:.6e} (balance start − end − lost: {:+.3e} of the start)",
                self.energy_lost, self.energy_balance
            )?;
        }
        writeln!(
            out,
            "momentum     drift |ΔP| = {:.3e} ({:.3e} of Σ m|v|){}",
            self.momentum.drift,
            relative(self.momentum.drift, momentum_scale),
            if about.walls > 0 {
                "; static shapes exchange momentum"
            } else {
                ""
            }
        )?;
        self.print_details(out)
    }

    /// The clusters, kernels, overlap and pressure lines.
    fn print_details(&self, out: &mut impl Write) -> std::io::Result<()> {
        let c = &self.collisions;
        let k = &self.clusters;
        if k.count > 0 {
            writeln!(
                out,
                "clusters     {} of two or more spheres, holding {} spheres; the largest {}",
                k.count, k.spheres, k.largest
            )?;
        }
        let k = &self.kernels;
        writeln!(
            out,
            "kernels      sphere {} (approaching pairs solved in f64, four at a time), plane {}, \
             cylinder {}, container {}",
            k.sphere, k.plane, k.cylinder, k.container
        )?;
        if c.pair + c.wall > 0 {
            let beyond = self.max_overlap.max(self.max_wall_overlap) > OVERLAP_TOLERANCE;
            writeln!(
                out,
                "max overlap  at collisions: {:.3e} of the contact distance (pairs), {:.3e} of \
                 the radius (static shapes){}",
                self.max_overlap,
                self.max_wall_overlap,
                if beyond {
                    ": beyond the tolerance 2⁻¹⁶ (docs/run-summary.md)"
                } else {
                    ""
                }
            )?;
        } else {
            writeln!(out, "max overlap  at collisions: none")?;
        }
        let s = &self.state_overlap;
        if let (Some(pairs), Some(shapes)) = (s.pairs, s.shapes) {
            writeln!(
                out,
                "state        checked at each snapshot and at the end: deepest overlap {:.3e} \
                 (pairs) and {:.3e} (static shapes) of the tolerance 2⁻¹⁶",
                pairs, shapes
            )?;
        }
        if c.wall > 0 && self.slid > 0 {
            writeln!(
                out,
                "sliding      {} left a container at its floor angle (docs/derivations/simulation.md, \"Concave walls\")",
                counted(self.slid, "wall collision", "wall collisions")
            )?;
        }
        if let Some(p) = &self.pressure {
            write!(
                out,
                "pressure     P = {:.6} (kT = {:.6}, φ = {:.4}), Z = PV/(NkT) = {:.4}",
                p.p, p.kt, p.phi, p.z
            )?;
            match p.carnahan_starling {
                Some(cs) => writeln!(out, " (Carnahan–Starling: {cs:.4})")?,
                None => writeln!(out)?,
            }
        }
        Ok(())
    }
}

/// What the kinetic energy's change from start to end is: its drift, an error, where the
/// collisions conserve it; a change where they take energy or gravity exchanges it with the
/// potential energy (the energy lost line then gives the balance of `K + U`). From rest the
/// change is absolute (`relative_drift` is then `end − start`).
fn kinetic_change(e: &Energy, about: &About) -> String {
    let gravity = about.gravity != DVec3::ZERO;
    let what = match (about.elastic && !gravity, e.start > 0.0) {
        (true, true) => "relative drift",
        (false, true) => "relative change",
        (_, false) => "change from rest",
    };
    let mut text = format!("{what} {:+.3e}", e.relative_drift);
    if gravity {
        text.push_str(
            "; under gravity K alone is not conserved: the balance of K + U is on the energy \
             lost line",
        );
    }
    text
}

/// A rate with an SI prefix.
fn si(x: f64) -> String {
    match x {
        x if x >= 1e9 => format!("{:.2} G", x / 1e9),
        x if x >= 1e6 => format!("{:.2} M", x / 1e6),
        x if x >= 1e3 => format!("{:.2} k", x / 1e3),
        x => format!("{x:.1}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    /// A summary with every optional field present.
    fn full() -> Summary {
        let settings = super::super::options::Settings {
            t_end: 1.0,
            snapshot_every: Some(0.5),
            checkpoint_every: None,
            record_events: true,
            geometry: true,
        };
        Summary {
            scene: "gas.toml".into(),
            engine: "elastic, periodic".into(),
            spheres: 2,
            static_shapes: 0,
            t_end: 1.0,
            stopped_short: Some("refused".into()),
            flown_apart: Some(0.5),
            wall_seconds: 0.5,
            collisions: Collisions {
                pair: 1,
                wall: 0,
                per_second: 2.0,
            },
            kinetic_energy: Energy {
                start: 1.0,
                end: 1.0,
                relative_drift: 0.0,
            },
            potential_energy: Energy {
                start: 0.0,
                end: 0.0,
                relative_drift: 0.0,
            },
            energy_lost: 0.0,
            energy_balance: 0.0,
            momentum: Momentum {
                start: [0.0; 3],
                end: [0.0; 3],
                drift: 0.0,
            },
            clusters: Clusters {
                count: 0,
                spheres: 0,
                largest: 0,
                joins: 0,
            },
            kernels: Kernels {
                sphere: 8,
                plane: 0,
                cylinder: 0,
                container: 0,
            },
            max_overlap: 0.0,
            max_wall_overlap: 0.0,
            slid: 0,
            state_overlap: StateOverlap {
                pairs: Some(0.0),
                shapes: Some(0.0),
            },
            crossings: 0,
            stale: 0,
            predictions: 2,
            guarded: 0,
            virial: 1.0,
            pressure: Some(Pressure {
                p: 1.0,
                z: 1.0,
                phi: 0.1,
                kt: 1.0,
                carnahan_starling: Some(1.0),
            }),
            frames: 3,
            events: Some(1),
            run: Manifest::new(7, &settings),
        }
    }

    /// The dotted paths of a JSON value's fields (arrays are values).
    fn paths(v: &serde_json::Value, prefix: &str, out: &mut BTreeSet<String>) {
        match v {
            serde_json::Value::Object(m) => {
                for (k, v) in m {
                    paths(v, &format!("{prefix}{k}."), out);
                }
            }
            _ => {
                out.insert(prefix.trim_end_matches('.').to_string());
            }
        }
    }

    /// docs/run-summary.md's table of the fields of summary.json lists exactly the fields
    /// written.
    #[test]
    fn the_documented_fields_are_the_fields_written() {
        let value = serde_json::to_value(full()).unwrap();
        let mut written = BTreeSet::new();
        paths(&value, "", &mut written);
        let doc = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../docs/run-summary.md"
        ))
        .unwrap();
        let table = doc
            .split("## The fields of summary.json")
            .nth(1)
            .expect("docs/run-summary.md has a section 'The fields of summary.json'");
        let documented: Vec<String> = table
            .lines()
            .skip_while(|l| !l.starts_with("| `"))
            .take_while(|l| l.starts_with("| `"))
            .map(|l| l[3..].split('`').next().unwrap().to_string())
            .collect();
        let set: BTreeSet<String> = documented.iter().cloned().collect();
        assert_eq!(set.len(), documented.len(), "a field is listed twice");
        let missing: Vec<_> = written.difference(&set).collect();
        let extra: Vec<_> = set.difference(&written).collect();
        assert!(
            missing.is_empty() && extra.is_empty(),
            "not documented: {missing:?}; documented but not written: {extra:?}"
        );
    }
}
