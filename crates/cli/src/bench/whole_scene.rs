//! The broad phase and the whole first-contact query on the uniform gas at φ = 0.3 and 0.05,
//! half a radius of travel: ours on one and on two threads, parry3d on one, in the same run;
//! and the memory per sphere the query holds (measured in a fresh process, `memory_probe`).

use std::hint::black_box;
use std::time::Duration;

use indicatif::ProgressBar;
use rayon::ThreadPool;
use spheresweep::broad::{Grid, GridOptions};
use spheresweep::query::SceneQuery;
use spheresweep::scene::Scene;
use spheresweep::{Accuracy, QueryOptions, SphereStore};
use spheresweep_bench::peer::{ParryIncremental, ParryQuery, ParryRebuild, swept_boxes_into};
use spheresweep_bench::scenes;

use super::interleaved::{self, Timed};
use super::{Line, best_ns, memory_probe};

/// The packing fractions of the gas, each its own groups.
const PHIS: [f64; 2] = [0.3, 0.05];

/// The rayon pools ours run in: one thread and two threads.
pub struct Pools {
    pub one: ThreadPool,
    pub two: ThreadPool,
}

impl Pools {
    pub fn new() -> Result<Self, rayon::ThreadPoolBuildError> {
        let pool = |n| rayon::ThreadPoolBuilder::new().num_threads(n).build();
        Ok(Pools {
            one: pool(1)?,
            two: pool(2)?,
        })
    }
}

/// How long each line is timed: best of `rounds` timings of at least `min` each.
#[derive(Debug, Clone, Copy)]
pub struct Timing {
    pub rounds: usize,
    pub min: Duration,
}

/// The sizes measured: N = 10⁴ and 10⁵ quick, 10³ … 10⁶ in full.
pub fn sizes(quick: bool) -> &'static [usize] {
    if quick {
        &[10_000, 100_000]
    } else {
        &[1_000, 10_000, 100_000, 1_000_000]
    }
}

/// Progress steps of [`lines`]: two per packing fraction and size.
pub fn steps(quick: bool) -> u64 {
    (2 * PHIS.len() * sizes(quick).len()) as u64
}

/// The broad-phase and whole-query lines at every packing fraction and size.
pub fn lines(
    lines: &mut Vec<Line>,
    quick: bool,
    pools: &Pools,
    timing: Timing,
    progress: &ProgressBar,
) {
    let t_max = scenes::window(0.5);
    for phi in PHIS {
        for &n in sizes(quick) {
            progress.set_message(format!("broad phase and query, φ = {phi}, N = {n}"));
            let store = scenes::uniform_gas(n, phi, 7);
            let timing = if n >= 1_000_000 {
                Timing {
                    rounds: 3,
                    min: Duration::ZERO,
                }
            } else {
                timing
            };
            broad_phase(lines, &store, phi, t_max, pools, timing);
            progress.inc(1);
            query(lines, store, phi, t_max, pools, timing);
            progress.inc(1);
        }
    }
}

/// The note of a two-thread line: its speed-up over one thread.
fn speed_up(one: f64, two: f64) -> String {
    format!("{:.2}× one thread", one / two)
}

/// The grid on one and two threads against parry's `Bvh` updated incrementally (and, at
/// φ = 0.3 up to N = 10⁵, rebuilt), on the same swept boxes.
fn broad_phase(
    lines: &mut Vec<Line>,
    store: &SphereStore,
    phi: f64,
    t_max: f32,
    pools: &Pools,
    Timing { rounds, min }: Timing,
) {
    let n = store.len();
    let group = format!("broad phase (uniform gas, phi {phi}, half a radius of travel)");
    let (mut lo, mut hi) = (Vec::new(), Vec::new());
    swept_boxes_into(store, t_max, &mut lo, &mut hi);
    let (mut grid, mut grid2) = (Grid::new(), Grid::new());
    let mut incremental = ParryIncremental::new();
    let mut peer_pairs = 0;
    let [one, two, peer] = interleaved::best_ns(
        n,
        rounds,
        [
            Timed {
                pool: &pools.one,
                min,
                work: &mut || {
                    grid.build(store, t_max, GridOptions::default());
                    black_box(grid.pairs().len());
                },
            },
            Timed {
                pool: &pools.two,
                min,
                work: &mut || {
                    grid2.build(store, t_max, GridOptions::default());
                    black_box(grid2.pairs().len());
                },
            },
            Timed {
                pool: &pools.one,
                min,
                work: &mut || peer_pairs = incremental.count(&lo, &hi),
            },
        ],
    );
    let candidates = grid.pairs().len();
    let per_sphere = |pairs: f64| pairs / n as f64;
    lines.push(Line {
        group: group.clone(),
        name: format!("grid vs Bvh incremental, N = {n}"),
        n,
        ns: one,
        peer_ns: Some(peer),
        note: format!(
            "{:.2} / {:.2} candidates per sphere",
            per_sphere(candidates as f64),
            per_sphere(peer_pairs as f64)
        ),
        ..Line::default()
    });
    lines.push(Line {
        group: group.clone(),
        name: format!("grid, 2 threads vs Bvh incremental, N = {n}"),
        n,
        ns: two,
        peer_ns: Some(peer),
        note: speed_up(one, two),
        threads: 2,
        ..Line::default()
    });
    if phi == 0.3 && n <= 100_000 {
        let mut rebuild = ParryRebuild::new();
        let peer = pools.one.install(|| {
            best_ns(n, rounds.min(3), Duration::ZERO, || {
                black_box(rebuild.count(&lo, &hi));
            })
        });
        lines.push(Line {
            group,
            name: format!("grid vs Bvh rebuilt, N = {n}"),
            n,
            ns: one,
            peer_ns: Some(peer),
            ..Line::default()
        });
    }
}

