//! `spheresweep render`: pictures of a scene file (its world at `t = 0`) or of recorded
//! snapshots (extended XYZ, as `spheresweep run` writes them: one frame, or every frame as a
//! numbered sequence), side and/or top view, as SVG and/or PNG.
//!
//! Pictures are framed by the scene's periodic box, open box or vessel, else by a robust
//! extent of the spheres (`picture::frame`); spheres outside the frame are counted in the
//! caption. Everything that can be refused (the input — a snapshot with a position that is
//! not finite or a negative radius included —, the frame, the scene of shapes, the output
//! directory) is refused before any picture is written; each picture is written under a
//! temporary name and renamed into place, and if writing one fails, the pictures this run had
//! already added are removed again.

use std::error::Error;
use std::io::Write;
use std::path::{Path, PathBuf};

use glam::DVec3;
use rayon::prelude::*;
use spheresweep::ShapeKind;
use spheresweep::io::scene_file::SceneFile;
use spheresweep::io::xyz::{self, Frame};
use spheresweep::sim::SphereState;

use crate::number::counted;
use crate::picture::{
    self, Canvas, Content, Format, Key, MATERIAL_COLOURS, Paint, Panel, Rgb, Shapes, Size, View,
};

/// Options of `spheresweep render`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// A scene file (TOML, or JSON if its name ends in .json), drawn at t = 0; or snapshots in
    /// extended XYZ (a name ending in .xyz or .extxyz), such as `run` writes in trajectory.xyz.
    input: PathBuf,
    /// Directory for the pictures (default: `<stem>-render/` beside the input). A scene gives
    /// `<stem>.svg`/`.png`; snapshots give `frame-0000.svg`/`.png`, `frame-0001…`, numbered
    /// by frame (every frame: refused if the directory holds other frame pictures).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Snapshots only: draw frame K (counted from 0, below the number of frames). Default:
    /// every frame.
    #[arg(long, value_name = "K")]
    frame: Option<usize>,
    /// Snapshots only: draw this scene file's planes, cylinders, containers and boundary with
    /// the spheres, frame the pictures by its boundary or vessel, and name its materials in
    /// the legend. Default: the scene that the summary.json beside the snapshots names (as
    /// `run` writes it), looked for from here, then beside the run, if it still builds the
    /// world the run started from; else none, the spheres only, with a warning.
    #[arg(long, value_name = "SCENE")]
    scene: Option<PathBuf>,
    /// Which files: svg, png or both.
    #[arg(long, value_enum, default_value_t = Format::Both)]
    format: Format,
    /// Which view: side (x to the right, z up), top (x to the right, y up) or both side by
    /// side.
    #[arg(long, value_enum, default_value_t = Views::Both)]
    view: Views,
    /// Picture size in pixels, WIDTHxHEIGHT (default: 1600x800 for both views, 800x800 for
    /// one).
    #[arg(long, value_name = "WxH")]
    size: Option<Size>,
}

/// The `--view` choices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Views {
    Side,
    Top,
    Both,
}

impl Views {
    fn list(self) -> &'static [View] {
        match self {
            Views::Side => &[View::Side],
            Views::Top => &[View::Top],
            Views::Both => &[View::Side, View::Top],
        }
    }
}

/// What the input is.
enum Input {
    Scene,
    Snapshots,
}

fn kind_of(path: &Path) -> Result<Input, String> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("toml" | "json") => Ok(Input::Scene),
        Some("xyz" | "extxyz") => Ok(Input::Snapshots),
        _ => Err(format!(
            "{}: cannot tell what to draw: name a scene file .toml or .json, or snapshots .xyz \
             or .extxyz",
            path.display()
        )),
    }
}

/// One picture to draw: its file stem, title, spheres and time.
struct Picture<'a> {
    stem: String,
    title: String,
    spheres: &'a [SphereState],
}

/// The default output directory: `<stem>-render/` beside the input.
fn default_out(input: &Path) -> PathBuf {
    let stem = input
        .file_stem()
        .map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    let dir = match input.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    dir.join(format!("{stem}-render"))
}

fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// Reads every frame of an extended XYZ file, naming the path (and line) at fault.
fn read_snapshots(path: &Path) -> Result<Vec<Frame>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let frames = xyz::read_frames(&text)
        .map_err(|e| format!("{}:{}: {}", path.display(), e.line, e.problem))?;
    if frames.is_empty() {
        return Err(format!("{}: no frames", path.display()));
    }
    Ok(frames)
}

/// What is drawn: the frames, which of them, the static shapes and the names of materials.
struct Record {
    frames: Vec<Frame>,
    chosen: Vec<usize>,
    shapes: Shapes,
    /// Legend entries of the static shapes, naming their materials.
    shape_keys: Vec<(Key, String)>,
    material_names: Vec<String>,
    /// The scene file the shapes come from, if any.
    scene_path: Option<PathBuf>,
    /// Where the shapes came from, when not named on the command line.
    note: Option<String>,
}

/// A scene file, drawn at `t = 0`.
fn scene_record(args: &Args) -> Result<Record, Box<dyn Error>> {
    if args.frame.is_some() {
        return Err(format!(
            "--frame applies to snapshots (.xyz), not to the scene file {}",
            args.input.display()
        )
        .into());
    }
    if args.scene.is_some() {
        return Err(format!(
            "--scene applies to snapshots (.xyz): {} is a scene file already",
            args.input.display()
        )
        .into());
    }
    let (scene, world) = scene_and_world(&args.input)?;
    if let Some(why) = refusal(&scene, &world) {
        // Drawn all the same: the picture is how one sees what is wrong.
        eprintln!(
            "warning: {}: drawn, but `run` refuses this scene: {why}",
            args.input.display()
        );
    }
    let shapes = Shapes::of_world(&world);
    Ok(Record {
        chosen: vec![0],
        shape_keys: shape_keys(&world),
        material_names: world.materials,
        frames: vec![Frame {
            time: 0.0,
            periodic_box: shapes.periodic_box,
            spheres: world.spheres,
        }],
        shapes,
        scene_path: None,
        note: None,
    })
}

/// Why `run` would refuse `scene`'s `world` (spheres overlapping, or through a shape, at the
/// start), located in the file; `None` if it would run it.
fn refusal(scene: &SceneFile, world: &spheresweep::sim::World) -> Option<String> {
    let err = spheresweep::sim::Simulation::new(world.clone()).err()?;
    Some(scene.locate(err).to_string())
}

/// A scene file and its world, refused up front if too large for memory.
fn scene_and_world(path: &Path) -> Result<(SceneFile, spheresweep::sim::World), Box<dyn Error>> {
    let scene = SceneFile::from_path(path)?;
    crate::memory::check_scene(path, &scene, size_of::<SphereState>())?;
    let world = scene.build()?.0;
    Ok((scene, world))
}

/// Recorded snapshots, with the shapes and material names of `--scene`, or else of the scene
/// that `run` recorded in the `summary.json` beside them (when it exists and has as many
/// spheres as the first frame).
fn snapshot_record(args: &Args) -> Result<Record, Box<dyn Error>> {
    let frames = read_snapshots(&args.input)?;
    let chosen = match args.frame {
        Some(k) if k >= frames.len() => {
            return Err(format!(
                "--frame {k}: {} has {} (0 to {})",
                args.input.display(),
                counted(frames.len() as u64, "frame", "frames"),
                frames.len() - 1
            )
            .into());
        }
        Some(k) => vec![k],
        None => (0..frames.len()).collect(),
    };
    let (world, scene_path, note) = match &args.scene {
        Some(path) => {
            let (_, world) = scene_and_world(path)?;
            let (theirs, ours) = (world.spheres.len(), frames[0].spheres.len());
            if theirs != ours {
                // Shapes drawn over spheres of another run may be what the user wants (a
                // scene's walls over data from elsewhere), so a warning, not a refusal.
                eprintln!(
                    "warning: --scene {} has {}, the snapshots {ours}: its shapes and \
                     materials may not be those the snapshots were recorded with",
                    path.display(),
                    counted(theirs as u64, "sphere", "spheres"),
                );
            }
            (Some(world), Some(path.clone()), None)
        }
        None => match scene_of_run(&args.input, frames[0].spheres.len()).unwrap_or_else(|why| {
            eprintln!("{why}");
            None
        }) {
            Some((path, world)) => {
                let note = format!(
                    "shapes and materials of {} (the scene summary.json names; --scene to \
                     choose another)",
                    path.display()
                );
                (Some(world), Some(path), Some(note))
            }
            None => (None, None, None),
        },
    };
    let mut shapes = world.as_ref().map(Shapes::of_world).unwrap_or_default();
    if shapes.periodic_box.is_none() {
        shapes.periodic_box = frames[0].periodic_box;
    }
    Ok(Record {
        frames,
        chosen,
        shapes,
        shape_keys: world.as_ref().map(shape_keys).unwrap_or_default(),
        material_names: world.map(|w| w.materials).unwrap_or_default(),
        scene_path,
        note,
    })
}

