//! `events.csv`: a header, then one row per collision (docs/scene-format.md).

use std::io::Write;

use spheresweep::sim::EventRecord;

/// The header line.
pub fn header(geometry: bool) -> String {
    let mut h = String::from("time,sphere,other_kind,other_index,approach,restitution,energy_lost");
    if geometry {
        h.push_str(",px,py,pz,nx,ny,nz");
    }
    h
}

/// One row per event; floats read back bit for bit.
pub fn write(w: &mut impl Write, events: &[EventRecord], geometry: bool) -> std::io::Result<()> {
    for e in events {
        write!(
            w,
            "{:?},{},{},{},{:?},{:?},{:?}",
            e.time, e.sphere, e.other.kind, e.other.index, e.approach, e.restitution, e.energy_lost
        )?;
        if geometry {
            match e.geometry {
                Some(g) => write!(
                    w,
                    ",{:?},{:?},{:?},{:?},{:?},{:?}",
                    g.point.x, g.point.y, g.point.z, g.normal.x, g.normal.y, g.normal.z
                )?,
                None => write!(w, ",,,,,,")?,
            }
        }
        writeln!(w)?;
    }
    Ok(())
}
