//! `spheresweep demo`: the whole mission on the built-in scene
//! ([`spheresweep::sim::demo_world`]): 4000 glass and glue beads in a vessel with a floor and
//! pillars, simulated through the event-driven engine with a progress bar, then a summary and a
//! picture (SVG and PNG) of the end state and of sampled trajectories. `--table` prints the
//! nine-sphere first-contact table of the query layer instead.

use std::error::Error;
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use glam::DVec3;
use spheresweep::query::first_contacts;
use spheresweep::scene::{Scene, demo};
use spheresweep::sim::{Simulation, SphereState, Stats, World, demo_world};
use spheresweep::{Accuracy, Container, Cylinder, Plane, QueryOptions};

use crate::picture::{
    self, Canvas, Content, Format, Key, Paint, Panel, Path as Trajectory, Rgb, Shapes, Size, View,
};

/// Options of `spheresweep demo`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Print the first-contact table of the nine-sphere query scene instead (implied by
    /// --t-max, --accuracy and --svg).
    #[arg(long)]
    table: bool,
    /// With the table: end of the time window [0, t_max] (zero or more; inf for no end)
    /// [default: 10]; rounded down to the kernels' f32.
    #[arg(long, value_name = "T", allow_negative_numbers = true, value_parser = crate::number::window_end)]
    t_max: Option<f32>,
    /// With the table: accuracy mode of the kernels, textbook, stable or double [default:
    /// stable].
    #[arg(long, value_name = "MODE")]
    accuracy: Option<Accuracy>,
    /// With the table: also draw the scene from above, with every sphere's path to its first
    /// contact, as SVG. Default: no picture.
    #[arg(long, value_name = "FILE")]
    svg: Option<PathBuf>,
    /// Directory for the pictures demo.svg and demo.png [default: spheresweep-demo].
    #[arg(long, value_name = "DIR", conflicts_with_all = ["table", "t_max", "accuracy", "svg"])]
    out: Option<PathBuf>,
    /// A tenth of the run (to t = 30 instead of t = 300), for a quick look.
    #[arg(long, conflicts_with_all = ["table", "t_max", "accuracy", "svg"])]
    quick: bool,
    /// Size of the pictures in pixels, WIDTHxHEIGHT.
    #[arg(long, value_name = "WxH", default_value = "1600x800",
          conflicts_with_all = ["table", "t_max", "accuracy", "svg"])]
    size: Size,
    /// No progress bar (there is none either when stderr is not a terminal).
    #[arg(long)]
    quiet: bool,
}

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    if args.table || args.t_max.is_some() || args.accuracy.is_some() || args.svg.is_some() {
        table(args)
    } else {
        simulate(args)
    }
}

/// The nine-sphere scene of the query layer: every sphere's first contact, as a table.
fn table(args: &Args) -> Result<(), Box<dyn Error>> {
    let t_max = args.t_max.unwrap_or(10.0);
    let accuracy = args.accuracy.unwrap_or(Accuracy::Stable);
    let options = QueryOptions::new(t_max, accuracy)
        .map_err(|_| format!("--t-max must be zero or more (or inf for no end), got {t_max}"))?
        .with_geometry(true);
    if let Some(path) = &args.svg {
        // Before any output: a bad path fails now, not after the table.
        crate::output::check_writable(path)?;
    }
    let scene = demo();
    let mut out = std::io::stdout().lock();
    writeln!(out, "{}", describe(&scene))?;
    writeln!(
        out,
        "First contacts in [0, {t_max}] ({accuracy} mode, 8-wide kernels; point and normal from the f64 reference):\n",
    )?;
    writeln!(
        out,
        "{:>6}  {:<13} {:>9}  {:>26}  {:>23}",
        "sphere", "hits", "time", "contact point", "normal on sphere"
    )?;
    let contacts = first_contacts(&scene, options);
    for (i, contact) in contacts.iter().enumerate() {
        match contact {
            None => writeln!(out, "{i:>6}  {:<13} {:>9}", "nothing", "-")?,
            Some(hit) => {
                let c = hit.geometry.expect("geometry was asked for");
                // `+ 0.0` turns IEEE −0.0 into 0.0 for display.
                let (p, n) = (c.point + 0.0, c.normal + 0.0);
                writeln!(
                    out,
                    "{i:>6}  {:<13} {:>9.4}  ({:>7.3}, {:>7.3}, {:>7.3})  ({:>6.3}, {:>6.3}, {:>6.3})",
                    hit.body.to_string(),
                    hit.time,
                    p.x,
                    p.y,
                    p.z,
                    n.x,
                    n.y,
                    n.z
                )?;
            }
        }
    }
    if let Some(path) = &args.svg {
        let picture = picture::top_view(&scene, &contacts, t_max).svg();
        crate::atomic::write_atomic(path, picture.as_bytes())?;
        writeln!(out, "\nwrote {}", path.display())?;
    }
    Ok(())
}

