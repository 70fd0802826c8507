//! What a whole-scene query will hold at its peak, estimated before it runs, so that a caller
//! can refuse one too large for memory instead of being aborted part way through.
//!
//! The query never holds its candidate sphere pairs (its fused pass tests them a few thousand
//! at a time, see [`crate::query`]), so its memory is [`PER_SPHERE`] bytes a sphere whatever
//! the window, plus, for [`all_contacts`](super::all_contacts), the contacts it returns. The
//! estimate counts:
//!
//! - **candidate pairs** (the work, not memory): exactly `n (n − 1) / 2` for an infinite
//!   window (an upper bound: its successive windows test fewer); otherwise from a sample of
//!   [`SAMPLE`] spheres spread evenly over the store, each tested against every sphere with
//!   the broad phase's overlap rule (swept boxes overlapping on all three axes), scaled to all
//!   `n` (exact when `n <= SAMPLE`);
//! - **contacts** (for [`all_contacts`](super::all_contacts)): the fraction of up to
//!   [`KERNEL_SAMPLE`] sampled candidate pairs that the kernel finds touching, times the
//!   candidates, plus one per sphere and shape (the most a static contact list can hold);
//! - **bytes**: [`PER_SPHERE`] a sphere and, for every contact, two [`ContactEvent`]s (the
//!   list grows by doubling).
//!
//! ```
//! use spheresweep::{QueryOptions, query::estimate};
//! let scene = spheresweep::scene::demo();
//! let e = estimate::estimate(&scene, QueryOptions::default(), false); // infinite window
//! let n = scene.spheres.len() as u64;
//! assert_eq!(e.candidate_pairs, n * (n - 1) / 2);
//! ```

use super::ContactEvent;
use crate::QueryOptions;
use crate::batch;
use crate::scene::Scene;
use crate::store::{PAD, SphereStore};

/// Spheres sampled to count candidate pairs.
pub const SAMPLE: usize = 128;
/// Sampled candidate pairs whose time the kernel computes to estimate the share that touch.
pub const KERNEL_SAMPLE: usize = 1 << 14;
/// Bytes a sphere costs the query whatever the window: the grid's keys, order, boxes and
/// cells, the records in cell order, the slots (8 bytes for each rayon thread) and the answer;
/// a bound on [`SceneQuery::heap_bytes`](super::SceneQuery::heap_bytes) per sphere (about 140
/// on one or two threads, checked by a test) up to about twenty threads.
pub const PER_SPHERE: usize = 320;

/// A query's estimated size (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Estimate {
    /// Candidate sphere pairs the narrow phase will test.
    pub candidate_pairs: u64,
    /// Contacts the answer will hold (only for every contact; 0 otherwise).
    pub contacts: u64,
    /// Peak bytes, all told.
    pub bytes: u64,
}

/// The swept box of sphere `i` over `[0, t]` as `[lo; 3, hi; 3]` (the grid's definition).
fn swept(store: &SphereStore, i: usize, t: f32) -> [f32; 6] {
    let (b, l) = (&store.blocks()[i / PAD], i % PAD);
    let mut out = [0.0; 6];
    for (a, (c, v)) in [(b.cx[l], b.vx[l]), (b.cy[l], b.vy[l]), (b.cz[l], b.vz[l])]
        .into_iter()
        .enumerate()
    {
        let e = c + v * t;
        out[a] = c.min(e) - b.r[l];
        out[a + 3] = c.max(e) + b.r[l];
    }
    out
}

/// The spheres whose swept boxes overlap sphere `i`'s (all of them for an infinite window).
fn partners(store: &SphereStore, i: usize, t: f32) -> impl Iterator<Item = usize> + '_ {
    let me = swept(store, i, t);
    (0..store.len()).filter(move |&j| {
        if j == i {
            return false;
        }
        if !t.is_finite() {
            return true;
        }
        let other = swept(store, j, t);
        (0..3).all(|a| me[a] <= other[a + 3] && other[a] <= me[a + 3])
    })
}

/// The estimated size of a first-contact query (`every_contact` false) or an every-contact
/// query (true) of `scene` with `options`.
pub fn estimate(scene: &Scene, options: QueryOptions, every_contact: bool) -> Estimate {
    let store = &scene.spheres;
    let n = store.len();
    let t = options.t_max();
    let all_pairs = (n as u64) * (n.saturating_sub(1) as u64) / 2;
    let rows: Vec<usize> = if n <= SAMPLE {
        (0..n).collect()
    } else {
        (0..SAMPLE).map(|k| k * n / SAMPLE).collect()
    };
    let candidate_pairs = if !t.is_finite() || n < 2 {
        all_pairs
    } else {
        let degrees: u64 = rows
            .iter()
            .map(|&i| partners(store, i, t).count() as u64)
            .sum();
        // Each pair is seen from both ends: n / rows sampled degrees, halved.
        ((degrees as f64) * (n as f64) / (2.0 * rows.len() as f64)).round() as u64
    };
    let contacts = if every_contact {
        let shapes = scene.statics.len();
        touching_share(store, &rows, options, candidate_pairs) + (n as u64) * (shapes as u64)
    } else {
        0
    };
    let event = 2 * std::mem::size_of::<ContactEvent>() as u64;
    let bytes = (n as u64)
        .saturating_mul(PER_SPHERE as u64)
        .saturating_add(contacts.saturating_mul(event));
    Estimate {
        candidate_pairs,
        contacts,
        bytes,
    }
}

