//! `spheresweep bench`: a quick, self-contained throughput report — every kernel and mode
//! against parry3d's `cast_shapes`, the broad phase against parry3d's `Bvh`, and the whole
//! first-contact query against parry's `Bvh` + `cast_shapes` — measured side by side in one
//! run, one thread, best of several interleaved timings, printed with the ratios.

use std::error::Error;
use std::hint::black_box;
use std::io::Write;
use std::time::{Duration, Instant};

use indicatif::ProgressBar;
use spheresweep::broad::{Grid, GridOptions};
use spheresweep::query::SceneQuery;
use spheresweep::scene::Scene;
use spheresweep::{Accuracy, QueryOptions};
use spheresweep_bench::narrow::{self, T_MAX};
use spheresweep_bench::peer::{ParryIncremental, ParryQuery, ParryRebuild, swept_boxes_into};
use spheresweep_bench::scenes;

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
    /// N = 4000, φ = 0.1 … 0.4 and larger N, the cost of unused effects, bytes per sphere.
    #[arg(long)]
    sim: bool,
    /// A checkout of Smallenburg's EDMD (github.com/FSmallenburg/EDMD): its "Single" program
    /// is built with gcc -Ofast -march=native and run beside ours, alternately, in this run.
    /// Default: none (the peer is not run).
    #[arg(long, value_name = "DIR", env = "EDMD_DIR")]
    edmd: Option<std::path::PathBuf>,
}

/// One measured line: what, how big, ns per item, and the peer's ns per item if it has one.
struct Line {
    group: &'static str,
    name: String,
    n: usize,
    ns: f64,
    peer_ns: Option<f64>,
    note: String,
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
    let mut best = f64::INFINITY;
    f();
    for _ in 0..rounds {
        let (start, mut reps) = (Instant::now(), 0u32);
        while reps == 0 || start.elapsed() < min {
            f();
            reps += 1;
        }
        let ns = start.elapsed().as_secs_f64() * 1e9 / (f64::from(reps) * items as f64);
        best = best.min(ns);
    }
    best
}

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let (rounds, min) = if args.quick {
        (5, Duration::from_millis(20))
    } else {
        (11, Duration::from_millis(60))
    };
    let mut lines = Vec::new();
    let progress = crate::progress::bar(
        if args.quick { 8 } else { 12 },
        "{spinner} {wide_bar} {pos}/{len} {msg}",
        args.json,
    )?;
    if args.sim {
        progress.set_length(if args.quick { 6 } else { 10 });
        sim_lines(&mut lines, args, &progress);
    } else {
        pool.install(|| {
            narrow_lines(&mut lines, rounds, min, &progress);
            broad_lines(&mut lines, args.quick, rounds, min, &progress);
        });
    }
    progress.finish_and_clear();
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", json(&lines))?;
    } else {
        write_tables(&mut out, &lines)?;
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
            group: "narrow phase, in cache (4096 pairs)",
            name: format!("sphere-sphere {mode}"),
            n,
            ns,
            peer_ns: Some(peer),
            note: "parry cast_shapes".into(),
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
                group: "narrow phase, in cache (4096 pairs)",
                name: format!("{kind} {mode}"),
                n,
                ns,
                peer_ns: peer,
                note: if peer.is_some() {
                    "parry cast_shapes".into()
                } else {
                    "parry has no inside-of-a-ball cast".into()
                },
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

fn broad_lines(
    lines: &mut Vec<Line>,
    quick: bool,
    rounds: usize,
    min: Duration,
    progress: &ProgressBar,
) {
    let sizes: &[usize] = if quick {
        &[10_000, 100_000]
    } else {
        &[1_000, 10_000, 100_000, 1_000_000]
    };
    let t_max = scenes::window(0.5);
    for &n in sizes {
        progress.set_message(format!("broad phase and query, N = {n}"));
        let store = scenes::uniform_gas(n, 0.3, 7);
        let (rounds, min) = if n >= 1_000_000 {
            (3, Duration::ZERO)
        } else {
            (rounds, min)
        };
        let mut grid = Grid::new();
        let ours = best_ns(n, rounds, min, || {
            grid.build(&store, t_max, GridOptions::default());
            black_box(grid.pairs().len());
        });
        let candidates = grid.pairs().len();
        let (mut lo, mut hi) = (Vec::new(), Vec::new());
        swept_boxes_into(&store, t_max, &mut lo, &mut hi);
        let mut incremental = ParryIncremental::new();
        incremental.count(&lo, &hi);
        let mut peer_pairs = 0;
        let peer = best_ns(n, rounds, min, || {
            peer_pairs = incremental.count(&lo, &hi);
        });
        lines.push(Line {
            group: "broad phase (uniform gas, phi 0.3, half a radius of travel)",
            name: format!("grid vs Bvh incremental, N = {n}"),
            n,
            ns: ours,
            peer_ns: Some(peer),
            note: format!(
                "{:.2} / {:.2} candidates per sphere",
                candidates as f64 / n as f64,
                peer_pairs as f64 / n as f64
            ),
        });
        if n <= 100_000 {
            let mut rebuild = ParryRebuild::new();
            let peer = best_ns(n, rounds.min(3), Duration::ZERO, || {
                black_box(rebuild.count(&lo, &hi));
            });
            lines.push(Line {
                group: "broad phase (uniform gas, phi 0.3, half a radius of travel)",
                name: format!("grid vs Bvh rebuilt, N = {n}"),
                n,
                ns: ours,
                peer_ns: Some(peer),
                note: String::new(),
            });
        }
        let scene = Scene {
            spheres: store,
            ..Scene::default()
        };
        let options = QueryOptions::new(t_max, Accuracy::Stable).expect("valid window");
        let (mut query, mut firsts) = (SceneQuery::new(), Vec::new());
        let ours = best_ns(n, rounds, min, || {
            query.first_contacts_into(&scene, options, &mut firsts);
            black_box(&firsts);
        });
        let mut parry = ParryQuery::new();
        let mut out = vec![0.0f32; n];
        parry.first_contacts(&scene.spheres, t_max, &mut out);
        let peer = best_ns(n, rounds.min(5), Duration::ZERO, || {
            parry.first_contacts(&scene.spheres, t_max, &mut out);
        });
        lines.push(Line {
            group: "whole query: first contact per sphere (stable)",
            name: format!("N = {n}"),
            n,
            ns: ours,
            peer_ns: Some(peer),
            note: "parry Bvh incremental + cast_shapes".into(),
        });
        progress.inc(2);
    }
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
    let mut cases: Vec<(usize, f64, u64)> = [0.1, 0.2, 0.25, 0.3, 0.4]
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
            group: GROUP,
            name: format!("gas N = {n}, φ = {phi}"),
            n,
            ns: ours,
            peer_ns: peer,
            note: format!(
                "{:.0} k/s; per collision: {:.2} predictions, {:.2} crossings, {:.1} lanes",
                1e6 / ours,
                per(s.predictions),
                per(s.crossings),
                per(s.kernels.sphere)
            ),
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
        group: "simulation: effects a scene declares but does not use (ns per collision; \"peer\" = the plain gas)",
        name: "gas N = 4000, φ = 0.25, sticky + inelastic declared".into(),
        n: 4000,
        ns: declared,
        peer_ns: Some(plain),
        note: format!("engine assembled: {engine}"),
    });
    progress.inc(1);
    if !args.quick {
        progress.set_message("N = 10⁶ memory");
        let r = sim::measure(sim::gas(1_000_000, 0.25, 1), 2_000_000);
        let peak = sim::peak_resident_bytes().map_or(String::new(), |p| {
            format!("; this process's peak resident {:.0} MB", p as f64 / 1e6)
        });
        lines.push(Line {
            group: GROUP,
            name: "gas N = 1000000, φ = 0.25".into(),
            n: 1_000_000,
            ns: 1e9 / r.per_second(),
            peer_ns: None,
            note: format!(
                "{:.0} bytes per sphere held by the simulation{peak}",
                r.bytes as f64 / 1e6
            ),
        });
        progress.inc(1);
    }
    if !peer_note.is_empty() {
        eprintln!("{peer_note}");
    }
}

