//! Apache Parquet and Arrow IPC in and out (feature `parquet`): columns found by name, of
//! type Float32 or Float64 (rounded to f32), without nulls. Parquet is read a batch of
//! `--chunk-rows` rows at a time, decoded page by page within a row group; IPC a record batch
//! at a time. Results are written one row group (Parquet, snappy) or one record batch (IPC)
//! per chunk, so memory stays flat.
//!
//! This build reads uncompressed and snappy Parquet only: the column chunks' codecs are
//! checked before any page is read, and a file that uses another codec is refused naming it.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read};
use std::path::Path;
use std::sync::Arc;

use arrow_array::cast::AsArray;
use arrow_array::types::{Float32Type, Float64Type};
use arrow_array::{
    Array, ArrayRef, Float32Array, Float64Array, Int64Array, RecordBatch, RecordBatchReader,
    UInt8Array,
};
use arrow_schema::{DataType, Field, Schema, SchemaRef};
use parquet::arrow::ArrowWriter;
use parquet::arrow::ProjectionMask;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::basic::Compression;
use parquet::file::properties::WriterProperties;

use super::layout::{Chunk, Layout, OutColumn, OutType, Results, Values, beyond_f32, narrow};
use super::{Sink, Source, guarded};
use crate::atomic::{AtomicFile, finish_writer};

/// The codecs this build decodes, and the cargo feature of `parquet` another one needs.
fn missing_codec(c: Compression) -> Option<(&'static str, &'static str)> {
    match c {
        Compression::UNCOMPRESSED | Compression::SNAPPY => None,
        Compression::GZIP(_) => Some(("GZIP", "flate2")),
        Compression::BROTLI(_) => Some(("BROTLI", "brotli")),
        Compression::LZ4 => Some(("LZ4", "lz4")),
        Compression::LZ4_RAW => Some(("LZ4_RAW", "lz4")),
        Compression::ZSTD(_) => Some(("ZSTD", "zstd")),
        Compression::LZO => Some(("LZO", "none: parquet has no LZO decoder")),
    }
}

/// Checks that every column of the layout is in `schema` as a float column.
fn check_schema(what: &str, schema: &Schema, layout: Layout) -> Result<Vec<usize>, String> {
    layout
        .columns()
        .iter()
        .map(|&name| {
            let (k, field) = schema.column_with_name(name).ok_or_else(|| {
                let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
                format!(
                    "{what}: no column {name}: {} has the columns {} (the file has {}){}",
                    layout.file_noun(),
                    layout.column_list(),
                    names.join(", "),
                    layout.other_layout_hint(|c| names.contains(&c))
                )
            })?;
            match field.data_type() {
                DataType::Float32 | DataType::Float64 => Ok(k),
                other => Err(format!(
                    "{what}: column {name} has type {other}, expected Float32 or Float64"
                )),
            }
        })
        .collect()
}

/// Record batches of any size cut into chunks of the requested rows.
pub struct BatchSource {
    what: String,
    layout: Layout,
    batches: Box<dyn Iterator<Item = Result<RecordBatch, String>>>,
    pending: Option<(RecordBatch, usize)>,
    rows: u64,
    total: Option<u64>,
}

