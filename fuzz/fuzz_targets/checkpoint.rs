//! Bytes → `Simulation::restore` into a small world: a simulation or an error, never a panic.
//! Half the inputs are taken as they are; the other half overwrite part of a real checkpoint
//! of that world and carry a correct checksum, so that the fuzzer reaches the decoding of
//! every field behind the checksum.
#![no_main]

#[allow(dead_code)]
#[path = "../src/checks.rs"]
mod checks;

libfuzzer_sys::fuzz_target!(|data: &[u8]| checks::checkpoint(data));
