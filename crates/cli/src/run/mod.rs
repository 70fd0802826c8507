//! `spheresweep run SCENE`: a scene file simulated to its end time, with snapshots, an event
//! log and a summary (docs/scene-format.md).
//!
//! The stages, in order: the flags are checked; a checkpoint to resume is read (its checksum
//! first); the scene is parsed and built; the run's settings are resolved and, on a resume,
//! compared with the checkpoint's; the simulation is built or restored; the output directory is
//! checked; the loop runs ([`simulate::Run::advance`]); the outputs are committed and the
//! summary written and printed. Nothing is written until the scene has parsed and its world
//! has been built, so a bad scene leaves no output behind. The trajectory and event log are
//! appended to partial files as the run goes and renamed into place when it completes: an
//! earlier run's files are either kept whole or replaced whole.

mod checkpoint;
mod events;
pub(crate) mod hash;
mod limits;
mod options;
mod outputs;
mod simulate;
mod staged;
mod summary;

use std::error::Error;

use spheresweep::io::scene_file::{RunSettings, SceneFile};
use spheresweep::sim::{Simulation, SphereState, World};

use checkpoint::RunCheckpoint;
pub use options::Args;
use options::Settings;
use outputs::OutDir;
use simulate::{Place, Run};

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    // Ctrl-C and SIGTERM from here on stop the simulation at its next poll.
    crate::interrupt::install()?;
    // Everything that can be refused is refused before any output exists.
    options::check_flags(args)?;
    let resume = read_checkpoint(args)?;
    let (scene, world, run_table) = build_world(args)?;
    let settings = Settings::resolve(args, &run_table, &world.effects);
    let fingerprint = hash::world(&world);
    if let Some(c) = &resume {
        same_run(args, c, &settings, fingerprint)?;
    }
    settings.check().map_err(|e| {
        // Where the spacing and the end came from: the flags, or the scene file.
        let from = |flag: bool, name: &str, key: &str| {
            if flag {
                name.to_string()
            } else {
                format!("{}'s {key}", args.scene.display())
            }
        };
        format!(
            "{e} ({}, {})",
            from(args.snapshots.is_some(), "--snapshots", "snapshot_every"),
            from(args.t_end.is_some(), "--t-end", "t_end")
        )
    })?;
    let about = summary::About::of(&args.scene, &world);
    let periodic_box = simulate::periodic_box(world.boundary);
    let n = world.spheres.len();
    // Said once the world is valid, before the run, which they do not stop.
    let warnings = scene.warnings(&world);
    let mut sim = build_simulation(args, &scene, world, resume.as_ref())?;
    for warning in warnings {
        eprintln!("warning: {warning}");
    }
    if args.break_walls_for_testing {
        sim.break_walls_for_testing();
    }
    let place = place(args, resume.as_ref(), &settings, n, periodic_box)?;
    let mut run = match resume {
        Some(c) => Run::resume(sim, c, place)?,
        None => {
            let manifest = outputs::Manifest::new(fingerprint, &settings);
            place.dir.claim(&manifest, args.force)?;
            Run::start(sim, settings, fingerprint, place)?
        }
    };
    let every = std::time::Duration::from_secs_f64(args.progress_every);
    if let Err(e) = run.advance(args.quiet, every) {
        if e.is::<simulate::StoppedShort>() {
            summary::finish(run, &about)?;
            return Err(e);
        }
        if !e.is::<crate::interrupt::Interrupted>() {
            run.abandon();
        }
        return Err(e);
    }
    summary::finish(run, &about)
}

