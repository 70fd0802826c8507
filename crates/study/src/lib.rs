//! The accuracy study of spheresweep: an exact oracle, hard-case families, error measures
//! per accuracy mode and family, and the published trade-off of error against throughput
//! (`spheresweep accuracy --out docs/accuracy.md --force` writes docs/accuracy.md). A
//! workspace member of its own, so that the library never compiles its oracle, plots or peer.

pub mod condition;
pub mod families;
pub mod measure;
pub mod oracle;
pub mod pair;
pub mod report;

pub use condition::{condition, ulp32};
pub use families::{Family, Scaling, scaled_case};
pub use measure::{
    CONDITION_CASES, FamilyResult, Path, PathResult, Summary, band, measure_family, throughput,
    window_band, wrong_outside_band,
};
pub use oracle::{Exact, Inputs};
pub use pair::{Case, Pair, Paths, case_times, kernel_times};
pub use report::Report;
pub use spheresweep::rng::Rng;

/// The families swept over difficulty `k = 1 ..= 6` in the report (for the offset families,
/// the scene `10¹ … 10⁶` from the origin).
pub const SWEPT: [Family; 10] = [
    Family::Grazing,
    Family::FarSmall,
    Family::FarFromPlane,
    Family::PlaneFarAnchor,
    Family::LargeOffset,
    Family::PlaneOffsetNear,
    Family::PlaneOffsetFar,
    Family::CylinderOffsetNear,
    Family::CylinderOffsetFar,
    Family::ContainerOffset,
];

/// Runs the whole study: every family at its stated difficulty, the swept families at every
/// difficulty (a quarter of the cases each), then the throughput of every path; `progress` is
/// told after each step (`done`, `total`).
///
/// ``` no_run
/// // The whole study takes minutes (`spheresweep accuracy --cases N` runs it).
/// let report = spheresweep_study::run(1000, 1, |done, total| eprintln!("{done}/{total}"));
/// assert_eq!(report.families.len(), spheresweep_study::Family::ALL.len());
/// ```
pub fn run(cases: usize, seed: u64, mut progress: impl FnMut(usize, usize)) -> Report {
    let total = Family::ALL.len() + SWEPT.len() + 1;
    let families = Family::ALL
        .into_iter()
        .enumerate()
        .map(|(i, family)| {
            let result = measure_family(family, family.stated_level(), cases, seed);
            progress(i + 1, total);
            result
        })
        .collect();
    let sweeps = SWEPT
        .into_iter()
        .enumerate()
        .flat_map(|(i, family)| {
            let levels: Vec<FamilyResult> = (1..=6)
                .map(|k| measure_family(family, k, cases.div_ceil(4), seed))
                .collect();
            progress(Family::ALL.len() + i + 1, total);
            levels
        })
        .collect();
    let throughput = throughput(4096, 1024, 15, seed);
    progress(total, total);
    Report {
        families,
        sweeps,
        throughput,
        cases,
        seed,
        machine: machine(),
        date: today(),
    }
}

/// The CPU model and core count, from /proc/cpuinfo where there is one.
fn machine() -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".to_owned());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!("{model}, {cores} cores")
}

/// Today's UTC date as `YYYY-MM-DD` (civil-from-days, no calendar crate needed for this).
fn today() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let z = (secs / 86_400) as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02}")
}