fn describe(s: &Scene) -> String {
    format!(
        "Built-in scene: {} spheres, {}.",
        s.spheres.len(),
        crate::statics_text(&s.statics)
    )
}

/// Simulated time of the full run and of `--quick`.
const T_END: f64 = 300.0;
const T_QUICK: f64 = 30.0;
/// Times at which the tracked beads' positions are sampled (and the progress bar moves).
const SAMPLES: usize = 300;
/// Beads whose paths are drawn: this many glass and this many glue.
const TRACKED: usize = 10;
/// Materials of the demo world.
const GLASS: u16 = 0;
const GLUE: u16 = 1;

const GLASS_FILL: Rgb = Rgb::hex(0xa9cbe6);
const GLUE_FREE: Rgb = Rgb::hex(0xf28e2b);
const GLUE_RESTING: Rgb = Rgb::hex(0x8c4a1c);
/// Glue clusters, largest first (repeating).
const CLUSTER_COLOURS: [Rgb; 8] = [
    Rgb::hex(0xd62728),
    Rgb::hex(0x2ca02c),
    Rgb::hex(0x9467bd),
    Rgb::hex(0xe377c2),
    Rgb::hex(0x17becf),
    Rgb::hex(0xbcbd22),
    Rgb::hex(0xae017e),
    Rgb::hex(0xe6ab02),
];
const GLASS_PATH: Rgb = Rgb::hex(0x08306b);
const GLUE_PATH: Rgb = Rgb::hex(0x7a0010);

/// The simulation demo: run, summary, pictures.
fn simulate(args: &Args) -> Result<(), Box<dyn Error>> {
    // Ctrl-C and SIGTERM from here on stop the simulation at its next poll.
    crate::interrupt::install()?;
    let files = picture_paths(args)?;
    let world = demo_world();
    let shapes = Shapes {
        ground: true,
        ..Shapes::of_world(&world)
    };
    let n = world.spheres.len();
    let tracked = tracked(&world);
    let vessel = world.statics.of::<Container>().shapes()[0];
    let floor = world.statics.of::<Plane>().shapes()[0].point().z;
    let mut out = std::io::stdout().lock();
    introduce(&mut out, &world)?;
    let t_end = if args.quick { T_QUICK } else { T_END };
    let mut sim = Simulation::new(world)?;
    let ke0 = sim.kinetic_energy();
    let sampled = advance(&mut sim, args, t_end, &tracked)?;
    let End {
        spheres,
        clusters,
        collisions,
        at_rest,
    } = summarise(&mut out, &sim, args, ke0, &sampled)?;
    let paths = sampled.paths;

    // The picture.
    let mut cluster_of = vec![usize::MAX; n];
    let mut ranked: Vec<&Vec<u32>> = clusters.iter().collect();
    ranked.sort_by_key(|c| std::cmp::Reverse(c.len()));
    for (rank, members) in ranked.iter().enumerate() {
        for &s in members.iter() {
            cluster_of[s as usize] = rank;
        }
    }
    let fill = |i: usize, s: &SphereState| -> Paint {
        if s.material != GLUE {
            GLASS_FILL.into()
        } else if cluster_of[i] != usize::MAX {
            CLUSTER_COLOURS[cluster_of[i] % CLUSTER_COLOURS.len()].into()
        } else if resting(s) {
            GLUE_RESTING.into()
        } else {
            GLUE_FREE.into()
        }
    };
    // Glue beads from the start (they end in clusters or on the floor); glass beads, whose
    // paths would fill the vessel, over the last tenth of the run only.
    let recent = SAMPLES - SAMPLES / 10;
    let trajectories: Vec<Trajectory> = paths
        .into_iter()
        .zip(&tracked)
        .map(|(points, &i)| {
            if spheres[i].material == GLUE {
                Trajectory {
                    colour: GLUE_PATH,
                    points,
                }
            } else {
                Trajectory {
                    colour: GLASS_PATH,
                    points: points[recent..].to_vec(),
                }
            }
        })
        .collect();
    let r = f64::from(vessel.radius());
    let content = Content {
        spheres: &spheres,
        fill: &fill,
        shapes: &shapes,
        paths: &trajectories,
        bounds: (DVec3::splat(-r * 1.03), DVec3::splat(r * 1.03)),
    };
    let floor = f64::from(floor);
    let title = format!(
        "spheresweep demo at t = {t_end}: {collisions} collisions, {} glue clusters, {at_rest} glue beads on the floor",
        clusters.len()
    );
    let canvas = draw(args.size, &title, &content, floor, t_end);
    let mut wrote = Vec::new();
    for (path, ext) in files.iter().zip(Format::Both.extensions()) {
        let bytes = Format::encode(&canvas, ext)?;
        crate::atomic::write_atomic(path, &bytes)?;
        wrote.push(path.display().to_string());
    }
    writeln!(
        out,
        "picture      {} ({} × {} px): side view (slice |y| < {SLICE}) and top view (floor layer), \
         paths of {} glue beads (from the start) and of {} glass beads (the last tenth of the run)",
        wrote.join(", "),
        args.size.width,
        args.size.height,
        TRACKED,
        TRACKED
    )?;
    Ok(())
}

