//! Ctrl-C and SIGTERM: `run` stops between two events, writes a last checkpoint (when
//! checkpoints are on), removes its temporary files, leaves earlier files untouched, says what
//! was done and exits with 130; resumed from that checkpoint it ends byte for byte as a run
//! never interrupted. `demo` and `query` stop the same way.

mod common;
mod run_support;

use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::Duration;

use common::{bin, scratch, spawn_gas_run};
use run_support::{physics, read};

fn signal(child: &Child, name: &str) {
    let ok = Command::new("kill")
        .args([format!("-{name}"), child.id().to_string()])
        .status()
        .expect("kill runs")
        .success();
    assert!(ok, "kill -{name} failed");
}

/// Waits until `path` exists (the run is under way), then sends the signal.
fn interrupt_once(child: &mut Child, path: &Path, name: &str) -> Output {
    while !path.exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before {} appeared",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let stderr = child.stderr.take().unwrap();
    stop(child, name, stderr)
}

/// Sends the signal, waits for the process to end, and reads what is left of its standard
/// error from `stderr` (the child's, or a reader that already took its first lines).
fn stop(child: &mut Child, name: &str, mut stderr: impl Read) -> Output {
    signal(child, name);
    let status = child.wait().unwrap();
    let mut err = Vec::new();
    stderr.read_to_end(&mut err).unwrap();
    Output {
        status,
        stdout: Vec::new(),
        stderr: err,
    }
}

/// No temporary file (`*.tmp`) is left in `dir`.
fn assert_no_temporaries(dir: &Path) {
    let left = temporary_files(dir);
    assert!(left.is_empty(), "{left:?}");
}

fn temporary_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

