//! Sphere `i`'s contacts with the spheres of its neighbour list, predicted in f64, four at a
//! time; the two earliest are kept (`predict_pairs`). A prediction screens its list four
//! entries at a time (`screen`) and answers only the approaching pairs that can meet before
//! the sphere's shell event (`answer`): three in five of the others, at φ = 0.4, would be
//! overtaken by that event (rule 6 of docs/derivations/simulation.md). Both passes load the
//! partners' bodies with no branch on what they load, through `passes::named` (every lane
//! names a sphere: `passes.rs`).

use wide::{f64x4, u32x4};

use super::lists::{Quotient, split};
use super::passes::{KEPT_FIRST, named};
use super::*;
use crate::sim::predict::{Kept, arrivals};

/// A neighbour's relative motion from now, as a prediction's passes compute it (`relative`):
/// `r0` and `v` in the first three lanes, the contact distance in the fourth lane of `v`.
#[derive(Debug, Clone, Copy)]
struct Approach {
    r0: f64x4,
    v: f64x4,
    j: u32,
}

/// How many list entries a prediction's first pass wrote to `near` (the pairs to answer), and
/// whether it left out any that cannot meet within its horizon.
struct Screened {
    near: usize,
    beyond: bool,
}

/// Whether the pair is already in contact (a contact is reported once).
fn touching<R: Responder>(responder: &R, i: u32, a: &Approach) -> bool {
    let d = a.v.to_array()[3];
    let (q, d2) = (xyz(a.r0).length_squared(), d * d);
    q < d2 * (1.0 - 1e-9) || responder.touching(i, a.j) && q <= d2 * (1.0 + 1e-9)
}

/// A sphere's body at now as `own_lanes` gives it.
type Own = (f64x4, f64x4);

/// Sphere `i`'s body as lanes of four, its velocity's fourth lane negated: the relative
/// velocity's fourth lane is then the radii's sum, `radiusⱼ − (−radiusᵢ)`, the contact
/// distance, to the bit `radiusᵢ + radiusⱼ` (the sign flip is exact).
#[inline(always)]
fn own_lanes(b: &Trajectory) -> Own {
    let (r, v) = lanes(b);
    (r, v * f64x4::new([1.0, 1.0, 1.0, -1.0]))
}

/// List entry `e`'s motion relative to sphere `i` (`own`, from `own_lanes`) from `now`,
/// lane by lane the same operations, in the same order, as on `DVec3`: the same bits. The
/// fourth lanes carry, in `r0`, `(tⱼ − tᵢ) + radiusⱼ·dt` (unused), and in `v` the contact
/// distance.
///
/// # Safety
///
/// `e` names a sphere: `split(e).0 < bodies.len()` (`passes.rs`, "Every lane names a
/// sphere"). The bounds check this spares was 5 % of the gas's instructions and 2 % of its
/// time (docs/benchmarks.md, "Unchecked loads"); `debug_assert` keeps it in tests.
#[inline(always)]
unsafe fn relative<const GRAVITY: bool>(
    bodies: &[Trajectory],
    shift: &ShiftLanes,
    (ri, vi): (f64x4, f64x4),
    now: f64,
    g: f64x4,
    e: u32,
) -> Approach {
    let (j, code) = split(e);
    // SAFETY: the caller's promise.
    let bj = unsafe { named(bodies, j) };
    let dt = now - bj.t;
    let (rj, vj) = lanes(bj);
    let mut r0 = (rj - ri) + shift[usize::from(code)] + vj * f64x4::splat(dt);
    let mut v = vj - vi;
    if GRAVITY {
        // Both fall alike: their relative motion from now on is a straight line.
        r0 += g * f64x4::splat(0.5 * dt * dt);
        v += g * f64x4::splat(dt);
    }
    Approach { r0, v, j }
}

/// The periodic shift of each list entry's code in lanes of four, the fourth zero.
pub(super) type ShiftLanes = [f64x4; super::lists::SHIFT_ROWS];

/// The shift table in lanes of four.
pub(super) fn shift_lanes(shift: [DVec3; super::lists::SHIFT_ROWS]) -> ShiftLanes {
    shift.map(vector_lanes)
}

/// A vector in lanes of four, the fourth zero.
#[inline(always)]
fn vector_lanes(a: DVec3) -> f64x4 {
    f64x4::new([a.x, a.y, a.z, 0.0])
}

