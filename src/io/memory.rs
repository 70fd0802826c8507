//! The memory this process may still take, read before a large allocation so that an input
//! too large is refused with a message instead of an aborted process.
//!
//! The memory available is `SPHERESWEEP_MAX_MEMORY` when set (bytes, suffixes K, M, G, T for
//! powers of 1024), else the smallest of what the machine has free (`MemAvailable`), what the
//! process's address-space limit (`ulimit -v`, RLIMIT_AS) leaves, and what its cgroup's memory
//! limit leaves (v2 `memory.max`, v1 `memory.limit_in_bytes`, at its cgroup and every ancestor).
//! Linux's /proc and /sys are read; where none can be read, nothing is refused. The CLI and the
//! Python binding both refuse by [`check`].
//!
//! ```
//! use spheresweep::io::memory::{check, human, parse_bytes};
//! assert_eq!(parse_bytes("512M"), Some(512 << 20));
//! assert_eq!(human(3 << 29), "1.50 GiB (1610612736 B)");
//! assert!(check("a small buffer", 1024).is_ok());
//! ```

use std::path::{Path, PathBuf};

/// Environment variable that sets the memory available, in bytes (suffixes K, M, G, T for
/// powers of 1024), instead of the system's limits: for tests, and for machines shared with
/// other work.
pub const MAX_MEMORY_VAR: &str = "SPHERESWEEP_MAX_MEMORY";

/// Bytes a size such as `512M`, `2G` or `1000000` stands for.
pub fn parse_bytes(text: &str) -> Option<u64> {
    let text = text.trim();
    let (digits, unit) = match text.char_indices().last()? {
        (i, c) if c.is_ascii_alphabetic() => (&text[..i], c.to_ascii_uppercase()),
        _ => (text, 'B'),
    };
    let shift = match unit {
        'B' => 0,
        'K' => 10,
        'M' => 20,
        'G' => 30,
        'T' => 40,
        _ => return None,
    };
    digits.trim().parse::<u64>().ok()?.checked_mul(1 << shift)
}

/// Why [`check`] refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MemoryError {
    /// `SPHERESWEEP_MAX_MEMORY` is set to something that is not a size.
    #[error("{0}")]
    Setting(String),
    /// What was asked for exceeds the memory available: the message gives the estimate, the
    /// figure and where it comes from.
    #[error("{0}")]
    Refused(String),
}

/// Memory this process may still take, and the limit that says so.
#[derive(Debug, Clone, PartialEq)]
pub struct Limit {
    /// Bytes still available.
    pub bytes: u64,
    /// Where the figure comes from (the variable, /proc/meminfo, the address-space limit or a
    /// cgroup file), for the message.
    pub source: String,
}

/// The memory available: `SPHERESWEEP_MAX_MEMORY` when set, else the smallest of the
/// system's limits; `None` when none can be read (then nothing is refused).
pub fn available() -> Result<Option<Limit>, MemoryError> {
    if let Ok(text) = std::env::var(MAX_MEMORY_VAR) {
        return parse_bytes(&text)
            .map(|bytes| {
                Some(Limit {
                    bytes,
                    source: MAX_MEMORY_VAR.into(),
                })
            })
            .ok_or_else(|| {
                MemoryError::Setting(format!(
                    "{MAX_MEMORY_VAR}={text:?} is not a size in bytes (e.g. 512M, 8G)"
                ))
            });
    }
    Ok([mem_available(), address_space(), cgroup()]
        .into_iter()
        .flatten()
        .min_by_key(|l| l.bytes))
}

/// `MemAvailable` of /proc/meminfo.
fn mem_available() -> Option<Limit> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kb = kib_field(&meminfo, "MemAvailable:")?;
    Some(Limit {
        bytes: kb.saturating_mul(1024),
        source: "MemAvailable in /proc/meminfo".into(),
    })
}

/// A `NAME:   123 kB` field of /proc/meminfo or /proc/self/status, in KiB.
fn kib_field(text: &str, name: &str) -> Option<u64> {
    let value = text.lines().find_map(|l| l.strip_prefix(name))?;
    value.trim().strip_suffix("kB")?.trim().parse().ok()
}

/// The soft limit of `Max address space` in /proc/self/limits; `None` when unlimited.
fn parse_address_limit(limits: &str) -> Option<u64> {
    let line = limits
        .lines()
        .find_map(|l| l.strip_prefix("Max address space"))?;
    line.split_whitespace().next()?.parse().ok()
}

/// What the address-space limit (RLIMIT_AS, `ulimit -v`) leaves: the limit less the
/// process's mapped size (`VmSize`).
fn address_space() -> Option<Limit> {
    let limit = parse_address_limit(&std::fs::read_to_string("/proc/self/limits").ok()?)?;
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let used = kib_field(&status, "VmSize:")
        .unwrap_or(0)
        .saturating_mul(1024);
    Some(Limit {
        bytes: limit.saturating_sub(used),
        source: format!(
            "the address-space limit, ulimit -v, of {} less {} mapped",
            short(limit),
            short(used)
        ),
    })
}

/// The process's cgroup of the memory controller in /proc/self/cgroup: `(true, path)` for
/// cgroup v2 (`0::PATH`), `(false, path)` for v1 (`N:…memory…:PATH`).
fn parse_cgroups(text: &str) -> Vec<(bool, String)> {
    text.lines()
        .filter_map(|line| {
            let mut parts = line.splitn(3, ':');
            let (id, controllers, path) = (parts.next()?, parts.next()?, parts.next()?);
            if id == "0" && controllers.is_empty() {
                Some((true, path.to_string()))
            } else if controllers.split(',').any(|c| c == "memory") {
                Some((false, path.to_string()))
            } else {
                None
            }
        })
        .collect()
}

