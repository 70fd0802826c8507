//! A top view (x–y) of a scene and every sphere's path to its first contact, as SVG.

use std::error::Error;

use plotters::prelude::*;
use spheresweep::FirstContact;
use spheresweep::scene::Scene;

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
    let extent = scene
        .containers
        .iter()
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
        for k in &scene.containers {
            let c = k.centre();
            let ring = circle(c.x.into(), c.y.into(), k.radius().into());
            chart.draw_series(std::iter::once(PathElement::new(
                ring,
                grey.stroke_width(2),
            )))?;
        }
        for cyl in &scene.cylinders {
            let (p, s) = (cyl.point(), cyl.axis());
            if s.z.abs() > 0.99 {
                let disk = circle(p.x.into(), p.y.into(), cyl.radius().into());
                chart.draw_series(std::iter::once(Polygon::new(disk, grey.mix(0.5).filled())))?;
            }
        }
        for plane in &scene.planes {
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
