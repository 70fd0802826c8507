//! NumPy `.npy` in and out (through `npyz`): one 1-D array per column (a directory, or
//! several files named after their columns), or one 2-D array with a column per input column
//! (`(N, 7)` spheres, `(N, 14)` pairs), in C or Fortran order; `f4` or `f8` (rounded to f32).
//! Read in chunks through buffered readers, so memory stays flat whatever the file's size.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read};
use std::path::{Path, PathBuf};

use npyz::{NpyFile, NpyReader, Order, WriteOptions, WriterBuilder};

use super::layout::{Chunk, Layout, OutColumn, Results, Values, beyond_f32, narrow};
use super::{Sink, Source, guarded};
use crate::atomic::{AtomicDir, AtomicFile};

type In = BufReader<File>;

/// An `f8` element beyond `f32`'s range, `offset` elements into a read: the read stops there.
#[derive(Debug)]
struct Beyond {
    offset: usize,
    value: f64,
}

impl std::fmt::Display for Beyond {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&beyond_f32(crate::number::num(self.value)))
    }
}

impl std::error::Error for Beyond {}

/// `v` as `f32`, or the error that stops a read at element `offset`.
fn rounded(v: f64, offset: usize) -> std::io::Result<f32> {
    narrow(v).ok_or_else(|| std::io::Error::other(Beyond { offset, value: v }))
}

/// A reader of one array's elements, in file order: little-endian floats (what NumPy writes
/// on every common machine) straight from the bytes, anything else through `npyz`'s typed
/// readers.
enum Elements {
    /// Little-endian `f4` (`wide == false`) or `f8`, read in blocks of bytes.
    Raw {
        reader: In,
        wide: bool,
        /// The element the reader is at.
        at: u64,
        bytes: Vec<u8>,
    },
    F32(NpyReader<f32, In>),
    F64(NpyReader<f64, In>),
}

impl Elements {
    /// Reads `n` elements, rounding f64 to f32, and hands each to `put`.
    fn read(&mut self, n: usize, mut put: impl FnMut(usize, f32)) -> std::io::Result<()> {
        let eof = || std::io::Error::from(std::io::ErrorKind::UnexpectedEof);
        match self {
            Elements::Raw {
                reader,
                wide,
                at,
                bytes,
            } => {
                // A block of at most 64 Ki elements at a time: a bounded buffer.
                let size = if *wide { 8 } else { 4 };
                let mut k = 0;
                while k < n {
                    let m = (n - k).min(1 << 16);
                    bytes.resize(m * size, 0);
                    reader.read_exact(bytes)?;
                    if *wide {
                        for (j, b) in bytes.chunks_exact(8).enumerate() {
                            let v = f64::from_le_bytes(b.try_into().map_err(|_| eof())?);
                            put(k + j, rounded(v, k + j)?);
                        }
                    } else {
                        for (j, b) in bytes.chunks_exact(4).enumerate() {
                            put(k + j, f32::from_le_bytes(b.try_into().map_err(|_| eof())?));
                        }
                    }
                    k += m;
                }
                *at += n as u64;
            }
            Elements::F32(r) => {
                for k in 0..n {
                    put(k, r.next().ok_or_else(eof)??);
                }
            }
            Elements::F64(r) => {
                for k in 0..n {
                    put(k, rounded(r.next().ok_or_else(eof)??, k)?);
                }
            }
        }
        Ok(())
    }