/// The pictures' paths, `demo.svg` and `demo.png` in `--out`, checked before any work.
fn picture_paths(args: &Args) -> Result<Vec<PathBuf>, Box<dyn Error>> {
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("spheresweep-demo"));
    if dir.exists() && !dir.is_dir() {
        return Err(format!("--out {}: not a directory", dir.display()).into());
    }
    let files: Vec<PathBuf> = Format::Both
        .extensions()
        .iter()
        .map(|ext| dir.join(format!("demo.{ext}")))
        .collect();
    for f in &files {
        crate::output::check_writable(f)?;
    }
    Ok(files)
}

/// The beads whose paths are drawn: the first [`TRACKED`] glass, then the first glue ones.
fn tracked(world: &World) -> Vec<usize> {
    let n = world.spheres.len();
    let pick = |m: u16| -> Vec<usize> {
        (0..n)
            .filter(|&i| world.spheres[i].material == m)
            .take(TRACKED)
            .collect()
    };
    [pick(GLASS), pick(GLUE)].concat()
}

/// The lines that say what is simulated, before the run.
fn introduce(out: &mut impl Write, world: &World) -> std::io::Result<()> {
    let n = world.spheres.len();
    let glue_count = world.spheres.iter().filter(|s| s.material == GLUE).count();
    let vessel = world.statics.of::<Container>().shapes()[0];
    let floor = world.statics.of::<Plane>().shapes()[0].point().z;
    writeln!(
        out,
        "spheresweep demo: {n} beads ({} glass, {glue_count} glue) of radius {} in a spherical vessel \
         of radius {}, over a floor at z = {floor} and around {} pillars; no gravity.",
        n - glue_count,
        world.spheres[0].radius,
        vessel.radius(),
        world.statics.of::<Cylinder>().len()
    )?;
    writeln!(
        out,
        "Glue sticks to glue and to the floor; every other collision is elastic.\n"
    )?;
    out.flush()
}

/// What the run gathered as it went.
struct Sampled {
    /// The tracked beads' centres at time 0 and at each sample.
    paths: Vec<Vec<DVec3>>,
    /// Wall time of the run.
    seconds: f64,
    /// The deepest overlaps in the state over the samples, pairs and walls, each of its
    /// tolerance.
    worst: (f64, f64),
}