/// A limit in a cgroup file: a number of bytes, or none (`max`, or v1's unlimited, which is
/// close to 2⁶³).
fn limit_value(text: &str) -> Option<u64> {
    text.trim().parse::<u64>().ok().filter(|&b| b < 1 << 60)
}

/// What the cgroup memory limits leave: at the process's cgroup and each ancestor, the limit
/// less the usage; the smallest.
fn cgroup() -> Option<Limit> {
    let text = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    let mut best: Option<Limit> = None;
    for (v2, path) in parse_cgroups(&text) {
        let (roots, limit, usage): (&[&str], _, _) = if v2 {
            (
                &["/sys/fs/cgroup", "/sys/fs/cgroup/unified"],
                "memory.max",
                "memory.current",
            )
        } else {
            (
                &["/sys/fs/cgroup/memory"],
                "memory.limit_in_bytes",
                "memory.usage_in_bytes",
            )
        };
        for root in roots {
            let mut dir = PathBuf::from(root).join(path.trim_start_matches('/'));
            loop {
                if let Some(found) = cgroup_level(&dir, limit, usage)
                    && best.as_ref().is_none_or(|b| found.bytes < b.bytes)
                {
                    best = Some(found);
                }
                if dir == Path::new(root) || !dir.pop() {
                    break;
                }
            }
        }
    }
    best
}

/// The limit of one cgroup directory less its usage.
fn cgroup_level(dir: &Path, limit: &str, usage: &str) -> Option<Limit> {
    let file = dir.join(limit);
    let max = limit_value(&std::fs::read_to_string(&file).ok()?)?;
    let used = std::fs::read_to_string(dir.join(usage))
        .ok()
        .and_then(|t| t.trim().parse::<u64>().ok())
        .unwrap_or(0);
    Some(Limit {
        bytes: max.saturating_sub(used),
        source: format!(
            "the cgroup memory limit, {}, of {} less {} in use",
            file.display(),
            short(max),
            short(used)
        ),
    })
}

/// Refuses `bytes` (what `what` needs, estimated) above the memory available, before anything
/// is allocated: the message names `what`, the estimate, the figure and its source.
pub fn check(what: &str, bytes: u64) -> Result<(), MemoryError> {
    match available()? {
        Some(limit) if bytes > limit.bytes => Err(MemoryError::Refused(format!(
            "{what} needs about {} but {} is available ({}): refused before allocating",
            human(bytes),
            human(limit.bytes),
            limit.source
        ))),
        _ => Ok(()),
    }
}

/// Bytes in GiB, MiB or KiB, and exactly (below a KiB, only exactly).
pub fn human(bytes: u64) -> String {
    if bytes < 1 << 10 {
        format!("{bytes} B")
    } else {
        format!("{} ({bytes} B)", short(bytes))
    }
}

/// Bytes in GiB, MiB or KiB.
fn short(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= (1u64 << 30) as f64 {
        format!("{:.2} GiB", b / (1u64 << 30) as f64)
    } else if b >= (1u64 << 20) as f64 {
        format!("{:.1} MiB", b / (1u64 << 20) as f64)
    } else {
        format!("{:.1} KiB", b / 1024.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_suffixes() {
        assert_eq!(parse_bytes("1000"), Some(1000));
        assert_eq!(parse_bytes("512M"), Some(512 << 20));
        assert_eq!(parse_bytes("2g"), Some(2 << 30));
        assert_eq!(parse_bytes("x"), None);
        assert_eq!(parse_bytes("5Q"), None);
        assert_eq!(parse_bytes("99999999999T"), None);
    }

    #[test]
    fn the_address_space_limit_is_read_from_proc_limits() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units     \n\
                      Max stack size            8388608              unlimited            bytes     \n\
                      Max address space         2147483648           unlimited            bytes     \n";
        assert_eq!(parse_address_limit(limits), Some(2 << 30));
        let unlimited = limits.replace("2147483648", "unlimited");
        assert_eq!(parse_address_limit(&unlimited), None);
        assert_eq!(
            kib_field("VmPeak:\t 10 kB\nVmSize:\t  2048 kB\n", "VmSize:"),
            Some(2048)
        );
    }

    #[test]
    fn the_memory_cgroup_is_found_in_v1_and_v2() {
        let hybrid = "9:name=systemd:/\n4:memory:/jobs/42\n3:cpu,cpuacct:/\n0::/user.slice\n";
        assert_eq!(
            parse_cgroups(hybrid),
            [(false, "/jobs/42".into()), (true, "/user.slice".into())]
        );
        assert_eq!(parse_cgroups("4:cpu,memory:/a\n"), [(false, "/a".into())]);
        assert_eq!(limit_value("max\n"), None);
        assert_eq!(limit_value("9223372036854771712\n"), None);
        assert_eq!(limit_value("4294967296\n"), Some(4 << 30));
    }

    #[test]
    fn a_cgroup_level_leaves_its_limit_less_its_usage() {
        let dir = std::env::temp_dir().join(format!("spheresweep-cgroup-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("memory.max"), "1073741824\n").unwrap();
        std::fs::write(dir.join("memory.current"), "268435456\n").unwrap();
        let found = cgroup_level(&dir, "memory.max", "memory.current").unwrap();
        assert_eq!(found.bytes, 3 << 28);
        assert!(
            found.source.contains("memory.max") && found.source.contains("1.00 GiB less 256.0 MiB"),
            "{}",
            found.source
        );
        std::fs::write(dir.join("memory.max"), "max\n").unwrap();
        assert_eq!(cgroup_level(&dir, "memory.max", "memory.current"), None);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
