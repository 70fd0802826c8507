//! The checkpoint file of `spheresweep run` (`checkpoint.bin`): the run's settings and scene
//! fingerprint, its counters, how far each partial output had got, and the engine's state; one
//! CRC-64 over every byte before it. Its size does not grow with the run: the outputs stay in
//! their partial files, which the checkpoint identifies by length and hash of that prefix.
//!
//! Layout (little-endian; offsets in bytes):
//!
//! | offset | bytes | section | contents |
//! |---|---|---|---|
//! | 0 | 8 | header | `SSRUN\0\0` and the format version (2) |
//! | 8 | 34 | settings | scene fingerprint u64; t_end, snapshot_every, checkpoint_every f64 (0: none); flags u8 (1 record_events, 2 geometry); a reserved u8 (0) |
//! | 42 | 72 | counters | next stop, frames, events logged u64; start kinetic energy, momentum (3), Σ m\|v\|, wall seconds f64 |
//! | 114 | 16 | trajectory | partial length, CRC-64 of those bytes u64 |
//! | 130 | 16 | events | partial length, CRC-64 of those bytes u64 |
//! | 146 | 8 + n | engine | n, then `Simulation::checkpoint`'s n bytes |
//! | 154 + n | 8 | checksum | CRC-64 of bytes 0 … 154 + n |

use std::path::Path;

use glam::DVec3;

use super::hash;
use super::options::Settings;

const MAGIC: &[u8; 7] = b"SSRUN\0\0";
const VERSION: u8 = 2;

/// How far a partial output had got: its length and the hash of those bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Progress {
    pub len: u64,
    pub hash: u64,
}

/// A run's counters: where it was and what it had written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Counters {
    /// Index of the stop the run continues with.
    pub next_stop: u64,
    pub frames: u64,
    pub logged: u64,
    /// Kinetic energy and momentum at t = 0, and Σ m|v| then (the momentum's scale).
    pub ke0: f64,
    pub p0: DVec3,
    pub momentum_scale: f64,
    /// Wall-clock seconds spent simulating so far.
    pub simulated: f64,
}

/// Everything a resume needs.
#[derive(Debug, Clone, PartialEq)]
pub struct RunCheckpoint {
    pub fingerprint: u64,
    pub settings: Settings,
    pub counters: Counters,
    pub trajectory: Progress,
    pub events: Progress,
    pub engine: Vec<u8>,
}

impl RunCheckpoint {
    pub fn to_bytes(&self) -> Vec<u8> {
        let s = &self.settings;
        let c = &self.counters;
        let mut b = Vec::with_capacity(162 + self.engine.len());
        b.extend_from_slice(MAGIC);
        b.push(VERSION);
        b.extend_from_slice(&self.fingerprint.to_le_bytes());
        for x in [
            s.t_end,
            s.snapshot_every.unwrap_or(0.0),
            s.checkpoint_every.unwrap_or(0.0),
        ] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        b.push(u8::from(s.record_events) | u8::from(s.geometry) << 1);
        b.push(0);
        for x in [c.next_stop, c.frames, c.logged] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        for x in [c.ke0, c.p0.x, c.p0.y, c.p0.z, c.momentum_scale, c.simulated] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        for p in [self.trajectory, self.events] {
            b.extend_from_slice(&p.len.to_le_bytes());
            b.extend_from_slice(&p.hash.to_le_bytes());
        }
        b.extend_from_slice(&(self.engine.len() as u64).to_le_bytes());
        b.extend_from_slice(&self.engine);
        let sum = hash::of(&b);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// Reads a checkpoint, refusing (with `path` and the reason) one that is not a checkpoint
    /// of `run`, is of another format version, or whose checksum does not match.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Self, String> {
        let refuse = |why: &str| format!("{}: {why}; it cannot be resumed from", path.display());
        let not_ours = || refuse("not a checkpoint of `spheresweep run`");
        if bytes.len() < MAGIC.len() + 1 || !bytes.starts_with(MAGIC) {
            return Err(not_ours());
        }
        if bytes[MAGIC.len()] != VERSION {
            return Err(refuse(&format!(
                "a checkpoint of format version {}; this build reads version {VERSION}",
                bytes[MAGIC.len()]
            )));
        }
        let damaged = || {
            refuse(&format!(
                "damaged: its checksum (CRC-64 over its {} bytes) does not match",
                bytes.len()
            ))
        };
        let (body, sum) = bytes.split_last_chunk::<8>().ok_or_else(damaged)?;
        if body.len() < 154 || hash::of(body) != u64::from_le_bytes(*sum) {
            return Err(damaged());
        }
        // From here the bytes are those that were written: a mismatch is a bug of the writer.
        let mut r = Reader(&body[8..]);
        let fingerprint = r.u64();
        let [t_end, snapshot_every, checkpoint_every] = [r.f64(), r.f64(), r.f64()];
        let flags = r.take(2)[0];
        let settings = Settings {
            t_end,
            snapshot_every: (snapshot_every > 0.0).then_some(snapshot_every),
            checkpoint_every: (checkpoint_every > 0.0).then_some(checkpoint_every),
            record_events: flags & 1 != 0,
            geometry: flags & 2 != 0,
        };
        let counters = Counters {
            next_stop: r.u64(),
            frames: r.u64(),
            logged: r.u64(),
            ke0: r.f64(),
            p0: DVec3::new(r.f64(), r.f64(), r.f64()),
            momentum_scale: r.f64(),
            simulated: r.f64(),
        };
        let mut progress = || Progress {
            len: r.u64(),
            hash: r.u64(),
        };
        let (trajectory, events) = (progress(), progress());
        let n = r.u64();
        if n != r.0.len() as u64 {
            return Err(damaged());
        }
        Ok(Self {
            fingerprint,
            settings,
            counters,
            trajectory,
            events,
            engine: r.0.to_vec(),
        })
    }
}

