//! Checkpoints: a running simulation's whole dynamic state as bytes, and back. The engine is
//! deterministic and its calendar pops in exact `(time, sphere)` order, so each sphere's state
//! and pending event, the counters, the event records not yet taken and the response's state
//! are enough: a run restored from a
//! checkpoint continues bit for bit as the run that wrote it (tested in `sim::tests`).
//!
//! The format is little-endian: the magic `SSCK`, a format version, a fingerprint of the world
//! the simulation was built from, the state, and an FNV-1a checksum of everything before it. A
//! checkpoint is only restored into the same world (the fingerprint must match), and a damaged
//! one is refused (the checksum, then every index and length, are checked).

use super::model::SimError;
use super::{Simulation, World};

/// Format version; bump when the layout changes, or when the physics does (a run resumed by
/// another rule would mix two in one trajectory: 8, the TC hop only on resting contacts).
pub(crate) const VERSION: u32 = 8;
pub(crate) const MAGIC: &[u8; 4] = b"SSCK";

/// Appends values to a byte buffer.
#[derive(Debug, Default)]
pub(crate) struct Encoder(pub Vec<u8>);

impl Encoder {
    pub fn u8(&mut self, x: u8) {
        self.0.push(x);
    }
    pub fn u32(&mut self, x: u32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    pub fn f64(&mut self, x: f64) {
        self.u64(x.to_bits());
    }
    pub fn len(&mut self, n: usize) {
        self.u64(n as u64);
    }
}

/// Reads values back, failing (never panicking) on a short or malformed buffer.
#[derive(Debug)]
pub(crate) struct Decoder<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Decoder<'a> {
    pub fn new(buf: &'a [u8]) -> Self {
        Self { buf, pos: 0 }
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], SimError> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.buf.len())
            .ok_or_else(|| {
                SimError::Checkpoint(format!(
                    "truncated: {} bytes needed at byte {} of {}",
                    n,
                    self.pos,
                    self.buf.len()
                ))
            })?;
        let s = &self.buf[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    pub fn u8(&mut self) -> Result<u8, SimError> {
        Ok(self.take(1)?[0])
    }
    pub fn u32(&mut self) -> Result<u32, SimError> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().expect("4 bytes"),
        ))
    }
    pub fn u64(&mut self) -> Result<u64, SimError> {
        Ok(u64::from_le_bytes(
            self.take(8)?.try_into().expect("8 bytes"),
        ))
    }
    pub fn f64(&mut self) -> Result<f64, SimError> {
        Ok(f64::from_bits(self.u64()?))
    }
    /// A length that must equal `expected` (a per-sphere array of this world).
    pub fn len_eq(&mut self, expected: usize, what: &str) -> Result<(), SimError> {
        let n = self.u64()?;
        if n != expected as u64 {
            return Err(SimError::Checkpoint(format!(
                "{what}: {n} entries, the world has {expected}"
            )));
        }
        Ok(())
    }
    /// A length, bounded by what the rest of the buffer could hold at `min_bytes` each.
    pub fn len(&mut self, min_bytes: usize, what: &str) -> Result<usize, SimError> {
        let n = self.u64()?;
        let left = (self.buf.len() - self.pos) as u64;
        if n.saturating_mul(min_bytes.max(1) as u64) > left {
            return Err(SimError::Checkpoint(format!(
                "{what}: {n} entries cannot fit in {left} bytes"
            )));
        }
        Ok(n as usize)
    }
    /// Fails unless every byte was read.
    pub fn finish(&self) -> Result<(), SimError> {
        if self.pos == self.buf.len() {
            Ok(())
        } else {
            Err(SimError::Checkpoint(format!(
                "{} bytes left over",
                self.buf.len() - self.pos
            )))
        }
    }
}

