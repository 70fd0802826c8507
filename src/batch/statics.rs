//! Static-shape entry points: every sphere of a store against one plane, cylinder or
//! container, or against a whole slice of them (the earliest per sphere). A slice that is
//! empty never runs its kind's kernel.

use std::marker::PhantomData;

use super::driver::{LaneKernel, fill, store_lanes, with_mode};
use super::{BatchError, FirstContact, QueryOptions, check_output};
use crate::contact::{Body, contact_at};
use crate::kernels::against_static;
use crate::kernels::quadratic::Solver;
use crate::lanes::Lanes;
pub use crate::statics::StaticShape;
use crate::statics::{ShapeFn, Static};
use crate::store::SphereStore;

struct AgainstOne<'a, L: Lanes, S, K: StaticShape> {
    spheres: &'a SphereStore,
    original: &'a K,
    shape: K::Lanes<L>,
    t_max: L,
    solver: PhantomData<S>,
}

impl<L: Lanes, S: Solver, K: StaticShape> LaneKernel for AgainstOne<'_, L, S, K> {
    type Item = f32;
    const WIDTH: usize = L::WIDTH;
    #[inline(always)]
    fn write(&self, i: usize, out: &mut [f32]) {
        let g = i / L::WIDTH;
        let reload = || self.spheres.lanes(g);
        let t =
            against_static::<L, S, K>(&reload(), &self.shape, self.original, self.t_max, reload);
        store_lanes(t, out);
    }
}

/// Time of impact of every sphere of `spheres` with one static `shape`, into `out`: no
/// allocation, the layout for a hot loop against one floor, pillar or vessel.
///
/// # Errors
/// If `out` does not have one slot per sphere.
///
/// ```
/// use spheresweep::{Container, QueryOptions, Sphere, SphereStore, batch::static_times};
/// let vessel = Container::new([0.0; 3], 5.0)?;
/// let balls = SphereStore::from_spheres(&[Sphere::new([0.0; 3], [0.0, 2.0, 0.0], 1.0, 1.0)?]);
/// let mut out = [0.0];
/// static_times(&balls, &vessel, QueryOptions::default(), &mut out)?;
/// assert_eq!(out, [2.0]);
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub fn static_times<K: StaticShape>(
    spheres: &SphereStore,
    shape: &K,
    options: QueryOptions,
    out: &mut [f32],
) -> Result<(), BatchError> {
    check_output(spheres.len(), out)?;
    fn run<L: Lanes, S: Solver, K: StaticShape>(
        spheres: &SphereStore,
        shape: &K,
        t: f32,
        out: &mut [f32],
    ) {
        let (t_max, solver) = (L::splat(t), PhantomData::<S>);
        let kernel = AgainstOne::<L, S, K> {
            spheres,
            original: shape,
            shape: shape.prepare::<L>(),
            t_max,
            solver,
        };
        fill(out, &kernel);
    }
    with_mode!(
        options.accuracy(),
        run::<K>(spheres, shape, options.t_max(), out)
    );
    Ok(())
}

/// [`static_times`] for one shape of a kind known at run time ([`Static`]).
///
/// # Errors
/// If `out` does not have one slot per sphere.
///
/// ```
/// use spheresweep::{Plane, QueryOptions, Sphere, SphereStore, Static, batch::static_times_any};
/// let floor = Static::from(Plane::new([0.0; 3], [0.0, 0.0, 1.0])?);
/// let balls = SphereStore::from_spheres(&[Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0)?]);
/// let mut out = [0.0];
/// static_times_any(&balls, &floor, QueryOptions::default(), &mut out)?;
/// assert_eq!(out, [2.0]);
/// # Ok::<(), spheresweep::Error>(())
/// ```
pub fn static_times_any(
    spheres: &SphereStore,
    shape: &Static,
    options: QueryOptions,
    out: &mut [f32],
) -> Result<(), BatchError> {
    struct Times<'a> {
        spheres: &'a SphereStore,
        options: QueryOptions,
        out: &'a mut [f32],
    }
    impl ShapeFn for Times<'_> {
        type Output = Result<(), BatchError>;
        fn call<K: StaticShape>(self, shape: &K) -> Self::Output {
            static_times(self.spheres, shape, self.options, self.out)
        }
    }
    shape.apply(Times {
        spheres,
        options,
        out,
    })
}

