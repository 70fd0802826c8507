//! `spheresweep query`: the time of impact of every row of a file of sphere pairs, or of
//! every sphere of a file against the static shapes of a shapes file, written to a file of the
//! same format (docs/query-format.md).
//!
//! The input is read in chunks of `--chunk-rows` rows, each validated by the library's
//! constructors, queried by its batch entry points and written out before the next is read,
//! so memory stays flat whatever the input's size. Everything that can be refused before the
//! first row (arguments, the shapes file, the input's header or schema, the output path) is
//! refused before any output exists; the output is written under a temporary name and renamed
//! into place when complete, so a query that fails half-way leaves nothing behind.
//!
//! - `layout`: the columns of each layout, chunks and results;
//! - `compute`: a chunk through the library;
//! - `shapes`: the shapes file (the scene file's shape tables);
//! - `csv`, `npy`, `columnar` (feature `parquet`): the formats, each output written whole or
//!   not at all (`crate::atomic`).

mod compute;
mod csv;
mod layout;
mod npy;
mod shapes;
#[cfg(test)]
mod tests;

#[cfg(feature = "parquet")]
mod columnar;

use std::error::Error;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use spheresweep::{Accuracy, QueryOptions};

use crate::number::counted;
use compute::Shapes;
use layout::{Chunk, Layout, OutColumn, Results};

/// Options of `spheresweep query`.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "File layouts, column by column with types and units: docs/query-format.md."
)]
pub struct Args {
    /// The input: a CSV file with a header; a .npy file holding one (N, 14) array (pairs) or
    /// (N, 7) array (spheres); a directory of .npy files, one per column (ax.npy, ay.npy, …);
    /// several .npy column files; a .parquet file or an Arrow IPC file (.arrow, .feather,
    /// .ipc; .arrows for the stream format), with the `parquet` feature. A pairs file has
    /// the columns ax, ay, az, avx, avy, avz, ar, bx, by, bz, bvx, bvy, bvz, br (centre at
    /// t = 0, velocity, radius of spheres A and B); a spheres file (with --against) has x, y,
    /// z, vx, vy, vz, r.
    #[arg(required = true, num_args = 1.., value_name = "INPUT")]
    input: Vec<PathBuf>,
    /// Query every sphere of the input (a spheres file) against the planes, cylinders and
    /// containers of this file: the plane, cylinder and container tables of a scene file
    /// (TOML, or JSON if it ends in .json; docs/scene-format.md; the run table is optional).
    /// Default: none, the input is a pairs file.
    #[arg(long, value_name = "SHAPES")]
    against: Option<PathBuf>,
    /// Where the results go; its extension picks the format (.csv, .parquet, .arrow,
    /// .feather, .ipc, .arrows, .npy for a single time column; no extension: a directory of
    /// .npy columns). Default: beside the input, named `<input>-toi`, in the input's format.
    #[arg(long, value_name = "PATH")]
    out: Option<PathBuf>,
    /// Accuracy mode of the kernels: textbook (the formula as written, f32), stable (f32,
    /// rearranged to keep its digits) or double (the stable formulas in f64).
    #[arg(long, default_value_t = Accuracy::Stable)]
    accuracy: Accuracy,
    /// End of the time window [0, t_max], in the input's time unit (its lengths over its
    /// speeds): zero or more, inf for no end; rounded down to the kernels' f32, so that no
    /// contact after it is reported.
    #[arg(long, default_value_t = f32::INFINITY, allow_negative_numbers = true, value_parser = crate::number::window_end)]
    t_max: f32,
    /// Also write the contact point and normal of every contact (px, py, pz, nx, ny, nz).
    #[arg(long)]
    geometry: bool,
    /// Rows read, queried and written at a time, 1 to 67 108 864 (2²⁶): memory grows with it
    /// (about 0.3 KiB a row at most, 0.7 from CSV; for at most the rows the input has room
    /// for), not with the input. A chunk larger than the memory
    /// available (the least of MemAvailable, what ulimit -v and the cgroup's memory limit
    /// leave; or SPHERESWEEP_MAX_MEMORY in bytes, e.g. 512M) is refused.
    #[arg(long, default_value_t = 1 << 20, value_name = "N")]
    chunk_rows: usize,
    /// Replace an existing output file that is not a query's CSV result (one whose header is
    /// a result's columns is replaced without it; a directory of .npy columns is replaced
    /// when it holds only result columns). Default: such a file is refused, naming it.
    #[arg(long)]
    force: bool,
}

