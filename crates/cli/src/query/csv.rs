//! CSV in and out: a header line naming the columns (any order; other columns are read past),
//! then one row per line, read in chunks; results written with round-trip decimals.
//!
//! The reader is line based, so every message names the line of the file as an editor counts
//! it: fields are separated by commas, may be quoted (`"..."`, with `""` for a quote inside),
//! and are trimmed of spaces; blank lines are skipped; a quoted field may not span lines.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::layout::{Chunk, Layout, OutColumn, Results, Values, beyond_f32, kind_name};
use super::{Sink, Source};
use crate::atomic::{AtomicFile, finish_writer};

/// The fields of one line, as byte ranges of it (quotes removed; `""` inside a quoted field
/// is kept as is and only matters to text columns, which are never read).
fn split(line: &[u8], fields: &mut Vec<(usize, usize)>) -> Result<(), &'static str> {
    fields.clear();
    let mut i = 0;
    loop {
        while i < line.len() && (line[i] == b' ' || line[i] == b'\t') {
            i += 1;
        }
        let (start, end);
        if i < line.len() && line[i] == b'"' {
            let mut j = i + 1;
            loop {
                match line[j..].iter().position(|&b| b == b'"') {
                    None => return Err("a quoted field does not end on its line"),
                    Some(k) if line.get(j + k + 1) == Some(&b'"') => j += k + 2,
                    Some(k) => {
                        (start, end) = (i + 1, j + k);
                        i = j + k + 1;
                        break;
                    }
                }
            }
            while i < line.len() && (line[i] == b' ' || line[i] == b'\t') {
                i += 1;
            }
            if i < line.len() && line[i] != b',' {
                return Err("text after a quoted field");
            }
        } else {
            start = i;
            while i < line.len() && line[i] != b',' {
                i += 1;
            }
            let mut e = i;
            while e > start && (line[e - 1] == b' ' || line[e - 1] == b'\t') {
                e -= 1;
            }
            end = e;
        }
        fields.push((start, end));
        if i >= line.len() {
            return Ok(());
        }
        i += 1; // the comma
    }
}

/// Lines read at a time before they are parsed in parallel (a few MiB of text).
const BATCH_LINES: usize = 1 << 16;
/// Lines parsed by one parallel task.
const TASK_LINES: usize = 1 << 12;

/// A CSV input: lines read in batches, each batch parsed in parallel.
pub struct CsvSource {
    path: PathBuf,
    layout: Layout,
    reader: BufReader<File>,
    /// For each input column of the layout, its field in a row.
    fields: Vec<usize>,
    /// Fields in the header (every row has as many).
    width: usize,
    /// Lines read so far.
    line: u64,
    /// Rows read so far.
    rows: u64,
    /// The text of a batch of rows, and where each starts with its line number.
    text: Vec<u8>,
    starts: Vec<(usize, u64)>,
}

