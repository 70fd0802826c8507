//! `spheresweep query` on CSV, `.npy` (and Parquet / Arrow IPC with the `parquet` feature):
//! results bit for bit the library's, streaming in chunks, and every malformed-input class
//! (issue 16). .ci/run runs this file with the `parquet` feature.

mod common;

use std::path::Path;

use spheresweep::batch::{earliest_static_contacts, pair_times, zip_times};
use spheresweep::contact::contact_at;
use spheresweep::rng::Rng;
use spheresweep::{Accuracy, Container, Cylinder, Plane, QueryOptions, Shape, Sphere, SphereStore};

use common::{run, scratch, shipped, text};

const PAIR_COLUMNS: [&str; 14] = [
    "ax", "ay", "az", "avx", "avy", "avz", "ar", "bx", "by", "bz", "bvx", "bvy", "bvz", "br",
];
const SPHERE_COLUMNS: [&str; 7] = ["x", "y", "z", "vx", "vy", "vz", "r"];
const GEOMETRY: [&str; 6] = ["px", "py", "pz", "nx", "ny", "nz"];

/// `n` pairs of spheres as rows of 14 values: every third aimed so that they meet, the
/// rest at random (most miss within the window).
fn pair_rows(n: usize, seed: u64) -> Vec<[f32; 14]> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|i| {
            let mut row = [0.0f32; 14];
            for side in [0, 7] {
                for k in 0..3 {
                    row[side + k] = rng.range(-6.0, 6.0) as f32;
                    row[side + 3 + k] = rng.range(-2.0, 2.0) as f32;
                }
                row[side + 6] = rng.range(0.0, 1.2) as f32;
            }
            if i % 3 == 0 {
                for k in 0..3 {
                    row[10 + k] = row[3 + k] + (row[k] - row[7 + k]) * 0.4;
                }
            }
            row
        })
        .collect()
}

/// `n` spheres as rows of 7 values, inside a vessel of radius 20.
fn sphere_rows(n: usize, seed: u64) -> Vec<[f32; 7]> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| {
            let mut row = [0.0f32; 7];
            for k in 0..3 {
                row[k] = rng.range(-8.0, 8.0) as f32;
                row[3 + k] = rng.range(-3.0, 3.0) as f32;
            }
            row[6] = rng.range(0.0, 1.0) as f32;
            row
        })
        .collect()
}

fn sphere(r: &[f32]) -> Sphere {
    Sphere::new([r[0], r[1], r[2]], [r[3], r[4], r[5]], r[6], 1.0).unwrap()
}

fn geometry_of(c: &spheresweep::Contact) -> [f64; 6] {
    [
        c.point.x, c.point.y, c.point.z, c.normal.x, c.normal.y, c.normal.z,
    ]
}

/// The library's answer for a pairs file: `zip_times` (checked against `pair_times` on one
/// store holding both sides), and each contact's geometry from `contact_at`.
fn library_pairs(rows: &[[f32; 14]], options: QueryOptions) -> (Vec<f32>, Vec<[f64; 6]>) {
    let a: Vec<Sphere> = rows.iter().map(|r| sphere(&r[..7])).collect();
    let b: Vec<Sphere> = rows.iter().map(|r| sphere(&r[7..])).collect();
    let n = rows.len();
    let mut times = vec![0.0; n];
    zip_times(
        &SphereStore::from_spheres(&a),
        &SphereStore::from_spheres(&b),
        options,
        &mut times,
    )
    .unwrap();
    let both = SphereStore::from_spheres(&[a.clone(), b.clone()].concat());
    let list: Vec<[u32; 2]> = (0..n as u32).map(|i| [i, n as u32 + i]).collect();
    let mut listed = vec![0.0; n];
    pair_times(&both, &list, options, &mut listed).unwrap();
    assert_eq!(
        bits(&times),
        bits(&listed),
        "zip_times and pair_times agree"
    );
    let geometry = (0..n)
        .map(|i| match times[i].is_finite() {
            true => geometry_of(&contact_at(
                &a[i],
                &Shape::Sphere(b[i]),
                f64::from(times[i]),
            )),
            false => [f64::NAN; 6],
        })
        .collect();
    (times, geometry)
}

/// The shapes of the spheres-against-shapes tests: two identical floors (a tie: plane 0
/// wins), a wall, two pillars and a vessel.
const SHAPES_TOML: &str = "\
[[plane]]
point = [0.0, 0.0, -6.0]
normal = [0.0, 0.0, 1.0]

[[plane]]
point = [0.0, 0.0, -6.0]
normal = [0.0, 0.0, 2.0]

[[plane]]
point = [7.0, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]

[[cylinder]]
p1 = [2.0, 2.0, 0.0]
p2 = [2.0, 2.0, 1.0]
radius = 0.5

[[cylinder]]
p1 = [-3.0, 0.0, 1.0]
p2 = [-3.0, 1.0, 1.0]
radius = 1.0

[[container]]
centre = [0.0, 0.0, 0.0]
radius = 20.0
";

/// The library's answer for spheres against [`SHAPES_TOML`]: `earliest_static_contacts`
/// per kind, merged by the library's tie rule (kind, then index): time, kind code, index,
/// geometry.
fn library_statics(rows: &[[f32; 7]], options: QueryOptions) -> Vec<(f32, u8, i64, [f64; 6])> {
    let planes = [
        Plane::new([0.0, 0.0, -6.0], [0.0, 0.0, 1.0]).unwrap(),
        Plane::new([0.0, 0.0, -6.0], [0.0, 0.0, 2.0]).unwrap(),
        Plane::new([7.0, 0.0, 0.0], [-1.0, 0.0, 0.0]).unwrap(),
    ];
    let cylinders = [
        Cylinder::new([2.0, 2.0, 0.0], [2.0, 2.0, 1.0], 0.5).unwrap(),
        Cylinder::new([-3.0, 0.0, 1.0], [-3.0, 1.0, 1.0], 1.0).unwrap(),
    ];
    let containers = [Container::new([0.0; 3], 20.0).unwrap()];
    library_statics_of(rows, options, &planes, &cylinders, &containers)
}

