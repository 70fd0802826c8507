//! `spheresweep demo`: the built-in scene, queried for first contacts, as a table.

use std::error::Error;
use std::io::Write;

use spheresweep::query::first_contacts;
use spheresweep::scene::{Scene, demo};
use spheresweep::{Accuracy, QueryOptions};

/// Options of `spheresweep demo`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// End of the time window [0, t_max] (zero or more; inf for no end).
    #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
    t_max: f32,
    /// Accuracy mode of the kernels: textbook, stable or double.
    #[arg(long, default_value_t = Accuracy::Stable)]
    accuracy: Accuracy,
    /// Also draw the scene from above, with every sphere's path to its first contact, as SVG.
    #[arg(long, value_name = "FILE")]
    svg: Option<std::path::PathBuf>,
}

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    let options = QueryOptions::new(args.t_max, args.accuracy)?.with_geometry(true);
    if let Some(path) = &args.svg {
        // Before any output: a bad path fails now, not after the table.
        crate::output::check_writable(path)?;
    }
    let scene = demo();
    let mut out = std::io::stdout().lock();
    writeln!(out, "{}", describe(&scene))?;
    writeln!(
        out,
        "First contacts in [0, {}] ({} mode, 8-wide kernels; point and normal from the f64 reference):\n",
        args.t_max, args.accuracy
    )?;
    writeln!(
        out,
        "{:>6}  {:<13} {:>9}  {:>26}  {:>23}",
        "sphere", "hits", "time", "contact point", "normal on sphere"
    )?;
    let contacts = first_contacts(&scene, options);
    for (i, contact) in contacts.iter().enumerate() {
        match contact {
            None => writeln!(out, "{i:>6}  {:<13} {:>9}", "nothing", "-")?,
            Some(hit) => {
                let c = hit.geometry.expect("geometry was asked for");
                // `+ 0.0` turns IEEE −0.0 into 0.0 for display.
                let (p, n) = (c.point + 0.0, c.normal + 0.0);
                writeln!(
                    out,
                    "{i:>6}  {:<13} {:>9.4}  ({:>7.3}, {:>7.3}, {:>7.3})  ({:>6.3}, {:>6.3}, {:>6.3})",
                    hit.body.to_string(),
                    hit.time,
                    p.x,
                    p.y,
                    p.z,
                    n.x,
                    n.y,
                    n.z
                )?;
            }
        }
    }
    if let Some(path) = &args.svg {
        let picture = super::picture::top_view(&scene, &contacts, args.t_max)?;
        crate::output::write_atomic(path, picture.as_bytes())?;
        writeln!(out, "\nwrote {}", path.display())?;
    }
    Ok(())
}

fn describe(s: &Scene) -> String {
    format!(
        "Built-in scene: {} spheres, {} plane(s), {} cylinder(s), {} container(s).",
        s.spheres.len(),
        s.planes.len(),
        s.cylinders.len(),
        s.containers.len()
    )
}
