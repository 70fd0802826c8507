//! The demo table's picture: the nine-sphere query scene seen from above, with each sphere at
//! `t = 0`, where it first touches something, and its path between — drawn into the same
//! display list as every other picture, on a square plot with ticks.

use glam::Vec2;
use spheresweep::scene::Scene;
use spheresweep::{Container, Cylinder, FirstContact, Plane};

use super::canvas::{Anchor, Canvas, Rect, Rgb};
use super::panel::{format_length, round_length};
use super::{FRAME, INK, MATERIAL_COLOURS};

/// The picture's size in pixels.
const WIDTH: u32 = 640;
const HEIGHT: u32 = 660;
/// Colours of the static shapes and of the grid.
const SHAPE: Rgb = Rgb(120, 120, 120);
const GRID: Rgb = Rgb::hex(0xe6e6e6);

/// Draws the scene seen from above: vessel and vertical pillars as circles, vertical planes
/// as lines, each sphere at `t = 0` (thin) and where it first touches something (thick), joined
/// by its path; spheres without contact are drawn to where they are at `t_max`.
pub fn top_view(scene: &Scene, contacts: &[Option<FirstContact>], t_max: f32) -> Canvas {
    let mut canvas = Canvas::new(WIDTH, HEIGHT, Rgb(255, 255, 255));
    let (w, h) = (f64::from(WIDTH), f64::from(HEIGHT));
    canvas.text(
        (w / 2.0, 28.0),
        "Top view: paths to the first contact",
        18.0,
        INK,
        Anchor::Middle,
    );
    canvas.text(
        (w / 2.0, h - 10.0),
        "thin: t = 0 · thick: at first contact · ×: contact point · horizontal planes not shown",
        12.0,
        INK,
        Anchor::Middle,
    );
    let extent = extent(scene);
    let side = (w - 70.0).min(h - 110.0);
    let plot = Rect {
        x: 54.0 + ((w - 70.0) - side) / 2.0,
        y: 44.0,
        w: side,
        h: side,
    };
    let axes = Axes { plot, extent };
    axes.draw(&mut canvas);
    canvas.clip_to(Some(plot));
    statics(&mut canvas, &axes, scene);
    spheres(&mut canvas, &axes, scene, contacts, t_max);
    canvas.clip_to(None);
    canvas
}

/// How far from the vertical axis the vessel and the spheres reach, with a tenth to spare: the
/// plot shows `[-extent, extent]` on both axes.
fn extent(scene: &Scene) -> f64 {
    scene
        .statics
        .of::<Container>()
        .shapes()
        .iter()
        .map(|k| k.centre().truncate().length() + k.radius())
        .chain(
            scene
                .spheres
                .iter()
                .map(|s| s.centre().truncate().length() + s.radius()),
        )
        .fold(1.0f32, f32::max) as f64
        * 1.1
}

/// The square plot of `[-extent, extent]²` in pixels, `y` up.
struct Axes {
    plot: Rect,
    extent: f64,
}

impl Axes {
    fn scale(&self) -> f64 {
        self.plot.w / (2.0 * self.extent)
    }

    fn px(&self, p: Vec2) -> (f64, f64) {
        let s = self.scale();
        (
            self.plot.x + (f64::from(p.x) + self.extent) * s,
            self.plot.y + (self.extent - f64::from(p.y)) * s,
        )
    }

    /// The frame, grid lines at round values with their labels, and the axis names.
    fn draw(&self, canvas: &mut Canvas) {
        let p = self.plot;
        canvas.rect(p, FRAME);
        canvas.rect(p.inset(1.0), Rgb(255, 255, 255));
        let step = round_length(self.extent / 3.0);
        let first = (-self.extent / step).ceil() as i64;
        let last = (self.extent / step).floor() as i64;
        for k in first..=last {
            let v = k as f64 * step;
            let (x, y) = self.px(Vec2::splat(v as f32));
            canvas.line(vec![(x, p.y + 1.0), (x, p.y + p.h - 1.0)], GRID, 1.0);
            canvas.line(vec![(p.x + 1.0, y), (p.x + p.w - 1.0, y)], GRID, 1.0);
            canvas.line(vec![(x, p.y + p.h), (x, p.y + p.h + 5.0)], FRAME, 1.0);
            canvas.line(vec![(p.x - 5.0, y), (p.x, y)], FRAME, 1.0);
            let label = tick_label(v);
            canvas.text((x, p.y + p.h + 18.0), &label, 11.0, INK, Anchor::Middle);
            canvas.text((p.x - 8.0, y + 4.0), &label, 11.0, INK, Anchor::End);
        }
        let (mid_x, mid_y) = (p.x + p.w / 2.0, p.y + p.h / 2.0);
        canvas.text((mid_x, p.y + p.h + 36.0), "x", 13.0, INK, Anchor::Middle);
        canvas.text((p.x - 40.0, mid_y + 4.0), "y", 13.0, INK, Anchor::Middle);
    }
}