/// FNV-1a over bytes.
pub(crate) fn checksum(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// FNV-1a over a world's description: a checkpoint restores only into the world it came from.
pub(crate) fn fingerprint(text: &str) -> u64 {
    checksum(text.as_bytes())
}

impl Simulation {
    /// The whole dynamic state as bytes: restored with [`restore`](Self::restore) into the same
    /// world, the run continues bit for bit as this one would. Take it between
    /// [`advance_with`](Self::advance_with) calls (or when one stops early); the event records
    /// not yet taken are part of it ([`take_events`](Self::take_events) gives them after a
    /// restore, unless the world restored into records none).
    ///
    /// ```
    /// # use glam::DVec3;
    /// # use spheresweep::sim::{Effects, Simulation, SphereState, World};
    /// # let ball = |x: f64, vx: f64| SphereState {
    /// #     centre: DVec3::new(x, 0.0, 0.0),
    /// #     velocity: DVec3::new(vx, 0.0, 0.0),
    /// #     radius: 0.5,
    /// #     mass: 1.0,
    /// #     material: 0,
    /// # };
    /// // Two beads 3 apart closing at 2: they meet at t = 1 and swap velocities.
    /// let world = World {
    ///     spheres: vec![ball(0.0, 1.0), ball(3.0, -1.0)],
    ///     effects: Effects { record_events: true, geometry: true, ..Effects::default() },
    ///     ..World::default()
    /// };
    /// let mut sim = Simulation::new(world.clone())?;
    /// sim.advance_to(0.5)?;
    /// let saved = sim.checkpoint();
    /// let mut again = Simulation::restore(world, &saved)?;
    /// assert_eq!(again.time(), 0.5);
    /// again.advance_to(2.0)?;
    /// sim.advance_to(2.0)?;
    /// assert_eq!(again.spheres(), sim.spheres()); // bit for bit
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn checkpoint(&self) -> Vec<u8> {
        let mut e = Encoder::default();
        e.0.extend_from_slice(MAGIC);
        e.u32(VERSION);
        e.u64(self.fingerprint);
        self.engine.save(&mut e);
        let sum = checksum(&e.0);
        e.u64(sum);
        e.0
    }

    /// The simulation of `world` at the state a [`checkpoint`](Self::checkpoint) holds.
    ///
    /// # Errors
    /// [`SimError::Checkpoint`] if the bytes are not a checkpoint of this format, belong to
    /// another world, or are damaged (every index is checked; nothing panics).
    ///
    /// ```
    /// use spheresweep::sim::{Simulation, World, generate};
    /// let mut world = World::default();
    /// generate::periodic_gas(&mut world, 256, 0.3, 0.5, 1.0, 3)?;
    /// let mut a = Simulation::new(world.clone())?;
    /// a.advance_to(1.0)?;
    /// let saved = a.checkpoint();
    /// a.advance_to(2.0)?;
    /// let mut b = Simulation::restore(world, &saved)?;
    /// b.advance_to(2.0)?;
    /// assert_eq!(a.spheres(), b.spheres());
    /// # Ok::<(), spheresweep::sim::SimError>(())
    /// ```
    pub fn restore(world: World, bytes: &[u8]) -> Result<Self, SimError> {
        let mut sim = Simulation::new(world)?;
        let Some((body, sum)) = bytes.split_last_chunk::<8>() else {
            return Err(SimError::Checkpoint(format!(
                "truncated: {} bytes",
                bytes.len()
            )));
        };
        let mut d = Decoder::new(body);
        let magic = [d.u8()?, d.u8()?, d.u8()?, d.u8()?];
        if &magic != MAGIC {
            return Err(SimError::Checkpoint("not a spheresweep checkpoint".into()));
        }
        if checksum(body) != u64::from_le_bytes(*sum) {
            return Err(SimError::Checkpoint(
                "damaged: the checksum does not match".into(),
            ));
        }
        let version = d.u32()?;
        if version != VERSION {
            return Err(SimError::Checkpoint(format!(
                "format version {version}; this build reads version {}",
                VERSION
            )));
        }
        if d.u64()? != sim.fingerprint {
            return Err(SimError::Checkpoint(
                "written for another world (shapes, boundary, effects, masses or materials differ)"
                    .into(),
            ));
        }
        let (masses, materials) = (sim.masses.clone(), sim.materials.clone());
        sim.engine.load(&mut d, &masses, &materials)?;
        d.finish()?;
        Ok(sim)
    }
}

/// What a checkpoint must match: everything in the world but the spheres' positions and
/// velocities (which the checkpoint carries) and what is recorded (`record_events`, `geometry`:
/// they change what is written, not the dynamics).
pub(super) fn world_fingerprint(w: &World) -> u64 {
    let per_sphere: Vec<(u64, u64, u16)> = w
        .spheres
        .iter()
        .map(|s| (s.radius.to_bits(), s.mass.to_bits(), s.material))
        .collect();
    // Gravity joins the text only when there is some, so that a world without it keeps the
    // fingerprint it had before gravity existed (and its checkpoints stay readable).
    let gravity = w.effects.gravity;
    let gravity = if gravity == glam::DVec3::ZERO {
        String::new()
    } else {
        format!("gravity {gravity:?}")
    };
    let effects = effects_text(&w.effects);
    fingerprint(&format!(
        "{:?}{:?}{:?}{:?}{effects}{gravity}",
        per_sphere, w.statics, w.boundary, w.materials,
    ))
}

/// The effects that change the dynamics, as `Effects`' derived `Debug` wrote them before it
/// had `gravity` (with nothing recorded).
fn effects_text(fx: &super::Effects) -> String {
    format!(
        "Effects {{ response: {:?}, pairs: {:?}, tc: {:?}, geometry: false, record_events: false }}",
        fx.response, fx.pairs, fx.tc
    )
}

#[cfg(test)]
mod tests {
    /// The effects' text is what the derived `Debug` of `Effects` wrote before `gravity`
    /// existed, so that worlds without gravity keep their fingerprints.
    #[test]
    fn the_fingerprint_text_of_effects_is_the_one_before_gravity() {
        #[derive(Debug)]
        #[allow(dead_code)]
        struct Effects {
            response: super::super::Response,
            pairs: Vec<super::super::MaterialPair>,
            tc: f64,
            geometry: bool,
            record_events: bool,
        }
        let fx = super::super::Effects {
            response: super::super::Response::Inelastic { restitution: 0.5 },
            pairs: vec![super::super::MaterialPair {
                a: 0,
                b: 1,
                response: super::super::Response::Sticky,
            }],
            tc: 1e-3,
            ..Default::default()
        };
        let before = Effects {
            response: fx.response,
            pairs: fx.pairs.clone(),
            tc: fx.tc,
            geometry: false,
            record_events: false,
        };
        assert_eq!(super::effects_text(&fx), format!("{before:?}"));
    }
}