/// The most rows a chunk may hold (about 3.5 GiB of pair columns).
const MAX_CHUNK_ROWS: usize = 1 << 26;

/// Rows of an input, read a chunk at a time.
pub trait Source {
    /// Fills `chunk` with the next rows, at most `max` of them; `false` once the input is
    /// exhausted (the chunk is then empty).
    fn next(&mut self, max: usize, chunk: &mut Chunk) -> Result<bool, String>;
    /// Rows in all, when the format tells before reading them.
    fn total_rows(&self) -> Option<u64>;
}

/// Results written a chunk at a time to a staged output.
pub trait Sink {
    /// Appends one chunk's results.
    fn write(&mut self, results: &Results) -> Result<(), String>;
    /// Completes the output and renames it into place.
    fn commit(self: Box<Self>) -> Result<(), String>;
    /// The final path.
    fn path(&self) -> &Path;
}

/// Runs `f`, turning a panic inside a third-party reader into an error naming `what` (the
/// last resort: inputs are checked before they are read, and the readers report errors as
/// values). The panic message is not printed.
pub(crate) fn guarded<T>(what: &str, f: impl FnOnce() -> T) -> Result<T, String> {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    std::panic::set_hook(hook);
    result.map_err(|panic| {
        let message = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".into());
        format!("cannot read {what}: the reader failed: {message}")
    })
}

/// What the input is, from its path(s).
#[derive(Debug, Clone, PartialEq)]
enum Input {
    Csv(PathBuf),
    NpyMatrix(PathBuf),
    NpyDir(PathBuf),
    NpyFiles(Vec<PathBuf>),
    Parquet(PathBuf),
    Ipc(PathBuf),
}

/// What the output is, from its path or the input's format.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Output {
    Csv,
    NpyFile,
    NpyDir,
    Parquet,
    Ipc { stream: bool },
}

impl Output {
    fn name(self) -> &'static str {
        match self {
            Output::Csv => "CSV",
            Output::NpyFile => ".npy array",
            Output::NpyDir => "directory of .npy columns",
            Output::Parquet => "Parquet",
            Output::Ipc { stream: false } => "Arrow IPC file",
            Output::Ipc { stream: true } => "Arrow IPC stream",
        }
    }
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
}

const FORMATS: &str = ".csv, .npy, a directory of .npy columns, .parquet or .pq, .arrow, \
                       .feather, .ipc, .arrows";

impl Input {
    fn detect(paths: &[PathBuf]) -> Result<Self, String> {
        for p in paths {
            std::fs::metadata(p).map_err(|e| format!("cannot read {}: {e}", p.display()))?;
        }
        if paths.len() > 1 {
            if let Some(p) = paths
                .iter()
                .find(|p| extension(p).as_deref() != Some("npy"))
            {
                return Err(format!(
                    "{}: several inputs are read as .npy column files (ax.npy, ay.npy, …), and \
                     this is not one",
                    p.display()
                ));
            }
            return Ok(Input::NpyFiles(paths.to_vec()));
        }
        let path = paths[0].clone();
        if path.is_dir() {
            return Ok(Input::NpyDir(path));
        }
        match extension(&path).as_deref() {
            Some("csv") => Ok(Input::Csv(path)),
            Some("npy") => Ok(Input::NpyMatrix(path)),
            Some("parquet" | "pq") => Ok(Input::Parquet(path)),
            Some("arrow" | "feather" | "ipc" | "arrows") => Ok(Input::Ipc(path)),
            _ => Err(format!(
                "{}: cannot tell the format from the name: expected {FORMATS}",
                path.display()
            )),
        }
    }

    /// The path named in messages.
    fn label(&self) -> String {
        match self {
            Input::Csv(p)
            | Input::NpyMatrix(p)
            | Input::NpyDir(p)
            | Input::Parquet(p)
            | Input::Ipc(p) => p.display().to_string(),
            Input::NpyFiles(ps) => {
                let names: Vec<String> = ps.iter().map(|p| p.display().to_string()).collect();
                names.join(" ")
            }
        }
    }

