//! Each sphere's neighbour list with a shell (the recipe of Smallenburg's EDMD, Eur. Phys. J. E
//! 45, 22 (2022)): sphere `i` has a shell centre `cᵢ`, where it was when its list was last
//! built, and stays within `δ` of it until its shell event. Its list holds every sphere `j`
//! (with the periodic shift of `j`'s image) whose centre is within `dᵢⱼ + reach` of `cᵢ`,
//! where `reach` is `2δ` and a little more. Two spheres that touch before either leaves its
//! shell therefore have centres closer than that, so each is in the other's list. The lists
//! are symmetric and change only when a sphere rebuilds its own.
//! The bound and its rounding: docs/derivations/simulation.md, "Neighbour lists".

use glam::DVec3;
use wide::f64x2;

use crate::sim::runs::Runs;

/// The shift code of no periodic shift (every entry's in an open domain; `x + 3y + 9z` with
/// each of `x, y, z` in `0…2` for a shift of `−1, 0, +1` box lengths).
pub(crate) const NO_SHIFT: u8 = 13;

/// Bits of an entry that hold the shift code.
pub(crate) const CODE_BITS: u32 = 5;

/// The most spheres a list entry can name.
pub(crate) const MAX_SPHERES: usize = 1 << (32 - CODE_BITS);

/// A list entry: sphere `j` and the shift code of its image.
#[inline(always)]
pub(crate) fn entry(j: u32, code: u8) -> u32 {
    j << CODE_BITS | u32::from(code)
}

/// The sphere and shift code of a list entry.
#[inline(always)]
pub(crate) fn split(e: u32) -> (u32, u8) {
    (e >> CODE_BITS, (e & ((1 << CODE_BITS) - 1)) as u8)
}

/// The shift code seen from the other sphere (the shift negated).
#[inline(always)]
pub(crate) fn mirror(code: u8) -> u8 {
    26 - code
}

/// Bits of a rebuild's mark below its epoch: a shift code, and whether the entry is kept.
const MARK_BITS: u32 = CODE_BITS + 1;

/// Where an entry of a new list stood in the list it replaces (`NeighbourLists::match_new`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Before {
    /// The same entry: it stays in both lists.
    Same,
    /// The same sphere, another image.
    OtherImage,
    /// Not there.
    Absent,
}

/// Rows of the shift table: one for every value of an entry's code bits, so that a code
/// indexes it with no bounds check (codes 27–31 never occur; their rows are zero).
pub(crate) const SHIFT_ROWS: usize = 1 << CODE_BITS;

/// The periodic shift of each code for box lengths `len` (all zero for an open domain).
pub(crate) fn shifts(len: DVec3, periodic: bool) -> [DVec3; SHIFT_ROWS] {
    std::array::from_fn(|code| {
        if !periodic || code >= 27 {
            return DVec3::ZERO;
        }
        let s = [code % 3, code / 3 % 3, code / 9].map(|x| x as f64 - 1.0);
        DVec3::from_array(s) * len
    })
}

/// A time from now left as the quotient `num / den` (`num ≥ 0`, `den > 0`): a prediction's
/// screen multiplies through by `den` rather than wait on the division (rule 6 of
/// docs/derivations/simulation.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Quotient {
    pub num: f64,
    pub den: f64,
}

impl Quotient {
    /// The time, `num / den` (at least zero).
    #[inline(always)]
    pub fn value(self) -> f64 {
        (self.num / self.den).max(0.0)
    }

    /// A quotient no shorter than the time from `now` to `fl(now + self.value())`, the
    /// event as scheduled: `num (1 + 2⁻⁵⁰) + now 2⁻⁵⁰ den` over `den` covers the two
    /// roundings (rule 6 of docs/derivations/simulation.md, "Which τ").
    #[inline(always)]
    pub fn reaching(self, now: f64) -> Self {
        const SLACK: f64 = 1.0 / (1u64 << 50) as f64;
        Self {
            num: self.num.mul_add(1.0 + SLACK, now * SLACK * self.den),
            den: self.den,
        }
    }
}

