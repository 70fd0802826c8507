//! Up-front memory refusal: a scene or a chunk too large for the memory available is refused
//! before anything is allocated, with the count, the estimated bytes and the memory available.

/// Environment variable that sets the memory available, in bytes (suffixes K, M, G, T for
/// powers of 1024), instead of `MemAvailable` of /proc/meminfo: for tests, and for machines
/// shared with other work.
pub const MAX_MEMORY_VAR: &str = "SPHERESWEEP_MAX_MEMORY";

/// Bytes a size such as `512M`, `2G` or `1000000` stands for.
fn parse_bytes(text: &str) -> Option<u64> {
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

/// The memory available and where the figure comes from: the environment variable, else
/// `MemAvailable` of /proc/meminfo; `None` when neither is there (then nothing is refused).
pub fn available() -> Result<Option<(u64, &'static str)>, String> {
    if let Ok(text) = std::env::var(MAX_MEMORY_VAR) {
        return parse_bytes(&text)
            .map(|b| Some((b, MAX_MEMORY_VAR)))
            .ok_or_else(|| {
                format!("{MAX_MEMORY_VAR}={text:?} is not a size in bytes (e.g. 512M, 8G)")
            });
    }
    let Ok(meminfo) = std::fs::read_to_string("/proc/meminfo") else {
        return Ok(None);
    };
    Ok(meminfo
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))
        .and_then(|v| v.trim().strip_suffix("kB"))
        .and_then(|kb| kb.trim().parse::<u64>().ok())
        .map(|kb| (kb.saturating_mul(1024), "MemAvailable in /proc/meminfo")))
}

/// Refuses `bytes` (for `what`) above the memory available.
pub fn check(what: &str, bytes: u64) -> Result<(), String> {
    match available()? {
        Some((limit, source)) if bytes > limit => Err(format!(
            "{what} needs about {} but {} is available ({source}): refused before allocating",
            human(bytes),
            human(limit)
        )),
        _ => Ok(()),
    }
}

/// Refuses a scene file whose spheres (counted before any is generated) would not fit in the
/// memory available at `per_sphere` bytes each, naming the file and the count.
pub fn check_scene(
    path: &std::path::Path,
    scene: &spheresweep::io::scene_file::SceneFile,
    per_sphere: usize,
) -> Result<(), String> {
    match scene.sphere_count() {
        Some(n) => check(
            &format!("{}: {n} spheres", path.display()),
            n.saturating_mul(per_sphere) as u64,
        ),
        None => Ok(()),
    }
}

/// Bytes in MiB or GiB.
pub fn human(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= (1u64 << 30) as f64 {
        format!("{:.2} GiB ({bytes} B)", b / (1u64 << 30) as f64)
    } else {
        format!("{:.1} MiB ({bytes} B)", b / (1u64 << 20) as f64)
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
}
