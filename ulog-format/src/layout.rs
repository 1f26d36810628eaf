//! Layout: where every field of a format lies in a message payload.
//!
//! A [`Layout`] is a [`Format`] with its nested types resolved: every field's offset
//! and size, nested types laid out with their own (internal and trailing) padding, the
//! full size and the size without the trailing padding (which writers may omit), and
//! the flattened leaf fields in the order and with the paths that pyulog's columns use
//! (`timestamp`, `q[0]`, `esc[3].esc_rpm`, a `char[N]` string as one leaf).

use std::collections::{BTreeMap, HashMap};
use std::sync::{Arc, OnceLock};

use crate::basic::BasicType;
use crate::error::{LayoutError, LayoutErrorKind};
use crate::parse::{Format, TypeName};

/// Anything that finds a format by name: the formats of one log, or of one macro
/// invocation.
pub trait FormatLookup {
    /// The format with this name.
    fn lookup_format(&self, name: &str) -> Option<&Format>;
}

impl FormatLookup for [Format] {
    fn lookup_format(&self, name: &str) -> Option<&Format> {
        self.iter().rev().find(|f| f.name == name)
    }
}

impl FormatLookup for Vec<Format> {
    fn lookup_format(&self, name: &str) -> Option<&Format> {
        self.as_slice().lookup_format(name)
    }
}

impl<S: std::hash::BuildHasher> FormatLookup for HashMap<String, Format, S> {
    fn lookup_format(&self, name: &str) -> Option<&Format> {
        self.get(name)
    }
}

impl FormatLookup for BTreeMap<String, Format> {
    fn lookup_format(&self, name: &str) -> Option<&Format> {
        self.get(name)
    }
}

/// Bounds that a hostile log cannot push layout resolution past.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Deepest nesting of formats (a top-level format is depth 1).
    pub max_depth: usize,
    /// Largest size in bytes of a laid-out format. A data message cannot carry more
    /// than 65,533 bytes, so no loggable format is larger.
    pub max_size: usize,
    /// Most fields and array elements a layout may expand to, nested ones counted as
    /// often as they occur (zero-size arrays count too, so that a small size cannot
    /// hide an exponential tree).
    pub max_nodes: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_depth: 32,
            max_size: 65535,
            max_nodes: 1 << 18,
        }
    }
}

/// The type of a laid-out field.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LayoutType {
    /// A basic type.
    Basic(BasicType),
    /// A nested format, laid out.
    Nested(Arc<Layout>),
}

impl LayoutType {
    /// Size in bytes of one element.
    pub fn size(&self) -> usize {
        match self {
            LayoutType::Basic(b) => b.size(),
            LayoutType::Nested(l) => l.size(),
        }
    }

    /// The type name as written in a format string.
    pub fn name(&self) -> &str {
        match self {
            LayoutType::Basic(b) => b.name(),
            LayoutType::Nested(l) => l.name(),
        }
    }
}

/// A field of a layout, with its place in the payload.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LayoutField {
    /// The field name.
    pub name: String,
    /// Its type.
    pub ty: LayoutType,
    /// The array length, for arrays.
    pub array_len: Option<usize>,
    /// Byte offset from the start of the enclosing format.
    pub offset: usize,
    /// Size in bytes of the whole field (all array elements).
    pub size: usize,
}

impl LayoutField {
    /// Whether this is a padding field.
    pub fn is_padding(&self) -> bool {
        crate::is_padding_name(&self.name)
    }
}

/// What a leaf holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LeafKind {
    /// One value of a basic type (an array element counts as one).
    Scalar,
    /// A `char[N]` string, `count` bytes.
    String,
    /// Padding bytes (`count` of them), never shown as a value.
    Padding,
}