/// The scene a run's `summary.json` beside `snapshots` names, and its world, if some file of
/// that name builds the world the run started from (its `run.fingerprint`; a summary without
/// one: as many spheres as the snapshots). A relative name is `run`'s working directory's, so
/// it is looked for from here, then from the run's directory and the one above it. `Ok(None)`
/// without a summary; `Err` says why a named scene is not drawn.
fn scene_of_run(
    snapshots: &Path,
    spheres: usize,
) -> Result<Option<(PathBuf, spheresweep::sim::World)>, String> {
    let summary = snapshots.with_file_name("summary.json");
    let Some(json) = std::fs::read_to_string(&summary)
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
    else {
        return Ok(None);
    };
    let Some(named) = json
        .get("scene")
        .and_then(|v| v.as_str())
        .map(PathBuf::from)
    else {
        return Ok(None);
    };
    let fingerprint = json
        .pointer("/run/fingerprint")
        .and_then(|v| v.as_str())
        .map(str::to_owned);
    let run_dir = match summary.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let mut candidates = vec![named.clone()];
    if named.is_relative() {
        candidates.push(run_dir.join(&named));
        candidates.push(above(&run_dir).join(&named));
    }
    candidates.dedup();
    let matches = |path: &PathBuf| -> Option<spheresweep::sim::World> {
        let scene = SceneFile::from_path(path).ok()?;
        if scene.sphere_count()? != spheres {
            return None;
        }
        crate::memory::check_scene(path, &scene, size_of::<SphereState>()).ok()?;
        let world = scene.build().ok()?.0;
        let same = match &fingerprint {
            Some(f) => *f == crate::run::hash::text(crate::run::hash::world(&world)),
            None => true,
        };
        same.then_some(world)
    };
    if let Some((path, world)) = candidates
        .iter()
        .find_map(|p| matches(p).map(|w| (p.clone(), w)))
    {
        return Ok(Some((path, world)));
    }
    let found = candidates.iter().any(|p| p.is_file());
    Err(format!(
        "warning: {} names the scene {}, but {}: the spheres are drawn without shapes \
         (--scene FILE draws a scene's)",
        summary.display(),
        named.display(),
        if found {
            "no file of that name here or beside the run builds the world the run started \
             from (changed since, or another file)"
        } else {
            "no file of that name is found here or beside the run"
        }
    ))
}

/// The directory above `dir`, as short as it can be said: `..` above `.`, `../..` above `..`.
fn above(dir: &Path) -> PathBuf {
    if dir == Path::new(".") {
        PathBuf::from("..")
    } else if dir.ends_with("..") {
        dir.join("..")
    } else {
        match dir.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        }
    }
}