/// A body as two lanes of four, as it lies in memory: centre and time, velocity and radius.
#[inline(always)]
fn lanes(b: &Trajectory) -> (f64x4, f64x4) {
    (
        f64x4::new([b.r.x, b.r.y, b.r.z, b.t]),
        f64x4::new([b.v.x, b.v.y, b.v.z, b.radius]),
    )
}

/// The first three lanes as a vector.
#[inline(always)]
fn xyz(l: f64x4) -> DVec3 {
    let a = l.to_array();
    DVec3::new(a[0], a[1], a[2])
}

/// The latest time a merge may keep from a list and its completeness: anything for a complete
/// list; for an incomplete one, no later than its last kept candidate (what it left out is
/// no earlier than that).
#[inline]
fn bound((l, complete): ([Candidate; 2], bool)) -> f64 {
    if complete {
        f64::INFINITY
    } else {
        l.iter()
            .rev()
            .find(|c| c.t.is_finite())
            .map_or(f64::NEG_INFINITY, |c| c.t)
    }
}

/// The two earliest of two sorted candidate lists and whether the result holds every
/// candidate. An incomplete list only bounds what it left out (no earlier than its last kept
/// candidate), so nothing later than that bound may be kept from the other list: it could come
/// after a candidate nobody kept.
#[inline]
pub(super) fn merge(
    a: ([Candidate; 2], bool),
    b: ([Candidate; 2], bool),
) -> ([Candidate; 2], bool) {
    let limit = bound(a).min(bound(b));
    // The two least of the four, kept as they come (no sort) by the prediction's own rule.
    let mut kept = Kept::default();
    for c in [a.0[0], a.0[1], b.0[0], b.0[1]] {
        if c.t.is_finite() && c.t <= limit {
            kept.add(c);
        }
    }
    let (out, complete) = kept.result();
    (out, a.1 && b.1 && complete)
}

impl<
    R: Responder,
    const PERIODIC: bool,
    const WALLS: bool,
    const GEOMETRY: bool,
    const GRAVITY: bool,
