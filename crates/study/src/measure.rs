//! Error measures per path (accuracy mode or parry3d) and family against the exact oracle,
//! and throughput measured in the same run.

use std::time::Instant;

use rayon::prelude::*;

use super::condition::{condition, ulp32};
use super::families::Family;
use super::oracle::Exact;
use super::pair::{Case, Pair, case_times};
use spheresweep::rng::Rng;
use spheresweep::{Accuracy, Shape, SphereStore};
use spheresweep::{QueryOptions, batch};

/// A way to answer a pair: one of our accuracy modes, or parry3d.
///
/// ```
/// use spheresweep::Accuracy;
/// use spheresweep_study::Path;
/// assert_eq!(Path::ALL.len(), 4); // three modes and parry3d
/// assert_eq!(Path::Mode(Accuracy::Stable).name(), "stable");
/// ```
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
    ///
    /// ```
    /// assert_eq!(spheresweep_study::Path::Parry.name(), "parry3d");
    /// ```
    pub fn name(self) -> &'static str {
        match self {
            Path::Mode(m) => m.name(),
            Path::Parry => "parry3d",
        }
    }
}

/// Percentiles of a sample.
///
/// ```
/// use spheresweep_study::Summary;
/// let s = Summary::of((1..=100).map(f64::from).collect());
/// assert_eq!((s.p50, s.p99, s.max, s.count), (51.0, 99.0, 100.0, 100)); // nearest rank
/// ```
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
    ///
    /// ```
    /// use spheresweep_study::Summary;
    /// assert_eq!(Summary::of(vec![3.0, 1.0, 2.0]).p50, 2.0);
    /// assert_eq!(Summary::of(Vec::new()), Summary::default());
    /// ```
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
///
/// ```
/// use spheresweep::Accuracy;
/// use spheresweep_study::{Family, Path, measure_family};
/// let result = measure_family(Family::Baseline, 0, 100, 1);
/// let stable = result.paths.iter().find(|r| r.path == Path::Mode(Accuracy::Stable)).unwrap();
/// assert_eq!(stable.cases, 100);
/// assert_eq!(stable.wrong_outside_band, 0); // every wrong answer lies in the stated band
/// ```
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
    /// Answers of `0` where the oracle's time is above 0 or there is no contact: a false
    /// contact at `t = 0` (counted among the wrong answers when the oracle says no contact).
    pub false_zero: usize,
    /// `|t − t*|` in f32 ulps of `t*`, over pairs both call hits with `t* > 0`.
    pub time_ulps: Summary,
    /// `|t − t*| / κ` (ulps per unit of the condition number, [`crate::condition`](mod@crate::condition)) over the
    /// same pairs among the first [`CONDITION_CASES`] cases, where `κ` is finite: about the
    /// number of ulps each input would have to move for the answer to be exact. Small on an
    /// ill-conditioned family answered by an accurate kernel.
    pub time_per_condition: Summary,
    /// `|t − t*| / t*` over the same pairs.
    pub time_rel: Summary,
    /// `|dist(t) − D| / (u · (coordinates + D))` at the reported time: the geometric error in
    /// units of the f32 rounding of the scene's coordinates.
    pub gap_coord: Summary,
    /// `|dist(t) − D| / D` at the reported time.
    pub gap_rel: Summary,
}

/// Every path's result on one family at one difficulty.
///
/// ```
/// use spheresweep_study::{Family, Path, measure_family};
/// let result = measure_family(Family::Grazing, 3, 50, 1);
/// assert_eq!((result.family, result.level), (Family::Grazing, 3));
/// assert_eq!(result.paths.len(), Path::ALL.len());
/// assert!(result.condition.count + result.unbounded <= 50);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyResult {
    /// The family.
    pub family: Family,
    /// Its difficulty `k`.
    pub level: u32,
    /// One result per path, in [`Path::ALL`] order.
    pub paths: Vec<PathResult>,
    /// The finite condition numbers `κ` of the cases with a contact ahead among the first
    /// [`CONDITION_CASES`].
    pub condition: Summary,
    /// Of those cases, how many have `κ = +∞` (a one-ulp change of one input loses the
    /// contact).
    pub unbounded: usize,
}

/// The condition number is estimated on the first this many cases of each family and level
/// (about 20 exact solves per case).
pub const CONDITION_CASES: usize = 2000;

