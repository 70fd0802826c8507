//! The event calendar: one pending event per sphere in a bucket (calendar) queue, after
//! Paul's O(1) queue as Smallenburg's EDMD uses it.
//!
//! Buckets of width `w` cover one "year" of `nb · w` ahead of the current bucket. Each sphere
//! has one slot (its time and two links, 16 bytes); a bucket is a doubly linked list of slots,
//! so re-scheduling a sphere unlinks its old event in O(1) and no stale copy waits in a
//! bucket. The current bucket is a binary min-heap of `(time, sphere, version)` entries, so
//! events leave in exact `(time, sphere)` order whatever the width (the width only sets the
//! cost: a few events a bucket is best); an event re-scheduled while in the heap, or in the
//! overflow list of events beyond a year, is left there and dropped by its version when it
//! surfaces.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// One event in the heap or the overflow list: when, whose, and which of its schedules,
/// packed into one key whose unsigned order is their order (time as `f64::total_cmp` orders
/// it, then sphere, then version), so that the heap compares two events in one integer comparison.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Entry(u128);

/// The sign bit of an `f64`.
const SIGN: u64 = 1 << 63;

/// Flips the magnitude bits of a negative `f64`'s bits, as `f64::total_cmp` does (its own
/// inverse: the sign bit is left as it is).
#[inline(always)]
fn flip_negative(bits: u64) -> u64 {
    bits ^ (((bits as i64) >> 63) as u64 >> 1)
}

impl Entry {
    #[inline(always)]
    fn new(t: f64, sphere: u32, version: u32) -> Self {
        let low = u64::from(sphere) << 32 | u64::from(version);
        // With the sign bit flipped too, the unsigned order is the times' total order.
        let time = flip_negative(t.to_bits()) ^ SIGN;
        Self(u128::from(time) << 64 | u128::from(low))
    }

    #[inline(always)]
    pub fn t(self) -> f64 {
        f64::from_bits(flip_negative((self.0 >> 64) as u64 ^ SIGN))
    }

    #[inline(always)]
    pub fn sphere(self) -> u32 {
        (self.0 >> 32) as u32
    }

    #[inline(always)]
    pub fn version(self) -> u32 {
        self.0 as u32
    }
}

/// The bucket of time `t` (`inv_width` buckets a unit of time), saturating: a negative time
/// (or NaN) is in bucket 0, a huge one in the last, with the overflow list. Through `i64`,
/// after `max`, where a cast to `u64` takes two conversions and a fix-up.
#[inline(always)]
fn bucket(t: f64, inv_width: f64) -> u64 {
    (t * inv_width).max(0.0) as i64 as u64
}

/// No sphere: the end of a bucket's list.
const NIL: u32 = u32::MAX;
/// `prev` of a slot that is first in its bucket.
const HEAD: u32 = u32::MAX - 1;
/// `prev` of a slot in no bucket (its event, if any, is in the heap or the overflow list).
const UNLINKED: u32 = u32::MAX - 2;

/// A sphere's place in the calendar.
#[derive(Debug, Clone, Copy)]
struct Slot {
    /// Its pending event's time, `+∞` when it has none.
    t: f64,
    next: u32,
    prev: u32,
}

/// A calendar queue over non-negative, finite times, for a fixed number of spheres.
#[derive(Debug, Clone)]
pub(crate) struct Calendar {
    inv_width: f64,
    /// First sphere of each bucket's list.
    heads: Vec<u32>,
    mask: u64,
    /// Absolute index of the bucket the heap holds.
    current: u64,
    slots: Vec<Slot>,
    /// Each sphere's schedule count: a heap or overflow entry of an older one is stale.
    version: Vec<u32>,
    heap: BinaryHeap<Reverse<Entry>>,
    far: Vec<Entry>,
    /// Spheres linked into a bucket. Pending events are not counted: every one is in a
    /// bucket, the heap or the overflow list, and `pop` ends when all three are empty.
    linked: usize,
}

impl Calendar {
    /// A calendar for `spheres` spheres (none scheduled) of `buckets` (rounded up to a power
    /// of two) buckets of `width`, starting at time `t0`.
    pub fn new(width: f64, buckets: usize, spheres: usize, t0: f64) -> Self {
        let nb = buckets.max(2).next_power_of_two();
        let inv_width = 1.0 / width;
        let empty = Slot {
            t: f64::INFINITY,
            next: NIL,
            prev: UNLINKED,
        };
        Self {
            inv_width,
            heads: super::pages::filled(NIL, nb),
            mask: nb as u64 - 1,
            current: bucket(t0, inv_width),
            slots: super::pages::filled(empty, spheres),
            version: super::pages::filled(0, spheres),
            heap: BinaryHeap::new(),
            far: Vec::new(),
            linked: 0,
        }
    }

