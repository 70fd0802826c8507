//! `spheresweep accuracy`: runs the accuracy study and writes the report and its plot.

use std::error::Error;
use std::path::PathBuf;

use spheresweep_study::{self as study, Path};

/// Options of `spheresweep accuracy`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Pairs per hard-case family (1 to 1 000 000; the study holds about 70 bytes per pair
    /// and family in memory).
    #[arg(long, default_value_t = 4000)]
    cases: usize,
    /// Seed of the case generator (any integer from 0 to 2⁶⁴ − 1).
    #[arg(long, default_value_t = 2026)]
    seed: u64,
    /// Where to write the Markdown report (default: spheresweep-accuracy/accuracy.md in the
    /// current directory).
    #[arg(long, default_value = "spheresweep-accuracy/accuracy.md")]
    out: PathBuf,
    /// Where to write the SVG plot (linked from the report by file name); by default beside
    /// the report, with the extension `.svg`.
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Replace the report or plot even if a git checkout tracks it (as `--out
    /// docs/accuracy.md` at the root of this project's checkout does); without it, such a
    /// file is refused before the study runs.
    #[arg(long)]
    force: bool,
}

/// The most pairs per family `--cases` accepts.
const MAX_CASES: usize = 1_000_000;

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    if !(1..=MAX_CASES).contains(&args.cases) {
        return Err(format!(
            "--cases must be between 1 and {MAX_CASES}, got {}",
            args.cases
        )
        .into());
    }
    let svg = args
        .svg
        .clone()
        .unwrap_or_else(|| args.out.with_extension("svg"));
    // The study cannot stop half-way: Ctrl-C or SIGTERM ends the process at once, before
    // anything is written. The handler is in place before the outputs are probed with a
    // temporary file, so a signal never leaves the probe behind.
    crate::interrupt::install()?;
    // Check both outputs before the study runs: a bad path fails now, not after the work, and
    // no existing file is touched until its replacement is complete.
    crate::output::distinct(&args.out, &svg)?;
    crate::output::check_writable(&args.out)?;
    crate::output::check_writable(&svg)?;
    crate::checkout::refuse_tracked(&args.out, "--out", args.force)?;
    crate::checkout::refuse_tracked(&svg, "--svg", args.force)?;
    let bar = crate::progress::bar(
        (study::Family::ALL.len() + study::SWEPT.len()) as u64 + 1,
        "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} {msg}",
        false,
    )?;
    bar.set_message("families against the exact oracle, then throughput");
    eprintln!(
        "accuracy: the study, {} pairs per family, then throughput",
        args.cases
    );
    let report = crate::interrupt::exit_if_requested_during(
        &format!(
            "during the study: nothing written, {} and {} untouched",
            args.out.display(),
            svg.display()
        ),
        || {
            study::run(args.cases, args.seed, |done, _| {
                bar.set_position(done as u64)
            })
        },
    )?;
    bar.finish_and_clear();
    let svg_name = svg
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| format!("--svg {} has no file name", svg.display()))?;
    // Render both first, then replace the files: a failure leaves the old ones whole.
    let (markdown, picture) = (report.markdown(svg_name), report.svg()?);
    crate::atomic::write_atomic(&svg, picture.as_bytes())?;
    crate::atomic::write_atomic(&args.out, markdown.as_bytes())?;
    println!(
        "{:<9} {:>12} {:>26}",
        "path", "M pairs/s", "worst p99 geometric error"
    );
    for path in Path::ALL {
        let rate = report
            .throughput
            .iter()
            .find(|(p, _)| *p == path)
            .map_or(f64::NAN, |(_, r)| r / 1e6);
        println!(
            "{:<9} {:>12.1} {:>26.2}",
            path.name(),
            rate,
            report.worst_gap(path)
        );
    }
    println!("wrote {} and {}", args.out.display(), svg.display());
    Ok(())
}
