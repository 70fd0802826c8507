//! The sphere pairs of a finite window in one fused pass: the grid hands its candidate pairs
//! on a few thousand at a time, the 8-wide pair kernel runs on them at once from the spheres
//! copied into cell order, and each hit is kept where it is needed — the earliest per sphere
//! (slots indexed by cell position, so the offers land in nearby memory) or the list of
//! contacts. No list of all candidate pairs is ever held: memory is linear in the number of
//! spheres for any window, and every stage runs on rayon with the same bits for any thread
//! count (the slots keep a `min`, the contact list is sorted).

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::compact::CompactContact;
use super::{ContactEvent, SceneQuery};
use crate::batch::{QueryOptions, pairs::listed_hits};
use crate::contact::Body;
use crate::shape::ShapeKind;
use crate::store::SphereStore;

impl SceneQuery {
    /// Stages 1–2: the cells for the window and the spheres copied into cell order.
    fn cells_and_records(&mut self, store: &SphereStore, t_max: f32) {
        self.grid.build_cells(store, t_max, self.options);
        // Packed records first (one pass in order), then gathered into cell order: one cache
        // line per scattered sphere instead of the blocks' seven.
        self.packed.pack(store);
        self.sorted.permute_from(&self.packed, self.grid.order());
    }

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
        self.cells_and_records(store, options.t_max());
        self.slots.reset(n);
        let (order, sorted, slots) = (self.grid.order(), &self.sorted, &self.slots);
        let candidates = AtomicUsize::new(0);
        self.grid.visit_pairs(&|pairs| {
            candidates.fetch_add(pairs.len(), Ordering::Relaxed);
            listed_hits(sorted, pairs, options, &mut |[p, q], time| {
                let (p, q) = (p as usize, q as usize);
                slots.offer(p, CompactContact::sphere(time, order[q]));
                slots.offer(q, CompactContact::sphere(time, order[p]));
            });
        });
        let order = self.grid.order();
        for p in 0..n {
            let i = order[p] as usize;
            out[i] = out[i].min(self.slots.get(p));
        }
        candidates.into_inner()
    }

    /// Every sphere–sphere contact in the (finite) window, appended to `events` (in no
    /// particular order; the caller sorts). Returns the number of candidate pairs.
    pub(super) fn sphere_contacts_in_window(
        &mut self,
        store: &SphereStore,
        options: QueryOptions,
        events: &mut Vec<ContactEvent>,
    ) -> usize {
        self.cells_and_records(store, options.t_max());
        let (order, sorted) = (self.grid.order(), &self.sorted);
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
        self.grid.heap_bytes()
            + (self.packed.0.capacity() + self.sorted.0.capacity()) * 32
            + self.slots.heap_bytes()
            + self.times.capacity() * 4
            + self.compact.capacity() * 8
    }
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
        Scene {
            spheres: SphereStore::from_spheres(&spheres),
            ..Scene::default()
        }
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