impl BatchSource {
    /// A Parquet file, after its codecs and schema are checked.
    pub fn parquet(path: &Path, layout: Layout, batch_rows: usize) -> Result<Self, String> {
        let what = path.display().to_string();
        let file = File::open(path).map_err(|e| format!("cannot read {what}: {e}"))?;
        let builder = guarded(&what, || ParquetRecordBatchReaderBuilder::try_new(file))?
            .map_err(|e| format!("{what}: not a readable Parquet file: {e}"))?;
        let indices = check_schema(&what, builder.schema(), layout)?;
        let names = layout.columns();
        for group in builder.metadata().row_groups() {
            for column in group.columns() {
                let name = column.column_path().string();
                if !names.contains(&name.as_str()) {
                    continue;
                }
                if let Some((codec, feature)) = missing_codec(column.compression()) {
                    return Err(format!(
                        "{what}: column {name} is compressed with {codec}, which this build \
                         cannot decode (it reads uncompressed and SNAPPY Parquet; the codec \
                         needs parquet's `{feature}` feature): rewrite the file with snappy \
                         compression or none"
                    ));
                }
            }
        }
        let total = u64::try_from(builder.metadata().file_metadata().num_rows()).ok();
        let mask = ProjectionMask::roots(builder.parquet_schema(), indices);
        let reader = builder
            .with_batch_size(batch_rows.max(1))
            .with_projection(mask)
            .build()
            .map_err(|e| format!("{what}: {e}"))?;
        let label = what.clone();
        let mut reader = Some(reader);
        let batches = std::iter::from_fn(move || {
            let r = reader.as_mut()?;
            match guarded(&label, || r.next()) {
                Ok(Some(Ok(b))) => Some(Ok(b)),
                Ok(Some(Err(e))) => Some(Err(format!("cannot read {label}: {e}"))),
                Ok(None) => None,
                Err(e) => {
                    reader = None;
                    Some(Err(e))
                }
            }
        });
        Ok(Self {
            what,
            layout,
            batches: Box::new(batches),
            pending: None,
            rows: 0,
            total,
        })
    }

    /// An Arrow IPC file (`ARROW1` magic) or stream.
    pub fn ipc(path: &Path, layout: Layout) -> Result<Self, String> {
        let what = path.display().to_string();
        let open = || File::open(path).map_err(|e| format!("cannot read {what}: {e}"));
        let mut magic = [0u8; 6];
        let is_file = open()?.read_exact(&mut magic).is_ok() && &magic == b"ARROW1";
        let input = BufReader::with_capacity(1 << 20, open()?);
        let not_ipc =
            |e: arrow_schema::ArrowError| format!("{what}: not a readable Arrow IPC file: {e}");
        let reader: Box<dyn RecordBatchReader> = if is_file {
            Box::new(arrow_ipc::reader::FileReader::try_new(input, None).map_err(not_ipc)?)
        } else {
            Box::new(arrow_ipc::reader::StreamReader::try_new(input, None).map_err(not_ipc)?)
        };
        check_schema(&what, &reader.schema(), layout)?;
        let label = what.clone();
        let batches = reader.map(move |b| {
            b.map_err(|e| {
                let text = e.to_string();
                // arrow-ipc is built without its lz4 and zstd features: say so plainly.
                match ["lz4", "zstd"]
                    .into_iter()
                    .find(|c| text.contains(&format!("requires the {c} feature")))
                {
                    Some(codec) => format!(
                        "{label}: the record batches are compressed with {}, which this build \
                         cannot decode (it reads uncompressed Arrow IPC): rewrite the file \
                         uncompressed",
                        codec.to_uppercase()
                    ),
                    None => format!("cannot read {label}: {text}"),
                }
            })
        });
        Ok(Self {
            what,
            layout,
            batches: Box::new(batches),
            pending: None,
            rows: 0,
            total: None,
        })
    }
}

/// What is wrong with a column of a record batch.
enum Refused {
    /// A null at this row of the batch.
    Null(usize),
    /// Not a float column.
    Type(DataType),
    /// A Float64 value beyond f32's range at this row of the batch.
    Beyond(usize, f64),
}

/// Appends rows `range` of a float column to `out`, refusing nulls and other types.
fn append(
    array: &ArrayRef,
    range: std::ops::Range<usize>,
    out: &mut Vec<f32>,
) -> Result<(), Refused> {
    if array.null_count() > 0
        && let Some(i) = range.clone().find(|&i| array.is_null(i))
    {
        return Err(Refused::Null(i));
    }
    match array.data_type() {
        DataType::Float32 => {
            out.extend_from_slice(&array.as_primitive::<Float32Type>().values()[range]);
        }
        DataType::Float64 => {
            let values = &array.as_primitive::<Float64Type>().values()[range.clone()];
            if let Some(k) = values.iter().position(|&v| narrow(v).is_none()) {
                return Err(Refused::Beyond(range.start + k, values[k]));
            }
            out.extend(values.iter().map(|&v| v as f32));
        }
        other => return Err(Refused::Type(other.clone())),
    }
    Ok(())
}

