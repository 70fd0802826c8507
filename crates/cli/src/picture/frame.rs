//! The region a picture shows. A scene with a boundary or a vessel is framed by it: the
//! periodic box, else the open box of the cell grid, else its containers. Otherwise the frame
//! is a robust extent of the spheres — the box from the 1st to the 99th percentile of their
//! centres on each axis, grown by a tenth of its size and the largest radius — with the
//! anchors of the planes and cylinders, so that a few far-flung spheres do not shrink the
//! scene to a dot: they are left out of the frame and counted ([`outside`]).

use glam::DVec3;
use spheresweep::sim::SphereState;
use spheresweep::{Container, Cylinder, Plane};

use super::Shapes;

/// The share of the spheres, on each side of each axis, a robust extent may leave out.
const TAIL: f64 = 0.01;

/// The frame of spheres and shapes (every frame of a record at once, so that a sequence
/// stays still), padded by 4 % on each axis.
pub fn bounds<'a>(
    spheres: impl IntoIterator<Item = &'a SphereState>,
    shapes: &Shapes,
) -> (DVec3, DVec3) {
    let (lo, hi) = match own_region(shapes) {
        Some(region) => region,
        None => robust(spheres, shapes),
    };
    if !(lo.is_finite() && hi.is_finite() && hi.cmpge(lo).all()) {
        return (DVec3::splat(-1.0), DVec3::splat(1.0));
    }
    // Each axis by 4 % of its own extent, and at least 1 % of the largest: at any scale (a
    // nanometre scene in metres is framed as one in nanometres). A frame of no extent (points
    // at one place) is given a millionth of its distance from the origin, or 1 at it.
    let extent = hi - lo;
    let least = match extent.max_element() {
        e if e > 0.0 => e * 0.01,
        _ => match lo.abs().max(hi.abs()).max_element() * 1e-6 {
            d if d > 0.0 => d,
            _ => 1.0,
        },
    };
    let pad = (extent * 0.04).max(DVec3::splat(least));
    (lo - pad, hi + pad)
}

/// How many of `spheres` have their centre outside `frame`.
pub fn outside(spheres: &[SphereState], (lo, hi): (DVec3, DVec3)) -> usize {
    spheres
        .iter()
        .filter(|s| !(s.centre.cmpge(lo).all() && s.centre.cmple(hi).all()))
        .count()
}

/// The scene's own region: its periodic box, its open box, or its containers' bounds.
fn own_region(shapes: &Shapes) -> Option<(DVec3, DVec3)> {
    if let Some(size) = shapes.periodic_box {
        return Some((DVec3::ZERO, size));
    }
    if shapes.region.is_some() {
        return shapes.region;
    }
    shapes
        .statics
        .of::<Container>()
        .shapes()
        .iter()
        .map(|k| {
            let (c, r) = (k.centre().as_dvec3(), f64::from(k.radius()));
            (c - r, c + r)
        })
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
}

/// The percentile box of the centres grown by a tenth and the largest radius, with the
/// planes' and cylinders' anchors.
fn robust<'a>(
    spheres: impl IntoIterator<Item = &'a SphereState>,
    shapes: &Shapes,
) -> (DVec3, DVec3) {
    let mut axes: [Vec<f64>; 3] = Default::default();
    let mut radius: f64 = 0.0;
    for s in spheres {
        if s.centre.is_finite() && s.radius.is_finite() {
            for (k, axis) in axes.iter_mut().enumerate() {
                axis.push(s.centre[k]);
            }
            radius = radius.max(s.radius);
        }
    }
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    if !axes[0].is_empty() {
        for (k, axis) in axes.iter_mut().enumerate() {
            let (a, b) = percentiles(axis);
            let grow = (b - a) * 0.1 + radius;
            (lo[k], hi[k]) = (a - grow, b + grow);
        }
    }
    let mut add = |c: DVec3, r: f64| {
        if c.is_finite() && r.is_finite() {
            lo = lo.min(c - r);
            hi = hi.max(c + r);
        }
    };
    for c in shapes.statics.of::<Cylinder>().shapes() {
        add(c.point().as_dvec3(), f64::from(c.radius()));
    }
    for p in shapes.statics.of::<Plane>().shapes() {
        add(p.point().as_dvec3(), 0.0);
    }
    (lo, hi)
}