/// Legend entries of a world's static shapes: how many of each kind, and their materials.
fn shape_keys(world: &spheresweep::sim::World) -> Vec<(Key, String)> {
    let (vessel, pillar, floor) = picture::SHAPE_COLOURS;
    let named = |materials: Vec<u16>, one: &str, many: &str| {
        let mut names: Vec<&str> = materials
            .iter()
            .map(|&m| {
                world
                    .materials
                    .get(usize::from(m))
                    .map_or("?", String::as_str)
            })
            .collect();
        names.dedup();
        let n = materials.len();
        format!(
            "{n} {}: {}",
            if n == 1 { one } else { many },
            names.join(", ")
        )
    };
    let mut keys = Vec::new();
    for (kind, swatch) in [
        (ShapeKind::Plane, floor),
        (ShapeKind::Cylinder, pillar),
        (ShapeKind::Container, vessel),
    ] {
        let m: Vec<u16> = (world.statics.iter())
            .filter(|(b, _, _)| b.kind == kind)
            .map(|(_, _, &m)| m)
            .collect();
        if !m.is_empty() {
            let many = format!("{kind}s");
            keys.push((Key::Swatch(swatch), named(m, kind.name(), &many)));
        }
    }
    let (periodic, region) = picture::BOX_COLOURS;
    match world.boundary {
        spheresweep::sim::Boundary::Periodic { .. } => {
            keys.push((Key::Swatch(periodic), "periodic box".into()));
        }
        spheresweep::sim::Boundary::OpenBox { .. } => {
            keys.push((Key::Swatch(region), "open box (the frame)".into()));
        }
        _ => {}
    }
    keys
}

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    // The input, and everything asked of it, before any output.
    let kind = kind_of(&args.input)?;
    let views = args.view.list();
    let size = picture_size(args.size, views);
    let Record {
        frames,
        chosen,
        shapes,
        shape_keys,
        material_names,
        scene_path,
        note,
    } = match kind {
        Input::Scene => scene_record(args)?,
        Input::Snapshots => snapshot_record(args)?,
    };

    // Every picture shares one view of the whole record, so that a sequence stays still.
    let bounds = picture::bounds(frames.iter().flat_map(|f| &f.spheres), &shapes);
    let pictures = pictures(args, &kind, &frames, &chosen, bounds);
    // Ctrl-C and SIGTERM from here on: pictures not yet started are skipped; each written
    // one is whole (written under a temporary name and renamed). Installed before the
    // output directory is probed with a temporary file.
    crate::interrupt::install()?;
    let dir = checked_outputs(args, &pictures, scene_path.as_deref())?;
    let legend = legend(&frames, &chosen, &material_names, shape_keys);
    let extensions = args.format.extensions();
    let results: Vec<Result<Vec<(PathBuf, bool)>, String>> = pictures
        .par_iter()
        .map(|p| {
            if crate::interrupt::requested() {
                return Ok(Vec::new());
            }
            let canvas = draw(size, views, p, &shapes, bounds, &legend);
            let mut written = Vec::new();
            for ext in extensions {
                let path = dir.join(format!("{}.{ext}", p.stem));
                let existed = path.exists();
                let bytes = Format::encode(&canvas, ext)?;
                crate::atomic::write_atomic(&path, &bytes)?;
                written.push((path, !existed));
            }
            Ok(written)
        })
        .collect();
    let written = all_or_none(results)?;
    let files = written.len();
    if files < pictures.len() * extensions.len() {
        return Err(crate::interrupt::Interrupted(format!(
            "after {files} of {} pictures: those are whole and kept in {}, the rest not drawn",
            pictures.len() * extensions.len(),
            dir.display()
        ))
        .into());
    }
    report(note, &written, size)?;
    Ok(())
}

/// `--size`, by default 1600×800 for both views and 800×800 for one.
fn picture_size(asked: Option<Size>, views: &[View]) -> Size {
    asked.unwrap_or(if views.len() == 2 {
        Size {
            width: 1600,
            height: 800,
        }
    } else {
        Size {
            width: 800,
            height: 800,
        }
    })
}

