//! `ULog.align`: several topics on one time base (`ulog_core::align`), the selected
//! columns as numpy arrays of their own types with a mask of the steps that have a
//! value, as `ulog align` writes them to CSV.

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyList;
use ulog_core::align::{AlignOptions, Grid, Method, Selection};
use ulog_core::format::BasicType;
use ulog_core::read::FieldShape;
use ulog_core::{ULog, Value};

use crate::ULogError;

/// What `ULog.align` asks for (times in seconds since the start of the log's span).
pub struct Request {
    pub selections: Vec<String>,
    pub on: Option<String>,
    pub rate: Option<f64>,
    pub method: String,
    pub tolerance: Option<f64>,
    pub start: Option<f64>,
    pub end: Option<f64>,
}

/// One column's values, in its own type; absent steps hold zero (or "").
enum Values {
    I64(Vec<i64>),
    U64(Vec<u64>),
    F32(Vec<f32>),
    F64(Vec<f64>),
    Bool(Vec<bool>),
    Text(Vec<String>),
}

impl Values {
    fn push(&mut self, v: Option<Value<'_>>) {
        match (self, v) {
            (Values::F32(c), v) => c.push(match v {
                Some(Value::F32(x)) => x,
                _ => f32::NAN,
            }),
            (Values::F64(c), v) => c.push(match v {
                Some(Value::F64(x)) => x,
                _ => f64::NAN,
            }),
            (Values::Bool(c), v) => c.push(matches!(v, Some(Value::Bool(true)))),
            (Values::Text(c), Some(Value::Str(s))) => c.push(s.to_string()),
            (Values::Text(c), _) => c.push(String::new()),
            (Values::U64(c), v) => c.push(match v {
                Some(Value::U64(x)) => x,
                Some(Value::U32(x)) => x.into(),
                Some(Value::U16(x)) => x.into(),
                Some(Value::U8(x)) => x.into(),
                Some(Value::Char(x)) => x.into(),
                _ => 0,
            }),
            (Values::I64(c), v) => c.push(match v {
                Some(Value::I64(x)) => x,
                Some(Value::I32(x)) => x.into(),
                Some(Value::I16(x)) => x.into(),
                Some(Value::I8(x)) => x.into(),
                _ => 0,
            }),
        }
    }
}

/// The aligned table: `(times, [(column name, values, present)])`.
pub fn align<'py>(
    py: Python<'py>,
    log: &ULog<'_>,
    r: &Request,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyList>)> {
    let err = |e: &dyn std::fmt::Display| ULogError::new_err(e.to_string());
    let selections: Vec<Selection> = r
        .selections
        .iter()
        .map(|s| s.parse())
        .collect::<Result<_, _>>()
        .map_err(|e| err(&e))?;
    let method: Method = r.method.parse().map_err(|e| err(&e))?;
    let tables = log.select_columns(&selections).map_err(|e| err(&e))?;
    let options =
        AlignOptions::in_seconds(log, r.tolerance, r.start, r.end).map_err(|e| err(&e))?;
    let grid = match (&r.on, r.rate) {
        (Some(on), _) => {
            let s: Selection = on.parse().map_err(|e| err(&e))?;
            s.grid(log).map_err(|e| err(&e))?
        }
        (None, Some(hz)) => Grid::Rate(hz),
        (None, None) => return Err(ULogError::new_err("give `on=TOPIC` or `rate=HZ`")),
    };
    let steps = log.align(&grid, &options).map_err(|e| err(&e))?;
    let n = steps.times().len();
    let columns = PyList::empty(py);
    for t in &tables {
        let prefix = match t.topic.multi_id() {
            0 => t.topic.name().to_owned(),
            k => format!("{}:{k}", t.topic.name()),
        };
        let mut values: Vec<Values> = t
            .columns
            .iter()
            .map(|(_, reader)| match (reader.shape(), reader.ty()) {
                (FieldShape::String(_), _) => Values::Text(Vec::with_capacity(n)),
                (_, BasicType::Float) => Values::F32(Vec::with_capacity(n)),
                (_, BasicType::Double) => Values::F64(Vec::with_capacity(n)),
                (_, BasicType::Bool) => Values::Bool(Vec::with_capacity(n)),
                (_, BasicType::Int8 | BasicType::Int16 | BasicType::Int32 | BasicType::Int64) => {
                    Values::I64(Vec::with_capacity(n))
                }
                // Unsigned integers and single chars.
                _ => Values::U64(Vec::with_capacity(n)),
            })
            .collect();
        let mut present: Vec<bool> = Vec::with_capacity(n);
        let rows = steps
            .rows(t.topic.name(), t.topic.multi_id(), method)
            .map_err(|e| err(&e))?;
        for row in rows.take(n) {
            present.push(row.is_some());
            for ((_, reader), v) in t.columns.iter().zip(values.iter_mut()) {
                let value = row.as_ref().and_then(|row| match reader.shape() {
                    FieldShape::String(_) => reader.read(row.earlier()),
                    _ => reader.read(row.bytes()),
                });
                v.push(value);
            }
        }
        let present = present.into_pyarray(py);
        for ((path, _), v) in t.columns.iter().zip(values) {
            let array: Bound<'py, PyAny> = match v {
                Values::I64(c) => c.into_pyarray(py).into_any(),
                Values::U64(c) => c.into_pyarray(py).into_any(),
                Values::F32(c) => c.into_pyarray(py).into_any(),
                Values::F64(c) => c.into_pyarray(py).into_any(),
                Values::Bool(c) => c.into_pyarray(py).into_any(),
                Values::Text(c) => PyList::new(py, c)?.into_any(),
            };
            columns.append((format!("{prefix}.{path}"), array, present.clone()))?;
        }
    }
    Ok((steps.times().to_vec().into_pyarray(py).into_any(), columns))
}
