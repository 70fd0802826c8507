//! `spheresweep run` keeps every sphere in its vessel, checked from its `trajectory.xyz` alone
//! with this file's own reader and geometry: the report's scene (one sphere, restitution 0.3,
//! out of its vessel at t ≈ 15.5 before the fix) and others like it; and a run whose wall
//! rule is broken on purpose (`--break-walls-for-testing`) stops with a non-zero exit naming
//! the sphere, the container and the time, and leaves no outputs.

mod common;

use std::path::Path;

use common::{bin, scratch};

/// One frame: its time, and each sphere's centre and radius.
type Frame = (f64, Vec<([f64; 3], f64)>);

/// Every frame of an extended-XYZ file, from the columns the `Properties` key names.
fn frames(path: &Path) -> Vec<Frame> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let mut out = Vec::new();
    while let Some(count) = lines.next() {
        let n: usize = count.trim().parse().unwrap();
        let header = lines.next().unwrap();
        let value = |key: &str| {
            header
                .split_whitespace()
                .find_map(|w| w.strip_prefix(key))
                .unwrap_or_else(|| panic!("no {key} in {header}"))
        };
        let time: f64 = value("Time=").parse().unwrap();
        let (mut column, mut pos, mut radius) = (0, 0, 0);
        for f in value("Properties=")
            .split(':')
            .collect::<Vec<_>>()
            .chunks(3)
        {
            match f[0] {
                "pos" => pos = column,
                "radius" => radius = column,
                _ => {}
            }
            column += f[2].parse::<usize>().unwrap();
        }
        let spheres = (0..n)
            .map(|_| {
                let w: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
                let x = |k: usize| w[k].parse::<f64>().unwrap();
                ([x(pos), x(pos + 1), x(pos + 2)], x(radius))
            })
            .collect();
        out.push((time, spheres));
    }
    out
}

/// A scene of `spheres` in a vessel of radius 6 at the origin, inelastic.
fn scene(dir: &Path, name: &str, restitution: f64, tc: f64, t_end: f64, spheres: &str) -> String {
    let path = dir.join(name);
    std::fs::write(
        &path,
        format!(
            "[run]\nt_end = {t_end}\nsnapshot_every = 1.0\nseed = 4\n\n[effects]\n\
             response = \"inelastic\"\nrestitution = {restitution}\ntc = {tc}\n\n{spheres}\n\
             [[container]]\ncentre = [0.0, 0.0, 0.0]\nradius = 6.0\n"
        ),
    )
    .unwrap();
    path.to_str().unwrap().to_string()
}

const ONE: &str =
    "[[sphere]]\ncentre = [3.0, 0.0, 0.0]\nvelocity = [0.3, 1.0, 0.2]\nradius = 0.5\n";

/// The deepest a sphere of any frame gets past the vessel's wall, over its radius.
fn deepest(out: &Path) -> (f64, usize) {
    let frames = frames(&out.join("trajectory.xyz"));
    let worst = frames
        .iter()
        .flat_map(|(_, s)| s.iter())
        .map(|&([x, y, z], r)| ((x * x + y * y + z * z).sqrt() + r - 6.0) / r)
        .fold(f64::NEG_INFINITY, f64::max);
    (worst, frames.len())
}

#[test]
fn the_reported_scenes_stay_in_their_vessel() {
    let dir = scratch("walls");
    let random = "[[generate]]\nkind = \"random\"\nn = 60\nradius = 0.3\nspeed = 1.0\ninside = 0\n";
    for (name, e, tc, t_end, spheres) in [
        ("one-0.3.toml", 0.3, 0.0, 200.0, ONE),
        ("one-0.99.toml", 0.99, 0.0, 2500.0, ONE),
        ("many-0.05.toml", 0.05, 1e-3, 300.0, random),
        ("many-0.3.toml", 0.3, 0.0, 300.0, random),
    ] {
        let path = scene(&dir, name, e, tc, t_end, spheres);
        let out = dir.join(format!("{name}-out"));
        let run = bin()
            .args(["run", "--quiet", &path, "--out", out.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        let (worst, count) = deepest(&out);
        assert_eq!(count, t_end as usize + 1, "{name}");
        assert!(
            worst <= spheresweep::sim::OVERLAP_TOLERANCE,
            "{name}: a sphere {worst:e} of its radius past the wall"
        );
        let stdout = String::from_utf8_lossy(&run.stdout);
        assert!(stdout.contains("state        checked"), "{stdout}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// With the container rules of before 2026-12-01 the sphere leaves at t ≈ 15.5: the run's
/// check at the next snapshot stops it, exit 1, naming the sphere, the container and the
/// time; nothing is left in the output directory.
#[test]
fn a_broken_wall_rule_stops_the_run_with_an_error() {
    let dir = scratch("walls-broken");
    let path = scene(&dir, "one.toml", 0.3, 0.0, 200.0, ONE);
    let out = dir.join("out");
    let run = bin()
        .args(["run", "--quiet", &path, "--out", out.to_str().unwrap()])
        .arg("--break-walls-for-testing")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("sphere 0 is past the wall of container 0")
            && stderr.contains("broke its invariant"),
        "{stderr}"
    );
    let t: f64 = stderr
        .split("t = ")
        .nth(1)
        .and_then(|s| s.split(':').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no time in {stderr}"));
    assert!((15.0..=17.0).contains(&t), "{t}");
    let left: Vec<_> = std::fs::read_dir(&out)
        .map(|d| d.flatten().map(|e| e.file_name()).collect())
        .unwrap_or_default();
    assert!(left.is_empty(), "left behind: {left:?}");
    std::fs::remove_dir_all(&dir).ok();
}
