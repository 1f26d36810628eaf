//! A topic's union schema across the firmware versions of a dataset
//! ([`union_schema`]), published as `_schemas/<topic>.parquet` so that an engine that
//! takes one schema for a folder of files (Spark) reads every version through it.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use arrow_schema::{DataType, Field, Fields, Schema};

/// The folder of a dataset that holds each topic's union schema, one file per topic
/// folder (`_schemas/<folder>.parquet`, no rows). Its name starts with `_`, which
/// query engines skip when they discover a table's files.
pub const SCHEMAS_DIR: &str = "_schemas";

/// The key of a union schema's metadata that names its topic.
pub const TOPIC_KEY: &str = "ulog.union.topic";

/// The key of a union schema's metadata that lists the fields left out of it: their
/// types differ across the files in a way no widening holds losslessly (`path: type
/// and type`, separated by `; `). A union schema given to [`union_schema`] again
/// keeps them out.
pub const CONFLICTS_KEY: &str = "ulog.union.conflicts";

/// The schema every one of `schemas` widens into, by field name (nested structs
/// field by field), in the order fields first appear:
///
/// - a field some schemas lack is nullable (NULL there);
/// - integers widen to the smallest type that holds both (`uint8` and `int32` →
///   `int32`; `uint32` and `int32` → `int64`), floats to the wider float;
/// - fixed-size lists of different lengths become lists, of the items' union;
/// - anything else that differs (an integer and a float, a number and a string,
///   `uint64` and a signed type) has no lossless widening: the field is left out, and
///   named in the metadata under [`CONFLICTS_KEY`].
///
/// ```
/// use ulog_core::export::arrow_schema::{DataType, Field, Schema};
/// use ulog_core::export::union_schema;
/// let v1 = Schema::new(vec![Field::new("cell_count", DataType::Int32, false)]);
/// let v2 = Schema::new(vec![
///     Field::new("cell_count", DataType::UInt8, false),
///     Field::new("temperature", DataType::Float32, false),
/// ]);
/// let union = union_schema([&v1, &v2], "battery_status");
/// assert_eq!(union.field_with_name("cell_count")?.data_type(), &DataType::Int32);
/// assert!(union.field_with_name("temperature")?.is_nullable());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn union_schema<'a>(schemas: impl IntoIterator<Item = &'a Schema>, topic: &str) -> Schema {
    let mut conflicts = Vec::new();
    let mut merged: Option<Fields> = None;
    let mut positions: BTreeMap<String, usize> = BTreeMap::new();
    for schema in schemas {
        match schema.metadata().get(ORDER_KEY) {
            // A union read back: the positions it recorded.
            Some(text) => {
                for item in text.split(';') {
                    if let Some((path, at)) = item.rsplit_once('=') {
                        if let Ok(at) = at.parse::<usize>() {
                            least(&mut positions, path, at);
                        }
                    }
                }
            }
            None => record_positions(schema.fields(), "", &mut positions),
        }
        // A union read back keeps the conflicts it had: the fields stay out.
        if let Some(text) = schema.metadata().get(CONFLICTS_KEY) {
            for item in text.split("; ") {
                if let Some((path, types)) = item.split_once(": ") {
                    conflicts.push((path.to_owned(), types.to_owned()));
                }
            }
        }

        merged = Some(match merged {
            None => schema.fields().clone(),
            Some(m) => union_fields(&m, schema.fields(), "", &mut conflicts),
        });
    }
    let mut fields = merged.unwrap_or_default();
    // A conflict of an earlier union whose field a later schema brought back.
    if !conflicts.is_empty() {
        fields = fields
            .iter()
            .filter_map(|f| without_conflicts(f, "", &conflicts))
            .collect();
    }
    // The same union whatever order the schemas came in: fields by where they first
    // stand in any of them, then by name; no type of one version in their metadata.
    let fields = canonical(&fields, "", &positions);
    let mut metadata = std::collections::HashMap::new();
    // Not `ulog.topic`, which names the topic of a file of rows: a search of the
    // dataset's files by it finds those.
    metadata.insert(TOPIC_KEY.to_owned(), topic.to_owned());
    let order: Vec<String> = positions
        .iter()
        .map(|(p, at)| format!("{p}={at}"))
        .collect();
    metadata.insert(ORDER_KEY.to_owned(), order.join(";"));
    // Each path once, with every type met.
    let mut by_path: BTreeMap<String, std::collections::BTreeSet<String>> = BTreeMap::new();
    for (path, types) in &conflicts {
        by_path
            .entry(path.clone())
            .or_default()
            .extend(types.split(" and ").map(str::to_owned));
    }
    if !by_path.is_empty() {
        let text: Vec<String> = by_path
            .iter()
            .map(|(p, types)| {
                format!(
                    "{p}: {}",
                    types.iter().cloned().collect::<Vec<_>>().join(" and ")
                )
            })
            .collect();
        metadata.insert(CONFLICTS_KEY.to_owned(), text.join("; "));
    }
    Schema::new_with_metadata(fields, metadata)
}

