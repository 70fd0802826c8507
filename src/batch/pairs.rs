//! Sphere-pair entry points: two stores paired element by element, explicit pair lists, one
//! sphere against a store, and the single-pair query for any kind of body.

use std::marker::PhantomData;

use super::driver::{LaneKernel, fill, store_lanes, with_mode};
use super::{BatchError, FirstContact, QueryOptions, check_output};
use crate::contact::{Body, contact_at};
use crate::kernels::quadratic::Solver;
use crate::kernels::{StaticKernel, against_static, sphere_pair};
use crate::lanes::Lanes;
use crate::shape::{Container, Cylinder, Plane, Shape, ShapeKind, Sphere};
use crate::store::{Gather, SphereLanes, SphereStore};

struct Zip<'a, L, S> {
    a: &'a SphereStore,
    b: &'a SphereStore,
    t_max: L,
    solver: PhantomData<S>,
}

impl<L: Lanes, S: Solver> LaneKernel for Zip<'_, L, S> {
    type Item = f32;
    const WIDTH: usize = L::WIDTH;
    #[inline(always)]
    fn write(&self, i: usize, out: &mut [f32]) {
        let g = i / L::WIDTH;
        let reload = || [self.a.lanes(g), self.b.lanes(g)];
        let t = sphere_pair::<L, S>(&self.a.lanes(g), &self.b.lanes(g), self.t_max, reload);
        store_lanes(t, out);
    }
}

struct Listed<'a, L, S, G> {
    store: &'a G,
    pairs: &'a [[u32; 2]],
    t_max: L,
    solver: PhantomData<S>,
}

impl<L: Lanes, S: Solver, G: Gather> LaneKernel for Listed<'_, L, S, G> {
    type Item = f32;
    const WIDTH: usize = L::WIDTH;
    #[inline(always)]
    fn write(&self, i: usize, out: &mut [f32]) {
        let group = &self.pairs[i..i + out.len()];
        let gather = |k: usize| {
            self.store
                .gather::<L>(group.iter().map(move |p| p[k] as usize))
        };
        let reload = || [gather(0), gather(1)];
        let t = sphere_pair::<L, S>(&gather(0), &gather(1), self.t_max, reload);
        store_lanes(t, out);
    }
}

struct OneAgainst<'a, L, S> {
    one: SphereLanes<L>,
    block: &'a SphereStore,
    t_max: L,
    solver: PhantomData<S>,
}

impl<L: Lanes, S: Solver> LaneKernel for OneAgainst<'_, L, S> {
    type Item = f32;
    const WIDTH: usize = L::WIDTH;
    #[inline(always)]
    fn write(&self, i: usize, out: &mut [f32]) {
        let g = i / L::WIDTH;
        let reload = || [self.one, self.block.lanes(g)];
        let t = sphere_pair::<L, S>(&self.one, &self.block.lanes(g), self.t_max, reload);
        store_lanes(t, out);
    }
}

/// Time of impact of `a[i]` with `b[i]` for every `i`, into `out[i]` (`+∞`: no contact).
/// The fastest layout: both stores are read as contiguous blocks.
///
/// # Errors
/// If the stores differ in length or `out` does not have one slot per pair.
///
/// ```
/// use spheresweep::{Accuracy, QueryOptions, Sphere, SphereStore, batch::zip_times};
/// let a = SphereStore::from_spheres(&[Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?]);
/// let b = SphereStore::from_spheres(&[Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?]);
/// let mut out = [0.0];
/// zip_times(&a, &b, QueryOptions::new(100.0, Accuracy::Stable)?, &mut out)?;
/// assert_eq!(out, [4.0]);
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub fn zip_times(
    a: &SphereStore,
    b: &SphereStore,
    options: QueryOptions,
    out: &mut [f32],
) -> Result<(), BatchError> {
    if a.len() != b.len() {
        return Err(BatchError::StoreLengths {
            a: a.len(),
            b: b.len(),
        });
    }
    check_output(a.len(), out)?;
    fn run<L: Lanes, S: Solver>(a: &SphereStore, b: &SphereStore, t: f32, out: &mut [f32]) {
        let (t_max, solver) = (L::splat(t), PhantomData::<S>);
        fill(
            out,
            &Zip {
                a,
                b,
                t_max,
                solver,
            },
        );
    }
    with_mode!(options.accuracy(), run(a, b, options.t_max(), out));
    Ok(())
}