    fn format_name(&self) -> &'static str {
        match self {
            Input::Csv(_) => "CSV",
            Input::NpyMatrix(_) => ".npy array",
            Input::NpyDir(_) => "directory of .npy columns",
            Input::NpyFiles(_) => ".npy column files",
            Input::Parquet(_) => "Parquet",
            Input::Ipc(_) => "Arrow IPC",
        }
    }

    /// The default output: beside the input, `<name>-toi`, in the same format.
    fn default_output(&self) -> (PathBuf, Output) {
        let beside = |p: &Path, ext: Option<&str>| {
            let stem = p.file_stem().unwrap_or_default().to_string_lossy();
            let name = match ext {
                Some(e) => format!("{stem}-toi.{e}"),
                None => format!("{stem}-toi"),
            };
            p.with_file_name(name)
        };
        match self {
            Input::Csv(p) => (beside(p, Some("csv")), Output::Csv),
            Input::NpyMatrix(p) => (beside(p, None), Output::NpyDir),
            Input::NpyDir(p) => {
                let name = p.file_name().unwrap_or_default().to_string_lossy();
                (p.with_file_name(format!("{name}-toi")), Output::NpyDir)
            }
            Input::NpyFiles(ps) => {
                let dir = ps.first().and_then(|p| p.parent()).unwrap_or(Path::new(""));
                (dir.join("toi"), Output::NpyDir)
            }
            Input::Parquet(p) => {
                let ext = extension(p).unwrap_or_else(|| "parquet".into());
                (beside(p, Some(&ext)), Output::Parquet)
            }
            Input::Ipc(p) => {
                let ext = extension(p).unwrap_or_else(|| "arrow".into());
                let stream = ext == "arrows";
                (beside(p, Some(&ext)), Output::Ipc { stream })
            }
        }
    }

    fn paths(&self) -> Vec<&Path> {
        match self {
            Input::NpyFiles(ps) => ps.iter().map(PathBuf::as_path).collect(),
            Input::Csv(p)
            | Input::NpyMatrix(p)
            | Input::NpyDir(p)
            | Input::Parquet(p)
            | Input::Ipc(p) => vec![p.as_path()],
        }
    }

    fn open(&self, layout: Layout, chunk_rows: usize) -> Result<Box<dyn Source>, String> {
        #[cfg(not(feature = "parquet"))]
        let _ = chunk_rows;
        Ok(match self {
            Input::Csv(p) => Box::new(csv::CsvSource::open(p, layout)?),
            Input::NpyMatrix(p) => Box::new(npy::NpySource::matrix(p, layout)?),
            Input::NpyDir(p) => Box::new(npy::NpySource::directory(p, layout)?),
            Input::NpyFiles(ps) => Box::new(npy::NpySource::files(ps, layout)?),
            #[cfg(feature = "parquet")]
            Input::Parquet(p) => Box::new(columnar::BatchSource::parquet(p, layout, chunk_rows)?),
            #[cfg(feature = "parquet")]
            Input::Ipc(p) => Box::new(columnar::BatchSource::ipc(p, layout)?),
            #[cfg(not(feature = "parquet"))]
            Input::Parquet(p) | Input::Ipc(p) => return Err(no_columnar(p)),
        })
    }
}

#[cfg(not(feature = "parquet"))]
fn no_columnar(p: &Path) -> String {
    format!(
        "{}: Parquet and Arrow IPC files need the `parquet` feature of spheresweep-cli, which \
         this build lacks: cargo build --release -p spheresweep-cli --features parquet",
        p.display()
    )
}

impl Output {
    fn from_path(path: &Path) -> Result<Self, String> {
        if path.is_dir() {
            return Ok(Output::NpyDir);
        }
        match extension(path).as_deref() {
            None => Ok(Output::NpyDir),
            Some("csv") => Ok(Output::Csv),
            Some("npy") => Ok(Output::NpyFile),
            Some("parquet" | "pq") => Ok(Output::Parquet),
            Some("arrow" | "feather" | "ipc") => Ok(Output::Ipc { stream: false }),
            Some("arrows") => Ok(Output::Ipc { stream: true }),
            Some(other) => Err(format!(
                "--out {}: cannot tell the format from the extension .{other}: expected {FORMATS} \
                 (no extension: a directory)",
                path.display()
            )),
        }
    }

