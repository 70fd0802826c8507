//! Messages that name what is wrong, and only that: an `f8` value beyond `f32`'s range in a
//! `.npy` input is refused as CSV refuses it (value, row, column); a scene file's generator is
//! blamed by name, line and field for the one condition that failed, never as `effects:` or
//! as `[boundary]`; numbers far from 1 are printed in exponent form; a CSV file whose lines end
//! in CR alone is refused saying so.

mod common;

use std::path::Path;
use std::process::Output;

use common::{bin, scratch};

fn spheresweep(args: &[&str]) -> Output {
    bin().args(args).output().expect("the binary runs")
}

/// The error of a command that must fail with exit code 1.
fn refused(args: &[&str]) -> String {
    let out = spheresweep(args);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
    err
}

const PAIR: [f64; 14] = [0., 0., 0., 1., 0., 0., 1., 5., 0., 0., 0., 0., 0., 1.];

/// A 2-D `f8` array of pairs, C order (C) or Fortran order, or the 14 column files.
fn npy_pairs(path: &Path, rows: &[[f64; 14]], fortran: bool) {
    use npyz::WriterBuilder;
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let order = if fortran {
        npyz::Order::Fortran
    } else {
        npyz::Order::C
    };
    let mut w = npyz::WriteOptions::<f64>::new()
        .default_dtype()
        .shape(&[rows.len() as u64, 14])
        .order(order)
        .writer(file)
        .begin_nd()
        .unwrap();
    if fortran {
        for j in 0..14 {
            w.extend(rows.iter().map(|r| r[j])).unwrap();
        }
    } else {
        w.extend(rows.iter().flatten().copied()).unwrap();
    }
    w.finish().unwrap();
}

