//! Error measures per path (accuracy mode or parry3d) and family against the exact oracle,
//! and throughput measured in the same run.

use std::time::Instant;

use super::families::Family;
use super::oracle::Exact;
use super::pair::{Pair, Paths, kernel_times};
use spheresweep::rng::Rng;
use spheresweep::{Accuracy, Shape, SphereStore};
use spheresweep::{QueryOptions, batch};

/// A way to answer a pair: one of our accuracy modes, or parry3d.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Path {
    /// An 8-wide kernel in this mode.
    Mode(Accuracy),
    /// parry3d 0.31 `query::cast_shapes`.
    Parry,
}

impl Path {
    /// Every path, in table order.
    pub const ALL: [Path; 4] = [
        Path::Mode(Accuracy::Textbook),
        Path::Mode(Accuracy::Stable),
        Path::Mode(Accuracy::Double),
        Path::Parry,
    ];
    /// Name for tables.
    pub fn name(self) -> &'static str {
        match self {
            Path::Mode(m) => m.name(),
            Path::Parry => "parry3d",
        }
    }
}

/// Percentiles of a sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Summary {
    /// Median.
    pub p50: f64,
    /// 99th percentile.
    pub p99: f64,
    /// Largest value.
    pub max: f64,
    /// Sample size.
    pub count: usize,
}

impl Summary {
    /// Percentiles of `values` (all zero for an empty sample).
    pub fn of(mut values: Vec<f64>) -> Self {
        if values.is_empty() {
            return Self::default();
        }
        values.sort_by(f64::total_cmp);
        let at = |p: f64| values[((values.len() - 1) as f64 * p).round() as usize];
        Self {
            p50: at(0.5),
            p99: at(0.99),
            max: *values.last().expect("non-empty"),
            count: values.len(),
        }
    }
}

/// How one path did on one family.
#[derive(Debug, Clone, PartialEq)]
pub struct PathResult {
    /// Which path.
    pub path: Path,
    /// Pairs it could answer (parry has no container).
    pub cases: usize,
    /// Hit/miss answers that differ from the oracle.
    pub wrong: usize,
    /// Of those, how many lie outside the path's stated band of ill-conditioning.
    pub wrong_outside_band: usize,
    /// `|t − t*|` in f32 ulps of `t*`, over pairs both call hits with `t* > 0`.
    pub time_ulps: Summary,
    /// `|t − t*| / t*` over the same pairs.
    pub time_rel: Summary,
    /// `|dist(t) − D| / (u · (coordinates + D))` at the reported time: the geometric error in
    /// units of the f32 rounding of the scene's coordinates.
    pub gap_coord: Summary,
    /// `|dist(t) − D| / D` at the reported time.
    pub gap_rel: Summary,
}

/// Every path's result on one family at one difficulty.
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyResult {
    /// The family.
    pub family: Family,
    /// Its difficulty `k`.
    pub level: u32,
    /// One result per path, in [`Path::ALL`] order.
    pub paths: Vec<PathResult>,
}

/// f32 unit roundoff.
pub const U32: f64 = 1.0 / (1u64 << 24) as f64;
/// f64 unit roundoff.
pub const U64: f64 = 1.0 / (1u64 << 53) as f64;

/// The band of grazing margins `|D − d_min|` inside which `path` may give the wrong hit/miss
/// answer (docs/derivations/accuracy.md): `Stable` `8u(X + D)`, `Double` `8u₆₄(X + D)`,
/// `Textbook` `4u(X² + D²)/D`. parry3d is given no band.
pub fn band(path: Path, pair: &Pair, d: f64) -> f64 {
    match path {
        Path::Mode(Accuracy::Stable) => 8.0 * U32 * (pair.operand_scale(Accuracy::Stable) + d),
        Path::Mode(Accuracy::Double) => 8.0 * U64 * (pair.operand_scale(Accuracy::Double) + d),
        Path::Mode(Accuracy::Textbook) => {
            let x = pair.operand_scale(Accuracy::Textbook);
            4.0 * U32 * (x * x + d * d) / d.abs().max(f64::MIN_POSITIVE)
        }
        Path::Parry => 0.0,
    }
}

fn ulp32(t: f64) -> f64 {
    let f = t as f32;
    f64::from(f32::from_bits(f.to_bits() + 1) - f)
}

/// Measures every path on `n` pairs of `family` at difficulty `level` (window `[0, ∞)`).
pub fn measure_family(family: Family, level: u32, n: usize, seed: u64) -> FamilyResult {
    let mut rng = Rng::new(seed ^ (family as u64) << 32 ^ u64::from(level));
    let pairs: Vec<Pair> = (0..n).map(|_| family.generate(&mut rng, level)).collect();
    let exact: Vec<Exact> = pairs.iter().map(Exact::of).collect();
    let truth: Vec<Option<f64>> = exact.iter().map(|e| e.time(f64::INFINITY)).collect();
    let paths = Path::ALL
        .into_iter()
        .map(|path| {
            let answers: Vec<Option<Option<f32>>> = match path {
                Path::Mode(mode) => kernel_times(&pairs, mode, f32::INFINITY)
                    .into_iter()
                    .map(Some)
                    .collect(),
                Path::Parry => pairs.iter().map(|p| p.parry(f32::MAX)).collect(),
            };
            score(path, &pairs, &exact, &truth, &answers)
        })
        .collect();
    FamilyResult {
        family,
        level,
        paths,
    }
}

