//! `ulog align -o OUT.parquet`: the aligned table as one Parquet file, written a
//! record batch of steps at a time.

use std::fs::File;
use std::path::Path;
use std::sync::Arc;

use ulog_core::align::{Row, Rows};
use ulog_core::export::arrow_array::{ArrayRef, RecordBatch, UInt64Array};
use ulog_core::export::arrow_schema::{DataType, Field, Schema, SchemaRef};
use ulog_core::export::parquet::arrow::ArrowWriter;
use ulog_core::export::parquet::errors::ParquetError;
use ulog_core::export::{self, Compression};
use ulog_core::read::FieldShape;

use super::{column_names, Table};
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
    tables: &[Table],
    mut rows: Vec<Rows<'_, '_>>,
) -> Result<(), Failure> {
    write_with(path, tables, |out| {
        for steps in times.chunks(out.batch) {
            let picked: Vec<Vec<Option<Row<'_>>>> = rows
                .iter_mut()
                .map(|r| r.by_ref().take(steps.len()).collect())
                .collect();
            // An interpolated row's payload holds the earlier row's bytes but for its
            // floats: every column reads from it, text included.
            let payloads: Vec<Vec<Option<&[u8]>>> = picked
                .iter()
                .map(|p| p.iter().map(|r| r.as_ref().map(Row::bytes)).collect())
                .collect();
            out.write(steps, &payloads)?;
        }
        Ok(())
    })
}

/// Creates the file at `path`, hands `fill` the table's writer, and closes it; a
/// failed write removes what it wrote.
pub(super) fn write_with(
    path: &Path,
    tables: &[Table],
    fill: impl FnOnce(&mut TableWriter<'_>) -> Result<(), Error>,
) -> Result<(), Failure> {
    let mut fields = vec![Field::new("timestamp", DataType::UInt64, false)];
    let readers = tables.iter().flat_map(|t| t.columns.iter().map(|(_, r)| r));
    for (name, reader) in column_names(tables).into_iter().zip(readers) {
        fields.push(Field::new(name, export::field_data_type(reader), true));
    }
    let schema: SchemaRef = Arc::new(Schema::new(fields));
    let file = File::create(path).map_err(|e| Failure::unreadable(path.display(), io_text(&e)))?;
    let result = TableWriter::new(file, schema, tables).and_then(|mut out| {
        fill(&mut out)?;
        out.writer.close().map(drop).map_err(Error::Parquet)
    });
    if result.is_err() {
        let _ = std::fs::remove_file(path);
    }
    result.map_err(|e| match e {
        Error::Parquet(e) => Failure::unreadable(path.display(), parquet_text(&e)),
        Error::Export(e) => Failure::about(path.display(), e),
        Error::Other(f) => f,
    })
}

/// What stops the file from being written.
pub(super) enum Error {
    Parquet(ParquetError),
    Export(export::ExportError),
    /// Reading the log failed.
    Other(Failure),
}

/// The Parquet writer of an aligned table, taking a batch of steps at a time.
pub(super) struct TableWriter<'t> {
    writer: ArrowWriter<File>,
    schema: SchemaRef,
    tables: &'t [Table],
    /// Steps per batch.
    pub(super) batch: usize,
}

impl<'t> TableWriter<'t> {
    fn new(file: File, schema: SchemaRef, tables: &'t [Table]) -> Result<TableWriter<'t>, Error> {
        // The encodings `ulog parquet` writes its files with, and its default codec.
        let props = export::writer_properties(&schema, Compression::Zstd);
        let writer =
            ArrowWriter::try_new(file, schema.clone(), Some(props)).map_err(Error::Parquet)?;
        let width: usize = 8 + tables
            .iter()
            .flat_map(|t| &t.columns)
            .map(|(_, r)| match r.shape() {
                FieldShape::Scalar => r.ty().size(),
                FieldShape::Array(n) | FieldShape::String(n) => n * r.ty().size(),
            })
            .sum::<usize>();
        Ok(TableWriter {
            writer,
            schema,
            tables,
            batch: (BATCH_BYTES / width).clamp(1024, BATCH_STEPS),
        })
    }

    /// Writes the steps `times`, with each table's row payload at each step.
    pub(super) fn write(
        &mut self,
        times: &[u64],
        payloads: &[Vec<Option<&[u8]>>],
    ) -> Result<(), Error> {
        let mut columns: Vec<ArrayRef> = Vec::with_capacity(self.schema.fields().len());
        columns.push(Arc::new(UInt64Array::from(times.to_vec())));
        for (table, payloads) in self.tables.iter().zip(payloads) {
            for (_, reader) in &table.columns {
                columns.push(export::field_array(reader, payloads).map_err(Error::Export)?);
            }
        }
        let batch = RecordBatch::try_new(self.schema.clone(), columns)
            .map_err(|e| Error::Parquet(e.into()))?;
        self.writer.write(&batch).map_err(Error::Parquet)?;
        if self.writer.in_progress_size() >= ROW_GROUP_BYTES {
            self.writer.flush().map_err(Error::Parquet)?;
        }
        Ok(())
    }
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
