//! parry3d 0.31 `Bvh` as a broad-phase peer: candidate pairs of swept AABBs.
//!
//! Two strategies are offered, both reporting every unordered pair `i < j` of
//! boxes whose *closed* extents overlap on all three axes (boxes that only
//! touch on a face, edge or corner count as overlapping, as in parry):
//!
//! * [`ParryRebuild`]: builds a fresh tree from all boxes every step
//!   (`Bvh::from_iter` with the binned SAH builder), then self-traverses it.
//! * [`ParryIncremental`]: keeps one tree; each step rewrites every leaf in
//!   place (`Bvh::insert_or_update_partially`, margin 0), refits all internal
//!   boxes (`Bvh::refit`), then self-traverses it. Topology is kept from the
//!   first build, so this is the peer's best case when the scene moves little.
//!
//! Boxes are given as parallel slices `lo[i]`, `hi[i]` (`lo <= hi` per axis);
//! box `i` becomes leaf `i`. Pair callbacks receive `(i, j)` with `i < j`.

use parry3d::bounding_volume::Aabb;
use parry3d::math::Vector;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

/// Converts one `lo`/`hi` box into parry's [`Aabb`].
///
/// ```
/// let aabb = spheresweep_bench::peer::to_aabb([0.0, 1.0, 2.0], [3.0, 4.0, 5.0]);
/// assert_eq!((aabb.mins.x, aabb.maxs.z), (0.0, 5.0));
/// ```
#[inline]
pub fn to_aabb(lo: [f32; 3], hi: [f32; 3]) -> Aabb {
    Aabb::new(Vector::from(lo), Vector::from(hi))
}

/// Iterator of `(leaf index, Aabb)` over parallel `lo`/`hi` slices.
fn leaves<'a>(
    lo: &'a [[f32; 3]],
    hi: &'a [[f32; 3]],
) -> impl ExactSizeIterator<Item = (usize, Aabb)> + 'a {
    assert_eq!(lo.len(), hi.len(), "lo and hi must have the same length");
    assert!(
        lo.len() < (1 << 30),
        "parry's Bvh stores leaf counts in 30 bits"
    );
    lo.iter().zip(hi).map(|(l, h)| to_aabb(*l, *h)).enumerate()
}

/// Self-traversal of `bvh`: calls `f(i, j)` (with `i < j`) once per
/// overlapping leaf pair and returns the number of pairs.
///
/// Uses `traverse_bvtt_single_tree::<false>`, i.e. without change detection:
/// all overlapping pairs are reported, not only those involving moved leaves.
fn self_pairs(bvh: &Bvh, ws: &mut BvhWorkspace, f: &mut impl FnMut(u32, u32)) -> u64 {
    let mut count = 0u64;
    bvh.traverse_bvtt_single_tree::<false>(ws, &mut |a, b| {
        count += 1;
        if a < b { f(a, b) } else { f(b, a) }
    });
    count
}

/// Rebuild-every-step peer: a fresh `Bvh` per step, then a self-traversal.
///
/// ```
/// // Boxes 0 and 1 overlap, 1 and 2 touch on a face (closed boxes: a pair), 0 and 2 are apart.
/// let lo = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
/// let hi = [[2.0, 1.0, 1.0], [3.0, 1.0, 1.0], [4.0, 1.0, 1.0]];
/// use spheresweep_bench::peer::ParryRebuild;
/// let mut pairs = Vec::new();
/// assert_eq!(ParryRebuild::new().collect(&lo, &hi, &mut pairs), 2);
/// pairs.sort();
/// assert_eq!(pairs, [(0, 1), (1, 2)]);
/// ```
#[derive(Default)]
pub struct ParryRebuild {
    /// Build strategy (default: [`BvhBuildStrategy::Binned`], the faster builder).
    pub strategy: BvhBuildStrategy,
    ws: BvhWorkspace,
}

