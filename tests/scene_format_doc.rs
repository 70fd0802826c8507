//! docs/scene-format.md against the parser: every ```toml block of the document is a whole
//! scene that parses, builds and starts; and every table the document describes lists exactly
//! the fields the parser accepts, and every `kind`/`response` the values it accepts.
//!
//! The parser's own lists come from its errors: a table with an unknown field is refused with
//! "unknown field `…`, expected one of `a`, `b`, …", an unknown enum value with "unknown
//! variant `…`, expected one of …" (serde's messages for `deny_unknown_fields` structs and
//! unit enums). So a field added to `src/io/scene_file.rs` and not to the document, or the
//! reverse, fails here.
#![cfg(feature = "scene-file")]

use std::collections::{BTreeMap, BTreeSet};

use spheresweep::io::scene_file::SceneFile;

const DOC: &str = include_str!("../docs/scene-format.md");

/// The ```toml blocks of the document, with the line each starts on.
fn toml_blocks() -> Vec<(usize, String)> {
    let mut blocks = Vec::new();
    let mut current: Option<(usize, String)> = None;
    for (i, line) in DOC.lines().enumerate() {
        let trimmed = line.trim_start();
        match current.as_mut() {
            None if trimmed == "```toml" => current = Some((i + 1, String::new())),
            Some(_) if trimmed == "```" => blocks.push(current.take().unwrap()),
            Some((_, text)) => {
                text.push_str(line);
                text.push('\n');
            }
            None => {}
        }
    }
    assert!(current.is_none(), "a ```toml block is not closed");
    blocks
}

#[test]
fn every_toml_example_of_the_document_parses_builds_and_starts() {
    let blocks = toml_blocks();
    assert!(
        blocks.len() >= 2,
        "expected the document's TOML examples, found {}",
        blocks.len()
    );
    for (line, text) in &blocks {
        let scene = SceneFile::from_toml_str(text)
            .unwrap_or_else(|e| panic!("docs/scene-format.md:{line}: {e}"));
        let count = scene.sphere_count();
        let (sim, run) = scene
            .start()
            .unwrap_or_else(|e| panic!("docs/scene-format.md:{line}: {e}"));
        assert_eq!(
            Some(sim.spheres().len()),
            count,
            "docs/scene-format.md:{line}: sphere_count disagrees with the built world"
        );
        assert!(run.t_end > 0.0);
    }
}

/// The names between backticks at the start of `text`'s cells: "`lo`, `hi`" gives both.
fn backticked(cell: &str) -> Vec<String> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_owned)
        .collect()
}

/// For each table of the format (`"run"`, `"effects.pair"`, `"generate"`, …): the fields the
/// document's tables list under it, and for each field the text of its row.
fn documented_fields() -> BTreeMap<String, BTreeMap<String, String>> {
    let mut out: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    let mut table: Option<String> = None;
    for line in DOC.lines() {
        // A section names its table as `[run]`, `[[effects.pair]]`, **`[[plane]]`**.
        let heading = line.starts_with('#') || line.starts_with("**`[");
        if heading {
            table = line
                .split('`')
                .nth(1)
                .filter(|s| s.starts_with('['))
                .map(|s| s.trim_matches(['[', ']']).to_owned());
            continue;
        }
        let (Some(t), Some(row)) = (&table, line.strip_prefix("| `")) else {
            continue;
        };
        let first = row.split('|').next().unwrap_or("");
        for field in backticked(&format!("`{first}")) {
            out.entry(t.clone())
                .or_default()
                .insert(field, line.to_owned());
        }
    }
    out
}

/// The list in a serde "unknown … `x`, expected one of `a`, `b`" message (or "expected `a`"
/// when there is one).
fn expected_list(message: &str) -> BTreeSet<String> {
    let line = message
        .lines()
        .find(|l| l.starts_with("unknown "))
        .unwrap_or_else(|| panic!("no 'unknown field/variant' line in {message:?}"));
    let list = line
        .split_once(", expected ")
        .unwrap_or_else(|| panic!("no list of what is expected in {line:?}"))
        .1;
    backticked(list).into_iter().collect()
}