    fn create(self, path: &Path, columns: Vec<OutColumn>) -> Result<Box<dyn Sink>, String> {
        Ok(match self {
            Output::Csv => Box::new(csv::CsvSink::create(path, columns)?),
            Output::NpyDir => Box::new(npy::NpyDirSink::create(path, &columns)?),
            Output::NpyFile => {
                if columns != [OutColumn::Time] {
                    let names: Vec<&str> = columns.iter().map(|c| c.name()).collect();
                    return Err(format!(
                        "--out {}: one .npy array holds one column, and the results have {} \
                         ({}): give a directory (a name without an extension) for one .npy \
                         per column",
                        path.display(),
                        columns.len(),
                        names.join(", ")
                    ));
                }
                Box::new(npy::NpyFileSink::create(path)?)
            }
            #[cfg(feature = "parquet")]
            Output::Parquet => Box::new(columnar::ParquetSink::create(path, columns)?),
            #[cfg(feature = "parquet")]
            Output::Ipc { stream } => Box::new(columnar::IpcSink::create(path, columns, stream)?),
            #[cfg(not(feature = "parquet"))]
            Output::Parquet | Output::Ipc { .. } => return Err(no_columnar(path)),
        })
    }
}

/// `n` items per second as a short figure: `41.2 million`, `930.5 thousand`.
fn rate(n: f64, seconds: f64) -> String {
    if seconds <= 0.0 {
        return "-".into();
    }
    let r = n / seconds;
    if r >= 1e6 {
        format!("{:.1} million", r / 1e6)
    } else if r >= 1e3 {
        format!("{:.1} thousand", r / 1e3)
    } else {
        format!("{r:.0}")
    }
}

/// The process's peak resident memory, where the system tells it (Linux).
fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

fn shapes_text(s: &Shapes) -> String {
    let n = s.len();
    let each: Vec<String> = (s.counts().into_iter())
        .map(|(kind, k)| counted(k as u64, &kind.to_string(), &format!("{kind}s")))
        .collect();
    format!(
        "{} ({})",
        counted(n as u64, "shape", "shapes"),
        each.join(", ")
    )
}

/// Bytes one row of a chunk holds at most, from the types that hold it: its input columns
/// (f32) and CSV line number, the text of a CSV row (up to 32 bytes a number; none for the
/// binary formats), two spheres in stores (eight f32 lanes each), a first-contact record, and
/// the results (time, kind, index, six geometry values).
fn row_bytes(input_columns: usize, text: bool) -> u64 {
    use std::mem::size_of;
    let text = if text { 32 } else { 0 };
    let bytes = input_columns * (size_of::<f32>() + text)
        + size_of::<u64>()
        + 2 * 8 * size_of::<f32>()
        + size_of::<Option<spheresweep::FirstContact>>()
        + size_of::<f32>()
        + size_of::<u8>()
        + size_of::<i64>()
        + 6 * size_of::<f64>();
    bytes as u64
}