/// Runs the simulation to `t_end` in [`SAMPLES`] steps behind the progress bar, checking the
/// state and sampling the tracked beads at each; an interruption is the demo's error.
fn advance(
    sim: &mut Simulation,
    args: &Args,
    t_end: f64,
    tracked: &[usize],
) -> Result<Sampled, Box<dyn Error>> {
    let start = sim.spheres();
    let mut paths: Vec<Vec<DVec3>> = tracked.iter().map(|&i| vec![start[i].centre]).collect();
    let bar = crate::progress::SimProgress::new(
        t_end,
        args.quiet,
        1,
        true,
        std::time::Duration::from_secs(60),
    )?;
    let started = Instant::now();
    let mut worst = (0.0f64, 0.0f64);
    for k in 1..=SAMPLES {
        let stop = t_end * k as f64 / SAMPLES as f64;
        let finished = sim.advance_with(stop, &mut |t, s| {
            bar.show(t, s) && !crate::interrupt::requested()
        })? && !crate::interrupt::requested();
        if !finished {
            bar.finish();
            let s = sim.stats();
            return Err(crate::interrupt::Interrupted(format!(
                "at t = {:.1} of {t_end} after {} collisions; no picture written (earlier ones \
                 kept)",
                sim.time(),
                s.pair_collisions + s.wall_collisions
            ))
            .into());
        }
        bar.show(sim.time(), sim.stats());
        // The state every run keeps, at each sample: a breach is the demo's error.
        let state = sim.check_invariant()?;
        worst = (worst.0.max(state.pairs), worst.1.max(state.walls));
        let now = sim.spheres();
        for (path, &i) in paths.iter_mut().zip(tracked) {
            path.push(now[i].centre);
        }
    }
    let seconds = started.elapsed().as_secs_f64();
    bar.finish();
    Ok(Sampled {
        paths,
        seconds,
        worst,
    })
}

/// A glue bead resting on the floor (stuck there, not moving).
fn resting(s: &SphereState) -> bool {
    s.material == GLUE && s.velocity == DVec3::ZERO
}

/// The state at the end, as the summary counts it and the picture shows it.
struct End {
    spheres: Vec<SphereState>,
    clusters: Vec<Vec<u32>>,
    /// Pair and wall collisions.
    collisions: u64,
    /// Glue beads resting on the floor.
    at_rest: usize,
}

/// Prints the summary of the run.
fn summarise(
    out: &mut impl Write,
    sim: &Simulation,
    args: &Args,
    ke0: f64,
    sampled: &Sampled,
) -> Result<End, Box<dyn Error>> {
    let (seconds, worst) = (sampled.seconds, sampled.worst);
    let t_end = if args.quick { T_QUICK } else { T_END };
    let stats = *sim.stats();
    let spheres = sim.spheres();
    let clusters = sim.clusters();
    let ke1 = sim.kinetic_energy();
    let collisions = stats.pair_collisions + stats.wall_collisions;
    let glue_count = spheres.iter().filter(|s| s.material == GLUE).count();
    let at_rest = spheres.iter().filter(|s| resting(s)).count();
    let in_clusters: usize = clusters.iter().map(Vec::len).sum();
    let largest = clusters.iter().map(Vec::len).max().unwrap_or(0);
    writeln!(
        out,
        "engine       {} (event-driven: every collision in time order)",
        sim.engine_name()
    )?;
    writeln!(
        out,
        "simulated    t = 0 → {t_end} in {seconds:.2} s of wall time{}",
        if args.quick {
            " (--quick: a tenth of the run)"
        } else {
            ""
        }
    )?;
    writeln!(
        out,
        "collisions   {} bead–bead and {} bead–wall: {collisions} in all, {} per second",
        stats.pair_collisions,
        stats.wall_collisions,
        si(collisions as f64 / seconds.max(1e-9))
    )?;
    writeln!(
        out,
        "clusters     {} glue clusters formed ({} joins), holding {in_clusters} of the {glue_count} glue beads; \
         the largest has {largest}; {at_rest} glue beads rest on the floor",
        clusters.len(),
        stats.joins
    )?;
    writeln!(
        out,
        "energy       {:.1} of {ke0:.1} lost in sticky collisions ({:.1} %); \
         start − end − lost = {:+.1e} of the start",
        stats.energy_lost,
        100.0 * stats.energy_lost / ke0,
        (ke0 - ke1 - stats.energy_lost) / ke0
    )?;
    write_kernels(out, &stats)?;
    if collisions > 0 {
        writeln!(
            out,
            "max overlap  at collisions {:.1e} of the contact distance (pairs), {:.1e} of the \
             radius (walls); in the state, checked {SAMPLES} times, {:.1e} and {:.1e} of the \
             tolerance",
            stats.max_overlap, stats.max_wall_overlap, worst.0, worst.1
        )?;
    }
    out.flush()?;
    Ok(End {
        spheres,
        clusters,
        collisions,
        at_rest,
    })
}

