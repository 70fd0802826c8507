//! What a scene file asks that the engine can only approximate, said as warnings (the run goes
//! on): a sphere so far from the origin that its contacts may overlap past the tolerance
//! ([`World::coarse_sphere`]), and a static shape that its rounding to `f32` moves by more than
//! `2⁻¹⁰` of the smallest sphere's radius where the scene is (docs/derivations/simulation.md,
//! "Contacts far from the origin").

use glam::DVec3;

use super::SceneFile;
use super::error::location;
use super::locate::Seg::{self, At, Key};
use crate::error::Num;
use crate::sim::{Boundary, World};
use crate::{ShapeKind, Static};

/// How far rounding may move a shape, over the smallest sphere's radius, before it is said: a
/// gap or a step sized to a sphere is designed to about a thousandth of it.
const SHAPE_MOVE: f64 = 1.0 / 1024.0;

/// The most shapes named one by one; the rest are counted.
const NAMED: usize = 10;

/// One shape moved by rounding: which, and how far its surface is from the file's within the
/// scene.
struct Moved {
    path: [Seg; 2],
    item: String,
    by: f64,
}

impl SceneFile {
    /// Warnings for the world [`build`](Self::build) made from this file, each at its entry's
    /// line (none in JSON): its coarsest sphere ([`World::coarse_sphere`]), and each shape
    /// whose surface, as stored in `f32`, is more than `2⁻¹⁰` of the smallest sphere's radius
    /// from the file's anywhere within the scene's extent at the start.
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// let text = "[run]\nt_end = 1\n[[sphere]]\ncentre = [0, 0, 1]\nradius = 0.5\n\
    ///     [[plane]]\npoint = [0, 0, 100000000.3]\nnormal = [0, 0, -1]\n";
    /// let scene = SceneFile::from_toml_str(text)?;
    /// let (world, _) = scene.build()?;
    /// let warnings = scene.warnings(&world);
    /// assert!(warnings[0].starts_with("line 6: plane 0: stored in f32"), "{warnings:?}");
    /// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
    /// ```
    pub fn warnings(&self, world: &World) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(coarse) = world.coarse_sphere() {
            let (item, path) = self.sphere_item(coarse.sphere);
            out.push(format!("{}{item}: {}", self.at(&path), coarse.problem()));
        }
        let smallest = world
            .spheres
            .iter()
            .map(|s| s.radius)
            .fold(f64::INFINITY, f64::min);
        let limit = SHAPE_MOVE * smallest;
        let moved: Vec<Moved> = moved_shapes(self, world)
            .into_iter()
            .filter(|m| m.by > limit)
            .collect();
        for m in moved.iter().take(NAMED) {
            out.push(format!(
                "{}{}: stored in f32 (as the library's shapes are), its surface is up to {:.2e} \
                 from the file's where the scene is, more than {:.2e} (2⁻¹⁰ of the smallest \
                 sphere radius, {}): contacts with it happen that far from where the file puts \
                 it; move the scene nearer the origin or use larger length units",
                self.at(&m.path),
                m.item,
                m.by,
                limit,
                Num(smallest)
            ));
        }
        if moved.len() > NAMED {
            out.push(format!(
                "{} more shapes are moved likewise",
                moved.len() - NAMED
            ));
        }
        out
    }

    /// Where the item at `path` is, as errors begin.
    fn at(&self, path: &[Seg]) -> String {
        location(self.origin.file.as_deref(), self.origin.line(path))
    }
}

/// The box the scene spans at the start: its spheres (their surfaces) and its boundary's box.
fn scene_box(world: &World) -> (DVec3, DVec3) {
    let start = match world.boundary {
        Boundary::Open => (DVec3::INFINITY, DVec3::NEG_INFINITY),
        Boundary::OpenBox { lo, hi } => (lo, hi),
        Boundary::Periodic { size } => (DVec3::ZERO, size),
    };
    world.spheres.iter().fold(start, |(lo, hi), s| {
        let r = DVec3::splat(s.radius);
        (lo.min(s.centre - r), hi.max(s.centre + r))
    })
}

/// How far the scene reaches from `p`: the farthest corner of its box (at least as far as any
/// sphere's surface in it), once the box has been found.
fn reach_from((lo, hi): (DVec3, DVec3), p: DVec3) -> f64 {
    if lo.cmpgt(hi).any() {
        return 0.0;
    }
    (p - lo).abs().max((hi - p).abs()).length()
}

/// Each shape of the file against the one stored, a bound on the distance between their
/// surfaces where the scene is: a plane's offset at its point and its normal's tilt times how
/// far the scene's box reaches from it; a cylinder's axis moved across itself, its tilt times
/// how far the box reaches from its point, and its radius; a container's centre and radius.
fn moved_shapes(file: &SceneFile, world: &World) -> Vec<Moved> {
    let scene = scene_box(world);
    let mut out = Vec::new();
    for (body, shape, _) in world.statics.iter() {
        let i = body.index as usize;
        let (table, by) = match (body.kind, shape) {
            (ShapeKind::Plane, Static::Plane(s)) => {
                let Some(t) = file.plane.get(i) else { continue };
                let (p, n) = (DVec3::from_array(t.point), DVec3::from_array(t.normal));
                let n = n.normalize_or_zero();
                let (q, m) = (
                    s.point().as_dvec3(),
                    s.normal().as_dvec3().normalize_or_zero(),
                );
                let tilt = (n - m).length() * reach_from(scene, p);
                ("plane", m.dot(q - p).abs() + tilt)
            }
            (ShapeKind::Cylinder, Static::Cylinder(s)) => {
                let Some(t) = file.cylinder.get(i) else {
                    continue;
                };
                let p = DVec3::from_array(t.p1);
                let a = (DVec3::from_array(t.p2) - p).normalize_or_zero();
                let (q, b) = (
                    s.point().as_dvec3(),
                    s.axis().as_dvec3().normalize_or_zero(),
                );
                let d = q - p;
                let across = (d - a * d.dot(a)).length();
                let along = reach_from(scene, p);
                let radius = (f64::from(s.radius()) - t.radius).abs();
                ("cylinder", across + (a - b).length() * along + radius)
            }
            (ShapeKind::Container, Static::Container(s)) => {
                let Some(t) = file.container.get(i) else {
                    continue;
                };
                let centre = (s.centre().as_dvec3() - DVec3::from_array(t.centre)).length();
                (
                    "container",
                    centre + (f64::from(s.radius()) - t.radius).abs(),
                )
            }
            _ => continue,
        };
        out.push(Moved {
            path: [Key(table), At(i)],
            item: format!("{table} {i}"),
            by,
        });
    }
    out
}