/// Time from now until a sphere at `p` from its shell centre, moving at `v`, is `delta` from
/// it: the larger root of `‖p + v t‖² = δ²` (`‖p‖ ≤ δ`), in the form without cancellation;
/// `+∞` at rest.
#[cfg(test)]
pub(crate) fn shell_exit(p: DVec3, v: DVec3, delta: f64) -> f64 {
    shell_exit_quotient(p, v, delta).map_or(f64::INFINITY, Quotient::value)
}

/// `shell_exit` before its division; `None` at rest.
#[inline(always)]
pub(crate) fn shell_exit_quotient(p: DVec3, v: DVec3, delta: f64) -> Option<Quotient> {
    let a = v.length_squared();
    if a == 0.0 {
        return None;
    }
    let b = p.dot(v);
    let c = (p.length_squared() - delta * delta).min(0.0);
    let root = (b * b - a * c).max(0.0).sqrt();
    // The operands chosen by a blend, not a branch: the sign of `b` is a coin toss (`if` on
    // scalars compiled to a branch in some of the engine's copies).
    let positive = f64x2::splat(b).simd_gt(f64x2::ZERO);
    let chosen = positive.select(f64x2::new([-c, b + root]), f64x2::new([root - b, a]));
    let [num, den] = chosen.to_array();
    Some(Quotient { num, den })
}

/// Under a uniform acceleration `g`, a time before which a sphere `p` from its shell centre,
/// moving at `v`, cannot leave a shell of half-width `delta`: it moves at most
/// `‖v‖ t + ‖g‖ t²/2` in time `t`, so the positive root of `‖g‖ t²/2 + ‖v‖ t = delta − ‖p‖`
/// (in the form without cancellation) is a lower bound on the exact quartic's root. A shell
/// event that comes early only rebuilds the list sooner (docs/derivations/gravity.md).
pub(crate) fn shell_exit_falling(p: DVec3, v: DVec3, g: DVec3, delta: f64) -> f64 {
    let (a, b) = (0.5 * g.length(), v.length());
    let c = (delta - p.length()).max(0.0);
    let t = 2.0 * c / (b + (b * b + 4.0 * a * c).sqrt());
    if t.is_nan() { 0.0 } else { t }
}

/// A sphere's shell centre and its radius, side by side: a rebuild reads one line per
/// sphere it looks at.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(C, align(32))]
pub(crate) struct Shell {
    pub c: DVec3,
    pub radius: f64,
}

/// The lists, one run of slots per sphere, and the shell centres.
#[derive(Debug, Clone)]
pub(crate) struct NeighbourLists {
    /// How far a sphere may move from its shell centre before its shell event.
    pub delta: f64,
    /// Added to a pair's contact distance for the list test: `2δ` and a rounding margin.
    pub reach: f64,
    /// The widest list test, the largest diameter plus the reach, with a margin: no sphere
    /// is listed by a centre farther than this.
    pub far: f64,
    /// Each sphere's shell centre (periodic centres inside the box) and radius.
    pub centre: Vec<Shell>,
    /// Each sphere's entries.
    entries: Runs,
    /// Scratch for a rebuild: each sphere's mark from the last rebuild that met it, the
    /// epoch and a code (`mark`): listed in the list being replaced under that shift code, or
    /// kept in the new list under it too.
    seen: Vec<u32>,
    epoch: u32,
}

impl NeighbourLists {
    /// Empty lists for `n` spheres with shells of half-width `delta`, centred at `centre`.
    pub fn new(delta: f64, centre: Vec<Shell>) -> Self {
        let n = centre.len();
        let reach = 2.0 * delta * (1.0 + REACH_MARGIN);
        let widest = centre.iter().map(|s| 2.0 * s.radius).fold(0.0, f64::max);
        Self {
            delta,
            reach,
            far: (widest + reach) * (1.0 + REACH_MARGIN),
            centre,
            entries: Runs::new(n, 8),
            seen: vec![0; n],
            epoch: 0,
        }
    }

