//! Byte-level property tests of `spheresweep query`'s readers: random bytes and mutated valid
//! files (CSV, .npy; Parquet and Arrow IPC with the `parquet` feature) run through the whole
//! query; none panics, and every refusal names the input file (CSV ones also the line).

use std::sync::atomic::{AtomicUsize, Ordering};

use proptest::prelude::*;

use super::{Args, run};
use spheresweep::Accuracy;

/// Writes `bytes` as `name` in a fresh directory and queries it (pairs, or spheres against a
/// floor), in chunks of 3 rows; the error text if it is refused.
fn query_bytes(name: &str, bytes: &[u8], spheres: bool) -> Result<(), String> {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "spheresweep-readers-{}-{}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join(name);
    std::fs::write(&input, bytes).unwrap();
    let against = spheres.then(|| {
        let p = dir.join("floor.toml");
        std::fs::write(&p, "[[plane]]\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n").unwrap();
        p
    });
    let args = Args {
        input: vec![input],
        against,
        out: Some(dir.join("out.csv")),
        accuracy: Accuracy::Stable,
        t_max: f32::INFINITY,
        geometry: true,
        chunk_rows: 3,
        force: false,
    };
    let result = run(&args).map_err(|e| e.to_string());
    let _ = std::fs::remove_dir_all(&dir);
    result
}

const PAIRS_CSV: &str = "ax,ay,az,avx,avy,avz,ar,bx,by,bz,bvx,bvy,bvz,br\n\
0,0,0,1,0,0,1,5,0,0,0,0,0,1\n\
0,0,0,0,1,0,0.5,0,9,0,0,-1,0,0.5\n\
1e3,0,0,0,0,0,1,0,0,0,0,0,0,1\n\
0,0,0,1,1,1,0.25,3,3,3,-1,-1,-1,0.25\n";

const SPHERES_CSV: &str = "x,y,z,vx,vy,vz,r\n0,0,5,0,0,-1,1\n1,1,3,0,0,1,0.5\n2,2,2,0,0,0,1\n";

/// A little-endian f4 .npy file of `rows` × `cols` values.
fn npy(rows: usize, cols: usize, values: &[f32]) -> Vec<u8> {
    let mut header =
        format!("{{'descr': '<f4', 'fortran_order': False, 'shape': ({rows}, {cols}), }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

fn valid_npy() -> Vec<u8> {
    let row = [
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    let values: Vec<f32> = row.iter().chain(&row).chain(&row).copied().collect();
    npy(3, 14, &values)
}

/// A mutation of a valid file: overwrite, insert or delete bytes, or cut it.
#[derive(Debug, Clone)]
enum Edit {
    Set(usize, u8),
    Insert(usize, Vec<u8>),
    Delete(usize, usize),
    Cut(usize),
}

fn edits() -> impl Strategy<Value = Vec<Edit>> {
    let edit = prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Edit::Set(i, b)),
        (any::<usize>(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(i, b)| Edit::Insert(i, b)),
        (any::<usize>(), 1usize..16).prop_map(|(i, n)| Edit::Delete(i, n)),
        any::<usize>().prop_map(Edit::Cut),
    ];
    prop::collection::vec(edit, 1..5)
}

fn apply(mut bytes: Vec<u8>, edits: &[Edit]) -> Vec<u8> {
    for e in edits {
        let len = bytes.len().max(1);
        match e {
            Edit::Set(i, b) => {
                if !bytes.is_empty() {
                    let i = i % bytes.len();
                    bytes[i] = *b;
                }
            }
            Edit::Insert(i, b) => {
                let i = i % (bytes.len() + 1);
                bytes.splice(i..i, b.iter().copied());
            }
            Edit::Delete(i, n) => {
                let i = i % len;
                let end = (i + n).min(bytes.len());
                if i < end {
                    bytes.drain(i..end);
                }
            }
            Edit::Cut(i) => bytes.truncate(i % len),
        }
    }
    bytes
}

/// CSV refusals name the file and, for a row, its line (a header or a file-level problem may
/// name only the file).
fn check_csv_error(result: Result<(), String>, name: &str) -> Result<(), TestCaseError> {
    if let Err(e) = result {
        prop_assert!(e.contains(name), "the error does not name {name}: {e}");
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_as_csv_are_refused_with_the_file_named(
        bytes in prop::collection::vec(any::<u8>(), 0..300),
        spheres in any::<bool>(),
    ) {
        check_csv_error(query_bytes("random.csv", &bytes, spheres), "random.csv")?;
    }

    #[test]
    fn mutated_csv_files_never_panic(edits in edits(), spheres in any::<bool>()) {
        let valid = if spheres { SPHERES_CSV } else { PAIRS_CSV };
        let bytes = apply(valid.as_bytes().to_vec(), &edits);
        let result = query_bytes("mutated.csv", &bytes, spheres);
        if let Err(e) = &result {
            // A refused row is named by its line.
            if e.contains("row") {
                prop_assert!(e.contains("line"), "a row error without its line: {e}");
            }
        }
        check_csv_error(result, "mutated.csv")?;
    }

    #[test]
    fn random_and_mutated_npy_files_never_panic(
        edits in edits(),
        random in prop::collection::vec(any::<u8>(), 0..200),
        use_random in any::<bool>(),
    ) {
        let bytes = if use_random { random } else { apply(valid_npy(), &edits) };
        if let Err(e) = query_bytes("pairs.npy", &bytes, false) {
            prop_assert!(e.contains("pairs.npy"), "the error does not name the file: {e}");
        }
    }
}

#[cfg(feature = "parquet")]
proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_as_parquet_and_arrow_are_refused_with_the_file_named(
        bytes in prop::collection::vec(any::<u8>(), 0..300),
        magic in any::<bool>(),
    ) {
        for name in ["random.parquet", "random.arrow"] {
            let mut data = bytes.clone();
            if magic && name.ends_with("parquet") {
                // The magic at both ends, so that the footer is parsed.
                data.splice(0..0, *b"PAR1");
                data.extend_from_slice(b"PAR1");
            }
            if let Err(e) = query_bytes(name, &data, false) {
                prop_assert!(e.contains(name), "the error does not name {name}: {e}");
            }
        }
    }
}

/// The valid files the mutations start from are accepted.
#[test]
fn the_valid_files_are_accepted() {
    query_bytes("pairs.csv", PAIRS_CSV.as_bytes(), false).unwrap();
    query_bytes("spheres.csv", SPHERES_CSV.as_bytes(), true).unwrap();
    query_bytes("pairs.npy", &valid_npy(), false).unwrap();
}