/// A minimal scene whose table `table` holds an unknown field: the parser's error lists the
/// fields it accepts there.
fn accepted_fields(table: &str) -> BTreeSet<String> {
    let run = if table == "run" {
        ""
    } else {
        "[run]\nt_end = 1\n"
    };
    let header = match table {
        "run" | "boundary" | "effects" => format!("[{table}]"),
        _ => format!("[[{table}]]"),
    };
    let text = format!("{run}{header}\nzz_not_a_field = 1\n");
    let err = SceneFile::from_toml_str(&text)
        .expect_err(&text)
        .to_string();
    assert!(err.contains("zz_not_a_field"), "{text}: {err}");
    expected_list(&err)
}

#[test]
fn the_document_lists_exactly_the_fields_each_table_accepts() {
    let documented = documented_fields();
    let tables: BTreeSet<&str> = documented.keys().map(String::as_str).collect();
    let expected: BTreeSet<&str> = [
        "run",
        "boundary",
        "material",
        "effects",
        "effects.pair",
        "sphere",
        "generate",
        "plane",
        "cylinder",
        "container",
    ]
    .into();
    assert_eq!(tables, expected, "the document's sections");
    for (table, fields) in &documented {
        let fields: BTreeSet<String> = fields.keys().cloned().collect();
        let mut accepted = accepted_fields(table);
        // `[[effects.pair]]` is a table of its own, documented in its own section.
        if table == "effects" {
            accepted.remove("pair");
        }
        assert_eq!(fields, accepted, "fields of [{table}]");
    }
    // The top level: every table above, and nothing else.
    let err = SceneFile::from_toml_str("[run]\nt_end = 1\n[zz_not_a_table]\n")
        .unwrap_err()
        .to_string();
    let mut top = expected_list(&err);
    top.insert("effects.pair".into());
    let expected: BTreeSet<String> = expected.iter().map(|s| s.to_string()).collect();
    assert_eq!(top, expected, "top-level tables");
}

/// The quoted values (`"open"`) in a row's range column.
fn quoted_values(row: &str) -> BTreeSet<String> {
    let cells: Vec<&str> = row.split('|').collect();
    // | field | unit | range | … or | field | range | … (tables without a unit column).
    let range = cells
        .iter()
        .find(|c| c.contains("`\""))
        .unwrap_or_else(|| panic!("no quoted values in {row:?}"));
    backticked(range)
        .into_iter()
        .filter_map(|v| v.strip_prefix('"')?.strip_suffix('"').map(str::to_owned))
        .collect()
}

#[test]
fn the_document_lists_exactly_the_values_each_kind_and_response_accepts() {
    let documented = documented_fields();
    // (table, field, a scene with `field = "zz"` in that table)
    let cases = [
        (
            "boundary",
            "kind",
            "[run]\nt_end = 1\n[boundary]\nkind = \"zz\"\n",
        ),
        (
            "effects",
            "response",
            "[run]\nt_end = 1\n[effects]\nresponse = \"zz\"\n",
        ),
        (
            "generate",
            "kind",
            "[run]\nt_end = 1\n[[generate]]\nkind = \"zz\"\n",
        ),
    ];
    for (table, field, text) in cases {
        let row = &documented[table][field];
        let err = SceneFile::from_toml_str(text).unwrap_err().to_string();
        assert!(err.contains("unknown variant"), "{text}: {err}");
        assert_eq!(quoted_values(row), expected_list(&err), "[{table}] {field}");
    }
    // A pair's response is any of the scene's but "none" (refused when the scene is built).
    let mut pair = quoted_values(&documented["effects"]["response"]);
    pair.remove("none");
    assert_eq!(
        quoted_values(&documented["effects.pair"]["response"]),
        pair,
        "[[effects.pair]] response"
    );
}