#[test]
fn sigterm_stops_run_with_a_checkpoint_that_resumes_to_the_same_bytes() {
    let dir = scratch("sigterm");
    let (full, cut) = (dir.join("full"), dir.join("cut"));
    let out = spawn_gas_run(&full, &[]).wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    // An earlier run's files in the output directory must survive the interruption.
    std::fs::create_dir_all(&cut).unwrap();
    for name in ["trajectory.xyz", "summary.json"] {
        std::fs::write(cut.join(name), b"an earlier run").unwrap();
    }
    // --force: the directory holds another run's files (kept until this run completes).
    let mut child = spawn_gas_run(&cut, &["--checkpoint-every", "2", "--force"]);
    let stopped = interrupt_once(&mut child, &cut.join("checkpoint.bin"), "TERM");
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted at t = ")
            && err.contains("collisions")
            && err.contains("checkpoint.bin")
            && err.contains("--resume"),
        "{err}"
    );
    for name in ["trajectory.xyz", "summary.json"] {
        assert_eq!(
            std::fs::read(cut.join(name)).unwrap(),
            b"an earlier run",
            "{name}"
        );
    }
    assert!(
        temporary_files(&cut).is_empty(),
        "{:?}",
        temporary_files(&cut)
    );

    let ckpt = cut.join("checkpoint.bin");
    let resumed = spawn_gas_run(
        &cut,
        &[
            "--checkpoint-every",
            "2",
            "--resume",
            ckpt.to_str().unwrap(),
        ],
    )
    .wait_with_output()
    .unwrap();
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert!(
        read(&full.join("trajectory.xyz")) == read(&cut.join("trajectory.xyz")),
        "the trajectory of the interrupted and resumed run differs ({err})"
    );
    assert_eq!(
        physics(&full.join("summary.json")),
        physics(&cut.join("summary.json"))
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sigint_stops_run_without_checkpoints_and_keeps_earlier_files() {
    let dir = scratch("sigint");
    std::fs::write(dir.join("summary.json"), b"an earlier run").unwrap();
    // The run has started simulating once its partial trajectory exists.
    let mut child = spawn_gas_run(&dir, &["--force"]);
    let partial = dir.join(".trajectory.xyz.partial");
    while !partial.exists() {
        assert!(child.try_wait().unwrap().is_none(), "the run ended first");
        std::thread::sleep(Duration::from_millis(5));
    }
    let stopped = interrupt_once(&mut child, &dir, "INT");
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted at t = ") && err.contains("nothing written"),
        "{err}"
    );
    assert_eq!(
        std::fs::read(dir.join("summary.json")).unwrap(),
        b"an earlier run"
    );
    assert!(!dir.join("trajectory.xyz").exists() && !dir.join("checkpoint.bin").exists());
    assert!(
        !partial.exists(),
        "without checkpoints the partial trajectory is removed"
    );
    assert_no_temporaries(&dir);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sigterm_stops_demo_without_writing_a_picture() {
    let dir = scratch("demo-term");
    let mut child = bin()
        .args(["demo", "--quiet", "--out"])
        .arg(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The demo prints its scene before it simulates, with the handler installed.
    let mut stdout = child.stdout.take().unwrap();
    let mut first = [0u8; 1];
    stdout.read_exact(&mut first).unwrap();
    let stopped = interrupt_once(&mut child, &dir, "TERM");
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted at t = ") && err.contains("no picture"),
        "{err}"
    );
    assert!(
        std::fs::read_dir(&dir).unwrap().next().is_none(),
        "the demo wrote a file"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A small scene whose stops each take fewer than 4096 events (so the engine never polls
/// inside one) is still stopped, at the next stop.
#[test]
fn sigterm_stops_a_run_of_short_steps() {
    let dir = scratch("short-steps");
    let scene = dir.join("small.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 400000\nsnapshot_every = 1\n\n[boundary]\nkind = \"periodic\"\n\n[[generate]]\nkind = \"periodic_gas\"\nn = 32\nphi = 0.2\nradius = 0.5\ntemperature = 1.0\n",
    )
    .unwrap();
    let out = dir.join("out");
    let mut child = bin()
        .args(["run", "--quiet", "--checkpoint-every", "5", "--out"])
        .arg(&out)
        .arg(&scene)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stopped = interrupt_once(&mut child, &out.join("checkpoint.bin"), "TERM");
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted at t = ") && err.contains("--resume"),
        "{err}"
    );
    assert!(
        temporary_files(&out).is_empty(),
        "{:?}",
        temporary_files(&out)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `query` stops between two chunks: its staged output is removed and an earlier output kept.
#[test]
fn sigterm_stops_query_between_chunks() {
    let dir = scratch("query-term");
    let input = dir.join("pairs.csv");
    let mut text = String::from("ax,ay,az,avx,avy,avz,ar,bx,by,bz,bvx,bvy,bvz,br\n");
    for i in 0..200_000 {
        text.push_str(&format!("0,0,0,1,0,0,1,{},0,0,0,0,0,1\n", 3 + i % 7));
    }
    std::fs::write(&input, text).unwrap();
    let output = dir.join("times.csv");
    // An earlier query's result (a file that is not one is refused without --force).
    std::fs::write(&output, b"time\n4.0\n").unwrap();
    let mut child = bin()
        .args(["query", "--chunk-rows", "1", "--out"])
        .arg(&output)
        .arg(&input)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The staged output exists once the query has started on its chunks.
    while temporary_files(&dir).is_empty() {
        assert!(child.try_wait().unwrap().is_none(), "the query ended first");
        std::thread::sleep(Duration::from_millis(2));
    }
    let stopped = interrupt_once(&mut child, &dir, "TERM");
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted after") && err.contains("chunks"),
        "{err}"
    );
    assert_eq!(std::fs::read(&output).unwrap(), b"time\n4.0\n");
    assert_no_temporaries(&dir);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `render` of a sequence stops drawing: the pictures it finished are whole, no temporary
/// file is left, and it says how many it wrote.
#[test]
fn sigterm_stops_render_of_a_sequence() {
    let dir = scratch("render-term");
    let scene = dir.join("small.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 300\nsnapshot_every = 1\n\n[boundary]\nkind = \"periodic\"\n\n[[generate]]\nkind = \"periodic_gas\"\nn = 64\nphi = 0.2\nradius = 0.5\ntemperature = 1.0\n",
    )
    .unwrap();
    let ran = bin()
        .args(["run", "--quiet", "--out"])
        .arg(dir.join("run"))
        .arg(&scene)
        .output()
        .unwrap();
    assert!(
        ran.status.success(),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let pictures = dir.join("pictures");
    let mut child = bin()
        .args(["render", "--out"])
        .arg(&pictures)
        .arg(dir.join("run/trajectory.xyz"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stopped = interrupt_once(&mut child, &pictures.join("frame-0000.png"), "TERM");
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted after") && err.contains("of 602 pictures"),
        "{err}"
    );
    assert!(
        temporary_files(&pictures).is_empty(),
        "{:?}",
        temporary_files(&pictures)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `accuracy` cannot stop its study half-way: SIGTERM ends it at once with 130, saying that
/// nothing was written, and the earlier report and picture are untouched.
#[test]
fn sigterm_stops_accuracy_before_anything_is_written() {
    let dir = scratch("accuracy-term");
    let (report, svg) = (dir.join("accuracy.md"), dir.join("accuracy.svg"));
    std::fs::write(&report, "earlier report").unwrap();
    std::fs::write(&svg, "earlier picture").unwrap();
    let mut child = bin()
        .args(["accuracy", "--cases", "1000000", "--out"])
        .arg(&report)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // It says when the study starts (the handler is installed by then).
    let mut stderr = child.stderr.take().unwrap();
    let mut first = [0u8; 9];
    stderr.read_exact(&mut first).unwrap();
    assert_eq!(&first, b"accuracy:");
    let stopped = stop(&mut child, "TERM", stderr);
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted during the study: nothing written"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&report).unwrap(), "earlier report");
    assert_eq!(std::fs::read_to_string(&svg).unwrap(), "earlier picture");
    assert_no_temporaries(&dir);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `bench` is ended at once by SIGINT, with 130 and a message.
#[test]
fn sigint_stops_bench() {
    let mut child = bin()
        .args(["bench", "--quick"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // It says when the measurements start (the handler is installed by then).
    let mut stderr = child.stderr.take().unwrap();
    let mut first = [0u8; 6];
    stderr.read_exact(&mut first).unwrap();
    assert_eq!(&first, b"bench:");
    let stopped = stop(&mut child, "INT", stderr);
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted the benchmark"), "{err}");
}

/// `run` of a scene of a million spheres, interrupted while the world and the engine are built
/// (which cannot poll): it ends at once with 130, having written nothing.
#[test]
fn sigterm_while_a_large_scene_is_built_ends_at_once() {
    let dir = scratch("build-term");
    let scene = dir.join("big.toml");
    std::fs::write(
        &scene,
        "[run]\nt_end = 1.0\n\n[boundary]\nkind = \"periodic\"\n\n[[generate]]\n\
         kind = \"periodic_gas\"\nn = 1000000\nphi = 0.3\nradius = 0.5\ntemperature = 1.0\n",
    )
    .unwrap();
    let out = dir.join("out");
    let mut child = bin()
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // It says when the build starts (the handler is installed by then).
    let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    use std::io::BufRead;
    stderr.read_line(&mut line).unwrap();
    assert!(line.contains("building 1000000 spheres"), "{line}");
    let stopped = stop(&mut child, "TERM", stderr);
    let err = String::from_utf8_lossy(&stopped.stderr);
    assert_eq!(stopped.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted while the scene was built: nothing written"),
        "{err}"
    );
    assert!(!out.exists(), "the output directory was created");
    let _ = std::fs::remove_dir_all(&dir);
}