impl ParryRebuild {
    /// A rebuilder using the binned SAH build.
    ///
    /// ```
    /// assert_eq!(spheresweep_bench::peer::ParryRebuild::new().count(&[], &[]), 0);
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// Builds a tree over the boxes and returns the number of overlapping pairs.
    ///
    /// ```
    /// # let lo = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
    /// # let hi = [[2.0, 1.0, 1.0], [3.0, 1.0, 1.0], [4.0, 1.0, 1.0]];
    /// assert_eq!(spheresweep_bench::peer::ParryRebuild::new().count(&lo, &hi), 2);
    /// ```
    pub fn count(&mut self, lo: &[[f32; 3]], hi: &[[f32; 3]]) -> u64 {
        self.for_each_pair(lo, hi, |_, _| {})
    }

    /// Like [`Self::count`], also appending every pair `(i, j)`, `i < j`, to `out`.
    ///
    /// ```
    /// # let lo = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
    /// # let hi = [[2.0, 1.0, 1.0], [3.0, 1.0, 1.0], [4.0, 1.0, 1.0]];
    /// let mut pairs = vec![(7, 7)]; // appended to
    /// spheresweep_bench::peer::ParryRebuild::new().collect(&lo, &hi, &mut pairs);
    /// assert_eq!(pairs.len(), 3);
    /// ```
    pub fn collect(&mut self, lo: &[[f32; 3]], hi: &[[f32; 3]], out: &mut Vec<(u32, u32)>) -> u64 {
        self.for_each_pair(lo, hi, |i, j| out.push((i, j)))
    }

    /// Builds a tree over the boxes and calls `f(i, j)` per overlapping pair.
    ///
    /// ```
    /// # let lo = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
    /// # let hi = [[2.0, 1.0, 1.0], [3.0, 1.0, 1.0], [4.0, 1.0, 1.0]];
    /// let mut touched = [0; 3];
    /// spheresweep_bench::peer::ParryRebuild::new().for_each_pair(&lo, &hi, |i, j| {
    ///     assert!(i < j);
    ///     touched[i as usize] += 1;
    ///     touched[j as usize] += 1;
    /// });
    /// assert_eq!(touched, [1, 2, 1]);
    /// ```
    pub fn for_each_pair(
        &mut self,
        lo: &[[f32; 3]],
        hi: &[[f32; 3]],
        mut f: impl FnMut(u32, u32),
    ) -> u64 {
        let bvh = Bvh::from_iter(self.strategy, leaves(lo, hi));
        self_pairs(&bvh, &mut self.ws, &mut f)
    }
}

/// Persistent-tree peer: update leaves in place, refit, self-traverse.
///
/// ```
/// // Boxes 0 and 1 overlap, 1 and 2 touch on a face (closed boxes: a pair), 0 and 2 are apart.
/// let lo = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
/// let hi = [[2.0, 1.0, 1.0], [3.0, 1.0, 1.0], [4.0, 1.0, 1.0]];
/// use spheresweep_bench::peer::ParryIncremental;
/// let mut peer = ParryIncremental::new();
/// assert_eq!(peer.count(&lo, &hi), 2); // builds the tree
/// let far = [[0.0; 3], [10.0, 0.0, 0.0], [20.0, 0.0, 0.0]];
/// let far_hi = [[2.0, 1.0, 1.0], [12.0, 1.0, 1.0], [22.0, 1.0, 1.0]];
/// assert_eq!(peer.count(&far, &far_hi), 0); // leaves moved in place, tree refitted
/// ```
#[derive(Default)]
pub struct ParryIncremental {
    bvh: Bvh,
    ws: BvhWorkspace,
    /// If set, also run `Bvh::optimize_incremental` after each refit
    /// (re-builds ~5% of the tree per call, as a physics engine would).
    pub optimize: bool,
}

impl ParryIncremental {
    /// An empty peer; the first step (or any change of box count) builds the tree.
    ///
    /// ```
    /// assert_eq!(spheresweep_bench::peer::ParryIncremental::new().count(&[], &[]), 0);
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// Updates the tree to the boxes and returns the number of overlapping pairs.
    ///
    /// ```
    /// # let lo = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
    /// # let hi = [[2.0, 1.0, 1.0], [3.0, 1.0, 1.0], [4.0, 1.0, 1.0]];
    /// let mut peer = spheresweep_bench::peer::ParryIncremental::new();
    /// assert_eq!((peer.count(&lo, &hi), peer.count(&lo, &hi)), (2, 2)); // build, then update
    /// ```
    pub fn count(&mut self, lo: &[[f32; 3]], hi: &[[f32; 3]]) -> u64 {
        self.for_each_pair(lo, hi, |_, _| {})
    }

