//! Pictures: the demo table's top view (plotters, SVG), and pictures of simulation scenes and
//! snapshots — side and top views of the spheres, the static shapes and sampled trajectories —
//! drawn once into a [`Canvas`] and written as SVG or PNG (no system fonts: see `canvas`).

mod canvas;
mod font;
mod frame;

use std::error::Error;

use glam::DVec3;
use plotters::prelude::*;
use spheresweep::FirstContact;
use spheresweep::scene::Scene;
use spheresweep::sim::SphereState;
use spheresweep::{Container, Cylinder, Plane};

pub use canvas::{Anchor, Canvas, Paint, Rect, Rgb, text_width};
pub use frame::{bounds, outside};

/// A closed polyline approximating the circle of radius `r` around `(x, y)` (data units).
fn circle(x: f64, y: f64, r: f64) -> Vec<(f64, f64)> {
    (0..=72)
        .map(|k| {
            let a = f64::from(k) * std::f64::consts::TAU / 72.0;
            (x + r * a.cos(), y + r * a.sin())
        })
        .collect()
}

/// Draws the scene seen from above: vessel and vertical pillars as circles, vertical planes
/// as lines, each sphere at `t = 0` (thin) and where it first touches something (thick), joined
/// by its path; spheres without contact are drawn to where they are at `t_max`.
pub fn top_view(
    scene: &Scene,
    contacts: &[Option<FirstContact>],
    t_max: f32,
) -> Result<String, Box<dyn Error>> {
    let extent = (scene.statics.of::<Container>().shapes().iter())
        .map(|k| k.centre().truncate().length() + k.radius())
        .chain(
            scene
                .spheres
                .iter()
                .map(|s| s.centre().truncate().length() + s.radius()),
        )
        .fold(1.0f32, f32::max) as f64
        * 1.1;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (640, 660)).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption("Top view: paths to the first contact", ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(30)
            .y_label_area_size(40)
            .build_cartesian_2d(-extent..extent, -extent..extent)?;
        chart
            .configure_mesh()
            .x_desc("x")
            .y_desc("y")
            .light_line_style(WHITE)
            .draw()?;
        let grey = RGBColor(120, 120, 120);
        for k in scene.statics.of::<Container>().shapes() {
            let c = k.centre();
            let ring = circle(c.x.into(), c.y.into(), k.radius().into());
            chart.draw_series(std::iter::once(PathElement::new(
                ring,
                grey.stroke_width(2),
            )))?;
        }
        for cyl in scene.statics.of::<Cylinder>().shapes() {
            let (p, s) = (cyl.point(), cyl.axis());
            if s.z.abs() > 0.99 {
                let disk = circle(p.x.into(), p.y.into(), cyl.radius().into());
                chart.draw_series(std::iter::once(Polygon::new(disk, grey.mix(0.5).filled())))?;
            }
        }
        for plane in scene.statics.of::<Plane>().shapes() {
            let (p, n) = (plane.point(), plane.normal());
            if n.z.abs() < 0.01 {
                // A vertical plane is a line seen from above.
                let (d, e) = (glam::Vec2::new(-n.y, n.x), extent as f32 * 2.0);
                let (a, b) = (p.truncate() - d * e, p.truncate() + d * e);
                let line = vec![(a.x.into(), a.y.into()), (b.x.into(), b.y.into())];
                chart.draw_series(std::iter::once(PathElement::new(
                    line,
                    grey.stroke_width(3),
                )))?;
            }
        }
        for (i, (s, contact)) in scene.spheres.iter().zip(contacts).enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            let t = contact.map_or(t_max, |c| c.time);
            let (start, end) = (s.centre(), s.centre_at(t));
            let r = f64::from(s.radius());
            let path = vec![
                (start.x.into(), start.y.into()),
                (end.x.into(), end.y.into()),
            ];
            chart.draw_series(std::iter::once(PathElement::new(
                path,
                colour.stroke_width(1),
            )))?;
            let first = circle(start.x.into(), start.y.into(), r);
            chart.draw_series(std::iter::once(PathElement::new(
                first,
                colour.stroke_width(1),
            )))?;
            let width = if contact.is_some() { 3 } else { 1 };
            let last = circle(end.x.into(), end.y.into(), r);
            chart.draw_series(std::iter::once(PathElement::new(
                last,
                colour.stroke_width(width),
            )))?;
            if let Some(point) = contact.and_then(|c| c.geometry).map(|g| g.point) {
                let cross = Cross::new((point.x, point.y), 5, BLACK.stroke_width(2));
                chart.draw_series(std::iter::once(cross))?;
            }
            let label = (f64::from(start.x) + r, f64::from(start.y) + r);
            let text = Text::new(
                i.to_string(),
                label,
                ("sans-serif", 14).into_font().color(&colour),
            );
            chart.draw_series(std::iter::once(text))?;
        }
        root.titled(
            "thin: t = 0 · thick: at first contact · ×: contact point · horizontal planes not shown",
            ("sans-serif", 12),
        )?;
        root.present()?;
    }
    Ok(svg)
}