impl Source for BatchSource {
    fn next(&mut self, max: usize, chunk: &mut Chunk) -> Result<bool, String> {
        chunk.clear(self.rows);
        let names = self.layout.columns();
        while chunk.rows() < max {
            let (batch, offset) = match self.pending.take() {
                Some(p) => p,
                None => match self.batches.next() {
                    Some(b) => (b?, 0),
                    None => break,
                },
            };
            let take = (max - chunk.rows()).min(batch.num_rows() - offset);
            for (col, &name) in chunk.columns.iter_mut().zip(names) {
                let array = batch
                    .column_by_name(name)
                    .ok_or_else(|| format!("{}: a record batch has no column {name}", self.what))?;
                append(array, offset..offset + take, col).map_err(|refused| match refused {
                    Refused::Null(i) => format!(
                        "{}: row {}, column {name}: null (every row needs a value)",
                        self.what,
                        self.rows + (i - offset) as u64
                    ),
                    Refused::Beyond(i, v) => format!(
                        "{}: row {}, column {name}: {}",
                        self.what,
                        self.rows + (i - offset) as u64,
                        beyond_f32(crate::number::num(v))
                    ),
                    Refused::Type(t) => format!(
                        "{}: column {name} has type {t}, expected Float32 or Float64",
                        self.what
                    ),
                })?;
            }
            self.rows += take as u64;
            if offset + take < batch.num_rows() {
                self.pending = Some((batch, offset + take));
            }
        }
        Ok(chunk.rows() > 0)
    }

    fn total_rows(&self) -> Option<u64> {
        self.total
    }
}

/// The schema of the result columns.
fn schema(columns: &[OutColumn]) -> SchemaRef {
    Arc::new(Schema::new(
        columns
            .iter()
            .map(|c| {
                let ty = match c.ty() {
                    OutType::F32 => DataType::Float32,
                    OutType::F64 => DataType::Float64,
                    OutType::U8 => DataType::UInt8,
                    OutType::I64 => DataType::Int64,
                };
                Field::new(c.name(), ty, false)
            })
            .collect::<Vec<_>>(),
    ))
}

/// One chunk of results as a record batch.
fn batch(
    schema: &SchemaRef,
    columns: &[OutColumn],
    results: &Results,
) -> Result<RecordBatch, String> {
    let arrays: Vec<ArrayRef> = columns
        .iter()
        .map(|&c| -> ArrayRef {
            match results.values(c) {
                Values::F32(v) => Arc::new(Float32Array::from(v.to_vec())),
                Values::F64(v) => Arc::new(Float64Array::from(v.to_vec())),
                Values::U8(v) => Arc::new(UInt8Array::from(v.to_vec())),
                Values::I64(v) => Arc::new(Int64Array::from(v.to_vec())),
            }
        })
        .collect();
    RecordBatch::try_new(schema.clone(), arrays).map_err(|e| e.to_string())
}

/// Results as a Parquet file: one snappy row group per chunk.
pub struct ParquetSink {
    staged: AtomicFile,
    writer: ArrowWriter<File>,
    schema: SchemaRef,
    columns: Vec<OutColumn>,
}