/// Of `candidates` pairs, how many the kernel finds touching: the share among sampled pairs.
fn touching_share(
    store: &SphereStore,
    rows: &[usize],
    options: QueryOptions,
    candidates: u64,
) -> u64 {
    let t = options.t_max();
    let per_row = (KERNEL_SAMPLE / rows.len().max(1)).max(1);
    let pairs: Vec<[u32; 2]> = rows
        .iter()
        .flat_map(|&i| {
            partners(store, i, t)
                .take(per_row)
                .map(move |j| [i.min(j) as u32, i.max(j) as u32])
        })
        .collect();
    if pairs.is_empty() {
        return 0;
    }
    let mut times = vec![0.0; pairs.len()];
    batch::pair_times(store, &pairs, options, &mut times).expect("sampled pairs are in range");
    let touching = times.iter().filter(|t| t.is_finite()).count() as f64;
    (touching / pairs.len() as f64 * candidates as f64).ceil() as u64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::query::SceneQuery;
    use crate::rng::Rng;
    use crate::{Accuracy, Plane, Sphere};

    /// `n` spheres of radius 0.3 in a cube of side `side`, velocity components in ±1.
    fn gas(n: usize, side: f32, seed: u64) -> Scene {
        let mut rng = Rng::new(seed);
        let mut u = |a: f32, b: f32| rng.range(f64::from(a), f64::from(b)) as f32;
        let spheres: Vec<Sphere> = (0..n)
            .map(|_| {
                let c = [u(0.0, side), u(0.0, side), u(0.0, side)];
                let v = [u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0)];
                Sphere::new(c, v, 0.3, 1.0).expect("valid")
            })
            .collect();
        Scene {
            spheres: SphereStore::from_spheres(&spheres),
            statics: crate::Statics::new()
                .with(Plane::new([0.0; 3], [0.0, 0.0, 1.0]).expect("valid"), ()),
        }
    }

    fn options(t: f32) -> QueryOptions {
        QueryOptions::new(t, Accuracy::Stable).expect("valid")
    }

    #[test]
    fn candidate_pairs_are_those_the_query_tests() {
        for (n, side, t) in [
            (100, 10.0, 1.0),
            (5000, 40.0, 0.5),
            (5000, 40.0, 8.0),
            (3000, 10.0, 30.0),
        ] {
            let scene = gas(n, side, n as u64);
            let mut query = SceneQuery::new();
            let found = query.all_contacts(&scene, options(t)).len() as f64;
            let real = query.stats().candidate_pairs as f64;
            let e = estimate(&scene, options(t), true);
            let ratio = e.candidate_pairs as f64 / real;
            // Exact below SAMPLE spheres; a sample of 128 within 25 % above it.
            if n <= SAMPLE {
                assert_eq!(e.candidate_pairs as f64, real);
            }
            assert!(
                (0.75..1.25).contains(&ratio),
                "n {n} t {t}: {} vs {real}",
                e.candidate_pairs
            );
            // Contacts: at least the ones found (the static bound is generous), within 3×.
            assert!(
                e.contacts as f64 >= 0.75 * found
                    && (e.contacts as f64) < 3.0 * found + 2.0 * n as f64,
                "n {n} t {t}: {} contacts estimated, {found} found",
                e.contacts
            );
        }
    }

    #[test]
    fn an_infinite_window_counts_every_pair_but_holds_none() {
        let scene = gas(1000, 20.0, 5);
        let e = estimate(&scene, options(f32::INFINITY), false);
        assert_eq!(e.candidate_pairs, 1000 * 999 / 2);
        assert_eq!(e.bytes, 1000 * PER_SPHERE as u64);
        let mut query = SceneQuery::new();
        query.first_contacts(&scene, options(f32::INFINITY));
        let tested = query.stats().candidate_pairs as u64;
        assert!(tested <= e.candidate_pairs * 2, "{tested} pairs tested");
        assert!(
            query.heap_bytes() as u64 <= e.bytes,
            "{} bytes held",
            query.heap_bytes()
        );
    }

    #[test]
    fn the_bytes_per_sphere_bound_the_query_at_every_window() {
        for (n, t) in [(3000, 0.5), (3000, 30.0), (20_000, 0.5), (20_000, 1e6)] {
            let scene = gas(n, 20.0 * (n as f32 / 1000.0).cbrt(), 9);
            let mut query = SceneQuery::new();
            query.first_contacts(&scene, options(t));
            query.all_contacts(&scene, options(t.min(1.0)));
            let held = query.heap_bytes();
            assert!(held <= n * PER_SPHERE, "n {n} t {t}: {held} bytes held");
        }
    }
}