/// Which way a panel looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum View {
    /// Along `+y`: `x` to the right, `z` up.
    Side,
    /// From above, along `−z`: `x` to the right, `y` up.
    Top,
}

impl View {
    /// The screen axes (right, up) and the depth axis (towards the viewer) as unit vectors.
    fn axes(self) -> (DVec3, DVec3, DVec3) {
        match self {
            View::Side => (DVec3::X, DVec3::Z, -DVec3::Y),
            View::Top => (DVec3::X, DVec3::Y, DVec3::Z),
        }
    }

    /// Screen coordinates `(u, v)` of a point, in scene units.
    pub fn project(self, p: DVec3) -> (f64, f64) {
        let (u, v, _) = self.axes();
        (p.dot(u), p.dot(v))
    }

    /// The coordinate along the axis the view looks along (`y` for the side view, `z` for the
    /// top view), which a slab limits.
    pub fn depth_coordinate(self, p: DVec3) -> f64 {
        match self {
            View::Side => p.y,
            View::Top => p.z,
        }
    }

    /// Larger is nearer the viewer.
    fn nearness(self, p: DVec3) -> f64 {
        p.dot(self.axes().2)
    }

    /// The screen axes' names.
    pub fn axis_names(self) -> (&'static str, &'static str) {
        match self {
            View::Side => ("x", "z"),
            View::Top => ("x", "y"),
        }
    }
}

/// The static shapes of a scene (the library's shapes) and its periodic box, if any.
#[derive(Debug, Clone, Default)]
pub struct Shapes {
    pub planes: Vec<Plane>,
    pub cylinders: Vec<Cylinder>,
    pub containers: Vec<Container>,
    pub periodic_box: Option<DVec3>,
    /// The region of an open box boundary (`[boundary] kind = "box"`): open space, framed.
    pub region: Option<(DVec3, DVec3)>,
    /// Shade the side of each plane its normal points away from, as ground.
    pub ground: bool,
}

impl Shapes {
    /// The shapes of a simulation world.
    pub fn of_world(world: &spheresweep::sim::World) -> Self {
        Self {
            planes: world.statics.of::<Plane>().shapes().to_vec(),
            cylinders: world.statics.of::<Cylinder>().shapes().to_vec(),
            containers: world.statics.of::<Container>().shapes().to_vec(),
            periodic_box: match world.boundary {
                spheresweep::sim::Boundary::Periodic { size } => Some(size),
                _ => None,
            },
            region: match world.boundary {
                spheresweep::sim::Boundary::OpenBox { lo, hi } => Some((lo, hi)),
                _ => None,
            },
            ground: false,
        }
    }
}

/// A sampled trajectory: its colour and the positions at the sample times.
#[derive(Debug, Clone)]
pub struct Path {
    pub colour: Rgb,
    pub points: Vec<DVec3>,
}

/// Everything a panel draws, in scene coordinates.
pub struct Content<'a> {
    pub spheres: &'a [SphereState],
    /// Each sphere's fill.
    pub fill: &'a dyn Fn(usize, &SphereState) -> Paint,
    pub shapes: &'a Shapes,
    pub paths: &'a [Path],
    /// The region every panel shows (fitted, same scale on both axes).
    pub bounds: (DVec3, DVec3),
}

/// One panel: where on the canvas, which view, its title, and optionally a slab of the depth
/// coordinate outside which spheres are not drawn.
pub struct Panel {
    pub rect: Rect,
    pub view: View,
    pub title: String,
    pub slab: Option<(f64, f64)>,
}

