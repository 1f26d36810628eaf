//! `ulog align -o OUT.parquet`: the aligned table as one Parquet file, written a
//! record batch of steps at a time.

use std::fs::File;
use std::path::Path;
use std::sync::Arc;

use ulog_core::align::{Row, Rows, SelectedColumns};
use ulog_core::export::arrow_array::{ArrayRef, RecordBatch, UInt64Array};
use ulog_core::export::arrow_schema::{DataType, Field, Schema, SchemaRef};
use ulog_core::export::parquet::arrow::ArrowWriter;
use ulog_core::export::parquet::errors::ParquetError;
use ulog_core::export::{self, Compression};
use ulog_core::read::FieldShape;

use super::column_names;
use crate::failure::{io_text, Failure};

/// Steps per record batch at most: what is held at a time is one batch of values
/// (and the interpolated rows behind it), whatever the number of steps.
const BATCH_STEPS: usize = 65_536;

/// Bytes of values in a record batch, about: wide tables get fewer steps a batch.
const BATCH_BYTES: usize = 8 << 20;

/// Encoded bytes of a row group the writer holds before it writes the group out (its
/// own bound, a million rows, is hundreds of megabytes for a wide table).
const ROW_GROUP_BYTES: usize = 16 << 20;

/// Writes the table to a Parquet file at `path`: `timestamp` (not null), then each
/// column typed as its field is, null where the topic has no value at the step. A
/// failed write removes what it wrote.
pub(super) fn write(
    path: &Path,
    times: &[u64],
    tables: &[SelectedColumns<'_, '_>],
    rows: Vec<Rows<'_, '_>>,
) -> Result<(), Failure> {
    let mut fields = vec![Field::new("timestamp", DataType::UInt64, false)];
    let readers = tables.iter().flat_map(|t| t.columns.iter().map(|(_, r)| r));
    for (name, reader) in column_names(tables).into_iter().zip(readers) {
        fields.push(Field::new(name, export::field_data_type(reader), true));
    }
    let schema: SchemaRef = Arc::new(Schema::new(fields));
    let file = File::create(path).map_err(|e| Failure::unreadable(path.display(), io_text(&e)))?;
    let result = write_batches(file, schema, times, tables, rows);
    if result.is_err() {
        let _ = std::fs::remove_file(path);
    }
    result.map_err(|e| match e {
        Error::Parquet(e) => Failure::unreadable(path.display(), parquet_text(&e)),
        Error::Export(e) => Failure::about(path.display(), e),
    })
}

/// What stops the file from being written.
enum Error {
    Parquet(ParquetError),
    Export(export::ExportError),
}

fn write_batches(
    file: File,
    schema: SchemaRef,
    times: &[u64],
    tables: &[SelectedColumns<'_, '_>],
    mut rows: Vec<Rows<'_, '_>>,
) -> Result<(), Error> {
    // The encodings `ulog parquet` writes its files with, and its default codec.
    let props = export::writer_properties(&schema, Compression::Zstd);
    let mut writer =
        ArrowWriter::try_new(file, schema.clone(), Some(props)).map_err(Error::Parquet)?;
    let width: usize = 8 + tables
        .iter()
        .flat_map(|t| &t.columns)
        .map(|(_, r)| match r.shape() {
            FieldShape::Scalar => r.ty().size(),
            FieldShape::Array(n) | FieldShape::String(n) => n * r.ty().size(),
        })
        .sum::<usize>();
    let batch = (BATCH_BYTES / width).clamp(1024, BATCH_STEPS);
    for steps in times.chunks(batch) {
        let mut columns: Vec<ArrayRef> = Vec::with_capacity(schema.fields().len());
        columns.push(Arc::new(UInt64Array::from(steps.to_vec())));
        for (table, rows) in tables.iter().zip(rows.iter_mut()) {
            let picked: Vec<Option<Row<'_>>> = rows.by_ref().take(steps.len()).collect();
            // An interpolated row's payload holds the earlier row's bytes but for its
            // floats: every column reads from it, text included.
            let payloads: Vec<Option<&[u8]>> =
                picked.iter().map(|r| r.as_ref().map(Row::bytes)).collect();
            for (_, reader) in &table.columns {
                columns.push(export::field_array(reader, &payloads).map_err(Error::Export)?);
            }
        }
        let batch =
            RecordBatch::try_new(schema.clone(), columns).map_err(|e| Error::Parquet(e.into()))?;
        writer.write(&batch).map_err(Error::Parquet)?;
        if writer.in_progress_size() >= ROW_GROUP_BYTES {
            writer.flush().map_err(Error::Parquet)?;
        }
    }
    writer.close().map(drop).map_err(Error::Parquet)
}

/// A Parquet error's text; an I/O error's as `ulog` words them.
fn parquet_text(e: &ParquetError) -> String {
    if let ParquetError::External(inner) = e {
        if let Some(io) = inner.downcast_ref::<std::io::Error>() {
            return io_text(io);
        }
    }
    e.to_string()
}
