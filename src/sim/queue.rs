//! The event calendar: one pending event per sphere in a bucket (calendar) queue, after
//! Paul's O(1) queue as Smallenburg's EDMD uses it.
//!
//! Buckets of width `w` cover one "year" of `nb · w` ahead of the current bucket. Each sphere
//! has one slot (its time and two links, 16 bytes); a bucket is a doubly linked list of slots,
//! so re-scheduling a sphere unlinks its old event in O(1). The current bucket is an array of
//! `(time, sphere)` keys sorted latest first, so events leave in exact `(time, sphere)` order
//! whatever the width, and a pop is the array's last entry. Events beyond a year wait in an
//! overflow array. An event is in exactly one of the three places, and re-scheduling its
//! sphere takes it out at once: no stale copy is left anywhere, so the calendar keeps no
//! versions and never pops an event only to drop it.
//!
//! The width sets the cost only, and a few events a bucket is best. A bucket is sorted once
//! as it becomes current (a heap's logarithm an event, however many it holds); but an event
//! put into the current bucket after that, or taken out of it other than at its end, moves
//! the entries after it. With the engine's width that is rare (the current bucket or the
//! overflow is touched by 0.2 re-schedules a collision at φ = 0.4, 0.11 of them a take-out
//! from the current bucket) and short (about four events a bucket); with a width far too
//! wide for the gas it is neither: with all 20 000 events of a stress test in one bucket, a
//! pop and two re-schedules took 8 µs, where the heap before took 0.3 µs (2026-12-07).

