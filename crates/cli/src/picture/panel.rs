//! One panel of a scene picture, drawn in named stages: the frame and title, the inside of the
//! containers, the cylinders (disks, or bands kept for the depth order), the planes' sections
//! (and the bands tilted ones sweep over the depths shown), the cover outside the containers,
//! the spheres far to near with the bands between them, the containers' and boxes' outlines,
//! the trajectories, a scale bar and the axis names.

use glam::DVec3;
use spheresweep::{Container, Cylinder, Plane};

use super::canvas::{Anchor, Canvas, Rect, Rgb};
use super::{
    Content, FLOOR, FRAME, INK, PANEL, PERIODIC, PILLAR, Panel, REGION, Shapes, VESSEL, View,
    text_size,
};
use crate::number::counted;

/// The fill inside a container, and of the ground behind a plane.
const VESSEL_INSIDE: Rgb = Rgb::hex(0xeef2f6);
const GROUND: Rgb = Rgb::hex(0xe8dcc8);

/// Draws one panel: background and frame, title, shapes, spheres far to near, trajectories,
/// and a scale bar.
pub fn draw_panel(canvas: &mut Canvas, panel: &Panel, content: &Content) {
    let fs = text_size(canvas.width);
    let inner = frame(canvas, panel, fs);
    canvas.clip_to(Some(inner));
    let scope = Scope::new(inner, panel, content.bounds);
    let shapes = content.shapes;
    container_insides(canvas, &scope, shapes);
    let mut bands = cylinders(canvas, &scope, shapes);
    if !shapes.statics.of::<Container>().is_empty() {
        // The cover outside the containers must go over the bands: no depth order.
        bands.drain(..).for_each(|b| b.draw(canvas));
    }
    plane_sections(canvas, &scope, shapes);
    cover_outside_containers(canvas, &scope, shapes);
    let dots = spheres_far_to_near(canvas, &scope, content, panel.slab, bands);
    container_outlines(canvas, &scope, shapes);
    box_outlines(canvas, &scope, shapes);
    trajectories(canvas, &scope, content);
    scale_bar(canvas, &scope, fs);
    axis_names(canvas, &scope, fs);
    small_spheres_note(canvas, &scope, fs, dots);
    canvas.clip_to(None);
}

/// Pixels from scene units for one panel: the same scale on both axes, centred.
struct Map {
    scale: f64,
    origin: (f64, f64),
    u0: f64,
    v0: f64,
}