/// The output directory, taken for this run, and the bytes its outputs may take: a run whose
/// frames would pass them is refused here.
fn place(
    args: &Args,
    resume: Option<&RunCheckpoint>,
    settings: &Settings,
    spheres: usize,
    periodic_box: Option<glam::DVec3>,
) -> Result<Place, String> {
    // A resume writes where its checkpoint is, unless told otherwise: the run's directory.
    let resumed_in = args
        .resume
        .as_deref()
        .and_then(std::path::Path::parent)
        .map(|d| {
            if d.as_os_str().is_empty() {
                std::path::Path::new(".")
            } else {
                d
            }
        });
    let dir = OutDir::new(args.out.as_deref().or(resumed_in), &args.scene)?;
    let lock = dir.lock()?;
    let budget = limits::Budget::new(args.max_output.as_deref(), &dir.0)?;
    let (next_stop, written) = resume.map_or((0, 0), |c| {
        (c.counters.next_stop, c.trajectory.len + c.events.len)
    });
    budget.check_projection(
        settings.frames_from(next_stop),
        limits::frame_bound(spheres, periodic_box.is_some()),
        written,
    )?;
    Ok(Place {
        scene: args.scene.clone(),
        dir,
        periodic_box,
        budget,
        _lock: lock,
    })
}

/// The checkpoint `--resume` names, read and checked whole before the scene is read.
fn read_checkpoint(args: &Args) -> Result<Option<RunCheckpoint>, String> {
    let Some(path) = &args.resume else {
        return Ok(None);
    };
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    RunCheckpoint::from_bytes(&bytes, path).map(Some)
}

/// The scene parsed and its world built, after the memory check.
fn build_world(args: &Args) -> Result<(SceneFile, World, RunSettings), Box<dyn Error>> {
    let scene = SceneFile::from_path(&args.scene)?;
    // Too large for memory: refused before a sphere is generated. The world (one
    // `SphereState` a sphere) is held while the simulation is built from it.
    if let Some(n) = crate::memory::scene_count(&scene) {
        let bytes = Simulation::estimated_bytes(n)
            .saturating_add(n.saturating_mul(std::mem::size_of::<SphereState>()));
        crate::memory::check(
            &format!("{}: a simulation of {n} spheres", args.scene.display()),
            bytes as u64,
        )?;
        if !args.quiet && n >= 100_000 {
            eprintln!("{}: building {n} spheres…", args.scene.display());
        }
    }
    // Building the world and the engine cannot poll (a large generated scene takes seconds):
    // an interruption meanwhile ends the process at once, before any output exists.
    let (world, run_table) =
        crate::interrupt::exit_if_requested_during(BUILDING, || scene.build())??;
    Ok((scene, world, run_table))
}

const BUILDING: &str = "while the scene was built: nothing written";

/// A resume continues the same run: the same settings and the same scene.
fn same_run(
    args: &Args,
    c: &RunCheckpoint,
    settings: &Settings,
    fingerprint: u64,
) -> Result<(), String> {
    let path = args.resume.as_deref().unwrap_or(std::path::Path::new(""));
    settings
        .same_run(&c.settings)
        .map_err(|e| format!("cannot resume from {}: {e}", path.display()))?;
    if c.fingerprint != fingerprint {
        return Err(format!(
            "cannot resume from {}: it was written for another scene ({} builds a world whose \
             fingerprint is {}, the checkpoint's is {}: spheres, seed, shapes, boundary, \
             materials or effects differ)",
            path.display(),
            args.scene.display(),
            hash::text(fingerprint),
            hash::text(c.fingerprint)
        ));
    }
    Ok(())
}

/// The simulation of `world`, from t = 0 or restored from the checkpoint.
fn build_simulation(
    args: &Args,
    scene: &SceneFile,
    world: World,
    resume: Option<&RunCheckpoint>,
) -> Result<Simulation, Box<dyn Error>> {
    let sim = crate::interrupt::exit_if_requested_during(BUILDING, || match resume {
        Some(c) => Simulation::restore(world, &c.engine).map_err(|e| {
            let path = args.resume.as_deref().unwrap_or(std::path::Path::new(""));
            format!("{}: {e}", path.display())
        }),
        None => Simulation::new(world).map_err(|e| scene.locate(e).to_string()),
    })??;
    Ok(sim)
}
