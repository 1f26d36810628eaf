//! [`FieldReader`]: a field path resolved once against a topic's layout, then read
//! from every payload with a load at a fixed offset.

use ulog_format::{BasicType, Layout, LeafKind};

use crate::value::{LogText, Value, ValueArray};

/// What a resolved field path reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldShape {
    /// One value.
    Scalar,
    /// A whole array of `n` values.
    Array(usize),
    /// A `char[n]` string.
    String(usize),
}

/// A field path resolved against a topic's layout: read it from any payload of that
/// topic with [`FieldReader::read`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldReader {
    pub(crate) path: String,
    pub(crate) offset: usize,
    pub(crate) ty: BasicType,
    pub(crate) shape: FieldShape,
}

impl FieldReader {
    /// The path it was resolved from.
    pub fn path(&self) -> &str {
        &self.path
    }

    /// Byte offset in the payload.
    pub fn offset(&self) -> usize {
        self.offset
    }

    /// The basic (element) type.
    pub fn ty(&self) -> BasicType {
        self.ty
    }

    /// Scalar, array or string.
    pub fn shape(&self) -> FieldShape {
        self.shape
    }

    #[inline]
    fn size(&self) -> usize {
        match self.shape {
            FieldShape::Scalar => self.ty.size(),
            FieldShape::Array(n) | FieldShape::String(n) => n * self.ty.size(),
        }
    }

    /// The field's value in `payload`; `None` if the payload is too short (a field in
    /// omitted trailing padding).
    #[inline]
    pub fn read<'a>(&self, payload: &'a [u8]) -> Option<Value<'a>> {
        let b = payload.get(self.offset..self.offset + self.size())?;
        Some(match self.shape {
            FieldShape::Scalar => Value::read_scalar(self.ty, b),
            FieldShape::Array(_) => Value::Array(ValueArray::new(self.ty, b)),
            FieldShape::String(_) => Value::Str(LogText(b)),
        })
    }

    /// The field as `f64` (numbers and booleans).
    #[inline]
    pub fn read_f64(&self, payload: &[u8]) -> Option<f64> {
        if self.shape != FieldShape::Scalar {
            return None;
        }
        let b = payload.get(self.offset..self.offset + self.ty.size())?;
        Value::read_scalar(self.ty, b).as_f64()
    }
}

impl FieldReader {
    /// Readers for every leaf field of `layout` (padding left out; arrays element by
    /// element, `char[N]` as one string), as [`Topic::fields`](crate::Topic::fields)
    /// gives them: for payloads met without a parsed log (a pass's records), resolved
    /// once per subscription.
    ///
    /// ```
    /// let layout = ulog_core::format::Resolver::default()
    ///     .resolve("t", &[ulog_core::format::Format::parse("t:uint64_t timestamp;float[2] v;").unwrap()][..])
    ///     .unwrap();
    /// let paths: Vec<String> = ulog_core::FieldReader::all(&layout)
    ///     .iter()
    ///     .map(|c| c.path().to_owned())
    ///     .collect();
    /// assert_eq!(paths, ["timestamp", "v[0]", "v[1]"]);
    /// ```
    pub fn all(layout: &Layout) -> Vec<FieldReader> {
        layout
            .columns()
            .map(|leaf| FieldReader {
                path: leaf.path.clone(),
                offset: leaf.offset,
                ty: leaf.ty,
                shape: if leaf.kind == LeafKind::String {
                    FieldShape::String(leaf.count)
                } else {
                    FieldShape::Scalar
                },
            })
            .collect()
    }
}