/// A flattened leaf field: one column of a table of the topic.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Leaf {
    /// The path, as pyulog names columns: `a`, `a[2]`, `outer.inner`, `outer[1].inner`.
    pub path: String,
    /// Byte offset in the payload.
    pub offset: usize,
    /// The basic type (for padding, `uint8_t`).
    pub ty: BasicType,
    /// Number of values: 1 for a scalar, `N` for a `char[N]` string or padding bytes.
    pub count: usize,
    /// Scalar, string or padding.
    pub kind: LeafKind,
}

/// The place of a field found by path (see [`Layout::find`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldRef {
    /// Byte offset in the payload.
    pub offset: usize,
    /// The element type.
    pub ty: LayoutType,
    /// Number of elements: the array length for a whole array, otherwise 1.
    pub count: usize,
    /// Whether the path names a whole array (not one element of it).
    pub is_array: bool,
}

impl FieldRef {
    /// Size in bytes of what the path names.
    pub fn size(&self) -> usize {
        self.ty.size() * self.count
    }
}

/// A format with its nested types resolved and every field placed.
///
/// The flattened leaves are computed on first use: a small format text can describe
/// tens of thousands of leaves (`uint8_t[65535] x`), and a reader that lays out every
/// subscription of a hostile file must not pay for them up front.
#[derive(Debug, Clone)]
pub struct Layout {
    format: Format,
    fields: Vec<LayoutField>,
    size: usize,
    trailing_padding: usize,
    depth: usize,
    nodes: usize,
    leaves: OnceLock<Vec<Leaf>>,
}

impl PartialEq for Layout {
    /// Two layouts are equal when they are made of the same formats (each compared
    /// once, so that shared nested formats do not make the comparison exponential).
    fn eq(&self, other: &Layout) -> bool {
        self.size == other.size
            && self.trailing_padding == other.trailing_padding
            && self.formats() == other.formats()
    }
}

impl Eq for Layout {}

impl Layout {
    /// Resolves the format `name` from `formats` with the default [`Limits`].
    pub fn resolve<L: FormatLookup + ?Sized>(
        name: &str,
        formats: &L,
    ) -> Result<Layout, LayoutError> {
        Resolver::new(Limits::default())
            .resolve(name, formats)
            .map(|l| (*l).clone())
    }

    /// The message name.
    pub fn name(&self) -> &str {
        &self.format.name
    }

    /// The format this layout was made from.
    pub fn format(&self) -> &Format {
        &self.format
    }

    /// The top-level fields, placed.
    pub fn fields(&self) -> &[LayoutField] {
        &self.fields
    }

    /// Nesting depth: 1 for a format of basic fields only.
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// Fields and array elements the layout expands to, nested ones counted as often
    /// as they occur (bounded by [`Limits::max_nodes`]).
    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// The full size in bytes, padding included.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Bytes of top-level padding at the end, which a writer may leave out of a data
    /// message.
    pub fn trailing_padding(&self) -> usize {
        self.trailing_padding
    }

    /// The size without the trailing padding.
    pub fn min_size(&self) -> usize {
        self.size - self.trailing_padding
    }

    /// Whether a data payload of `len` bytes is valid for this format: the full size,
    /// or the full size without the trailing padding.
    pub fn accepts_len(&self, len: usize) -> bool {
        len == self.size || len == self.min_size()
    }

    /// Every leaf, padding included, in payload order (computed on first use).
    pub fn leaves(&self) -> &[Leaf] {
        self.leaves.get_or_init(|| {
            let mut leaves = Vec::new();
            push_leaves(&self.fields, "", 0, false, &mut leaves);
            leaves
        })
    }

    /// The leaves that are values (no padding), in pyulog's column order.
    pub fn columns(&self) -> impl Iterator<Item = &Leaf> {
        self.leaves().iter().filter(|l| l.kind != LeafKind::Padding)
    }

    /// The top-level field with this name.
    pub fn field(&self, name: &str) -> Option<&LayoutField> {
        self.fields.iter().find(|f| f.name == name)
    }