/// Colours of materials, in order (repeating): blue, orange, red, teal, green, yellow, purple,
/// pink, brown, grey.
pub const MATERIAL_COLOURS: [Rgb; 10] = [
    Rgb::hex(0x4e79a7),
    Rgb::hex(0xf28e2b),
    Rgb::hex(0xe15759),
    Rgb::hex(0x76b7b2),
    Rgb::hex(0x59a14f),
    Rgb::hex(0xedc948),
    Rgb::hex(0xb07aa1),
    Rgb::hex(0xff9da7),
    Rgb::hex(0x9c755f),
    Rgb::hex(0xbab0ac),
];

const INK: Rgb = Rgb::hex(0x222222);
const FRAME: Rgb = Rgb::hex(0x9a9a9a);
const PANEL: Rgb = Rgb::hex(0xfbfbfb);
const VESSEL: Rgb = Rgb::hex(0x5a6470);
const PILLAR: Rgb = Rgb::hex(0x8a939e);
const FLOOR: Rgb = Rgb::hex(0x8c6d46);
const PERIODIC: Rgb = Rgb::hex(0xd62728);
const REGION: Rgb = Rgb::hex(0xb0b0b0);

/// A cylinder seen from the side: a band along its projected axis, in pixels, and how near
/// the viewer its axis passes.
struct Band {
    nearness: f64,
    corners: [(f64, f64); 4],
}

impl Band {
    fn draw(self, canvas: &mut Canvas) {
        let [a, b, c, d] = self.corners;
        canvas.polygon(self.corners.to_vec(), PILLAR);
        canvas.line(vec![a, b], PILLAR.shade(0.7), 1.5);
        canvas.line(vec![d, c], PILLAR.shade(0.7), 1.5);
    }
}

/// Pixels from scene units for one panel.
struct Map {
    scale: f64,
    origin: (f64, f64),
    u0: f64,
    v0: f64,
}

impl Map {
    fn new(rect: Rect, u: (f64, f64), v: (f64, f64)) -> Self {
        let (du, dv) = ((u.1 - u.0).max(1e-12), (v.1 - v.0).max(1e-12));
        let scale = (rect.w / du).min(rect.h / dv);
        let origin = (
            rect.x + (rect.w - scale * du) / 2.0,
            rect.y + rect.h - (rect.h - scale * dv) / 2.0,
        );
        Self {
            scale,
            origin,
            u0: u.0,
            v0: v.0,
        }
    }

    fn px(&self, (u, v): (f64, f64)) -> (f64, f64) {
        (
            self.origin.0 + (u - self.u0) * self.scale,
            self.origin.1 - (v - self.v0) * self.scale,
        )
    }
}

/// Base text size for a picture `width` pixels wide.
pub fn text_size(width: u32) -> f64 {
    if width >= 1000 { 20.0 } else { 10.0 }
}