    /// Like [`Self::count`], also appending every pair `(i, j)`, `i < j`, to `out`.
    ///
    /// ```
    /// # let lo = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
    /// # let hi = [[2.0, 1.0, 1.0], [3.0, 1.0, 1.0], [4.0, 1.0, 1.0]];
    /// let mut pairs = Vec::new();
    /// spheresweep_bench::peer::ParryIncremental::new().collect(&lo, &hi, &mut pairs);
    /// pairs.sort();
    /// assert_eq!(pairs, [(0, 1), (1, 2)]);
    /// ```
    pub fn collect(&mut self, lo: &[[f32; 3]], hi: &[[f32; 3]], out: &mut Vec<(u32, u32)>) -> u64 {
        self.for_each_pair(lo, hi, |i, j| out.push((i, j)))
    }

    /// Updates the tree to the boxes and calls `f(i, j)` per overlapping pair.
    ///
    /// When the number of boxes differs from the tree's leaf count the tree is
    /// rebuilt from scratch (binned); otherwise every leaf `i` is overwritten
    /// with box `i` (no fattening margin, so the reported pairs are exact)
    /// and the tree is refitted bottom-up with its topology unchanged.
    ///
    /// ```
    /// # let lo = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
    /// # let hi = [[2.0, 1.0, 1.0], [3.0, 1.0, 1.0], [4.0, 1.0, 1.0]];
    /// let mut count = 0;
    /// let mut peer = spheresweep_bench::peer::ParryIncremental::new();
    /// let n = peer.for_each_pair(&lo, &hi, |_, _| count += 1);
    /// assert_eq!((n, count), (2, 2));
    /// ```
    pub fn for_each_pair(
        &mut self,
        lo: &[[f32; 3]],
        hi: &[[f32; 3]],
        mut f: impl FnMut(u32, u32),
    ) -> u64 {
        if self.bvh.leaf_count() as usize != lo.len() {
            self.bvh = Bvh::from_iter(BvhBuildStrategy::Binned, leaves(lo, hi));
        } else {
            for (i, aabb) in leaves(lo, hi) {
                self.bvh.insert_or_update_partially(aabb, i as u32, 0.0);
            }
            self.bvh.refit(&mut self.ws);
            if self.optimize {
                self.bvh.optimize_incremental(&mut self.ws);
            }
        }
        self_pairs(&self.bvh, &mut self.ws, &mut f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed-box overlap, the reference predicate.
    fn overlap(lo: &[[f32; 3]], hi: &[[f32; 3]], i: usize, j: usize) -> bool {
        (0..3).all(|k| lo[i][k] <= hi[j][k] && lo[j][k] <= hi[i][k])
    }

    fn brute(lo: &[[f32; 3]], hi: &[[f32; 3]]) -> Vec<(u32, u32)> {
        let mut v = Vec::new();
        for i in 0..lo.len() {
            for j in i + 1..lo.len() {
                if overlap(lo, hi, i, j) {
                    v.push((i as u32, j as u32));
                }
            }
        }
        v
    }

    /// SplitMix64 in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn f(&mut self) -> f32 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    fn scene(rng: &mut Rng, n: usize, side: f32) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
        let mut lo = Vec::with_capacity(n);
        let mut hi = Vec::with_capacity(n);
        for _ in 0..n {
            let c = [rng.f() * side, rng.f() * side, rng.f() * side];
            let e = [
                0.2 + 2.0 * rng.f(),
                0.2 + 2.0 * rng.f(),
                0.2 + 2.0 * rng.f(),
            ];
            lo.push([c[0] - e[0], c[1] - e[1], c[2] - e[2]]);
            hi.push([c[0] + e[0], c[1] + e[1], c[2] + e[2]]);
        }
        (lo, hi)
    }

    fn check(got: &mut Vec<(u32, u32)>, count: u64, want: &[(u32, u32)]) {
        assert_eq!(count as usize, got.len());
        got.sort_unstable();
        assert!(got.windows(2).all(|w| w[0] != w[1]), "duplicate pair");
        assert_eq!(got.as_slice(), want);
    }

    #[test]
    fn random_scene_matches_brute_force() {
        let mut rng = Rng(7);
        let (mut lo, mut hi) = scene(&mut rng, 2000, 40.0);
        let want = brute(&lo, &hi);
        assert!(want.len() > 1000, "scene too sparse: {}", want.len());

        let mut got = Vec::new();
        let count = ParryRebuild::new().collect(&lo, &hi, &mut got);
        check(&mut got, count, &want);

        let mut inc = ParryIncremental::new();
        let mut inc_opt = ParryIncremental {
            optimize: true,
            ..Default::default()
        };
        for step in 0..6 {
            let want = brute(&lo, &hi);
            for p in [&mut inc, &mut inc_opt] {
                got.clear();
                let count = p.collect(&lo, &hi, &mut got);
                check(&mut got, count, &want);
            }
            eprintln!("step {step}: {} pairs", want.len());
            // Jitter every box (including large jumps for a few) before the next step.
            for i in 0..lo.len() {
                let jump = if i % 97 == 0 { 20.0 } else { 0.5 };
                for k in 0..3 {
                    let d = (rng.f() - 0.5) * jump;
                    lo[i][k] += d;
                    hi[i][k] += d;
                }
            }
        }
    }

    #[test]
    fn touching_and_degenerate_boxes() {
        // 0 and 1 share the face x = 1; 2 touches 1 only at the corner (2,1,1);
        // 3 is a point on 0's surface; 4 is a copy of 0; 5 is separated by a float ulp.
        let lo = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 1.0, 1.0],
            [0.5, 1.0, 0.5],
            [0.0, 0.0, 0.0],
            [f32::from_bits(2.0f32.to_bits() + 1), 0.0, 0.0],
        ];
        let hi = [
            [1.0, 1.0, 1.0],
            [2.0, 1.0, 1.0],
            [3.0, 2.0, 2.0],
            [0.5, 1.0, 0.5],
            [1.0, 1.0, 1.0],
            [3.0, 0.5, 0.5],
        ];
        let want = brute(&lo, &hi);
        assert!(want.contains(&(0, 1)) && want.contains(&(1, 2)) && want.contains(&(0, 3)));
        assert!(!want.iter().any(|&(i, j)| i == 5 || j == 5));
        let mut got = Vec::new();
        let count = ParryRebuild::new().collect(&lo, &hi, &mut got);
        check(&mut got, count, &want);
        let mut inc = ParryIncremental::new();
        for _ in 0..2 {
            got.clear();
            let count = inc.collect(&lo, &hi, &mut got);
            check(&mut got, count, &want);
        }
    }

    #[test]
    fn tiny_inputs() {
        for n in 0..4 {
            let lo = vec![[0.0; 3]; n];
            let hi = vec![[1.0; 3]; n];
            let want = (n * n.saturating_sub(1) / 2) as u64;
            assert_eq!(ParryRebuild::new().count(&lo, &hi), want, "rebuild n={n}");
            let mut inc = ParryIncremental::new();
            assert_eq!(inc.count(&lo, &hi), want, "incremental build n={n}");
            assert_eq!(inc.count(&lo, &hi), want, "incremental update n={n}");
        }
    }
}