impl Map {
    fn new(rect: Rect, u: (f64, f64), v: (f64, f64)) -> Self {
        // The frame has extent at any scale (`frame::bounds`); the floor only spares a zero.
        let (du, dv) = (
            (u.1 - u.0).max(f64::MIN_POSITIVE),
            (v.1 - v.0).max(f64::MIN_POSITIVE),
        );
        // Finite however small the frame (a point at 10⁻³⁰⁰ is framed by 10⁻³⁰⁶).
        let scale = (rect.w / du).min(rect.h / dv).min(f64::MAX);
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

/// What every stage of a panel needs: the view, the inner rectangle and its map, and the
/// section through which planes are cut.
struct Scope {
    view: View,
    inner: Rect,
    map: Map,
    /// The bounds' middle.
    middle: DVec3,
    /// A point of the section plane: the slab's middle, or the bounds' middle.
    section: DVec3,
    /// The depths the panel shows: the slab, or the bounds'.
    depths: (f64, f64),
    /// Scene units enough to leave the panel from any point in it.
    reach: f64,
}

impl Scope {
    fn new(inner: Rect, panel: &Panel, (lo, hi): (DVec3, DVec3)) -> Self {
        let view = panel.view;
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
        let middle = (lo + hi) / 2.0;
        let mid = panel
            .slab
            .map_or_else(|| view.depth_coordinate(middle), |(a, b)| (a + b) / 2.0);
        let section = at_depth(view, mid);
        let (d0, d1) = (view.depth_coordinate(lo), view.depth_coordinate(hi));
        let depths = panel.slab.unwrap_or((d0.min(d1), d0.max(d1)));
        let reach = inner.w.hypot(inner.h) / map.scale.max(1e-300) + 1.0;
        Self {
            view,
            inner,
            map,
            middle,
            section,
            depths,
            reach,
        }
    }

    /// A point of the scene in pixels.
    fn px(&self, p: DVec3) -> (f64, f64) {
        self.map.px(self.view.project(p))
    }

    /// Scene units from the middle of the panel to `(u, v)`, added to the reach: a line from
    /// `(u, v)` this long leaves the panel.
    fn reach_from(&self, (u, v): (f64, f64)) -> f64 {
        let c = self.view.project(self.middle);
        self.reach + (u - c.0).hypot(v - c.1)
    }
}

/// The title above the panel, its frame and background; returns the rectangle inside the
/// frame.
fn frame(canvas: &mut Canvas, panel: &Panel, fs: f64) -> Rect {
    let rect = panel.rect;
    canvas.clip_to(None);
    canvas.text(
        (rect.x, rect.y - fs * 0.45),
        &panel.title,
        fs,
        INK,
        Anchor::Start,
    );
    canvas.rect(rect, FRAME);
    let inner = rect.inset(1.0);
    canvas.rect(inner, PANEL);
    inner
}

/// A light fill inside each container (its outline comes after the spheres).
fn container_insides(canvas: &mut Canvas, scope: &Scope, shapes: &Shapes) {
    for k in shapes.statics.of::<Container>().shapes() {
        let c = scope.px(k.centre().as_dvec3());
        let r = f64::from(k.radius()) * scope.map.scale;
        canvas.disk(c, r, Some(VESSEL_INSIDE.into()), None);
    }
}

/// A cylinder seen from the side: a band along its projected axis, in pixels, and how near
/// the viewer its axis passes.
struct Band {
    nearness: f64,
    corners: [(f64, f64); 4],
}

/// How opaque a pillar seen from the side is: the spheres behind it show through, dimmed
/// (a granular jet falling between four pillars was hidden whole behind the nearer ones).
const BAND_OPACITY: f32 = 0.6;

impl Band {
    fn draw(self, canvas: &mut Canvas) {
        let [a, b, c, d] = self.corners;
        canvas.polygon(self.corners.to_vec(), PILLAR.alpha(BAND_OPACITY));
        canvas.line(vec![a, b], PILLAR.shade(0.7), 1.5);
        canvas.line(vec![d, c], PILLAR.shade(0.7), 1.5);
    }
}

/// Cylinders seen along their axis as disks, drawn now; the others as bands of half-width r,
/// returned nearest last, to be drawn in depth order with the spheres (a sphere behind a
/// pillar is dimmed by it, `BAND_OPACITY`; one in front is drawn over it).
fn cylinders(canvas: &mut Canvas, scope: &Scope, shapes: &Shapes) -> Vec<Band> {
    let (view, map) = (scope.view, &scope.map);
    let (eu, ev, _) = view.axes();
    let mut bands = Vec::new();
    for c in shapes.statics.of::<Cylinder>().shapes() {
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
        let reach = scope.reach_from(centre);
        bands.push(Band {
            nearness: view.nearness(q + axis * (scope.middle - q).dot(axis)),
            corners: [
                p(-reach, -1.0),
                p(reach, -1.0),
                p(reach, 1.0),
                p(-reach, 1.0),
            ],
        });
    }
    bands.sort_by(|a, b| a.nearness.total_cmp(&b.nearness));
    bands
}

/// A point at depth `d` on the view's axis of depth.
fn at_depth(view: View, d: f64) -> DVec3 {
    match view {
        View::Side => DVec3::Y * d,
        View::Top => DVec3::Z * d,
    }
}

/// How opaque the band a tilted plane sweeps across the panel's depths is.
const SWEPT_OPACITY: f32 = 0.18;

/// Each plane as the line where it crosses the section plane, with the ground behind it
/// shaded if the shapes ask for it. A plane tilted along the line of sight also shades the
/// band it sweeps over the panel's depths: a sphere drawn on its line may be clear of it at
/// its own depth.
fn plane_sections(canvas: &mut Canvas, scope: &Scope, shapes: &Shapes) {
    let (eu, ev, _) = scope.view.axes();
    let map = &scope.map;
    for p in shapes.statics.of::<Plane>().shapes() {
        let (n, q) = (p.normal().as_dvec3(), p.point().as_dvec3());
        let (nu, nv) = (n.dot(eu), n.dot(ev));
        let len2 = nu * nu + nv * nv;
        if len2 < 1e-12 {
            continue;
        }
        // The line where the plane crosses depth `d`: its foot from the projected origin and
        // its two ends, far enough to leave the panel.
        let line_at = |point: DVec3| {
            let rhs = n.dot(q) - n.dot(point);
            let foot = (nu * rhs / len2, nv * rhs / len2);
            let along = (-nv / len2.sqrt(), nu / len2.sqrt());
            let far = scope.reach_from(foot);
            (
                (foot.0 - along.0 * far, foot.1 - along.1 * far),
                (foot.0 + along.0 * far, foot.1 + along.1 * far),
                far,
            )
        };
        let (a, b, far) = line_at(scope.section);
        let (first, last) = (
            at_depth(scope.view, scope.depths.0),
            at_depth(scope.view, scope.depths.1),
        );
        // How far apart, in pixels, its lines at the first and the last depth are.
        let apart = n.dot(first - last).abs() / len2.sqrt() * map.scale;
        if apart > 1.0 {
            let (near, deep) = (line_at(first), line_at(last));
            let swept = vec![
                map.px(near.0),
                map.px(near.1),
                map.px(deep.1),
                map.px(deep.0),
            ];
            canvas.polygon(swept, FLOOR.alpha(SWEPT_OPACITY));
        }
        if shapes.ground {
            let back = (-nu / len2.sqrt() * far, -nv / len2.sqrt() * far);
            let ground = vec![
                map.px(a),
                map.px(b),
                map.px((b.0 + back.0, b.1 + back.1)),
                map.px((a.0 + back.0, a.1 + back.1)),
            ];
            canvas.polygon(ground, GROUND);
        }
        canvas.line(vec![map.px(a), map.px(b)], FLOOR, 3.0);
    }
}

/// Nothing lives outside a container: a wide ring of the panel's colour covers what the
/// shapes drew there.
fn cover_outside_containers(canvas: &mut Canvas, scope: &Scope, shapes: &Shapes) {
    let outside = scope.inner.w.hypot(scope.inner.h) * 2.0;
    for k in shapes.statics.of::<Container>().shapes() {
        let c = scope.px(k.centre().as_dvec3());
        let r = f64::from(k.radius()) * scope.map.scale;
        canvas.disk(c, r + outside / 2.0, None, Some((PANEL.into(), outside)));
    }
}

/// The spheres in the slab (all without one), far to near, each band drawn just before the
/// first sphere nearer than its axis.
fn spheres_far_to_near(
    canvas: &mut Canvas,
    scope: &Scope,
    content: &Content,
    slab: Option<(f64, f64)>,
    bands: Vec<Band>,
) -> usize {
    let view = scope.view;
    let mut dots = 0;
    let mut order: Vec<usize> = (0..content.spheres.len())
        .filter(|&i| {
            let s = &content.spheres[i];
            slab.is_none_or(|(a, b)| {
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
        let r = s.radius * scope.map.scale;
        let stroke = (r >= 2.5).then(|| (fill.rgb.shade(0.6).alpha(fill.alpha), 0.8));
        dots += usize::from(r < MIN_DOT);
        canvas.disk(scope.px(s.centre), r.max(MIN_DOT), Some(fill), stroke);
    }
    bands.for_each(|b| b.draw(canvas));
    dots
}

/// The least radius a sphere is drawn at, in pixels: a smaller one (a sphere far from the
/// rest widens the view until the others are specks) would vanish, and the picture would look
/// empty; such spheres are counted in a note in the panel's corner (`small_spheres_note`).
pub(super) const MIN_DOT: f64 = 1.5;

/// How many spheres were drawn larger than they are, in the panel's top right corner.
fn small_spheres_note(canvas: &mut Canvas, scope: &Scope, fs: f64, dots: usize) {
    if dots == 0 {
        return;
    }
    let inner = scope.inner;
    canvas.text(
        (inner.x + inner.w - fs * 0.5, inner.y + fs * 1.2),
        format!(
            "{} under {:.0} px drawn as dots",
            counted(dots as u64, "sphere", "spheres"),
            2.0 * MIN_DOT
        ),
        fs * 0.7,
        INK,
        Anchor::End,
    );
}

/// The containers' walls, over the spheres.
fn container_outlines(canvas: &mut Canvas, scope: &Scope, shapes: &Shapes) {
    for k in shapes.statics.of::<Container>().shapes() {
        let c = scope.px(k.centre().as_dvec3());
        let r = f64::from(k.radius()) * scope.map.scale;
        canvas.disk(c, r, None, Some((VESSEL.into(), 2.5)));
    }
}

/// The periodic box over the spheres (they fill it to its faces), and the open box of the
/// cell grid, which spheres may leave.
fn box_outlines(canvas: &mut Canvas, scope: &Scope, shapes: &Shapes) {
    let outline = |canvas: &mut Canvas, (lo, hi): (DVec3, DVec3), colour: Rgb, width: f64| {
        let (a, c) = (scope.px(lo), scope.px(hi));
        canvas.line(vec![a, (c.0, a.1), c, (a.0, c.1), a], colour, width);
    };
    if let Some(b) = shapes.periodic_box {
        outline(canvas, (DVec3::ZERO, b), PERIODIC, 2.0);
    }
    if let Some(region) = shapes.region {
        outline(canvas, region, REGION, 1.5);
    }
}

/// Sampled trajectories: a line through the samples, the start ○ and the end ●.
fn trajectories(canvas: &mut Canvas, scope: &Scope, content: &Content) {
    for path in content.paths {
        let points: Vec<(f64, f64)> = path.points.iter().map(|p| scope.px(*p)).collect();
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
}

/// A scale bar in the lower left corner: a round length about a fifth of the panel.
fn scale_bar(canvas: &mut Canvas, scope: &Scope, fs: f64) {
    let (inner, scale) = (scope.inner, scope.map.scale);
    let target = inner.w / 5.0 / scale;
    if !(target.is_finite() && target > 0.0) {
        return;
    }
    let length = round_length(target);
    let (x0, y0) = (inner.x + fs * 0.8, inner.y + inner.h - fs * 0.8);
    let x1 = x0 + length * scale;
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

/// The largest of 1, 2 or 5 times a power of ten not over `target` (positive, finite).
pub(super) fn round_length(target: f64) -> f64 {
    let step = 10f64.powf(target.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|k| k * step)
        .find(|&l| l <= target)
        .unwrap_or(step)
}

/// A length for a label: at most three decimals, no trailing zeros.
pub(super) fn format_length(l: f64) -> String {
    if (1e-3..1e6).contains(&l) {
        let s = format!("{l:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{l:e}")
    }
}

/// The screen axes' names in the panel's corners.
fn axis_names(canvas: &mut Canvas, scope: &Scope, fs: f64) {
    let inner = scope.inner;
    let (a, b) = scope.view.axis_names();
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
}

#[cfg(test)]
mod tests {
    use spheresweep::Cylinder;
    use spheresweep::sim::SphereState;

    use super::super::canvas::Paint;
    use super::*;

    /// A sphere at `(x, y, z)` of radius `radius`.
    fn ball(x: f64, y: f64, z: f64, radius: f64) -> SphereState {
        SphereState {
            centre: DVec3::new(x, y, z),
            velocity: DVec3::ZERO,
            radius,
            mass: 1.0,
            material: 0,
        }
    }

    /// Every sphere red.
    fn red(_: usize, _: &SphereState) -> Paint {
        Paint::from(Rgb::hex(0xff0000))
    }

    /// A side view panel of 202 by 202 pixels and its canvas.
    fn side_panel() -> (Canvas, Panel) {
        let rect = Rect {
            x: 0.0,
            y: 0.0,
            w: 202.0,
            h: 202.0,
        };
        let panel = Panel {
            rect,
            view: View::Side,
            title: String::new(),
            slab: None,
        };
        (Canvas::new(202, 202, PANEL), panel)
    }

    /// In the side view a pillar dims the sphere behind it and not the one in front (the
    /// pillar used to be drawn under every sphere, then hid those behind it whole).
    #[test]
    fn a_pillar_is_drawn_in_depth_order_with_the_spheres() {
        // The pillar along z at y = -4 (nearer than y = 0 seen along +y); a sphere behind it
        // at y = 0 and one in front at y = -6, both over its band in the picture.
        let spheres = [ball(0.0, 0.0, -2.0, 0.5), ball(0.0, -6.0, 3.0, 0.5)];
        let shapes = Shapes {
            statics: spheresweep::Statics::new().with(
                Cylinder::new([0.0, -4.0, 0.0], [0.0, -4.0, 1.0], 1.0).unwrap(),
                (),
            ),
            ..Shapes::default()
        };
        let content = Content {
            spheres: &spheres,
            fill: &red,
            shapes: &shapes,
            paths: &[],
            bounds: (DVec3::new(-5.0, -8.0, -5.0), DVec3::new(5.0, 8.0, 5.0)),
        };
        let (mut canvas, panel) = side_panel();
        draw_panel(&mut canvas, &panel, &content);
        let raster = canvas.raster();
        // 20 pixels a unit, the scene's (x, z) = (0, 0) at pixel (101, 101).
        let at = |x: f64, z: f64| {
            let (i, j) = ((101.0 + x * 20.0) as usize, (101.0 - z * 20.0) as usize);
            let k = 3 * (j * 202 + i);
            [raster[k], raster[k + 1], raster[k + 2]]
        };
        // Each channel of `top` at opacity `alpha` over `under`, within a unit of rounding.
        let over = |top: Rgb, under: [u8; 3], alpha: f32| {
            let mix = |t: u8, u: u8| f32::from(t) * alpha + f32::from(u) * (1.0 - alpha);
            [
                mix(top.0, under[0]),
                mix(top.1, under[1]),
                mix(top.2, under[2]),
            ]
        };
        let near = |got: [u8; 3], want: [f32; 3]| {
            got.iter()
                .zip(want)
                .all(|(&g, w)| (f32::from(g) - w).abs() <= 1.5)
        };
        let (pillar, ground) = (at(0.0, 0.0), at(4.0, 0.0));
        assert!(
            near(pillar, over(PILLAR, ground, BAND_OPACITY)),
            "the pillar is drawn: {pillar:?} over {ground:?}"
        );
        let behind = at(0.0, -2.0);
        assert!(
            near(behind, over(PILLAR, [255, 0, 0], BAND_OPACITY)),
            "the sphere behind the pillar is dimmed by it: {behind:?}"
        );
        assert_eq!(
            at(0.0, 3.0),
            [255, 0, 0],
            "the sphere in front is drawn over it"
        );
    }

    /// A sphere far smaller than a pixel (a far-flung sphere widens the view until the others
    /// are specks) is still drawn, as a dot of the least radius, and counted for the note: the
    /// picture of such a scene was blank.
    #[test]
    fn a_sphere_smaller_than_a_pixel_is_drawn_as_a_dot() {
        let spheres = [ball(0.0, 0.0, 0.0, 1e-6)];
        let shapes = Shapes::default();
        let content = Content {
            spheres: &spheres,
            fill: &red,
            shapes: &shapes,
            paths: &[],
            bounds: (DVec3::splat(-5.0), DVec3::splat(5.0)),
        };
        let (mut canvas, panel) = side_panel();
        let fs = text_size(canvas.width);
        let inner = frame(&mut canvas, &panel, fs);
        let scope = Scope::new(inner, &panel, content.bounds);
        let dots = spheres_far_to_near(&mut canvas, &scope, &content, None, Vec::new());
        assert_eq!(dots, 1);
        let (x, y) = scope.px(DVec3::ZERO);
        let raster = canvas.raster();
        let k = 3 * (y as usize * 202 + x as usize);
        assert_eq!(
            raster[k..k + 3],
            [255, 0, 0],
            "the speck's dot at ({x}, {y})"
        );
    }

    #[test]
    fn scale_bars_have_round_lengths() {
        assert_eq!(round_length(7.3), 5.0);
        assert_eq!(round_length(0.031), 0.02);
        assert_eq!(round_length(100.0), 100.0);
        assert_eq!(format_length(0.02), "0.02");
        assert_eq!(format_length(2e7), "2e7");
    }
}