/// One event in the current bucket: when and whose, packed into one key whose unsigned order
/// is their order (time as `f64::total_cmp` orders it, then sphere), so that two events
/// compare in one integer comparison.
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
    fn new(t: f64, sphere: u32) -> Self {
        // With the sign bit flipped too, the unsigned order is the times' total order.
        let time = flip_negative(t.to_bits()) ^ SIGN;
        Self(u128::from(time) << 64 | u128::from(sphere))
    }

    #[inline(always)]
    pub fn t(self) -> f64 {
        f64::from_bits(flip_negative((self.0 >> 64) as u64 ^ SIGN))
    }

    #[inline(always)]
    pub fn sphere(self) -> u32 {
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
/// `prev` of a slot with no pending event.
const UNLINKED: u32 = u32::MAX - 2;
/// `prev` of a slot whose event is in the current bucket's sorted array.
const CURRENT: u32 = u32::MAX - 3;
/// `prev` of a slot whose event is in the overflow array (its `next` is its place there).
const FAR: u32 = u32::MAX - 4;

/// A sphere's place in the calendar.
#[derive(Debug, Clone, Copy)]
struct Slot {
    /// Its pending event's time (meaningless when `prev` is `UNLINKED`).
    t: f64,
    /// The next sphere in its bucket's list, or its index in the overflow array.
    next: u32,
    /// The sphere before it in its bucket's list, or where its event is: `HEAD`, `UNLINKED`,
    /// `CURRENT`, `FAR`.
    prev: u32,
}

/// Buckets at most this long are sorted by insertion when they become current; longer ones
/// by `sort_unstable`, so that sorting a crowded bucket costs its length's logarithm an
/// event, as a heap would.
const INSERTION_SORT_MAX: usize = 16;

/// A calendar queue over non-negative, finite times, for a fixed number of spheres.
#[derive(Debug, Clone)]
pub(crate) struct Calendar {
    inv_width: f64,
    /// First sphere of each bucket's list.
    heads: Vec<u32>,
    mask: u64,
    /// Absolute index of the bucket `now` holds.
    current: u64,
    slots: Vec<Slot>,
    /// The current bucket's events, latest first: the next event is the last.
    now: Vec<Entry>,
    /// Spheres whose events lie beyond a year, in no order.
    far: Vec<u32>,
    /// Spheres linked into a bucket. Pending events are not counted: every one is in a
    /// bucket, the current bucket's array or the overflow array, and `pop` ends when all
    /// three are empty.
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
            now: Vec::new(),
            far: Vec::new(),
            linked: 0,
        }
    }

    /// Spheres with a pending event.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.slots.iter().filter(|s| s.prev != UNLINKED).count()
    }

    #[inline]
    fn bucket_of(&self, t: f64) -> u64 {
        bucket(t, self.inv_width)
    }

    /// Bytes the calendar holds (bucket heads, slots, the current bucket, overflow).
    pub fn bytes(&self) -> usize {
        use std::mem::size_of;
        self.heads.capacity() * size_of::<u32>()
            + self.slots.capacity() * size_of::<Slot>()
            + self.now.capacity() * size_of::<Entry>()
            + self.far.capacity() * size_of::<u32>()
    }

    /// Bytes a calendar for `spheres` spheres and `buckets` buckets holds, before its current
    /// bucket and overflow array grow (a few entries).
    pub fn estimated_bytes(spheres: usize, buckets: usize) -> usize {
        use std::mem::size_of;
        let nb = buckets
            .max(2)
            .checked_next_power_of_two()
            .unwrap_or(usize::MAX);
        nb.saturating_mul(size_of::<u32>())
            .saturating_add(spheres.saturating_mul(size_of::<Slot>()))
    }

    /// Sphere `i`'s pending event is now at `t` (`+∞`: none); its earlier one, if any, is
    /// dropped. `t` must not precede the last popped time.
    ///
    /// The usual case inline: an event from a bucket's list or none, to a bucket within the
    /// year. The others (from or to the current bucket or the overflow array, or no event)
    /// are one call at the end, so that the usual case saves no registers for it.
    #[inline]
    pub fn schedule(&mut self, i: u32, t: f64) {
        let Slot { t: old, next, prev } = self.slots[i as usize];
        match prev {
            UNLINKED => {}
            CURRENT | FAR => return self.schedule_elsewhere(i, t),
            _ => self.unlink(old, next, prev),
        }
        let k = self.bucket_of(t);
        // Within the ring and after the current bucket: `1 ≤ k − current ≤ mask`; and not +∞,
        // whose bucket (the last) may be within the ring. NaN fails the test.
        if k.wrapping_sub(self.current).wrapping_sub(1) < self.mask && t < f64::INFINITY {
            self.slots[i as usize].t = t;
            self.link(i, k);
        } else {
            self.slots[i as usize].prev = UNLINKED;
            self.schedule_elsewhere(i, t);
        }
    }

    /// `schedule` for the cases it does not inline: sphere `i`'s event, if any, taken out of
    /// wherever it is, and the new one, if `t` is finite, put where it belongs.
    #[cold]
    #[inline(never)]
    fn schedule_elsewhere(&mut self, i: u32, t: f64) {
        self.take_out(i);
        if !t.is_finite() {
            self.slots[i as usize].prev = UNLINKED;
            return;
        }
        self.slots[i as usize].t = t;
        let k = self.bucket_of(t);
        if k <= self.current {
            self.slots[i as usize].prev = CURRENT;
            self.insert_now(Entry::new(t, i));
        } else if k - self.current <= self.mask {
            self.link(i, k);
        } else {
            self.put_far(i);
        }
    }

    /// The earliest pending event (time, sphere), removed.
    #[inline]
    pub fn pop(&mut self) -> Option<(f64, u32)> {
        loop {
            if let Some(e) = self.now.pop() {
                self.slots[e.sphere() as usize].prev = UNLINKED;
                return Some((e.t(), e.sphere()));
            }
            if !self.advance() {
                return None;
            }
        }
    }

    /// The sphere whose event most likely comes next (a hint: the current bucket's first,
    /// else the first of the next bucket's list), for its records to be fetched ahead.
    #[inline]
    pub fn likely_next(&self) -> Option<u32> {
        match self.now.last() {
            Some(e) => Some(e.sphere()),
            None => {
                let i = self.heads[(self.current.wrapping_add(1) & self.mask) as usize];
                (i != NIL).then_some(i)
            }
        }
    }

    /// Where sphere `i`'s slot lies, which moving its bucket into the current one reads (for
    /// fetching it ahead; `None` past the last sphere).
    #[inline]
    pub fn lines_of(&self, i: u32) -> Option<*const u8> {
        let slot = self.slots.get(i as usize)?;
        Some((slot as *const Slot).cast())
    }

    /// The sphere after `i` in its bucket's list, if `i` is in a list and not its last.
    #[inline]
    pub fn linked_after(&self, i: u32) -> Option<u32> {
        let s = self.slots.get(i as usize)?;
        (s.prev < FAR || s.prev == HEAD)
            .then_some(s.next)
            .filter(|&n| n != NIL)
    }

    /// Takes sphere `i`'s pending event, if any, out of wherever it is (its slot's `prev` is
    /// left for the caller to set).
    #[inline(always)]
    fn take_out(&mut self, i: u32) {
        let Slot { t, next, prev } = self.slots[i as usize];
        match prev {
            UNLINKED => {}
            CURRENT => self.remove_now(Entry::new(t, i)),
            FAR => {
                self.far.swap_remove(next as usize);
                if let Some(&moved) = self.far.get(next as usize) {
                    self.slots[moved as usize].next = next;
                }
            }
            _ => self.unlink(t, next, prev),
        }
    }

    /// Puts `e` in its place in the current bucket's array (latest first).
    #[inline]
    fn insert_now(&mut self, e: Entry) {
        let at = self.now.partition_point(|&x| x > e);
        self.now.insert(at, e);
    }

    /// Takes `e` out of the current bucket's array: most often its last entry (the partner
    /// of the collision just popped).
    #[inline]
    fn remove_now(&mut self, e: Entry) {
        if self.now.last() == Some(&e) {
            self.now.pop();
        } else {
            let at = self.now.partition_point(|&x| x > e);
            debug_assert_eq!(self.now.get(at), Some(&e));
            self.now.remove(at);
        }
    }

    /// Puts sphere `i` at the end of the overflow array.
    #[inline]
    fn put_far(&mut self, i: u32) {
        let s = &mut self.slots[i as usize];
        (s.next, s.prev) = (self.far.len() as u32, FAR);
        self.far.push(i);
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

    /// Takes the sphere at time `t` between `prev` and `next` out of its bucket's list.
    #[inline]
    fn unlink(&mut self, t: f64, next: u32, prev: u32) {
        if prev == HEAD {
            let b = (self.bucket_of(t) & self.mask) as usize;
            self.heads[b] = next;
        } else {
            self.slots[prev as usize].next = next;
        }
        if next != NIL {
            self.slots[next as usize].prev = prev;
        }
        self.linked -= 1;
    }

    /// Moves to the next bucket, with the current one empty: its list becomes the sorted
    /// array. Overflow events move into the ring at each new year; when no bucket holds an
    /// event, the calendar jumps to the earliest overflow event. `false` when no event is
    /// pending.
    fn advance(&mut self) -> bool {
        if self.linked == 0 {
            if self.far.is_empty() {
                // No event is held anywhere (the current bucket is empty too): none is
                // pending, and `pop` ends instead of turning the ring for ever.
                return false;
            }
            let first = self
                .far
                .iter()
                .map(|&i| self.bucket_of(self.slots[i as usize].t))
                .min();
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
            s.prev = CURRENT;
            let (t, next) = (s.t, s.next);
            self.linked -= 1;
            self.now.push(Entry::new(t, i));
            i = next;
        }
        sort_latest_first(&mut self.now);
        true
    }

    /// Moves the overflow events that now fall within a year of the current bucket into the
    /// ring (every overflow event lies after the current bucket: it was beyond a year when
    /// scheduled, and this runs at least once a year).
    #[cold]
    fn refill_from_far(&mut self) {
        let mut kept = 0;
        for at in 0..self.far.len() {
            let i = self.far[at];
            let k = self.bucket_of(self.slots[i as usize].t);
            if k - self.current <= self.mask {
                self.link(i, k);
            } else {
                self.far[kept] = i;
                self.slots[i as usize].next = kept as u32;
                kept += 1;
            }
        }
        self.far.truncate(kept);
    }
}