/// The pictures to draw, one per chosen frame: file stems and titles.
fn pictures<'a>(
    args: &Args,
    kind: &Input,
    frames: &'a [Frame],
    chosen: &[usize],
    bounds: (DVec3, DVec3),
) -> Vec<Picture<'a>> {
    let name = file_name(&args.input);
    let digits = frames.len().saturating_sub(1).to_string().len().max(4);
    chosen
        .iter()
        .map(|&k| {
            let f = &frames[k];
            // Spheres the frame leaves out are counted, never silently dropped.
            let spheres = match picture::outside(&f.spheres, bounds) {
                0 => format!("{} spheres", f.spheres.len()),
                n => format!("{} spheres ({n} outside the frame)", f.spheres.len()),
            };
            match kind {
                Input::Scene => Picture {
                    stem: args
                        .input
                        .file_stem()
                        .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned()),
                    title: format!("{name}: {spheres} at t = 0"),
                    spheres: &f.spheres,
                },
                Input::Snapshots => Picture {
                    stem: format!("frame-{k:0digits$}"),
                    title: format!(
                        "{name}: frame {k} of {}, t = {}, {spheres}",
                        frames.len(),
                        crate::number::num(f.time),
                    ),
                    spheres: &f.spheres,
                },
            }
        })
        .collect()
}

/// The output directory, checked with every picture's path (none is an input, the directory
/// can be written) and rid of the temporaries a killed render left there.
fn checked_outputs(
    args: &Args,
    pictures: &[Picture],
    scene_path: Option<&Path>,
) -> Result<PathBuf, Box<dyn Error>> {
    let dir = args.out.clone().unwrap_or_else(|| default_out(&args.input));
    if dir.exists() && !dir.is_dir() {
        return Err(format!("--out {}: not a directory", dir.display()).into());
    }
    let extensions = args.format.extensions();
    let outputs: Vec<PathBuf> = pictures
        .iter()
        .flat_map(|p| {
            extensions
                .iter()
                .map(|ext| dir.join(format!("{}.{ext}", p.stem)))
        })
        .collect();
    let inputs: Vec<&Path> = std::iter::once(args.input.as_path())
        .chain(scene_path)
        .collect();
    for path in &outputs {
        crate::output::not_an_input(path, &inputs)?;
    }
    if args.frame.is_none() && matches!(kind_of(&args.input), Ok(Input::Snapshots)) {
        let stale = other_frames(&dir, &outputs, extensions);
        if let Some(first) = stale.first() {
            return Err(format!(
                "--out {}: holds {} this render does not write ({}{}), from another \
                 render: they would read as one sequence with these; remove them or choose \
                 another --out",
                dir.display(),
                counted(stale.len() as u64, "frame picture", "frame pictures"),
                first.display(),
                if stale.len() > 1 { ", …" } else { "" }
            )
            .into());
        }
    }
    crate::output::check_writable(&outputs[0])?;
    crate::atomic::remove_stale_temporaries(&outputs);
    Ok(dir)
}

/// The frame pictures in `dir` (`frame-*` of the extensions written) that are not among
/// `outputs`, sorted: a render of every frame would leave them beside its own.
fn other_frames(dir: &Path, outputs: &[PathBuf], extensions: &[&str]) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut found: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let named = p
                .file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("frame-"));
            let ext = p.extension().and_then(|e| e.to_str());
            named && ext.is_some_and(|e| extensions.contains(&e)) && !outputs.contains(p)
        })
        .collect();
    found.sort();
    found
}

/// The legend: the materials of the chosen frames' spheres, by name, then the shapes' keys.
fn legend(
    frames: &[Frame],
    chosen: &[usize],
    material_names: &[String],
    shape_keys: Vec<(Key, String)>,
) -> Vec<(Key, String)> {
    let used: Vec<u16> = {
        let mut m: Vec<u16> = chosen
            .iter()
            .flat_map(|&k| frames[k].spheres.iter().map(|s| s.material))
            .collect();
        m.sort_unstable();
        m.dedup();
        m
    };
    used.iter()
        .map(|&m| {
            let label = material_names
                .get(usize::from(m))
                .cloned()
                .unwrap_or_else(|| format!("material {m}"));
            (Key::Disk(colour(m)), label)
        })
        .chain(shape_keys)
        .collect()
}