    /// Reads `n` rows of `columns.len()` elements (a C-order 2-D array), one into each column.
    fn read_rows(&mut self, n: usize, columns: &mut [Vec<f32>]) -> std::io::Result<()> {
        let k = columns.len();
        let Elements::Raw {
            reader,
            wide,
            at,
            bytes,
        } = self
        else {
            let mut j = 0;
            return self.read(n * k, |_, v| {
                columns[j].push(v);
                j = if j + 1 == k { 0 } else { j + 1 };
            });
        };
        let size = if *wide { 8 } else { 4 };
        let mut done = 0;
        while done < n {
            let m = (n - done).min((1 << 16) / k.max(1)).max(1);
            bytes.resize(m * k * size, 0);
            reader.read_exact(bytes)?;
            if *wide {
                for (e, b) in bytes.chunks_exact(8).enumerate() {
                    rounded(
                        f64::from_le_bytes(b.try_into().unwrap_or([0; 8])),
                        done * k + e,
                    )?;
                }
            }
            // Column by column over the block (it stays in cache): each column is extended
            // by an exact-size iterator rather than pushed to element by element.
            for (j, column) in columns.iter_mut().enumerate() {
                let rows = bytes.chunks_exact(k * size);
                if *wide {
                    column.extend(rows.map(|row| {
                        let b = &row[j * 8..j * 8 + 8];
                        f64::from_le_bytes(b.try_into().unwrap_or([0; 8])) as f32
                    }));
                } else {
                    column.extend(rows.map(|row| {
                        let b = &row[j * 4..j * 4 + 4];
                        f32::from_le_bytes(b.try_into().unwrap_or([0; 4]))
                    }));
                }
            }
            done += m;
        }
        *at += (n * k) as u64;
        Ok(())
    }

    /// Moves to element `index` (in file order; at most the array's length).
    fn seek_to(&mut self, index: u64) -> std::io::Result<()> {
        match self {
            Elements::Raw {
                reader, wide, at, ..
            } => {
                let size: i64 = if *wide { 8 } else { 4 };
                let delta = i64::try_from(index).unwrap_or(i64::MAX)
                    - i64::try_from(*at).unwrap_or(i64::MAX);
                reader.seek_relative(delta.saturating_mul(size))?;
                *at = index;
                Ok(())
            }
            Elements::F32(r) => r.seek_to(index),
            Elements::F64(r) => r.seek_to(index),
        }
    }
}

/// An opened array: its shape, its order and a typed reader.
struct Array {
    shape: Vec<u64>,
    order: Order,
    elements: Elements,
}

/// Opens `path`, naming `what` (`column ax (dir/ax.npy)`) in messages.
fn open_array(path: &Path, what: &str) -> Result<Array, String> {
    let file = File::open(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    // npyz parses the header; a header it cannot take is an error, never a panic.
    let npy = guarded(what, || {
        NpyFile::new(BufReader::with_capacity(1 << 20, file))
    })?
    .map_err(|e| format!("{what}: not a readable .npy file: {e}"))?;
    let (shape, order, descr) = (npy.shape().to_vec(), npy.order(), npy.dtype().descr());
    let elements = match descr.as_str() {
        "'<f4'" | "'<f8'" => Elements::Raw {
            wide: descr == "'<f8'",
            reader: npy.into_inner(),
            at: 0,
            bytes: Vec::new(),
        },
        _ => match npy.try_data::<f32>() {
            Ok(r) => Elements::F32(r),
            Err(npy) => match npy.try_data::<f64>() {
                Ok(r) => Elements::F64(r),
                Err(_) => {
                    return Err(format!("{what}: dtype {descr} is not a float (f4 or f8)"));
                }
            },
        },
    };
    Ok(Array {
        shape,
        order,
        elements,
    })
}

fn shape_text(shape: &[u64]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => {
            let dims: Vec<String> = shape.iter().map(u64::to_string).collect();
            format!("({})", dims.join(", "))
        }
    }
}

/// How the input's columns are laid out on disk.
enum Arrays {
    /// One reader per column, each positioned at its column's next element.
    Columns(Vec<Elements>),
    /// One C-order 2-D array: a row holds a value of every column.
    Rows(Elements),
}

/// A `.npy` input.
pub struct NpySource {
    what: String,
    layout: Layout,
    arrays: Arrays,
    rows: u64,
    read: u64,
}

impl NpySource {
    /// One array per column: `files[k]` holds column `k` of the layout.
    pub fn columns(files: &[PathBuf], layout: Layout, what: String) -> Result<Self, String> {
        let names = layout.columns();
        let mut readers = Vec::with_capacity(names.len());
        let mut rows: Option<(u64, &str)> = None;
        for (path, &name) in files.iter().zip(names) {
            let label = format!("column {name} ({})", path.display());
            let array = open_array(path, &label)?;
            let [n] = array.shape[..] else {
                return Err(format!(
                    "{label}: shape {}, expected one dimension (N,)",
                    shape_text(&array.shape)
                ));
            };
            match rows {
                None => rows = Some((n, name)),
                Some((m, first)) if m != n => {
                    return Err(format!(
                        "{label}: {n} rows, but column {first} has {m} (every column has one \
                         entry per row)"
                    ));
                }
                _ => {}
            }
            readers.push(array.elements);
        }
        Ok(Self {
            what,
            layout,
            arrays: Arrays::Columns(readers),
            rows: rows.map_or(0, |r| r.0),
            read: 0,
        })
    }

