//! The one hash of `run`: CRC-64/XZ (the `crc` crate, slice-by-16 tables). It detects every
//! change of up to 64 consecutive bits (so every single-bit flip) and misses other damage with
//! probability 2⁻⁶⁴. It protects checkpoints, identifies the partial outputs a checkpoint
//! continues, and fingerprints a scene's world.

use crc::{CRC_64_XZ, Crc, Digest, Table};
use spheresweep::sim::World;

static CRC: Crc<u64, Table<16>> = Crc::<u64, Table<16>>::new(&CRC_64_XZ);

/// A hash being computed over bytes fed in pieces.
pub type Hasher = Digest<'static, u64, Table<16>>;

/// A new hash over nothing yet.
pub fn hasher() -> Hasher {
    CRC.digest()
}

/// The hash of `bytes`.
pub fn of(bytes: &[u8]) -> u64 {
    CRC.checksum(bytes)
}

/// Identifies a scene's world: every sphere's start (centre, velocity, radius, mass, material,
/// bit for bit), the shapes, the boundary, the materials and the effects. Two scene files that
/// build the same world have the same fingerprint.
pub fn world(w: &World) -> u64 {
    let mut h = hasher();
    h.update(&(w.spheres.len() as u64).to_le_bytes());
    for s in &w.spheres {
        let (c, v) = (s.centre, s.velocity);
        for x in [c.x, c.y, c.z, v.x, v.y, v.z, s.radius, s.mass] {
            h.update(&x.to_bits().to_le_bytes());
        }
        h.update(&s.material.to_le_bytes());
    }
    // Debug prints every float so that it reads back bit for bit.
    let rest = format!(
        "{:?}{:?}{:?}{:?}",
        w.statics, w.boundary, w.materials, w.effects
    );
    h.update(rest.as_bytes());
    h.finalize()
}

/// A fingerprint as it is written in `summary.json` and named in messages: 16 hexadecimal digits.
pub fn text(fingerprint: u64) -> String {
    format!("{fingerprint:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use spheresweep::sim::generate;

    #[test]
    fn the_fingerprint_changes_with_the_start_and_the_effects() {
        let gas = |seed| {
            let mut w = World::default();
            generate::periodic_gas(&mut w, 64, 0.2, 0.5, 1.0, seed).unwrap();
            w
        };
        let a = gas(1);
        assert_eq!(world(&a), world(&gas(1)));
        assert_ne!(world(&a), world(&gas(2)));
        let mut b = a.clone();
        b.spheres[63].velocity.z = f64::from_bits(b.spheres[63].velocity.z.to_bits() ^ 1);
        assert_ne!(world(&a), world(&b));
        let mut c = a.clone();
        c.effects.record_events = true;
        assert_ne!(world(&a), world(&c));
    }

    #[test]
    fn a_hash_in_pieces_is_the_hash_of_the_whole() {
        let mut h = hasher();
        h.update(b"spheres");
        h.update(b"weep");
        assert_eq!(h.finalize(), of(b"spheresweep"));
    }
}
