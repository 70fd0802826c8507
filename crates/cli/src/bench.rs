//! `spheresweep bench`: a quick, self-contained throughput report — every kernel and mode
//! against parry3d's `cast_shapes`, the broad phase against parry3d's `Bvh`, and the whole
//! first-contact query against parry's `Bvh` + `cast_shapes` (with the memory it holds per
//! sphere and, in the full run, the memory floor) — measured side by side in one run, ours on
//! one and two threads, the peer on one, best of several interleaved timings, printed with the
//! ratios.

mod floor;
mod interleaved;
mod memory_probe;
mod whole_scene;

use std::error::Error;
use std::hint::black_box;
use std::io::Write;
use std::time::Duration;

use indicatif::ProgressBar;
use spheresweep::{Accuracy, QueryOptions};
use spheresweep_bench::narrow::{self, T_MAX};

use memory_probe::QueryMemory;
use whole_scene::{Pools, Timing};

/// Options of `spheresweep bench`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Smaller sizes and shorter timings: finishes in well under a minute.
    #[arg(long)]
    quick: bool,
    /// Print the results as JSON (one object) instead of tables.
    #[arg(long)]
    json: bool,
    /// Run only the simulation section: collisions per second of the hard-sphere gas at
    /// N = 4000, φ = 0.1 … 0.5 and larger N, the cost of unused effects, bytes per sphere.
    #[arg(long)]
    sim: bool,
    /// A checkout of Smallenburg's EDMD (github.com/FSmallenburg/EDMD): its "Single" program
    /// is built with gcc -Ofast -march=native and run beside ours, alternately, in this run.
    /// Default: none (the peer is not run).
    #[arg(long, value_name = "DIR", env = "EDMD_DIR")]
    edmd: Option<std::path::PathBuf>,
    /// Internal: one query of N spheres in this fresh process, its memory per sphere printed
    /// (the full report runs itself with it for the query's memory line).
    #[arg(long, hide = true, value_name = "N")]
    memory_probe: Option<usize>,
    /// Internal: the packing fraction of `--memory-probe`'s gas.
    #[arg(long, hide = true, default_value_t = 0.3)]
    memory_probe_phi: f64,
}

/// One measured line: what, how big, ns per item, and the peer's ns per item if it has one;
/// the threads ours ran on, and the memory per sphere where it was measured.
struct Line {
    group: String,
    name: String,
    n: usize,
    ns: f64,
    peer_ns: Option<f64>,
    note: String,
    threads: usize,
    memory: Option<QueryMemory>,
}

impl Default for Line {
    fn default() -> Self {
        Line {
            group: String::new(),
            name: String::new(),
            n: 0,
            ns: f64::NAN,
            peer_ns: None,
            note: String::new(),
            threads: 1,
            memory: None,
        }
    }
}

/// The SIMD level this binary was compiled for.
fn simd_level() -> &'static str {
    if cfg!(target_feature = "avx512f") {
        "AVX-512"
    } else if cfg!(all(target_feature = "avx2", target_feature = "fma")) {
        "AVX2 + FMA (x86-64-v3)"
    } else if cfg!(target_feature = "avx") {
        "AVX"
    } else if cfg!(target_feature = "sse2") {
        "SSE2"
    } else {
        "scalar"
    }
}

/// Best time per item of `f` over `rounds` timings of at least `min` each.
fn best_ns(items: usize, rounds: usize, min: Duration, mut f: impl FnMut()) -> f64 {
    f();
    (0..rounds)
        .map(|_| interleaved::timing_ns(items, min, &mut f))
        .fold(f64::INFINITY, f64::min)
}

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    if let Some(n) = args.memory_probe {
        return memory_probe::run(n, args.memory_probe_phi);
    }
    let load = load_average();
    let pools = Pools::new()?;
    let timing = if args.quick {
        Timing {
            rounds: 5,
            min: Duration::from_millis(20),
        }
    } else {
        Timing {
            rounds: 11,
            min: Duration::from_millis(60),
        }
    };
    let mut lines = Vec::new();
    let floor_steps = if args.quick { 0 } else { 1 };
    let progress = crate::progress::bar(
        4 + whole_scene::steps(args.quick) + floor_steps,
        "{spinner} {wide_bar} {pos}/{len} {msg}",
        args.json,
    )?;
    if args.sim {
        progress.set_length(if args.quick { 6 } else { 10 });
        sim_lines(&mut lines, args, &progress);
    } else {
        pools
            .one
            .install(|| narrow_lines(&mut lines, timing.rounds, timing.min, &progress));
        whole_scene::lines(&mut lines, args.quick, &pools, timing, &progress);
        if !args.quick {
            progress.set_message("memory floor (800 MB arrays)");
            floor::lines(&mut lines);
            progress.inc(1);
        }
    }
    progress.finish_and_clear();
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", json(&lines, load))?;
    } else {
        write_tables(&mut out, &lines, load)?;
    }
    Ok(())
}