/// Draws one panel: background and frame, title, shapes, spheres far to near, trajectories,
/// and a scale bar.
pub fn draw_panel(canvas: &mut Canvas, panel: &Panel, content: &Content) {
    let rect = panel.rect;
    let fs = text_size(canvas.width);
    canvas.clip_to(None);
    canvas.text(
        (rect.x, rect.y - fs * 0.45),
        &panel.title,
        fs,
        INK,
        Anchor::Start,
    );
    canvas.rect(rect, FRAME);
    let inner = Rect {
        x: rect.x + 1.0,
        y: rect.y + 1.0,
        w: rect.w - 2.0,
        h: rect.h - 2.0,
    };
    canvas.rect(inner, PANEL);
    canvas.clip_to(Some(inner));
    let view = panel.view;
    let (lo, hi) = content.bounds;
    let corners = [lo, hi];
    let (mut u, mut v) = (
        (f64::INFINITY, f64::NEG_INFINITY),
        (f64::INFINITY, f64::NEG_INFINITY),
    );
    for k in 0..8 {
        let p = DVec3::new(corners[k & 1].x, corners[(k >> 1) & 1].y, corners[k >> 2].z);
        let (a, b) = view.project(p);
        u = (u.0.min(a), u.1.max(a));
        v = (v.0.min(b), v.1.max(b));
    }
    let map = Map::new(inner, u, v);
    let (eu, ev, _) = view.axes();
    // The depth of the section through which planes are cut: the slab's middle, or the
    // bounds' middle.
    let mid = panel.slab.map_or_else(
        || view.depth_coordinate((lo + hi) / 2.0),
        |(a, b)| (a + b) / 2.0,
    );
    let section = match view {
        View::Side => DVec3::Y * mid,
        View::Top => DVec3::Z * mid,
    };
    // Far enough to leave the panel from any point inside the bounds.
    let reach = (hi - lo).length() * 4.0 + 1.0;
    let shapes = content.shapes;

    // Containers: a light fill inside, then the outline (after the spheres).
    for k in &shapes.containers {
        let c = map.px(view.project(k.centre().as_dvec3()));
        let r = f64::from(k.radius()) * map.scale;
        canvas.disk(c, r, Some(Rgb::hex(0xeef2f6).into()), None);
    }
    // Cylinders: a disk when seen along the axis, otherwise a band of half-width r, drawn in
    // depth order with the spheres (a sphere behind a pillar is hidden by it) unless a
    // container's cover must go over them.
    let mut bands = Vec::new();
    let middle = (lo + hi) / 2.0;
    for c in &shapes.cylinders {
        let (axis, q, r) = (
            c.axis().as_dvec3(),
            c.point().as_dvec3(),
            f64::from(c.radius()),
        );
        let (au, av) = (axis.dot(eu), axis.dot(ev));
        let len = au.hypot(av);
        let centre = view.project(q);
        if len < 1e-3 {
            canvas.disk(
                map.px(centre),
                r * map.scale,
                Some(PILLAR.into()),
                Some((PILLAR.shade(0.7).into(), 1.5)),
            );
            continue;
        }
        let (du, dv) = (au / len, av / len);
        let (nu, nv) = (-dv * r, du * r);
        let p = |s: f64, side: f64| {
            map.px((centre.0 + du * s + nu * side, centre.1 + dv * s + nv * side))
        };
        bands.push(Band {
            nearness: view.nearness(q + axis * (middle - q).dot(axis)),
            corners: [
                p(-reach, -1.0),
                p(reach, -1.0),
                p(reach, 1.0),
                p(-reach, 1.0),
            ],
        });
    }
    let in_depth_order = shapes.containers.is_empty();
    if !in_depth_order {
        bands.drain(..).for_each(|b| b.draw(canvas));
    }
    bands.sort_by(|a, b| a.nearness.total_cmp(&b.nearness));
    // Planes: the line where each crosses the section plane.
    for p in &shapes.planes {
        let (n, q) = (p.normal().as_dvec3(), p.point().as_dvec3());
        let (nu, nv) = (n.dot(eu), n.dot(ev));
        let len2 = nu * nu + nv * nv;
        if len2 < 1e-12 {
            continue;
        }
        let rhs = n.dot(q) - n.dot(section);
        let foot = (nu * rhs / len2, nv * rhs / len2);
        let along = (-nv / len2.sqrt(), nu / len2.sqrt());
        let centre = view.project((lo + hi) / 2.0);
        let far = reach + ((foot.0 - centre.0).powi(2) + (foot.1 - centre.1).powi(2)).sqrt();
        let a = (foot.0 - along.0 * far, foot.1 - along.1 * far);
        let b = (foot.0 + along.0 * far, foot.1 + along.1 * far);
        if shapes.ground {
            let back = (-nu / len2.sqrt() * far, -nv / len2.sqrt() * far);
            let ground = vec![
                map.px(a),
                map.px(b),
                map.px((b.0 + back.0, b.1 + back.1)),
                map.px((a.0 + back.0, a.1 + back.1)),
            ];
            canvas.polygon(ground, Rgb::hex(0xe8dcc8));
        }
        canvas.line(vec![map.px(a), map.px(b)], FLOOR, 3.0);
    }
    // Nothing lives outside a container: cover what the shapes drew there.
    let outside = inner.w.hypot(inner.h) * 2.0;
    for k in &shapes.containers {
        let c = map.px(view.project(k.centre().as_dvec3()));
        let r = f64::from(k.radius()) * map.scale;
        canvas.disk(c, r + outside / 2.0, None, Some((PANEL.into(), outside)));
    }
    // Spheres, far to near.
    let mut order: Vec<usize> = (0..content.spheres.len())
        .filter(|&i| {
            let s = &content.spheres[i];
            panel.slab.is_none_or(|(a, b)| {
                let d = view.depth_coordinate(s.centre);
                d >= a && d <= b
            })
        })
        .collect();
    order.sort_by(|&a, &b| {
        view.nearness(content.spheres[a].centre)
            .total_cmp(&view.nearness(content.spheres[b].centre))
    });
    let mut bands = bands.into_iter().peekable();
    for i in order {
        let s = &content.spheres[i];
        while let Some(band) = bands.next_if(|b| b.nearness <= view.nearness(s.centre)) {
            band.draw(canvas);
        }
        let fill = (content.fill)(i, s);
        let r = s.radius * map.scale;
        let stroke = (r >= 2.5).then(|| (fill.rgb.shade(0.6).alpha(fill.alpha), 0.8));
        canvas.disk(map.px(view.project(s.centre)), r, Some(fill), stroke);
    }
    bands.for_each(|b| b.draw(canvas));
    for k in &shapes.containers {
        let c = map.px(view.project(k.centre().as_dvec3()));
        let r = f64::from(k.radius()) * map.scale;
        canvas.disk(c, r, None, Some((VESSEL.into(), 2.5)));
    }
    // The periodic box over the spheres (they fill it to its faces), and the open box of the
    // cell grid, which spheres may leave.
    let outline = |canvas: &mut Canvas, (lo, hi): (DVec3, DVec3), colour: Rgb, width: f64| {
        let (a, c) = (map.px(view.project(lo)), map.px(view.project(hi)));
        canvas.line(vec![a, (c.0, a.1), c, (a.0, c.1), a], colour, width);
    };
    if let Some(b) = shapes.periodic_box {
        outline(canvas, (DVec3::ZERO, b), PERIODIC, 2.0);
    }
    if let Some(region) = shapes.region {
        outline(canvas, region, REGION, 1.5);
    }
    // Trajectories: start ○, end ●.
    for path in content.paths {
        let points: Vec<(f64, f64)> = path
            .points
            .iter()
            .map(|p| map.px(view.project(*p)))
            .collect();
        if let (Some(&first), Some(&last)) = (points.first(), points.last()) {
            canvas.line(points, path.colour, 1.6);
            canvas.disk(
                first,
                3.5,
                Some(Rgb(255, 255, 255).into()),
                Some((path.colour.into(), 1.5)),
            );
            canvas.disk(last, 3.5, Some(path.colour.into()), None);
        }
    }
    // A scale bar: a round length about a fifth of the panel.
    let target = inner.w / 5.0 / map.scale;
    if target.is_finite() && target > 0.0 {
        let step = 10f64.powf(target.log10().floor());
        let length = [5.0, 2.0, 1.0]
            .into_iter()
            .map(|k| k * step)
            .find(|&l| l <= target)
            .unwrap_or(step);
        let (x0, y0) = (inner.x + fs * 0.8, inner.y + inner.h - fs * 0.8);
        let x1 = x0 + length * map.scale;
        canvas.line(vec![(x0, y0), (x1, y0)], INK, 2.0);
        canvas.line(vec![(x0, y0 - fs * 0.3), (x0, y0 + fs * 0.3)], INK, 2.0);
        canvas.line(vec![(x1, y0 - fs * 0.3), (x1, y0 + fs * 0.3)], INK, 2.0);
        canvas.text(
            ((x0 + x1) / 2.0, y0 - fs * 0.5),
            format_length(length),
            fs * 0.8,
            INK,
            Anchor::Middle,
        );
    }
    // Axis names.
    let (a, b) = view.axis_names();
    canvas.text(
        (inner.x + inner.w - fs * 0.5, inner.y + inner.h - fs * 0.5),
        format!("{a} →"),
        fs * 0.8,
        INK,
        Anchor::End,
    );
    canvas.text(
        (inner.x + fs * 0.5, inner.y + fs * 1.2),
        format!("{b} ↑"),
        fs * 0.8,
        INK,
        Anchor::Start,
    );
    canvas.clip_to(None);
}

