//! The compact answer of a first-contact query: a sphere's earliest contact in 8 bytes, the
//! time's bits above the body's, so that the query's tie rule (earlier time, then lower
//! body: kind, then index) is the order of the integers and "keep the earlier" is `min`.
//! A `min` does not depend on the order it is taken in, so the threads of a parallel pass may
//! offer contacts to a slot in any order and the answer is the same bits.

use std::sync::atomic::{AtomicU64, Ordering};

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

/// Slots that threads offer contacts to: each keeps the least it was offered. One thread
/// writes them as plain values ([`plain`](Slots::plain)), several through atomics
/// ([`offer`](Slots::offer)); a slot holds the same bits either way.
#[derive(Debug, Default)]
pub(crate) struct Slots {
    shared: Vec<AtomicU64>,
    plain: Vec<CompactContact>,
    /// Which of the two the last [`reset`](Slots::reset) and writes used.
    is_plain: bool,
    /// The slots in the caller's order, for the parallel scatter.
    by_scene: Vec<AtomicU64>,
}

impl Slots {
    /// `n` empty shared slots (the buffer is kept between calls), filled on rayon.
    pub(crate) fn reset(&mut self, n: usize) {
        self.is_plain = false;
        self.shared.truncate(n);
        self.shared
            .par_iter()
            .with_min_len(MIN_LEN)
            .for_each(|s| s.store(u64::MAX, Ordering::Relaxed));
        self.shared.resize_with(n, || AtomicU64::new(u64::MAX));
    }

    /// `out[order[p]]` becomes the lesser of itself and slot `p`, for every position `p`.
    /// On rayon when `par`: each slot is stored once into a buffer in the caller's order
    /// (an atomic store is a plain move; every index is written once, so no order matters),
    /// then merged into `out` in one streaming pass.
    pub(crate) fn scatter_min(&mut self, order: &[u32], out: &mut [CompactContact], par: bool) {
        if !par {
            for (p, &i) in order.iter().enumerate() {
                let i = i as usize;
                out[i] = out[i].min(self.get(p));
            }
            return;
        }
        let n = order.len();
        if self.by_scene.len() < n {
            self.by_scene.resize_with(n, Default::default);
        }
        let (by_scene, shared, plain) = (&self.by_scene[..n], &self.shared, &self.plain);
        let is_plain = self.is_plain;
        let slot = |p: usize| {
            if is_plain {
                plain[p].0
            } else {
                shared[p].load(Ordering::Relaxed)
            }
        };
        order
            .par_iter()
            .enumerate()
            .with_min_len(MIN_LEN)
            .for_each(|(p, &i)| {
                by_scene[i as usize].store(slot(p), Ordering::Relaxed);
            });
        out.par_iter_mut()
            .zip(by_scene.par_iter())
            .with_min_len(MIN_LEN)
            .for_each(|(o, s)| *o = (*o).min(CompactContact(s.load(Ordering::Relaxed))));
    }

    /// `n` empty slots as plain values, for one thread.
    pub(crate) fn plain(&mut self, n: usize) -> &mut [CompactContact] {
        self.is_plain = true;
        self.plain.clear();
        self.plain.resize(n, CompactContact::NONE);
        &mut self.plain
    }

    /// Keeps `c` in slot `i` if it is less than what the slot holds. A plain load first: most
    /// offers after the first lose and need no locked instruction.
    #[inline(always)]
    pub(crate) fn offer(&self, i: usize, c: CompactContact) {
        let slot = &self.shared[i];
        if c.0 < slot.load(Ordering::Relaxed) {
            slot.fetch_min(c.0, Ordering::Relaxed);
        }
    }

    /// What slot `i` holds.
    #[inline(always)]
    pub(crate) fn get(&mut self, i: usize) -> CompactContact {
        if self.is_plain {
            self.plain[i]
        } else {
            CompactContact(*self.shared[i].get_mut())
        }
    }

    /// Heap bytes held.
    pub(crate) fn heap_bytes(&self) -> usize {
        (self.shared.capacity() + self.plain.capacity() + self.by_scene.capacity()) * 8
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
    fn slots_keep_the_least_offer_in_any_order() {
        let mut slots = Slots::default();
        slots.reset(2);
        let offers = [3.0, 1.0, 2.0, 1.0].map(|t| CompactContact::sphere(t, t as u32));
        for &c in &offers {
            slots.offer(0, c);
        }
        for &c in offers.iter().rev() {
            slots.offer(1, c);
        }
        assert_eq!(slots.get(0), CompactContact::sphere(1.0, 1));
        assert_eq!(slots.get(0), slots.get(1));
    }
}
