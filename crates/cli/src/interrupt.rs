//! Ctrl-C and SIGTERM: the long subcommands install [`install`] and poll [`requested`] where
//! they already poll (the simulation every 4096 events, the query per chunk), stop at a
//! consistent point, and return [`Interrupted`] saying what was done; `main` prints it and
//! exits with 130, as a shell does for a command stopped by SIGINT. Their staged outputs are
//! dropped (temporary files removed) and earlier files are never touched.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set by the signal handler; read by the work loops.
static STOP: AtomicBool = AtomicBool::new(false);

/// Exit code of an interrupted command (128 + SIGINT).
pub const EXIT_CODE: u8 = 130;

/// Catches SIGINT and SIGTERM (and SIGHUP) from now on: they set a flag instead of killing
/// the process. Call it only in a subcommand that polls [`requested`]; the handler is
/// installed once per process, later calls return the first call's outcome.
pub fn install() -> Result<(), String> {
    static INSTALLED: OnceLock<Result<(), String>> = OnceLock::new();
    INSTALLED
        .get_or_init(|| {
            ctrlc::set_handler(|| STOP.store(true, Ordering::SeqCst))
                .map_err(|e| format!("cannot catch Ctrl-C and SIGTERM: {e}"))
        })
        .clone()
}

/// Whether an interruption has been asked for.
pub fn requested() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// The error a subcommand returns when interrupted: what it had done, and how to go on.
#[derive(Debug)]
pub struct Interrupted(pub String);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "interrupted {}", self.0)
    }
}

impl std::error::Error for Interrupted {}

/// Runs `work`, which cannot poll and writes nothing until it returns (the accuracy study,
/// the benchmarks): if an interruption is asked for meanwhile, a watcher prints
/// `interrupted {what}` and ends the process with [`EXIT_CODE`] at once, so no output of
/// `work` exists yet and earlier files are untouched. Once `work` has returned, a signal is
/// left to the caller's next [`requested`] check.
pub fn exit_if_requested_during<T>(what: &str, work: impl FnOnce() -> T) -> Result<T, String> {
    install()?;
    let done = AtomicBool::new(false);
    let value = std::thread::scope(|scope| {
        scope.spawn(|| {
            while !done.load(Ordering::SeqCst) {
                if requested() {
                    eprintln!("interrupted {what}");
                    std::process::exit(i32::from(EXIT_CODE));
                }
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
        });
        let value = work();
        done.store(true, Ordering::SeqCst);
        value
    });
    Ok(value)
}
