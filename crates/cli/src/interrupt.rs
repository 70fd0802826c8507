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
