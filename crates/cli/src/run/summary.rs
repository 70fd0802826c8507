//! The end of a run: the outputs committed, the observables computed, `summary.json` written
//! and the summary printed.

use std::error::Error;
use std::io::Write;
use std::path::Path;

use glam::DVec3;
use serde_json::json;
use spheresweep::sim::{Boundary, Response, World};

use super::outputs::{self, Manifest};
use super::simulate::Run;

/// What the summary says of the scene, taken from its world before the simulation is built.
pub struct About {
    pub scene: String,
    pub describe: String,
    pub spheres: usize,
    pub walls: usize,
    pub elastic: bool,
    pub equal_radii: bool,
    pub sphere_volume: f64,
}

impl About {
    pub fn of(scene: &Path, world: &World) -> Self {
        let describe = format!(
            "{}: {} spheres, {} material(s), {} plane(s), {} cylinder(s), {} container(s), {}",
            scene.display(),
            world.spheres.len(),
            world.materials.len(),
            world.planes.len(),
            world.cylinders.len(),
            world.containers.len(),
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
            walls: world.planes.len() + world.cylinders.len() + world.containers.len(),
            elastic: world.effects.response == Response::Elastic && world.effects.pairs.is_empty(),
            equal_radii: world.spheres.windows(2).all(|w| w[0].radius == w[1].radius),
            sphere_volume: world
                .spheres
                .iter()
                .map(|s| 4.0 / 3.0 * std::f64::consts::PI * s.radius.powi(3))
                .sum(),
        }
    }
}

fn relative(change: f64, scale: f64) -> f64 {
    if scale > 0.0 { change / scale } else { change }
}