fn format_length(l: f64) -> String {
    if (1e-3..1e6).contains(&l) {
        let s = format!("{l:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{l:e}")
    }
}

/// One entry of a legend.
pub enum Key {
    /// A filled disk.
    Disk(Paint),
    /// A line with a dot at its end.
    Path(Rgb),
    /// A filled square.
    Swatch(Rgb),
}

/// A legend in one row from `(x, y)` (the text baseline), as far as `max_x`; returns the x
/// reached.
pub fn legend(
    canvas: &mut Canvas,
    (x, y): (f64, f64),
    max_x: f64,
    entries: &[(Key, String)],
) -> f64 {
    let fs = text_size(canvas.width) * 0.8;
    let mut x = x;
    for (key, label) in entries {
        let need = fs * 1.6 + text_width(label, fs) + fs * 1.4;
        if x + need > max_x {
            break;
        }
        let (cx, cy) = (x + fs * 0.5, y - fs * 0.35);
        match key {
            Key::Disk(p) => canvas.disk(
                (cx, cy),
                fs * 0.45,
                Some(*p),
                Some((p.rgb.shade(0.6).into(), 0.8)),
            ),
            Key::Path(c) => {
                canvas.line(
                    vec![(x - fs * 0.2, cy + fs * 0.3), (x + fs * 1.0, cy - fs * 0.3)],
                    *c,
                    1.6,
                );
                canvas.disk(
                    (x + fs * 1.0, cy - fs * 0.3),
                    fs * 0.2,
                    Some((*c).into()),
                    None,
                );
            }
            Key::Swatch(c) => canvas.rect(
                Rect {
                    x,
                    y: cy - fs * 0.45,
                    w: fs * 0.9,
                    h: fs * 0.9,
                },
                *c,
            ),
        }
        canvas.text((x + fs * 1.6, y), label, fs, INK, Anchor::Start);
        x += need;
    }
    x
}

