//! A legend: one row of keys (a disk, a path or a swatch) and their labels, as many as fit.

use super::canvas::{Anchor, Canvas, Paint, Rect, Rgb};
use super::raster::text_width;
use super::{INK, text_size};

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
        draw_key(canvas, key, (x, y - fs * 0.35), fs);
        canvas.text((x + fs * 1.6, y), label, fs, INK, Anchor::Start);
        x += need;
    }
    x
}

/// One key with its left edge at `x` and its middle at `cy`.
fn draw_key(canvas: &mut Canvas, key: &Key, (x, cy): (f64, f64), fs: f64) {
    match key {
        Key::Disk(p) => canvas.disk(
            (x + fs * 0.5, cy),
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
}
