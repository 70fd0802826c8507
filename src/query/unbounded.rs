//! Sphere pairs over an infinite window (`t_max = ∞`), where swept boxes are unbounded and no
//! grid can cull, in memory linear in the number of spheres and with the brute force's bits.
//!
//! **First contacts: successive windows.** A round runs the fused grid pass over the window
//! `[0, T]`. Every pair time the kernel reports below `T` in an infinite window it also
//! reports in `[0, T]`, with the same bits (the f32 path filters its time by `t ≤ T`; the f64
//! rescue filters `t64 ≤ T`, and `f32(t64) < T` implies `t64 < T` because rounding is
//! monotone and `T` is an f32). So a sphere whose earliest contact after a round is *below*
//! `T` has its final answer, ties included: a contact at `T` or later cannot be earlier, nor
//! tie. `T` starts at the time a typical sphere takes to travel its radius and doubles while
//! the next round is expected to cost less than the rows it saves (it closes about as many
//! spheres as the last). Then each sphere still open is tested against every sphere, as the
//! brute force does (one row of `N` times per thread).
//!
//! **All contacts**: the brute force's rows, on rayon; memory is the contacts found plus one
//! row per thread.

use rayon::prelude::*;

use super::compact::CompactContact;
use super::fused::sphere_event;
use super::{ContactEvent, SceneQuery};
use crate::batch::{QueryOptions, one_against_times};
use crate::store::SphereStore;

impl SceneQuery {
    /// Each sphere's earliest contact with another sphere in an infinite window, offered to
    /// `out` (scene order). Returns the pairs tested (candidates of the rounds plus rows).
    pub(super) fn sphere_firsts_unbounded(
        &mut self,
        store: &SphereStore,
        options: QueryOptions,
        out: &mut [CompactContact],
    ) -> usize {
        let n = store.len();
        let mut window = first_window(store);
        let reach = Reach::of(store);
        let (mut tested, mut before) = (0, n);
        let open = loop {
            let round = QueryOptions::new(window, options.accuracy())
                .expect("a finite window >= 0")
                .with_geometry(false);
            let candidates = self.sphere_firsts_in_window(store, round, out);
            tested += candidates;
            let open = out.iter().filter(|c| !final_below(**c, window)).count();
            let closed = before - open;
            before = open;
            let next = window * 2.0;
            // The next round costs its grid and more candidates than this one (up to 8×: a
            // swept box's volume grows as T³); it pays if it closes about as many spheres as
            // this one did, each of which would otherwise cost a row of `n`.
            let next_cost =
                (ROUND_COST * n) as u128 + 4 * (CANDIDATE_COST as u128) * candidates as u128;
            let rows_saved = closed as u128 * n as u128;
            if open == 0 || !reach.finite_at(next) || next_cost >= rows_saved {
                break open;
            }
            window = next;
        };
        if open > 0 {
            tested += open * n;
            self.finish_rows(store, options, window, out);
        }
        tested
    }

    /// The spheres not final after the last round (window `window`), each against every
    /// sphere in the infinite window.
    fn finish_rows(
        &self,
        store: &SphereStore,
        options: QueryOptions,
        window: f32,
        out: &mut [CompactContact],
    ) {
        let open: Vec<u32> = (0..out.len() as u32)
            .filter(|&i| !final_below(out[i as usize], window))
            .collect();
        let rows: Vec<CompactContact> = open
            .par_iter()
            .with_min_len(16)
            .map_init(
                || vec![0.0f32; store.len()],
                |times, &i| earliest_in_row(store, i, options, times),
            )
            .collect();
        for (&i, row) in open.iter().zip(rows) {
            out[i as usize] = out[i as usize].min(row);
        }
    }

    /// Every sphere–sphere contact in an infinite window, appended to `events` (unsorted).
    /// Returns the pairs tested.
    pub(super) fn sphere_contacts_unbounded(
        &self,
        store: &SphereStore,
        options: QueryOptions,
        events: &mut Vec<ContactEvent>,
    ) -> usize {
        let n = store.len();
        let rows: Vec<Vec<ContactEvent>> = (0..n as u32)
            .into_par_iter()
            .with_min_len(16)
            .map_init(
                || vec![0.0f32; n],
                |times, i| {
                    let sphere = store.get(i as usize).expect("a sphere of the store");
                    one_against_times(&sphere, store, options, times).expect("one slot each");
                    let later = times.iter().enumerate().skip(i as usize + 1);
                    later
                        .filter(|(_, t)| t.is_finite())
                        .map(|(j, &t)| sphere_event(i, j as u32, t))
                        .collect()
                },
            )
            .collect();
        events.extend(rows.into_iter().flatten());
        n * n.saturating_sub(1) / 2
    }
}

/// A round's grid costs about this many pair tests of a row per sphere (measured: about 50 ns
/// a sphere against 1.5 ns a pair of a row, whose spheres are read in order).
const ROUND_COST: usize = 30;
/// A candidate pair of a round costs about this many pair tests of a row (measured with
/// `examples/unbounded_window`: about 7 ns, listed and gathered, against 1.5 ns).
const CANDIDATE_COST: usize = 5;

