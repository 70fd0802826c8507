//! The display list every picture is drawn into: shapes in pixel coordinates (circles,
//! polylines, rectangles, polygons, text), each with its paint and clip rectangle, in drawing
//! order. `svg` writes it as SVG text and `raster` rasterises it (tiny-skia) into a PNG with the
//! built-in font, so one drawing gives both files.

/// An sRGB colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    /// From `0xRRGGBB`.
    pub const fn hex(v: u32) -> Self {
        Self((v >> 16) as u8, (v >> 8) as u8, v as u8)
    }

    /// This colour mixed with black (`k < 1` darker) or towards white (`k > 1`).
    pub fn shade(self, k: f64) -> Self {
        let f = |c: u8| {
            let c = f64::from(c);
            let v = if k <= 1.0 {
                c * k
            } else {
                c + (255.0 - c) * (k - 1.0).min(1.0)
            };
            v.round().clamp(0.0, 255.0) as u8
        };
        Self(f(self.0), f(self.1), f(self.2))
    }

    /// This colour at opacity `alpha`.
    pub fn alpha(self, alpha: f32) -> Paint {
        Paint { rgb: self, alpha }
    }
}

/// A colour and its opacity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Paint {
    /// The colour.
    pub rgb: Rgb,
    /// Opacity in `[0, 1]`.
    pub alpha: f32,
}

impl From<Rgb> for Paint {
    fn from(rgb: Rgb) -> Self {
        Self { rgb, alpha: 1.0 }
    }
}

/// A rectangle in pixels: left, top, width, height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
}

impl Rect {
    /// This rectangle shrunk by `d` on every side.
    pub fn inset(self, d: f64) -> Self {
        Self {
            x: self.x + d,
            y: self.y + d,
            w: self.w - 2.0 * d,
            h: self.h - 2.0 * d,
        }
    }
}

/// Where a text's anchor point lies along it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

/// An outline: its paint and width in pixels (centred on the shape's edge).
pub type Stroke = (Paint, f64);

/// One shape of the display list.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// A circle, filled and/or outlined.
    Disk {
        centre: (f64, f64),
        radius: f64,
        fill: Option<Paint>,
        stroke: Option<Stroke>,
    },
    /// An open polyline of the given width, with round joins and caps.
    Line {
        points: Vec<(f64, f64)>,
        paint: Paint,
        width: f64,
    },
    /// A filled rectangle.
    Rect { rect: Rect, paint: Paint },
    /// A filled polygon (closed; the non-zero rule).
    Polygon {
        points: Vec<(f64, f64)>,
        paint: Paint,
    },
    /// One line of text, `size` pixels high (capital height about 0.7 of it), its baseline at
    /// `at.1`.
    Text {
        at: (f64, f64),
        text: String,
        size: f64,
        colour: Rgb,
        anchor: Anchor,
    },
}

/// A picture: its size, background, the clip rectangles, and the shapes in drawing order,
/// each with the index of the clip rectangle it is drawn in (`None`: the whole picture).
#[derive(Debug, Clone)]
pub struct Canvas {
    pub width: u32,
    pub height: u32,
    pub(super) background: Rgb,
    pub(super) clips: Vec<Rect>,
    pub(super) items: Vec<(Option<usize>, Item)>,
    clip: Option<usize>,
}

impl Canvas {
    pub fn new(width: u32, height: u32, background: Rgb) -> Self {
        Self {
            width,
            height,
            background,
            clips: Vec::new(),
            items: Vec::new(),
            clip: None,
        }
    }

    /// Clips every shape added from now on to `rect` (`None`: the whole picture).
    pub fn clip_to(&mut self, rect: Option<Rect>) {
        self.clip = rect.map(|r| {
            self.clips.push(r);
            self.clips.len() - 1
        });
    }

    pub fn push(&mut self, item: Item) {
        self.items.push((self.clip, item));
    }

    pub fn disk(
        &mut self,
        centre: (f64, f64),
        radius: f64,
        fill: Option<Paint>,
        stroke: Option<Stroke>,
    ) {
        self.push(Item::Disk {
            centre,
            radius,
            fill,
            stroke,
        });
    }

    pub fn line(&mut self, points: Vec<(f64, f64)>, paint: impl Into<Paint>, width: f64) {
        self.push(Item::Line {
            points,
            paint: paint.into(),
            width,
        });
    }

    pub fn polygon(&mut self, points: Vec<(f64, f64)>, paint: impl Into<Paint>) {
        self.push(Item::Polygon {
            points,
            paint: paint.into(),
        });
    }

    pub fn rect(&mut self, rect: Rect, paint: impl Into<Paint>) {
        self.push(Item::Rect {
            rect,
            paint: paint.into(),
        });
    }

    pub fn text(
        &mut self,
        at: (f64, f64),
        text: impl Into<String>,
        size: f64,
        colour: Rgb,
        anchor: Anchor,
    ) {
        self.push(Item::Text {
            at,
            text: text.into(),
            size,
            colour,
            anchor,
        });
    }
}
