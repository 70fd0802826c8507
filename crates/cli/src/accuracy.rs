//! `spheresweep accuracy`: runs the accuracy study and writes the report and its plot.

use std::error::Error;
use std::io::Write;
use std::path::PathBuf;

use indicatif::{ProgressBar, ProgressStyle};
use spheresweep_study::{self as study, Path};

/// Options of `spheresweep accuracy`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Pairs per hard-case family.
    #[arg(long, default_value_t = 4000)]
    cases: usize,
    /// Seed of the case generator.
    #[arg(long, default_value_t = 2026)]
    seed: u64,
    /// Where to write the Markdown report.
    #[arg(long, default_value = "docs/accuracy.md")]
    out: PathBuf,
    /// Where to write the SVG plot (linked from the report by file name).
    #[arg(long, default_value = "docs/accuracy.svg")]
    svg: PathBuf,
}

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    if args.cases == 0 {
        return Err("--cases must be at least 1".into());
    }
    // Open both outputs before the study runs: a bad path fails now, not after the work.
    let open = |path: &PathBuf| -> Result<std::fs::File, String> {
        let fail = |e: std::io::Error| format!("cannot write {}: {e}", path.display());
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(fail)?;
        }
        std::fs::File::create(path).map_err(fail)
    };
    let (mut md_file, mut svg_file) = (open(&args.out)?, open(&args.svg)?);
    let bar = ProgressBar::new((study::Family::ALL.len() + study::SWEPT.len()) as u64 + 1);
    bar.set_style(ProgressStyle::with_template(
        "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} {msg}",
    )?);
    bar.set_message("families against the exact oracle, then throughput");
    let report = study::run(args.cases, args.seed, |done, _| {
        bar.set_position(done as u64)
    });
    bar.finish_and_clear();
    let svg_name = args
        .svg
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| format!("--svg {} has no file name", args.svg.display()))?;
    let write = |file: &mut std::fs::File, path: &PathBuf, text: &str| {
        file.write_all(text.as_bytes())
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    write(&mut md_file, &args.out, &report.markdown(svg_name))?;
    write(&mut svg_file, &args.svg, &report.svg()?)?;
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
    println!("wrote {} and {}", args.out.display(), args.svg.display());
    Ok(())
}
