//! Extended XYZ snapshots of a simulation, as OVITO and ASE read them.
//!
//! One frame is a count line, a comment line of `key=value` pairs and one line per sphere:
//!
//! ```text
//! 2
//! Lattice="10.0 0 0 0 10.0 0 0 0 10.0" Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:material:I:1 Time=0.5 pbc="T T T"
//! X 1.0 2.0 3.0 0.5 0.0 -0.25 0.5 0
//! X 4.0 5.0 6.0 -0.5 0.0 0.25 0.5 1
//! ```
//!
//! Open scenes omit `Lattice` and write `pbc="F F F"`. Every float is written as the shortest
//! decimal that reads back to the same `f64` (Rust's `{:?}`, exponent form for very large
//! and very small magnitudes), so a written frame reads back bit for bit. The species is `X`
//! (ASE's dummy element) for every sphere; the `material` column holds the material index.
//! Masses are not written: [`read_frames`] gives every sphere mass 1 unless the file has a
//! `mass:R:1` column.
//!
//! ```
//! use glam::DVec3;
//! use spheresweep::io::xyz::{read_frames, write_frame};
//! use spheresweep::sim::SphereState;
//! let spheres = [SphereState {
//!     centre: DVec3::new(0.1, 0.2, 0.3),
//!     velocity: DVec3::new(1.0, -2.0, 1e-300),
//!     radius: 0.5,
//!     mass: 1.0,
//!     material: 2,
//! }];
//! let mut text = Vec::new();
//! write_frame(&mut text, &spheres, 0.25, Some(DVec3::splat(4.0)))?;
//! let frames = read_frames(std::str::from_utf8(&text).unwrap()).unwrap();
//! assert_eq!(frames[0].spheres, spheres);
//! assert_eq!(frames[0].periodic_box, Some(DVec3::splat(4.0)));
//! # Ok::<(), std::io::Error>(())
//! ```

use std::fmt;
use std::io::{self, Write};

use glam::DVec3;

use crate::sim::SphereState;

/// The `Properties` value this module writes.
pub const PROPERTIES: &str = "species:S:1:pos:R:3:velo:R:3:radius:R:1:material:I:1";

/// One snapshot read back from a file.
///
/// ```
/// use spheresweep::io::xyz::read_frames;
/// let text = "1\nProperties=species:S:1:pos:R:3:radius:R:1 Time=2.5\nX 1 2 3 0.5\n";
/// let frame = &read_frames(text)?[0];
/// assert_eq!((frame.time, frame.spheres[0].centre.y, frame.periodic_box), (2.5, 2.0, None));
/// # Ok::<(), spheresweep::io::xyz::XyzError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// The frame's `Time` (0 when the comment line has none).
    pub time: f64,
    /// The spheres, in file order.
    pub spheres: Vec<SphereState>,
    /// The periodic box lengths (from `Lattice`, when `pbc` is true on every axis).
    pub periodic_box: Option<DVec3>,
}

/// A malformed file: the line (counting from 1) and what is wrong there.
///
/// ```
/// use spheresweep::io::xyz::read_frames;
/// let err = read_frames("2\nProperties=species:S:1:pos:R:3:radius:R:1\nX 1 2 3 0.5\n").unwrap_err();
/// assert_eq!(err.line, 4);
/// assert_eq!(err.to_string(), "line 4: the frame ends after 1 of its 2 spheres");
/// ```
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {problem}")]
pub struct XyzError {
    /// The line at fault, counting from 1.
    pub line: usize,
    /// What is wrong with it.
    pub problem: String,
}

/// A float that reads back to the same bits.
struct Exact(f64);

impl fmt::Display for Exact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.0)
    }
}