#[test]
fn an_f8_value_beyond_f32_is_refused_as_csv_refuses_it() {
    let dir = scratch("npy-beyond");
    let mut bad = PAIR;
    bad[3] = 1e39; // avx of row 1
    let (c, f) = (dir.join("c.npy"), dir.join("f.npy"));
    npy_pairs(&c, &[PAIR, bad, PAIR], false);
    npy_pairs(&f, &[PAIR, bad, PAIR], true);
    for path in [&c, &f] {
        let err = refused(&["query", path.to_str().unwrap()]);
        assert!(
            err.contains(&format!(
                "{}: row 1, column avx: 1e39 is beyond the range of f32 (magnitudes up to 3.4e38)",
                path.display()
            )),
            "{err}"
        );
    }
    // Column files, one of them big-endian (read through npyz's typed reader).
    let cols = dir.join("cols");
    std::fs::create_dir(&cols).unwrap();
    let names = [
        "ax", "ay", "az", "avx", "avy", "avz", "ar", "bx", "by", "bz", "bvx", "bvy", "bvz", "br",
    ];
    for (j, name) in names.iter().enumerate() {
        let mut values = vec![PAIR[j]; 3];
        if *name == "bvz" {
            values[2] = -3e300;
        }
        let path = cols.join(format!("{name}.npy"));
        let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
        use npyz::WriterBuilder;
        let mut w = npyz::WriteOptions::<f64>::new()
            .dtype(npyz::DType::new_scalar(">f8".parse().unwrap()))
            .shape(&[3])
            .writer(file)
            .begin_nd()
            .unwrap();
        w.extend(values).unwrap();
        w.finish().unwrap();
    }
    let err = refused(&["query", cols.to_str().unwrap()]);
    assert!(
        err.contains("row 2, column bvz: -3e300 is beyond the range of f32"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A scene file of one `[[generate]]` block after two lattices (so the block is `generate 2`
/// and its fields' lines are known), with `block` appended.
fn scene_with(dir: &Path, name: &str, head: &str, block: &str) -> String {
    let text = format!(
        "[run]\n{head}\n\n\
         [[generate]]\nkind = \"lattice\"\nlo = [0, 0, 0]\ncounts = [2, 2, 2]\nspacing = 3\nradius = 0.5\n\n\
         [[generate]]\nkind = \"lattice\"\nlo = [50, 0, 0]\ncounts = [2, 2, 2]\nspacing = 3\nradius = 0.5\n\n\
         {block}"
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

const NOZZLE: &str = "[[generate]]\nkind = \"nozzle\"\norigin = [0, 0, 20]\n\
                      direction = [0, 0, 1]\nn = 10\nradius = 0.5\nspeed = 1\n";

#[test]
fn a_generators_error_names_it_its_line_and_the_one_field_that_failed() {
    let dir = scratch("generator-errors");
    // Lines: 1 [run], 2 t_end, 4-9 and 11-16 the lattices, 18 the nozzle, 19 kind,
    // 20 origin, 21 direction, 22 n, 23 radius, 24 speed, 25 the field added.
    for (extra, line, want) in [
        (
            "spacing = 0.5\n",
            25,
            "generate 2 (nozzle): spacing = 0.5 must be at least a diameter (1.0)",
        ),
        (
            "jitter = 3.0\n",
            25,
            "generate 2 (nozzle): jitter = 3.0 must be at least 0 and below the spacing (1.1)",
        ),
        (
            "spread = inf\n",
            25,
            "generate 2 (nozzle): spread = inf must be finite",
        ),
    ] {
        let scene = scene_with(
            &dir,
            "nozzle.toml",
            "t_end = 10",
            &format!("{NOZZLE}{extra}"),
        );
        let err = refused(&["run", "--quiet", &scene]);
        assert!(
            err.contains(&format!("nozzle.toml:{line}: {want}")),
            "{err}"
        );
        for other in ["effects:", "direction must", "jitter", "spacing"] {
            if !want.contains(other) {
                assert!(!err.contains(other), "{other} in {err}");
            }
        }
    }
    let zero = NOZZLE.replace("direction = [0, 0, 1]", "direction = [0, 0, 0]");
    let scene = scene_with(&dir, "zero.toml", "t_end = 10", &zero);
    let err = refused(&["run", "--quiet", &scene]);
    assert!(
        err.contains("zero.toml:21: generate 2 (nozzle): direction = [0, 0, 0] has no direction")
            && !err.contains("spacing"),
        "{err}"
    );
    let lattice = "[[generate]]\nkind = \"lattice\"\nlo = [0, 0, 90]\ncounts = [2, 2, 2]\n\
                   spacing = 0.9\nradius = 0.5\n";
    let scene = scene_with(&dir, "lattice.toml", "t_end = 10", lattice);
    let err = refused(&["run", "--quiet", &scene]);
    assert!(
        err.contains(
            "lattice.toml:22: generate 2 (lattice): spacing = 0.9 must be at least a diameter (1.0)"
        ) && !err.contains("effects:"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_periodic_gas_too_small_for_its_box_blames_the_gas_and_says_why() {
    let dir = scratch("gas-errors");
    let gas = |n: u32, phi: f64| {
        let path = dir.join(format!("gas{n}.toml"));
        std::fs::write(
            &path,
            format!(
                "[run]\nt_end = 1\n\n[boundary]\nkind = \"periodic\"\n\n[[generate]]\n\
                 kind = \"periodic_gas\"\nn = {n}\nphi = {phi}\nradius = 0.5\n"
            ),
        )
        .unwrap();
        path
    };
    for n in [1, 2] {
        let path = gas(n, 0.3);
        let err = refused(&["run", "--quiet", path.to_str().unwrap()]);
        assert!(
            err.contains(&format!(
                "gas{n}.toml:9: generate 0 (periodic_gas): the box side from n = {n} and phi = 0.3 is"
            )) && err.contains("less than three diameters (3.0): use more spheres (at least")
                && !err.contains("boundary")
                && !err.contains("effects:"),
            "{err}"
        );
    }
    let path = gas(100, 0.69);
    let err = refused(&["run", "--quiet", path.to_str().unwrap()]);
    assert!(
        err.contains(
            "gas100.toml:10: generate 0 (periodic_gas): packing fraction 0.69 is too dense"
        ) && !err.contains("effects:"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn numbers_far_from_one_are_printed_in_exponent_form() {
    let dir = scratch("huge-numbers");
    let scene = scene_with(&dir, "t.toml", "t_end = -1e300", "");
    let err = refused(&["run", "--quiet", &scene]);
    assert!(
        err.contains("t.toml:2: run: t_end = -1e300 must be finite and greater than 0"),
        "{err}"
    );
    assert!(err.len() < 200, "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_csv_with_cr_line_endings_is_refused_saying_so() {
    let dir = scratch("cr-csv");
    let input = dir.join("mac.csv");
    std::fs::write(
        &input,
        "ax,ay,az,avx,avy,avz,ar,bx,by,bz,bvx,bvy,bvz,br\r0,0,0,1,0,0,1,5,0,0,0,0,0,1\r",
    )
    .unwrap();
    let err = refused(&["query", input.to_str().unwrap()]);
    assert!(
        err.contains("mac.csv: line 1 (the header): the lines end in a carriage return alone")
            && err.contains("convert the file to \\n or \\r\\n line endings")
            && !err.contains("no column"),
        "{err}"
    );
    assert!(!dir.join("mac-toi.csv").exists());
    std::fs::remove_dir_all(&dir).ok();
}
