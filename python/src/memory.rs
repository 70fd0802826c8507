//! Memory: a `MemoryError` instead of an aborted interpreter. Two means, used by every entry
//! point whose allocations grow with its input:
//!
//! - an **up-front estimate** against the memory available ([`check`]), for what the library
//!   allocates inside one call (a sphere store, a scene query, a simulation);
//! - **fallible allocation** ([`filled`], [`with_capacity`]) for the buffers the binding
//!   allocates itself (result columns, copies).
//!
//! The memory available is the least of: `SPHERESWEEP_MAX_MEMORY` (bytes, suffixes K, M, G, T
//! for powers of 1024; the variable the CLI reads too), `MemAvailable` of /proc/meminfo, the
//! address-space limit (`ulimit -v`) less the process's address space now, and the cgroup's
//! `memory.max` less its `memory.current`. Where none is known nothing is refused.

use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;

/// The environment variable that caps the memory available (as in the CLI).
pub(crate) const MAX_MEMORY_VAR: &str = "SPHERESWEEP_MAX_MEMORY";

/// Bytes a size such as `512M`, `2G` or `1000000` stands for.
fn parse_bytes(text: &str) -> Option<u64> {
    let text = text.trim();
    let (digits, shift) = match text.chars().last()?.to_ascii_uppercase() {
        'K' => (&text[..text.len() - 1], 10),
        'M' => (&text[..text.len() - 1], 20),
        'G' => (&text[..text.len() - 1], 30),
        'T' => (&text[..text.len() - 1], 40),
        c if c.is_ascii_digit() => (text, 0),
        _ => return None,
    };
    digits.trim().parse::<u64>().ok()?.checked_mul(1 << shift)
}

/// The number after `key` on its line of `text` (e.g. `VmSize:` in /proc/self/status).
fn field(text: &str, key: &str) -> Option<u64> {
    text.lines()
        .find_map(|l| l.strip_prefix(key))?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// `MemAvailable`, in bytes.
fn mem_available() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    Some(field(&meminfo, "MemAvailable:")?.saturating_mul(1024))
}

/// The address-space limit (`ulimit -v`) less the address space in use, in bytes.
fn address_space_left() -> Option<u64> {
    let limits = std::fs::read_to_string("/proc/self/limits").ok()?;
    let limit: u64 = field(&limits, "Max address space")?;
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let used = field(&status, "VmSize:")?.saturating_mul(1024);
    Some(limit.saturating_sub(used))
}

/// The cgroup (v2) limit less its use, in bytes.
fn cgroup_left() -> Option<u64> {
    let cgroup = std::fs::read_to_string("/proc/self/cgroup").ok()?;
    let path = cgroup.lines().find_map(|l| l.strip_prefix("0::"))?;
    let dir = std::path::Path::new("/sys/fs/cgroup").join(path.trim_start_matches('/'));
    let read = |name: &str| -> Option<u64> {
        std::fs::read_to_string(dir.join(name))
            .ok()?
            .trim()
            .parse()
            .ok()
    };
    Some(read("memory.max")?.saturating_sub(read("memory.current")?))
}

/// The memory available and where that figure comes from (`None`: unknown).
pub(crate) fn available() -> PyResult<Option<(u64, &'static str)>> {
    let mut best: Option<(u64, &'static str)> = None;
    let mut offer = |bytes: Option<u64>, source: &'static str| {
        if let Some(b) = bytes
            && best.is_none_or(|(least, _)| b < least)
        {
            best = Some((b, source));
        }
    };
    if let Ok(text) = std::env::var(MAX_MEMORY_VAR) {
        let bytes = parse_bytes(&text).ok_or_else(|| {
            PyValueError::new_err(format!(
                "{MAX_MEMORY_VAR}={text:?} is not a size in bytes (e.g. 512M, 8G)"
            ))
        })?;
        offer(Some(bytes), MAX_MEMORY_VAR);
    }
    offer(mem_available(), "MemAvailable in /proc/meminfo");
    offer(
        address_space_left(),
        "the address-space limit (ulimit -v) less what is in use",
    );
    offer(cgroup_left(), "the cgroup's memory.max less memory.current");
    Ok(best)
}

/// Bytes in MiB or GiB, with the exact count.
pub(crate) fn human(bytes: u64) -> String {
    let b = bytes as f64;
    if bytes >= 1 << 30 {
        format!("{:.2} GiB ({bytes} B)", b / (1u64 << 30) as f64)
    } else {
        format!("{:.1} MiB ({bytes} B)", b / (1u64 << 20) as f64)
    }
}

/// `MemoryError` if `bytes` (what `what` needs, estimated) exceed the memory available: raised
/// before anything is allocated, with the estimate and the figure it was compared with.
pub(crate) fn check(what: &str, bytes: usize) -> PyResult<()> {
    let bytes = bytes as u64;
    match available()? {
        Some((limit, source)) if bytes > limit => Err(PyMemoryError::new_err(format!(
            "{what} needs about {} but {} is available ({source}): refused before allocating",
            human(bytes),
            human(limit)
        ))),
        _ => Ok(()),
    }
}

fn failed<T>(what: &str, n: usize) -> PyErr {
    let bytes = n.saturating_mul(std::mem::size_of::<T>()) as u64;
    PyMemoryError::new_err(format!(
        "{what}: cannot allocate {} ({n} entries)",
        human(bytes)
    ))
}

/// An empty vector with room for `n` entries, or `MemoryError` naming `what`.
pub(crate) fn with_capacity<T>(n: usize, what: &str) -> PyResult<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| failed::<T>(what, n))?;
    Ok(v)
}

/// A vector of `n` copies of `value`, or `MemoryError` naming `what`.
pub(crate) fn filled<T: Clone>(n: usize, value: T, what: &str) -> PyResult<Vec<T>> {
    let mut v = with_capacity(n, what)?;
    v.resize(n, value);
    Ok(v)
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
        assert_eq!(parse_bytes("99999999999T"), None);
    }

    #[test]
    fn fields_are_read_from_proc_style_text() {
        let status = "Name:\tpython\nVmSize:\t  123456 kB\n";
        assert_eq!(field(status, "VmSize:"), Some(123456));
        let limits = "Max address space         3221225472           unlimited            bytes\n";
        assert_eq!(field(limits, "Max address space"), Some(3221225472));
        let unlimited =
            "Max address space         unlimited            unlimited            bytes\n";
        assert_eq!(field(unlimited, "Max address space"), None);
    }
}