/// The key of a union schema's metadata that keeps, for each field (`a.b` inside a
/// struct, `a[]` a list's items), the least position it had in any schema of the
/// union: the order of its fields, which a union made again of it and more schemas
/// keeps, whatever the order they come in.
const ORDER_KEY: &str = "ulog.union.order";

fn least(positions: &mut BTreeMap<String, usize>, path: &str, at: usize) {
    let entry = positions.entry(path.to_owned()).or_insert(at);
    *entry = (*entry).min(at);
}

/// The position of each field of `fields` (and of the fields nested in them).
fn record_positions(fields: &Fields, prefix: &str, positions: &mut BTreeMap<String, usize>) {
    for (i, f) in fields.iter().enumerate() {
        let path = format!("{prefix}{}", f.name());
        least(positions, &path, i);
        nested_positions(f.data_type(), &path, positions);
    }
}

fn nested_positions(t: &DataType, path: &str, positions: &mut BTreeMap<String, usize>) {
    match t {
        DataType::Struct(inner) => record_positions(inner, &format!("{path}."), positions),
        DataType::List(item) | DataType::FixedSizeList(item, _) => {
            nested_positions(item.data_type(), &format!("{path}[]"), positions)
        }
        _ => {}
    }
}

/// `fields` ordered by their recorded positions then names, nested ones too, each
/// field's metadata but its unit left out (`ulog.type` is one version's type).
fn canonical(fields: &Fields, prefix: &str, positions: &BTreeMap<String, usize>) -> Fields {
    let mut out: Vec<(usize, String, Arc<Field>)> = fields
        .iter()
        .map(|f| {
            let path = format!("{prefix}{}", f.name());
            let at = positions.get(&path).copied().unwrap_or(usize::MAX);
            let ty = canonical_type(f.data_type(), &path, positions);
            let metadata = f
                .metadata()
                .iter()
                .filter(|(k, _)| k.as_str() == "unit")
                .map(|(k, v)| (k.clone(), v.clone()))
                .collect();
            let field = f
                .as_ref()
                .clone()
                .with_data_type(ty)
                .with_metadata(metadata);
            (at, f.name().clone(), Arc::new(field))
        })
        .collect();
    out.sort_by(|a, b| (a.0, &a.1).cmp(&(b.0, &b.1)));
    out.into_iter().map(|(_, _, f)| f).collect()
}

fn canonical_type(t: &DataType, path: &str, positions: &BTreeMap<String, usize>) -> DataType {
    let item = |f: &Arc<Field>| {
        let ty = canonical_type(f.data_type(), &format!("{path}[]"), positions);
        Arc::new(
            f.as_ref()
                .clone()
                .with_data_type(ty)
                .with_metadata(Default::default()),
        )
    };
    match t {
        DataType::Struct(inner) => {
            DataType::Struct(canonical(inner, &format!("{path}."), positions))
        }
        DataType::List(f) => DataType::List(item(f)),
        DataType::FixedSizeList(f, n) => DataType::FixedSizeList(item(f), *n),
        other => other.clone(),
    }
}

/// `a`'s fields widened by `b`'s, then `b`'s new fields, nullable.
fn union_fields(
    a: &Fields,
    b: &Fields,
    path: &str,
    conflicts: &mut Vec<(String, String)>,
) -> Fields {
    let in_b: BTreeMap<&str, &Arc<Field>> = b.iter().map(|f| (f.name().as_str(), f)).collect();
    let in_a: BTreeMap<&str, &Arc<Field>> = a.iter().map(|f| (f.name().as_str(), f)).collect();
    let mut out: Vec<Arc<Field>> = Vec::with_capacity(a.len().max(b.len()));
    for fa in a.iter() {
        let here = format!("{path}{}", fa.name());
        match in_b.get(fa.name().as_str()) {
            None => out.push(Arc::new(fa.as_ref().clone().with_nullable(true))),
            Some(fb) => {
                let ty = widen(fa.data_type(), fb.data_type(), &here, conflicts)
                    .unwrap_or_else(|| fa.data_type().clone());
                let nullable = fa.is_nullable() || fb.is_nullable();
                out.push(Arc::new(
                    fa.as_ref()
                        .clone()
                        .with_data_type(ty)
                        .with_nullable(nullable),
                ));
            }
        }
    }
    for fb in b.iter() {
        if !in_a.contains_key(fb.name().as_str()) {
            out.push(Arc::new(fb.as_ref().clone().with_nullable(true)));
        }
    }
    out.into()
}