/// Writes one frame: the count, the comment line (`Lattice` and `pbc="T T T"` when
/// `periodic_box` is given, `pbc="F F F"` otherwise; `Time`), then one line per sphere.
///
/// ```
/// use glam::DVec3;
/// use spheresweep::{io::xyz::write_frame, sim::SphereState};
/// let centre = DVec3::new(1.0, 2.0, 3.0);
/// let s = SphereState { centre, velocity: DVec3::ZERO, radius: 0.5, mass: 1.0, material: 1 };
/// let mut out = Vec::new();
/// write_frame(&mut out, &[s], 0.5, None)?;
/// let text = String::from_utf8(out).unwrap();
/// let lines: Vec<&str> = text.lines().collect();
/// assert_eq!(lines[0], "1");
/// assert!(lines[1].ends_with(r#"Time=0.5 pbc="F F F""#));
/// assert_eq!(lines[2], "X 1.0 2.0 3.0 0.0 0.0 0.0 0.5 1");
/// # Ok::<(), std::io::Error>(())
/// ```
pub fn write_frame<W: Write>(
    mut w: W,
    spheres: &[SphereState],
    time: f64,
    periodic_box: Option<DVec3>,
) -> io::Result<()> {
    writeln!(w, "{}", spheres.len())?;
    if let Some(b) = periodic_box {
        write!(
            w,
            "Lattice=\"{} 0 0 0 {} 0 0 0 {}\" ",
            Exact(b.x),
            Exact(b.y),
            Exact(b.z)
        )?;
    }
    let pbc = if periodic_box.is_some() {
        "T T T"
    } else {
        "F F F"
    };
    writeln!(
        w,
        "Properties={PROPERTIES} Time={} pbc=\"{pbc}\"",
        Exact(time)
    )?;
    for s in spheres {
        let (r, v) = (s.centre, s.velocity);
        writeln!(
            w,
            "X {} {} {} {} {} {} {} {}",
            Exact(r.x),
            Exact(r.y),
            Exact(r.z),
            Exact(v.x),
            Exact(v.y),
            Exact(v.z),
            Exact(s.radius),
            s.material
        )?;
    }
    Ok(())
}

/// Where a property's columns start, for the columns this reader uses.
#[derive(Debug, Default)]
struct Layout {
    width: usize,
    pos: Option<usize>,
    velo: Option<usize>,
    radius: Option<usize>,
    material: Option<usize>,
    mass: Option<usize>,
}

/// Reads every frame of an extended XYZ text: the frames [`write_frame`] writes, and more
/// generally any frame whose `Properties` has `pos:R:3` and `radius:R:1` (`velo:R:3`,
/// `material:I:1` and `mass:R:1` are read when present; other columns are skipped). Blank
/// lines between frames are allowed. A position or velocity that is not finite, a radius
/// that is negative or not finite, a mass that is not positive and finite are refused. Errors
/// name the line, and for a sphere its frame and index in the frame (both from 0).
///
/// ```
/// use spheresweep::io::xyz::read_frames;
/// // Another tool's file: an extra column (id), a mass column, two frames.
/// let comment = "Properties=species:S:1:id:I:1:pos:R:3:radius:R:1:mass:R:1 Time=1";
/// let frame = format!("1\n{comment}\nX 7 0 0 1 0.5 3.0\n");
/// let frames = read_frames(&format!("{frame}\n{frame}"))?;
/// assert_eq!(frames.len(), 2);
/// assert_eq!((frames[1].spheres[0].centre.z, frames[1].spheres[0].mass), (1.0, 3.0));
/// # Ok::<(), spheresweep::io::xyz::XyzError>(())
/// ```
pub fn read_frames(text: &str) -> Result<Vec<Frame>, XyzError> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l)).peekable();
    let mut frames = Vec::new();
    loop {
        // Skip blank lines between frames.
        while lines.peek().is_some_and(|(_, l)| l.trim().is_empty()) {
            lines.next();
        }
        let Some((line, count)) = lines.next() else {
            break;
        };
        let bad = |line, problem: String| Err(XyzError { line, problem });
        let n: usize = match count.trim().parse() {
            Ok(n) => n,
            Err(_) => {
                return bad(
                    line,
                    format!("expected the number of spheres, found {:?}", count.trim()),
                );
            }
        };
        let Some((cline, comment)) = lines.next() else {
            return bad(line + 1, "the comment line is missing".into());
        };
        let (time, periodic_box, layout) = comment_line(comment).map_err(|problem| XyzError {
            line: cline,
            problem,
        })?;
        let mut spheres = Vec::with_capacity(n.min(1 << 20));
        for k in 0..n {
            let Some((sline, body)) = lines.next() else {
                return bad(
                    cline + k + 1,
                    format!("the frame ends after {k} of its {n} spheres"),
                );
            };
            spheres.push(sphere_line(body, &layout).map_err(|problem| XyzError {
                line: sline,
                problem: format!("frame {}, sphere {k}: {problem}", frames.len()),
            })?);
        }
        frames.push(Frame {
            time,
            spheres,
            periodic_box,
        });
    }
    Ok(frames)
}

