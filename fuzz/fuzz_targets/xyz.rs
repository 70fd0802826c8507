//! Bytes → `io::xyz::read_frames`: frames, or an error naming a line of the text; never a
//! panic.
#![no_main]

#[allow(dead_code)]
#[path = "../src/checks.rs"]
mod checks;

libfuzzer_sys::fuzz_target!(|data: &[u8]| checks::xyz(data));