/// The type both `a` and `b` widen into losslessly, or `None` (a conflict noted at
/// `path`).
fn widen(
    a: &DataType,
    b: &DataType,
    path: &str,
    conflicts: &mut Vec<(String, String)>,
) -> Option<DataType> {
    use DataType as T;
    if a == b {
        return Some(a.clone());
    }
    let found = match (a, b) {
        (T::Struct(fa), T::Struct(fb)) => Some(T::Struct(union_fields(
            fa,
            fb,
            &format!("{path}."),
            conflicts,
        ))),
        (T::FixedSizeList(fa, na), T::FixedSizeList(fb, nb)) => {
            let item = widen(
                fa.data_type(),
                fb.data_type(),
                &format!("{path}[]"),
                conflicts,
            )?;
            let nullable = fa.is_nullable() || fb.is_nullable();
            let field = Arc::new(
                fa.as_ref()
                    .clone()
                    .with_data_type(item)
                    .with_nullable(nullable),
            );
            Some(if na == nb {
                T::FixedSizeList(field, *na)
            } else {
                T::List(field)
            })
        }
        (T::FixedSizeList(fa, _) | T::List(fa), T::FixedSizeList(fb, _) | T::List(fb)) => {
            let item = widen(
                fa.data_type(),
                fb.data_type(),
                &format!("{path}[]"),
                conflicts,
            )?;
            let nullable = fa.is_nullable() || fb.is_nullable();
            Some(T::List(Arc::new(
                fa.as_ref()
                    .clone()
                    .with_data_type(item)
                    .with_nullable(nullable),
            )))
        }
        _ => match (integer(a), integer(b)) {
            (Some(x), Some(y)) => integer_union(x, y),
            _ => match (float_bits(a), float_bits(b)) {
                (Some(x), Some(y)) => Some(if x >= y { a.clone() } else { b.clone() }),
                _ => None,
            },
        },
    };
    if found.is_none() && !matches!((a, b), (T::Struct(_), T::Struct(_))) {
        conflicts.push((path.to_owned(), format!("{a} and {b}")));
    }
    found
}

/// An integer type as (signed, bits).
fn integer(t: &DataType) -> Option<(bool, u8)> {
    use DataType as T;
    Some(match t {
        T::Int8 => (true, 8),
        T::Int16 => (true, 16),
        T::Int32 => (true, 32),
        T::Int64 => (true, 64),
        T::UInt8 => (false, 8),
        T::UInt16 => (false, 16),
        T::UInt32 => (false, 32),
        T::UInt64 => (false, 64),
        _ => return None,
    })
}

fn float_bits(t: &DataType) -> Option<u8> {
    match t {
        DataType::Float16 => Some(16),
        DataType::Float32 => Some(32),
        DataType::Float64 => Some(64),
        _ => None,
    }
}

/// The smallest integer type that holds every value of both.
fn integer_union(a: (bool, u8), b: (bool, u8)) -> Option<DataType> {
    let (signed, bits) = match (a, b) {
        ((true, x), (true, y)) => (true, x.max(y)),
        ((false, x), (false, y)) => (false, x.max(y)),
        ((true, s), (false, u)) | ((false, u), (true, s)) => {
            if u >= 64 {
                return None;
            }
            (true, s.max(u * 2))
        }
    };
    use DataType as T;
    Some(match (signed, bits) {
        (true, 8) => T::Int8,
        (true, 16) => T::Int16,
        (true, 32) => T::Int32,
        (true, _) => T::Int64,
        (false, 8) => T::UInt8,
        (false, 16) => T::UInt16,
        (false, 32) => T::UInt32,
        (false, _) => T::UInt64,
    })
}