impl CsvSource {
    /// Opens `path` and finds the layout's columns in its header (line 1).
    pub fn open(path: &Path, layout: Layout) -> Result<Self, String> {
        let file = File::open(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let mut reader = BufReader::with_capacity(1 << 20, file);
        let mut text = Vec::new();
        reader
            .read_until(b'\n', &mut text)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let header = text.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(&text);
        let at = format!("{}: line 1 (the header)", path.display());
        let header = trim_line(header);
        if header.contains(&b'\r') {
            return Err(format!(
                "{at}: the lines end in a carriage return alone (CR, as on classic Mac OS), which \
                 this reader does not take: convert the file to \\n or \\r\\n line endings (e.g. \
                 tr '\\r' '\\n' < in.csv > out.csv)"
            ));
        }
        if header.iter().all(u8::is_ascii_whitespace) {
            return Err(format!(
                "{at}: empty: expected the names of the columns {}",
                layout.column_list()
            ));
        }
        let mut spans = Vec::new();
        split(header, &mut spans).map_err(|e| format!("{at}: {e}"))?;
        let names: Vec<String> = spans
            .iter()
            .map(|&(a, b)| String::from_utf8_lossy(&header[a..b]).into_owned())
            .collect();
        let mut fields = Vec::with_capacity(layout.columns().len());
        for &col in layout.columns() {
            let mut at_col = names.iter().enumerate().filter(|(_, n)| *n == col);
            match (at_col.next(), at_col.next()) {
                (Some((k, _)), None) => fields.push(k),
                (Some(_), Some(_)) => {
                    return Err(format!("{at}: column {col} appears more than once"));
                }
                (None, _) => {
                    return Err(format!(
                        "{at}: no column {col}: {} has the columns {} (the header has {}){}",
                        layout.file_noun(),
                        layout.column_list(),
                        names.join(", "),
                        layout.other_layout_hint(|c| names.iter().any(|n| n == c))
                    ));
                }
            }
        }
        Ok(Self {
            path: path.to_path_buf(),
            layout,
            reader,
            fields,
            width: names.len(),
            line: 1,
            rows: 0,
            text: Vec::new(),
            starts: Vec::new(),
        })
    }

    /// Reads up to `n` non-blank lines into `text`; returns how many.
    fn read_lines(&mut self, n: usize) -> Result<usize, String> {
        self.text.clear();
        self.starts.clear();
        while self.starts.len() < n {
            let start = self.text.len();
            let got = self
                .reader
                .read_until(b'\n', &mut self.text)
                .map_err(|e| format!("cannot read {}: {e}", self.path.display()))?;
            if got == 0 {
                break;
            }
            self.line += 1;
            if self.text[start..].iter().all(u8::is_ascii_whitespace) {
                self.text.truncate(start);
            } else {
                self.starts.push((start, self.line));
            }
        }
        Ok(self.starts.len())
    }

    /// Parses lines `range` of the batch into one column per input column (rows counted from
    /// `first_row`), or names the first bad field.
    fn parse(
        &self,
        range: std::ops::Range<usize>,
        first_row: u64,
    ) -> Result<Vec<Vec<f32>>, String> {
        let names = self.layout.columns();
        let mut columns = vec![Vec::with_capacity(range.len()); self.fields.len()];
        let mut spans = Vec::with_capacity(self.width);
        for k in range.clone() {
            let (start, line) = self.starts[k];
            let end = self.starts.get(k + 1).map_or(self.text.len(), |s| s.0);
            let at = || format!("{}: line {line}", self.path.display());
            // One UTF-8 check per line; fields split at commas stay on char boundaries.
            let text = std::str::from_utf8(trim_line(&self.text[start..end]))
                .map_err(|_| format!("{}: not UTF-8 text", at()))?;
            split(text.as_bytes(), &mut spans).map_err(|e| format!("{}: {e}", at()))?;
            if spans.len() != self.width {
                return Err(format!(
                    "{}: {} fields, but the header has {}",
                    at(),
                    spans.len(),
                    self.width
                ));
            }
            for ((column, &f), name) in columns.iter_mut().zip(&self.fields).zip(names) {
                let (a, b) = spans[f];
                let value = number(text.get(a..b).unwrap_or_default()).map_err(|problem| {
                    let row = first_row + (k - range.start) as u64;
                    format!("{} (row {row}), column {name}: {problem}", at())
                })?;
                column.push(value);
            }
        }
        Ok(columns)
    }
}

/// A line without its terminator (`\n` or `\r\n`).
fn trim_line(line: &[u8]) -> &[u8] {
    let line = line.strip_suffix(b"\n").unwrap_or(line);
    line.strip_suffix(b"\r").unwrap_or(line)
}

/// The number in a CSV field, or what is wrong with it.
fn number(text: &str) -> Result<f32, String> {
    if text.is_empty() {
        return Err("is empty".into());
    }
    let value = text
        .parse::<f32>()
        .map_err(|_| format!("{text:?} is not a number"))?;
    if value.is_infinite() && !text.to_ascii_lowercase().contains("inf") {
        return Err(beyond_f32(text));
    }
    Ok(value)
}

impl Source for CsvSource {
    fn next(&mut self, max: usize, chunk: &mut Chunk) -> Result<bool, String> {
        chunk.clear(self.rows);
        let mut lines = chunk.lines.take().unwrap_or_default();
        lines.clear();
        while lines.len() < max {
            let n = self.read_lines(BATCH_LINES.min(max - lines.len()))?;
            if n == 0 {
                break;
            }
            // Tasks in order; the first error in file order is the one reported.
            let tasks: Vec<std::ops::Range<usize>> = (0..n)
                .step_by(TASK_LINES)
                .map(|a| a..(a + TASK_LINES).min(n))
                .collect();
            let rows = self.rows;
            let parsed: Vec<Result<Vec<Vec<f32>>, String>> = tasks
                .into_par_iter()
                .map(|r| {
                    let first = rows + r.start as u64;
                    self.parse(r, first)
                })
                .collect();
            for part in parsed {
                for (column, values) in chunk.columns.iter_mut().zip(part?) {
                    column.extend_from_slice(&values);
                }
            }
            lines.extend(self.starts.iter().map(|s| s.1));
            self.rows += n as u64;
        }
        let more = !lines.is_empty();
        chunk.lines = Some(lines);
        Ok(more)
    }

    fn total_rows(&self) -> Option<u64> {
        None
    }
}

/// CSV results: a header of the result columns, one line per input row.
pub struct CsvSink {
    staged: AtomicFile,
    out: BufWriter<File>,
    columns: Vec<OutColumn>,
}

impl CsvSink {
    /// Starts the file (under its temporary name) with the header.
    pub fn create(path: &Path, columns: Vec<OutColumn>) -> Result<Self, String> {
        crate::output::check_writable(path)?;
        let staged = AtomicFile::create(path)?;
        let mut out = staged.writer()?;
        let header: Vec<&str> = columns.iter().map(|c| c.name()).collect();
        writeln!(out, "{}", header.join(",")).map_err(|e| staged.error(e))?;
        Ok(Self {
            staged,
            out,
            columns,
        })
    }
}

impl Sink for CsvSink {
    fn write(&mut self, results: &Results) -> Result<(), String> {
        let values: Vec<Values<'_>> = self.columns.iter().map(|&c| results.values(c)).collect();
        let out = &mut self.out;
        let result = (|| -> std::io::Result<()> {
            for i in 0..results.rows() {
                for (k, v) in values.iter().enumerate() {
                    if k > 0 {
                        out.write_all(b",")?;
                    }
                    match v {
                        Values::F32(x) => write!(out, "{:?}", x[i])?,
                        Values::F64(x) => write!(out, "{:?}", x[i])?,
                        Values::U8(x) => out.write_all(kind_name(x[i]).as_bytes())?,
                        Values::I64(x) => write!(out, "{}", x[i])?,
                    }
                }
                out.write_all(b"\n")?;
            }
            Ok(())
        })();
        result.map_err(|e| self.staged.error(e))
    }

    fn commit(self: Box<Self>) -> Result<(), String> {
        let Self { staged, out, .. } = *self;
        finish_writer(out, |e| staged.error(e))?;
        staged.commit()
    }

    fn path(&self) -> &Path {
        self.staged.path()
    }
}