/// Refuses a chunk larger than the memory available, before any is read: `--chunk-rows`
/// rows, or as many as the input holds where that is fewer — as its header tells (`.npy`,
/// Parquet), or for CSV as its size has room for (a value takes at least two bytes, a digit
/// and a separator) — so that a small file is not refused for the default chunk's memory.
fn check_memory(args: &Args, plan: &Plan, source: &dyn Source) -> Result<(), String> {
    let columns = plan.layout.columns().len();
    let csv = match &plan.input {
        Input::Csv(p) => Some(p),
        _ => None,
    };
    let room = source.total_rows().or_else(|| {
        let bytes = std::fs::metadata(csv?).ok()?.len();
        Some(bytes / (2 * columns as u64) + 1)
    });
    let rows = (args.chunk_rows as u64).min(room.unwrap_or(u64::MAX));
    crate::memory::check(
        &format!(
            "--chunk-rows {} ({rows} rows at most in this input)",
            args.chunk_rows
        ),
        rows.saturating_mul(row_bytes(columns, csv.is_some())),
    )
}

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    // Ctrl-C and SIGTERM from here on stop the query between two chunks. Installed before
    // the staged output exists: a signal between its creation and the handler would end the
    // process with the temporary file left behind.
    crate::interrupt::install()?;
    let plan = Plan::of(args)?;
    let mut source = plan.input.open(plan.layout, args.chunk_rows)?;
    check_memory(args, &plan, source.as_ref())?;
    let columns = OutColumn::of(plan.layout, args.geometry);
    let column_names: Vec<&str> = columns.iter().map(|c| c.name()).collect();
    let mut sink = plan.output.create(&plan.out_path, columns)?;

    let start = Instant::now();
    let mut totals = stream(args, &plan, source.as_mut(), sink.as_mut())?;
    let written = sink.path().display().to_string();
    let t = Instant::now();
    sink.commit()?;
    totals.writing += t.elapsed();
    totals.total = start.elapsed();
    let mut out = std::io::stdout().lock();
    report(&mut out, args, &plan, &totals)?;
    writeln!(
        out,
        "output      {written}: {}, columns {}",
        plan.output.name(),
        column_names.join(", ")
    )?;
    Ok(())
}

/// What a query reads, computes and writes: every part that can be refused is refused here,
/// before any output exists.
struct Plan {
    options: QueryOptions,
    /// The shapes of `--against`; none for a pairs file.
    shapes: Option<Shapes>,
    layout: Layout,
    input: Input,
    out_path: PathBuf,
    output: Output,
}

impl Plan {
    fn of(args: &Args) -> Result<Self, Box<dyn Error>> {
        // The library's message names its parameter, `t_max`; here it is the option's.
        let options = QueryOptions::new(args.t_max, args.accuracy)
            .map_err(|_| {
                format!(
                    "--t-max must be zero or more (or inf for no end), got {}",
                    args.t_max
                )
            })?
            .with_geometry(args.geometry);
        if !(1..=MAX_CHUNK_ROWS).contains(&args.chunk_rows) {
            return Err(format!(
                "--chunk-rows {} must be between 1 and {MAX_CHUNK_ROWS}",
                args.chunk_rows
            )
            .into());
        }
        let shapes = args.against.as_deref().map(shapes::read).transpose()?;
        let layout = if shapes.is_some() {
            Layout::Spheres
        } else {
            Layout::Pairs
        };
        let input = Input::detect(&args.input)?;
        let (out_path, output) = match &args.out {
            Some(p) => (p.clone(), Output::from_path(p)?),
            None => input.default_output(),
        };
        // The output is none of the inputs, through a link or not; a directory of columns,
        // replaced whole, holds none of them.
        let mut inputs = input.paths();
        inputs.extend(args.against.as_deref());
        crate::output::not_an_input(&out_path, &inputs)?;
        if output != Output::NpyDir && !args.force {
            replaceable(&out_path)?;
        }
        if output == Output::NpyDir {
            crate::output::no_input_inside(&out_path, &inputs)?;
        }
        Ok(Self {
            options,
            shapes,
            layout,
            input,
            out_path,
            output,
        })
    }
}

/// Refuses an existing output file that is not an earlier CSV result of a query (its first
/// line names result columns only, `time` first): a user's data would be lost without a word.
fn replaceable(path: &Path) -> Result<(), String> {
    use std::io::{BufRead, Read};
    let Ok(file) = std::fs::File::open(path) else {
        return Ok(()); // absent (or unreadable: writing it says why)
    };
    let mut first = String::new();
    let _ = std::io::BufReader::new(file.take(4096)).read_line(&mut first);
    let names: Vec<&str> = first.trim_end().split(',').collect();
    let result = names.first() == Some(&"time")
        && names
            .iter()
            .all(|n| OutColumn::ALL.iter().any(|c| c.name() == *n));
    if result {
        return Ok(());
    }
    Err(format!(
        "the output {} exists and is not a query's CSV result: give --force to replace it, or \
         another --out",
        path.display()
    ))
}

/// What a query did: counts, and the time spent in each stage.
#[derive(Debug, Default)]
struct Totals {
    chunks: u64,
    rows: u64,
    contacts: u64,
    reading: Duration,
    validating: Duration,
    querying: Duration,
    writing: Duration,
    /// From the first read to the output in place.
    total: Duration,
}

