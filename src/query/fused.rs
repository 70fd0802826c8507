//! The sphere pairs of a finite window in one fused pass: the grid hands its candidate pairs
//! on a few thousand at a time, the 8-wide pair kernel runs on them at once from the spheres
//! copied into cell order, and each hit is kept where it is needed — the earliest per sphere
//! (slots indexed by cell position, so the offers land in nearby memory) or the list of
//! contacts. No list of all candidate pairs is ever held: memory is linear in the number of
//! spheres for any window. The pass runs on rayon with the same bits for any thread count:
//! each thread keeps slots of its own, merged by `min`, and the contact list is sorted.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::compact::CompactContact;
use super::{ContactEvent, SceneQuery};
use crate::batch::{QueryOptions, pairs::listed_hits};
use crate::contact::Body;
use crate::shape::ShapeKind;
use crate::store::SphereStore;

impl SceneQuery {
    /// Each sphere's earliest contact with another sphere in the (finite) window, offered to
    /// `out` (scene order): `out[i]` becomes the lesser of what it held and that contact.
    /// Returns the number of candidate pairs.
    pub(super) fn sphere_firsts_in_window(
        &mut self,
        store: &SphereStore,
        options: QueryOptions,
        out: &mut [CompactContact],
    ) -> usize {
        let n = store.len();
        // Stages 1–2: the cells, and the records in cell order (the grid's gather copies them).
        self.grid.build_cells(store, options.t_max(), self.options);
        let candidates = if self.grid.parallel() {
            self.offer_pairs_in_parallel(n, options)
        } else {
            self.offer_pairs_in_order(n, options)
        };
        let par = self.grid.parallel();
        self.slots.scatter_min(self.grid.order(), out, par);
        candidates
    }

    /// Stage 3 on rayon: each thread keeps its hits in slots of its own (no atomics, no
    /// sharing), merged by `min` at the end.
    fn offer_pairs_in_parallel(&mut self, n: usize, options: QueryOptions) -> usize {
        let workers = rayon::current_num_threads();
        self.slots.reset_workers(n, workers);
        let (order, sorted, slots) = (self.grid.order(), self.grid.sorted_spheres(), &self.slots);
        let candidates = AtomicUsize::new(0);
        self.grid.visit_pairs(&|pairs| {
            candidates.fetch_add(pairs.len(), Ordering::Relaxed);
            let worker = rayon::current_thread_index().unwrap_or(0) % workers;
            let mut mine = slots.worker(worker);
            listed_hits(sorted, pairs, options, &mut |pair, time| {
                offer_both(&mut mine, order, pair, time);
            });
        });
        self.slots.merge_workers(n, workers);
        candidates.into_inner()
    }

    /// Stage 3 on one thread: the same offers to plain slots.
    fn offer_pairs_in_order(&mut self, n: usize, options: QueryOptions) -> usize {
        let (order, sorted) = (self.grid.order(), self.grid.sorted_spheres());
        let slots = self.slots.plain(n);
        let mut candidates = 0;
        self.grid.visit_pairs_mut(&mut |pairs| {
            candidates += pairs.len();
            listed_hits(sorted, pairs, options, &mut |pair, time| {
                offer_both(slots, order, pair, time);
            });
        });
        candidates
    }

    /// Every sphere–sphere contact in the (finite) window, appended to `events` (in no
    /// particular order; the caller sorts). Returns the number of candidate pairs.
    pub(super) fn sphere_contacts_in_window(
        &mut self,
        store: &SphereStore,
        options: QueryOptions,
        events: &mut Vec<ContactEvent>,
    ) -> usize {
        // Stages 1–2: the cells, and the records in cell order (the grid's gather copies them).
        self.grid.build_cells(store, options.t_max(), self.options);
        let (order, sorted) = (self.grid.order(), self.grid.sorted_spheres());
        let found = Mutex::new(std::mem::take(events));
        let candidates = AtomicUsize::new(0);
        self.grid.visit_pairs(&|pairs| {
            candidates.fetch_add(pairs.len(), Ordering::Relaxed);
            let mut hits = Vec::new();
            listed_hits(sorted, pairs, options, &mut |[p, q], time| {
                let (i, j) = (order[p as usize], order[q as usize]);
                hits.push(sphere_event(i, j, time));
            });
            if !hits.is_empty() {
                let mut found = found.lock().unwrap_or_else(|e| e.into_inner());
                found.extend_from_slice(&hits);
            }
        });
        *events = found.into_inner().unwrap_or_else(|e| e.into_inner());
        candidates.into_inner()
    }

    /// Heap bytes the query holds between calls (grid, records, slots, buffers).
    pub fn heap_bytes(&self) -> usize {
        self.grid.heap_bytes() + self.slots.heap_bytes() + self.compact.capacity() * 8
    }
}

/// The contact of the spheres at cell positions `p` and `q` at `time`, offered to both their
/// slots (each slot names the other sphere by its scene index, `order[position]`).
#[inline(always)]
fn offer_both(slots: &mut [CompactContact], order: &[u32], [p, q]: [u32; 2], time: f32) {
    let (p, q) = (p as usize, q as usize);
    slots[p] = slots[p].min(CompactContact::sphere(time, order[q]));
    slots[q] = slots[q].min(CompactContact::sphere(time, order[p]));
}

/// The contact of spheres `i` and `j` at `time`, the lower index first.
pub(super) fn sphere_event(i: u32, j: u32, time: f32) -> ContactEvent {
    ContactEvent {
        time,
        sphere: i.min(j),
        other: Body::new(ShapeKind::Sphere, i.max(j)),
        geometry: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Accuracy;
    use crate::scene::Scene;

    /// A dense gas whose swept boxes span many cells: the pairs are many times the fused
    /// pass's buffer, so the flushes and the per-thread buffers are exercised.
    fn crowded(n: usize) -> Scene {
        let mut rng = crate::rng::Rng::new(11);
        let spheres: Vec<_> = (0..n)
            .map(|_| {
                let c = [0; 3].map(|_| rng.range(0.0, 20.0) as f32);
                let v = [0; 3].map(|_| rng.range(-1.0, 1.0) as f32);
                crate::Sphere::new(c, v, 0.3, 1.0).unwrap()
            })
            .collect();
        super::super::scene_of(&spheres)
    }

    #[test]
    fn the_fused_pass_sees_the_grids_pairs_with_the_kernels_times() {
        let scene = crowded(3000);
        let options = QueryOptions::new(4.0, Accuracy::Stable).unwrap();
        let mut query = SceneQuery::new();
        let mut firsts = vec![CompactContact::NONE; 3000];
        let candidates = query.sphere_firsts_in_window(&scene.spheres, options, &mut firsts);
        let mut grid = crate::broad::Grid::new();
        grid.build(&scene.spheres, 4.0, Default::default());
        assert_eq!(candidates, grid.pairs().len());
        assert!(
            candidates > 20_000,
            "{candidates} pairs: more than ten buffers' worth"
        );
        let brute = super::super::brute_force::first_contacts(&scene, options);
        for (i, (c, b)) in firsts.iter().zip(&brute).enumerate() {
            assert_eq!(c.get(), b.map(|b| (b.time, b.body)), "sphere {i}");
        }
    }
}