/// The library's answer for spheres against any shapes.
fn library_statics_of(
    rows: &[[f32; 7]],
    options: QueryOptions,
    planes: &[Plane],
    cylinders: &[Cylinder],
    containers: &[Container],
) -> Vec<(f32, u8, i64, [f64; 6])> {
    let store = SphereStore::from_spheres(&rows.iter().map(|r| sphere(r)).collect::<Vec<_>>());
    let options = options.with_geometry(true);
    let kinds = [
        (1u8, earliest_static_contacts(&store, planes, options)),
        (2, earliest_static_contacts(&store, cylinders, options)),
        (3, earliest_static_contacts(&store, containers, options)),
    ];
    (0..rows.len())
        .map(|i| {
            let mut best = (f32::INFINITY, 0u8, -1i64, [f64::NAN; 6]);
            for (code, hits) in &kinds {
                if let Some(h) = hits[i]
                    && h.time < best.0
                {
                    let g = geometry_of(&h.geometry.unwrap());
                    best = (h.time, *code, i64::from(h.body.index), g);
                }
            }
            best
        })
        .collect()
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn bits64(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Writes a CSV file: a header, then rows in round-trip decimals (so the CLI reads the
/// same `f32`s).
fn write_csv<const N: usize>(path: &Path, header: &[&str], rows: &[[f32; N]]) {
    let mut s = header.join(",");
    s.push('\n');
    for r in rows {
        let fields: Vec<String> = r.iter().map(|v| format!("{v:?}")).collect();
        s.push_str(&fields.join(","));
        s.push('\n');
    }
    std::fs::write(path, s).unwrap();
}

/// A CSV result: the header, and each column's fields.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut columns = vec![Vec::new(); header.len()];
    for line in lines {
        for (c, f) in columns.iter_mut().zip(line.split(',')) {
            c.push(f.to_string());
        }
    }
    (header, columns)
}

fn parse<T: std::str::FromStr>(fields: &[String]) -> Vec<T>
where
    T::Err: std::fmt::Debug,
{
    fields.iter().map(|f| f.parse().unwrap()).collect()
}

/// Writes a 1-D `.npy` array.
fn write_npy_1d<T: npyz::AutoSerialize + Copy>(path: &Path, values: &[T]) {
    npyz::to_file_1d(path, values.iter().copied()).unwrap();
}

/// Writes a 2-D `.npy` array of `rows`, in C or Fortran order, as `T`.
fn write_npy_2d<T: npyz::AutoSerialize + Copy, const N: usize>(
    path: &Path,
    rows: &[[f32; N]],
    fortran: bool,
    convert: impl Fn(f32, usize, usize) -> T,
) {
    use npyz::WriterBuilder;
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let order = if fortran {
        npyz::Order::Fortran
    } else {
        npyz::Order::C
    };
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[rows.len() as u64, N as u64])
        .order(order)
        .writer(file)
        .begin_nd()
        .unwrap();
    if fortran {
        for j in 0..N {
            for (i, r) in rows.iter().enumerate() {
                w.push(&convert(r[j], i, j)).unwrap();
            }
        }
    } else {
        for (i, r) in rows.iter().enumerate() {
            for (j, &v) in r.iter().enumerate() {
                w.push(&convert(v, i, j)).unwrap();
            }
        }
    }
    w.finish().unwrap();
}

/// Reads a 1-D `.npy` array.
fn read_npy<T: npyz::Deserialize>(path: &Path) -> Vec<T> {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let npy = npyz::NpyFile::new(std::io::BufReader::new(file)).unwrap();
    assert_eq!(npy.shape().len(), 1, "{}", path.display());
    npy.into_vec().unwrap()
}

/// A line of the summary, by its key.
fn summary<'a>(stdout: &'a str, key: &str) -> &'a str {
    stdout
        .lines()
        .find(|l| l.starts_with(key))
        .unwrap_or_else(|| panic!("no {key:?} line in\n{stdout}"))
}

/// Runs a query that must succeed; returns its standard output.
fn query(args: &[&str]) -> String {
    let mut all = vec!["query"];
    all.extend_from_slice(args);
    let out = run(&all);
    assert!(out.status.success(), "{args:?}: {}", text(&out.stderr));
    text(&out.stdout)
}

/// Runs a query that must fail: its message, after checking that nothing was written
/// into `dir` beyond the files `keep`.
fn refused(args: &[&str], dir: &Path, keep: &[&str]) -> String {
    let mut all = vec!["query"];
    all.extend_from_slice(args);
    let out = run(&all);
    assert!(!out.status.success(), "{args:?} should fail");
    let mut names = query_listing(dir);
    names.retain(|n| !keep.contains(&n.as_str()));
    assert!(names.is_empty(), "{args:?} left {names:?} behind");
    text(&out.stderr)
}

