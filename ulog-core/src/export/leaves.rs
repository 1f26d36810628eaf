//! Parquet files written one leaf column at a time.
//!
//! The `parquet` crate's `ArrowWriter` keeps a column writer for every leaf column of
//! a row group until the row group is flushed: kilobytes each whatever the row count,
//! which for a format of tens of thousands of fields was most of an export's memory
//! (bench/README.md). Here each row group is one record batch, built whole; its leaf
//! columns are encoded, appended to the file and dropped one after another, so the
//! memory is that of the batch and one column writer.

use std::io::Write;
use std::sync::Arc;

use arrow_array::{Array, ArrayRef, FixedSizeListArray, RecordBatch, StructArray};
use arrow_schema::{DataType, Field, FieldRef, Schema, SchemaRef};
use parquet::arrow::arrow_writer::{compute_leaves, get_column_writers};
use parquet::arrow::{add_encoded_arrow_schema_to_metadata, ArrowSchemaConverter};
use parquet::errors::Result;
use parquet::file::properties::{WriterProperties, WriterPropertiesPtr};
use parquet::file::writer::{SerializedFileWriter, SerializedRowGroupWriter};

/// A Parquet file of one Arrow schema, written a row group at a time.
pub(super) struct LeafWriter<W: Write + Send> {
    file: SerializedFileWriter<W>,
    schema: SchemaRef,
    props: WriterPropertiesPtr,
}

impl<W: Write + Send> LeafWriter<W> {
    /// A file of `schema` written to `out`; the Arrow schema is kept in the file's
    /// metadata, as `ArrowWriter` keeps it, so readers get the same Arrow types back.
    pub(super) fn try_new(out: W, schema: SchemaRef, mut props: WriterProperties) -> Result<Self> {
        let parquet = converter(&props).convert(&schema)?;
        add_encoded_arrow_schema_to_metadata(&schema, &mut props);
        let props = Arc::new(props);
        let file = SerializedFileWriter::new(out, parquet.root_schema_ptr(), props.clone())?;
        Ok(LeafWriter {
            file,
            schema,
            props,
        })
    }

    /// Writes `batch` (of the writer's schema) as one row group; none when it has no
    /// rows.
    pub(super) fn write_row_group(&mut self, batch: &RecordBatch) -> Result<()> {
        if batch.num_rows() == 0 {
            return Ok(());
        }
        let mut group = self.file.next_row_group()?;
        for (field, column) in self.schema.fields().iter().zip(batch.columns()) {
            for_each_leaf(field, column, &mut |field, column| {
                write_leaf(&mut group, &self.props, field, column)
            })?;
        }
        group.close()?;
        Ok(())
    }

    /// Writes a row group of `rows` rows whose top-level columns `column` builds, one
    /// at a time: each is encoded and dropped before the next is built, so a row
    /// group holds one column's values at a time, not the whole batch.
    pub(super) fn write_columns(
        &mut self,
        rows: usize,
        mut column: impl FnMut(usize) -> Result<ArrayRef>,
    ) -> Result<()> {
        if rows == 0 {
            return Ok(());
        }
        let mut group = self.file.next_row_group()?;
        for (i, field) in self.schema.fields().iter().enumerate() {
            let values = column(i)?;
            for_each_leaf(field, &values, &mut |field, column| {
                write_leaf(&mut group, &self.props, field, column)
            })?;
        }
        group.close()?;
        Ok(())
    }

    /// The writer the file goes to (what the Parquet writer buffers not yet in it).
    pub(super) fn out_mut(&mut self) -> &mut W {
        self.file.inner_mut()
    }

    /// Writes the footer and flushes the file.
    pub(super) fn close(self) -> Result<()> {
        self.file.close().map(drop)
    }
}

fn converter(props: &WriterProperties) -> ArrowSchemaConverter<'static> {
    ArrowSchemaConverter::new().with_coerce_types(props.coerce_types())
}

/// Encodes `column`, a field with exactly one leaf, and appends it to `group`: the
/// field's Parquet schema has the path and levels of that leaf in the whole schema
/// (the parents are the same), which the row group checks.
fn write_leaf<W: Write + Send>(
    group: &mut SerializedRowGroupWriter<'_, W>,
    props: &WriterPropertiesPtr,
    field: FieldRef,
    column: ArrayRef,
) -> Result<()> {
    let schema = Arc::new(Schema::new(vec![field.clone()]));
    let parquet = converter(props).convert(&schema)?;
    let writers = get_column_writers(&parquet, props, &schema)?;
    let leaves = compute_leaves(&field, &column)?;
    debug_assert_eq!((writers.len(), leaves.len()), (1, 1));
    for (mut writer, leaf) in writers.into_iter().zip(leaves) {
        writer.write(&leaf)?;
        writer.close()?.append_to_row_group(group)?;
    }
    Ok(())
}

/// Calls `f` with each leaf of `field` (`column` its values), in the order of the
/// Parquet columns, as a field of the same name whose structs and lists keep only
/// the path to that leaf.
fn for_each_leaf(
    field: &FieldRef,
    column: &ArrayRef,
    f: &mut dyn FnMut(FieldRef, ArrayRef) -> Result<()>,
) -> Result<()> {
    let with_type = |ty: DataType| {
        Arc::new(
            Field::new(field.name(), ty, field.is_nullable())
                .with_metadata(field.metadata().clone()),
        )
    };
    match field.data_type() {
        DataType::Struct(children) => {
            let parent = column
                .as_any()
                .downcast_ref::<StructArray>()
                .expect("a struct column holds a StructArray");
            for (child, values) in children.iter().zip(parent.columns()) {
                for_each_leaf(child, values, &mut |leaf_field, leaf| {
                    let fields = vec![leaf_field];
                    let array = StructArray::try_new(
                        fields.clone().into(),
                        vec![leaf],
                        parent.nulls().cloned(),
                    )?;
                    f(with_type(DataType::Struct(fields.into())), Arc::new(array))
                })?;
            }
            Ok(())
        }
        DataType::FixedSizeList(item, size) => {
            let list = column
                .as_any()
                .downcast_ref::<FixedSizeListArray>()
                .expect("a fixed-size list column holds a FixedSizeListArray");
            for_each_leaf(item, list.values(), &mut |leaf_field, leaf| {
                let array = FixedSizeListArray::try_new(
                    leaf_field.clone(),
                    *size,
                    leaf,
                    list.nulls().cloned(),
                )?;
                f(
                    with_type(DataType::FixedSizeList(leaf_field, *size)),
                    Arc::new(array),
                )
            })
        }
        _ => f(field.clone(), column.clone()),
    }
}