    /// Starts a rebuild: a new epoch, which no sphere's mark holds yet.
    #[inline]
    pub fn next_epoch(&mut self) {
        if self.epoch == u32::MAX >> MARK_BITS {
            self.seen.fill(0);
            self.epoch = 0;
        }
        self.epoch += 1;
    }

    /// This rebuild's mark of an entry with code `code`, listed in the old list, or `kept`
    /// in the new one as well.
    #[inline(always)]
    fn mark(&self, code: u8, kept: bool) -> u32 {
        self.epoch << MARK_BITS | u32::from(kept) << CODE_BITS | u32::from(code)
    }

    /// Marks entry `e` of the list being replaced.
    #[inline]
    pub fn mark_old(&mut self, e: u32) {
        let (j, code) = split(e);
        self.seen[j as usize] = self.mark(code, false);
    }

    /// Where entry `e` of the new list stood in the list it replaces: under the same code (it
    /// is then marked kept: both lists, and the other sphere's, keep it), under another code,
    /// or not at all.
    #[inline]
    pub fn match_new(&mut self, e: u32) -> Before {
        let (j, code) = split(e);
        let (old, kept) = (self.mark(code, false), self.mark(code, true));
        let seen = &mut self.seen[j as usize];
        if *seen == old {
            *seen = kept;
            Before::Same
        } else if *seen >> MARK_BITS == self.epoch {
            Before::OtherImage
        } else {
            Before::Absent
        }
    }

    /// Whether entry `e` of the replaced list is kept in the new one (after `match_new`).
    #[inline]
    pub fn was_kept(&self, e: u32) -> bool {
        let (j, code) = split(e);
        self.seen[j as usize] == self.mark(code, true)
    }

    /// Sphere `i`'s entries.
    #[inline(always)]
    pub fn of(&self, i: u32) -> &[u32] {
        self.entries.of(i as usize)
    }

    /// Sphere `i`'s entries read in groups of four (`Runs::in_fours`), and how many there are.
    #[inline(always)]
    pub fn in_fours(&self, i: u32) -> (&[u32], usize) {
        self.entries.in_fours(i as usize)
    }

    /// Sphere `i`'s list slots, used or not.
    #[inline(always)]
    pub fn room(&self, i: u32) -> &[u32] {
        self.entries.room(i as usize)
    }

    /// Adds an entry to sphere `i`'s list.
    #[inline]
    pub fn push(&mut self, i: u32, e: u32) {
        self.entries.push(i as usize, e);
    }

    /// Makes sphere `i`'s list `entries`.
    #[inline]
    pub fn set(&mut self, i: u32, entries: &[u32]) {
        self.entries.set(i as usize, entries);
    }

    /// Removes entry `e` from sphere `i`'s list (a list holds an entry at most once).
    #[inline]
    pub fn remove(&mut self, i: u32, e: u32) {
        self.entries.remove_value(i as usize, e);
    }

    /// Empties sphere `i`'s list.
    #[inline]
    pub fn clear(&mut self, i: u32) {
        self.entries.clear(i as usize);
    }

    /// Renumbers: sphere `new` takes old sphere `order[new]`'s centre and list, whose entries
    /// name spheres by `new_of_old`.
    pub fn permute(&mut self, order: &[u32], new_of_old: &[u32]) {
        self.centre = crate::sim::pages::collected(order.iter().map(|&o| self.centre[o as usize]));
        self.entries.permute(order, |e| {
            let (j, code) = split(e);
            entry(new_of_old[j as usize], code)
        });
        self.seen.fill(0);
        self.epoch = 0;
    }

    /// Bytes the lists and centres hold.
    pub fn bytes(&self) -> usize {
        self.entries.bytes()
            + self.seen.capacity() * 4
            + self.centre.capacity() * std::mem::size_of::<Shell>()
    }
}