    /// A directory holding `<column>.npy` for every column of the layout.
    pub fn directory(dir: &Path, layout: Layout) -> Result<Self, String> {
        let files: Vec<PathBuf> = layout
            .columns()
            .iter()
            .map(|c| dir.join(format!("{c}.npy")))
            .collect();
        if let Some((missing, name)) = files
            .iter()
            .zip(layout.columns())
            .find(|(f, _)| !f.is_file())
        {
            return Err(format!(
                "{}: no {} (column {name}): {} as a directory holds one .npy per column: {}{}",
                dir.display(),
                missing.file_name().unwrap_or_default().to_string_lossy(),
                layout.file_noun(),
                layout.column_list(),
                layout.other_layout_hint(|c| dir.join(format!("{c}.npy")).is_file())
            ));
        }
        Self::columns(&files, layout, dir.display().to_string())
    }

    /// Files named after their columns (`ax.npy`, …), in any order.
    pub fn files(paths: &[PathBuf], layout: Layout) -> Result<Self, String> {
        let mut files = vec![None; layout.columns().len()];
        for path in paths {
            let stem = path.file_stem().unwrap_or_default().to_string_lossy();
            let Some(k) = layout.columns().iter().position(|c| *c == stem) else {
                let stems: Vec<String> = paths
                    .iter()
                    .map(|p| {
                        p.file_stem()
                            .unwrap_or_default()
                            .to_string_lossy()
                            .into_owned()
                    })
                    .collect();
                return Err(format!(
                    "{}: {stem} is not a column of {}: {} (each file is named after its \
                     column){}",
                    path.display(),
                    layout.file_noun(),
                    layout.column_list(),
                    layout.other_layout_hint(|c| stems.iter().any(|s| s == c))
                ));
            };
            if files[k].replace(path.clone()).is_some() {
                return Err(format!("{}: column {stem} is given twice", path.display()));
            }
        }
        if let Some(k) = files.iter().position(Option::is_none) {
            return Err(format!(
                "no file for column {} ({}.npy): {} needs {}",
                layout.columns()[k],
                layout.columns()[k],
                layout.file_noun(),
                layout.column_list()
            ));
        }
        let files: Vec<PathBuf> = files.into_iter().flatten().collect();
        let what = paths
            .first()
            .and_then(|p| p.parent())
            .map_or_else(String::new, |d| format!("{}/*.npy", d.display()));
        Self::columns(&files, layout, what)
    }

    /// One 2-D array, `(N, 7)` for spheres or `(N, 14)` for pairs.
    pub fn matrix(path: &Path, layout: Layout) -> Result<Self, String> {
        let what = path.display().to_string();
        let k = layout.columns().len();
        let array = open_array(path, &what)?;
        let n = match array.shape[..] {
            [n, cols] if cols == k as u64 => n,
            _ => {
                let hint = match array.shape[..] {
                    [_, cols] => layout.other_shape_hint(cols),
                    _ => "",
                };
                return Err(format!(
                    "{what}: shape {}, expected (N, {k}) for {}: columns {}{hint}",
                    shape_text(&array.shape),
                    layout.file_noun(),
                    layout.column_list()
                ));
            }
        };
        let arrays = match array.order {
            Order::C => Arrays::Rows(array.elements),
            Order::Fortran => {
                // Column-major: each column is a run of N elements; one reader per column.
                let mut readers = vec![array.elements];
                for j in 1..k {
                    let mut r = open_array(path, &what)?.elements;
                    r.seek_to(j as u64 * n)
                        .map_err(|e| format!("cannot read {what}: {e}"))?;
                    readers.push(r);
                }
                Arrays::Columns(readers)
            }
        };
        Ok(Self {
            what,
            layout,
            arrays,
            rows: n,
            read: 0,
        })
    }
}

