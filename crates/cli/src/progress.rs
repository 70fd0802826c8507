//! Progress bars on stderr, for every subcommand that shows one (`run`, `demo`, `accuracy`,
//! `bench`): [`bar`] makes one, hidden when asked (`--quiet`, `--json`) or when stderr is not a
//! terminal; [`SimProgress`] is the bar of the subcommands that simulate, following simulated
//! time, and where stderr is not a terminal (a log file, a batch job) a plain line instead,
//! at most one a given interval.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use spheresweep::sim::Stats;
use std::cell::Cell;
use std::io::IsTerminal;
use std::time::{Duration, Instant};

pub use indicatif::style::TemplateError;

/// A bar of `len` steps drawn with the indicatif `template`; hidden when `hidden` is true or
/// stderr is not a terminal.
pub fn bar(len: u64, template: &str, hidden: bool) -> Result<ProgressBar, TemplateError> {
    let bar = ProgressBar::new(len);
    if hidden || !std::io::stderr().is_terminal() {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    bar.set_style(ProgressStyle::with_template(template)?);
    Ok(bar)
}

/// A bar from time 0 to `t_end`.
pub struct SimProgress {
    bar: ProgressBar,
    t_end: f64,
    /// Decimals of the time shown.
    decimals: usize,
    /// Whether the message also shows `t_end`.
    show_end: bool,
    /// Plain lines where stderr is not a terminal (and progress is not hidden).
    lines: Option<Lines>,
}

/// When the plain progress lines started and when the next is due.
struct Lines {
    every: Duration,
    start: Instant,
    next: Cell<Instant>,
}

impl SimProgress {
    /// A bar, or with stderr not a terminal a line every `every` (none if `quiet`).
    pub fn new(
        t_end: f64,
        quiet: bool,
        decimals: usize,
        show_end: bool,
        every: Duration,
    ) -> Result<Self, TemplateError> {
        let bar = bar(
            1000,
            "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% {msg}",
            quiet,
        )?;
        let start = Instant::now();
        let lines = (!quiet && !std::io::stderr().is_terminal()).then(|| Lines {
            every,
            start,
            next: Cell::new(start + every),
        });
        Ok(Self {
            bar,
            t_end,
            decimals,
            show_end,
            lines,
        })
    }

    /// Shows time `t` and the collisions so far; always `true`, so that it can be the
    /// `keep_going` of `Simulation::advance_with`.
    pub fn show(&self, t: f64, s: &Stats) -> bool {
        self.bar.set_position((t / self.t_end * 1000.0) as u64);
        let end = if self.show_end {
            format!(" of {}", self.t_end)
        } else {
            String::new()
        };
        let message = format!(
            "t = {t:.prec$}{end}, {} collisions",
            s.pair_collisions + s.wall_collisions,
            prec = self.decimals
        );
        if let Some(lines) = &self.lines {
            let now = Instant::now();
            if now >= lines.next.get() {
                lines.next.set(now + lines.every);
                eprintln!(
                    "progress: {message} ({:.1} % of t = {}), {:.0} s",
                    100.0 * t / self.t_end,
                    self.t_end,
                    (now - lines.start).as_secs_f64()
                );
            }
        }
        self.bar.set_message(message);
        true
    }

    /// Prints a line on stderr above the bar (which is drawn again below it).
    pub fn say(&self, line: &str) {
        self.bar.suspend(|| eprintln!("{line}"));
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