/// Splits `key=value` pairs, values optionally in double quotes.
fn pairs(comment: &str) -> Result<Vec<(&str, &str)>, String> {
    let mut out = Vec::new();
    let mut rest = comment.trim_start();
    while !rest.is_empty() {
        let Some(eq) = rest.find('=') else {
            return Err(format!("expected key=value, found {rest:?}"));
        };
        let key = rest[..eq].trim();
        if key.is_empty() || key.contains(char::is_whitespace) {
            return Err(format!("expected key=value, found {:?}", &rest[..eq]));
        }
        let after = rest[eq + 1..].trim_start();
        let (value, next) = if let Some(quoted) = after.strip_prefix('"') {
            match quoted.find('"') {
                Some(end) => (&quoted[..end], &quoted[end + 1..]),
                None => return Err(format!("{key}: the quoted value is not closed")),
            }
        } else {
            let end = after.find(char::is_whitespace).unwrap_or(after.len());
            (&after[..end], &after[end..])
        };
        out.push((key, value));
        rest = next.trim_start();
    }
    Ok(out)
}

fn number(key: &str, s: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .map_err(|_| format!("{key}: {s:?} is not a number"))
}

/// Time, periodic box and column layout from the comment line.
fn comment_line(comment: &str) -> Result<(f64, Option<DVec3>, Layout), String> {
    let mut time = 0.0;
    let mut lattice = None;
    let mut pbc = [false; 3];
    let mut layout = None;
    for (key, value) in pairs(comment)? {
        match key.to_ascii_lowercase().as_str() {
            "time" => time = number(key, value)?,
            "lattice" => {
                let v = value
                    .split_whitespace()
                    .map(|s| number(key, s))
                    .collect::<Result<Vec<_>, _>>()?;
                if v.len() != 9 {
                    return Err(format!("Lattice has {} numbers, not 9", v.len()));
                }
                if [1, 2, 3, 5, 6, 7].iter().any(|&k| v[k] != 0.0) {
                    return Err("Lattice is not diagonal (only rectangular boxes are read)".into());
                }
                lattice = Some(DVec3::new(v[0], v[4], v[8]));
            }
            "pbc" => {
                let flags: Vec<&str> = value.split_whitespace().collect();
                if flags.len() != 3 {
                    return Err(format!("pbc has {} flags, not 3", flags.len()));
                }
                for (k, f) in flags.iter().enumerate() {
                    pbc[k] = match *f {
                        "T" | "t" | "True" | "true" => true,
                        "F" | "f" | "False" | "false" => false,
                        _ => return Err(format!("pbc flag {f:?} is neither T nor F")),
                    };
                }
            }
            "properties" => layout = Some(properties(value)?),
            _ => {}
        }
    }
    let layout = layout.ok_or("the comment line has no Properties")?;
    let periodic_box = match (lattice, pbc) {
        (Some(b), [true, true, true]) => Some(b),
        (None, [true, true, true]) => return Err("pbc=\"T T T\" without a Lattice".into()),
        (_, [false, false, false]) => None,
        _ => return Err("pbc must be periodic on every axis or on none".into()),
    };
    Ok((time, periodic_box, layout))
}

