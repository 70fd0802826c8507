//! Sphere `i`'s neighbours, predicted in named stages: gather (the 27 cells around it, or
//! the 9 newly adjacent after a crossing, with their periodic images), screen eight at a time
//! in f32, settle the survivors in f64; the two earliest contacts are kept.

use super::*;

/// A predicted pair contact: when, with whom, and the partner's counter at the prediction (the
/// prediction is stale once the partner's velocity has changed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Candidate {
    pub t: f64,
    pub j: u32,
    pub counter: u32,
}

impl Candidate {
    pub(super) const NONE: Self = Self {
        t: f64::INFINITY,
        j: NONE,
        counter: 0,
    };

    #[inline]
    pub(super) fn before(&self, o: &Self) -> bool {
        self.t < o.t || (self.t == o.t && self.j < o.j)
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
    let bound = |(l, complete): ([Candidate; 2], bool)| {
        if complete {
            f64::INFINITY
        } else {
            l.iter()
                .rev()
                .find(|c| c.t.is_finite())
                .map_or(f64::NEG_INFINITY, |c| c.t)
        }
    };
    let limit = bound(a).min(bound(b));
    let mut all = [a.0[0], a.0[1], b.0[0], b.0[1]];
    all.sort_unstable_by(|x, y| x.t.total_cmp(&y.t).then(x.j.cmp(&y.j)));
    let mut out = [Candidate::NONE; 2];
    let mut complete = a.1 && b.1;
    for (kept, c) in all
        .into_iter()
        .filter(|c| c.t.is_finite() && c.t <= limit)
        .enumerate()
    {
        if kept == 2 {
            complete = false;
            break;
        }
        out[kept] = c;
    }
    (out, complete)
}

/// Every stencil image `x + 3y + 9z` (offsets `x − 1`, `y − 1`, `z − 1`).
const ALL_IMAGES: [u8; 27] = {
    let mut a = [0u8; 27];
    let mut k = 0;
    while k < 27 {
        a[k] = k as u8;
        k += 1;
    }
    a
};

/// The nine images of the layer a crossing reaches, per axis and direction (`2·axis + up`).
const LAYER_IMAGES: [[u8; 9]; 6] = {
    let mut t = [[0u8; 9]; 6];
    let mut axis = 0;
    while axis < 3 {
        let mut up = 0;
        while up < 2 {
            let (mut k, mut m) = (0usize, 0usize);
            while k < 27 {
                let o = [k % 3, k / 3 % 3, k / 9];
                if o[axis] == 2 * up {
                    t[2 * axis + up][m] = k as u8;
                    m += 1;
                }
                k += 1;
            }
            up += 1;
        }
        axis += 1;
    }
    t
};

impl<R: Responder, const PERIODIC: bool, const WALLS: bool, const GEOMETRY: bool>
    Engine<R, PERIODIC, WALLS, GEOMETRY>
{
    /// Gathers sphere `i`'s neighbours (all 27 cells, or the 9 newly adjacent after a crossing
    /// along `layer`), screens them eight at a time; returns the two earliest contacts and
    /// whether there were no others. The stages: gather, screen (f32), settle (f64).
    pub(super) fn predict_pairs(
        &mut self,
        i: u32,
        layer: Option<(usize, i32)>,
    ) -> ([Candidate; 2], bool) {
        let bi = self.m.bodies[i as usize];
        self.gather_neighbours(i, &bi, layer);
        let count = self.screen_neighbours(i, &bi);
        self.stats.kernels.sphere += count as u64;
        if count == 0 {
            return ([Candidate::NONE; 2], true);
        }
        self.settle_candidates(&bi)
    }

    /// The neighbours of sphere `i` (body `bi`) into `near` as (index, image), and each
    /// image's offset (its periodic shift minus `bi`'s centre) into `offsets`. Each
    /// neighbour's cache line is touched here, so that the misses overlap (the loads are
    /// independent) and the screen computes from lines already near.
    fn gather_neighbours(&mut self, i: u32, bi: &Trajectory, layer: Option<(usize, i32)>) {
        let ci = self.cells.at[i as usize];
        let n = self.cells.n;
        self.near.clear();
        let interior = (0..3).all(|k| ci[k] >= 1 && ci[k] <= n[k] - 2);
        let touch = if interior {
            self.gather_interior(ci, bi, layer)
        } else {
            self.gather_at_edge(ci, bi, layer)
        };
        std::hint::black_box(touch);
    }

    /// [`gather_neighbours`](Self::gather_neighbours) in a cell with no wrap and no edge: the
    /// stencil is a fixed table of index deltas. Returns the touched values' sum.
    fn gather_interior(
        &mut self,
        ci: [i32; 3],
        bi: &Trajectory,
        layer: Option<(usize, i32)>,
    ) -> f64 {
        let mut touch = 0.0;
        let base = self.cells.index(ci);
        let images: &[u8] = match layer {
            None => &ALL_IMAGES,
            Some((axis, step)) => &LAYER_IMAGES[2 * axis + usize::from(step > 0)],
        };
        for &image in images {
            let cell = base.wrapping_add_signed(self.cells.delta[usize::from(image)]);
            let members = self.cells.members(cell);
            if members.is_empty() {
                continue;
            }
            self.offsets[usize::from(image)] = -bi.r;
            for &j in members {
                touch += self.m.bodies[j as usize].t;
                self.near.push((j, image));
            }
        }
        touch
    }

    /// [`gather_neighbours`](Self::gather_neighbours) in a cell at the domain's edge: per axis
    /// the neighbour cells wrap (periodic, with an image shift) or are skipped (open).
    /// Returns the touched values' sum.
    fn gather_at_edge(
        &mut self,
        ci: [i32; 3],
        bi: &Trajectory,
        layer: Option<(usize, i32)>,
    ) -> f64 {
        let (n, len) = (self.cells.n, self.cells.len);
        // Per axis and offset −1, 0, +1: the wrapped cell coordinate (−1 when outside an open
        // domain) and the image shift.
        let mut coord = [[0i32; 3]; 3];
        let mut shift = [[0f64; 3]; 3];
        for k in 0..3 {
            for (o, d) in (-1..=1).enumerate() {
                let mut c = ci[k] + d;
                if c < 0 || c >= n[k] {
                    if PERIODIC {
                        let wrap = if c < 0 { 1 } else { -1 };
                        c += wrap * n[k];
                        shift[k][o] = -f64::from(wrap) * len[k];
                    } else {
                        c = -1;
                    }
                }
                coord[k][o] = c;
            }
        }
        // Which offsets to visit per axis.
        let (mut ox, mut oy, mut oz) = (0..3usize, 0..3usize, 0..3usize);
        if let Some((axis, step)) = layer {
            let o = (step + 1) as usize;
            match axis {
                0 => ox = o..o + 1,
                1 => oy = o..o + 1,
                _ => oz = o..o + 1,
            }
        }
        let mut touch = 0.0;
        let (nx, ny) = (n[0] as usize, n[1] as usize);
        for z in oz {
            let cz = coord[2][z];
            if !PERIODIC && cz < 0 {
                continue;
            }
            for y in oy.clone() {
                let cy = coord[1][y];
                if !PERIODIC && cy < 0 {
                    continue;
                }
                let row = (cz as usize * ny + cy as usize) * nx;
                for x in ox.clone() {
                    let cx = coord[0][x];
                    if !PERIODIC && cx < 0 {
                        continue;
                    }
                    let members = self.cells.members(row + cx as usize);
                    if members.is_empty() {
                        continue;
                    }
                    let image = x + 3 * y + 9 * z;
                    self.offsets[image] = DVec3::new(shift[0][x], shift[1][y], shift[2][z]) - bi.r;
                    for &j in members {
                        touch += self.m.bodies[j as usize].t;
                        self.near.push((j, image as u8));
                    }
                }
            }
        }
        touch
    }

    /// The f32 screen of the gathered neighbours against sphere `i` (body `bi`), eight at a
    /// time; returns how many pairs it ran.
    fn screen_neighbours(&mut self, i: u32, bi: &Trajectory) -> usize {
        let now = self.now;
        self.batch.start(self.near.len());
        for &(j, image) in &self.near {
            let bj = &self.m.bodies[j as usize];
            let r0 = bj.r + bj.v * (now - bj.t) + self.offsets[usize::from(image)];
            let v = bj.v - bi.v;
            let d = bi.radius + bj.radius;
            // Only an approaching pair (r0 · v < 0) can meet: the others are written but not
            // counted (no branch to mispredict). The sphere itself has v = 0.
            let mut keep = r0.dot(v) < 0.0;
            if R::REPORT_ONLY {
                // A pair already in contact is not reported again.
                let (q, d2) = (r0.length_squared(), d * d);
                keep &= !(q < d2 * (1.0 - 1e-9)
                    || self.responder.touching(i, j) && q <= d2 * (1.0 + 1e-9));
            }
            self.batch.push_if(keep, r0, v, d, j, image);
        }
        self.batch.finish();
        self.batch.len()
    }

    /// The screen's candidates settled in f64, four at a time: the two earliest contacts
    /// with sphere `bi`, and whether there were no others (the screen kept them all, and at
    /// most two settled).
    fn settle_candidates(&mut self, bi: &Trajectory) -> ([Candidate; 2], bool) {
        let now = self.now;
        let mut complete = self.batch.candidates(&mut self.candidates);
        let mut top = [Candidate::NONE; 2];
        let mut found = 0;
        for chunk in self.candidates.chunks(4) {
            let mut r0 = [DVec3::ZERO; 4];
            let mut v = [DVec3::ZERO; 4];
            let mut d = [f64::NAN; 4];
            for (lane, &k) in chunk.iter().enumerate() {
                let (j, image) = self.batch.who[k];
                let bj = &self.m.bodies[j as usize];
                r0[lane] = bj.r + bj.v * (now - bj.t) + self.offsets[usize::from(image)];
                v[lane] = bj.v - bi.v;
                d[lane] = bi.radius + bj.radius;
            }
            let t = refine(r0, v, d);
            for (lane, &k) in chunk.iter().enumerate() {
                let j = self.batch.who[k].0;
                found += usize::from(t[lane].is_finite());
                if !t[lane].is_finite() {
                    continue;
                }
                let c = Candidate {
                    t: now + t[lane],
                    j,
                    counter: self.m.counter[j as usize],
                };
                if c.before(&top[0]) {
                    top = [c, top[0]];
                } else if c.before(&top[1]) {
                    top[1] = c;
                }
            }
        }
        // A third contact settled in f64 is not kept either.
        complete &= found <= 2;
        (top, complete)
    }
}