impl Source for NpySource {
    fn next(&mut self, max: usize, chunk: &mut Chunk) -> Result<bool, String> {
        chunk.clear(self.read);
        let n = (self.rows - self.read).min(max as u64) as usize;
        if n == 0 {
            return Ok(false);
        }
        let truncated = |e: std::io::Error, column: Option<&str>| {
            if e.kind() == std::io::ErrorKind::UnexpectedEof {
                let what = column.map_or("the array".to_string(), |c| format!("column {c}"));
                format!(
                    "{}: {what} ends before its {} rows (the file is truncated)",
                    self.what, self.rows
                )
            } else {
                format!("cannot read {}: {e}", self.what)
            }
        };
        // A value beyond f32's range, named by its row and column as CSV names it.
        let beyond = |e: &std::io::Error, place: &dyn Fn(usize) -> (u64, &'static str)| {
            let b = e.get_ref()?.downcast_ref::<Beyond>()?;
            let (row, column) = place(b.offset);
            Some(format!("{}: row {row}, column {column}: {b}", self.what))
        };
        let (names, first) = (self.layout.columns(), self.read);
        match &mut self.arrays {
            Arrays::Columns(readers) => {
                for ((r, col), name) in readers.iter_mut().zip(&mut chunk.columns).zip(names) {
                    col.reserve(n);
                    r.read(n, |_, v| col.push(v)).map_err(|e| {
                        beyond(&e, &|at| (first + at as u64, *name))
                            .unwrap_or_else(|| truncated(e, Some(name)))
                    })?;
                }
            }
            Arrays::Rows(r) => {
                chunk.columns.iter_mut().for_each(|c| c.reserve(n));
                let k = names.len();
                r.read_rows(n, &mut chunk.columns).map_err(|e| {
                    beyond(&e, &|at| (first + (at / k) as u64, names[at % k]))
                        .unwrap_or_else(|| truncated(e, None))
                })?;
            }
        }
        self.read += n as u64;
        Ok(true)
    }

    fn total_rows(&self) -> Option<u64> {
        Some(self.rows)
    }
}

type Out = BufWriter<File>;

/// A typed writer of one 1-D result array.
enum ColumnWriter {
    F32(npyz::NpyWriter<f32, Out>),
    F64(npyz::NpyWriter<f64, Out>),
    U8(npyz::NpyWriter<u8, Out>),
    I64(npyz::NpyWriter<i64, Out>),
}

impl ColumnWriter {
    /// A 1-D array whose length is written when it is finished.
    fn begin(file: &File, column: OutColumn) -> std::io::Result<Self> {
        let out = BufWriter::with_capacity(1 << 20, file.try_clone()?);
        Ok(match column.ty() {
            super::layout::OutType::F32 => {
                ColumnWriter::F32(WriteOptions::new().default_dtype().writer(out).begin_1d()?)
            }
            super::layout::OutType::F64 => {
                ColumnWriter::F64(WriteOptions::new().default_dtype().writer(out).begin_1d()?)
            }
            super::layout::OutType::U8 => {
                ColumnWriter::U8(WriteOptions::new().default_dtype().writer(out).begin_1d()?)
            }
            super::layout::OutType::I64 => {
                ColumnWriter::I64(WriteOptions::new().default_dtype().writer(out).begin_1d()?)
            }
        })
    }

    fn write(&mut self, values: Values<'_>) -> std::io::Result<()> {
        match (self, values) {
            (ColumnWriter::F32(w), Values::F32(v)) => w.extend(v.iter().copied()),
            (ColumnWriter::F64(w), Values::F64(v)) => w.extend(v.iter().copied()),
            (ColumnWriter::U8(w), Values::U8(v)) => w.extend(v.iter().copied()),
            (ColumnWriter::I64(w), Values::I64(v)) => w.extend(v.iter().copied()),
            _ => Err(std::io::Error::other("a result column changed type")),
        }
    }