/// Column offsets of the properties this reader uses.
fn properties(spec: &str) -> Result<Layout, String> {
    let parts: Vec<&str> = spec.split(':').collect();
    if !parts.len().is_multiple_of(3) {
        return Err(format!(
            "Properties {spec:?} is not a list of name:type:count"
        ));
    }
    let mut layout = Layout::default();
    for p in parts.chunks(3) {
        let (name, kind) = (p[0], p[1]);
        let count: usize = p[2]
            .parse()
            .ok()
            .filter(|&c| c > 0)
            .ok_or_else(|| format!("Properties: {name} has count {:?}", p[2]))?;
        if !matches!(kind, "S" | "R" | "I" | "L") {
            return Err(format!("Properties: {name} has unknown type {kind:?}"));
        }
        let want = |k: &str, c: usize| {
            if kind == k && count == c {
                Ok(Some(layout.width))
            } else {
                Err(format!("Properties: {name} must be {name}:{k}:{c}"))
            }
        };
        match name {
            "pos" => layout.pos = want("R", 3)?,
            "velo" => layout.velo = want("R", 3)?,
            "radius" => layout.radius = want("R", 1)?,
            "material" => layout.material = want("I", 1)?,
            "mass" => layout.mass = want("R", 1)?,
            _ => {}
        }
        layout.width = layout
            .width
            .checked_add(count)
            .ok_or_else(|| format!("Properties: {name}'s count {count} makes too many columns"))?;
    }
    if layout.pos.is_none() || layout.radius.is_none() {
        return Err("Properties must include pos:R:3 and radius:R:1".into());
    }
    Ok(layout)
}