/// `field` without the parts named in `conflicts` (paths below `path`); `None` when
/// the field itself conflicts.
fn without_conflicts(
    field: &Field,
    path: &str,
    conflicts: &[(String, String)],
) -> Option<Arc<Field>> {
    let here = format!("{path}{}", field.name());
    // The field, or a list's items in it (a list is kept or left out whole).
    let items = format!("{here}[]");
    if conflicts
        .iter()
        .any(|(p, _)| *p == here || p.starts_with(&items))
    {
        return None;
    }
    let below = format!("{here}.");
    if !conflicts.iter().any(|(p, _)| p.starts_with(&below)) {
        return Some(Arc::new(field.clone()));
    }
    match field.data_type() {
        DataType::Struct(fields) => {
            let kept: Fields = fields
                .iter()
                .filter_map(|f| without_conflicts(f, &below, conflicts))
                .collect();
            Some(Arc::new(
                field.clone().with_data_type(DataType::Struct(kept)),
            ))
        }
        _ => Some(Arc::new(field.clone())),
    }
}

/// The Arrow schema of the Parquet file at `path` (from its footer).
pub(super) fn file_schema(path: &Path) -> Result<Schema, super::ExportError> {
    let file = std::fs::File::open(path).map_err(|e| super::ExportError::io(e, path))?;
    let builder = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(file)
        .map_err(|e| super::ExportError::encoding(e).in_file(path))?;
    Ok(builder.schema().as_ref().clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(name: &str, t: DataType) -> Field {
        Field::new(name, t, false)
    }

    fn versions() -> Vec<Schema> {
        let esc = |n| {
            DataType::FixedSizeList(
                Arc::new(Field::new(
                    "item",
                    DataType::Struct(vec![f("rpm", DataType::Int32)].into()),
                    false,
                )),
                n,
            )
        };
        vec![
            Schema::new(vec![
                f("timestamp", DataType::UInt64),
                f("cell_count", DataType::Int32),
                f("voltage", DataType::Float32),
                f("esc", esc(8)),
                f("dt", DataType::Float32),
            ]),
            Schema::new(vec![
                f("timestamp", DataType::UInt64),
                f("current", DataType::Float32),
                f("cell_count", DataType::UInt8),
                f("voltage", DataType::Float64),
                f("esc", esc(4)),
                f("dt", DataType::UInt32),
            ]),
            Schema::new(vec![
                f("timestamp", DataType::UInt64),
                f("cell_count", DataType::UInt32),
                f("flags", DataType::Boolean),
            ]),
        ]
    }

    #[test]
    fn types_widen_losslessly_and_conflicts_are_left_out() {
        let union = union_schema(versions().iter(), "t");
        let ty = |n: &str| union.field_with_name(n).map(|f| f.data_type().clone());
        // u8, i32 and u32: int64 holds them all.
        assert_eq!(ty("cell_count").unwrap(), DataType::Int64);
        assert_eq!(ty("voltage").unwrap(), DataType::Float64);
        assert!(matches!(ty("esc").unwrap(), DataType::List(_)));
        assert!(
            union.field_with_name("dt").is_err(),
            "float and uint32 conflict"
        );
        assert_eq!(
            union.metadata().get(CONFLICTS_KEY).map(String::as_str),
            Some("dt: Float32 and UInt32")
        );
        // Present everywhere: not nullable; missing somewhere: nullable.
        assert!(!union.field_with_name("timestamp").unwrap().is_nullable());
        assert!(union.field_with_name("current").unwrap().is_nullable());
        assert!(union.field_with_name("flags").unwrap().is_nullable());
        assert_eq!(integer_union((false, 64), (true, 64)), None);
        assert_eq!(integer_union((false, 16), (true, 8)), Some(DataType::Int32));
    }

    #[test]
    fn the_union_does_not_depend_on_the_order_or_on_being_made_in_steps() {
        let v = versions();
        let whole = union_schema(v.iter(), "t");
        for order in [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
        ] {
            let again = union_schema(order.iter().map(|&i| &v[i]), "t");
            assert_eq!(again, whole, "{order:?}");
            // In two steps, the first union read back as the published one is.
            let first = union_schema([&v[order[0]], &v[order[1]]], "t");
            let steps = union_schema([&first, &v[order[2]]], "t");
            assert_eq!(steps, whole, "{order:?} in steps");
        }
        // A conflict stays out though the field comes back in a later version.
        let first = union_schema([&v[0], &v[1]], "t");
        let later = union_schema([&first, &v[0]], "t");
        assert!(later.field_with_name("dt").is_err());
    }
}