fn narrow_lines(lines: &mut Vec<Line>, rounds: usize, min: Duration, progress: &ProgressBar) {
    let n = 4096;
    let mut out = vec![0.0f32; n];
    let pairs = narrow::SpherePairs::new(n, 1);
    progress.set_message("sphere pairs");
    let peer = best_ns(n, rounds, min, || {
        pairs.parry(&mut out);
        black_box(&mut out);
    });
    for mode in Accuracy::ALL {
        let options = QueryOptions::new(T_MAX, mode).expect("valid window");
        let ns = best_ns(n, rounds, min, || {
            pairs.ours(options, &mut out);
            black_box(&mut out);
        });
        lines.push(Line {
            group: "narrow phase, in cache (4096 pairs)".into(),
            name: format!("sphere-sphere {mode}"),
            n,
            ns,
            peer_ns: Some(peer),
            note: "parry cast_shapes".into(),
            ..Line::default()
        });
    }
    progress.inc(1);
    fn statics<K: spheresweep::batch::StaticShape>(
        lines: &mut Vec<Line>,
        kind: &str,
        set: &narrow::AgainstStatic<K>,
        rounds: usize,
        min: Duration,
    ) {
        let n = set.spheres.len();
        let mut out = vec![0.0f32; n];
        let peer = set.has_peer().then(|| {
            best_ns(n, rounds, min, || {
                set.parry(&mut out);
                black_box(&mut out);
            })
        });
        for mode in Accuracy::ALL {
            let options = QueryOptions::new(T_MAX, mode).expect("valid window");
            let ns = best_ns(n, rounds, min, || {
                set.ours(options, &mut out);
                black_box(&mut out);
            });
            lines.push(Line {
                group: "narrow phase, in cache (4096 pairs)".into(),
                name: format!("{kind} {mode}"),
                n,
                ns,
                peer_ns: peer,
                note: if peer.is_some() {
                    "parry cast_shapes".into()
                } else {
                    "parry has no inside-of-a-ball cast".into()
                },
                ..Line::default()
            });
        }
    }
    progress.set_message("planes");
    statics(lines, "sphere-plane", &narrow::plane(n, 2), rounds, min);
    progress.inc(1);
    progress.set_message("cylinders");
    statics(
        lines,
        "sphere-cylinder",
        &narrow::cylinder(n, 2),
        rounds,
        min,
    );
    progress.inc(1);
    progress.set_message("containers");
    statics(
        lines,
        "sphere-container",
        &narrow::container(n, 2),
        rounds,
        min,
    );
    progress.inc(1);
}

/// The event-driven engine on the peer's gas, ours and the peer alternately (best of the
/// repetitions each), in ns per collision; the cost of declared but unused effects; and bytes
/// per sphere at N = 10⁶.
fn sim_lines(lines: &mut Vec<Line>, args: &Args, progress: &ProgressBar) {
    use spheresweep_bench::sim;
    const GROUP: &str = "simulation: ns per collision, hard-sphere gas from FCC (peer: Smallenburg EDMD \"Single\", gcc -Ofast -march=native)";
    let (reps, small, large) = if args.quick {
        (1, 500_000, 500_000)
    } else {
        (3, 2_000_000, 3_000_000)
    };
    // Up to the dense fluid (freezing at 0.494) and into the coexistence region (0.5).
    let mut cases: Vec<(usize, f64, u64)> = [0.1, 0.2, 0.25, 0.3, 0.4, 0.45, 0.5]
        .iter()
        .map(|&phi| (4000, phi, small))
        .collect();
    cases.push((32_000, 0.25, large));
    if !args.quick {
        cases.push((108_000, 0.25, large));
    }
    let mut peer_note = String::new();
    for (n, phi, collisions) in cases {
        progress.set_message(format!("gas N = {n}, φ = {phi}"));
        let (mut ours, mut peer) = (f64::INFINITY, None::<f64>);
        let mut stats = None;
        for _ in 0..reps {
            let r = sim::measure(sim::gas(n, phi, 1), collisions);
            ours = ours.min(1e9 / r.per_second());
            stats = Some(r.stats);
            if let Some(dir) = &args.edmd {
                match sim::peer_rate(dir, n, phi, collisions) {
                    Ok(rate) => peer = Some(peer.map_or(1e9 / rate, |p: f64| p.min(1e9 / rate))),
                    Err(e) => peer_note = format!("peer not run: {e}"),
                }
            }
        }
        let s = stats.expect("one repetition");
        let per = |x: u64| x as f64 / s.pair_collisions as f64;
        lines.push(Line {
            group: GROUP.into(),
            name: format!("gas N = {n}, φ = {phi}"),
            n,
            ns: ours,
            peer_ns: peer,
            note: format!(
                "{:.0} k/s; per collision: {:.2} predictions, {:.2} shell events, {:.1} pairs answered",
                1e6 / ours,
                per(s.predictions),
                per(s.crossings),
                per(s.kernels.sphere)
            ),
            ..Line::default()
        });
        progress.inc(1);
    }
    if args.edmd.is_none() {
        peer_note =
            "peer not run: give --edmd DIR (a checkout of github.com/FSmallenburg/EDMD)".into();
    }
    // The same spheres with effects declared that they never use: the same engine, the same cost.
    progress.set_message("unused effects");
    let (mut plain, mut declared) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..reps.max(2) {
        plain = plain.min(1e9 / sim::measure(sim::gas(4000, 0.25, 1), small).per_second());
        declared = declared.min(
            1e9 / sim::measure(sim::gas_with_unused_effects(4000, 0.25, 1), small).per_second(),
        );
    }
    let engine = spheresweep::sim::Simulation::new(sim::gas_with_unused_effects(32, 0.25, 1))
        .map(|s| s.engine_name())
        .unwrap_or_default();
    lines.push(Line {
        group: "simulation: effects a scene declares but does not use (ns per collision; \"peer\" = the plain gas)".into(),
        name: "gas N = 4000, φ = 0.25, sticky + inelastic declared".into(),
        n: 4000,
        ns: declared,
        peer_ns: Some(plain),
        note: format!("engine assembled: {engine}"),
        ..Line::default()
    });
    progress.inc(1);
    if !args.quick {
        progress.set_message("N = 10⁶ memory");
        let r = sim::measure(sim::gas(1_000_000, 0.25, 1), 2_000_000);
        let peak = sim::peak_resident_bytes().map_or(String::new(), |p| {
            format!("; this process's peak resident {:.0} MB", p as f64 / 1e6)
        });
        lines.push(Line {
            group: GROUP.into(),
            name: "gas N = 1000000, φ = 0.25".into(),
            n: 1_000_000,
            ns: 1e9 / r.per_second(),
            peer_ns: None,
            note: format!(
                "{:.0} bytes per sphere held by the simulation{peak}",
                r.bytes as f64 / 1e6
            ),
            ..Line::default()
        });
        progress.inc(1);
    }
    if !peer_note.is_empty() {
        eprintln!("{peer_note}");
    }
}