/// Colours of the vessel, pillars and floor, for legends.
pub const SHAPE_COLOURS: (Rgb, Rgb, Rgb) = (VESSEL, PILLAR, FLOOR);
/// Colours of the periodic box's and the open box's outlines, for legends.
pub const BOX_COLOURS: (Rgb, Rgb) = (PERIODIC, REGION);

/// A picture size in pixels, parsed from `WIDTHxHEIGHT`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

impl Size {
    /// Smallest and largest side accepted, and the most pixels.
    pub const MIN: (u32, u32) = (160, 120);
    pub const MAX_SIDE: u32 = 8192;
    pub const MAX_PIXELS: u64 = 40_000_000;
}

impl std::str::FromStr for Size {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let bad = |why: &str| format!("{s:?} is not a picture size: {why}");
        let (w, h) = s
            .split_once(['x', 'X', '×'])
            .ok_or_else(|| bad("give WIDTHxHEIGHT in pixels, e.g. 1600x800"))?;
        let side = |v: &str, name: &str, min: u32| -> Result<u32, String> {
            let n: u32 = v
                .trim()
                .parse()
                .map_err(|_| bad(&format!("the {name} {v:?} is not a whole number")))?;
            if n < min || n > Self::MAX_SIDE {
                return Err(bad(&format!(
                    "the {name} must be between {min} and {} pixels",
                    Self::MAX_SIDE
                )));
            }
            Ok(n)
        };
        let size = Self {
            width: side(w, "width", Self::MIN.0)?,
            height: side(h, "height", Self::MIN.1)?,
        };
        if u64::from(size.width) * u64::from(size.height) > Self::MAX_PIXELS {
            return Err(bad(&format!("more than {} pixels", Self::MAX_PIXELS)));
        }
        Ok(size)
    }
}

impl std::fmt::Display for Size {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

/// Which files a picture is written as.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    Svg,
    Png,
    Both,
}

impl Format {
    /// The file extensions, in writing order.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            Format::Svg => &["svg"],
            Format::Png => &["png"],
            Format::Both => &["svg", "png"],
        }
    }

    /// The picture encoded for a file of extension `ext`.
    pub fn encode(canvas: &Canvas, ext: &str) -> Result<Vec<u8>, String> {
        if ext == "png" {
            canvas.png()
        } else {
            Ok(canvas.svg().into_bytes())
        }
    }
}