    /// Finds a field by path: `timestamp`, `q`, `q[2]`, `esc[3].esc_rpm`, `esc[1]`.
    pub fn find(&self, path: &str) -> Option<FieldRef> {
        let mut layout = self;
        let mut base = 0usize;
        let mut parts = path.split('.').peekable();
        while let Some(part) = parts.next() {
            let (name, index) = match part.find('[') {
                Some(open) => {
                    let idx = part[open + 1..].strip_suffix(']')?.parse::<usize>().ok()?;
                    (&part[..open], Some(idx))
                }
                None => (part, None),
            };
            let field = layout.field(name)?;
            let elem = field.ty.size();
            let (offset, count, is_array) = match (index, field.array_len) {
                (Some(i), Some(n)) if i < n => (base + field.offset + i * elem, 1, false),
                (Some(_), _) => return None,
                (None, Some(n)) => (base + field.offset, n, true),
                (None, None) => (base + field.offset, 1, false),
            };
            if parts.peek().is_none() {
                return Some(FieldRef {
                    offset,
                    ty: field.ty.clone(),
                    count,
                    is_array,
                });
            }
            match &field.ty {
                LayoutType::Nested(inner) if !is_array => {
                    layout = inner;
                    base = offset;
                }
                _ => return None,
            }
        }
        None
    }

    /// Every format this layout uses, itself last, each once, nested ones before the
    /// formats that use them: the `F` messages a writer must emit.
    pub fn formats(&self) -> Vec<&Format> {
        let mut out: Vec<&Format> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        self.collect_formats(&mut out, &mut seen);
        out
    }

    fn collect_formats<'a>(
        &'a self,
        out: &mut Vec<&'a Format>,
        seen: &mut std::collections::HashSet<&'a str>,
    ) {
        if !seen.insert(&self.format.name) {
            return;
        }
        for f in &self.fields {
            if let LayoutType::Nested(inner) = &f.ty {
                inner.collect_formats(out, seen);
            }
        }
        out.push(&self.format);
    }
}

/// Resolves formats into layouts, sharing the layouts of nested formats between the
/// formats that use them. One resolver serves one set of formats (one log).
#[derive(Debug, Default, Clone)]
pub struct Resolver {
    limits: Limits,
    done: HashMap<String, Result<Arc<Layout>, LayoutError>>,
}

impl Resolver {
    /// A resolver with these limits.
    pub fn new(limits: Limits) -> Resolver {
        Resolver {
            limits,
            done: HashMap::new(),
        }
    }

    /// The layout of format `name`, or why it has none.
    pub fn resolve<L: FormatLookup + ?Sized>(
        &mut self,
        name: &str,
        formats: &L,
    ) -> Result<Arc<Layout>, LayoutError> {
        let mut stack = Vec::new();
        self.resolve_inner(name, formats, &mut stack)
            .map_err(|kind| LayoutError {
                format: name.to_owned(),
                kind,
            })
    }

    /// Forgets every layout, for when the set of formats changes.
    pub fn clear(&mut self) {
        self.done.clear();
    }