/// The pictures written, each with whether it is new; if one failed, the new ones are removed
/// again and the first failure is the error.
fn all_or_none(
    results: Vec<Result<Vec<(PathBuf, bool)>, String>>,
) -> Result<Vec<(PathBuf, bool)>, String> {
    let mut written = Vec::new();
    let mut failure = None;
    for r in results {
        match r {
            Ok(w) => written.extend(w),
            Err(e) => failure = failure.or(Some(e)),
        }
    }
    if let Some(e) = failure {
        for (path, new) in &written {
            if *new {
                let _ = std::fs::remove_file(path);
            }
        }
        return Err(e);
    }
    Ok(written)
}

/// Prints the note on the input, if any, and the pictures written.
fn report(note: Option<String>, written: &[(PathBuf, bool)], size: Size) -> std::io::Result<()> {
    let files = written.len();
    let mut out = std::io::stdout().lock();
    if let Some(note) = note {
        writeln!(out, "{note}")?;
    }
    match written {
        [] => {}
        [(only, _)] => writeln!(out, "wrote {} ({size} px)", only.display())?,
        [(a, _), (b, _)] => writeln!(out, "wrote {} and {} ({size} px)", a.display(), b.display())?,
        [(a, _), .., (z, _)] => writeln!(
            out,
            "wrote {files} pictures ({size} px): {} … {}",
            a.display(),
            z.display()
        )?,
    }
    Ok(())
}

/// The colour of material `m`.
fn colour(m: u16) -> Paint {
    MATERIAL_COLOURS[usize::from(m) % MATERIAL_COLOURS.len()].into()
}

/// One picture: the title, a panel per view, the legend of materials.
fn draw(
    size: Size,
    views: &[View],
    p: &Picture,
    shapes: &Shapes,
    bounds: (DVec3, DVec3),
    legend: &[(Key, String)],
) -> Canvas {
    let mut canvas = Canvas::new(size.width, size.height, Rgb(255, 255, 255));
    let fs = picture::text_size(size.width);
    let (w, h) = (f64::from(size.width), f64::from(size.height));
    canvas.text(
        (fs, fs * 1.5),
        &p.title,
        fs,
        Rgb::hex(0x222222),
        picture::Anchor::Start,
    );
    let legend_y = h - fs * 0.7;
    let rects = picture::panel_rects(size.width, fs * 2.0, legend_y - fs * 1.6, views.len(), fs);
    let fill = |_: usize, s: &SphereState| colour(s.material);
    let content = Content {
        spheres: p.spheres,
        fill: &fill,
        shapes,
        paths: &[],
        bounds,
    };
    for (rect, &view) in rects.iter().zip(views) {
        let (a, b) = view.axis_names();
        let panel = Panel {
            rect: *rect,
            view,
            title: match view {
                View::Side => format!("side ({a}–{b})"),
                View::Top => format!("top ({a}–{b})"),
            },
            slab: None,
        };
        picture::draw_panel(&mut canvas, &panel, &content);
    }
    let left = rects.first().map_or(fs, |r| r.x);
    picture::legend(&mut canvas, (left, legend_y), w - fs, legend);
    canvas
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inputs_are_told_apart_by_their_names() {
        assert!(matches!(kind_of(Path::new("a/b.toml")), Ok(Input::Scene)));
        assert!(matches!(kind_of(Path::new("b.JSON")), Ok(Input::Scene)));
        assert!(matches!(kind_of(Path::new("t.xyz")), Ok(Input::Snapshots)));
        let e = kind_of(Path::new("notes.txt")).err().unwrap();
        assert!(e.contains("notes.txt") && e.contains(".xyz"), "{e}");
    }

    #[test]
    fn the_default_output_is_beside_the_input() {
        assert_eq!(
            default_out(Path::new("scenes/jet.toml")),
            Path::new("scenes/jet-render")
        );
        assert_eq!(default_out(Path::new("t.xyz")), Path::new("./t-render"));
    }
}