    /// Writes the length into the header and flushes.
    fn finish(self) -> std::io::Result<()> {
        match self {
            ColumnWriter::F32(w) => w.finish(),
            ColumnWriter::F64(w) => w.finish(),
            ColumnWriter::U8(w) => w.finish(),
            ColumnWriter::I64(w) => w.finish(),
        }
    }
}

/// Results as a directory of 1-D `.npy` arrays, one per result column.
pub struct NpyDirSink {
    staged: AtomicDir,
    columns: Vec<(OutColumn, File, ColumnWriter)>,
}

impl NpyDirSink {
    /// Starts `<column>.npy` for every result column in the staged directory. An existing
    /// directory at `path` is replaced only if it holds nothing but column files a query
    /// writes (an earlier result); anything else is refused before any work.
    pub fn create(path: &Path, columns: &[OutColumn]) -> Result<Self, String> {
        refuse_foreign(path)?;
        let staged = AtomicDir::create(path)?;
        let mut open = Vec::with_capacity(columns.len());
        for &c in columns {
            let file = staged.create_file(&format!("{}.npy", c.name()))?;
            let writer = ColumnWriter::begin(&file, c).map_err(|e| staged.error(e))?;
            open.push((c, file, writer));
        }
        Ok(Self {
            staged,
            columns: open,
        })
    }
}

/// Refuses a directory output whose path exists and is not a directory of result columns.
fn refuse_foreign(path: &Path) -> Result<(), String> {
    let fail = |e: std::io::Error| format!("cannot write {}: {e}", path.display());
    if path.file_name().is_none() {
        return Err(format!(
            "cannot write {}: no directory name",
            path.display()
        ));
    }
    if !path.exists() {
        return Ok(());
    }
    if !path.is_dir() {
        return Err(format!(
            "cannot write {}: it exists and is not a directory (results in .npy columns go to \
             a directory)",
            path.display()
        ));
    }
    for entry in std::fs::read_dir(path).map_err(fail)? {
        let entry = entry.map_err(fail)?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let ours = OutColumn::ALL
            .iter()
            .any(|c| name == format!("{}.npy", c.name()));
        if !ours || !entry.path().is_file() {
            return Err(format!(
                "cannot write {}: the directory holds {name}, which is not a result column; \
                 give a new directory (an earlier result is replaced whole)",
                path.display()
            ));
        }
    }
    Ok(())
}

impl Sink for NpyDirSink {
    fn write(&mut self, results: &Results) -> Result<(), String> {
        for (c, _, w) in &mut self.columns {
            w.write(results.values(*c))
                .map_err(|e| self.staged.error(e))?;
        }
        Ok(())
    }

    fn commit(self: Box<Self>) -> Result<(), String> {
        let Self { staged, columns } = *self;
        for (_, file, w) in columns {
            w.finish().map_err(|e| staged.error(e))?;
            file.sync_all().map_err(|e| staged.error(e))?;
        }
        staged.commit()
    }

    fn path(&self) -> &Path {
        self.staged.path()
    }
}

/// Results as one 1-D `.npy` array: only when the only result column is `time`.
pub struct NpyFileSink {
    staged: AtomicFile,
    writer: Option<npyz::NpyWriter<f32, Out>>,
}

impl NpyFileSink {
    /// Starts the array under its temporary name.
    pub fn create(path: &Path) -> Result<Self, String> {
        crate::output::check_writable(path)?;
        let staged = AtomicFile::create(path)?;
        let writer = WriteOptions::new()
            .default_dtype()
            .writer(staged.writer()?)
            .begin_1d()
            .map_err(|e| staged.error(e))?;
        Ok(Self {
            staged,
            writer: Some(writer),
        })
    }
}

impl Sink for NpyFileSink {
    fn write(&mut self, results: &Results) -> Result<(), String> {
        let w = self.writer.as_mut().ok_or("finished")?;
        w.extend(results.time.iter().copied())
            .map_err(|e| self.staged.error(e))
    }

    fn commit(self: Box<Self>) -> Result<(), String> {
        let Self { staged, writer } = *self;
        if let Some(w) = writer {
            w.finish().map_err(|e| staged.error(e))?;
        }
        staged.commit()
    }

    fn path(&self) -> &Path {
        self.staged.path()
    }
}
