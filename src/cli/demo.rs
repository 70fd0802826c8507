//! `spheresweep demo`: the built-in scene, queried for first contacts, as a table.

use std::error::Error;
use std::io::Write;

use spheresweep::reference::scene::{Body, first_contacts};
use spheresweep::scene::{Scene, demo};

/// Options of `spheresweep demo`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// End of the time window [0, t_max].
    #[arg(long, default_value_t = 10.0)]
    t_max: f64,
}

pub fn run(args: &Args) -> Result<(), Box<dyn Error>> {
    if args.t_max.is_nan() || args.t_max < 0.0 {
        return Err(format!("--t-max must be zero or more, got {}", args.t_max).into());
    }
    let scene = demo();
    let mut out = std::io::stdout().lock();
    writeln!(out, "{}", describe(&scene))?;
    writeln!(
        out,
        "First contacts in [0, {}] (scalar f64 reference):\n",
        args.t_max
    )?;
    writeln!(
        out,
        "{:>6}  {:<13} {:>9}  {:>26}  {:>23}",
        "sphere", "hits", "time", "contact point", "normal on sphere"
    )?;
    for (i, contact) in first_contacts(&scene, args.t_max).iter().enumerate() {
        match contact {
            None => writeln!(out, "{i:>6}  {:<13} {:>9}", "nothing", "-")?,
            Some((body, c)) => {
                let p = c.point;
                let n = c.normal;
                writeln!(
                    out,
                    "{i:>6}  {:<13} {:>9.4}  ({:>7.3}, {:>7.3}, {:>7.3})  ({:>6.3}, {:>6.3}, {:>6.3})",
                    name(*body),
                    c.time,
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
    Ok(())
}

fn name(body: Body) -> String {
    match body {
        Body::Sphere(j) => format!("sphere {j}"),
        Body::Plane(j) => format!("plane {j}"),
        Body::Cylinder(j) => format!("cylinder {j}"),
        Body::Container(j) => format!("container {j}"),
    }
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