/// The swept boxes of `store`'s spheres over `[0, t_max]`, as the peer takes them (`lo`, `hi`
/// cleared first): `min(c, c + v t_max) − r` and `max(…) + r` per axis.
///
/// ```
/// use spheresweep::{Sphere, SphereStore};
/// use spheresweep_bench::peer::swept_boxes_into;
/// let sphere = Sphere::new([0.0; 3], [-1.0, 0.0, 2.0], 0.5, 1.0).unwrap();
/// let store = SphereStore::from_spheres(&[sphere]);
/// let (mut lo, mut hi) = (Vec::new(), Vec::new());
/// swept_boxes_into(&store, 2.0, &mut lo, &mut hi);
/// assert_eq!((lo[0], hi[0]), ([-2.5, -0.5, -0.5], [0.5, 0.5, 4.5]));
/// ```
pub fn swept_boxes_into(
    store: &spheresweep::SphereStore,
    t_max: f32,
    lo: &mut Vec<[f32; 3]>,
    hi: &mut Vec<[f32; 3]>,
) {
    lo.clear();
    hi.clear();
    for s in store.iter() {
        let (c, e, r) = (s.centre(), s.centre_at(t_max), s.radius());
        lo.push((c.min(e) - r).to_array());
        hi.push((c.max(e) + r).to_array());
    }
}