fn write_tables(out: &mut impl Write, lines: &[Line]) -> std::io::Result<()> {
    writeln!(
        out,
        "spheresweep {} — built for {}; one thread; {} cores available",
        env!("CARGO_PKG_VERSION"),
        simd_level(),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    )?;
    // Each group once, in order of first appearance.
    let mut groups: Vec<&str> = Vec::new();
    for l in lines {
        if !groups.contains(&l.group) {
            groups.push(l.group);
        }
    }
    let mut sorted: Vec<&Line> = lines.iter().collect();
    sorted.sort_by_key(|l| groups.iter().position(|g| *g == l.group));
    let mut group = "";
    for l in sorted {
        if l.group != group {
            group = l.group;
            writeln!(out, "\n{group}")?;
            writeln!(
                out,
                "  {:<40} {:>12} {:>12} {:>10}",
                "", "ns / item", "peer ns", "× peer"
            )?;
        }
        let (peer, ratio) = match l.peer_ns {
            Some(p) => (format!("{p:.2}"), format!("{:.1}×", p / l.ns)),
            None => ("–".into(), "–".into()),
        };
        writeln!(
            out,
            "  {:<40} {:>12.3} {:>12} {:>10}  {}",
            l.name, l.ns, peer, ratio, l.note
        )?;
    }
    Ok(())
}

fn json(lines: &[Line]) -> String {
    let esc = |s: &str| s.replace('\\', "\\\\").replace('"', "\\\"");
    let items: Vec<String> = lines
        .iter()
        .map(|l| {
            format!(
                "{{\"group\":\"{}\",\"name\":\"{}\",\"n\":{},\"ns_per_item\":{:.4},\"peer_ns_per_item\":{},\"ratio\":{},\"note\":\"{}\"}}",
                esc(l.group),
                esc(&l.name),
                l.n,
                l.ns,
                l.peer_ns.map_or("null".into(), |p| format!("{p:.4}")),
                l.peer_ns.map_or("null".into(), |p| format!("{:.3}", p / l.ns)),
                esc(&l.note)
            )
        })
        .collect();
    format!(
        "{{\"version\":\"{}\",\"simd\":\"{}\",\"threads\":1,\"lines\":[{}]}}",
        env!("CARGO_PKG_VERSION"),
        simd_level(),
        items.join(",")
    )
}