/// Rectangles for `count` square-ish panels side by side in the band `top..bottom` of a
/// picture `width` wide, leaving `margin` around them and room above each for its title.
pub fn panel_rects(width: u32, top: f64, bottom: f64, count: usize, margin: f64) -> Vec<Rect> {
    let fs = text_size(width);
    let count = count.max(1) as f64;
    let top = top + fs * 1.3;
    let avail_w = ((f64::from(width) - margin * (count + 1.0)) / count).max(1.0);
    let avail_h = (bottom - top).max(1.0);
    let side_w = avail_w.min(avail_h * 1.6);
    let used = side_w * count + margin * (count - 1.0);
    let left = (f64::from(width) - used) / 2.0;
    (0..count as usize)
        .map(|k| Rect {
            x: (left + k as f64 * (side_w + margin)).round(),
            y: top.round(),
            w: side_w.round(),
            h: avail_h.round(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_bad_ones_say_why() {
        assert_eq!(
            "1600x800".parse::<Size>(),
            Ok(Size {
                width: 1600,
                height: 800
            })
        );
        assert_eq!(
            "640×480".parse::<Size>().map(|s| s.to_string()),
            Ok("640x480".into())
        );
        for (bad, why) in [
            ("1600", "WIDTHxHEIGHT"),
            ("0x600", "between 160 and 8192"),
            ("axb", "not a whole number"),
            ("-5x100", "not a whole number"),
            ("8192x8192", "more than"),
        ] {
            let e = bad.parse::<Size>().unwrap_err();
            assert!(e.contains(why), "{bad}: {e}");
        }
    }

    /// In the side view a pillar hides the sphere behind it and not the one in front (the
    /// pillar used to be drawn under every sphere).
    #[test]
    fn a_pillar_is_drawn_in_depth_order_with_the_spheres() {
        let ball = |x: f64, y: f64, z: f64| SphereState {
            centre: DVec3::new(x, y, z),
            velocity: DVec3::ZERO,
            radius: 0.5,
            mass: 1.0,
            material: 0,
        };
        // The pillar along z at y = -4 (nearer than y = 0 seen along +y); a sphere behind it
        // at y = 0 and one in front at y = -6, both over its band in the picture.
        let spheres = [ball(0.0, 0.0, -2.0), ball(0.0, -6.0, 3.0)];
        let shapes = Shapes {
            cylinders: vec![Cylinder::new([0.0, -4.0, 0.0], [0.0, -4.0, 1.0], 1.0).unwrap()],
            ..Shapes::default()
        };
        let red = Rgb::hex(0xff0000);
        let fill = move |_: usize, _: &SphereState| Paint::from(red);
        let content = Content {
            spheres: &spheres,
            fill: &fill,
            shapes: &shapes,
            paths: &[],
            bounds: (DVec3::new(-5.0, -8.0, -5.0), DVec3::new(5.0, 8.0, 5.0)),
        };
        let panel = Panel {
            rect: Rect {
                x: 0.0,
                y: 0.0,
                w: 202.0,
                h: 202.0,
            },
            view: View::Side,
            title: String::new(),
            slab: None,
        };
        let mut canvas = Canvas::new(202, 202, PANEL);
        draw_panel(&mut canvas, &panel, &content);
        let raster = canvas.raster();
        // 20 pixels a unit, the scene's (x, z) = (0, 0) at pixel (101, 101).
        let at = |x: f64, z: f64| {
            let (i, j) = ((101.0 + x * 20.0) as usize, (101.0 - z * 20.0) as usize);
            let k = 3 * (j * 202 + i);
            [raster[k], raster[k + 1], raster[k + 2]]
        };
        let pillar = at(0.0, 0.0);
        assert_ne!(pillar, at(4.0, 0.0), "the pillar is drawn");
        assert_eq!(
            at(0.0, -2.0),
            pillar,
            "the sphere behind the pillar is hidden"
        );
        assert_ne!(at(0.0, 3.0), pillar, "the sphere in front is drawn over it");
    }

    #[test]
    fn views_project_and_order_by_depth() {
        let p = DVec3::new(1.0, 2.0, 3.0);
        assert_eq!(View::Side.project(p), (1.0, 3.0));
        assert_eq!(View::Top.project(p), (1.0, 2.0));
        // Seen along +y, a smaller y is nearer; seen from above, a larger z.
        assert!(View::Side.nearness(DVec3::ZERO) > View::Side.nearness(DVec3::Y));
        assert!(View::Top.nearness(DVec3::Z) > View::Top.nearness(DVec3::ZERO));
    }
}