/// The whole first-contact query on parry3d: [`ParryIncremental`] for the candidate pairs,
/// then `query::cast_shapes` on each, the earliest per sphere kept — what a parry user writes.
///
/// ```
/// use spheresweep::{QueryOptions, Sphere, SphereStore, batch::earliest_sphere_contact};
/// use spheresweep_bench::peer::ParryQuery;
/// let store = SphereStore::from_spheres(&[
///     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0).unwrap(),
///     Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0).unwrap(),
///     Sphere::new([0.0, 50.0, 0.0], [0.0; 3], 1.0, 1.0).unwrap(),
/// ]);
/// let mut out = [0.0; 3];
/// ParryQuery::new().first_contacts(&store, 10.0, &mut out);
/// assert!((out[0] - 4.0).abs() < 1e-3 && (out[1] - 4.0).abs() < 1e-3);
/// assert_eq!(out[2], f32::INFINITY);
/// ```
#[derive(Default)]
pub struct ParryQuery {
    broad: ParryIncremental,
    lo: Vec<[f32; 3]>,
    hi: Vec<[f32; 3]>,
    balls: Vec<(parry3d::math::Pose, Vector, parry3d::shape::Ball)>,
}

impl ParryQuery {
    /// A query with an empty tree.
    ///
    /// ```
    /// use spheresweep::SphereStore;
    /// let mut out: [f32; 0] = [];
    /// let mut query = spheresweep_bench::peer::ParryQuery::new();
    /// assert_eq!(query.first_contacts(&SphereStore::new(), 1.0, &mut out), 0);
    /// ```
    pub fn new() -> Self {
        Self::default()
    }

    /// The earliest contact time of every sphere of `store` with any other in `[0, t_max]`
    /// (`+∞` for none), written to `out`; returns the number of candidate pairs.
    ///
    /// ```
    /// use spheresweep::{Sphere, SphereStore};
    /// use spheresweep_bench::peer::ParryQuery;
    /// let store = SphereStore::from_spheres(&[
    ///     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0).unwrap(),
    ///     Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0).unwrap(),
    /// ]);
    /// let mut out = [0.0; 2];
    /// // One candidate pair over [0, 10]; none over [0, 1], where the boxes are apart.
    /// assert_eq!(ParryQuery::new().first_contacts(&store, 10.0, &mut out), 1);
    /// assert_eq!(ParryQuery::new().first_contacts(&store, 1.0, &mut out), 0);
    /// assert_eq!(out, [f32::INFINITY; 2]);
    /// ```
    pub fn first_contacts(
        &mut self,
        store: &spheresweep::SphereStore,
        t_max: f32,
        out: &mut [f32],
    ) -> u64 {
        use parry3d::query::{ShapeCastOptions, cast_shapes};
        swept_boxes_into(store, t_max, &mut self.lo, &mut self.hi);
        self.balls.clear();
        self.balls.extend(store.iter().map(|s| {
            (
                parry3d::math::Pose::from_translation(s.centre()),
                s.velocity(),
                parry3d::shape::Ball::new(s.radius()),
            )
        }));
        out.fill(f32::INFINITY);
        let options = ShapeCastOptions {
            max_time_of_impact: t_max,
            stop_at_penetration: true,
            ..Default::default()
        };
        let balls = &self.balls;
        self.broad.for_each_pair(&self.lo, &self.hi, |i, j| {
            let ((p1, v1, g1), (p2, v2, g2)) = (&balls[i as usize], &balls[j as usize]);
            if let Ok(Some(hit)) = cast_shapes(p1, *v1, g1, p2, *v2, g2, options) {
                let t = hit.time_of_impact;
                out[i as usize] = out[i as usize].min(t);
                out[j as usize] = out[j as usize].min(t);
            }
        })
    }
}
