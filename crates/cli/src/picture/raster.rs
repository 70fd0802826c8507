//! The display list rasterised by tiny-skia (anti-aliased fills and strokes, source-over
//! blending in sRGB) and encoded as an 8-bit RGB PNG. Text is drawn in the built-in pixel font
//! (`font`), so the PNG needs no system fonts.

use tiny_skia as skia;

use super::canvas::{Anchor, Canvas, Item, Paint, Rect};
use super::font;

impl Canvas {
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

    /// The picture's pixels, row by row, three bytes (R, G, B) each.
    pub fn raster(&self) -> Vec<u8> {
        let Some(mut pixmap) = skia::Pixmap::new(self.width, self.height) else {
            // A picture of no pixels.
            return Vec::new();
        };
        pixmap.fill(colour(self.background.into()));
        let masks: Vec<Option<skia::Mask>> = self
            .clips
            .iter()
            .map(|r| clip_mask(*r, self.width, self.height))
            .collect();
        for (clip, item) in &self.items {
            let mask = clip.and_then(|k| masks[k].as_ref());
            draw(&mut pixmap, item, mask);
        }
        // The background is opaque, so every pixel is: premultiplied equals straight colour.
        pixmap
            .data()
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect()
    }
}

/// The mask of a clip rectangle, rounded to whole pixels.
fn clip_mask(r: Rect, width: u32, height: u32) -> Option<skia::Mask> {
    let mut mask = skia::Mask::new(width, height)?;
    let (x0, y0) = (r.x.round(), r.y.round());
    let (x1, y1) = ((r.x + r.w).round(), (r.y + r.h).round());
    if let Some(rect) = skia::Rect::from_ltrb(x0 as f32, y0 as f32, x1 as f32, y1 as f32) {
        let path = skia::PathBuilder::from_rect(rect);
        mask.fill_path(
            &path,
            skia::FillRule::Winding,
            false,
            skia::Transform::identity(),
        );
    }
    Some(mask)
}

fn colour(p: Paint) -> skia::Color {
    let a = (p.alpha.clamp(0.0, 1.0) * 255.0).round() as u8;
    skia::Color::from_rgba8(p.rgb.0, p.rgb.1, p.rgb.2, a)
}

fn brush(p: Paint) -> skia::Paint<'static> {
    let mut paint = skia::Paint::default();
    paint.set_color(colour(p));
    paint.anti_alias = true;
    paint
}

/// A round-joined, round-capped stroke `width` pixels wide (tiny-skia draws one below a pixel
/// as a hairline faded by its width).
fn pen(width: f64) -> skia::Stroke {
    skia::Stroke {
        width: width.max(0.0) as f32,
        line_cap: skia::LineCap::Round,
        line_join: skia::LineJoin::Round,
        ..skia::Stroke::default()
    }
}

/// An open polyline's path (`None` if it has no length to draw).
fn polyline(points: &[(f64, f64)], close: bool) -> Option<skia::Path> {
    let mut b = skia::PathBuilder::new();
    let (first, rest) = points.split_first()?;
    b.move_to(first.0 as f32, first.1 as f32);
    if rest.is_empty() {
        // One point: a dot, as SVG draws a round-capped zero-length line.
        b.line_to(first.0 as f32, first.1 as f32);
    }
    for p in rest {
        b.line_to(p.0 as f32, p.1 as f32);
    }
    if close {
        b.close();
    }
    b.finish()
}

/// A circle as a polygon whose edges stray from the arc by under 0.02 px, and whose area is
/// the circle's. (tiny-skia's own circle is four conics drawn as quadratic curves about 0.1 px
/// inside the circle: a disk of radius 10 px lost 2 % of its ink.)
fn circle((cx, cy): (f64, f64), r: f64) -> Option<skia::Path> {
    if !(r > 0.0 && r.is_finite()) {
        return None;
    }
    let step = (1.0 - (0.02 / r).min(1.0)).acos();
    let n = (std::f64::consts::PI / step).ceil().clamp(8.0, 4096.0);
    let angle = std::f64::consts::TAU / n;
    let r = r * (angle / angle.sin()).sqrt();
    let points: Vec<(f64, f64)> = (0..n as usize)
        .map(|k| {
            let a = k as f64 * angle;
            (cx + r * a.cos(), cy + r * a.sin())
        })
        .collect();
    polyline(&points, true)
}

