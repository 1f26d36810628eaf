//! Topics as Arrow record batches, handed to Python through Arrow's C data interface
//! (the PyCapsule protocol pyarrow, polars and DuckDB read): the record batch the
//! Parquet export writes (`ulog_core::export::topic_record_batch`: the log's types,
//! nested types as structs, arrays as fixed-size lists), its buffers moved, not
//! copied.

use std::ffi::CStr;

use arrow_array::ffi::to_ffi;
use arrow_array::{Array, StructArray};
use pyo3::prelude::*;
use pyo3::types::PyCapsule;
use ulog_core::export::{topic_record_batch, Options};
use ulog_core::ULog;

use crate::ULogError;

const SCHEMA: &CStr = c"arrow_schema";
const ARRAY: &CStr = c"arrow_array";

/// A record batch as the capsules of the C data interface: (schema, array).
pub type Capsules<'py> = (Bound<'py, PyCapsule>, Bound<'py, PyCapsule>);

/// The record batch of each of `topics` (`(name, multi_id)`) of `log`, as the two
/// capsules of the C data interface (schema, array); `None` for a topic the log does
/// not have.
pub fn batches<'py>(
    py: Python<'py>,
    log: &ULog<'_>,
    topics: &[(String, u8)],
) -> PyResult<Vec<Option<Capsules<'py>>>> {
    let options = Options::default();
    let mut out = Vec::with_capacity(topics.len());
    for (name, multi_id) in topics {
        let Ok(topic) = log.topic(name, *multi_id) else {
            out.push(None);
            continue;
        };
        let batch = topic_record_batch(&topic, &options)
            .map_err(|e| ULogError::new_err(format!("topic {name}/{multi_id}: {e}")))?;
        let data = StructArray::from(batch).into_data();
        let (array, schema) = to_ffi(&data)
            .map_err(|e| ULogError::new_err(format!("topic {name}/{multi_id}: {e}")))?;
        out.push(Some((
            PyCapsule::new_with_value(py, schema, SCHEMA)?,
            PyCapsule::new_with_value(py, array, ARRAY)?,
        )));
    }
    Ok(out)
}