/// f32 unit roundoff.
pub const U32: f64 = 1.0 / (1u64 << 24) as f64;
/// f64 unit roundoff.
pub const U64: f64 = 1.0 / (1u64 << 53) as f64;

/// The band of grazing margins `|D − d_min|` inside which `path` may give the wrong hit/miss
/// answer (docs/derivations/accuracy.md): `Stable` `8u(X + D)`, `Double` `8u₆₄(X + D)`,
/// `Textbook` `4u(X² + D²)/D`. parry3d is given no band.
///
/// ```
/// # use spheresweep::{Sphere, reference::Pair};
/// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
/// let pair = Pair {
///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
/// };
/// use spheresweep::Accuracy;
/// use spheresweep_study::{Path, band, measure::U32};
/// // stable: 8u(X + D), X = ‖r_B0 − r_A0‖ = 10, D = 2.
/// assert_eq!(band(Path::Mode(Accuracy::Stable), &pair, 2.0), 8.0 * U32 * 12.0);
/// assert_eq!(band(Path::Parry, &pair, 2.0), 0.0);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
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

/// The band of contact times around the window's end inside which `path` may give the wrong
/// hit/miss answer, in ulps of the contact time, for a case of condition number `kappa`: a
/// kernel whose answer is the exact time of its inputs moved by up to 8 of its own roundings
/// each is off by up to `8κ` ulps (`8κ u₆₄/u` for `double`), plus the final rounding of an
/// f32 time. parry3d is given no band.
///
/// ```
/// use spheresweep::Accuracy;
/// use spheresweep_study::{Path, window_band};
/// assert_eq!(window_band(Path::Mode(Accuracy::Stable), 1.0), 9.0); // 8κ + 1
/// assert_eq!(window_band(Path::Parry, 1.0), 0.0);
/// ```
pub fn window_band(path: Path, kappa: f64) -> f64 {
    match path {
        Path::Mode(Accuracy::Double) => 8.0 * kappa * U64 / U32,
        Path::Mode(_) => 8.0 * kappa + 1.0,
        Path::Parry => 0.0,
    }
}

/// Whether a wrong hit/miss answer of `path` on `case` lies outside the path's band: the
/// closest approach is farther from grazing than [`band`], and the unwindowed contact time is
/// farther from the window's end than [`window_band`] (with `kappa`, the case's condition
/// number if already known: it is estimated here otherwise).
///
/// ```
/// # use spheresweep::{Sphere, reference::Pair};
/// // B 10 ahead of A and closing at speed 2, contact distance 2: contact at t = 4.
/// let pair = Pair {
///     sphere: Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?,
///     other: Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?.into(),
/// };
/// use spheresweep::Accuracy;
/// use spheresweep_study::{Case, Exact, Path, wrong_outside_band};
/// let stable = Path::Mode(Accuracy::Stable);
/// // Head-on, 2 from grazing, an open window: a wrong answer here would be outside the band.
/// assert!(wrong_outside_band(stable, &Case::open(pair), &Exact::of(&pair), None));
/// // Exactly grazing: inside it.
/// let aside = Sphere::new([10.0, 2.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?;
/// let grazing = Pair { other: aside.into(), ..pair };
/// assert!(!wrong_outside_band(stable, &Case::open(grazing), &Exact::of(&grazing), None));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn wrong_outside_band(path: Path, case: &Case, exact: &Exact, kappa: Option<f64>) -> bool {
    let d = exact.contact_distance().abs();
    if exact.grazing_margin() <= band(path, &case.pair, d) {
        return false;
    }
    if case.t_max.is_finite()
        && let Some(t) = exact.time(f64::INFINITY)
        && t > 0.0
    {
        let kappa = kappa
            .or_else(|| condition(&case.pair))
            .unwrap_or(f64::INFINITY);
        let window = f64::from(case.t_max);
        if (t - window).abs() <= window_band(path, kappa) * ulp32(t) {
            return false;
        }
    }
    true
}