/// Draws one shape of the display list, within `mask` if given.
fn draw(pixmap: &mut skia::Pixmap, item: &Item, mask: Option<&skia::Mask>) {
    let id = skia::Transform::identity();
    match item {
        Item::Disk {
            centre,
            radius,
            fill,
            stroke,
        } => {
            let Some(circle) = circle(*centre, *radius) else {
                return;
            };
            if let Some(p) = fill {
                pixmap.fill_path(&circle, &brush(*p), skia::FillRule::Winding, id, mask);
            }
            if let Some((p, w)) = stroke {
                pixmap.stroke_path(&circle, &brush(*p), &pen(*w), id, mask);
            }
        }
        Item::Line {
            points,
            paint,
            width,
        } => {
            if let Some(path) = polyline(points, false) {
                pixmap.stroke_path(&path, &brush(*paint), &pen(*width), id, mask);
            }
        }
        Item::Rect { rect, paint } => {
            let r =
                skia::Rect::from_xywh(rect.x as f32, rect.y as f32, rect.w as f32, rect.h as f32);
            if let Some(r) = r {
                pixmap.fill_rect(r, &brush(*paint), id, mask);
            }
        }
        Item::Polygon { points, paint } => {
            if let Some(path) = polyline(points, true) {
                pixmap.fill_path(&path, &brush(*paint), skia::FillRule::Winding, id, mask);
            }
        }
        Item::Text {
            at,
            text,
            size,
            colour,
            anchor,
        } => {
            if let Some(path) = glyphs(*at, text, *size, *anchor) {
                let mut paint = brush((*colour).into());
                // Whole pixels: no blur at the glyphs' edges.
                paint.anti_alias = false;
                pixmap.fill_path(&path, &paint, skia::FillRule::Winding, id, mask);
            }
        }
    }
}

/// The built-in font's scale (a whole number of pixels per font pixel) at text `size`.
fn font_scale(size: f64) -> f64 {
    (size / 10.0).round().max(1.0)
}

/// Width of `text` in pixels as the PNG draws it at `size` (for layout).
pub fn text_width(text: &str, size: f64) -> f64 {
    (text.chars().count() as f64 * f64::from(font::ADVANCE) - 1.0) * font_scale(size)
}

/// `text` in the 5×7 font as one path of whole-pixel squares, its baseline at `at.1`.
fn glyphs(at: (f64, f64), text: &str, size: f64, anchor: Anchor) -> Option<skia::Path> {
    let scale = font_scale(size);
    let width = text_width(text, size);
    let left = match anchor {
        Anchor::Start => at.0,
        Anchor::Middle => at.0 - width / 2.0,
        Anchor::End => at.0 - width,
    }
    .round();
    let top = (at.1 - f64::from(font::HEIGHT) * scale).round();
    let mut b = skia::PathBuilder::new();
    for (k, ch) in text.chars().enumerate() {
        let cell = left + (k as f64) * f64::from(font::ADVANCE) * scale;
        for (row, bits) in font::glyph(ch).iter().enumerate() {
            for col in (0..5u8).filter(|&col| bits & (0x10 >> col) != 0) {
                let (x, y) = (cell + f64::from(col) * scale, top + row as f64 * scale);
                if let Some(r) =
                    skia::Rect::from_xywh(x as f32, y as f32, scale as f32, scale as f32)
                {
                    b.push_rect(r);
                }
            }
        }
    }
    b.finish()
}

#[cfg(test)]
mod tests {
    use super::super::canvas::Rgb;
    use super::*;

    /// The ink of a disk is its area, at any size and position.
    #[test]
    fn a_disk_covers_its_area() {
        for (r, centre) in [
            (10.0, (20.0, 20.0)),
            (2.0, (20.3, 19.6)),
            (17.5, (20.5, 20.5)),
        ] {
            let mut c = Canvas::new(40, 40, Rgb(255, 255, 255));
            c.disk(centre, r, Some(Rgb(0, 0, 0).into()), None);
            let px = c.raster();
            let dark: f64 = px.chunks(3).map(|p| 1.0 - f64::from(p[0]) / 255.0).sum();
            let area = std::f64::consts::PI * r * r;
            assert!((dark - area).abs() < 0.01 * area, "{r}: {dark} vs {area}");
        }
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
    }

    /// Half-transparent black over white is mid grey, and a translucent polyline's joint is
    /// not darker than its segments.
    #[test]
    fn alpha_blends_once_per_shape() {
        let mut c = Canvas::new(30, 30, Rgb(255, 255, 255));
        c.line(
            vec![(5.0, 5.5), (25.0, 5.5), (25.0, 25.0)],
            Rgb(0, 0, 0).alpha(0.5),
            3.0,
        );
        let px = c.raster();
        let at = |x: usize, y: usize| px[3 * (y * 30 + x)];
        assert!((i32::from(at(15, 5)) - 128).abs() <= 2, "{}", at(15, 5));
        assert_eq!(at(25, 5), at(15, 5), "the joint");
        assert_eq!(at(15, 20), 255);
    }

    /// Text is drawn in the built-in font: the glyph of `I` (a bar and two serifs) in whole
    /// pixels, scaled by two at size 20.
    #[test]
    fn text_is_drawn_in_the_pixel_font() {
        let mut c = Canvas::new(20, 20, Rgb(255, 255, 255));
        c.text((2.0, 16.0), "I", 20.0, Rgb(0, 0, 0), Anchor::Start);
        let px = c.raster();
        let ink = |x: usize, y: usize| px[3 * (y * 20 + x)] == 0;
        // Top row 0x0E: columns 1..4 at scale 2 → pixels 4..10, rows 2..4.
        assert!(ink(4, 2) && ink(9, 3) && !ink(3, 2) && !ink(10, 2));
        // The bar (column 2) down to the baseline.
        assert!(ink(6, 10) && ink(7, 15) && !ink(5, 10));
        assert_eq!(px.iter().filter(|&&v| v != 0 && v != 255).count(), 0);
        assert_eq!(text_width("I", 20.0), 10.0);
    }
}