    fn resolve_inner<L: FormatLookup + ?Sized>(
        &mut self,
        name: &str,
        formats: &L,
        stack: &mut Vec<String>,
    ) -> Result<Arc<Layout>, LayoutErrorKind> {
        if let Some(done) = self.done.get(name) {
            // A layout laid out before may sit deeper here than where it was made.
            if let Ok(l) = done {
                if stack.len() + l.depth > self.limits.max_depth {
                    return Err(LayoutErrorKind::TooDeep {
                        limit: self.limits.max_depth,
                    });
                }
            }
            return done.clone().map_err(|e| e.kind);
        }
        if stack.iter().any(|s| s == name) {
            let mut chain = stack.clone();
            chain.push(name.to_owned());
            return Err(LayoutErrorKind::Cycle { chain });
        }
        if stack.len() >= self.limits.max_depth {
            return Err(LayoutErrorKind::TooDeep {
                limit: self.limits.max_depth,
            });
        }
        let Some(format) = formats.lookup_format(name) else {
            return Err(LayoutErrorKind::UnknownType {
                name: name.to_owned(),
            });
        };
        stack.push(name.to_owned());
        let result = self.lay_out(format, formats, stack);
        stack.pop();
        // Errors that depend on the path taken (cycles, depth) are not cached, so that
        // the same format reached another way is judged on its own.
        match &result {
            Ok(layout) => {
                self.done.insert(name.to_owned(), Ok(layout.clone()));
            }
            Err(kind @ LayoutErrorKind::UnknownType { .. })
            | Err(kind @ LayoutErrorKind::TooLarge { .. }) => {
                self.done.insert(
                    name.to_owned(),
                    Err(LayoutError {
                        format: name.to_owned(),
                        kind: kind.clone(),
                    }),
                );
            }
            Err(_) => {}
        }
        result
    }

    fn lay_out<L: FormatLookup + ?Sized>(
        &mut self,
        format: &Format,
        formats: &L,
        stack: &mut Vec<String>,
    ) -> Result<Arc<Layout>, LayoutErrorKind> {
        let too_large = LayoutErrorKind::TooLarge {
            what: "size",
            limit: self.limits.max_size,
        };
        let too_many = LayoutErrorKind::TooLarge {
            what: "fields and elements",
            limit: self.limits.max_nodes,
        };
        let mut fields = Vec::with_capacity(format.fields.len());
        let mut offset = 0usize;
        let mut depth = 1usize;
        let mut nodes = 0usize;
        for field in &format.fields {
            let ty = match &field.ty {
                TypeName::Basic(b) => LayoutType::Basic(*b),
                TypeName::Nested(n) => LayoutType::Nested(self.resolve_inner(n, formats, stack)?),
            };
            let n = field.array_len.unwrap_or(1);
            let per_element = match &ty {
                LayoutType::Basic(_) => 1,
                LayoutType::Nested(inner) => {
                    depth = depth.max(inner.depth + 1);
                    inner.nodes
                }
            };
            nodes = per_element
                .checked_mul(n)
                .and_then(|x| x.checked_add(nodes + 1))
                .filter(|&x| x <= self.limits.max_nodes)
                .ok_or_else(|| too_many.clone())?;
            let size = ty
                .size()
                .checked_mul(field.array_len.unwrap_or(1))
                .filter(|&s| s <= self.limits.max_size)
                .ok_or_else(|| too_large.clone())?;
            fields.push(LayoutField {
                name: field.name.clone(),
                ty,
                array_len: field.array_len,
                offset,
                size,
            });
            offset += size;
            if offset > self.limits.max_size {
                return Err(too_large);
            }
        }
        let trailing_padding = fields
            .iter()
            .rev()
            .take_while(|f| f.is_padding())
            .map(|f| f.size)
            .sum();
        Ok(Arc::new(Layout {
            format: format.clone(),
            fields,
            size: offset,
            trailing_padding,
            depth,
            nodes,
            leaves: OnceLock::new(),
        }))
    }
}