/// The one-minute load average when the run started (Linux `/proc/loadavg`), if known: with
/// other work on the machine, two threads of ours share the cores with it.
fn load_average() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    text.split_whitespace().next()?.parse().ok()
}

fn write_tables(out: &mut impl Write, lines: &[Line], load: Option<f64>) -> std::io::Result<()> {
    let load = load.map_or(String::new(), |l| {
        format!(", load average {l:.2} at the start")
    });
    writeln!(
        out,
        "spheresweep {} — built for {}; ours on one thread unless a line says two, the peer on one; {} cores available{load}",
        env!("CARGO_PKG_VERSION"),
        simd_level(),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    )?;
    // Each group once, in order of first appearance.
    let mut groups: Vec<&str> = Vec::new();
    for l in lines {
        if !groups.contains(&l.group.as_str()) {
            groups.push(&l.group);
        }
    }
    let mut sorted: Vec<&Line> = lines.iter().collect();
    sorted.sort_by_key(|l| groups.iter().position(|g| *g == l.group));
    let mut group = "";
    for l in sorted {
        if l.group != group {
            group = &l.group;
            writeln!(out, "\n{group}")?;
            writeln!(
                out,
                "  {:<48} {:>12} {:>12} {:>10}",
                "", "ns / item", "peer ns", "× peer"
            )?;
        }
        let (peer, ratio) = match l.peer_ns {
            Some(p) => (format!("{p:.2}"), format!("{:.1}×", p / l.ns)),
            None => ("–".into(), "–".into()),
        };
        writeln!(
            out,
            "  {:<48} {:>12.3} {:>12} {:>10}  {}",
            l.name, l.ns, peer, ratio, l.note
        )?;
    }
    Ok(())
}

/// The report as one JSON object: every line with its threads, ratio and (for the query)
/// bytes per sphere held after the first call and at its peak.
fn json(lines: &[Line], load: Option<f64>) -> String {
    let items: Vec<serde_json::Value> = lines
        .iter()
        .map(|l| {
            serde_json::json!({
                "group": l.group,
                "name": l.name,
                "n": l.n,
                "threads": l.threads,
                "ns_per_item": l.ns,
                "peer_ns_per_item": l.peer_ns,
                "ratio": l.peer_ns.map(|p| p / l.ns),
                "held_bytes_per_sphere": l.memory.map(|m| m.held),
                "peak_bytes_per_sphere": l.memory.and_then(|m| m.peak),
                "note": l.note,
            })
        })
        .collect();
    serde_json::json!({
        "version": env!("CARGO_PKG_VERSION"),
        "simd": simd_level(),
        "peer_threads": 1,
        "cores": std::thread::available_parallelism().map_or(1, |n| n.get()),
        "load_average": load,
        "lines": items,
    })
    .to_string()
}
