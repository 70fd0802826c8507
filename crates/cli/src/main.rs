//! The `spheresweep` command-line tool: one subcommand a file.

mod accuracy;
mod atomic;
mod bench;
mod checkout;
mod demo;
mod interrupt;
mod memory;
mod number;
mod output;
mod picture;
mod progress;
mod query;
mod render;
mod run;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Continuous collision detection of moving spheres.
#[derive(Debug, Parser)]
#[command(name = "spheresweep", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// The whole mission on a built-in scene in seconds: 4000 glass and glue beads in a vessel
    /// with a floor and pillars, simulated event by event (progress bar), a summary, and a
    /// picture in spheresweep-demo/ (SVG and PNG). `--table`: the first-contact table of the
    /// nine-sphere query scene instead.
    Demo(demo::Args),
    /// Throughput of every kernel and mode, the broad phase and the whole query, each against
    /// parry3d in the same run, ours on one and two threads (`--quick` for a run under a
    /// minute, `--json`).
    Bench(bench::Args),
    /// Measure every accuracy mode (and parry3d) against an exact oracle on hard cases, with
    /// throughput from the same run; write the report and its SVG plot to
    /// spheresweep-accuracy/ (`--out docs/accuracy.md --force` regenerates the committed one).
    Accuracy(accuracy::Args),
    /// Simulate a scene file (TOML or JSON; docs/scene-format.md) to its end time: a progress
    /// bar, then a summary; trajectory.xyz, events.csv and summary.json in the output directory.
    Run(run::Args),
    /// Time of impact for files of sphere pairs or of spheres against shapes (CSV, NumPy .npy,
    /// Parquet), written to the same formats.
    Query(query::Args),
    /// Pictures of a scene file or of recorded snapshots (extended XYZ).
    Render(render::Args),
}

/// Parses the command line and runs it; errors go to stderr with a non-zero exit code.
fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(args) => demo::run(&args),
        Command::Accuracy(args) => accuracy::run(&args),
        // The benchmarks cannot stop half-way; they write no file, so an interruption ends
        // them at once.
        Command::Bench(args) => interrupt::exit_if_requested_during(
            "the benchmark (it writes no file; the figures printed so far stand)",
            || {
                eprintln!("bench: measuring (Ctrl-C or SIGTERM ends it at once)");
                bench::run(&args)
            },
        )
        .map_err(Into::into)
        .and_then(|result| result),
        Command::Run(args) => run::run(&args),
        Command::Query(args) => query::run(&args),
        Command::Render(args) => render::run(&args),
    };
    if result.is_err() {
        atomic::remove_made_dirs();
    }
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.is::<interrupt::Interrupted>() => {
            eprintln!("{e}");
            ExitCode::from(interrupt::EXIT_CODE)
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// How many static shapes of each kind, as the summaries print it: `1 plane(s), 3
/// cylinder(s), 1 container(s)`.
fn statics_text<P>(statics: &spheresweep::Statics<P>) -> String {
    let each: Vec<String> = (statics.counts().into_iter())
        .map(|(kind, n)| format!("{n} {kind}(s)"))
        .collect();
    each.join(", ")
}