/// Time of impact of every listed pair `[i, j]` of spheres of `store`, into `out`.
///
/// # Errors
/// If an index is out of range or `out` does not have one slot per pair.
///
/// ```
/// use spheresweep::{QueryOptions, Sphere, SphereStore, batch::pair_times};
/// let store = SphereStore::from_spheres(&[
///     Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?,
///     Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?,
///     Sphere::new([0.0, 9.0, 0.0], [0.0; 3], 1.0, 1.0)?,
/// ]);
/// let mut out = [0.0; 2];
/// pair_times(&store, &[[0, 1], [0, 2]], QueryOptions::default(), &mut out)?;
/// assert_eq!(out, [4.0, f32::INFINITY]);
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub fn pair_times(
    store: &SphereStore,
    pairs: &[[u32; 2]],
    options: QueryOptions,
    out: &mut [f32],
) -> Result<(), BatchError> {
    listed_times(store, pairs, options, out)
}

/// [`pair_times`] over any gather source (the store, or packed records in a broad phase's
/// cell order).
pub(crate) fn listed_times<G: Gather>(
    store: &G,
    pairs: &[[u32; 2]],
    options: QueryOptions,
    out: &mut [f32],
) -> Result<(), BatchError> {
    check_output(pairs.len(), out)?;
    for (pair, ij) in pairs.iter().enumerate() {
        if let Some(&index) = ij.iter().find(|&&k| k as usize >= store.count()) {
            return Err(BatchError::IndexOutOfRange {
                pair,
                index,
                len: store.count(),
            });
        }
    }
    fn run<L: Lanes, S: Solver, G: Gather>(store: &G, pairs: &[[u32; 2]], t: f32, o: &mut [f32]) {
        let (t_max, solver) = (L::splat(t), PhantomData::<S>);
        fill(
            o,
            &Listed {
                store,
                pairs,
                t_max,
                solver,
            },
        );
    }
    with_mode!(
        options.accuracy(),
        run::<G>(store, pairs, options.t_max(), out)
    );
    Ok(())
}

/// The pairs of `pairs` (indices into `store`, checked by the caller) that touch in the
/// window: `hit(pair, time)` for each, in order; the same times, bit for bit, as
/// [`pair_times`]. One thread, no output buffer: the fused pass of the scene query calls it on
/// the few thousand pairs the broad phase has just found.
#[inline]
pub(crate) fn listed_hits<G: Gather>(
    store: &G,
    pairs: &[[u32; 2]],
    options: QueryOptions,
    hit: &mut impl FnMut([u32; 2], f32),
) {
    fn run<L: Lanes, S: Solver, G: Gather>(
        store: &G,
        pairs: &[[u32; 2]],
        t: f32,
        hit: &mut impl FnMut([u32; 2], f32),
    ) {
        let t_max = L::splat(t);
        let none = L::splat(f32::INFINITY);
        for group in pairs.chunks(L::WIDTH) {
            let gather = |k: usize| {
                if L::WIDTH == 8 && group.len() == 8 {
                    store.gather8::<L>(std::array::from_fn(|j| group[j][k] as usize))
                } else {
                    store.gather::<L>(group.iter().map(move |p| p[k] as usize))
                }
            };
            let reload = || [gather(0), gather(1)];
            let t = sphere_pair::<L, S>(&gather(0), &gather(1), t_max, reload);
            // Padding lanes (NaN spheres) never hit.
            let mut touching = t.lt(none).bits();
            if touching == 0 {
                continue;
            }
            let mut times = [0.0f32; 8];
            t.store(&mut times[..L::WIDTH]);
            while touching != 0 {
                let k = touching.trailing_zeros() as usize;
                hit(group[k], times[k]);
                touching &= touching - 1;
            }
        }
    }
    with_mode!(
        options.accuracy(),
        run::<G>(store, pairs, options.t_max(), hit)
    );
}