/// The reach's margin over `2δ`, relative: far above the rounding of a shell event's time and
/// position (a few ulps of `δ`, docs/derivations/simulation.md), far below anything that
/// costs.
pub(crate) const REACH_MARGIN: f64 = 1.0 / (1 << 20) as f64;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn entries_round_trip_and_mirror() {
        for (j, code) in [(0, 0), (5, 13), (MAX_SPHERES as u32 - 1, 26)] {
            assert_eq!(split(entry(j, code)), (j, code));
        }
        let s = shifts(DVec3::new(2.0, 3.0, 5.0), true);
        for code in 0..27u8 {
            assert_eq!(s[usize::from(mirror(code))], -s[usize::from(code)]);
        }
        assert_eq!(s[usize::from(NO_SHIFT)], DVec3::ZERO);
        assert!(shifts(DVec3::ONE, false).iter().all(|s| *s == DVec3::ZERO));
    }

    /// The exit time puts the sphere on the shell, from anywhere inside it, both ways.
    #[test]
    fn a_falling_sphere_is_inside_its_shell_until_the_bound() {
        let mut rng = Rng::new(5);
        for _ in 0..10_000 {
            let delta = 0.1 + rng.unit();
            let p = rng.direction() * delta * rng.unit();
            let v = rng.direction() * 10f64.powf(4.0 * rng.unit() - 2.0);
            let g = rng.direction() * 10f64.powf(4.0 * rng.unit() - 2.0);
            let t = shell_exit_falling(p, v, g, delta);
            assert!(t > 0.0 || p.length() >= delta);
            // Sampled along the way, and at the bound itself: never out.
            for k in 0..=16 {
                let s = t * f64::from(k) / 16.0;
                let at = (p + v * s + g * (0.5 * s * s)).length();
                assert!(at <= delta * (1.0 + 1e-12), "{p} {v} {g}: {at} vs {delta}");
            }
            // Not needlessly early: without gravity it is the straight line's own bound.
            let straight = shell_exit_falling(p, v, DVec3::ZERO, delta);
            let expected = (delta - p.length()) / v.length();
            assert!((straight - expected).abs() <= 1e-12 * expected);
        }
    }

    #[test]
    fn the_shell_exit_is_on_the_shell() {
        let mut rng = Rng::new(3);
        for _ in 0..10_000 {
            let delta = 0.1 + rng.unit();
            let p = rng.direction() * delta * rng.unit();
            let v = rng.direction() * 10f64.powf(4.0 * rng.unit() - 2.0);
            let t = shell_exit(p, v, delta);
            let at = (p + v * t).length();
            assert!(
                (at - delta).abs() <= 1e-12 * delta,
                "{p} {v}: {at} vs {delta}"
            );
        }
        assert_eq!(shell_exit(DVec3::X, DVec3::ZERO, 2.0), f64::INFINITY);
        // On the shell and leaving: now.
        assert_eq!(shell_exit(DVec3::X, DVec3::X, 1.0), 0.0);
    }

    /// `m 2^e` of a positive normal `x`, exactly.
    fn dyadic(x: f64) -> (i128, i32) {
        assert!(x.is_normal() && x > 0.0, "{x}");
        let bits = x.to_bits();
        let e = (bits >> 52) as i32;
        (i128::from(bits & ((1 << 52) - 1) | 1 << 52), e - 1075)
    }

    /// Whether `num / den ≥ later − now`, in exact arithmetic (`later ≥ now`), for the
    /// magnitudes of the test below: every product fits in an `i128`.
    fn reaches(num: f64, den: f64, now: f64, later: f64) -> bool {
        let ((m_now, e_now), (m_later, e_later)) = (dyadic(now), dyadic(later));
        // `later − now` in units of `now`'s last place (`later` is in its binade or above).
        let gap = (m_later << (e_later - e_now)) - m_now;
        let ((m_den, e_den), (m_num, e_num)) = (dyadic(den), dyadic(num));
        let shift = e_num - (e_now + e_den);
        assert!((0..60).contains(&shift), "{shift}");
        m_num << shift >= gap * m_den
    }

    /// The horizon reaches the shell event as scheduled, `fl(now + fl(num / den))`, past
    /// both roundings, exactly; the quotient before `reaching` falls short of it in some
    /// cases, so the slack is needed (rule 6 of docs/derivations/simulation.md, "Which τ").
    #[test]
    fn the_horizon_reaches_the_shell_event_as_scheduled() {
        let mut rng = Rng::new(11);
        let mut short = 0;
        for _ in 0..200_000 {
            let now = 2f64.powf(rng.range(10.0, 19.9));
            let (num, den) = (2f64.powf(rng.range(-4.9, 4.9)), rng.range(1.0, 1.999));
            let q = Quotient { num, den };
            let scheduled = now + q.value();
            let r = q.reaching(now);
            assert!(reaches(r.num, r.den, now, scheduled), "{num} {den} {now}");
            short += usize::from(!reaches(num, den, now, scheduled));
        }
        assert!(short > 1000, "{short}");
    }

    /// A rebuild's marks: an entry of both lists is kept, by its sphere and code; another
    /// image of a listed sphere is not the same entry; a new epoch forgets every mark.
    #[test]
    fn a_rebuild_keeps_the_entries_of_both_lists_by_sphere_and_code() {
        let mut l = NeighbourLists::new(0.1, vec![Shell::default(); 3]);
        // Sphere 1 under two images (codes 4 and 22) in the old list, only one in the new.
        for (old, matched) in [
            ([entry(1, 4), entry(1, 22), entry(2, 13)], Before::Same),
            (
                [entry(1, 22), entry(1, 4), entry(2, 13)],
                Before::OtherImage,
            ),
        ] {
            l.next_epoch();
            for &e in &old {
                l.mark_old(e);
            }
            assert_eq!(l.match_new(entry(1, 22)), matched);
            assert_eq!(l.match_new(entry(0, 13)), Before::Absent);
            assert_eq!(l.was_kept(entry(1, 22)), matched == Before::Same);
            assert!(!l.was_kept(entry(1, 4)));
            assert!(!l.was_kept(entry(2, 13)));
        }
        l.next_epoch();
        assert!(!l.was_kept(entry(1, 22)));
        assert_eq!(l.match_new(entry(1, 22)), Before::Absent);
        // The epochs wrap: every mark is cleared, none survives.
        l.mark_old(entry(2, 13));
        l.epoch = u32::MAX >> MARK_BITS;
        l.next_epoch();
        assert_eq!(l.epoch, 1);
        assert_eq!(l.match_new(entry(2, 13)), Before::Absent);
    }

    #[test]
    fn lists_push_remove_grow_and_permute() {
        let mut l = NeighbourLists::new(0.1, vec![Shell::default(); 3]);
        for k in 0..40 {
            l.push(1, entry(k % 3, (k % 27) as u8));
        }
        assert_eq!(l.of(1).len(), 40);
        for k in (0..40).filter(|k| k % 3 == 2) {
            l.remove(1, entry(2, (k % 27) as u8));
        }
        assert_eq!(l.of(1).len(), 27);
        assert!(l.of(1).iter().all(|&e| split(e).0 != 2));
        // An entry not there changes nothing.
        l.remove(1, entry(2, 0));
        assert_eq!(l.of(1).len(), 27);
        l.push(0, entry(1, 4));
        // Reversed order: new 0 is old 2, new 2 is old 0.
        let order = [2, 1, 0];
        l.permute(&order, &order);
        assert_eq!(l.of(2), &[entry(1, 4)]);
        assert_eq!(l.of(1).len(), 27);
        assert!(l.of(1).iter().all(|&e| split(e).0 != 0));
        assert!(l.of(0).is_empty());
        l.clear(1);
        assert!(l.of(1).is_empty());
    }
}
