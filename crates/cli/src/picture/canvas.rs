//! A picture as a list of shapes in pixel coordinates, written as SVG text or rasterised into
//! a PNG by a small anti-aliased rasteriser (coverage from the distance to each shape's edge),
//! with text in a built-in 5×7 pixel font: the PNG needs no system fonts.

use std::fmt::Write as _;

use super::font;

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

    fn css(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }

    fn linear(self) -> [f32; 3] {
        [self.0, self.1, self.2].map(|c| f32::from(c) / 255.0)
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

impl Rgb {
    /// This colour at opacity `alpha`.
    pub fn alpha(self, alpha: f32) -> Paint {
        Paint { rgb: self, alpha }
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

/// Where a text's anchor point lies along it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

/// One shape.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// A circle, filled and/or outlined (the outline centred on the circle).
    Disk {
        centre: (f64, f64),
        radius: f64,
        fill: Option<Paint>,
        stroke: Option<(Paint, f64)>,
    },
    /// An open polyline of the given width.
    Line {
        points: Vec<(f64, f64)>,
        paint: Paint,
        width: f64,
    },
    /// A filled convex polygon.
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

/// A picture: its size, background and shapes in drawing order, each clipped to a rectangle.
#[derive(Debug, Clone)]
pub struct Canvas {
    pub width: u32,
    pub height: u32,
    background: Rgb,
    clips: Vec<Rect>,
    items: Vec<(Option<usize>, Item)>,
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
        stroke: Option<(Paint, f64)>,
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

    pub fn rect(&mut self, r: Rect, paint: impl Into<Paint>) {
        self.polygon(
            vec![
                (r.x, r.y),
                (r.x + r.w, r.y),
                (r.x + r.w, r.y + r.h),
                (r.x, r.y + r.h),
            ],
            paint,
        );
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

    /// The picture as an SVG document.
    pub fn svg(&self) -> String {
        let (w, h) = (self.width, self.height);
        let mut s = String::with_capacity(64 * self.items.len() + 512);
        let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
        );
        if !self.clips.is_empty() {
            s.push_str("<defs>\n");
            for (k, r) in self.clips.iter().enumerate() {
                let _ = writeln!(
                    s,
                    r#"<clipPath id="clip{k}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath>"#,
                    num(r.x),
                    num(r.y),
                    num(r.w),
                    num(r.h)
                );
            }
            s.push_str("</defs>\n");
        }
        let _ = writeln!(
            s,
            r#"<rect width="{w}" height="{h}" fill="{}"/>"#,
            self.background.css()
        );
        let mut open: Option<usize> = None;
        for (clip, item) in &self.items {
            if *clip != open {
                if open.is_some() {
                    s.push_str("</g>\n");
                }
                if let Some(k) = clip {
                    let _ = writeln!(s, r#"<g clip-path="url(#clip{k})">"#);
                }
                open = *clip;
            }
            svg_item(&mut s, item);
        }
        if open.is_some() {
            s.push_str("</g>\n");
        }
        s.push_str("</svg>\n");
        s
    }

    /// The picture as a PNG file (8-bit RGB).
    pub fn png(&self) -> Result<Vec<u8>, String> {
        let pixels = self.raster();
        let mut bytes = Vec::new();
        {
            let mut encoder = png::Encoder::new(&mut bytes, self.width, self.height);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            let mut writer = encoder
                .write_header()
                .map_err(|e| format!("PNG encoding: {e}"))?;
            writer
                .write_image_data(&pixels)
                .map_err(|e| format!("PNG encoding: {e}"))?;
            writer.finish().map_err(|e| format!("PNG encoding: {e}"))?;
        }
        Ok(bytes)
    }

    /// The picture's pixels, row by row, three bytes each.
    pub fn raster(&self) -> Vec<u8> {
        let mut r = Raster {
            w: self.width as usize,
            h: self.height as usize,
            px: vec![self.background.linear(); self.width as usize * self.height as usize],
            clip: (0, 0, self.width as usize, self.height as usize),
        };
        let full = r.clip;
        for (clip, item) in &self.items {
            r.clip = match clip {
                None => full,
                Some(k) => {
                    let c = self.clips[*k];
                    let lo = |v: f64, max: usize| (v.max(0.0).round() as usize).min(max);
                    (
                        lo(c.x, r.w),
                        lo(c.y, r.h),
                        lo(c.x + c.w, r.w),
                        lo(c.y + c.h, r.h),
                    )
                }
            };
            r.draw(item);
        }
        r.px.iter()
            .flat_map(|p| p.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8))
            .collect()
    }
}

/// A number for SVG: two decimals, no trailing zeros.
fn num(v: f64) -> String {
    let v = if v.is_finite() { v } else { 0.0 };
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn paint_attr(kind: &str, p: Paint) -> String {
    if p.alpha >= 1.0 {
        format!(r#"{kind}="{}""#, p.rgb.css())
    } else {
        format!(
            r#"{kind}="{}" {kind}-opacity="{}""#,
            p.rgb.css(),
            num(f64::from(p.alpha))
        )
    }
}

fn points_attr(points: &[(f64, f64)]) -> String {
    let mut s = String::with_capacity(points.len() * 14);
    for (k, (x, y)) in points.iter().enumerate() {
        if k > 0 {
            s.push(' ');
        }
        s.push_str(&num(*x));
        s.push(',');
        s.push_str(&num(*y));
    }
    s
}

fn svg_item(s: &mut String, item: &Item) {
    match item {
        Item::Disk {
            centre,
            radius,
            fill,
            stroke,
        } => {
            let fill = fill.map_or_else(|| r#"fill="none""#.to_string(), |p| paint_attr("fill", p));
            let stroke = stroke.map_or_else(String::new, |(p, w)| {
                format!(r#" {} stroke-width="{}""#, paint_attr("stroke", p), num(w))
            });
            let _ = writeln!(
                s,
                r#"<circle cx="{}" cy="{}" r="{}" {fill}{stroke}/>"#,
                num(centre.0),
                num(centre.1),
                num(*radius)
            );
        }
        Item::Line {
            points,
            paint,
            width,
        } => {
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" {} stroke-width="{}" stroke-linejoin="round" stroke-linecap="round"/>"#,
                points_attr(points),
                paint_attr("stroke", *paint),
                num(*width)
            );
        }
        Item::Polygon { points, paint } => {
            let _ = writeln!(
                s,
                r#"<polygon points="{}" {}/>"#,
                points_attr(points),
                paint_attr("fill", *paint)
            );
        }
        Item::Text {
            at,
            text,
            size,
            colour,
            anchor,
        } => {
            let anchor = match anchor {
                Anchor::Start => "start",
                Anchor::Middle => "middle",
                Anchor::End => "end",
            };
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}" font-family="sans-serif" font-size="{}" fill="{}" text-anchor="{anchor}">{}</text>"#,
                num(at.0),
                num(at.1),
                num(*size),
                colour.css(),
                escape(text)
            );
        }
    }
}

/// Pixels in linear-in-sRGB floats, and the clip rectangle (x0, y0, x1, y1) in force.
struct Raster {
    w: usize,
    h: usize,
    px: Vec<[f32; 3]>,
    clip: (usize, usize, usize, usize),
}

fn coverage(distance_inside: f64) -> f32 {
    (distance_inside + 0.5).clamp(0.0, 1.0) as f32
}

impl Raster {
    /// The pixel range covering `[x0, x1] × [y0, y1]` (pixel units), within the clip.
    fn span(&self, x0: f64, y0: f64, x1: f64, y1: f64) -> Option<(usize, usize, usize, usize)> {
        let (cx0, cy0, cx1, cy1) = self.clip;
        if !(x0.is_finite() && y0.is_finite() && x1.is_finite() && y1.is_finite()) {
            return None;
        }
        let a = (
            x0.floor().max(cx0 as f64) as usize,
            y0.floor().max(cy0 as f64) as usize,
        );
        let b = (
            (x1.ceil().max(0.0) as usize).min(cx1),
            (y1.ceil().max(0.0) as usize).min(cy1),
        );
        (a.0 < b.0 && a.1 < b.1).then_some((a.0, a.1, b.0, b.1))
    }

    fn blend(&mut self, x: usize, y: usize, c: [f32; 3], a: f32) {
        if a <= 0.0 {
            return;
        }
        let p = &mut self.px[y * self.w + x];
        for k in 0..3 {
            p[k] += (c[k] - p[k]) * a;
        }
    }

    fn draw(&mut self, item: &Item) {
        match item {
            Item::Disk {
                centre,
                radius,
                fill,
                stroke,
            } => {
                let (cx, cy, r) = (centre.0, centre.1, radius.max(0.0));
                let half = stroke.map_or(0.0, |(_, w)| w / 2.0);
                let reach = r + half + 1.0;
                let Some((x0, y0, x1, y1)) =
                    self.span(cx - reach, cy - reach, cx + reach, cy + reach)
                else {
                    return;
                };
                for y in y0..y1 {
                    for x in x0..x1 {
                        let d = (x as f64 + 0.5 - cx).hypot(y as f64 + 0.5 - cy);
                        if let Some(p) = fill {
                            self.blend(x, y, p.rgb.linear(), p.alpha * coverage(r - d));
                        }
                        if let Some((p, w)) = stroke {
                            // Thin strokes: full width, faded.
                            let (w, fade) = if *w < 1.0 {
                                (1.0, *w as f32)
                            } else {
                                (*w, 1.0)
                            };
                            let a = coverage(w / 2.0 - (d - r).abs());
                            self.blend(x, y, p.rgb.linear(), p.alpha * fade * a);
                        }
                    }
                }
            }
            Item::Line {
                points,
                paint,
                width,
            } => self.polyline(points, *paint, *width),
            Item::Polygon { points, paint } => self.polygon(points, *paint),
            Item::Text {
                at,
                text,
                size,
                colour,
                anchor,
            } => self.text(*at, text, *size, *colour, *anchor),
        }
    }

    /// A polyline: the coverage of every segment is combined by maximum before blending once,
    /// so joints of a translucent line are not darker.
    fn polyline(&mut self, points: &[(f64, f64)], paint: Paint, width: f64) {
        if points.is_empty() {
            return;
        }
        let (w, fade) = if width < 1.0 {
            (1.0, width as f32)
        } else {
            (width, 1.0)
        };
        let half = w / 2.0;
        let (mut lo, mut hi) = (
            (f64::INFINITY, f64::INFINITY),
            (f64::NEG_INFINITY, f64::NEG_INFINITY),
        );
        for p in points {
            lo = (lo.0.min(p.0), lo.1.min(p.1));
            hi = (hi.0.max(p.0), hi.1.max(p.1));
        }
        let Some((x0, y0, x1, y1)) = self.span(
            lo.0 - half - 1.0,
            lo.1 - half - 1.0,
            hi.0 + half + 1.0,
            hi.1 + half + 1.0,
        ) else {
            return;
        };
        let bw = x1 - x0;
        let mut cov = vec![0f32; bw * (y1 - y0)];
        let segments: Vec<((f64, f64), (f64, f64))> = if points.len() == 1 {
            vec![(points[0], points[0])]
        } else {
            points.windows(2).map(|s| (s[0], s[1])).collect()
        };
        for (a, b) in segments {
            let Some((sx0, sy0, sx1, sy1)) = self.span(
                a.0.min(b.0) - half - 1.0,
                a.1.min(b.1) - half - 1.0,
                a.0.max(b.0) + half + 1.0,
                a.1.max(b.1) + half + 1.0,
            ) else {
                continue;
            };
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let len2 = dx * dx + dy * dy;
            for y in sy0..sy1 {
                for x in sx0..sx1 {
                    let (px, py) = (x as f64 + 0.5 - a.0, y as f64 + 0.5 - a.1);
                    let t = if len2 > 0.0 {
                        ((px * dx + py * dy) / len2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let d = (px - t * dx).hypot(py - t * dy);
                    let c = &mut cov[(y - y0) * bw + (x - x0)];
                    *c = c.max(coverage(half - d));
                }
            }
        }
        let colour = paint.rgb.linear();
        for y in y0..y1 {
            for x in x0..x1 {
                let c = cov[(y - y0) * bw + (x - x0)];
                self.blend(x, y, colour, paint.alpha * fade * c);
            }
        }
    }

    /// A convex polygon: coverage from the signed distance to the nearest edge.
    fn polygon(&mut self, points: &[(f64, f64)], paint: Paint) {
        if points.len() < 3 {
            return;
        }
        let area: f64 = (0..points.len())
            .map(|k| {
                let (a, b) = (points[k], points[(k + 1) % points.len()]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum();
        if area == 0.0 || !area.is_finite() {
            return;
        }
        let sign = area.signum();
        // Inward unit normals and offsets: inside where n·p − c ≥ 0 for every edge.
        let edges: Vec<(f64, f64, f64)> = (0..points.len())
            .filter_map(|k| {
                let (a, b) = (points[k], points[(k + 1) % points.len()]);
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let len = dx.hypot(dy);
                (len > 0.0).then(|| {
                    let (nx, ny) = (-dy * sign / len, dx * sign / len);
                    (nx, ny, nx * a.0 + ny * a.1)
                })
            })
            .collect();
        let (mut lo, mut hi) = (
            (f64::INFINITY, f64::INFINITY),
            (f64::NEG_INFINITY, f64::NEG_INFINITY),
        );
        for p in points {
            lo = (lo.0.min(p.0), lo.1.min(p.1));
            hi = (hi.0.max(p.0), hi.1.max(p.1));
        }
        let Some((x0, y0, x1, y1)) = self.span(lo.0 - 1.0, lo.1 - 1.0, hi.0 + 1.0, hi.1 + 1.0)
        else {
            return;
        };
        let colour = paint.rgb.linear();
        for y in y0..y1 {
            for x in x0..x1 {
                let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                let inside = edges
                    .iter()
                    .map(|(nx, ny, c)| nx * px + ny * py - c)
                    .fold(f64::INFINITY, f64::min);
                self.blend(x, y, colour, paint.alpha * coverage(inside));
            }
        }
    }

    /// Text in the 5×7 font, scaled by a whole number of pixels.
    fn text(&mut self, at: (f64, f64), text: &str, size: f64, colour: Rgb, anchor: Anchor) {
        let scale = (size / 10.0).round().max(1.0) as usize;
        let count = text.chars().count();
        let width = (count as f64 * f64::from(font::ADVANCE) - 1.0) * scale as f64;
        let left = match anchor {
            Anchor::Start => at.0,
            Anchor::Middle => at.0 - width / 2.0,
            Anchor::End => at.0 - width,
        }
        .round();
        let top = (at.1 - f64::from(font::HEIGHT) * scale as f64).round();
        let c = colour.linear();
        for (k, ch) in text.chars().enumerate() {
            let glyph = font::glyph(ch);
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..5 {
                    if bits & (0x10 >> col) == 0 {
                        continue;
                    }
                    let x = left + ((k * font::ADVANCE as usize + col) * scale) as f64;
                    let y = top + (row * scale) as f64;
                    if let Some((x0, y0, x1, y1)) =
                        self.span(x, y, x + scale as f64, y + scale as f64)
                    {
                        for py in y0..y1 {
                            for px in x0..x1 {
                                self.blend(px, py, c, 1.0);
                            }
                        }
                    }
                }
            }
        }
    }
}

/// Width of `text` in pixels as the PNG draws it at `size` (for layout).
pub fn text_width(text: &str, size: f64) -> f64 {
    let scale = (size / 10.0).round().max(1.0);
    (text.chars().count() as f64 * f64::from(font::ADVANCE) - 1.0) * scale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_disk_covers_its_area() {
        let mut c = Canvas::new(40, 40, Rgb(255, 255, 255));
        c.disk((20.0, 20.0), 10.0, Some(Rgb(0, 0, 0).into()), None);
        let px = c.raster();
        let dark: f64 = px.chunks(3).map(|p| 1.0 - f64::from(p[0]) / 255.0).sum();
        let area = std::f64::consts::PI * 100.0;
        assert!((dark - area).abs() < 0.01 * area, "{dark} vs {area}");
    }

    #[test]
    fn clipping_keeps_shapes_in_their_rectangle() {
        let mut c = Canvas::new(20, 10, Rgb(255, 255, 255));
        c.clip_to(Some(Rect {
            x: 0.0,
            y: 0.0,
            w: 10.0,
            h: 10.0,
        }));
        c.rect(
            Rect {
                x: -5.0,
                y: -5.0,
                w: 40.0,
                h: 40.0,
            },
            Rgb(0, 0, 0),
        );
        let px = c.raster();
        assert_eq!(px[3 * 9], 0);
        assert_eq!(px[3 * 10], 255);
        assert!(c.svg().contains(r#"clip-path="url(#clip0)""#));
    }

    #[test]
    fn svg_numbers_are_short() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(-0.001), "0");
        assert_eq!(num(2.346), "2.35");
        assert_eq!(num(f64::NAN), "0");
    }
}
