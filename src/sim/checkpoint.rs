//! Checkpoints: a running simulation's whole dynamic state as bytes, and back. The engine is
//! deterministic and its calendar pops in exact `(time, sphere)` order, so each sphere's state
//! and pending event, the counters and the response's state are enough: a run restored from a
//! checkpoint continues bit for bit as the run that wrote it (tested in `sim::tests`).
//!
//! The format is little-endian: the magic `SSCK`, a format version, a fingerprint of the world
//! the simulation was built from, the state, and an FNV-1a checksum of everything before it. A
//! checkpoint is only restored into the same world (the fingerprint must match), and a damaged
//! one is refused (the checksum, then every index and length, are checked).

use super::model::SimError;

/// Format version; bump when the layout changes.
pub(crate) const VERSION: u32 = 2;
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