/// Reads, queries and writes the input a chunk at a time until it is exhausted, checking for
/// an interruption before each chunk.
fn stream(
    args: &Args,
    plan: &Plan,
    source: &mut dyn Source,
    sink: &mut dyn Sink,
) -> Result<Totals, Box<dyn Error>> {
    let layout = plan.layout;
    let mut totals = Totals::default();
    let mut chunk = Chunk::new(layout.columns().len());
    let mut results = Results::default();
    let label = plan.input.label();
    loop {
        if crate::interrupt::requested() {
            return Err(crate::interrupt::Interrupted(format!(
                "after {} chunks ({} rows) of {label}; nothing written, {} untouched",
                totals.chunks,
                totals.rows,
                plan.out_path.display()
            ))
            .into());
        }
        let t = Instant::now();
        let more = source.next(args.chunk_rows, &mut chunk)?;
        totals.reading += t.elapsed();
        if !more {
            break;
        }
        let tally = match &plan.shapes {
            None => compute::pairs(&chunk, layout.columns(), plan.options, &mut results),
            Some(s) => compute::statics(&chunk, layout.columns(), s, plan.options, &mut results),
        }
        .map_err(|e| format!("{label}: {e}"))?;
        totals.validating += tally.validating;
        totals.querying += tally.querying;
        let t = Instant::now();
        sink.write(&results)?;
        totals.writing += t.elapsed();
        totals.chunks += 1;
        totals.rows += chunk.rows() as u64;
        totals.contacts += tally.contacts as u64;
    }
    if let Some(expected) = source.total_rows()
        && expected != totals.rows
    {
        return Err(format!(
            "{label}: read {} rows of the {expected} the file declares",
            totals.rows
        )
        .into());
    }
    Ok(totals)
}

/// Prints what was queried, the contacts found, the time and throughput, and the peak memory.
fn report(
    out: &mut impl Write,
    args: &Args,
    plan: &Plan,
    totals: &Totals,
) -> Result<(), Box<dyn Error>> {
    let Totals {
        chunks,
        rows,
        contacts,
        ..
    } = *totals;
    let (shapes, label) = (&plan.shapes, plan.input.label());
    let per_row = shapes.as_ref().map_or(1, Shapes::len) as f64;
    let tests = rows as f64 * per_row;
    match shapes {
        None => writeln!(
            out,
            "input       {label}: {}, {rows} pairs",
            plan.input.format_name()
        )?,
        Some(s) => writeln!(
            out,
            "input       {label}: {}, {rows} spheres against {}",
            plan.input.format_name(),
            shapes_text(s)
        )?,
    }
    writeln!(
        out,
        "chunks      {chunks} of at most {} rows",
        args.chunk_rows
    )?;
    writeln!(
        out,
        "query       {} mode, t_max {}, {}",
        args.accuracy,
        args.t_max,
        if args.geometry {
            "with geometry"
        } else {
            "times only"
        }
    )?;
    let share = if rows > 0 {
        100.0 * contacts as f64 / rows as f64
    } else {
        0.0
    };
    writeln!(
        out,
        "contacts    {contacts} of {rows} {} ({share:.2}%)",
        plan.layout.rows_noun()
    )?;
    let unit = if shapes.is_some() {
        "sphere-shape pairs/s"
    } else {
        "pairs/s"
    };
    let secs = |d: Duration| d.as_secs_f64();
    let t = totals;
    writeln!(
        out,
        "time        {:.3} s: reading {:.3}, validating {:.3}, querying {:.3}, writing {:.3}",
        secs(t.total),
        secs(t.reading),
        secs(t.validating),
        secs(t.querying),
        secs(t.writing)
    )?;
    writeln!(
        out,
        "throughput  {} {unit} excluding I/O (validating and querying), {} including it; {} \
         in the queries alone",
        rate(tests, secs(t.validating + t.querying)),
        rate(tests, secs(t.total)),
        rate(tests, secs(t.querying)),
    )?;
    if let Some(mib) = peak_memory_mib() {
        writeln!(out, "peak memory {mib:.0} MiB")?;
    }
    Ok(())
}