    /// Spheres with a pending event.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.slots.iter().filter(|s| s.t.is_finite()).count()
    }

    #[inline]
    fn bucket_of(&self, t: f64) -> u64 {
        bucket(t, self.inv_width)
    }

    /// Bytes the calendar holds (bucket heads, slots, versions, heap, overflow).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.heads.capacity() * size_of::<u32>()
            + self.slots.capacity() * size_of::<Slot>()
            + self.version.capacity() * size_of::<u32>()
            + (self.heap.capacity() + self.far.capacity()) * size_of::<Entry>()
    }

    /// Bytes a calendar for `spheres` spheres and `buckets` buckets holds, before its heap
    /// and overflow list grow (a few entries).
    pub fn estimated_bytes(spheres: usize, buckets: usize) -> usize {
        use std::mem::size_of;
        let nb = buckets
            .max(2)
            .checked_next_power_of_two()
            .unwrap_or(usize::MAX);
        nb.saturating_mul(size_of::<u32>())
            .saturating_add(spheres.saturating_mul(size_of::<Slot>() + size_of::<u32>()))
    }

    /// Sphere `i`'s pending event is now at `t` (`+∞`: none); its earlier one, if any, is
    /// dropped. `t` must not precede the last popped time.
    #[inline]
    pub fn schedule(&mut self, i: u32, t: f64) {
        self.unlink(i);
        let v = &mut self.version[i as usize];
        *v = v.wrapping_add(1);
        self.slots[i as usize].t = t;
        if !t.is_finite() {
            return;
        }
        let k = self.bucket_of(t);
        if k <= self.current {
            self.heap.push(Reverse(self.entry(i)));
        } else if k - self.current <= self.mask {
            self.link(i, k);
        } else {
            self.far.push(self.entry(i));
        }
    }

    /// The earliest pending event (time, sphere), removed.
    #[inline]
    pub fn pop(&mut self) -> Option<(f64, u32)> {
        loop {
            if let Some(Reverse(e)) = self.heap.pop() {
                if e.version() != self.version[e.sphere() as usize] {
                    continue;
                }
                self.slots[e.sphere() as usize].t = f64::INFINITY;
                return Some((e.t(), e.sphere()));
            }
            if !self.advance() {
                return None;
            }
        }
    }

    /// The sphere whose event most likely comes next (a hint: the heap's first, else the
    /// first of the next bucket's list), for its records to be fetched ahead.
    #[inline]
    pub fn likely_next(&self) -> Option<u32> {
        match self.heap.peek() {
            Some(Reverse(e)) => Some(e.sphere()),
            None => {
                let i = self.heads[(self.current.wrapping_add(1) & self.mask) as usize];
                (i != NIL).then_some(i)
            }
        }
    }

    /// Where sphere `i`'s slot and version lie, which moving its bucket into the heap reads
    /// (for fetching them ahead; `None` past the last sphere).
    #[inline]
    pub fn lines_of(&self, i: u32) -> Option<[*const u8; 2]> {
        let slot = self.slots.get(i as usize)?;
        let version = self.version.get(i as usize)?;
        Some([(slot as *const Slot).cast(), (version as *const u32).cast()])
    }

    /// The sphere after `i` in its bucket's list, if `i` is in a list and not its last.
    #[inline]
    pub fn linked_after(&self, i: u32) -> Option<u32> {
        let s = self.slots.get(i as usize)?;
        (s.prev != UNLINKED && s.next != NIL).then_some(s.next)
    }

    #[inline]
    fn entry(&self, i: u32) -> Entry {
        Entry::new(self.slots[i as usize].t, i, self.version[i as usize])
    }

    /// Puts sphere `i` first in bucket `k`'s list.
    #[inline]
    fn link(&mut self, i: u32, k: u64) {
        let b = (k & self.mask) as usize;
        let next = self.heads[b];
        if next != NIL {
            self.slots[next as usize].prev = i;
        }
        let s = &mut self.slots[i as usize];
        (s.next, s.prev) = (next, HEAD);
        self.heads[b] = i;
        self.linked += 1;
    }

    /// Takes sphere `i` out of its bucket's list, if it is in one.
    #[inline]
    fn unlink(&mut self, i: u32) {
        let Slot { t, next, prev } = self.slots[i as usize];
        if prev == UNLINKED {
            return;
        }
        if prev == HEAD {
            let b = (self.bucket_of(t) & self.mask) as usize;
            self.heads[b] = next;
        } else {
            self.slots[prev as usize].next = next;
        }
        if next != NIL {
            self.slots[next as usize].prev = prev;
        }
        self.slots[i as usize].prev = UNLINKED;
        self.linked -= 1;
    }

    /// Moves to the next bucket, with the heap empty: its list goes into the heap. Overflow
    /// events move into the ring at each new year; when no bucket holds an event, the
    /// calendar jumps to the earliest overflow event. `false` when no event is pending.
    fn advance(&mut self) -> bool {
        if self.linked == 0 {
            self.far
                .retain(|e| e.version() == self.version[e.sphere() as usize]);
            if self.far.is_empty() {
                // No event is held anywhere (the heap is empty too): none is pending, and
                // `pop` ends instead of turning the ring for ever.
                return false;
            }
            let first = self.far.iter().map(|e| self.bucket_of(e.t())).min();
            self.current = first.unwrap_or(self.current).saturating_sub(1);
            self.refill_from_far();
        }
        self.current += 1;
        if self.current & self.mask == 0 && !self.far.is_empty() {
            self.refill_from_far();
        }
        let b = (self.current & self.mask) as usize;
        let mut i = std::mem::replace(&mut self.heads[b], NIL);
        while i != NIL {
            let s = &mut self.slots[i as usize];
            s.prev = UNLINKED;
            let (t, next) = (s.t, s.next);
            self.linked -= 1;
            self.heap
                .push(Reverse(Entry::new(t, i, self.version[i as usize])));
            i = next;
        }
        true
    }

    /// Moves the live overflow events that now fall within a year of the current bucket into
    /// the ring (every overflow event lies after the current bucket: it was beyond a year when
    /// scheduled, and this runs at least once a year); stale ones are dropped.
    #[cold]
    fn refill_from_far(&mut self) {
        let far = std::mem::take(&mut self.far);
        for e in far {
            if e.version() != self.version[e.sphere() as usize] {
                continue;
            }
            let k = self.bucket_of(e.t());
            if k - self.current <= self.mask {
                self.link(e.sphere(), k);
            } else {
                self.far.push(e);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// The hint of what comes next: none when empty, the heap's first when the current bucket
    /// holds events, else the first of the next bucket's list; never a wrong answer to `pop`.
    #[test]
    fn the_likely_next_is_the_heap_first_or_the_next_bucket() {
        let mut c = Calendar::new(1.0, 8, 4, 0.0);
        assert_eq!(c.likely_next(), None);
        c.schedule(2, 1.5);
        c.schedule(3, 1.7);
        // Bucket 1 is the next one: its list's first is the one scheduled last.
        assert_eq!(c.likely_next(), Some(3));
        c.schedule(1, 0.5);
        assert_eq!(c.likely_next(), Some(1));
        assert_eq!(c.pop(), Some((0.5, 1)));
        assert_eq!(c.likely_next(), Some(3));
        assert_eq!(c.pop(), Some((1.5, 2)));
        assert_eq!(c.likely_next(), Some(3));
        assert_eq!(c.pop(), Some((1.7, 3)));
        assert_eq!(c.likely_next(), None);
    }

    /// `linked_after` walks a bucket's list as `advance` will (last scheduled first) and
    /// stops at its end, and says nothing of an event already in the heap; `lines_of` names a
    /// sphere's own slot and version, and nothing past the last sphere.
    #[test]
    fn linked_after_follows_a_buckets_list() {
        let mut c = Calendar::new(1.0, 8, 4, 0.0);
        for i in [0, 1, 2] {
            c.schedule(i, 1.5 + f64::from(i) * 0.1);
        }
        c.schedule(3, 2.5);
        assert_eq!(c.likely_next(), Some(2));
        assert_eq!(c.linked_after(2), Some(1));
        assert_eq!(c.linked_after(1), Some(0));
        assert_eq!(c.linked_after(0), None);
        assert_eq!(c.linked_after(3), None);
        assert_eq!(c.linked_after(4), None);
        assert_eq!(c.pop(), Some((1.5, 0)));
        assert_eq!(c.linked_after(2), None, "in the heap now");
        let [slot, version] = c.lines_of(1).expect("sphere 1 has a slot");
        assert_eq!(slot, (&c.slots[1] as *const Slot).cast());
        assert_eq!(version, (&c.version[1] as *const u32).cast());
        assert!(c.lines_of(4).is_none());
    }

    /// An entry gives back its time, sphere and version to the bit, and entries order as
    /// their (time by `f64::total_cmp`, sphere, version) tuples, over signed zeros,
    /// subnormals, negative and huge times and ties.
    #[test]
    fn entries_order_as_their_fields() {
        let mut rng = Rng::new(11);
        let special = [
            0.0,
            -0.0,
            5e-324,
            -5e-324,
            1.0,
            -1.0,
            1e300,
            -1e300,
            f64::MAX,
        ];
        let mut times: Vec<f64> = special.to_vec();
        for k in 0..200 {
            times.push(match k % 2 {
                0 => rng.range(-2.0, 2.0),
                _ => rng.range(0.0, 1.0) * 10f64.powi((k % 40) - 20),
            });
        }
        // Every time with several spheres and versions, high bits included, so that ties in
        // time (and in time and sphere) are common.
        let mut fields = Vec::new();
        for (k, &t) in times.iter().enumerate() {
            for m in 0..3u32 {
                let sphere = (k as u32 % 5 + m).wrapping_mul(0x9E37_79B9);
                let version = (k as u32 % 3 + 2 * m).wrapping_mul(0x7F4A_7C15);
                fields.push((t, sphere, version));
            }
        }
        for &(t, s, v) in &fields {
            let e = Entry::new(t, s, v);
            assert_eq!(
                (e.t().to_bits(), e.sphere(), e.version()),
                (t.to_bits(), s, v)
            );
        }
        for &(ta, sa, va) in &fields {
            for &(tb, sb, vb) in &fields {
                let want = ta.total_cmp(&tb).then(sa.cmp(&sb)).then(va.cmp(&vb));
                let got = Entry::new(ta, sa, va).cmp(&Entry::new(tb, sb, vb));
                assert_eq!(
                    got, want,
                    "({ta:e}, {sa}, {va}) against ({tb:e}, {sb}, {vb})"
                );
            }
        }
    }

    /// Times before the calendar's start (a restored state may hold them) leave first, in
    /// order, before the later ones.
    #[test]
    fn times_before_the_start_leave_first() {
        let mut q = Calendar::new(1.0, 8, 4, 0.0);
        q.schedule(0, 2.5);
        q.schedule(1, -1.0);
        q.schedule(2, -0.25);
        q.schedule(3, 0.5);
        let order: Vec<u32> = std::iter::from_fn(|| q.pop().map(|(_, i)| i)).collect();
        assert_eq!(order, [1, 2, 3, 0]);
    }

    /// Events leave in exact (time, sphere) order whatever the width, including times far
    /// beyond one year, bucket numbers past `i64::MAX` (the saturating cast: width 1e-290)
    /// and equal times; a sphere scheduled again leaves once, at its last time, wherever its
    /// earlier event was (a bucket, the heap, the overflow list).
    #[test]
    fn pops_in_order_for_any_width() {
        const N: usize = 500;
        for &width in &[1e-290, 1e-3, 0.1, 1.0, 50.0] {
            let mut rng = Rng::new(7);
            let mut q = Calendar::new(width, 16, N, 0.0);
            let mut now = 0.0;
            let mut pending = [f64::INFINITY; N];
            let mut popped = Vec::new();
            let mut expected = Vec::new();
            for step in 1..20_000u32 {
                let i = (rng.unit() * N as f64) as u32 % N as u32;
                let t = match step % 97 {
                    0 => f64::INFINITY,
                    1 => now,
                    2 => now + 1e4 * rng.unit(),
                    _ => now + rng.unit(),
                };
                // The event `i` had is dropped, the new one kept.
                q.schedule(i, t);
                pending[i as usize] = t;
                if step % 3 == 0
                    && let Some((t, i)) = q.pop()
                {
                    assert!(t >= now, "time went back: {t} < {now}");
                    assert_eq!(pending[i as usize], t, "sphere {i} left at a dropped time");
                    expected.push((t, i));
                    pending[i as usize] = f64::INFINITY;
                    now = t;
                    popped.push((t, i));
                }
                assert_eq!(q.len(), pending.iter().filter(|t| t.is_finite()).count());
            }
            let mut rest: Vec<(f64, u32)> = (0..N as u32)
                .filter(|&i| pending[i as usize].is_finite())
                .map(|i| (pending[i as usize], i))
                .collect();
            rest.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            while let Some(e) = q.pop() {
                popped.push(e);
            }
            assert_eq!(q.len(), 0);
            expected.extend(rest);
            // Every live event comes out once, in time order (the rest, scheduled before any
            // of them left, also in sphere order at equal times).
            if let Some(k) = popped.windows(2).position(|w| w[0].0 > w[1].0) {
                panic!("width {width}: {:?}", &popped[k.saturating_sub(3)..k + 3]);
            }
            assert_eq!(popped, expected, "width {width}");
        }
    }
}
