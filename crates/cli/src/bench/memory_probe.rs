//! The memory a fresh `SceneQuery` holds after its first call on the uniform gas, per sphere.
//! The library does not report it (no `SceneQuery::heap_bytes` yet), so it is read from Linux's
//! `/proc/self/status`: resident memory before and after the call, and the peak during it (the
//! peak reset through `/proc/self/clear_refs`). It runs in a fresh process (`spheresweep bench
//! --memory-probe N`), where no memory freed by earlier measurements can be reused unseen, with
//! glibc's mmap threshold fixed at 64 KiB (`MALLOC_MMAP_THRESHOLD_`): every large buffer is
//! mapped for itself and unmapped when freed, so none left by building the scene is reused.
//! Resident memory counts touched pages only: capacity reserved and never written is not in it.

use std::fmt;
use std::process::{Command, Stdio};

use spheresweep::query::SceneQuery;
use spheresweep::scene::Scene;
use spheresweep::{Accuracy, QueryOptions};
use spheresweep_bench::scenes;

/// Bytes per sphere a query held after its first call, and its peak growth during the call.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QueryMemory {
    /// Resident growth from before the call to after it, the answers' vector excluded.
    pub held: f64,
    /// Peak resident growth during the call (answers included), if the peak could be reset.
    pub peak: Option<f64>,
}

impl fmt::Display for QueryMemory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "query holds {:.0} B/sphere", self.held)?;
        match self.peak {
            Some(peak) => write!(f, " (peak +{peak:.0})"),
            None => Ok(()),
        }
    }
}

/// Runs this binary as `bench --memory-probe N --memory-probe-phi PHI` and reads its answer.
pub fn measure(n: usize, phi: f64) -> Result<QueryMemory, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let out = Command::new(exe)
        .args(["bench", "--memory-probe", &n.to_string()])
        .args(["--memory-probe-phi", &phi.to_string()])
        .env("MALLOC_MMAP_THRESHOLD_", "65536")
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .output()
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        return Err(format!("the probe ended with {}", out.status));
    }
    let mut fields = text.split_whitespace().map(str::parse::<f64>);
    let mut next = || fields.next().and_then(Result::ok);
    let (Some(held), Some(peak)) = (next(), next()) else {
        return Err(format!("the probe answered {text:?}"));
    };
    Ok(QueryMemory {
        held,
        peak: (peak >= 0.0).then_some(peak),
    })
}

/// The probe itself (in the child): one query of `n` spheres at `phi`, one thread, and its
/// figures printed as `held peak` in bytes per sphere (`-1` for a peak not measured).
pub fn run(n: usize, phi: f64) -> Result<(), Box<dyn std::error::Error>> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let scene = Scene {
        spheres: scenes::uniform_gas(n, phi, 7),
        ..Scene::default()
    };
    let options = QueryOptions::new(scenes::window(0.5), Accuracy::Stable)?;
    let (mut query, mut answers) = (SceneQuery::new(), Vec::new());
    pool.install(|| ());
    let peak_reset = std::fs::write("/proc/self/clear_refs", "5").is_ok();
    let before = status_bytes("VmRSS:").ok_or("no VmRSS in /proc/self/status")?;
    pool.install(|| query.first_contacts_into(&scene, options, &mut answers));
    let after = status_bytes("VmRSS:").ok_or("no VmRSS in /proc/self/status")?;
    let peak = status_bytes("VmHWM:").filter(|_| peak_reset);
    let answer_bytes = answers.capacity() * element_size(&answers);
    let per_sphere = |bytes: u64| bytes as f64 / n.max(1) as f64;
    let held = per_sphere(
        after
            .saturating_sub(before)
            .saturating_sub(answer_bytes as u64),
    );
    let peak = peak.map_or(-1.0, |p| per_sphere(p.saturating_sub(before)));
    println!("{held} {peak}");
    Ok(())
}

/// The size of a vector's element, whatever the query's answer type is.
fn element_size<T>(_: &[T]) -> usize {
    std::mem::size_of::<T>()
}

/// A `kB` figure of `/proc/self/status` (e.g. `VmRSS:`), in bytes.
fn status_bytes(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
