//! What a scene file asks that the engine can only approximate, said as warnings (the run goes
//! on): a sphere so far from the origin that its contacts may overlap past the tolerance
//! ([`World::coarse_sphere`]), and a static shape whose `f32` rounding moves it by more than
//! `2⁻¹⁰` of the smallest sphere's radius (docs/derivations/simulation.md, "Contacts far from
//! the origin").

use glam::DVec3;

use super::SceneFile;
use super::locate::Seg::{self, At, Key};
use crate::sim::World;

/// How far, over the smallest sphere's radius, rounding may move a shape unsaid: a gap or a
/// step sized to a sphere is designed to about this (a thousandth), while every coordinate of
/// a shape within `2¹⁴` radii of the origin rounds by less (`f32` keeps 24 bits).
const SHAPE_MOVE: f64 = 1.0 / 1024.0;

/// `x` as a person writes it: `0.5`, `1e-30` (Rust's `{}` would write 31 digits).
fn short(x: f64) -> String {
    if (1e-4..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A value as the library's shapes store it, back in `f64`.
fn stored(x: f64) -> f64 {
    f64::from(x as f32)
}

/// A point as the library's shapes store it.
fn stored3(p: [f64; 3]) -> DVec3 {
    DVec3::from_array(p.map(stored))
}

/// One shape field moved by rounding: where, what, and by how much across the surface.
struct Moved {
    path: [Seg; 3],
    item: String,
    field: &'static str,
    by: f64,
}

impl SceneFile {
    /// Warnings for the world [`build`](Self::build) made from this file, each at its entry's
    /// line: its coarsest sphere ([`World::coarse_sphere`]), and each shape whose position or
    /// radius, rounded to `f32` as the library's shapes are, moves across its surface by more
    /// than `2⁻¹⁰` of the smallest sphere's radius.
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// let text = "[run]\nt_end = 1\n[[sphere]]\ncentre = [0, 0, 1]\nradius = 0.5\n\
    ///     [[plane]]\npoint = [0, 0, 100000000.3]\nnormal = [0, 0, -1]\n";
    /// let scene = SceneFile::from_toml_str(text)?;
    /// let (world, _) = scene.build()?;
    /// let warnings = scene.warnings(&world);
    /// assert!(warnings[0].starts_with("line 7: plane 0: its point is stored as f32"), "{warnings:?}");
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
        for m in self.moved_shapes() {
            if m.by > limit {
                out.push(format!(
                    "{}{}: its {} is stored as f32 (as the library's shapes are), which moves \
                     its surface by {:.3e}, more than {:.3e} (2⁻¹⁰ of the smallest radius, \
                     {}): contacts with it happen that far from where the file puts \
                     it (units or an origin nearer the scene resolve it)",
                    self.at(&m.path),
                    m.item,
                    m.field,
                    m.by,
                    limit,
                    short(smallest)
                ));
            }
        }
        out
    }

    /// `FILE:LINE: ` for the item at `path`, as the errors begin.
    fn at(&self, path: &[Seg]) -> String {
        match (&self.origin.file, self.origin.line(path)) {
            (Some(p), Some(l)) => format!("{}:{l}: ", p.display()),
            (Some(p), None) => format!("{}: ", p.display()),
            (None, Some(l)) => format!("line {l}: "),
            (None, None) => String::new(),
        }
    }

    /// Each shape field and how far its `f32` rounding moves the surface: a plane's point
    /// along its normal; a cylinder's ends across its axis, and its radius; a container's
    /// centre and its radius.
    fn moved_shapes(&self) -> Vec<Moved> {
        let mut out = Vec::new();
        let mut push = |table, i, item: String, field, by: f64| {
            out.push(Moved {
                path: [Key(table), At(i), Key(field)],
                item,
                field,
                by,
            });
        };
        for (i, p) in self.plane.iter().enumerate() {
            let n = DVec3::from_array(p.normal).normalize_or_zero();
            let by = (stored3(p.point) - DVec3::from_array(p.point)).dot(n).abs();
            push("plane", i, format!("plane {i}"), "point", by);
        }
        for (i, c) in self.cylinder.iter().enumerate() {
            let axis = (DVec3::from_array(c.p2) - DVec3::from_array(c.p1)).normalize_or_zero();
            for (field, p) in [("p1", c.p1), ("p2", c.p2)] {
                let d = stored3(p) - DVec3::from_array(p);
                let by = (d - axis * d.dot(axis)).length();
                push("cylinder", i, format!("cylinder {i}"), field, by);
            }
            let by = (stored(c.radius) - c.radius).abs();
            push("cylinder", i, format!("cylinder {i}"), "radius", by);
        }
        for (i, c) in self.container.iter().enumerate() {
            let by = (stored3(c.centre) - DVec3::from_array(c.centre)).length();
            push("container", i, format!("container {i}"), "centre", by);
            let by = (stored(c.radius) - c.radius).abs();
            push("container", i, format!("container {i}"), "radius", by);
        }
        out
    }
}