/// The `TAIL` and `1 − TAIL` quantiles of `values` (nearest rank: the least and the greatest
/// of up to 101 values).
fn percentiles(values: &mut [f64]) -> (f64, f64) {
    let last = values.len() - 1;
    let (i, j) = (
        (TAIL * last as f64).floor() as usize,
        ((1.0 - TAIL) * last as f64).ceil() as usize,
    );
    let a = *values.select_nth_unstable_by(i, f64::total_cmp).1;
    let b = *values.select_nth_unstable_by(j, f64::total_cmp).1;
    (a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ball(x: f64, y: f64, z: f64) -> SphereState {
        SphereState {
            centre: DVec3::new(x, y, z),
            velocity: DVec3::ZERO,
            radius: 0.5,
            mass: 1.0,
            material: 0,
        }
    }

    /// A cloud of 1000 spheres in a unit-spaced 10³ lattice, and one far away.
    fn cloud_and_outlier() -> Vec<SphereState> {
        let mut s: Vec<SphereState> = (0..1000)
            .map(|k| {
                ball(
                    f64::from(k % 10),
                    f64::from(k / 10 % 10),
                    f64::from(k / 100),
                )
            })
            .collect();
        s.push(ball(1e4, 0.0, 0.0));
        s
    }

    #[test]
    fn an_outlier_does_not_change_the_frame_and_is_counted() {
        let spheres = cloud_and_outlier();
        let with = bounds(&spheres, &Shapes::default());
        let without = bounds(&spheres[..1000], &Shapes::default());
        assert_eq!(with, without);
        // 0 … 9 grown by 0.9 and the radius, then padded.
        assert!(with.0.x > -2.0 && with.1.x < 11.0, "{with:?}");
        assert_eq!(outside(&spheres, with), 1);
        assert_eq!(outside(&spheres[..1000], with), 0);
    }

    fn near(a: (DVec3, DVec3), b: (DVec3, DVec3)) -> bool {
        a.0.abs_diff_eq(b.0, 1e-12) && a.1.abs_diff_eq(b.1, 1e-12)
    }

    #[test]
    fn a_boundary_or_vessel_frames_the_scene() {
        let spheres = cloud_and_outlier();
        let boxed = Shapes {
            periodic_box: Some(DVec3::splat(20.0)),
            ..Shapes::default()
        };
        let frame = bounds(&spheres, &boxed);
        assert!(
            near(frame, (DVec3::splat(-0.8), DVec3::splat(20.8))),
            "{frame:?}"
        );
        let open = Shapes {
            region: Some((DVec3::splat(-5.0), DVec3::splat(5.0))),
            ..Shapes::default()
        };
        let frame = bounds(&spheres, &open);
        assert!(
            near(frame, (DVec3::splat(-5.4), DVec3::splat(5.4))),
            "{frame:?}"
        );
        // Spheres beyond 5 (x, y or z of 6 … 9), and the outlier.
        assert_eq!(outside(&spheres, frame), 1000 - 6 * 6 * 6 + 1);
        let vessel = Shapes {
            statics: spheresweep::Statics::new().with(
                spheresweep::Container::new([1.0, 0.0, 0.0], 10.0).unwrap(),
                (),
            ),
            ..Shapes::default()
        };
        let frame = bounds(&spheres, &vessel);
        let want = (DVec3::new(-9.8, -10.8, -10.8), DVec3::new(11.8, 10.8, 10.8));
        assert!(near(frame, want), "{frame:?}");
    }

    #[test]
    fn few_spheres_are_all_in_the_frame() {
        let spheres = [ball(0.0, 0.0, 0.0), ball(100.0, 0.0, 0.0)];
        let frame = bounds(&spheres, &Shapes::default());
        assert_eq!(outside(&spheres, frame), 0);
    }
}