/// Time of impact of `sphere` with every sphere of `block`, into `out`.
///
/// # Errors
/// If `out` does not have one slot per sphere of `block`.
///
/// ```
/// use spheresweep::{QueryOptions, Sphere, SphereStore, batch::one_against_times};
/// let ball = Sphere::new([0.0; 3], [2.0, 0.0, 0.0], 1.0, 1.0)?;
/// let block = SphereStore::from_spheres(&[
///     Sphere::new([10.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?, // gap 8 at speed 2
///     Sphere::new([0.0, 10.0, 0.0], [0.0; 3], 1.0, 1.0)?, // never reached
/// ]);
/// let mut out = [0.0; 2];
/// one_against_times(&ball, &block, QueryOptions::default(), &mut out)?;
/// assert_eq!(out, [4.0, f32::INFINITY]);
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub fn one_against_times(
    sphere: &Sphere,
    block: &SphereStore,
    options: QueryOptions,
    out: &mut [f32],
) -> Result<(), BatchError> {
    check_output(block.len(), out)?;
    fn run<L: Lanes, S: Solver>(s: &Sphere, block: &SphereStore, t: f32, out: &mut [f32]) {
        let (t_max, one, solver) = (L::splat(t), SphereLanes::splat(s), PhantomData::<S>);
        fill(
            out,
            &OneAgainst {
                one,
                block,
                t_max,
                solver,
            },
        );
    }
    with_mode!(options.accuracy(), run(sphere, block, options.t_max(), out));
    Ok(())
}

/// The earliest contact of `sphere` with any sphere of `block` (ties: the lowest index), with
/// its geometry if the options ask for it. If `sphere` is itself in `block`, it does not
/// touch itself (no relative motion).
///
/// ```
/// use spheresweep::{QueryOptions, ShapeKind, Sphere, SphereStore, batch::earliest_sphere_contact};
/// let ball = Sphere::new([0.0; 3], [1.0, 0.0, 0.0], 1.0, 1.0)?;
/// let others = SphereStore::from_spheres(&[Sphere::new([6.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0)?]);
/// let hit = earliest_sphere_contact(&ball, &others, QueryOptions::default()).unwrap();
/// assert_eq!((hit.time, hit.body.kind, hit.body.index), (4.0, ShapeKind::Sphere, 0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn earliest_sphere_contact(
    sphere: &Sphere,
    block: &SphereStore,
    options: QueryOptions,
) -> Option<FirstContact> {
    let mut times = vec![0.0; block.len()];
    one_against_times(sphere, block, options, &mut times).expect("one slot per sphere");
    let (index, &time) =
        times
            .iter()
            .enumerate()
            .fold(None, |best: Option<(usize, &f32)>, (j, t)| match best {
                Some((_, b)) if b <= t => best,
                _ if t.is_finite() => Some((j, t)),
                _ => best,
            })?;
    let other = block.get(index).expect("index below len");
    Some(FirstContact {
        time,
        body: Body::new(ShapeKind::Sphere, index as u32),
        geometry: options
            .geometry()
            .then(|| contact_at(sphere, &Shape::Sphere(other), time.into())),
    })
}

/// The time of impact of one sphere with one body of any kind, on the 8-wide kernel of the
/// options' accuracy mode (one lane used): the same bits a batch gives for the pair.
///
/// ```
/// use spheresweep::{Plane, QueryOptions, Sphere, time_of_impact};
/// let ball = Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0)?;
/// let floor = Plane::new([0.0; 3], [0.0, 0.0, 1.0])?;
/// assert_eq!(time_of_impact(&ball, &floor.into(), QueryOptions::default()), Some(2.0));
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn time_of_impact(sphere: &Sphere, other: &Shape, options: QueryOptions) -> Option<f32> {
    fn one<L: Lanes, S: Solver>(s: &Sphere, other: &Shape, t: f32) -> f32 {
        let (a, t_max) = (SphereLanes::<L>::splat(s), L::splat(t));
        let lanes = match other {
            Shape::Sphere(b) => {
                let b = SphereLanes::splat(b);
                sphere_pair::<L, S>(&a, &b, t_max, || [a, b])
            }
            Shape::Plane(p) => against_static::<L, S, Plane>(&a, &p.prepare::<L>(), p, t_max, || a),
            Shape::Cylinder(c) => {
                against_static::<L, S, Cylinder>(&a, &c.prepare::<L>(), c, t_max, || a)
            }
            Shape::Container(k) => {
                against_static::<L, S, Container>(&a, &k.prepare::<L>(), k, t_max, || a)
            }
        };
        let mut out = [0.0f32; 8];
        lanes.store(&mut out);
        out[0]
    }
    let t = with_mode!(options.accuracy(), one(sphere, other, options.t_max()));
    t.is_finite().then_some(t)
}
