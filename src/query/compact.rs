//! The compact answer of a first-contact query: a sphere's earliest contact in 8 bytes, the
//! time's bits above the body's, so that the query's tie rule (earlier time, then lower
//! body: kind, then index) is the order of the integers and "keep the earlier" is `min`.
//! A `min` does not depend on the order it is taken in, so the threads of a parallel pass may
//! offer contacts to a slot in any order and the answer is the same bits.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

use rayon::prelude::*;

use crate::contact::Body;
use crate::shape::ShapeKind;

/// Slots per rayon task in the passes over all slots.
const MIN_LEN: usize = 1 << 14;

/// Bits of the body's index; the two above them hold the kind's code.
const INDEX_BITS: u32 = 30;
/// The largest body index a compact contact holds (spheres: the grid's limit is lower).
pub const MAX_INDEX: u32 = (1 << INDEX_BITS) - 1;
const _: () = assert!(
    ShapeKind::ALL.len() <= 4,
    "two bits of kind: widen CompactContact's kind field for a fifth kind"
);

/// A sphere's earliest contact, or none, in 8 bytes: `time` (`≥ 0`, finite) and the body it
/// touches. Ordered as the query's tie rule, with "none" last.
///
/// ```
/// use spheresweep::{Body, ShapeKind, query::CompactContact};
/// let wall = CompactContact::new(2.0, Body::new(ShapeKind::Plane, 0));
/// let ball = CompactContact::new(2.0, Body::new(ShapeKind::Sphere, 7));
/// assert!(ball < wall && wall < CompactContact::NONE); // equal times: spheres first
/// assert_eq!(wall.get(), Some((2.0, Body::new(ShapeKind::Plane, 0))));
/// assert_eq!(CompactContact::NONE.get(), None);
/// ```
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[repr(transparent)]
pub struct CompactContact(u64);

impl CompactContact {
    /// No contact in the window.
    pub const NONE: CompactContact = CompactContact(u64::MAX);

    /// The contact at `time` with `body`.
    ///
    /// # Panics
    /// If `time` is negative, infinite or NaN, or `body.index` exceeds [`MAX_INDEX`].
    #[inline]
    pub fn new(time: f32, body: Body) -> Self {
        assert!(
            time.is_finite() && time >= 0.0 && body.index <= MAX_INDEX,
            "a compact contact needs a finite time >= 0 and an index <= {MAX_INDEX}, got {time} and {body}"
        );
        Self::key(time, body)
    }

    /// [`new`](Self::new) without the checks, for the query's hot loops (`-0.0` becomes
    /// `+0.0`, so the bits order as the times).
    #[inline(always)]
    pub(crate) fn key(time: f32, body: Body) -> Self {
        let time = (time + 0.0).to_bits() as u64;
        let body = (u64::from(body.kind.code()) << INDEX_BITS) | u64::from(body.index);
        CompactContact((time << 32) | body)
    }

    /// A contact with sphere `index` at `time` (the hot loops' case).
    #[inline(always)]
    pub(crate) fn sphere(time: f32, index: u32) -> Self {
        Self::key(time, Body::new(ShapeKind::Sphere, index))
    }

    /// Whether this is [`NONE`](Self::NONE).
    #[inline]
    pub fn is_none(self) -> bool {
        self == Self::NONE
    }

    /// Time and body, or `None`.
    #[inline]
    pub fn get(self) -> Option<(f32, Body)> {
        if self.is_none() {
            return None;
        }
        let time = f32::from_bits((self.0 >> 32) as u32);
        let kind = ShapeKind::from_code((self.0 >> INDEX_BITS & 3) as u8)?;
        Some((time, Body::new(kind, (self.0 as u32) & MAX_INDEX)))
    }

    /// The time, or `None`.
    #[inline]
    pub fn time(self) -> Option<f32> {
        self.get().map(|(t, _)| t)
    }

    /// The body touched, or `None`.
    #[inline]
    pub fn body(self) -> Option<Body> {
        self.get().map(|(_, b)| b)
    }

    /// The raw 8 bytes (time bits above kind and index), e.g. for a NumPy `u64` column.
    #[inline]
    pub fn to_bits(self) -> u64 {
        self.0
    }
}

impl std::fmt::Debug for CompactContact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.get() {
            Some((t, b)) => write!(f, "CompactContact({t}, {b})"),
            None => f.write_str("CompactContact::NONE"),
        }
    }
}

/// Slots that keep, each, the least contact offered: plain values written by one thread
/// ([`plain`](Slots::plain)), or one set per rayon thread ([`worker`](Slots::worker)) merged
/// by `min` at the end ([`merge_workers`](Slots::merge_workers)). No slot is shared between
/// threads while they write, and a `min` does not depend on the order of the offers: the
/// same bits for any thread count.
#[derive(Debug, Default)]
pub(crate) struct Slots {
    plain: Vec<CompactContact>,
    /// One set of plain slots per rayon thread, each written by its thread alone.
    workers: Vec<Mutex<Vec<CompactContact>>>,
    /// The slots in the caller's order, for the parallel scatter.
    by_scene: Vec<AtomicU64>,
}

impl Slots {
    /// `n` empty slots as plain values, for one thread.
    pub(crate) fn plain(&mut self, n: usize) -> &mut [CompactContact] {
        self.plain.clear();
        self.plain.resize(n, CompactContact::NONE);
        &mut self.plain
    }

