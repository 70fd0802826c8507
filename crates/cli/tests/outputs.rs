//! An output is never an input: `query`, `render` and `accuracy` refuse an output that is the
//! same file as an input (or as another output) through a symbolic or hard link, or a path
//! that leads to it once its directories are made, naming both; and the temporaries a killed
//! process left for an output are removed by the next command writing it, those of running
//! processes and of other names kept.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{bin, repo, scratch};

const PAIRS: &str = "ax,ay,az,avx,avy,avz,ar,bx,by,bz,bvx,bvy,bvz,br\n\
                     0,0,0,1,0,0,1,5,0,0,0,0,0,1\n";

fn spheresweep(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A `.npy` (N, 14) `<f4` array of pairs, written by hand.
fn npy_pairs(path: &Path, rows: &[[f32; 14]]) {
    let header = format!(
        "{{'descr': '<f4', 'fortran_order': False, 'shape': ({}, 14), }}",
        rows.len()
    );
    let pad = 63 - (header.len() + 10) % 64;
    let header = format!("{header}{}\n", " ".repeat(pad));
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend((header.len() as u16).to_le_bytes());
    bytes.extend(header.as_bytes());
    for v in rows.iter().flatten() {
        bytes.extend(v.to_le_bytes());
    }
    std::fs::write(path, bytes).unwrap();
}

/// Asserts `args` fail naming both paths as the same file, with `kept` unchanged.
fn refused_as_input(args: &[&str], output: &str, input: &str, kept: &Path) {
    let before = std::fs::read(kept).unwrap();
    let out = spheresweep(args);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    assert!(
        err.contains(&format!(
            "the output {output} and the input {input} are the same file"
        )),
        "{args:?}: {err}"
    );
    assert_eq!(std::fs::read(kept).unwrap(), before, "{args:?}");
}

#[test]
fn query_refuses_an_output_that_is_its_input_through_a_link() {
    let dir = scratch("out-is-in");
    let input = dir.join("in.csv");
    std::fs::write(&input, PAIRS).unwrap();
    let (link, hard) = (dir.join("link.csv"), dir.join("hard.csv"));
    std::os::unix::fs::symlink(&input, &link).unwrap();
    std::fs::hard_link(&input, &hard).unwrap();
    for (from, to) in [(&link, &input), (&hard, &input), (&input, &link)] {
        refused_as_input(&["query", s(from), "--out", s(to)], s(to), s(from), &input);
    }
    // An output not made yet whose path leads to the input once `new/` exists.
    let around = dir.join("new/../in.csv");
    refused_as_input(
        &["query", s(&input), "--out", s(&around)],
        s(&around),
        s(&input),
        &input,
    );
    assert!(
        !dir.join("new").exists(),
        "the refused output's directory was made"
    );
    // The shapes file of --against is an input too.
    let shapes = dir.join("shapes.toml");
    std::fs::write(
        &shapes,
        "[[plane]]\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n",
    )
    .unwrap();
    let spheres = dir.join("spheres.csv");
    std::fs::write(&spheres, "x,y,z,vx,vy,vz,r\n0,0,5,0,0,-1,1\n").unwrap();
    // The output's extension must name a format: a CSV hard link to the shapes file.
    let as_csv = dir.join("shapes.csv");
    std::fs::hard_link(&shapes, &as_csv).unwrap();
    refused_as_input(
        &[
            "query",
            s(&spheres),
            "--against",
            s(&shapes),
            "--out",
            s(&as_csv),
        ],
        s(&as_csv),
        s(&shapes),
        &shapes,
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn query_refuses_an_npy_output_that_is_its_input() {
    let dir = scratch("npy-out-is-in");
    let row = [0., 0., 0., 1., 0., 0., 1., 5., 0., 0., 0., 0., 0., 1.];
    let input = dir.join("pairs.npy");
    npy_pairs(&input, &[row]);
    let hard = dir.join("times.npy");
    std::fs::hard_link(&input, &hard).unwrap();
    refused_as_input(
        &["query", s(&input), "--out", s(&hard)],
        s(&hard),
        s(&input),
        &input,
    );
    // A directory of columns is replaced whole: an input inside it is refused.
    let out = dir.join("toi");
    std::fs::create_dir(&out).unwrap();
    let inside = out.join("time.npy");
    npy_pairs(&inside, &[row]);
    let result = spheresweep(&["query", s(&inside), "--out", s(&out)]);
    let err = stderr(&result);
    assert_eq!(result.status.code(), Some(1), "{err}");
    assert!(
        err.contains(&format!(
            "the input {} is inside the output directory {}",
            s(&inside),
            s(&out)
        )),
        "{err}"
    );
    assert!(inside.is_file());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn render_and_accuracy_refuse_one_file_for_two_roles() {
    let dir = scratch("render-out-is-in");
    let scene = dir.join("gas.toml");
    std::fs::copy(repo("scenes/hard_sphere_gas.toml"), &scene).unwrap();
    let pictures = dir.join("pictures");
    std::fs::create_dir(&pictures).unwrap();
    let picture = pictures.join("gas.png");
    std::fs::hard_link(&scene, &picture).unwrap();
    refused_as_input(
        &[
            "render",
            s(&scene),
            "--out",
            s(&pictures),
            "--format",
            "png",
        ],
        s(&picture),
        s(&scene),
        &scene,
    );
    // accuracy's two outputs, one file through a hard link.
    let (md, svg) = (dir.join("a.md"), dir.join("a.svg"));
    std::fs::write(&md, "kept\n").unwrap();
    std::fs::hard_link(&md, &svg).unwrap();
    let out = spheresweep(&[
        "accuracy",
        "--cases",
        "10",
        "--out",
        s(&md),
        "--svg",
        s(&svg),
    ]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("are the same file (through a link)"), "{err}");
    assert_eq!(std::fs::read_to_string(&md).unwrap(), "kept\n");
    std::fs::remove_dir_all(&dir).ok();
}

/// The id of a process that has ended (a child waited for).
fn ended_pid() -> u32 {
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    assert!(!Path::new(&format!("/proc/{pid}")).exists());
    pid
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Plants a temporary file (or directory) `name` in `dir`.
fn plant(dir: &Path, name: &str, directory: bool) -> PathBuf {
    let path = dir.join(name);
    if directory {
        std::fs::create_dir(&path).unwrap();
        std::fs::write(path.join("time.npy"), "half").unwrap();
    } else {
        std::fs::write(&path, "half").unwrap();
    }
    path
}

#[test]
fn a_killed_querys_temporaries_are_removed_by_the_next_query_into_that_output() {
    let dir = scratch("stale-tmp");
    let input = dir.join("in.csv");
    std::fs::write(&input, PAIRS).unwrap();
    let (dead, live) = (ended_pid(), std::process::id());
    let stale = plant(&dir, &format!(".times.csv.{dead}.tmp"), false);
    let running = plant(&dir, &format!(".times.csv.{live}.tmp"), false);
    let other = plant(&dir, &format!(".other.csv.{dead}.tmp"), false);
    let stale_dir = plant(&dir, &format!(".toi.{dead}.tmp"), true);
    // An earlier `toi` a killed query set aside between its two renames.
    let set_aside = plant(&dir, &format!(".toi.{dead}.old"), true);
    let out = spheresweep(&["query", s(&input), "--out", s(&dir.join("times.csv"))]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!stale.exists(), "{:?}", names(&dir));
    assert!(running.exists() && other.exists() && stale_dir.exists());
    // A directory of .npy columns: its temporary directory.
    let out = spheresweep(&["query", s(&input), "--out", s(&dir.join("toi"))]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!stale_dir.exists(), "{:?}", names(&dir));
    assert!(running.exists() && other.exists());
    // While `toi` did not exist, the set-aside copy was the only one, and was kept; with `toi`
    // in place, the next query into it removes it.
    assert!(set_aside.exists(), "{:?}", names(&dir));
    let out = spheresweep(&["query", s(&input), "--out", s(&dir.join("toi"))]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!set_aside.exists(), "{:?}", names(&dir));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_killed_renders_temporaries_are_removed_by_the_next_render() {
    let dir = scratch("stale-render");
    let dead = ended_pid();
    let stale = plant(&dir, &format!(".hard_sphere_gas.png.{dead}.tmp"), false);
    let kept = plant(&dir, &format!(".notes.png.{dead}.tmp"), false);
    let out = spheresweep(&[
        "render",
        s(&repo("scenes/hard_sphere_gas.toml")),
        "--out",
        s(&dir),
        "--format",
        "png",
        "--size",
        "320x200",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!stale.exists() && kept.exists(), "{:?}", names(&dir));
    std::fs::remove_dir_all(&dir).ok();
}

/// An existing file at `--out` is replaced only if it is an earlier CSV result of a query, or
/// with `--force` (a new user's trial: `--out precious.csv` replaced a data file without a
/// word); a refused query leaves the file as it was.
#[test]
fn query_replaces_only_an_earlier_result_without_force() {
    let dir = scratch("outputs-replace");
    let input = dir.join("pairs.csv");
    std::fs::write(&input, PAIRS).unwrap();
    for (name, data) in [
        ("data.csv", &b"precious data\n"[..]),
        ("t.npy", b"\x93NUMPY"),
    ] {
        let out_path = dir.join(name);
        std::fs::write(&out_path, data).unwrap();
        let out = spheresweep(&["query", s(&input), "--out", s(&out_path)]);
        let err = stderr(&out);
        assert!(
            !out.status.success() && err.contains("exists and is not a query's CSV result"),
            "{name}: {err}"
        );
        assert_eq!(std::fs::read(&out_path).unwrap(), data, "{name}");
        let out = spheresweep(&["query", s(&input), "--out", s(&out_path), "--force"]);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        assert_ne!(std::fs::read(&out_path).unwrap(), data, "{name}");
    }
    // An earlier result is replaced without --force.
    let result = dir.join("data.csv");
    let out = spheresweep(&["query", s(&input), "--out", s(&result)]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(&result).unwrap(), "time\n3.0\n"); // gap 3 at speed 1
    let _ = std::fs::remove_dir_all(&dir);
}