/// Measures every path on `n` cases of `family` at difficulty `level`, each on its own window.
///
/// ```
/// use spheresweep_study::{Family, Path, measure_family};
/// let result = measure_family(Family::ContainerWall, 2, 40, 7);
/// let parry = result.paths.iter().find(|r| r.path == Path::Parry).unwrap();
/// assert_eq!(parry.cases, 0); // parry3d has no container
/// assert!(result.paths.iter().filter(|r| r.path != Path::Parry).all(|r| r.cases == 40));
/// ```
pub fn measure_family(family: Family, level: u32, n: usize, seed: u64) -> FamilyResult {
    let mut rng = Rng::new(seed ^ (family as u64) << 32 ^ u64::from(level));
    let cases: Vec<Case> = (0..n).map(|_| family.case(&mut rng, level)).collect();
    let exact: Vec<Exact> = cases.par_iter().map(|c| Exact::of(&c.pair)).collect();
    let truth: Vec<Option<f64>> = exact
        .iter()
        .zip(&cases)
        .map(|(e, c)| e.time(f64::from(c.t_max)))
        .collect();
    let kappa: Vec<Option<f64>> = cases[..n.min(CONDITION_CASES)]
        .par_iter()
        .map(|c| condition(&c.pair))
        .collect();
    let paths = Path::ALL
        .into_iter()
        .map(|path| {
            let answers: Vec<Option<Option<f32>>> = match path {
                Path::Mode(mode) => case_times(&cases, mode).into_iter().map(Some).collect(),
                Path::Parry => cases.iter().map(Case::parry).collect(),
            };
            score(path, &cases, &exact, &truth, &answers, &kappa)
        })
        .collect();
    let finite: Vec<f64> = kappa
        .iter()
        .flatten()
        .copied()
        .filter(|k| k.is_finite())
        .collect();
    let unbounded = kappa.iter().flatten().filter(|k| k.is_infinite()).count();
    FamilyResult {
        family,
        level,
        paths,
        condition: Summary::of(finite),
        unbounded,
    }
}

fn score(
    path: Path,
    cases: &[Case],
    exact: &[Exact],
    truth: &[Option<f64>],
    answers: &[Option<Option<f32>>],
    kappa: &[Option<f64>],
) -> PathResult {
    let (mut count, mut wrong, mut outside, mut false_zero) = (0, 0, 0, 0);
    let (mut ulps, mut per_kappa, mut rel) = (Vec::new(), Vec::new(), Vec::new());
    let (mut gap_coord, mut gap_rel) = (Vec::new(), Vec::new());
    for (i, (((case, ex), t_true), answer)) in
        cases.iter().zip(exact).zip(truth).zip(answers).enumerate()
    {
        let Some(answer) = answer else { continue };
        count += 1;
        let known = kappa.get(i).map(|k| k.unwrap_or(f64::INFINITY));
        if *answer == Some(0.0) && *t_true != Some(0.0) {
            false_zero += 1;
        }
        match (t_true, answer) {
            (Some(t), Some(k)) => {
                let k = f64::from(*k);
                if *t > 0.0 {
                    let e = (k - t).abs() / ulp32(*t);
                    ulps.push(e);
                    if let Some(kap) = known.filter(|k| k.is_finite() && *k > 0.0) {
                        per_kappa.push(e / kap);
                    }
                    rel.push((k - t).abs() / t);
                    let d = ex.contact_distance().abs();
                    let gap = ex.gap(k).abs();
                    gap_coord.push(gap / (U32 * (case.pair.coordinate_scale(k) + d)));
                    if d > 0.0 {
                        gap_rel.push(gap / d);
                    }
                }
            }
            (None, None) => {}
            _ => {
                wrong += 1;
                if wrong_outside_band(path, case, ex, known) {
                    outside += 1;
                }
            }
        }
    }
    PathResult {
        path,
        cases: count,
        wrong,
        wrong_outside_band: outside,
        false_zero,
        time_ulps: Summary::of(ulps),
        time_per_condition: Summary::of(per_kappa),
        time_rel: Summary::of(rel),
        gap_coord: Summary::of(gap_coord),
        gap_rel: Summary::of(gap_rel),
    }
}

/// Pairs per second of every path on `n` baseline sphere pairs held in cache, one thread:
/// each timing evaluates the batch `inner` times (parry3d, `inner / 16` times, through
/// `query::cast_shapes` on shapes built beforehand); the best of `repeats` timings counts.
///
/// ```
/// use spheresweep_study::{Path, throughput};
/// let rates = throughput(64, 2, 1, 7);
/// assert_eq!(rates.iter().map(|(p, _)| *p).collect::<Vec<_>>(), Path::ALL);
/// assert!(rates.iter().all(|(_, r)| *r > 0.0));
/// ```
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