fn sphere_line(body: &str, layout: &Layout) -> Result<SphereState, String> {
    let fields: Vec<&str> = body.split_whitespace().collect();
    if fields.len() != layout.width {
        return Err(format!(
            "expected {} columns, found {}",
            layout.width,
            fields.len()
        ));
    }
    let real = |k: usize, what: &str| {
        fields[k]
            .parse::<f64>()
            .map_err(|_| format!("{what}: {:?} is not a number", fields[k]))
    };
    let vec3 = |at: Option<usize>, what: &str| -> Result<DVec3, String> {
        match at {
            Some(k) => Ok(DVec3::new(
                real(k, what)?,
                real(k + 1, what)?,
                real(k + 2, what)?,
            )),
            None => Ok(DVec3::ZERO),
        }
    };
    let centre = vec3(layout.pos, "pos")?;
    let velocity = vec3(layout.velo, "velo")?;
    let radius = layout.radius.map_or(Ok(0.0), |k| real(k, "radius"))?;
    let mass = layout.mass.map_or(Ok(1.0), |k| real(k, "mass"))?;
    let show = |v: DVec3| format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z);
    if !centre.is_finite() {
        return Err(format!("pos = {} is not finite", show(centre)));
    }
    if !velocity.is_finite() {
        return Err(format!("velo = {} is not finite", show(velocity)));
    }
    if !(radius.is_finite() && radius >= 0.0) {
        return Err(format!("radius = {radius:?} must be finite and at least 0"));
    }
    if !(mass.is_finite() && mass > 0.0) {
        return Err(format!("mass = {mass:?} must be finite and greater than 0"));
    }
    let material = match layout.material {
        Some(k) => fields[k]
            .parse::<u16>()
            .map_err(|_| format!("material: {:?} is not an integer in 0..=65535", fields[k]))?,
        None => 0,
    };
    Ok(SphereState {
        centre,
        velocity,
        radius,
        mass,
        material,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn awkward(rng: &mut Rng) -> f64 {
        // Every exponent range, both signs, and the odd special value.
        match (rng.unit() * 8.0) as u32 {
            0 => -0.0,
            1 => f64::MIN_POSITIVE * rng.unit(),
            2 => f64::MAX * rng.sign() * rng.unit(),
            3 => rng.range(-1.0, 1.0) * 1e-200,
            4 => rng.range(-1.0, 1.0) * 1e200,
            5 => 0.1 * (rng.unit() * 10.0).floor(),
            _ => rng.range(-1e3, 1e3),
        }
    }

    fn random_spheres(n: usize, seed: u64) -> Vec<SphereState> {
        let mut rng = Rng::new(seed);
        (0..n)
            .map(|k| SphereState {
                centre: DVec3::new(awkward(&mut rng), awkward(&mut rng), awkward(&mut rng)),
                velocity: DVec3::new(awkward(&mut rng), awkward(&mut rng), awkward(&mut rng)),
                radius: awkward(&mut rng).abs() + f64::MIN_POSITIVE,
                mass: 1.0,
                material: (k % 3) as u16 * 21845,
            })
            .collect()
    }

    fn bits(s: &[SphereState]) -> Vec<[u64; 7]> {
        s.iter()
            .map(|s| {
                [
                    s.centre.x.to_bits(),
                    s.centre.y.to_bits(),
                    s.centre.z.to_bits(),
                    s.velocity.x.to_bits(),
                    s.velocity.y.to_bits(),
                    s.velocity.z.to_bits(),
                    s.radius.to_bits(),
                ]
            })
            .collect()
    }

    #[test]
    fn frames_round_trip_bit_for_bit() {
        let a = random_spheres(500, 1);
        let b = random_spheres(3, 2);
        let boxed = DVec3::new(1.0 / 3.0, 1e-30, 7e25);
        let mut text = Vec::new();
        write_frame(&mut text, &a, 0.1 + 0.2, Some(boxed)).unwrap();
        write_frame(&mut text, &b, -0.0, None).unwrap();
        write_frame(&mut text, &[], 5e-324, None).unwrap();
        let frames = read_frames(std::str::from_utf8(&text).unwrap()).unwrap();
        assert_eq!(frames.len(), 3);
        assert_eq!(frames[0].time.to_bits(), (0.1f64 + 0.2).to_bits());
        assert_eq!(frames[1].time.to_bits(), (-0.0f64).to_bits());
        assert_eq!(frames[2].time.to_bits(), 5e-324f64.to_bits());
        assert_eq!(frames[0].periodic_box, Some(boxed));
        assert_eq!(frames[1].periodic_box, None);
        assert_eq!(bits(&frames[0].spheres), bits(&a));
        assert_eq!(bits(&frames[1].spheres), bits(&b));
        assert!(frames[2].spheres.is_empty());
        for (got, want) in frames[0].spheres.iter().zip(&a) {
            assert_eq!((got.material, got.mass), (want.material, 1.0));
        }
    }

    #[test]
    fn the_comment_line_is_what_ovito_and_ase_expect() {
        let s = SphereState {
            centre: DVec3::new(1.0, 2.0, 3.0),
            velocity: DVec3::ZERO,
            radius: 0.5,
            mass: 1.0,
            material: 1,
        };
        let mut text = Vec::new();
        write_frame(&mut text, &[s], 2.5, Some(DVec3::splat(10.0))).unwrap();
        assert_eq!(
            String::from_utf8(text).unwrap(),
            "1\nLattice=\"10.0 0 0 0 10.0 0 0 0 10.0\" \
             Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:material:I:1 Time=2.5 pbc=\"T T T\"\n\
             X 1.0 2.0 3.0 0.0 0.0 0.0 0.5 1\n"
        );
        let mut text = Vec::new();
        write_frame(&mut text, &[s], 0.0, None).unwrap();
        assert!(
            String::from_utf8(text)
                .unwrap()
                .lines()
                .nth(1)
                .is_some_and(|l| !l.contains("Lattice") && l.ends_with("pbc=\"F F F\""))
        );
    }

    #[test]
    fn foreign_columns_are_skipped_and_mass_is_read() {
        let text = "2\nProperties=species:S:1:pos:R:3:id:I:1:radius:R:1:mass:R:1 pbc=\"F F F\" \
                    comment=\"a b\"\nC 1 2 3 7 0.5 2.0\nC 4 5 6 8 0.25 3\n";
        let f = &read_frames(text).unwrap()[0];
        assert_eq!(f.time, 0.0);
        assert_eq!(f.spheres[1].centre, DVec3::new(4.0, 5.0, 6.0));
        assert_eq!((f.spheres[1].radius, f.spheres[1].mass), (0.25, 3.0));
        assert_eq!(f.spheres[0].velocity, DVec3::ZERO);
    }

    #[test]
    fn malformed_input_names_the_line() {
        let good = "1\nProperties=species:S:1:pos:R:3:velo:R:3:radius:R:1:material:I:1 Time=0 pbc=\"F F F\"\nX 0 0 0 0 0 0 1 0\n";
        assert!(read_frames(good).is_ok());
        let cases: &[(&str, usize, &str)] = &[
            ("x\n", 1, "number of spheres"),
            ("1\n", 2, "comment line is missing"),
            ("1\npbc=\"F F F\"\n", 2, "no Properties"),
            (
                "2\nProperties=pos:R:3:radius:R:1\n0 0 0 1\n",
                4,
                "ends after 1 of its 2",
            ),
            (
                "1\nProperties=pos:R:3:radius:R:1\n0 0 zero 1\n",
                3,
                "pos: \"zero\" is not a number",
            ),
            (
                "1\nProperties=pos:R:3:radius:R:1\n0 0 0\n",
                3,
                "expected 4 columns",
            ),
            (
                "1\nProperties=pos:R:3:radius:R:1:material:I:1\n0 0 0 1 -1\n",
                3,
                "material",
            ),
            ("1\nProperties=pos:R:2:radius:R:1\n0 0 1\n", 2, "pos:R:3"),
            (
                "1\nProperties=id:I:18446744073709551615:pos:R:3:radius:R:1\n0 0 0 1\n",
                2,
                "Properties: pos's count 3 makes too many columns",
            ),
            (
                "1\nProperties=pos:R:3:radius:R:1\n0 0 0 1\n\n2\nProperties=pos:R:3:radius:R:1\n0 0 0 1\n0 nan 0 1\n",
                8,
                "frame 1, sphere 1: pos = [0.0, NaN, 0.0] is not finite",
            ),
            (
                "1\nProperties=pos:R:3:radius:R:1\n0 0 0 -0.5\n",
                3,
                "frame 0, sphere 0: radius = -0.5 must be finite and at least 0",
            ),
            (
                "1\nProperties=pos:R:3:velo:R:3:radius:R:1\n0 0 0 inf 0 0 1\n",
                3,
                "velo = [inf, 0.0, 0.0] is not finite",
            ),
            (
                "1\nProperties=pos:R:3:radius:R:1:mass:R:1\n0 0 0 1 0\n",
                3,
                "mass = 0.0 must be finite and greater than 0",
            ),
            (
                "1\nProperties=pos:R:3:radius:R:1 pbc=\"T T T\"\n",
                2,
                "without a Lattice",
            ),
            (
                "1\nLattice=\"1 0 0 0 1 0 0 1 1\" Properties=pos:R:3:radius:R:1 pbc=\"T T T\"\n",
                2,
                "not diagonal",
            ),
            (
                "1\nTime=\"1 Properties=pos:R:3:radius:R:1\n",
                2,
                "not closed",
            ),
            (
                &format!("{good}\n1\nProperties=pos:R:3:radius:R:1 Time=soon\n"),
                6,
                "Time: \"soon\" is not a number",
            ),
        ];
        for (text, line, what) in cases {
            let err = read_frames(text).unwrap_err();
            assert_eq!(err.line, *line, "{text:?}: {err}");
            assert!(err.to_string().contains(what), "{text:?}: {err}");
            assert!(err.to_string().starts_with(&format!("line {line}: ")));
        }
    }
}
