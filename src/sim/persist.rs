//! One description of the state a checkpoint holds, read in both directions: [`Persist`] writes
//! a value with the [`Encoder`] and reads it back with the [`Decoder`], and
//! [`persist_fields!`] implements it for a struct from one list of its fields, so that `save`
//! and `load` cannot disagree and a field cannot be forgotten (the list must name every field:
//! the macro destructures the struct without `..`, and the compiler refuses a field left out).

use glam::DVec3;

use super::checkpoint::{Decoder, Encoder};
use super::model::SimError;
use crate::contact::Body;
use crate::shape::ShapeKind;

/// The largest counter a checkpoint may hold (2⁶⁰: 36 years at 10⁹ events a second); a larger
/// one is damage, refused at load rather than overflowing later.
pub(crate) const COUNT_LIMIT: u64 = 1 << 60;

/// A value a checkpoint holds: written by `save`, read back by `load` in the same layout.
/// `load` checks only what the value alone can tell (a counter beyond any run, a kind that
/// does not exist); what depends on the world is checked by the one who loads it.
pub(crate) trait Persist {
    /// Appends the value.
    fn save(&self, e: &mut Encoder);
    /// Replaces the value with the next one in `d`.
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError>;
}

impl Persist for u8 {
    fn save(&self, e: &mut Encoder) {
        e.u8(*self);
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        *self = d.u8()?;
        Ok(())
    }
}

impl Persist for u32 {
    fn save(&self, e: &mut Encoder) {
        e.u32(*self);
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        *self = d.u32()?;
        Ok(())
    }
}

/// Cell coordinates, as their `u32` bits (the grid checks the range).
impl Persist for i32 {
    fn save(&self, e: &mut Encoder) {
        e.u32(*self as u32);
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        *self = d.u32()? as i32;
        Ok(())
    }
}

/// Every `u64` in the state is a count that grows by one an event: a value no run can reach
/// is damage (found by fuzzing: a crossings count of 2⁶⁴ − 1 overflowed at the next crossing).
impl Persist for u64 {
    fn save(&self, e: &mut Encoder) {
        e.u64(*self);
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        let v = d.u64()?;
        if v > COUNT_LIMIT {
            return Err(SimError::Checkpoint(format!(
                "a counter of {v}, beyond any run"
            )));
        }
        *self = v;
        Ok(())
    }
}

/// Periodic image counts, as their `u64` bits, bounded as counters are.
impl Persist for i64 {
    fn save(&self, e: &mut Encoder) {
        e.u64(*self as u64);
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        let k = d.u64()? as i64;
        if k.unsigned_abs() > COUNT_LIMIT {
            return Err(SimError::Checkpoint(format!(
                "an image count of {k}, beyond any run"
            )));
        }
        *self = k;
        Ok(())
    }
}

impl Persist for f64 {
    fn save(&self, e: &mut Encoder) {
        e.f64(*self);
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        *self = d.f64()?;
        Ok(())
    }
}

/// One byte, any non-zero value read as `true`.
impl Persist for bool {
    fn save(&self, e: &mut Encoder) {
        e.u8(u8::from(*self));
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        *self = d.u8()? != 0;
        Ok(())
    }
}

/// `x`, `y`, `z`.
impl Persist for DVec3 {
    fn save(&self, e: &mut Encoder) {
        [self.x, self.y, self.z].save(e);
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        let mut xyz = [0.0; 3];
        xyz.load(d)?;
        *self = DVec3::from_array(xyz);
        Ok(())
    }
}

/// The elements in order, no length (it is the type's).
impl<T: Persist, const N: usize> Persist for [T; N] {
    fn save(&self, e: &mut Encoder) {
        for x in self {
            x.save(e);
        }
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        for x in self {
            x.load(d)?;
        }
        Ok(())
    }
}

/// A per-sphere array: its length, then the elements. The length must be the one the
/// world gave the array (a checkpoint never resizes one).
impl<T: Persist> Persist for Vec<T> {
    fn save(&self, e: &mut Encoder) {
        e.len(self.len());
        for x in self {
            x.save(e);
        }
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        d.len_eq(self.len(), "spheres")?;
        for x in self {
            x.load(d)?;
        }
        Ok(())
    }
}