/// For every sphere of `spheres`, its earliest contact with any of `shapes` (ties: the
/// lowest index), with geometry if the options ask for it. An empty slice runs no kernel.
///
/// # Panics
/// Above 2³² shapes (a [`Body`] index is a `u32`; such a slice would take 96 GiB).
///
/// ```
/// use spheresweep::{Plane, QueryOptions, Sphere, SphereStore, batch::earliest_static_contacts};
/// let floor = [Plane::new([0.0; 3], [0.0, 0.0, 1.0])?];
/// let balls = SphereStore::from_spheres(&[Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0)?]);
/// let hits = earliest_static_contacts(&balls, &floor, QueryOptions::default());
/// assert_eq!(hits[0].unwrap().time, 2.0);
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
pub fn earliest_static_contacts<K: StaticShape>(
    spheres: &SphereStore,
    shapes: &[K],
    options: QueryOptions,
) -> Vec<Option<FirstContact>> {
    assert!(
        u32::try_from(shapes.len()).is_ok(),
        "at most 2^32 static shapes of one kind"
    );
    let mut out = vec![None; spheres.len()];
    if shapes.is_empty() {
        return out;
    }
    with_mode!(
        options.accuracy(),
        run_earliest::<K>(spheres, shapes, options.t_max(), &mut out)
    );
    if options.geometry() {
        for (i, slot) in out.iter_mut().enumerate() {
            if let Some(hit) = slot {
                let sphere = spheres.get(i).expect("index below len");
                let shape = &shapes[hit.body.index as usize];
                hit.geometry = Some(contact_at(&sphere, &(*shape).into(), hit.time.into()));
            }
        }
    }
    out
}

/// Every sphere of a lane group against every prepared shape: the earliest, lowest index.
/// Indices ride in integer lanes beside the times.
struct EarliestOf<'a, L: Lanes, S, K: StaticShape> {
    spheres: &'a SphereStore,
    originals: &'a [K],
    shapes: Vec<K::Lanes<L>>,
    t_max: L,
    t_max_f32: f32,
    solver: PhantomData<S>,
}

impl<L: Lanes, S: Solver, K: StaticShape> LaneKernel for EarliestOf<'_, L, S, K> {
    type Item = Option<FirstContact>;
    const WIDTH: usize = L::WIDTH;
    #[inline(always)]
    fn write(&self, i: usize, out: &mut [Option<FirstContact>]) {
        let g = i / L::WIDTH;
        let s = self.spheres.lanes::<L>(g);
        let mut best = L::splat(f32::INFINITY);
        let mut best_j = L::index_splat(0);
        // With several shapes, one box around the group's swept spheres lets a shape the group
        // cannot reach skip its kernel (the lanes would all be +∞).
        let cull = (self.shapes.len() > 1)
            .then(|| group_box(self.spheres, i..i + out.len(), self.t_max_f32))
            .flatten();
        for (j, (shape, original)) in self.shapes.iter().zip(self.originals).enumerate() {
            if let Some((lo, hi)) = cull
                && !original.may_reach(lo, hi)
            {
                continue;
            }
            let reload = || self.spheres.lanes::<L>(g);
            let t = against_static::<L, S, K>(&s, shape, original, self.t_max, reload);
            let sooner = t.lt(best);
            best = L::select(sooner, t, best);
            best_j = L::index_select(sooner, L::index_splat(j as u32), best_j);
        }
        let (mut times, mut which) = ([0.0f32; 8], [0u32; 8]);
        best.store(&mut times);
        L::index_store(best_j, &mut which);
        for ((slot, time), j) in out.iter_mut().zip(times).zip(which) {
            *slot = time.is_finite().then_some(FirstContact {
                time,
                body: Body::new(K::KIND, j),
                geometry: None,
            });
        }
    }
}

fn run_earliest<L: Lanes, S: Solver, K: StaticShape>(
    spheres: &SphereStore,
    shapes: &[K],
    t: f32,
    out: &mut [Option<FirstContact>],
) {
    let kernel = EarliestOf::<L, S, K> {
        spheres,
        originals: shapes,
        shapes: shapes.iter().map(K::prepare).collect(),
        t_max: L::splat(t),
        t_max_f32: t,
        solver: PhantomData,
    };
    fill(out, &kernel);
}

/// The box around spheres `range` of `spheres` swept over `[0, t_max]`, in f64 and padded by
/// `2⁻¹⁰` of its size — far beyond any kernel's rounding, so a sphere a kernel could report
/// as touching a shape never lies outside it. `None` (no cull) when the box is not finite.
fn group_box(
    spheres: &SphereStore,
    range: std::ops::Range<usize>,
    t_max: f32,
) -> Option<(glam::DVec3, glam::DVec3)> {
    use glam::DVec3;
    let t = f64::from(t_max);
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for i in range {
        let s = spheres.get(i)?;
        let (c, v, r) = (
            s.centre().as_dvec3(),
            s.velocity().as_dvec3(),
            f64::from(s.radius()),
        );
        let e = c + v * t;
        lo = lo.min(c.min(e) - r);
        hi = hi.max(c.max(e) + r);
    }
    let pad = (lo.abs().max(hi.abs()).max_element() + (hi - lo).max_element()) / 1024.0
        + f64::MIN_POSITIVE;
    (lo.is_finite() && hi.is_finite()).then(|| (lo - pad, hi + pad))
}