    /// `n` empty slots for each of `workers` threads, filled on rayon.
    pub(crate) fn reset_workers(&mut self, n: usize, workers: usize) {
        if self.workers.len() < workers {
            self.workers.resize_with(workers, Default::default);
        }
        self.workers[..workers].par_iter_mut().for_each(|m| {
            let slots = m.get_mut().unwrap_or_else(|e| e.into_inner());
            slots.clear();
            slots.resize(n, CompactContact::NONE);
        });
    }

    /// Worker `w`'s slots (locked once a batch; no other thread asks for them).
    pub(crate) fn worker(&self, w: usize) -> MutexGuard<'_, Vec<CompactContact>> {
        self.workers[w].lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The plain slots become the least of the `workers` threads' slots, on rayon.
    pub(crate) fn merge_workers(&mut self, n: usize, workers: usize) {
        // Every slot is written below: only the length matters here, not a fill.
        self.plain.truncate(n);
        self.plain.resize(n, CompactContact::NONE);
        let sets: Vec<&Vec<CompactContact>> = self.workers[..workers]
            .iter_mut()
            .map(|m| &*m.get_mut().unwrap_or_else(|e| e.into_inner()))
            .collect();
        self.plain
            .par_chunks_mut(MIN_LEN)
            .enumerate()
            .for_each(|(c, chunk)| {
                let start = c * MIN_LEN;
                for (k, slot) in chunk.iter_mut().enumerate() {
                    *slot = sets
                        .iter()
                        .map(|s| s[start + k])
                        .min()
                        .unwrap_or(CompactContact::NONE);
                }
            });
    }

    /// `out[order[p]]` becomes the lesser of itself and slot `p`, for every position `p`.
    /// On rayon when `par`: each slot is stored once into a buffer in the caller's order
    /// (an atomic store is a plain move; every index is written once, so no order matters),
    /// then merged into `out` in one streaming pass.
    pub(crate) fn scatter_min(&mut self, order: &[u32], out: &mut [CompactContact], par: bool) {
        let plain = &self.plain;
        if !par {
            for (&c, &i) in plain.iter().zip(order) {
                let i = i as usize;
                out[i] = out[i].min(c);
            }
            return;
        }
        let n = order.len();
        if self.by_scene.len() < n {
            self.by_scene.resize_with(n, Default::default);
        }
        let by_scene = &self.by_scene[..n];
        order
            .par_iter()
            .zip(plain.par_iter())
            .with_min_len(MIN_LEN)
            .for_each(|(&i, c)| by_scene[i as usize].store(c.0, Ordering::Relaxed));
        out.par_iter_mut()
            .zip(by_scene.par_iter())
            .with_min_len(MIN_LEN)
            .for_each(|(o, s)| *o = (*o).min(CompactContact(s.load(Ordering::Relaxed))));
    }

    /// Heap bytes held.
    pub(crate) fn heap_bytes(&self) -> usize {
        let workers: usize = self
            .workers
            .iter()
            .map(|m| m.lock().unwrap_or_else(|e| e.into_inner()).capacity())
            .sum();
        (self.plain.capacity() + self.by_scene.capacity() + workers) * 8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_integer_order_is_the_tie_rule() {
        let all = [
            CompactContact::new(0.0, Body::new(ShapeKind::Sphere, 0)),
            CompactContact::new(0.0, Body::new(ShapeKind::Sphere, MAX_INDEX)),
            CompactContact::new(0.0, Body::new(ShapeKind::Plane, 0)),
            CompactContact::new(0.0, Body::new(ShapeKind::Container, 3)),
            CompactContact::new(f32::from_bits(1), Body::new(ShapeKind::Sphere, 0)),
            CompactContact::new(1.0, Body::new(ShapeKind::Cylinder, 9)),
            CompactContact::new(f32::MAX, Body::new(ShapeKind::Sphere, 0)),
            CompactContact::NONE,
        ];
        for w in all.windows(2) {
            assert!(w[0] < w[1], "{:?} < {:?}", w[0], w[1]);
            let (a, b) = (w[0].get(), w[1].get());
            if let (Some((ta, ba)), Some((tb, bb))) = (a, b) {
                assert!(ta < tb || (ta == tb && ba < bb));
            }
        }
        let plane = Body::new(ShapeKind::Plane, 1);
        assert_eq!(
            CompactContact::key(-0.0, plane),
            CompactContact::key(0.0, plane)
        );
        for kind in ShapeKind::ALL {
            let b = Body::new(kind, 12345);
            assert_eq!(CompactContact::new(0.5, b).get(), Some((0.5, b)));
        }
    }

    #[test]
    #[should_panic(expected = "compact contact")]
    fn an_infinite_time_is_refused() {
        CompactContact::new(f32::INFINITY, Body::new(ShapeKind::Sphere, 0));
    }

    #[test]
    fn worker_slots_merge_to_the_least_offer_in_any_order() {
        let mut slots = Slots::default();
        slots.reset_workers(2, 3);
        let offers = [3.0, 1.0, 2.0, 1.0].map(|t| CompactContact::sphere(t, t as u32));
        // Slot 0 offered everything by worker 0; slot 1 the same offers spread over the
        // workers in reverse.
        for &c in &offers {
            let mut w = slots.worker(0);
            w[0] = w[0].min(c);
        }
        for (k, &c) in offers.iter().rev().enumerate() {
            let mut w = slots.worker(k % 3);
            w[1] = w[1].min(c);
        }
        slots.merge_workers(2, 3);
        let mut out = vec![CompactContact::NONE; 2];
        slots.scatter_min(&[1, 0], &mut out, false);
        assert_eq!(out[1], CompactContact::sphere(1.0, 1));
        assert_eq!(out[0], out[1]);
    }
}
