//! Arbitrary f32 bit patterns for one pair of each kind (sphere–sphere, –plane, –cylinder,
//! –container) × every accuracy mode, through the public batch entry points (`zip_times`,
//! `static_times`): for every input the constructors accept, never a panic, never NaN, a
//! time within `[0, t_max]` or none. Where the inputs are in the range the differential
//! tests cover (tests/narrow_differential.rs), the time agrees with the f64 reference within
//! the rounding-error model of tests/common (docs/derivations/accuracy.md), and hit/miss agrees
//! outside its bands of ill-conditioning: the same criterion, not a looser one.
#![no_main]

#[allow(dead_code)]
#[path = "../src/checks.rs"]
mod checks;

libfuzzer_sys::fuzz_target!(|data: &[u8]| checks::kernels(data));
