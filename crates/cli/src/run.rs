//! `spheresweep run SCENE`: a scene file simulated to its end time, with snapshots, an event
//! log and a summary (docs/scene-format.md).
//!
//! Nothing is written until the scene has parsed and its world has been built, so a bad scene
//! leaves no output behind. Every output is written under a temporary name in the output
//! directory and renamed into place when complete: an earlier run's files are either kept
//! whole or replaced whole.

use std::error::Error;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::DVec3;
use serde_json::json;
use spheresweep::io::scene_file::SceneFile;
use spheresweep::io::xyz;
use spheresweep::sim::{Boundary, EventRecord, Response, Simulation, SphereState};

/// Options of `spheresweep run`.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "Ctrl-C or SIGTERM stops the run between two events: earlier files are \
kept, temporary files removed, a last checkpoint written with --checkpoint-every; exit code 130. \
A scene too large for the memory available (MemAvailable, or SPHERESWEEP_MAX_MEMORY in bytes, \
e.g. 512M) is refused before it is built."
)]
pub struct Args {
    /// The scene file: TOML, or JSON if its name ends in .json.
    scene: PathBuf,
    /// Directory for trajectory.xyz, events.csv and summary.json (default: `<stem>-run/`
    /// beside the scene).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// End time, in the scene's time unit (its lengths over its speeds); finite and greater
    /// than 0. Default: the scene's `[run] t_end`.
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    t_end: Option<f64>,
    /// Time between snapshots, in the scene's time unit; 0 for none, at most 10⁶ snapshots.
    /// Default: the scene's `[run] snapshot_every`.
    #[arg(long, value_name = "EVERY", allow_negative_numbers = true)]
    snapshots: Option<f64>,
    /// No progress bar (there is none either when stderr is not a terminal).
    #[arg(long)]
    quiet: bool,
    /// Write `checkpoint.bin` in the output directory every T of simulated time (at the first
    /// snapshot or progress step past each T), atomically: a run killed at any moment resumes
    /// from the last one, and Ctrl-C or SIGTERM writes a last one before stopping. T is in the
    /// scene's time unit, finite and greater than 0. Default: no checkpoints.
    #[arg(long, value_name = "T")]
    checkpoint_every: Option<f64>,
    /// Continue the run a checkpoint of this scene holds (`--checkpoint-every`): the outputs
    /// end exactly as those of a run never interrupted. Give the scene and options the run
    /// was started with. Default: start from t = 0.
    #[arg(long, value_name = "CHECKPOINT")]
    resume: Option<PathBuf>,
}

/// A run's checkpoint: where the run was, what it had written, and the simulation's state.
struct RunCheckpoint {
    next_stop: u64,
    frames: u64,
    logged: u64,
    ke0: f64,
    p0: DVec3,
    momentum_scale: f64,
    simulated: f64,
    trajectory: Vec<u8>,
    events: Vec<u8>,
    sim: Vec<u8>,
}

const RUN_MAGIC: &[u8; 8] = b"SSRUN\0\0\x01";

impl RunCheckpoint {
    fn to_bytes(&self) -> Vec<u8> {
        let mut b = RUN_MAGIC.to_vec();
        for x in [self.next_stop, self.frames, self.logged] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        for x in [
            self.ke0,
            self.p0.x,
            self.p0.y,
            self.p0.z,
            self.momentum_scale,
            self.simulated,
        ] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        for part in [&self.trajectory, &self.events, &self.sim] {
            b.extend_from_slice(&(part.len() as u64).to_le_bytes());
            b.extend_from_slice(part);
        }
        b
    }

    fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self, String> {
        let bad = || {
            format!(
                "{}: not a checkpoint of `spheresweep run`, or damaged",
                path.display()
            )
        };
        let rest = bytes.strip_prefix(RUN_MAGIC).ok_or_else(bad)?;
        let mut pos = 0usize;
        let mut take = |n: usize| -> Result<&[u8], String> {
            let end = pos
                .checked_add(n)
                .filter(|&e| e <= rest.len())
                .ok_or_else(bad)?;
            let s = &rest[pos..end];
            pos = end;
            Ok(s)
        };
        let mut u64s = [0u64; 3];
        for x in &mut u64s {
            *x = u64::from_le_bytes(take(8)?.try_into().map_err(|_| bad())?);
        }
        let mut f64s = [0f64; 6];
        for x in &mut f64s {
            *x = f64::from_le_bytes(take(8)?.try_into().map_err(|_| bad())?);
        }
        let mut parts: [Vec<u8>; 3] = Default::default();
        for part in &mut parts {
            let len = u64::from_le_bytes(take(8)?.try_into().map_err(|_| bad())?);
            *part = take(usize::try_from(len).map_err(|_| bad())?)?.to_vec();
        }
        if pos != rest.len() {
            return Err(bad());
        }
        let [trajectory, events, sim] = parts;
        Ok(Self {
            next_stop: u64s[0],
            frames: u64s[1],
            logged: u64s[2],
            ke0: f64s[0],
            p0: DVec3::new(f64s[1], f64s[2], f64s[3]),
            momentum_scale: f64s[4],
            simulated: f64s[5],
            trajectory,
            events,
            sim,
        })
    }
}

/// Progress steps of a run without snapshots.
const STEPS: usize = 50;

/// A file written as it goes under a temporary name beside its final path, renamed into place
/// by [`Staged::commit`]; removed if dropped before that.
struct Staged {
    path: PathBuf,
    tmp: PathBuf,
    out: Option<BufWriter<File>>,
}

impl Staged {
    fn create(path: PathBuf) -> Result<Self, String> {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
        let file =
            File::create(&tmp).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        Ok(Self {
            path,
            tmp,
            out: Some(BufWriter::with_capacity(1 << 20, file)),
        })
    }

    /// Everything written so far (flushed first).
    fn contents(&mut self) -> Result<Vec<u8>, String> {
        self.writer().flush().map_err(|e| self.fail(e))?;
        std::fs::read(&self.tmp).map_err(|e| self.fail(e))
    }

    fn writer(&mut self) -> &mut BufWriter<File> {
        self.out
            .as_mut()
            .expect("a staged file is open until commit")
    }

    fn fail(&self, e: std::io::Error) -> String {
        format!("cannot write {}: {e}", self.path.display())
    }