/// Its code ([`ShapeKind::code`]) in one byte; a byte that names no kind is refused.
impl Persist for ShapeKind {
    fn save(&self, e: &mut Encoder) {
        e.u8(self.code());
    }
    fn load(&mut self, d: &mut Decoder) -> Result<(), SimError> {
        let k = d.u8()?;
        *self = ShapeKind::from_code(k)
            .ok_or_else(|| SimError::Checkpoint(format!("shape kind {k}")))?;
        Ok(())
    }
}

/// Implements [`Persist`] for a struct from one list of its fields, in checkpoint order (which
/// need not be the declaration order). Every field must be listed: the struct is destructured
/// without `..`, so a field added to the struct and not here does not compile.
///
/// ```ignore
/// persist_fields!(KernelCounts { sphere, plane, cylinder, container });
/// ```
macro_rules! persist_fields {
    ($ty:ty { $($field:ident),+ $(,)? }) => {
        impl $crate::sim::persist::Persist for $ty {
            fn save(&self, e: &mut $crate::sim::checkpoint::Encoder) {
                let Self { $($field),+ } = self;
                $( $crate::sim::persist::Persist::save($field, e); )+
            }
            fn load(
                &mut self,
                d: &mut $crate::sim::checkpoint::Decoder,
            ) -> Result<(), $crate::sim::model::SimError> {
                let Self { $($field),+ } = self;
                $( $crate::sim::persist::Persist::load($field, d)?; )+
                Ok(())
            }
        }
    };
}
pub(crate) use persist_fields;

persist_fields!(Body { kind, index });

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// `T` loaded from a stream of distinct non-zero 8-byte words (`1, 2, 3, …` as `u64`,
    /// whose bits are also distinct non-zero `f64`s): a type of 8-byte fields then has each
    /// field set to a different value, none its default, by its own description.
    pub(crate) fn distinct<T: Persist + Default>() -> T {
        let words: Vec<u8> = (1..=256u64).flat_map(u64::to_le_bytes).collect();
        let mut value = T::default();
        value
            .load(&mut Decoder::new(&words))
            .expect("256 words suffice");
        value
    }

    /// Every number `Debug` prints for `value`: one per field, nested structs included.
    pub(crate) fn printed_numbers(value: &impl std::fmt::Debug) -> Vec<String> {
        let text = format!("{value:?}");
        text.split([',', '{', '}', '(', ')', '[', ']'])
            .filter_map(|part| part.rsplit_once(": ").map(|(_, v)| v.trim().to_string()))
            .filter(|v| !v.is_empty() && !v.ends_with(char::is_alphabetic))
            .collect()
    }

    /// Saves `value`, loads the bytes into a default `T`, and checks that the copy equals it
    /// and that saving the copy gives the same bytes.
    pub(crate) fn round_trip<T: Persist + Default + PartialEq + std::fmt::Debug>(value: &T) {
        let mut e = Encoder::default();
        value.save(&mut e);
        let mut copy = T::default();
        let mut d = Decoder::new(&e.0);
        copy.load(&mut d).expect("its own bytes");
        d.finish().expect("every byte read");
        assert_eq!(&copy, value);
        let mut again = Encoder::default();
        copy.save(&mut again);
        assert_eq!(again.0, e.0);
    }

    #[test]
    fn counters_beyond_any_run_and_unknown_kinds_are_refused() {
        let mut count = 0u64;
        let bytes = (COUNT_LIMIT + 1).to_le_bytes();
        assert!(count.load(&mut Decoder::new(&bytes)).is_err());
        let mut image = 0i64;
        let bytes = (-(COUNT_LIMIT as i64) - 1).to_le_bytes();
        assert!(image.load(&mut Decoder::new(&bytes)).is_err());
        let mut kind = ShapeKind::Sphere;
        assert!(kind.load(&mut Decoder::new(&[4])).is_err());
        kind.load(&mut Decoder::new(&[3])).unwrap();
        assert_eq!(kind, ShapeKind::Container);
    }

    #[test]
    fn printed_numbers_finds_every_field() {
        #[allow(dead_code)] // read by `Debug` only
        #[derive(Debug)]
        struct Inner {
            a: u64,
        }
        #[allow(dead_code)] // read by `Debug` only
        #[derive(Debug)]
        struct Outer {
            x: f64,
            inner: Inner,
            y: u32,
        }
        let o = Outer {
            x: 1.5e-300,
            inner: Inner { a: 0 },
            y: 7,
        };
        assert_eq!(printed_numbers(&o), ["1.5e-300", "0", "7"]);
    }
}
