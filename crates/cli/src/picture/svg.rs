//! The display list written as an SVG document: one element per shape, a `<g>` per run of
//! shapes in one clip rectangle, text in the viewer's sans-serif font.

use std::fmt::Write as _;

use super::canvas::{Anchor, Canvas, Item, Paint, Rgb};

impl Canvas {
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
            css(self.background)
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
            element(&mut s, item);
        }
        if open.is_some() {
            s.push_str("</g>\n");
        }
        s.push_str("</svg>\n");
        s
    }
}

/// A number for SVG: two decimals, no trailing zeros.
fn num(v: f64) -> String {
    let v = if v.is_finite() { v } else { 0.0 };
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.into() }
}

fn css(c: Rgb) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn paint_attr(kind: &str, p: Paint) -> String {
    if p.alpha >= 1.0 {
        format!(r#"{kind}="{}""#, css(p.rgb))
    } else {
        format!(
            r#"{kind}="{}" {kind}-opacity="{}""#,
            css(p.rgb),
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

/// One shape as one SVG element, on its own line.
fn element(s: &mut String, item: &Item) {
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
        Item::Rect { rect, paint } => {
            let _ = writeln!(
                s,
                r#"<rect x="{}" y="{}" width="{}" height="{}" {}/>"#,
                num(rect.x),
                num(rect.y),
                num(rect.w.max(0.0)),
                num(rect.h.max(0.0)),
                paint_attr("fill", *paint)
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
                css(*colour),
                escape(text)
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::canvas::Rect;
    use super::*;

    #[test]
    fn svg_numbers_are_short() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(-0.001), "0");
        assert_eq!(num(2.346), "2.35");
        assert_eq!(num(f64::NAN), "0");
    }

    #[test]
    fn shapes_in_a_clip_rectangle_are_grouped_under_it() {
        let mut c = Canvas::new(20, 10, Rgb(255, 255, 255));
        c.rect(
            Rect {
                x: 0.0,
                y: 0.0,
                w: 4.0,
                h: 4.0,
            },
            Rgb(1, 2, 3),
        );
        c.clip_to(Some(Rect {
            x: 0.0,
            y: 0.0,
            w: 10.0,
            h: 10.0,
        }));
        c.disk((5.0, 5.0), 2.5, Some(Rgb(0, 0, 0).alpha(0.5)), None);
        c.text((1.0, 9.0), "a<b", 10.0, Rgb(0, 0, 0), Anchor::Start);
        let svg = c.svg();
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let group = doc.descendants().find(|n| n.has_tag_name("g")).unwrap();
        assert_eq!(group.attribute("clip-path"), Some("url(#clip0)"));
        let inside: Vec<&str> = group
            .children()
            .filter(|n| n.is_element())
            .map(|n| n.tag_name().name())
            .collect();
        assert_eq!(inside, ["circle", "text"]);
        assert!(svg.contains(r##"<rect x="0" y="0" width="4" height="4" fill="#010203"/>"##));
        assert!(svg.contains(r#"fill-opacity="0.5""#));
        assert!(svg.contains(">a&lt;b</text>"));
    }
}
