//! The memory available is the smallest of the machine's free memory, the address-space limit
//! (`ulimit -v`) and the cgroup's limit: under `ulimit -v`, a scene, a chunk or a picture too
//! large for what the limit leaves is refused with a message naming it and exit code 1, not
//! aborted by a failed allocation (exit code 134); `SPHERESWEEP_MAX_MEMORY` still overrides.

mod common;

use std::process::Output;

use common::scratch;

/// The address-space limit every test runs the binary under: 1 GiB, in KiB for `ulimit -v`.
const LIMIT_KIB: u64 = 1 << 20;

/// `spheresweep ARGS` under `ulimit -v LIMIT_KIB`, with `env` set.
fn limited(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = std::process::Command::new("bash");
    command
        .args([
            "-c",
            &format!("ulimit -v {LIMIT_KIB} && exec \"$0\" \"$@\""),
        ])
        .arg(env!("CARGO_BIN_EXE_spheresweep"))
        .args(args)
        .env_remove("SPHERESWEEP_MAX_MEMORY");
    for (k, v) in env {
        command.env(k, v);
    }
    command.output().expect("bash runs")
}

/// A periodic gas of 2·10⁷ generated spheres (about 9 GiB to simulate).
fn big_scene(dir: &std::path::Path) -> String {
    let scene = dir.join("big.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 1\n\n[boundary]\nkind = \"periodic\"\n\n[[generate]]\n\
         kind = \"periodic_gas\"\nn = 20000000\nphi = 0.3\nradius = 0.5\n",
    )
    .unwrap();
    scene.to_str().unwrap().to_string()
}

fn refused_under_ulimit(out: &Output, what: &str) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains(what)
            && err.contains("needs about")
            && err.contains("the address-space limit, ulimit -v, of 1.00 GiB less")
            && err.contains("refused before allocating")
            && !err.contains("memory allocation"),
        "{err}"
    );
    err
}

#[test]
fn run_of_a_scene_too_large_for_ulimit_v_is_refused_with_exit_code_1() {
    let dir = scratch("ulimit-run");
    let scene = big_scene(&dir);
    let out_dir = dir.join("out");
    let out = limited(
        &["run", "--quiet", "--out", out_dir.to_str().unwrap(), &scene],
        &[],
    );
    refused_under_ulimit(&out, "a simulation of 20000000 spheres");
    assert!(!out_dir.exists(), "a refused run made its output directory");
    // The variable still decides when it is set.
    let out = limited(
        &["run", "--quiet", "--out", out_dir.to_str().unwrap(), &scene],
        &[("SPHERESWEEP_MAX_MEMORY", "512M")],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("512.0 MiB (536870912 B) is available (SPHERESWEEP_MAX_MEMORY)"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn render_and_query_check_against_ulimit_v_too() {
    let dir = scratch("ulimit-render");
    let scene = big_scene(&dir);
    let out = limited(
        &[
            "render",
            &scene,
            "--out",
            dir.join("pictures").to_str().unwrap(),
        ],
        &[],
    );
    refused_under_ulimit(&out, "20000000 spheres");
    // 2²² rows of about 0.7 KiB: some 2.8 GiB of chunk, in a file with room for them (a
    // header, then sparse: no row is read before the check).
    let input = dir.join("pairs.csv");
    common::sparse_pairs_csv(&input, 256 << 20);
    let out = limited(
        &["query", input.to_str().unwrap(), "--chunk-rows", "4194304"],
        &[],
    );
    refused_under_ulimit(&out, "--chunk-rows 4194304");
    std::fs::remove_dir_all(&dir).ok();
}
