//! Arbitrary f32 bit patterns → `SphereStore::from_columns`: an error naming a column or a
//! sphere, or a store whose spheres read back bit for bit.
#![no_main]

#[allow(dead_code)]
#[path = "../src/checks.rs"]
mod checks;

libfuzzer_sys::fuzz_target!(|data: &[u8]| checks::columns(data));