> Engine<R, PERIODIC, WALLS, GEOMETRY, GRAVITY>
{
    /// Sphere `i`'s two earliest contacts with the spheres of its list (or only the entries
    /// `fresh` holds, new to it at its shell event), whether there were no others, and whether
    /// approaching pairs that cannot meet within `horizon` from now (its shell event) were
    /// left out: the first pass screens every entry, the second answers the pairs kept.
    #[inline(always)]
    pub(super) fn predict_pairs(
        &mut self,
        i: u32,
        fresh_only: bool,
        horizon: Option<Quotient>,
    ) -> ([Candidate; 2], bool, bool) {
        let own = own_lanes(&self.m.bodies[i as usize]);
        let Screened { near, beyond } = match horizon {
            None => self.screen_all(i, fresh_only, own),
            Some(horizon) => self.screen(i, fresh_only, horizon, own),
        };
        #[cfg(test)]
        {
            self.left_out += u64::from(beyond);
        }
        let mut kept = Kept::default();
        self.answer(&mut kept, near, own);
        let (pairs, complete) = kept.result();
        (pairs, complete, beyond)
    }

    /// The first pass of a prediction with no horizon: every entry's relative motion from
    /// now, one at a time with no branch on what it loads; the approaching ones
    /// (`r0 · v < 0`) go to `near`. Fewer instructions a list entry than `screen`'s two
    /// tests four at a time, and the same `near`.
    fn screen_all(&mut self, i: u32, fresh_only: bool, own: Own) -> Screened {
        let list = if fresh_only {
            &self.fresh[..self.fresh_len]
        } else {
            self.lists.of(i)
        };
        let room = list.len().next_multiple_of(4);
        if self.near.len() < room {
            self.near.resize(room, 0);
        }
        let g = vector_lanes(self.m.g);
        let mut count = 0;
        for &e in list {
            // SAFETY: a list entry names a sphere.
            let a =
                unsafe { relative::<GRAVITY>(&self.m.bodies, &self.shift, own, self.now, g, e) };
            // The same sums as `DVec3::dot`, in the same order.
            let p = (a.r0 * a.v).to_array();
            let mut keep = (p[0] + p[1]) + p[2] < 0.0;
            if R::REPORT_ONLY {
                keep &= !touching(&self.responder, i, &a);
            }
            self.near[count] = e;
            count += usize::from(keep);
        }
        Screened {
            near: count,
            beyond: false,
        }
    }

    /// The first pass of a prediction: every entry's relative motion from now, four entries
    /// at a time, with no branch on what it loads. The approaching ones (`r0 · v < 0`) go to
    /// `near`, except those that cannot meet within `horizon` (`c + 2bτ > 0`, multiplied by
    /// the horizon's denominator: rule 6 of docs/derivations/simulation.md, "Why no collision
    /// is missed"), which are left out and noted (`Screened::beyond`).
    fn screen(&mut self, i: u32, fresh_only: bool, horizon: Quotient, own: Own) -> Screened {
        let (ri, vi) = own;
        let (list, len) = if fresh_only {
            (&self.fresh[..], self.fresh_len)
        } else {
            self.lists.in_fours(i)
        };
        let now = self.now;
        let room = list.len();
        if self.near.len() < room {
            self.near.resize(room, 0);
        }
        let near = &mut self.near;
        let g = vector_lanes(self.m.g);
        let (twice_num, den) = (f64x4::splat(2.0 * horizon.num), f64x4::splat(horizon.den));
        // SAFETY: every lane names a sphere: list entries, the slots after a list, `fresh`'s
        // zeros (`passes.rs`).
        let motion = |e: u32| unsafe {
            relative::<GRAVITY>(&self.m.bodies, &self.shift, (ri, vi), now, g, e)
        };
        let mut out = Screened {
            near: 0,
            beyond: false,
        };
        // The list is read in whole groups of four: the lanes past its end (slots after it, or
        // `fresh`'s zeros) name spheres and are not counted. No tail is copied.
        for (c, &four) in list.as_chunks::<4>().0.iter().enumerate() {
            let valid = (1u32 << (len - 4 * c).min(4)) - 1;
            let a = [
                motion(four[0]),
                motion(four[1]),
                motion(four[2]),
                motion(four[3]),
            ];
            // The four entries' `b = r0 · v` and `(c + 2bτ) den` at once, in lanes: `b` the
            // same sums as `DVec3::dot`, in the same order (to the bit as before the horizon).
            let [x, y, z, _] = f64x4::transpose([a[0].r0, a[1].r0, a[2].r0, a[3].r0]);
            let [vx, vy, vz, d] = f64x4::transpose([a[0].v, a[1].v, a[2].v, a[3].v]);
            let b = (x * vx + y * vy) + z * vz;
            let c = z.mul_add(z, y.mul_add(y, x * x)) - d * d;
            let e = c.mul_add(den, twice_num * b);
            let mut approaching = b.simd_lt(f64x4::ZERO).to_bitmask() & valid;
            if R::REPORT_ONLY {
                for (k, a) in a.iter().enumerate() {
                    approaching &= !(u32::from(touching(&self.responder, i, a)) << k);
                }
            }
            let late = e.simd_gt(f64x4::ZERO).to_bitmask();
            // The entries kept moved to the front, in order, and written at once (all four:
            // the next group overwrites those not kept; `near` has room for the list rounded
            // up, and a pass writes no more than it reads).
            let keep = approaching & !late;
            let packed = u32x4::new(four).shuffle(KEPT_FIRST[keep as usize & 15]);
            near[out.near..out.near + 4].copy_from_slice(packed.as_array());
            out.near += keep.count_ones() as usize;
            out.beyond |= approaching & late != 0;
        }
        out
    }

    /// The second pass: the first `count` entries of `near` answered four at a time, their
    /// relative motion computed again as the first pass did (`own` the sphere's, the same
    /// bits) and transposed into the kernel's lanes, into `kept` (`near` has room past the
    /// last, each lane naming a sphere; the lanes past it are not counted). Computing it
    /// again costs less than the first pass writing each pair's 96-byte motion for this one.
    #[inline(always)]
    fn answer(&mut self, kept: &mut Kept, count: usize, own: Own) {
        let now = self.now;
        let g = vector_lanes(self.m.g);
        for (at, four) in self.near[..count.next_multiple_of(4)]
            .as_chunks::<4>()
            .0
            .iter()
            .enumerate()
        {
            // SAFETY: every lane of `near` names a sphere (`passes.rs`).
            let motion = |e: u32| unsafe {
                relative::<GRAVITY>(&self.m.bodies, &self.shift, own, now, g, e)
            };
            let a = [
                motion(four[0]),
                motion(four[1]),
                motion(four[2]),
                motion(four[3]),
            ];
            let (t, finite) = arrivals(
                [a[0].r0, a[1].r0, a[2].r0, a[3].r0],
                [a[0].v, a[1].v, a[2].v, a[3].v],
            );
            let mut hits = finite & ((1 << (count - 4 * at).min(4)) - 1);
            while hits != 0 {
                let k = hits.trailing_zeros() as usize;
                hits &= hits - 1;
                // The partner from the entry itself, which is in memory: `a[k].j` was kept on
                // the stack for this (four stores a group).
                let j = split(four[k]).0;
                kept.add(Candidate {
                    t: now + t[k],
                    j,
                    counter: self.m.counter[j as usize],
                });
            }
        }
        self.stats.kernels.sphere += count as u64;
    }
}