/// The summary's line of kernel calls, naming the kinds that ran.
fn write_kernels(out: &mut impl Write, stats: &Stats) -> std::io::Result<()> {
    let k = stats.kernels;
    let ran: Vec<&str> = [
        ("sphere", k.sphere),
        ("plane", k.plane),
        ("cylinder", k.cylinder),
        ("container", k.container),
    ]
    .iter()
    .filter(|(_, c)| *c > 0)
    .map(|(name, _)| *name)
    .collect();
    writeln!(
        out,
        "kernels      sphere {} (approaching pairs solved in f64, four at a time), plane {}, \
         cylinder {}, container {}: {} ran",
        k.sphere,
        k.plane,
        k.cylinder,
        k.container,
        if ran.len() == 4 {
            "all four".to_string()
        } else {
            ran.join(", ")
        }
    )
}

/// Half-thickness of the side view's slice.
const SLICE: f64 = 3.0;
/// Height of the top view's floor layer above the floor.
const LAYER: f64 = 3.0;

/// The demo's picture: a title, the side view (a slice through the middle) and the top view
/// (the layer just above the floor), and a legend.
fn draw(size: Size, title: &str, content: &Content, floor: f64, t_end: f64) -> Canvas {
    let mut canvas = Canvas::new(size.width, size.height, Rgb(255, 255, 255));
    let fs = picture::text_size(size.width);
    let (w, h) = (f64::from(size.width), f64::from(size.height));
    canvas.text(
        (fs, fs * 1.5),
        title,
        fs,
        Rgb::hex(0x222222),
        picture::Anchor::Start,
    );
    let legend_y = h - fs * 0.7;
    let rects = picture::panel_rects(size.width, fs * 2.0, legend_y - fs * 1.6, 2, fs);
    let panels = [
        Panel {
            rect: rects[0],
            view: View::Side,
            title: format!("side, slice |y| < {SLICE}"),
            slab: Some((-SLICE, SLICE)),
        },
        Panel {
            rect: rects[1],
            view: View::Top,
            title: format!("top, beads within {LAYER} of the floor"),
            slab: Some((floor, floor + LAYER)),
        },
    ];
    for panel in &panels {
        picture::draw_panel(&mut canvas, panel, content);
    }
    let (vessel, pillar, ground) = picture::SHAPE_COLOURS;
    let recent = format!("glass path, t > {}", t_end - t_end / 10.0);
    let entries = [
        (Key::Disk(GLASS_FILL.into()), "glass".to_string()),
        (Key::Disk(GLUE_FREE.into()), "glue".to_string()),
        (
            Key::Disk(GLUE_RESTING.into()),
            "glue on the floor".to_string(),
        ),
        (
            Key::Disk(CLUSTER_COLOURS[0].into()),
            "glue clusters".to_string(),
        ),
        (Key::Path(GLUE_PATH), "glue path".to_string()),
        (Key::Path(GLASS_PATH), recent),
        (Key::Swatch(pillar), "pillars".to_string()),
        (Key::Swatch(ground), "floor".to_string()),
        (Key::Swatch(vessel), "vessel".to_string()),
    ];
    let left = rects.first().map_or(fs, |r| r.x);
    picture::legend(&mut canvas, (left, legend_y), w - fs, &entries);
    canvas
}

/// A rate with an SI prefix.
fn si(x: f64) -> String {
    match x {
        x if x >= 1e9 => format!("{:.2} G", x / 1e9),
        x if x >= 1e6 => format!("{:.2} M", x / 1e6),
        x if x >= 1e3 => format!("{:.1} k", x / 1e3),
        x => format!("{x:.1}"),
    }
}