    fn commit(mut self) -> Result<(), String> {
        let out = self.out.take().expect("committed once");
        let file = out.into_inner().map_err(|e| self.fail(e.into_error()))?;
        file.sync_all().map_err(|e| self.fail(e))?;
        std::fs::rename(&self.tmp, &self.path).map_err(|e| self.fail(e))
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if self.out.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// The events log: a header, then one row per collision.
fn events_header(geometry: bool) -> String {
    let mut h = String::from("time,sphere,other_kind,other_index,approach,restitution,energy_lost");
    if geometry {
        h.push_str(",px,py,pz,nx,ny,nz");
    }
    h
}

fn write_events(w: &mut impl Write, events: &[EventRecord], geometry: bool) -> std::io::Result<()> {
    for e in events {
        write!(
            w,
            "{:?},{},{},{},{:?},{:?},{:?}",
            e.time, e.sphere, e.other.kind, e.other.index, e.approach, e.restitution, e.energy_lost
        )?;
        if geometry {
            match e.geometry {
                Some(g) => write!(
                    w,
                    ",{:?},{:?},{:?},{:?},{:?},{:?}",
                    g.point.x, g.point.y, g.point.z, g.normal.x, g.normal.y, g.normal.z
                )?,
                None => write!(w, ",,,,,,")?,
            }
        }
        writeln!(w)?;
    }
    Ok(())
}

/// The default output directory: `<stem>-run/` beside the scene.
fn default_out(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
    let dir = match scene.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    dir.join(format!("{stem}-run"))
}

/// The times a run stops at: every snapshot time, or `STEPS` even steps, ending at `t_end`.
/// The flag says whether a snapshot is taken there.
fn stops(t_end: f64, every: Option<f64>) -> Vec<(f64, bool)> {
    match every {
        Some(dt) => {
            // Snapshots at k·dt (k ≥ 1) up to t_end, within rounding; t_end itself if it
            // falls between two.
            let last = ((t_end / dt) * (1.0 + 1e-12)).floor() as u64;
            let mut out: Vec<(f64, bool)> = (1..=last)
                .map(|k| ((k as f64 * dt).min(t_end), true))
                .collect();
            if out.last().is_none_or(|&(t, _)| t < t_end) {
                out.push((t_end, false));
            }
            out
        }
        None => (1..=STEPS)
            .map(|k| (t_end * k as f64 / STEPS as f64, false))
            .collect(),
    }
}

fn relative(change: f64, scale: f64) -> f64 {
    if scale > 0.0 { change / scale } else { change }
}

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    // Ctrl-C and SIGTERM from here on stop the simulation at its next poll.
    crate::interrupt::install()?;
    // Everything that can be refused is refused before any output exists.
    if let Some(t) = args.t_end
        && !(t.is_finite() && t > 0.0)
    {
        return Err(format!("--t-end {t} must be finite and greater than 0").into());
    }
    if let Some(s) = args.snapshots
        && !(s.is_finite() && s >= 0.0)
    {
        return Err(format!("--snapshots {s} must be finite and 0 (none) or more").into());
    }
    if let Some(c) = args.checkpoint_every
        && !(c.is_finite() && c > 0.0)
    {
        return Err(format!("--checkpoint-every {c} must be finite and greater than 0").into());
    }
    let resume = match &args.resume {
        Some(path) => {
            let bytes =
                std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            Some(RunCheckpoint::from_bytes(&bytes, path)?)
        }
        None => None,
    };
    let scene = SceneFile::from_path(&args.scene)?;
    // Too large for memory: refused before a sphere is generated. The world (one
    // `SphereState` a sphere) is held while the simulation is built from it.
    if let Some(n) = scene.sphere_count() {
        let bytes = Simulation::estimated_bytes(n)
            .saturating_add(n.saturating_mul(std::mem::size_of::<SphereState>()));
        crate::memory::check(
            &format!("{}: a simulation of {n} spheres", args.scene.display()),
            bytes as u64,
        )?;
    }
    if !args.quiet
        && let Some(n) = scene.sphere_count()
        && n >= 100_000
    {
        eprintln!("{}: building {n} spheres…", args.scene.display());
    }
    // Building the world and the engine cannot poll (a large generated scene takes seconds):
    // an interruption meanwhile ends the process at once, before any output exists.
    let building = "while the scene was built: nothing written";
    let (world, mut settings) =
        crate::interrupt::exit_if_requested_during(building, || scene.build())??;
    if let Some(t) = args.t_end {
        settings.t_end = t;
    }
    if let Some(s) = args.snapshots {
        settings.snapshot_every = (s > 0.0).then_some(s);
    }
    if let Some(dt) = settings.snapshot_every
        && settings.t_end / dt > 1e6
    {
        return Err(format!(
            "{} snapshots (t_end {} every {dt}) is more than a million: take them less often",
            (settings.t_end / dt).floor(),
            settings.t_end
        )
        .into());
    }
    let n = world.spheres.len();
    let periodic_box = match world.boundary {
        Boundary::Periodic { size } => Some(size),
        _ => None,
    };
    let walls = world.planes.len() + world.cylinders.len() + world.containers.len();
    let (record, geometry) = (
        world.effects.record_events,
        world.effects.record_events && world.effects.geometry,
    );
    let elastic = world.effects.response == Response::Elastic && world.effects.pairs.is_empty();
    let equal_radii = world.spheres.windows(2).all(|w| w[0].radius == w[1].radius);
    let sphere_volume: f64 = world
        .spheres
        .iter()
        .map(|s| 4.0 / 3.0 * std::f64::consts::PI * s.radius.powi(3))
        .sum();
    let describe = format!(
        "{}: {n} spheres, {} material(s), {} plane(s), {} cylinder(s), {} container(s), {}",
        args.scene.display(),
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
    let mut sim = crate::interrupt::exit_if_requested_during(building, || match &resume {
        Some(c) => Simulation::restore(world, &c.sim).map_err(|e| {
            format!(
                "{}: {e} (resume with the scene and options the checkpoint was written with)",
                args.resume
                    .as_ref()
                    .map_or(String::new(), |p| p.display().to_string())
            )
        }),
        None => Simulation::new(world).map_err(|e| scene.locate(e).to_string()),
    })??;

    // The outputs: checked, then staged in the output directory.
    let dir = args.out.clone().unwrap_or_else(|| default_out(&args.scene));
    if dir.exists() && !dir.is_dir() {
        return Err(format!("--out {}: not a directory", dir.display()).into());
    }
    let (xyz_path, csv_path, json_path) = (
        dir.join("trajectory.xyz"),
        dir.join("events.csv"),
        dir.join("summary.json"),
    );
    crate::output::check_writable(&json_path)?;
    let checkpoint_path = dir.join("checkpoint.bin");
    if resume.is_some() {
        // Temporary files an interrupted run left behind in this directory (a run killed
        // while it wrote a checkpoint or its summary leaves theirs too).
        let outputs = [
            "trajectory.xyz",
            "events.csv",
            "checkpoint.bin",
            "summary.json",
        ];
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if outputs
                .iter()
                .any(|o| name.starts_with(&format!(".{o}.")) && name.ends_with(".tmp"))
            {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
    let mut trajectory = match settings.snapshot_every {
        Some(_) => {
            let mut f = Staged::create(xyz_path.clone())?;
            if let Some(c) = &resume {
                f.writer().write_all(&c.trajectory).map_err(|e| f.fail(e))?;
            }
            Some(f)
        }
        None => None,
    };
    let mut events = if record {
        let mut f = Staged::create(csv_path.clone())?;
        match &resume {
            Some(c) => f.writer().write_all(&c.events).map_err(|e| f.fail(e))?,
            None => writeln!(f.writer(), "{}", events_header(geometry)).map_err(|e| f.fail(e))?,
        }
        Some(f)
    } else {
        None
    };

    let (ke0, p0) = match &resume {
        Some(c) => (c.ke0, c.p0),
        None => (sim.kinetic_energy(), sim.momentum()),
    };
    let momentum_scale: f64 = match &resume {
        Some(c) => c.momentum_scale,
        None => sim
            .spheres()
            .iter()
            .map(|s| s.mass * s.velocity.length())
            .sum(),
    };
    let mut frames = resume.as_ref().map_or(0, |c| c.frames as usize);
    if resume.is_none()
        && let Some(t) = trajectory.as_mut()
    {
        xyz::write_frame(t.writer(), &sim.spheres(), sim.time(), periodic_box)
            .map_err(|e| t.fail(e))?;
        frames += 1;
    }

    let t_end = settings.t_end;
    let bar = crate::progress::SimProgress::new(t_end, args.quiet, 4, false)?;
    let mut simulated = Duration::from_secs_f64(resume.as_ref().map_or(0.0, |c| c.simulated));
    let mut logged = resume.as_ref().map_or(0, |c| c.logged);
    let first = resume.as_ref().map_or(0, |c| c.next_stop as usize);
    let mut next_checkpoint = args.checkpoint_every.map(|c| sim.time() + c);
    let mut checkpoints = 0usize;
    // The run's state as a checkpoint that continues with stop `next_stop` (the same stop
    // when interrupted inside it, the next one at a periodic checkpoint).
    macro_rules! run_checkpoint {
        ($next_stop:expr) => {
            RunCheckpoint {
                next_stop: $next_stop,
                frames: frames as u64,
                logged,
                ke0,
                p0,
                momentum_scale,
                simulated: simulated.as_secs_f64(),
                trajectory: trajectory
                    .as_mut()
                    .map_or(Ok(Vec::new()), Staged::contents)?,
                events: events.as_mut().map_or(Ok(Vec::new()), Staged::contents)?,
                sim: sim.checkpoint(),
            }
        };
    }
    for (k, (stop, snapshot)) in stops(t_end, settings.snapshot_every)
        .into_iter()
        .enumerate()
        .skip(first)
    {
        let start = Instant::now();
        let finished = sim.advance_with(stop, &mut |t, s| {
            bar.show(t, s) && !crate::interrupt::requested()
        })? && !crate::interrupt::requested();
        simulated += start.elapsed();
        bar.show(sim.time(), sim.stats());
        if let Some(f) = events.as_mut() {
            let batch = sim.take_events();
            logged += batch.len() as u64;
            write_events(f.writer(), &batch, geometry).map_err(|e| f.fail(e))?;
        }
        if !finished {
            // Ctrl-C or SIGTERM: stopped between two events, or at this stop before its
            // snapshot (a stop of fewer than 4096 events is never polled inside). A last
            // checkpoint (if they are on) continues with this same stop; the staged outputs are
            // dropped (removed).
            bar.finish();
            let stats = *sim.stats();
            let done = format!(
                "at t = {} of {t_end} after {} collisions",
                sim.time(),
                stats.pair_collisions + stats.wall_collisions
            );
            if args.checkpoint_every.is_none() {
                return Err(crate::interrupt::Interrupted(format!(
                    "{done}; nothing written, earlier files in {} kept (with \
                     --checkpoint-every T an interrupted run can be resumed)",
                    dir.display()
                ))
                .into());
            }
            let c = run_checkpoint!(k as u64);
            crate::output::write_atomic(&checkpoint_path, &c.to_bytes())?;
            return Err(crate::interrupt::Interrupted(format!(
                "{done}; wrote {} ({frames} frames and {logged} events so far); resume with \
                 `spheresweep run {} --resume {}` and the same options",
                checkpoint_path.display(),
                args.scene.display(),
                checkpoint_path.display()
            ))
            .into());
        }
        if snapshot && let Some(t) = trajectory.as_mut() {
            xyz::write_frame(t.writer(), &sim.spheres(), sim.time(), periodic_box)
                .map_err(|e| t.fail(e))?;
            frames += 1;
        }
        if let (Some(at), Some(every)) = (next_checkpoint, args.checkpoint_every)
            && sim.time() >= at
            && stop < t_end
        {
            let c = run_checkpoint!(k as u64 + 1);
            crate::output::write_atomic(&checkpoint_path, &c.to_bytes())?;
            checkpoints += 1;
            next_checkpoint = Some(sim.time() + every);
        }
    }
    bar.finish();

    // Observables.
    let stats = *sim.stats();
    let wall_seconds = simulated.as_secs_f64();
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
    let pressure = periodic_box.map(|b| {
        let v = b.x * b.y * b.z;
        let p = (2.0 * ke1 / 3.0 + stats.virial / (3.0 * t_run)) / v;
        let kt = 2.0 * ke1 / (3.0 * n as f64);
        let z = p * v / (n as f64 * kt);
        let phi = sphere_volume / v;
        let cs = (elastic && equal_radii)
            .then(|| (1.0 + phi + phi * phi - phi.powi(3)) / (1.0 - phi).powi(3));
        (p, z, phi, kt, cs)
    });

    // Outputs, then the summary.
    let mut wrote = Vec::new();
    if let Some(t) = trajectory.take() {
        t.commit()?;
        wrote.push(format!("{} ({frames} frames)", xyz_path.display()));
    }
    if let Some(f) = events.take() {
        f.commit()?;
        wrote.push(format!("{} ({logged} events)", csv_path.display()));
    }
    let v3 = |v: DVec3| [v.x, v.y, v.z];
    let summary = json!({
        "scene": args.scene.display().to_string(),
        "engine": sim.engine_name(),
        "spheres": n,
        "static_shapes": walls,
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
        "frames": frames,
        "events": record.then_some(logged),
    });
    if checkpoints > 0 {
        wrote.push(format!(
            "{} ({checkpoints} written; the last is kept)",
            checkpoint_path.display()
        ));
    }
    let text = serde_json::to_string_pretty(&summary)?;
    crate::output::write_atomic(&json_path, format!("{text}\n").as_bytes())?;
    wrote.push(json_path.display().to_string());

    let mut out = std::io::stdout().lock();
    writeln!(out, "scene        {describe}")?;
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
        relative(dp, momentum_scale),
        if walls > 0 {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stops_end_at_t_end_and_mark_snapshots() {
        assert_eq!(
            stops(1.0, Some(0.25)),
            [(0.25, true), (0.5, true), (0.75, true), (1.0, true)]
        );
        assert_eq!(
            stops(1.0, Some(0.4)),
            [(0.4, true), (0.8, true), (1.0, false)]
        );
        // 0.1 · 3 rounds above 0.3: the last snapshot is still taken, at t_end.
        assert_eq!(stops(0.3, Some(0.1)).len(), 3);
        assert_eq!(stops(0.3, Some(0.1)).last(), Some(&(0.3, true)));
        let s = stops(2.0, None);
        assert_eq!((s.len(), s[STEPS - 1]), (STEPS, (2.0, false)));
    }

    #[test]
    fn the_default_output_is_beside_the_scene() {
        assert_eq!(
            default_out(Path::new("scenes/gas.toml")),
            Path::new("scenes/gas-run")
        );
        assert_eq!(default_out(Path::new("gas.toml")), Path::new("./gas-run"));
    }
}
