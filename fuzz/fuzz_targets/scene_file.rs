//! Bytes → a scene file, parsed as TOML and as JSON → `build` → `Simulation::new` → at most
//! one step of 4096 events: never a panic, every refusal a `SceneFileError`. Scenes of more
//! than `MAX_SPHERES` spheres (counted before anything is generated) are not built, so that
//! every run stays fast.
#![no_main]

#[allow(dead_code)]
#[path = "../src/checks.rs"]
mod checks;

libfuzzer_sys::fuzz_target!(|data: &[u8]| checks::scene_file(data));