impl ParquetSink {
    /// Starts the file under its temporary name.
    pub fn create(path: &Path, columns: Vec<OutColumn>) -> Result<Self, String> {
        crate::output::check_writable(path)?;
        let staged = AtomicFile::create(path)?;
        let schema = schema(&columns);
        let props = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .build();
        let file = staged
            .writer()?
            .into_inner()
            .map_err(|e| staged.error(e.into_error()))?;
        let writer =
            ArrowWriter::try_new(file, schema.clone(), Some(props)).map_err(|e| staged.error(e))?;
        Ok(Self {
            staged,
            writer,
            schema,
            columns,
        })
    }
}

impl Sink for ParquetSink {
    fn write(&mut self, results: &Results) -> Result<(), String> {
        let batch = batch(&self.schema, &self.columns, results)?;
        self.writer
            .write(&batch)
            .map_err(|e| self.staged.error(e))?;
        // One row group per chunk: nothing is held beyond it.
        self.writer.flush().map_err(|e| self.staged.error(e))
    }

    fn commit(self: Box<Self>) -> Result<(), String> {
        let Self { staged, writer, .. } = *self;
        writer.close().map_err(|e| staged.error(e))?;
        staged.commit()
    }

    fn path(&self) -> &Path {
        self.staged.path()
    }
}

/// Arrow IPC writers: the file format or the stream format.
enum IpcWriter {
    File(arrow_ipc::writer::FileWriter<BufWriter<File>>),
    Stream(arrow_ipc::writer::StreamWriter<BufWriter<File>>),
}

/// Results as an Arrow IPC file (or stream, for `.arrows`): one record batch per chunk.
pub struct IpcSink {
    staged: AtomicFile,
    writer: IpcWriter,
    schema: SchemaRef,
    columns: Vec<OutColumn>,
}

impl IpcSink {
    /// Starts the file under its temporary name.
    pub fn create(path: &Path, columns: Vec<OutColumn>, stream: bool) -> Result<Self, String> {
        crate::output::check_writable(path)?;
        let staged = AtomicFile::create(path)?;
        let schema = schema(&columns);
        let out = staged.writer()?;
        let writer = if stream {
            IpcWriter::Stream(
                arrow_ipc::writer::StreamWriter::try_new(out, &schema)
                    .map_err(|e| staged.error(e))?,
            )
        } else {
            IpcWriter::File(
                arrow_ipc::writer::FileWriter::try_new(out, &schema)
                    .map_err(|e| staged.error(e))?,
            )
        };
        Ok(Self {
            staged,
            writer,
            schema,
            columns,
        })
    }
}

impl Sink for IpcSink {
    fn write(&mut self, results: &Results) -> Result<(), String> {
        let batch = batch(&self.schema, &self.columns, results)?;
        match &mut self.writer {
            IpcWriter::File(w) => w.write(&batch),
            IpcWriter::Stream(w) => w.write(&batch),
        }
        .map_err(|e| self.staged.error(e))
    }

    fn commit(self: Box<Self>) -> Result<(), String> {
        let Self { staged, writer, .. } = *self;
        let out = match writer {
            IpcWriter::File(mut w) => {
                w.finish().map_err(|e| staged.error(e))?;
                w.into_inner()
            }
            IpcWriter::Stream(mut w) => {
                w.finish().map_err(|e| staged.error(e))?;
                w.into_inner()
            }
        }
        .map_err(|e| staged.error(e))?;
        finish_writer(out, |e| staged.error(e))?;
        staged.commit()
    }

    fn path(&self) -> &Path {
        self.staged.path()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Float64 value beyond f32's range is refused at its row, as CSV and `.npy` refuse it.
    #[test]
    fn a_float64_beyond_f32_is_refused_at_its_row() {
        let array: ArrayRef = Arc::new(Float64Array::from(vec![1.0, 2.0, -1e39, 4.0]));
        let mut out = Vec::new();
        assert!(matches!(
            append(&array, 1..4, &mut out),
            Err(Refused::Beyond(2, v)) if v == -1e39
        ));
        assert!(out.is_empty());
        append(&array, 0..2, &mut out).map_err(|_| ()).unwrap();
        assert_eq!(out, [1.0, 2.0]);
    }
}