/// How far any sphere's swept box reaches from the origin, per unit of window: a round's
/// window must keep every box finite (the grid's cells are computed in f32).
struct Reach {
    /// The largest `|c| + r` over coordinates and spheres.
    at_rest: f32,
    /// The largest `|v|` over coordinates and spheres.
    speed: f32,
}

impl Reach {
    fn of(store: &SphereStore) -> Reach {
        let (mut at_rest, mut speed) = (0.0f32, 0.0f32);
        for s in store.iter() {
            let (c, v) = (
                s.centre().abs().max_element(),
                s.velocity().abs().max_element(),
            );
            at_rest = at_rest.max(c + s.radius());
            speed = speed.max(v);
        }
        Reach { at_rest, speed }
    }

    /// Whether every swept box over `[0, window]` stays finite, with a factor of two to spare.
    fn finite_at(&self, window: f32) -> bool {
        (2.0 * (self.at_rest + self.speed * window)).is_finite()
    }
}

/// Whether `c` is a contact strictly before `window` (then it is final; see the module docs).
fn final_below(c: CompactContact, window: f32) -> bool {
    c.time().is_some_and(|t| t < window)
}

/// Sphere `i`'s earliest contact with any sphere of `store` (`times`: one slot per sphere).
fn earliest_in_row(
    store: &SphereStore,
    i: u32,
    options: QueryOptions,
    times: &mut [f32],
) -> CompactContact {
    let sphere = store.get(i as usize).expect("a sphere of the store");
    one_against_times(&sphere, store, options, times).expect("one slot each");
    times
        .iter()
        .enumerate()
        .filter(|(_, t)| t.is_finite())
        .map(|(j, &t)| CompactContact::sphere(t, j as u32))
        .min()
        .unwrap_or(CompactContact::NONE)
}

/// The first round's window: the time a sphere of mean radius takes to travel its radius at
/// the root-mean-square speed (`1` when nothing moves).
fn first_window(store: &SphereStore) -> f32 {
    let n = store.len().max(1) as f64;
    let (mut r, mut v2) = (0.0f64, 0.0f64);
    for s in store.iter() {
        r += f64::from(s.radius());
        v2 += f64::from(s.velocity().length_squared());
    }
    let (r, speed) = (r / n, (v2 / n).sqrt());
    let t = (r / speed) as f32;
    if t.is_finite() && t > 0.0 { t } else { 1.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Accuracy;
    use crate::scene::Scene;

    /// A cloud expanding from a ball: near pairs meet early, most never; and far away two
    /// spheres closing so slowly that they meet only after every round (the rows find them).
    fn expanding(n: usize, seed: u64) -> Scene {
        let mut rng = crate::rng::Rng::new(seed);
        let slow = [
            crate::Sphere::new([1e4, 0.0, 0.0], [1e-6, 0.0, 0.0], 0.5, 1.0).unwrap(),
            crate::Sphere::new([1e4 + 3.0, 0.0, 0.0], [0.0; 3], 0.5, 1.0).unwrap(),
        ];
        let spheres: Vec<_> = slow
            .into_iter()
            .chain((2..n).map(|_| {
                let c = rng.cube(10.0);
                let v = rng.direction() * rng.range(0.0, 2.0) + c * 0.1;
                let r = rng.range(0.1, 0.4) as f32;
                crate::Sphere::new(c.as_vec3().to_array(), v.as_vec3().to_array(), r, 1.0).unwrap()
            }))
            .collect();
        super::super::scene_of(&spheres)
    }

    #[test]
    fn a_window_stops_growing_before_a_box_would_overflow() {
        let store = SphereStore::from_spheres(&[crate::Sphere::new(
            [1e30, 0.0, 0.0],
            [1e8, 0.0, 0.0],
            1.0,
            1.0,
        )
        .unwrap()]);
        let reach = Reach::of(&store);
        assert!(reach.finite_at(1e20) && !reach.finite_at(1e31));
    }

    #[test]
    fn successive_windows_give_the_brute_forces_bits() {
        for (n, seed) in [(2, 1), (50, 2), (700, 3)] {
            let scene = expanding(n, seed);
            for accuracy in [Accuracy::Textbook, Accuracy::Stable, Accuracy::Double] {
                let options = QueryOptions::new(f32::INFINITY, accuracy).unwrap();
                let mut out = vec![CompactContact::NONE; n];
                SceneQuery::new().sphere_firsts_unbounded(&scene.spheres, options, &mut out);
                let brute = super::super::brute_force::first_contacts(&scene, options);
                let open = out.iter().filter(|c| c.is_none()).count();
                assert!(
                    n < 700 || (open > 0 && open < n),
                    "{open} of {n} never touch"
                );
                let slow = out[0].get().expect("the slow pair meets");
                assert!(slow.0 > 1e6 && slow.1.index == 1, "the slow pair: {slow:?}");
                for (i, (c, b)) in out.iter().zip(&brute).enumerate() {
                    assert_eq!(c.get(), b.map(|b| (b.time, b.body)), "sphere {i} of {n}");
                }
            }
        }
    }
}