/// The whole first-contact query (stable) on one and two threads against parry's `Bvh`
/// incremental + `cast_shapes`, in both forms of the answer (`first_contacts_into`, 128 bytes
/// per sphere; `first_contacts_compact_into`, 8), with the memory the query holds per sphere.
fn query(
    lines: &mut Vec<Line>,
    spheres: SphereStore,
    phi: f64,
    t_max: f32,
    pools: &Pools,
    Timing { rounds, min }: Timing,
) {
    let n = spheres.len();
    let memory = memory_probe::measure(n, phi);
    let scene = Scene {
        spheres,
        ..Scene::default()
    };
    let options = QueryOptions::new(t_max, Accuracy::Stable).expect("valid window");
    let (mut query, mut firsts) = (SceneQuery::new(), Vec::new());
    let (mut query2, mut firsts2) = (SceneQuery::new(), Vec::new());
    let (mut compact, mut hits) = (SceneQuery::new(), Vec::new());
    let (mut compact2, mut hits2) = (SceneQuery::new(), Vec::new());
    let mut parry = ParryQuery::new();
    let mut out = vec![0.0f32; n];
    let [one, two, compact_one, compact_two, peer] = interleaved::best_ns(
        n,
        rounds,
        [
            Timed {
                pool: &pools.one,
                min,
                work: &mut || {
                    query.first_contacts_into(&scene, options, &mut firsts);
                    black_box(&firsts);
                },
            },
            Timed {
                pool: &pools.two,
                min,
                work: &mut || {
                    query2.first_contacts_into(&scene, options, &mut firsts2);
                    black_box(&firsts2);
                },
            },
            Timed {
                pool: &pools.one,
                min,
                work: &mut || {
                    compact.first_contacts_compact_into(&scene, options, &mut hits);
                    black_box(&hits);
                },
            },
            Timed {
                pool: &pools.two,
                min,
                work: &mut || {
                    compact2.first_contacts_compact_into(&scene, options, &mut hits2);
                    black_box(&hits2);
                },
            },
            Timed {
                pool: &pools.one,
                min: Duration::ZERO,
                work: &mut || {
                    black_box(parry.first_contacts(&scene.spheres, t_max, &mut out));
                },
            },
        ],
    );
    let memory_note = match &memory {
        Ok(m) => format!("; {m}"),
        Err(e) => format!("; memory not measured: {e}"),
    };
    let group = format!(
        "whole query: first contact per sphere (stable, uniform gas, phi {phi}, half a radius of travel)"
    );
    let line = |name: String, ns: f64, threads: usize, note: String| Line {
        group: group.clone(),
        name,
        n,
        ns,
        peer_ns: Some(peer),
        note,
        threads,
        ..Line::default()
    };
    lines.push(Line {
        memory: memory.ok(),
        ..line(
            format!("N = {n}"),
            one,
            1,
            format!("parry Bvh incremental + cast_shapes{memory_note}"),
        )
    });
    lines.push(line(
        format!("N = {n}, 2 threads"),
        two,
        2,
        speed_up(one, two),
    ));
    lines.push(line(
        format!("N = {n}, compact answer"),
        compact_one,
        1,
        "first_contacts_compact_into: 8 bytes per sphere".into(),
    ));
    lines.push(line(
        format!("N = {n}, compact answer, 2 threads"),
        compact_two,
        2,
        speed_up(compact_one, compact_two),
    ));
}