/// Sorts a bucket's events latest first: by insertion when it holds a few (the usual case:
/// about two), else by `sort_unstable` (the keys are distinct, so the order is the same).
#[inline]
fn sort_latest_first(v: &mut [Entry]) {
    if v.len() > INSERTION_SORT_MAX {
        v.sort_unstable_by(|a, b| b.cmp(a));
        return;
    }
    for k in 1..v.len() {
        let e = v[k];
        let mut at = k;
        while at > 0 && v[at - 1] < e {
            v[at] = v[at - 1];
            at -= 1;
        }
        v[at] = e;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// The hint of what comes next: none when empty, the current bucket's first when it
    /// holds events, else the first of the next bucket's list; never a wrong answer to `pop`.
    #[test]
    fn the_likely_next_is_the_current_first_or_the_next_bucket() {
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
    /// stops at its end, and says nothing of an event already in the current bucket;
    /// `lines_of` names a sphere's own slot, and nothing past the last sphere.
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
        assert_eq!(c.linked_after(2), None, "in the current bucket now");
        let slot = c.lines_of(1).expect("sphere 1 has a slot");
        assert_eq!(slot, (&c.slots[1] as *const Slot).cast());
        assert!(c.lines_of(4).is_none());
    }

    /// An entry gives back its time and sphere to the bit, and entries order as their (time
    /// by `f64::total_cmp`, sphere) pairs, over signed zeros, subnormals, negative and huge
    /// times and ties.
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
        // Every time with several spheres, high bits included, so that ties in time are
        // common.
        let mut fields = Vec::new();
        for (k, &t) in times.iter().enumerate() {
            for m in 0..3u32 {
                let sphere = (k as u32 % 5 + m).wrapping_mul(0x9E37_79B9);
                fields.push((t, sphere));
            }
        }
        for &(t, s) in &fields {
            let e = Entry::new(t, s);
            assert_eq!((e.t().to_bits(), e.sphere()), (t.to_bits(), s));
        }
        for &(ta, sa) in &fields {
            for &(tb, sb) in &fields {
                let want = ta.total_cmp(&tb).then(sa.cmp(&sb));
                let got = Entry::new(ta, sa).cmp(&Entry::new(tb, sb));
                assert_eq!(got, want, "({ta:e}, {sa}) against ({tb:e}, {sb})");
            }
        }
    }

    /// No event is `+∞`, nor NaN, even where `+∞`'s bucket (the last, `i64::MAX`) is within a
    /// year of the current one: such a schedule only drops the sphere's earlier event.
    #[test]
    fn an_infinite_time_is_no_event_near_the_last_bucket() {
        // Bucket numbers near 2⁶³: the start's is `2⁶³ − 2¹⁰`, the ring 4096 long.
        let t0 = 2.0 - f64::EPSILON;
        let mut q = Calendar::new(2f64.powi(-62), 4096, 3, t0);
        assert_eq!(bucket(t0, q.inv_width), (1 << 63) - (1 << 10));
        q.schedule(0, t0);
        q.schedule(1, 2.0);
        q.schedule(0, f64::INFINITY);
        q.schedule(2, f64::INFINITY);
        q.schedule(1, f64::NAN);
        assert_eq!(q.len(), 0);
        assert_eq!(q.pop(), None);
        q.schedule(2, 2.0);
        assert_eq!(q.pop(), Some((2.0, 2)));
        assert_eq!(q.pop(), None);
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
    /// earlier event was (a bucket, the current bucket, the overflow array).
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