/// A tick's value: round, signed, no trailing zeros.
fn tick_label(v: f64) -> String {
    if v.abs() < 1e-9 {
        "0".into()
    } else if v < 0.0 {
        format!("−{}", format_length(-v))
    } else {
        format_length(v)
    }
}

/// Vessels as rings, vertical pillars as half-transparent disks, vertical planes as lines
/// (the others are not seen from above as a shape).
fn statics(canvas: &mut Canvas, axes: &Axes, scene: &Scene) {
    let s = axes.scale();
    for k in scene.statics.of::<Container>().shapes() {
        let c = axes.px(k.centre().truncate());
        canvas.disk(
            c,
            f64::from(k.radius()) * s,
            None,
            Some((SHAPE.into(), 2.0)),
        );
    }
    for cyl in scene.statics.of::<Cylinder>().shapes() {
        let (p, axis) = (cyl.point(), cyl.axis());
        if axis.z.abs() > 0.99 {
            let c = axes.px(p.truncate());
            canvas.disk(c, f64::from(cyl.radius()) * s, Some(SHAPE.alpha(0.5)), None);
        }
    }
    for plane in scene.statics.of::<Plane>().shapes() {
        let (p, n) = (plane.point(), plane.normal());
        if n.z.abs() < 0.01 {
            // A vertical plane is a line seen from above.
            let (d, e) = (Vec2::new(-n.y, n.x), axes.extent as f32 * 4.0);
            let (a, b) = (p.truncate() - d * e, p.truncate() + d * e);
            canvas.line(vec![axes.px(a), axes.px(b)], SHAPE, 3.0);
        }
    }
}

/// Each sphere: its path, its outline at `t = 0` (thin) and at its first contact (thick; thin
/// at `t_max` without one), the contact point (×) and its number.
fn spheres(
    canvas: &mut Canvas,
    axes: &Axes,
    scene: &Scene,
    contacts: &[Option<FirstContact>],
    t_max: f32,
) {
    let s = axes.scale();
    for (i, (sphere, contact)) in scene.spheres.iter().zip(contacts).enumerate() {
        let colour = MATERIAL_COLOURS[i % MATERIAL_COLOURS.len()].shade(0.85);
        let t = contact.map_or(t_max, |c| c.time);
        let (start, r) = (
            axes.px(sphere.centre().truncate()),
            f64::from(sphere.radius()) * s,
        );
        let end = sphere.centre_at(t).truncate();
        if end.is_finite() {
            let end = axes.px(end);
            canvas.line(vec![start, end], colour, 1.0);
            let width = if contact.is_some() { 3.0 } else { 1.0 };
            canvas.disk(end, r, None, Some((colour.into(), width)));
        }
        canvas.disk(start, r, None, Some((colour.into(), 1.0)));
        if let Some(point) = contact.and_then(|c| c.geometry).map(|g| g.point) {
            let (x, y) = axes.px(point.truncate().as_vec2());
            let black = Rgb(0, 0, 0);
            canvas.line(vec![(x - 5.0, y - 5.0), (x + 5.0, y + 5.0)], black, 2.0);
            canvas.line(vec![(x - 5.0, y + 5.0), (x + 5.0, y - 5.0)], black, 2.0);
        }
        // The number darker than the outlines, on a light backing: readable where it crosses
        // another sphere's outline.
        let (label, size) = (i.to_string(), 14.0);
        let at = (start.0 + r * 0.75, start.1 - r * 0.75 - 2.0);
        let backing = Rect {
            x: at.0 - 1.0,
            y: at.1 - size * 0.8,
            w: size * 0.6 * label.len() as f64 + 2.0,
            h: size * 0.9,
        };
        canvas.rect(backing, Rgb(255, 255, 255).alpha(0.8));
        canvas.text(at, label, size, colour.shade(0.6), Anchor::Start);
    }
}