#[cfg(test)]
mod tests {
    use super::super::lists::{NO_SHIFT, entry};
    use super::*;
    use crate::rng::Rng;

    /// The unchecked load's guard fires in a test build on an entry that names no sphere
    /// (and lets one that does through, to the same motion as `DVec3` arithmetic).
    #[test]
    #[cfg(debug_assertions)]
    fn an_entry_naming_no_sphere_stops_a_test_build() {
        let body = Trajectory {
            r: DVec3::new(1.0, 2.0, 3.0),
            t: 0.5,
            v: DVec3::new(-1.0, 0.0, 2.0),
            radius: 0.5,
        };
        let bodies = [body];
        let shift = shift_lanes(super::super::lists::shifts(DVec3::splat(10.0), false));
        let own = own_lanes(&Trajectory {
            t: 1.0,
            ..Trajectory::default()
        });
        let zero = f64x4::ZERO;
        // SAFETY: entry 0 names sphere 0 of one.
        let a = unsafe { relative::<false>(&bodies, &shift, own, 1.0, zero, entry(0, NO_SHIFT)) };
        assert_eq!(xyz(a.r0), body.r + body.v * 0.5);
        let past = std::panic::catch_unwind(|| {
            // SAFETY: not kept, on purpose: a test build checks the promise before the load.
            unsafe { relative::<false>(&bodies, &shift, own, 1.0, zero, entry(1, NO_SHIFT)) }
        });
        let message = past.expect_err("an entry past the last sphere is caught");
        let text = message
            .downcast_ref::<String>()
            .expect("a formatted message");
        assert!(text.contains("names no sphere"), "{text}");
    }

    /// The merge by its definition: sort the four, keep the first two within the lists'
    /// bound (`bound`, shared with `merge`: this test is of the selection).
    fn merged_by_sorting(
        a: ([Candidate; 2], bool),
        b: ([Candidate; 2], bool),
    ) -> ([Candidate; 2], bool) {
        let limit = bound(a).min(bound(b));
        let mut all: Vec<Candidate> = [a.0[0], a.0[1], b.0[0], b.0[1]]
            .into_iter()
            .filter(|c| c.t.is_finite() && c.t <= limit)
            .collect();
        all.sort_by(|x, y| x.t.total_cmp(&y.t).then(x.j.cmp(&y.j)));
        let mut out = [Candidate::NONE; 2];
        for (slot, c) in out.iter_mut().zip(&all) {
            *slot = *c;
        }
        (out, a.1 && b.1 && all.len() <= 2)
    }

    /// A sorted list of up to two candidates, times drawn from a few values so that ties
    /// in time (and in time and partner) are common.
    fn list(rng: &mut Rng) -> ([Candidate; 2], bool) {
        let mut pick = || {
            if rng.unit() < 0.25 {
                Candidate::NONE
            } else {
                Candidate {
                    t: (rng.unit() * 4.0).floor(),
                    j: (rng.unit() * 3.0) as u32,
                    counter: 0,
                }
            }
        };
        let mut l = [pick(), pick()];
        if l[1].before(&l[0]) {
            l.swap(0, 1);
        }
        (l, rng.unit() < 0.5)
    }

    #[test]
    fn merge_keeps_the_two_earliest_within_the_bound_as_sorting_would() {
        let mut rng = Rng::new(11);
        for _ in 0..100_000 {
            let (a, b) = (list(&mut rng), list(&mut rng));
            assert_eq!(merge(a, b), merged_by_sorting(a, b), "{a:?} {b:?}");
        }
    }
}