/// Commits the outputs, writes the summary and prints it.
pub fn finish(mut run: Run, about: &About) -> Result<(), Box<dyn Error>> {
    let sim = &run.sim;
    let n = about.spheres;
    let c = run.counters;
    let (ke0, p0) = (c.ke0, c.p0);
    let stats = *sim.stats();
    let wall_seconds = c.simulated;
    let collisions = stats.pair_collisions + stats.wall_collisions;
    let rate = collisions as f64 / wall_seconds.max(1e-9);
    let ke1 = sim.kinetic_energy();
    let drift = relative(ke1 - ke0, ke0);
    let balance = relative(ke0 - ke1 - stats.energy_lost, ke0);
    let dp = (sim.momentum() - p0).length();
    let clusters = sim.clusters();
    let largest = clusters.iter().map(Vec::len).max().unwrap_or(0);
    let clustered: usize = clusters.iter().map(Vec::len).sum();
    let t_run = sim.time();
    let pressure = run.place.periodic_box.map(|b| {
        let v = b.x * b.y * b.z;
        let p = (2.0 * ke1 / 3.0 + stats.virial / (3.0 * t_run)) / v;
        let kt = 2.0 * ke1 / (3.0 * n as f64);
        let z = p * v / (n as f64 * kt);
        let phi = about.sphere_volume / v;
        let cs = (about.elastic && about.equal_radii)
            .then(|| (1.0 + phi + phi * phi - phi.powi(3)) / (1.0 - phi).powi(3));
        (p, z, phi, kt, cs)
    });

    // Outputs, then the summary (with the manifest) last.
    let dir = run.place.dir.clone();
    let manifest = Manifest::new(run.fingerprint, &run.settings);
    let mut wrote = Vec::new();
    if run.trajectory.is_some() {
        wrote.push(format!(
            "{} ({} frames)",
            dir.file(outputs::TRAJECTORY).display(),
            c.frames
        ));
    }
    if run.events.is_some() {
        wrote.push(format!(
            "{} ({} events)",
            dir.file(outputs::EVENTS).display(),
            c.logged
        ));
    }
    let staged = [run.trajectory.take(), run.events.take()];
    dir.replace_outputs(staged.into_iter().flatten().collect(), &manifest)?;
    let v3 = |v: DVec3| [v.x, v.y, v.z];
    let summary = json!({
        "scene": about.scene,
        "engine": sim.engine_name(),
        "spheres": n,
        "static_shapes": about.walls,
        "t_end": t_run,
        "wall_seconds": wall_seconds,
        "collisions": {
            "pair": stats.pair_collisions,
            "wall": stats.wall_collisions,
            "per_second": rate,
        },
        "kinetic_energy": { "start": ke0, "end": ke1, "relative_drift": drift },
        "energy_lost": stats.energy_lost,
        "energy_balance": balance,
        "momentum": { "start": v3(p0), "end": v3(sim.momentum()), "drift": dp },
        "clusters": {
            "count": clusters.len(),
            "spheres": clustered,
            "largest": largest,
            "joins": stats.joins,
        },
        "kernels": {
            "sphere": stats.kernels.sphere,
            "plane": stats.kernels.plane,
            "cylinder": stats.kernels.cylinder,
            "container": stats.kernels.container,
        },
        "max_overlap": stats.max_overlap,
        "crossings": stats.crossings,
        "stale": stats.stale,
        "predictions": stats.predictions,
        "guarded": stats.guarded,
        "virial": stats.virial,
        "pressure": pressure.map(|(p, z, phi, kt, cs)| json!({
            "p": p, "z": z, "phi": phi, "kt": kt, "carnahan_starling": cs,
        })),
        "frames": c.frames,
        "events": run.settings.record_events.then_some(c.logged),
        "run": manifest,
    });
    let json_path = dir.file(outputs::SUMMARY);
    let text = serde_json::to_string_pretty(&summary)?;
    crate::output::write_atomic(&json_path, format!("{text}\n").as_bytes())?;
    wrote.push(json_path.display().to_string());

    let mut out = std::io::stdout().lock();
    writeln!(out, "scene        {}", about.describe)?;
    writeln!(out, "engine       {}", sim.engine_name())?;
    writeln!(
        out,
        "run          t = 0 → {t_run} in {wall_seconds:.3} s of wall time"
    )?;
    writeln!(
        out,
        "collisions   {} pair, {} wall: {} per second of wall time",
        stats.pair_collisions,
        stats.wall_collisions,
        si(rate)
    )?;
    writeln!(
        out,
        "kinetic      {ke0:.9e} → {ke1:.9e} (relative drift {drift:+.3e})"
    )?;
    writeln!(
        out,
        "energy lost  {:.6e} (balance start − end − lost: {balance:+.3e} of the start)",
        stats.energy_lost
    )?;
    writeln!(
        out,
        "momentum     drift |ΔP| = {dp:.3e} ({:.3e} of Σ m|v|){}",
        relative(dp, c.momentum_scale),
        if about.walls > 0 {
            "; static shapes exchange momentum"
        } else {
            ""
        }
    )?;
    if !clusters.is_empty() {
        writeln!(
            out,
            "clusters     {} of two or more spheres, holding {clustered} spheres; the largest {largest}",
            clusters.len(),
        )?;
    }
    let k = stats.kernels;
    writeln!(
        out,
        "kernels      sphere {} (8-wide lanes), plane {}, cylinder {}, container {}",
        k.sphere, k.plane, k.cylinder, k.container
    )?;
    if collisions > 0 {
        writeln!(
            out,
            "max overlap  {:.3e} of the contact distance",
            stats.max_overlap
        )?;
    } else {
        writeln!(out, "max overlap  none")?;
    }
    if let Some((p, z, phi, kt, cs)) = pressure {
        write!(
            out,
            "pressure     P = {p:.6} (kT = {kt:.6}, φ = {phi:.4}), Z = PV/(NkT) = {z:.4}"
        )?;
        match cs {
            Some(cs) => writeln!(out, " (Carnahan–Starling: {cs:.4})")?,
            None => writeln!(out)?,
        }
    }
    writeln!(out, "wrote        {}", wrote.join(", "))?;
    Ok(())
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