fn path_str(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn pairs_in_csv_agree_with_the_library_bit_for_bit() {
    let dir = scratch("query-csv");
    let rows = pair_rows(3000, 1);
    let input = dir.join("pairs.csv");
    write_csv(&input, &PAIR_COLUMNS, &rows);
    for mode in Accuracy::ALL {
        let out = dir.join(format!("{mode}.csv"));
        let stdout = query(&[
            path_str(&input),
            "--accuracy",
            mode.name(),
            "--t-max",
            "3",
            "--geometry",
            "--out",
            path_str(&out),
        ]);
        let options = QueryOptions::new(3.0, mode).unwrap().with_geometry(true);
        let (times, geometry) = library_pairs(&rows, options);
        let (header, columns) = read_csv(&out);
        assert_eq!(header, ["time", "px", "py", "pz", "nx", "ny", "nz"]);
        assert_eq!(bits(&parse::<f32>(&columns[0])), bits(&times), "{mode}");
        for k in 0..6 {
            let want: Vec<f64> = geometry.iter().map(|g| g[k]).collect();
            assert_eq!(
                bits64(&parse::<f64>(&columns[k + 1])),
                bits64(&want),
                "{mode} {k}"
            );
        }
        let contacts = times.iter().filter(|t| t.is_finite()).count();
        assert!(
            contacts > 500 && contacts < 2900,
            "{mode}: {contacts} contacts"
        );
        assert!(
            summary(&stdout, "contacts")
                .starts_with(&format!("contacts    {contacts} of 3000 pairs")),
            "{stdout}"
        );
        for key in ["input", "chunks      1 of", "time ", "throughput", "output"] {
            summary(&stdout, key);
        }
    }
    // The default output: beside the input, times only.
    query(&[path_str(&input)]);
    let (header, columns) = read_csv(&dir.join("pairs-toi.csv"));
    assert_eq!(header, ["time"]);
    let (times, _) = library_pairs(&rows, QueryOptions::default());
    assert_eq!(bits(&parse::<f32>(&columns[0])), bits(&times));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn pairs_in_every_npy_layout_agree_with_the_library() {
    let dir = scratch("query-npy");
    let rows = pair_rows(2000, 2);
    let options = QueryOptions::new(5.0, Accuracy::Stable)
        .unwrap()
        .with_geometry(true);
    let (times, geometry) = library_pairs(&rows, options);
    let check = |out: &Path, times: &[f32], geometry: &[[f64; 6]]| {
        assert_eq!(bits(&read_npy::<f32>(&out.join("time.npy"))), bits(times));
        for (k, name) in GEOMETRY.iter().enumerate() {
            let want: Vec<f64> = geometry.iter().map(|g| g[k]).collect();
            let got = read_npy::<f64>(&out.join(format!("{name}.npy")));
            assert_eq!(bits64(&got), bits64(&want), "{name}");
        }
        let mut names = query_listing(out);
        names.sort();
        assert_eq!(
            names,
            [
                "nx.npy", "ny.npy", "nz.npy", "px.npy", "py.npy", "pz.npy", "time.npy"
            ]
        );
    };
    // One (N, 14) f4 array in C order, and in Fortran order.
    for (name, fortran) in [("c.npy", false), ("fortran.npy", true)] {
        let input = dir.join(name);
        write_npy_2d(&input, &rows, fortran, |v, _, _| v);
        let stdout = query(&[path_str(&input), "--t-max", "5", "--geometry"]);
        let out = dir.join(format!("{}-toi", name.trim_end_matches(".npy")));
        assert!(summary(&stdout, "output").contains("directory of .npy columns"));
        check(&out, &times, &geometry);
    }
    // A directory of f4 columns, and the same columns named one by one (any order).
    let cols = dir.join("cols");
    std::fs::create_dir_all(&cols).unwrap();
    for (j, name) in PAIR_COLUMNS.iter().enumerate() {
        let column: Vec<f32> = rows.iter().map(|r| r[j]).collect();
        write_npy_1d(&cols.join(format!("{name}.npy")), &column);
    }
    std::fs::write(cols.join("notes.txt"), "other files are ignored\n").unwrap();
    query(&[path_str(&cols), "--t-max", "5", "--geometry"]);
    check(&dir.join("cols-toi"), &times, &geometry);
    let mut files: Vec<String> = PAIR_COLUMNS
        .iter()
        .rev()
        .map(|c| path_str(&cols.join(format!("{c}.npy"))).to_string())
        .collect();
    let out = dir.join("from-files");
    files.extend(["--t-max", "5", "--geometry", "--out"].map(String::from));
    files.push(path_str(&out).to_string());
    let args: Vec<&str> = files.iter().map(String::as_str).collect();
    query(&args);
    check(&out, &times, &geometry);
    // f8 values are rounded to the nearest f4, as `astype(np.float32)` does.
    let input = dir.join("f8.npy");
    let nudge = |v: f32, i: usize, j: usize| f64::from(v) * (1.0 + ((i + j) % 5) as f64 * 2.5e-8);
    write_npy_2d(&input, &rows, false, nudge);
    let rounded: Vec<[f32; 14]> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| std::array::from_fn(|j| nudge(r[j], i, j) as f32))
        .collect();
    assert!(rounded != rows, "some values round to another f32");
    let (times8, geometry8) = library_pairs(&rounded, options);
    query(&[path_str(&input), "--t-max", "5", "--geometry"]);
    check(&dir.join("f8-toi"), &times8, &geometry8);
    // One .npy array of the times alone.
    let single = dir.join("times.npy");
    query(&[
        path_str(&dir.join("c.npy")),
        "--t-max",
        "5",
        "--out",
        path_str(&single),
    ]);
    assert_eq!(bits(&read_npy::<f32>(&single)), bits(&times));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn spheres_against_shapes_agree_with_earliest_static_contacts() {
    let dir = scratch("query-statics");
    let shapes = dir.join("shapes.toml");
    std::fs::write(&shapes, SHAPES_TOML).unwrap();
    let mut rows = sphere_rows(2500, 3);
    // Falls onto the two identical floors at once: plane 0 by the tie rule.
    rows[0] = [0.0, 0.0, -3.0, 0.0, 0.0, -1.0, 1.0];
    let input = dir.join("spheres.csv");
    write_csv(&input, &SPHERE_COLUMNS, &rows);
    for mode in Accuracy::ALL {
        let out = dir.join(format!("{mode}.csv"));
        let stdout = query(&[
            path_str(&input),
            "--against",
            path_str(&shapes),
            "--accuracy",
            mode.name(),
            "--geometry",
            "--out",
            path_str(&out),
        ]);
        assert!(
            summary(&stdout, "input")
                .contains("2500 spheres against 6 shapes (3 planes, 2 cylinders, 1 container)"),
            "{stdout}"
        );
        let want = library_statics(&rows, QueryOptions::new(f32::INFINITY, mode).unwrap());
        let (header, columns) = read_csv(&out);
        assert_eq!(
            header,
            ["time", "kind", "index", "px", "py", "pz", "nx", "ny", "nz"]
        );
        let times: Vec<f32> = want.iter().map(|w| w.0).collect();
        assert_eq!(bits(&parse::<f32>(&columns[0])), bits(&times), "{mode}");
        let kinds: Vec<&str> = want
            .iter()
            .map(|w| ["none", "plane", "cylinder", "container"][usize::from(w.1)])
            .collect();
        assert_eq!(columns[1], kinds, "{mode}");
        let indices: Vec<i64> = want.iter().map(|w| w.2).collect();
        assert_eq!(parse::<i64>(&columns[2]), indices, "{mode}");
        for k in 0..6 {
            let g: Vec<f64> = want.iter().map(|w| w.3[k]).collect();
            assert_eq!(
                bits64(&parse::<f64>(&columns[3 + k])),
                bits64(&g),
                "{mode} {k}"
            );
        }
        assert_eq!((times[0], kinds[0], indices[0]), (2.0, "plane", 0));
        for kind in ["plane", "cylinder", "container"] {
            assert!(kinds.contains(&kind), "{mode}: no {kind} hit");
        }
    }
    // The same spheres as .npy columns: kind as u8 codes, index as i64.
    let cols = dir.join("cols");
    std::fs::create_dir_all(&cols).unwrap();
    for (j, name) in SPHERE_COLUMNS.iter().enumerate() {
        let column: Vec<f32> = rows.iter().map(|r| r[j]).collect();
        write_npy_1d(&cols.join(format!("{name}.npy")), &column);
    }
    query(&[path_str(&cols), "--against", path_str(&shapes)]);
    let want = library_statics(&rows, QueryOptions::default());
    let out = dir.join("cols-toi");
    let times: Vec<f32> = want.iter().map(|w| w.0).collect();
    assert_eq!(bits(&read_npy::<f32>(&out.join("time.npy"))), bits(&times));
    let kinds: Vec<u8> = want.iter().map(|w| w.1).collect();
    assert_eq!(read_npy::<u8>(&out.join("kind.npy")), kinds);
    let indices: Vec<i64> = want.iter().map(|w| w.2).collect();
    assert_eq!(read_npy::<i64>(&out.join("index.npy")), indices);
    // A whole scene file is a shapes file too (its spheres are not queried).
    let stdout = query(&[
        path_str(&input),
        "--against",
        &shipped("granular_jet"),
        "--out",
        path_str(&dir.join("jet.csv")),
    ]);
    assert!(
        summary(&stdout, "input").contains("2500 spheres against"),
        "{stdout}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Many shapes of each kind (the CLI answers them through `earliest_static_contacts`, few
/// through `static_times` one by one): the same bits, ties to the lowest index.
#[test]
fn many_shapes_of_a_kind_agree_with_the_library() {
    let dir = scratch("query-many-shapes");
    let mut rng = Rng::new(21);
    let mut v = |lo: f64, hi: f64| rng.range(lo, hi) as f32;
    let mut toml = String::new();
    let (mut planes, mut cylinders, mut containers) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..7 {
        // Planes 5 and 6 repeat planes 0 and 1: ties go to the lower index.
        let (p, n) = if k >= 5 {
            planes[k - 5]
        } else {
            (
                [v(-9.0, 9.0), v(-9.0, 9.0), v(-9.0, 9.0)],
                [v(-1.0, 1.0), v(-1.0, 1.0), v(0.1, 1.0)],
            )
        };
        planes.push((p, n));
        toml.push_str(&format!("[[plane]]\npoint = {p:?}\nnormal = {n:?}\n\n"));
    }
    for _ in 0..6 {
        let (p1, p2, r) = (
            [v(-8.0, 8.0), v(-8.0, 8.0), 0.0],
            [v(-8.0, 8.0), v(-8.0, 8.0), 5.0],
            v(0.1, 2.0),
        );
        cylinders.push((p1, p2, r));
        toml.push_str(&format!(
            "[[cylinder]]\np1 = {p1:?}\np2 = {p2:?}\nradius = {r:?}\n\n"
        ));
    }
    for _ in 0..5 {
        let (c, r) = ([v(-1.0, 1.0), v(-1.0, 1.0), v(-1.0, 1.0)], v(15.0, 25.0));
        containers.push((c, r));
        toml.push_str(&format!(
            "[[container]]\ncentre = {c:?}\nradius = {r:?}\n\n"
        ));
    }
    let shapes = dir.join("many.toml");
    std::fs::write(&shapes, toml).unwrap();
    let rows = sphere_rows(4000, 22);
    let input = dir.join("s.csv");
    write_csv(&input, &SPHERE_COLUMNS, &rows);
    let planes: Vec<Plane> = planes
        .iter()
        .map(|&(p, n)| Plane::new(p, n).unwrap())
        .collect();
    let cylinders: Vec<Cylinder> = cylinders
        .iter()
        .map(|&(a, b, r)| Cylinder::new(a, b, r).unwrap())
        .collect();
    let containers: Vec<Container> = containers
        .iter()
        .map(|&(c, r)| Container::new(c, r).unwrap())
        .collect();
    for mode in Accuracy::ALL {
        let out = dir.join(format!("{mode}.csv"));
        query(&[
            path_str(&input),
            "--against",
            path_str(&shapes),
            "--accuracy",
            mode.name(),
            "--t-max",
            "10",
            "--geometry",
            "--out",
            path_str(&out),
        ]);
        let options = QueryOptions::new(10.0, mode).unwrap();
        let want = library_statics_of(&rows, options, &planes, &cylinders, &containers);
        let (_, columns) = read_csv(&out);
        let times: Vec<f32> = want.iter().map(|w| w.0).collect();
        assert_eq!(bits(&parse::<f32>(&columns[0])), bits(&times), "{mode}");
        let indices: Vec<i64> = want.iter().map(|w| w.2).collect();
        assert_eq!(parse::<i64>(&columns[2]), indices, "{mode}");
        for k in 0..6 {
            let g: Vec<f64> = want.iter().map(|w| w.3[k]).collect();
            assert_eq!(
                bits64(&parse::<f64>(&columns[3 + k])),
                bits64(&g),
                "{mode} {k}"
            );
        }
        let kinds: Vec<&str> = columns[1].iter().map(String::as_str).collect();
        for kind in ["plane", "cylinder", "container"] {
            assert!(kinds.contains(&kind), "{mode}: no {kind} hit");
        }
        assert!(
            kinds
                .iter()
                .zip(&indices)
                .all(|(k, &i)| *k != "plane" || i < 5),
            "{mode}: a repeated plane won a tie"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_file_larger_than_the_chunk_is_streamed_in_chunks() {
    let dir = scratch("query-stream");
    let rows = pair_rows(25_000, 4);
    let cols = dir.join("big");
    std::fs::create_dir_all(&cols).unwrap();
    for (j, name) in PAIR_COLUMNS.iter().enumerate() {
        let column: Vec<f32> = rows.iter().map(|r| r[j]).collect();
        write_npy_1d(&cols.join(format!("{name}.npy")), &column);
    }
    let (times, _) = library_pairs(&rows, QueryOptions::new(4.0, Accuracy::Double).unwrap());
    let stdout = query(&[
        path_str(&cols),
        "--chunk-rows",
        "1000",
        "--t-max",
        "4",
        "--accuracy",
        "double",
    ]);
    assert_eq!(
        summary(&stdout, "chunks"),
        "chunks      25 of at most 1000 rows"
    );
    assert_eq!(
        bits(&read_npy::<f32>(&dir.join("big-toi/time.npy"))),
        bits(&times)
    );
    // CSV, with a chunk that does not divide the rows, to CSV.
    let csv = dir.join("big.csv");
    write_csv(&csv, &PAIR_COLUMNS, &rows[..2500]);
    let stdout = query(&[
        path_str(&csv),
        "--chunk-rows",
        "300",
        "--t-max",
        "4",
        "--accuracy",
        "double",
    ]);
    assert_eq!(
        summary(&stdout, "chunks"),
        "chunks      9 of at most 300 rows"
    );
    let (_, columns) = read_csv(&dir.join("big-toi.csv"));
    assert_eq!(bits(&parse::<f32>(&columns[0])), bits(&times[..2500]));
    // Spheres against shapes, chunk by chunk.
    let shapes = dir.join("shapes.toml");
    std::fs::write(&shapes, SHAPES_TOML).unwrap();
    let spheres = sphere_rows(3001, 5);
    let input = dir.join("spheres.csv");
    write_csv(&input, &SPHERE_COLUMNS, &spheres);
    let stdout = query(&[
        path_str(&input),
        "--against",
        path_str(&shapes),
        "--chunk-rows",
        "1000",
    ]);
    assert_eq!(
        summary(&stdout, "chunks"),
        "chunks      4 of at most 1000 rows"
    );
    let (_, columns) = read_csv(&dir.join("spheres-toi.csv"));
    let want: Vec<f32> = library_statics(&spheres, QueryOptions::default())
        .iter()
        .map(|w| w.0)
        .collect();
    assert_eq!(bits(&parse::<f32>(&columns[0])), bits(&want));
    std::fs::remove_dir_all(&dir).ok();
}

/// The peak memory of a query of a file 20 times the chunk stays near that of a small
/// chunk, far below that of the whole file in one chunk.
#[test]
fn memory_stays_flat_when_a_file_is_streamed() {
    let dir = scratch("query-memory");
    let rows = pair_rows(400_000, 6);
    let input = dir.join("pairs.npy");
    write_npy_2d(&input, &rows, false, |v, _, _| v);
    let peak = |chunk: &str| -> f64 {
        let stdout = query(&[path_str(&input), "--chunk-rows", chunk]);
        let line = summary(&stdout, "peak memory");
        line.split_whitespace().nth(2).unwrap().parse().unwrap()
    };
    let whole = peak("1048576");
    let streamed = peak("20000");
    // The whole file: 22 MiB of columns, 24 MiB of stores, 1.6 MiB of times at least.
    assert!(
        streamed + 30.0 < whole,
        "streamed {streamed} MiB, whole {whole} MiB"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn malformed_csv_rows_name_their_line_and_column() {
    let dir = scratch("query-malformed");
    let header = PAIR_COLUMNS.join(",");
    let good = "0,0,0,1,0,0,1,6,0,0,0,0,0,1";
    let input = dir.join("bad.csv");
    for (row, message) in [
        (
            "0,0,0,1,0,0,1,6,0,0,abc,0,0,1",
            "line 4 (row 1), column bvx: \"abc\" is not a number",
        ),
        (
            "0,0,0,1,0,0,1,6,0,0,0,0,0",
            "line 4: 13 fields, but the header has 14",
        ),
        (
            "0,0,0,1,0,0,1,6,0,0,0,0,0,1,7",
            "line 4: 15 fields, but the header has 14",
        ),
        (
            "0,0,0,1,,0,1,6,0,0,0,0,0,1",
            "line 4 (row 1), column avy: is empty",
        ),
        (
            "0,0,0,1,0,0,1,6,0,0,0,0,0,1e39",
            "line 4 (row 1), column br: 1e39 is beyond the range of f32",
        ),
        (
            "0,0,0,1,0,0,1,6,0,0,0,0,0,\"1",
            "line 4: a quoted field does not end on its line",
        ),
    ] {
        std::fs::write(&input, format!("{header}\n{good}\n\n{row}\n{good}\n")).unwrap();
        let err = refused(&[path_str(&input)], &dir, &["bad.csv"]);
        assert!(
            err.contains(&format!("{}: {message}", input.display())),
            "{err}"
        );
    }
    // Quoted fields, spaces, CRLF and other columns are fine.
    std::fs::write(
        &input,
        format!(
            "id, {}\r\n\"a, \"\"b\"\"\", 0,0,0, 1,0,0, 1, 6,0,0, 0,0,0, 1\r\n",
            PAIR_COLUMNS.join(", ")
        ),
    )
    .unwrap();
    query(&[path_str(&input)]);
    let (_, columns) = read_csv(&dir.join("bad-toi.csv"));
    assert_eq!(columns[0], ["4.0"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn columns_of_the_wrong_name_type_or_length_are_named() {
    let dir = scratch("query-columns");
    // CSV: a missing column, a column twice.
    let input = dir.join("p.csv");
    std::fs::write(&input, "ax,ay,az,avx,avy,avz,ar,bx,by,bz,bvz,br\n").unwrap();
    let err = refused(&[path_str(&input)], &dir, &["p.csv"]);
    assert!(
        err.contains("line 1 (the header): no column bvx: a pairs file has the columns ax, ay"),
        "{err}"
    );
    std::fs::write(&input, "x,y,z,vx,vy,vz,r,r\n").unwrap();
    let shapes = dir.join("shapes.toml");
    std::fs::write(&shapes, SHAPES_TOML).unwrap();
    let err = refused(
        &[path_str(&input), "--against", path_str(&shapes)],
        &dir,
        &["p.csv", "shapes.toml"],
    );
    assert!(err.contains("column r appears more than once"), "{err}");
    // .npy columns: an integer column, a short column, a 2-D column.
    let rows = pair_rows(50, 7);
    let cols = dir.join("cols");
    std::fs::create_dir_all(&cols).unwrap();
    let write_all = || {
        for (j, name) in PAIR_COLUMNS.iter().enumerate() {
            let column: Vec<f32> = rows.iter().map(|r| r[j]).collect();
            write_npy_1d(&cols.join(format!("{name}.npy")), &column);
        }
    };
    let keep = ["p.csv", "shapes.toml", "cols"];
    write_all();
    write_npy_1d(&cols.join("bvx.npy"), &(0..50i64).collect::<Vec<_>>());
    let err = refused(&[path_str(&cols)], &dir, &keep);
    assert!(
        err.contains("column bvx (") && err.contains("dtype '<i8' is not a float (f4 or f8)"),
        "{err}"
    );
    write_all();
    write_npy_1d(&cols.join("ar.npy"), &[1.0f32; 49]);
    let err = refused(&[path_str(&cols)], &dir, &keep);
    assert!(
        err.contains("column ar (") && err.contains("49 rows, but column ax has 50"),
        "{err}"
    );
    write_all();
    write_npy_2d(&cols.join("az.npy"), &[[0.0f32; 2]; 25], false, |v, _, _| v);
    let err = refused(&[path_str(&cols)], &dir, &keep);
    assert!(
        err.contains("column az (") && err.contains("shape (25, 2), expected one dimension (N,)"),
        "{err}"
    );
    // One 2-D array of the wrong width.
    let matrix = dir.join("m.npy");
    write_npy_2d(&matrix, &[[0.0f32; 7]; 3], false, |v, _, _| v);
    let err = refused(
        &[path_str(&matrix)],
        &dir,
        &["p.csv", "shapes.toml", "cols", "m.npy"],
    );
    assert!(
        err.contains("shape (3, 7), expected (N, 14) for a pairs file"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A spheres file queried without `--against` is told to add it (with what a shapes file
/// is), a pairs file queried with it to leave it out; an input with neither layout's columns
/// gets no such hint.
#[test]
fn a_file_of_the_other_layout_is_told_how_to_query_it() {
    let dir = scratch("query-other-layout");
    let spheres = dir.join("s.csv");
    write_csv(&spheres, &SPHERE_COLUMNS, &sphere_rows(3, 5));
    let matrix = dir.join("s.npy");
    write_npy_2d(&matrix, &sphere_rows(3, 5), false, |v, _, _| v);
    let pairs = dir.join("p.csv");
    write_csv(&pairs, &PAIR_COLUMNS, &pair_rows(3, 5));
    let other = dir.join("o.csv");
    std::fs::write(&other, "x,y,z\n0,0,0\n").unwrap();
    let shapes = dir.join("shapes.toml");
    std::fs::write(&shapes, SHAPES_TOML).unwrap();
    let keep = ["s.csv", "s.npy", "p.csv", "o.csv", "shapes.toml"];
    let against = "to query every sphere against static shapes, give the shapes with --against \
                   SHAPES (a TOML or JSON file of [[plane]], [[cylinder]] and [[container]] \
                   tables, as in a scene file; docs/query-format.md)";
    for input in [&spheres, &matrix] {
        let err = refused(&[path_str(input)], &dir, &keep);
        assert!(
            err.contains("these are a spheres file's columns") && err.contains(against),
            "{err}"
        );
    }
    let err = refused(
        &[path_str(&pairs), "--against", path_str(&shapes)],
        &dir,
        &keep,
    );
    assert!(
        err.contains("no column x: a spheres file")
            && err.contains(
                "these are a pairs file's columns: a pairs file is queried without --against"
            ),
        "{err}"
    );
    let err = refused(&[path_str(&other)], &dir, &keep);
    assert!(
        err.contains("no column ax") && !err.contains("--against"),
        "{err}"
    );
    // And with --against, the spheres file is answered.
    query(&[path_str(&spheres), "--against", path_str(&shapes)]);
}

#[test]
fn missing_files_name_their_path() {
    let dir = scratch("query-missing");
    let err = refused(&["/no/such/dir/pairs.csv"], &dir, &[]);
    assert!(err.contains("cannot read /no/such/dir/pairs.csv"), "{err}");
    let cols = dir.join("cols");
    std::fs::create_dir_all(&cols).unwrap();
    for name in &PAIR_COLUMNS[..5] {
        write_npy_1d(&cols.join(format!("{name}.npy")), &[0.0f32; 3]);
    }
    let err = refused(&[path_str(&cols)], &dir, &["cols"]);
    assert!(
        err.contains(&format!("{}: no avz.npy (column avz)", cols.display())),
        "{err}"
    );
    let csv = dir.join("s.csv");
    write_csv(&csv, &SPHERE_COLUMNS, &sphere_rows(3, 8));
    let err = refused(
        &[path_str(&csv), "--against", "/no/such/shapes.toml"],
        &dir,
        &["cols", "s.csv"],
    );
    assert!(err.contains("cannot read /no/such/shapes.toml"), "{err}");
    let ax = path_str(&cols.join("ax.npy")).to_string();
    let err = refused(&[&ax, "/no/such/ay.npy"], &dir, &["cols", "s.csv"]);
    assert!(err.contains("cannot read /no/such/ay.npy"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn nan_infinite_and_negative_values_name_their_row_and_column() {
    let dir = scratch("query-values");
    let rows = pair_rows(40, 9);
    let input = dir.join("p.csv");
    for (j, value, message) in [
        (
            4,
            "nan",
            "column avy = NaN: sphere velocity is NaN or infinite",
        ),
        (
            7,
            "-inf",
            "column bx = -inf: sphere centre is NaN or infinite",
        ),
        (13, "-0.5", "column br = -0.5: sphere radius is negative"),
    ] {
        let mut text = PAIR_COLUMNS.join(",") + "\n";
        for (i, r) in rows.iter().enumerate() {
            let mut fields: Vec<String> = r.iter().map(|v| format!("{v:?}")).collect();
            if i == 17 {
                fields[j] = value.into();
            }
            text.push_str(&fields.join(","));
            text.push('\n');
        }
        std::fs::write(&input, text).unwrap();
        let err = refused(&[path_str(&input), "--chunk-rows", "8"], &dir, &["p.csv"]);
        assert!(
            err.contains(&format!("{}: line 19 (row 17), {message}", input.display())),
            "{err}"
        );
    }
    // .npy: the row counted from 0, and the column.
    let cols = dir.join("cols");
    std::fs::create_dir_all(&cols).unwrap();
    for (j, name) in SPHERE_COLUMNS.iter().enumerate() {
        let mut column: Vec<f32> = sphere_rows(40, 10).iter().map(|r| r[j]).collect();
        if *name == "vz" {
            column[33] = f32::INFINITY;
        }
        write_npy_1d(&cols.join(format!("{name}.npy")), &column);
    }
    let shapes = dir.join("shapes.toml");
    std::fs::write(&shapes, SHAPES_TOML).unwrap();
    let err = refused(
        &[path_str(&cols), "--against", path_str(&shapes)],
        &dir,
        &["p.csv", "cols", "shapes.toml"],
    );
    assert!(
        err.contains(&format!(
            "{}: row 33, column vz = inf: sphere velocity is NaN or infinite",
            cols.display()
        )),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_failed_query_leaves_nothing_behind_and_earlier_results_whole() {
    let dir = scratch("query-atomic");
    let mut rows = pair_rows(3000, 11);
    rows[2500][6] = -1.0; // in the third chunk, after two were written
    let input = dir.join("p.csv");
    write_csv(&input, &PAIR_COLUMNS, &rows);
    let err = refused(
        &[path_str(&input), "--chunk-rows", "1000"],
        &dir,
        &["p.csv"],
    );
    assert!(
        err.contains("line 2502 (row 2500), column ar = -1: sphere radius is negative"),
        "{err}"
    );
    // An earlier result is kept whole, in CSV and as a directory of .npy columns.
    let old_csv = dir.join("p-toi.csv");
    std::fs::write(&old_csv, "time\n1.0\n").unwrap();
    let old_dir = dir.join("old");
    std::fs::create_dir_all(&old_dir).unwrap();
    write_npy_1d(&old_dir.join("time.npy"), &[1.0f32]);
    for out in [&old_csv, &old_dir] {
        refused(
            &[
                path_str(&input),
                "--chunk-rows",
                "1000",
                "--out",
                path_str(out),
            ],
            &dir,
            &["p.csv", "p-toi.csv", "old"],
        );
    }
    assert_eq!(std::fs::read_to_string(&old_csv).unwrap(), "time\n1.0\n");
    assert_eq!(read_npy::<f32>(&old_dir.join("time.npy")), [1.0]);
    assert_eq!(query_listing(&old_dir), ["time.npy"]);
    // A good query replaces the old directory whole.
    rows[2500][6] = 1.0;
    write_csv(&input, &PAIR_COLUMNS, &rows);
    query(&[path_str(&input), "--out", path_str(&old_dir), "--geometry"]);
    assert_eq!(read_npy::<f32>(&old_dir.join("time.npy")).len(), 3000);
    assert_eq!(query_listing(&old_dir).len(), 7);
    // A directory holding anything else is never replaced.
    let foreign = dir.join("foreign");
    std::fs::create_dir_all(&foreign).unwrap();
    std::fs::write(foreign.join("thesis.tex"), "keep me\n").unwrap();
    let err = refused(
        &[path_str(&input), "--out", path_str(&foreign)],
        &dir,
        &["p.csv", "p-toi.csv", "old", "foreign"],
    );
    assert!(
        err.contains("holds thesis.tex, which is not a result column"),
        "{err}"
    );
    assert_eq!(query_listing(&foreign), ["thesis.tex"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_bad_shapes_file_names_the_field_and_line() {
    let dir = scratch("query-shapes");
    let input = dir.join("s.csv");
    write_csv(&input, &SPHERE_COLUMNS, &sphere_rows(5, 12));
    let shapes = dir.join("shapes.toml");
    let keep = ["s.csv", "shapes.toml"];
    for (text, message) in [
        (
            "[[plane]]\npoint = [0.0, 0.0, 0.0]\nnormall = [0.0, 0.0, 1.0]\n",
            "line 3, column 1",
        ),
        (
            "[[plane]]\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n\n[[cylinder]]\np1 = [1.0, 1.0, 1.0]\np2 = [1.0, 1.0, 1.0]\nradius = 1.0\n",
            "line 7: cylinder 0: cylinder axis has zero length",
        ),
        (
            "# nothing here\n",
            "no [[plane]], [[cylinder]] or [[container]]",
        ),
    ] {
        std::fs::write(&shapes, text).unwrap();
        let err = refused(
            &[path_str(&input), "--against", path_str(&shapes)],
            &dir,
            &keep,
        );
        assert!(
            err.contains(&format!("{}: ", shapes.display())) && err.contains(message),
            "{err}"
        );
    }
    let json = dir.join("shapes.json");
    std::fs::write(
        &json,
        "{\n  \"plane\": [\n    {\"point\": [0, 0, 0], \"normal\": [0, 0, 0]}\n  ]\n}\n",
    )
    .unwrap();
    let err = refused(
        &[path_str(&input), "--against", path_str(&json)],
        &dir,
        &["s.csv", "shapes.toml", "shapes.json"],
    );
    assert!(
        err.contains("plane 0: plane normal has zero length"),
        "{err}"
    );
    std::fs::write(
        &json,
        "{\n  \"plane\": [\n    {\"point\": [0, 0, 0], \"normal\": [0, 0, 1]}\n  ]\n}\n",
    )
    .unwrap();
    query(&[path_str(&input), "--against", path_str(&json)]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_arguments_are_refused_before_any_output() {
    let dir = scratch("query-args");
    let input = dir.join("p.csv");
    write_csv(&input, &PAIR_COLUMNS, &pair_rows(10, 13));
    let p = path_str(&input);
    let keep = ["p.csv"];
    for (args, message) in [
        (
            vec![p, "--chunk-rows", "0"],
            "--chunk-rows 0 must be between 1 and",
        ),
        (
            vec![p, "--t-max=-1"],
            "--t-max must be zero or more (or inf for no end), got -1",
        ),
        (vec![p, "--accuracy", "fast"], "unknown accuracy mode"),
        (
            vec![p, "--out", "/tmp/x.txt"],
            "cannot tell the format from the extension .txt",
        ),
        (vec![p, "--out", p], "are the same file"),
    ] {
        let err = refused(&args, &dir, &keep);
        assert!(err.contains(message), "{args:?}: {err}");
    }
    let out = dir.join("x.npy");
    let err = refused(&[p, "--geometry", "--out", path_str(&out)], &dir, &keep);
    assert!(err.contains("one .npy array holds one column"), "{err}");
    let unknown = dir.join("p.dat");
    std::fs::write(&unknown, "").unwrap();
    let err = refused(&[path_str(&unknown)], &dir, &["p.csv", "p.dat"]);
    assert!(
        err.contains("cannot tell the format from the name"),
        "{err}"
    );
    #[cfg(not(feature = "parquet"))]
    {
        let parquet = dir.join("p.parquet");
        std::fs::write(&parquet, "").unwrap();
        let err = refused(
            &[path_str(&parquet)],
            &dir,
            &["p.csv", "p.dat", "p.parquet"],
        );
        assert!(err.contains("need the `parquet` feature"), "{err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Parquet and Arrow IPC, with the `parquet` feature.
#[cfg(feature = "parquet")]
mod columnar {
    use std::path::Path;
    use std::sync::Arc;

    use arrow_array::cast::AsArray;
    use arrow_array::types::{Float32Type, Float64Type, Int64Type, UInt8Type};
    use arrow_array::{ArrayRef, Float32Array, Float64Array, Int64Array, RecordBatch};
    use arrow_schema::{DataType, Field, Schema};
    use parquet::arrow::ArrowWriter;
    use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
    use parquet::basic::{Compression, ZstdLevel};
    use parquet::file::properties::WriterProperties;

    use super::*;

    /// A table of `rows` by name: every column f32 but `ar` (f64), and an extra `id`.
    fn table<const N: usize>(names: &[&str], rows: &[[f32; N]], nullable: bool) -> RecordBatch {
        let mut fields = vec![Field::new("id", DataType::Int64, false)];
        let mut arrays: Vec<ArrayRef> =
            vec![Arc::new(Int64Array::from_iter_values(0..rows.len() as i64))];
        for (j, name) in names.iter().enumerate() {
            let values = rows.iter().map(|r| r[j]);
            if *name == "ar" {
                fields.push(Field::new(*name, DataType::Float64, nullable));
                arrays.push(Arc::new(Float64Array::from_iter_values(
                    values.map(f64::from),
                )));
            } else {
                fields.push(Field::new(*name, DataType::Float32, nullable));
                arrays.push(Arc::new(Float32Array::from_iter_values(values)));
            }
        }
        RecordBatch::try_new(Arc::new(Schema::new(fields)), arrays).unwrap()
    }

    fn write_parquet(path: &Path, batch: &RecordBatch, compression: Compression, group: usize) {
        let props = WriterProperties::builder()
            .set_compression(compression)
            .set_max_row_group_row_count(Some(group))
            .build();
        let file = std::fs::File::create(path).unwrap();
        let mut w = ArrowWriter::try_new(file, batch.schema(), Some(props)).unwrap();
        w.write(batch).unwrap();
        w.close().unwrap();
    }

    fn read_parquet(path: &Path) -> (Vec<RecordBatch>, usize) {
        let file = std::fs::File::open(path).unwrap();
        let builder = ParquetRecordBatchReaderBuilder::try_new(file).unwrap();
        let groups = builder.metadata().num_row_groups();
        for g in builder.metadata().row_groups() {
            for c in g.columns() {
                assert_eq!(c.compression(), Compression::SNAPPY);
            }
        }
        (
            builder.build().unwrap().map(Result::unwrap).collect(),
            groups,
        )
    }

    fn f32_column(batches: &[RecordBatch], name: &str) -> Vec<f32> {
        batches
            .iter()
            .flat_map(|b| {
                b.column_by_name(name)
                    .unwrap()
                    .as_primitive::<Float32Type>()
                    .values()
                    .to_vec()
            })
            .collect()
    }

    fn f64_column(batches: &[RecordBatch], name: &str) -> Vec<f64> {
        batches
            .iter()
            .flat_map(|b| {
                b.column_by_name(name)
                    .unwrap()
                    .as_primitive::<Float64Type>()
                    .values()
                    .to_vec()
            })
            .collect()
    }

    #[test]
    fn parquet_and_arrow_ipc_agree_with_the_library_bit_for_bit() {
        let dir = scratch("query-parquet");
        let rows = pair_rows(2600, 14);
        let batch = table(&PAIR_COLUMNS, &rows, false);
        let input = dir.join("pairs.parquet");
        write_parquet(&input, &batch, Compression::SNAPPY, 700);
        let options = QueryOptions::new(5.0, Accuracy::Textbook)
            .unwrap()
            .with_geometry(true);
        let (times, geometry) = library_pairs(&rows, options);
        let stdout = query(&[
            path_str(&input),
            "--t-max",
            "5",
            "--accuracy",
            "textbook",
            "--geometry",
            "--chunk-rows",
            "1000",
        ]);
        assert_eq!(
            summary(&stdout, "chunks"),
            "chunks      3 of at most 1000 rows"
        );
        let (out, groups) = read_parquet(&dir.join("pairs-toi.parquet"));
        assert_eq!(groups, 3, "one row group per chunk");
        assert_eq!(bits(&f32_column(&out, "time")), bits(&times));
        for (k, name) in GEOMETRY.iter().enumerate() {
            let want: Vec<f64> = geometry.iter().map(|g| g[k]).collect();
            assert_eq!(bits64(&f64_column(&out, name)), bits64(&want), "{name}");
        }
        // Uncompressed Parquet in, Arrow IPC (file and stream) out and back in.
        let plain = dir.join("plain.parquet");
        write_parquet(&plain, &batch, Compression::UNCOMPRESSED, 1 << 20);
        for (name, stream) in [("r.arrow", false), ("r.arrows", true)] {
            let ipc = dir.join(name);
            query(&[
                path_str(&plain),
                "--t-max",
                "5",
                "--accuracy",
                "textbook",
                "--out",
                path_str(&ipc),
            ]);
            let file = std::fs::File::open(&ipc).unwrap();
            let batches: Vec<RecordBatch> = if stream {
                arrow_ipc::reader::StreamReader::try_new(file, None)
                    .unwrap()
                    .map(Result::unwrap)
                    .collect()
            } else {
                arrow_ipc::reader::FileReader::try_new(file, None)
                    .unwrap()
                    .map(Result::unwrap)
                    .collect()
            };
            assert_eq!(bits(&f32_column(&batches, "time")), bits(&times), "{name}");
        }
        // Arrow IPC in: the pairs as an IPC file, read a chunk at a time.
        let ipc_in = dir.join("in.arrow");
        let mut w = arrow_ipc::writer::FileWriter::try_new(
            std::fs::File::create(&ipc_in).unwrap(),
            &batch.schema(),
        )
        .unwrap();
        w.write(&batch.slice(0, 1000)).unwrap();
        w.write(&batch.slice(1000, 1600)).unwrap();
        w.finish().unwrap();
        let stdout = query(&[
            path_str(&ipc_in),
            "--t-max",
            "5",
            "--accuracy",
            "textbook",
            "--chunk-rows",
            "999",
            "--out",
            path_str(&dir.join("x.csv")),
        ]);
        assert_eq!(
            summary(&stdout, "chunks"),
            "chunks      3 of at most 999 rows"
        );
        let (_, columns) = read_csv(&dir.join("x.csv"));
        assert_eq!(bits(&parse::<f32>(&columns[0])), bits(&times));
        // Spheres against shapes: kind as UInt8, index as Int64.
        let spheres = sphere_rows(1500, 15);
        let input = dir.join("spheres.parquet");
        write_parquet(
            &input,
            &table(&SPHERE_COLUMNS, &spheres, false),
            Compression::SNAPPY,
            1 << 20,
        );
        let shapes = dir.join("shapes.toml");
        std::fs::write(&shapes, SHAPES_TOML).unwrap();
        query(&[path_str(&input), "--against", path_str(&shapes)]);
        let (out, _) = read_parquet(&dir.join("spheres-toi.parquet"));
        let want = library_statics(&spheres, QueryOptions::default());
        let times: Vec<f32> = want.iter().map(|w| w.0).collect();
        assert_eq!(bits(&f32_column(&out, "time")), bits(&times));
        let kinds: Vec<u8> = out
            .iter()
            .flat_map(|b| {
                b.column_by_name("kind")
                    .unwrap()
                    .as_primitive::<UInt8Type>()
                    .values()
                    .to_vec()
            })
            .collect();
        assert_eq!(kinds, want.iter().map(|w| w.1).collect::<Vec<_>>());
        let index: Vec<i64> = out
            .iter()
            .flat_map(|b| {
                b.column_by_name("index")
                    .unwrap()
                    .as_primitive::<Int64Type>()
                    .values()
                    .to_vec()
            })
            .collect();
        assert_eq!(index, want.iter().map(|w| w.2).collect::<Vec<_>>());
        std::fs::remove_dir_all(&dir).ok();
    }

    /// The footer of `path` rewritten so that every column chunk claims `codec`: the
    /// pages stay as they are (the check must refuse the file before reading one).
    fn claim_codec(path: &Path, codec: Compression) {
        use parquet::file::metadata::{ParquetMetaDataReader, ParquetMetaDataWriter};
        let meta = ParquetMetaDataReader::new()
            .parse_and_finish(&std::fs::File::open(path).unwrap())
            .unwrap();
        let bytes = std::fs::read(path).unwrap();
        let footer = u32::from_le_bytes(bytes[bytes.len() - 8..bytes.len() - 4].try_into().unwrap())
            as usize;
        let data_end = bytes.len() - 8 - footer;
        let mut builder = meta.into_builder();
        let groups = builder
            .take_row_groups()
            .into_iter()
            .map(|g| {
                let columns = g
                    .columns()
                    .iter()
                    .map(|c| {
                        c.clone()
                            .into_builder()
                            .set_compression(codec)
                            .build()
                            .unwrap()
                    })
                    .collect();
                g.into_builder()
                    .set_column_metadata(columns)
                    .build()
                    .unwrap()
            })
            .collect();
        let meta = builder.set_row_groups(groups).build();
        let mut out = bytes[..data_end].to_vec();
        ParquetMetaDataWriter::new(&mut out, &meta)
            .finish()
            .unwrap();
        std::fs::write(path, out).unwrap();
    }

    #[test]
    fn a_codec_this_build_lacks_is_named_not_a_panic() {
        let dir = scratch("query-codec");
        let rows = pair_rows(100, 16);
        let input = dir.join("z.parquet");
        for (codec, name) in [
            (Compression::ZSTD(ZstdLevel::default()), "ZSTD"),
            (Compression::LZ4_RAW, "LZ4_RAW"),
        ] {
            write_parquet(
                &input,
                &table(&PAIR_COLUMNS, &rows, false),
                Compression::UNCOMPRESSED,
                1 << 20,
            );
            claim_codec(&input, codec);
            let err = refused(&[path_str(&input)], &dir, &["z.parquet"]);
            assert!(
                err.contains(&format!(
                    "{}: column ax is compressed with {name}, which this build cannot decode",
                    input.display()
                )),
                "{err}"
            );
            assert!(!err.contains("panicked"), "{err}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A Parquet file twenty times the chunk, in row groups of 50 000 rows: the peak
    /// memory stays far below that of the whole file in one chunk, and the results are
    /// the same.
    #[test]
    fn a_parquet_file_larger_than_the_chunk_is_streamed_with_flat_memory() {
        let dir = scratch("query-parquet-memory");
        let rows = pair_rows(400_000, 18);
        let input = dir.join("big.parquet");
        write_parquet(
            &input,
            &table(&PAIR_COLUMNS, &rows, false),
            Compression::SNAPPY,
            50_000,
        );
        let run = |chunk: &str, out: &str| -> (f64, String) {
            let out = dir.join(out);
            let stdout = query(&[
                path_str(&input),
                "--chunk-rows",
                chunk,
                "--out",
                path_str(&out),
            ]);
            let peak = summary(&stdout, "peak memory")
                .split_whitespace()
                .nth(2)
                .unwrap()
                .parse()
                .unwrap();
            (peak, stdout)
        };
        let (whole, _) = run("1048576", "whole.parquet");
        let (streamed, stdout) = run("20000", "streamed.parquet");
        assert_eq!(
            summary(&stdout, "chunks"),
            "chunks      20 of at most 20000 rows"
        );
        assert!(
            streamed + 30.0 < whole,
            "streamed {streamed} MiB, whole {whole} MiB"
        );
        let (times, _) = library_pairs(&rows, QueryOptions::default());
        for name in ["whole.parquet", "streamed.parquet"] {
            let (out, _) = read_parquet(&dir.join(name));
            assert_eq!(bits(&f32_column(&out, "time")), bits(&times), "{name}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn nulls_and_wrong_types_in_parquet_are_named() {
        let dir = scratch("query-parquet-bad");
        let rows = pair_rows(30, 17);
        let good = table(&PAIR_COLUMNS, &rows, true);
        // A null in column bvz, row 21.
        let mut columns = good.columns().to_vec();
        let k = good.schema().index_of("bvz").unwrap();
        let values: Vec<Option<f32>> = rows
            .iter()
            .enumerate()
            .map(|(i, r)| (i != 21).then_some(r[12]))
            .collect();
        columns[k] = Arc::new(Float32Array::from(values));
        let input = dir.join("n.parquet");
        write_parquet(
            &input,
            &RecordBatch::try_new(good.schema(), columns).unwrap(),
            Compression::SNAPPY,
            1 << 20,
        );
        let err = refused(
            &[path_str(&input), "--chunk-rows", "8"],
            &dir,
            &["n.parquet"],
        );
        assert!(
            err.contains(&format!("{}: row 21, column bvz: null", input.display())),
            "{err}"
        );
        // An integer column where a float is expected.
        let mut fields: Vec<Field> = good
            .schema()
            .fields()
            .iter()
            .map(|f| f.as_ref().clone())
            .collect();
        let mut columns = good.columns().to_vec();
        let k = good.schema().index_of("az").unwrap();
        fields[k] = Field::new("az", DataType::Int64, false);
        columns[k] = Arc::new(Int64Array::from_iter_values(0..30));
        let input = dir.join("t.parquet");
        write_parquet(
            &input,
            &RecordBatch::try_new(Arc::new(Schema::new(fields)), columns).unwrap(),
            Compression::SNAPPY,
            1 << 20,
        );
        let err = refused(&[path_str(&input)], &dir, &["n.parquet", "t.parquet"]);
        assert!(
            err.contains("column az has type Int64, expected Float32 or Float64"),
            "{err}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}

/// The names in `dir`, sorted (query tests).
fn query_listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// `--t-max` is rounded down to the kernels' f32, never up: a pair meeting at exactly 4 is not
/// reported for a window ending at 3.9999999 (whose nearest f32 is 4), and the summary names
/// the window used.
#[test]
fn a_window_end_is_rounded_down_to_f32() {
    let dir = scratch("query-window");
    let input = dir.join("pair.csv");
    // A gap of 8 closed at speed 2: contact at t = 4, exactly.
    write_csv(
        &input,
        &PAIR_COLUMNS,
        &[[0., 0., 0., 0., 0., 0., 1., 10., 0., 0., -2., 0., 0., 1.]],
    );
    for (t_max, want) in [("4", "4.0"), ("3.9999999", "inf")] {
        let out = dir.join(format!("{t_max}.csv"));
        let stdout = query(&[path_str(&input), "--t-max", t_max, "--out", path_str(&out)]);
        let (_, columns) = read_csv(&out);
        assert_eq!(columns[0], [want], "--t-max {t_max}");
        let used = if t_max == "4" { "4" } else { "3.9999998" };
        assert!(
            summary(&stdout, "query").contains(&format!("t_max {used},")),
            "{stdout}"
        );
    }
}