fn push_leaves(
    fields: &[LayoutField],
    prefix: &str,
    base: usize,
    in_padding: bool,
    out: &mut Vec<Leaf>,
) {
    for f in fields {
        let path = format!("{prefix}{}", f.name);
        let offset = base + f.offset;
        if in_padding || f.is_padding() {
            out.push(Leaf {
                path,
                offset,
                ty: BasicType::UInt8,
                count: f.size,
                kind: LeafKind::Padding,
            });
            continue;
        }
        match (&f.ty, f.array_len) {
            (LayoutType::Basic(BasicType::Char), Some(n)) => out.push(Leaf {
                path,
                offset,
                ty: BasicType::Char,
                count: n,
                kind: LeafKind::String,
            }),
            (LayoutType::Basic(b), Some(n)) => {
                for i in 0..n {
                    out.push(Leaf {
                        path: format!("{path}[{i}]"),
                        offset: offset + i * b.size(),
                        ty: *b,
                        count: 1,
                        kind: LeafKind::Scalar,
                    });
                }
            }
            (LayoutType::Basic(b), None) => out.push(Leaf {
                path,
                offset,
                ty: *b,
                count: 1,
                kind: LeafKind::Scalar,
            }),
            (LayoutType::Nested(inner), Some(n)) => {
                for i in 0..n {
                    let p = format!("{path}[{i}].");
                    push_leaves(&inner.fields, &p, offset + i * inner.size, false, out);
                }
            }
            (LayoutType::Nested(inner), None) => {
                push_leaves(&inner.fields, &format!("{path}."), offset, false, out);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn formats(texts: &[&str]) -> Vec<Format> {
        texts.iter().map(|t| Format::parse(t).unwrap()).collect()
    }

    #[test]
    fn nested_types_keep_their_own_padding() {
        let f = formats(&[
            "esc_status:uint64_t timestamp;uint16_t counter;uint8_t esc_count;uint8_t esc_connectiontype;uint8_t[4] _padding0;esc_report[8] esc;",
            "esc_report:uint64_t timestamp;uint32_t esc_errorcount;int32_t esc_rpm;float esc_voltage;float esc_current;float esc_temperature;float esc_setpoint;uint16_t esc_setpoint_raw;uint16_t esc_address;uint16_t esc_version;uint16_t esc_state;uint8_t esc_vendor;uint8_t[7] _padding0;",
        ]);
        let l = Layout::resolve("esc_status", &f).unwrap();
        assert_eq!(l.size(), 400);
        // The last field is a nested type, not padding: nothing may be omitted.
        assert_eq!(l.trailing_padding(), 0);
        let cols: Vec<_> = l.columns().map(|c| c.path.as_str()).collect();
        assert_eq!(cols.len(), 4 + 8 * 12);
        assert_eq!(cols[4], "esc[0].timestamp");
        assert_eq!(cols[4 + 12 + 2], "esc[1].esc_rpm");
        let rpm = l.find("esc[1].esc_rpm").unwrap();
        assert_eq!(rpm.offset, 16 + 48 + 12);
        assert_eq!(rpm.ty, LayoutType::Basic(BasicType::Int32));
        assert_eq!(l.find("esc[8].esc_rpm"), None);
        assert_eq!(l.find("esc.esc_rpm"), None);
        let esc = l.find("esc").unwrap();
        assert_eq!((esc.count, esc.is_array, esc.size()), (8, true, 384));
        assert_eq!(
            l.formats()
                .iter()
                .map(|f| f.name.as_str())
                .collect::<Vec<_>>(),
            ["esc_report", "esc_status"]
        );
    }

    #[test]
    fn trailing_padding_and_accepted_lengths() {
        let f =
            formats(&["m:uint64_t timestamp;uint8_t a;uint8_t[3] _padding0;uint8_t[4] _padding1;"]);
        let l = Layout::resolve("m", &f).unwrap();
        assert_eq!((l.size(), l.trailing_padding(), l.min_size()), (16, 7, 9));
        assert!(l.accepts_len(16) && l.accepts_len(9));
        assert!(!l.accepts_len(10) && !l.accepts_len(17));
    }

    #[test]
    fn strings_and_arrays_flatten_like_pyulog() {
        let f = formats(&["m:uint64_t timestamp;char[4] name;float[2] q;"]);
        let l = Layout::resolve("m", &f).unwrap();
        let cols: Vec<_> = l
            .columns()
            .map(|c| (c.path.as_str(), c.kind, c.count))
            .collect();
        assert_eq!(
            cols,
            [
                ("timestamp", LeafKind::Scalar, 1),
                ("name", LeafKind::String, 4),
                ("q[0]", LeafKind::Scalar, 1),
                ("q[1]", LeafKind::Scalar, 1)
            ]
        );
    }

    #[test]
    fn cycles_unknown_types_and_limits_fail_only_that_format() {
        let f = formats(&[
            "a:b[2] x;",
            "b:a[4] y;",
            "c:nothing z;",
            "ok:uint8_t v;",
            "big:uint8_t[60000] x;uint8_t[60000] y;",
            "wide:huge[65535] x;",
            "huge:uint64_t[8000] v;",
        ]);
        let mut r = Resolver::new(Limits::default());
        match r.resolve("a", &f).unwrap_err().kind {
            LayoutErrorKind::Cycle { chain } => assert_eq!(chain, ["a", "b", "a"]),
            k => panic!("{k:?}"),
        }
        assert_eq!(
            r.resolve("c", &f).unwrap_err().kind,
            LayoutErrorKind::UnknownType {
                name: "nothing".into()
            }
        );
        assert!(matches!(
            r.resolve("big", &f).unwrap_err().kind,
            LayoutErrorKind::TooLarge { .. }
        ));
        assert!(matches!(
            r.resolve("wide", &f).unwrap_err().kind,
            LayoutErrorKind::TooLarge { .. }
        ));
        assert_eq!(r.resolve("ok", &f).unwrap().size(), 1);
    }

    #[test]
    fn depth_is_bounded() {
        let mut texts: Vec<String> = (0..40).map(|i| format!("t{i}:t{} x;", i + 1)).collect();
        texts.push("t40:uint8_t v;".into());
        let f: Vec<Format> = texts.iter().map(|t| Format::parse(t).unwrap()).collect();
        let err = Layout::resolve("t0", &f).unwrap_err();
        assert_eq!(err.kind, LayoutErrorKind::TooDeep { limit: 32 });
        assert_eq!(Layout::resolve("t20", &f).unwrap().size(), 1);
    }

    #[test]
    fn depth_is_bounded_through_the_cache_too() {
        // Laid out bottom-up, each format is one level over a cached one.
        let mut texts: Vec<String> = (0..100).map(|i| format!("t{i}:t{} x;", i + 1)).collect();
        texts.push("t100:uint8_t v;".into());
        let f: Vec<Format> = texts.iter().map(|t| Format::parse(t).unwrap()).collect();
        let mut r = Resolver::new(Limits::default());
        let mut deepest = 0;
        for i in (0..=100).rev() {
            if let Ok(l) = r.resolve(&format!("t{i}"), &f) {
                deepest = deepest.max(l.depth());
            }
        }
        assert_eq!(deepest, 32);
    }

    #[test]
    fn zero_size_fields_cannot_hide_an_exponential_tree() {
        let wide = |name: &str, ty: &str| {
            let fields: String = (0..7000).map(|i| format!("{ty} a{i};")).collect();
            format!("{name}:{fields}")
        };
        let texts = [
            "z:uint8_t[0] e;".to_owned(),
            wide("c", "z"),
            wide("b", "c"),
            "y:z[65535] a;".to_owned(),
            "x:y[65535] b;".to_owned(),
        ];
        let f: Vec<Format> = texts.iter().map(|t| Format::parse(t).unwrap()).collect();
        let mut r = Resolver::new(Limits::default());
        assert_eq!(r.resolve("c", &f).unwrap().size(), 0);
        for name in ["b", "x"] {
            assert!(matches!(
                r.resolve(name, &f).unwrap_err().kind,
                LayoutErrorKind::TooLarge {
                    what: "fields and elements",
                    ..
                }
            ));
        }
    }

    #[test]
    fn used_before_defined_and_duplicates_take_the_last() {
        let f = formats(&["outer:inner i;", "inner:uint8_t a;", "inner:uint16_t a;"]);
        assert_eq!(Layout::resolve("outer", &f).unwrap().size(), 2);
    }
}