fn score(
    path: Path,
    pairs: &[Pair],
    exact: &[Exact],
    truth: &[Option<f64>],
    answers: &[Option<Option<f32>>],
) -> PathResult {
    let (mut cases, mut wrong, mut outside) = (0, 0, 0);
    let (mut ulps, mut rel) = (Vec::new(), Vec::new());
    let (mut gap_coord, mut gap_rel) = (Vec::new(), Vec::new());
    for (((pair, ex), t_true), answer) in pairs.iter().zip(exact).zip(truth).zip(answers) {
        let Some(answer) = answer else { continue };
        cases += 1;
        match (t_true, answer) {
            (Some(t), Some(k)) => {
                let k = f64::from(*k);
                if *t > 0.0 {
                    ulps.push((k - t).abs() / ulp32(*t));
                    rel.push((k - t).abs() / t);
                    let d = ex.contact_distance().abs();
                    let gap = ex.gap(k).abs();
                    gap_coord.push(gap / (U32 * (pair.coordinate_scale(k) + d)));
                    if d > 0.0 {
                        gap_rel.push(gap / d);
                    }
                }
            }
            (None, None) => {}
            _ => {
                wrong += 1;
                let d = ex.contact_distance().abs();
                if ex.grazing_margin() > band(path, pair, d) {
                    outside += 1;
                }
            }
        }
    }
    PathResult {
        path,
        cases,
        wrong,
        wrong_outside_band: outside,
        time_ulps: Summary::of(ulps),
        time_rel: Summary::of(rel),
        gap_coord: Summary::of(gap_coord),
        gap_rel: Summary::of(gap_rel),
    }
}

/// Pairs per second of every path on `n` baseline sphere pairs held in cache, one thread:
/// each timing evaluates the batch `inner` times (parry3d, `inner / 16` times, through
/// `query::cast_shapes` on shapes built beforehand); the best of `repeats` timings counts.
pub fn throughput(n: usize, inner: usize, repeats: usize, seed: u64) -> Vec<(Path, f64)> {
    let mut rng = Rng::new(seed);
    let pairs: Vec<Pair> = (0..n)
        .map(|_| Family::Baseline.generate(&mut rng, 0))
        .collect();
    let a: SphereStore = pairs.iter().map(|p| p.sphere).collect();
    let b: SphereStore = pairs
        .iter()
        .map(|p| match p.other {
            Shape::Sphere(s) => s,
            _ => unreachable!("baseline pairs are sphere pairs"),
        })
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread pool");
    let best = |count: usize, run: &mut dyn FnMut()| {
        (0..repeats)
            .map(|_| {
                let start = Instant::now();
                run();
                count as f64 / start.elapsed().as_secs_f64()
            })
            .fold(0.0, f64::max)
    };
    let mut out = vec![0.0f32; n];
    Path::ALL
        .into_iter()
        .map(|path| {
            let rate = match path {
                Path::Mode(mode) => {
                    let q = QueryOptions::new(f32::INFINITY, mode).expect("valid window");
                    best(n * inner, &mut || {
                        pool.install(|| {
                            for _ in 0..inner {
                                batch::zip_times(&a, &b, q, &mut out).expect("equal lengths");
                                std::hint::black_box(&mut out);
                            }
                        })
                    })
                }
                Path::Parry => {
                    use parry3d::math::Pose;
                    use parry3d::query::{ShapeCastOptions, cast_shapes};
                    use parry3d::shape::Ball;
                    // Shapes and poses built beforehand: only the cast is timed.
                    let prepared: Vec<_> = (0..n)
                        .map(|i| {
                            let (x, y) = (a.get(i).expect("i < n"), b.get(i).expect("i < n"));
                            let pose = |s: &spheresweep::Sphere| Pose::from_translation(s.centre());
                            let ball = |s: &spheresweep::Sphere| Ball::new(s.radius());
                            (
                                pose(&x),
                                x.velocity(),
                                ball(&x),
                                pose(&y),
                                y.velocity(),
                                ball(&y),
                            )
                        })
                        .collect();
                    let options = ShapeCastOptions {
                        max_time_of_impact: f32::MAX,
                        stop_at_penetration: true,
                        ..Default::default()
                    };
                    best(n * inner / 16, &mut || {
                        for _ in 0..inner / 16 {
                            for ((p1, v1, g1, p2, v2, g2), o) in prepared.iter().zip(out.iter_mut())
                            {
                                let hit = cast_shapes(p1, *v1, g1, p2, *v2, g2, options);
                                *o = hit
                                    .ok()
                                    .flatten()
                                    .map_or(f32::INFINITY, |h| h.time_of_impact);
                            }
                            std::hint::black_box(&mut out);
                        }
                    })
                }
            };
            (path, rate)
        })
        .collect()
}