/// Reads fixed-size fields of a body whose length was checked.
struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn take(&mut self, n: usize) -> &[u8] {
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        head
    }
    fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.take(8).try_into().expect("8 bytes"))
    }
    fn f64(&mut self) -> f64 {
        f64::from_bits(self.u64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spheresweep::sim::{Simulation, World, generate};

    /// A checkpoint with a real engine section (a small gas).
    fn sample() -> RunCheckpoint {
        let mut world = World::default();
        generate::periodic_gas(&mut world, 32, 0.2, 0.5, 1.0, 1).unwrap();
        let mut sim = Simulation::new(world).unwrap();
        sim.advance_to(1.0).unwrap();
        RunCheckpoint {
            fingerprint: 0x0123_4567_89ab_cdef,
            settings: Settings {
                t_end: 40.0,
                snapshot_every: Some(2.0),
                checkpoint_every: Some(4.0),
                record_events: true,
                geometry: false,
            },
            counters: Counters {
                next_stop: 3,
                frames: 4,
                logged: 1234,
                ke0: 12.0,
                p0: DVec3::new(1e-16, -2e-16, 0.0),
                momentum_scale: 8.5,
                simulated: 0.25,
            },
            trajectory: Progress {
                len: 9876,
                hash: 42,
            },
            events: Progress { len: 5555, hash: 7 },
            engine: sim.checkpoint(),
        }
    }

    #[test]
    fn a_checkpoint_reads_back_as_written() {
        let c = sample();
        let bytes = c.to_bytes();
        assert_eq!(bytes.len(), 162 + c.engine.len());
        assert_eq!(RunCheckpoint::from_bytes(&bytes, Path::new("c.bin")), Ok(c));
    }

    /// Every single-bit flip anywhere in the file (header, settings, counters, the partial
    /// outputs' records, the engine, the checksum) is refused, saying why.
    #[test]
    fn every_bit_flip_is_refused() {
        let bytes = sample().to_bytes();
        for bit in 0..bytes.len() * 8 {
            let mut bad = bytes.clone();
            bad[bit / 8] ^= 1 << (bit % 8);
            let err = RunCheckpoint::from_bytes(&bad, Path::new("c.bin"))
                .expect_err(&format!("a flip of bit {bit} was accepted"));
            let why = if bit < 56 {
                "not a checkpoint of `spheresweep run`"
            } else if bit < 64 {
                "format version"
            } else {
                "damaged: its checksum (CRC-64 over its"
            };
            assert!(
                err.starts_with("c.bin: ") && err.contains(why),
                "bit {bit}: {err}"
            );
        }
    }

    #[test]
    fn a_cut_or_extended_checkpoint_is_refused() {
        let bytes = sample().to_bytes();
        for n in [0, 7, 8, 100, 161, bytes.len() - 1] {
            assert!(RunCheckpoint::from_bytes(&bytes[..n], Path::new("c.bin")).is_err());
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(RunCheckpoint::from_bytes(&longer, Path::new("c.bin")).is_err());
    }
}
