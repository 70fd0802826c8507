//! Pictures: side and top views of simulation scenes and snapshots (the spheres, the static
//! shapes and sampled trajectories), and the demo table's top view. Each is drawn once into a
//! display list ([`Canvas`]) and written as SVG or, rasterised by tiny-skia with the built-in
//! pixel font, as PNG (no system fonts).

mod canvas;
mod font;
mod format;
mod frame;
mod legend;
mod panel;
mod raster;
mod size;
mod svg;
mod top_view;

use glam::DVec3;
use spheresweep::Statics;
use spheresweep::sim::SphereState;

pub use canvas::{Anchor, Canvas, Paint, Rect, Rgb};
pub use format::Format;
pub use frame::{bounds, outside};
pub use legend::{Key, legend};
pub use panel::draw_panel;
pub use size::Size;
pub use top_view::top_view;

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
    /// The static shapes, by kind.
    pub statics: Statics,
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
            statics: world.statics.map(|_, _| ()),
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

/// Base text size for a picture `width` pixels wide.
pub fn text_size(width: u32) -> f64 {
    if width >= 1000 { 20.0 } else { 10.0 }
}

/// Colours of the vessel, pillars and floor, for legends.
pub const SHAPE_COLOURS: (Rgb, Rgb, Rgb) = (VESSEL, PILLAR, FLOOR);
/// Colours of the periodic box's and the open box's outlines, for legends.
pub const BOX_COLOURS: (Rgb, Rgb) = (PERIODIC, REGION);

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
    fn views_project_and_order_by_depth() {
        let p = DVec3::new(1.0, 2.0, 3.0);
        assert_eq!(View::Side.project(p), (1.0, 3.0));
        assert_eq!(View::Top.project(p), (1.0, 2.0));
        // Seen along +y, a smaller y is nearer; seen from above, a larger z.
        assert!(View::Side.nearness(DVec3::ZERO) > View::Side.nearness(DVec3::Y));
        assert!(View::Top.nearness(DVec3::Z) > View::Top.nearness(DVec3::ZERO));
    }
}
