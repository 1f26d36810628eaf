//! `Schema`: the ULog format of a binding, built once from its field list.

use std::sync::Arc;

use ulog_format::{BasicType, Field, Format, Layout, LayoutType, TypeName};

/// The ULog type of one value of a field: a basic type, or a nested message.
#[derive(Debug, Clone, Copy)]
pub enum FieldKind {
    /// One of the twelve basic types.
    Basic(BasicType),
    /// A nested message, by its schema.
    Nested(fn() -> &'static Schema),
}

/// What a binding takes when the log's format lacks a field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Absent {
    /// Nothing: the format does not fit (a [`Mismatch`](super::Mismatch)).
    Required,
    /// `None` (an `Option<T>` field).
    None,
    /// Its default (`#[ulog(default)]` or `#[ulog(default = …)]`).
    Default,
}

/// One field of a binding, as the derive describes it.
#[derive(Debug, Clone, Copy)]
pub struct FieldDef {
    name: &'static str,
    aliases: &'static [&'static str],
    kind: FieldKind,
    array_len: Option<usize>,
    absent: Absent,
    converts: &'static [BasicType],
}

impl FieldDef {
    /// A field named `name` in the format (also found under `aliases` when reading),
    /// of ULog type `kind`, an array of `array_len` elements if `Some`; required.
    pub const fn new(
        name: &'static str,
        aliases: &'static [&'static str],
        kind: FieldKind,
        array_len: Option<usize>,
    ) -> FieldDef {
        FieldDef {
            name,
            aliases,
            kind,
            array_len,
            absent: Absent::Required,
            converts: &[],
        }
    }

    /// The same field, read also from logs that hold it in one of `types`, through
    /// a conversion the binding declares (`#[ulog(convert(TYPE = function))]`).
    pub const fn converting(mut self, types: &'static [BasicType]) -> FieldDef {
        self.converts = types;
        self
    }

    /// The other basic types the binding reads the field from, by a conversion it
    /// declares (beyond the types that [widen](BasicType::widens_to) to its own).
    pub fn converts(&self) -> &'static [BasicType] {
        self.converts
    }

    /// The same field, taking `absent` when a log lacks it.
    pub const fn when_absent(mut self, absent: Absent) -> FieldDef {
        self.absent = absent;
        self
    }

    /// The field's ULog name.
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// Other names the field is found under in a log (older firmware).
    pub fn aliases(&self) -> &'static [&'static str] {
        self.aliases
    }

    /// The ULog type of one element.
    pub fn kind(&self) -> FieldKind {
        self.kind
    }

    /// The array length, for arrays.
    pub fn array_len(&self) -> Option<usize> {
        self.array_len
    }

    /// What the binding takes when a log lacks the field.
    pub fn absent(&self) -> Absent {
        self.absent
    }

    /// The presence slots the field takes: its own when optional, then its nested
    /// binding's.
    pub(crate) fn slots(&self) -> usize {
        let own = usize::from(self.absent != Absent::Required);
        match self.kind {
            FieldKind::Nested(schema) => own + schema().optional_slots(),
            FieldKind::Basic(_) => own,
        }
    }
}

/// The ULog side of a binding: its format, the nested formats it uses, and its
/// layout. Built once per type (the derive keeps it in a `static`).
#[derive(Debug)]
pub struct Schema {
    fields: &'static [FieldDef],
    format: Format,
    formats: Vec<Format>,
    layout: Arc<Layout>,
    rust_name: &'static str,
    named_after_struct: bool,
    optional_slots: usize,
    /// The basic fields of the wire image, in the order of a plan's payload offsets.
    image_leaves: Vec<ImageLeaf>,
}

impl Schema {
    /// Builds the schema of message `name` with `fields`, in order.
    ///
    /// # Panics
    ///
    /// When the names are not valid ULog names, or two nested types share a message
    /// name with different formats. The derive checks names at compile time, so this
    /// only happens with hand-written `FieldDef`s or conflicting nested bindings.
    ///
    /// ```
    /// use ulog_core::typed::{FieldDef, FieldKind, Schema};
    /// use ulog_core::format::BasicType;
    ///
    /// static FIELDS: [FieldDef; 2] = [
    ///     FieldDef::new("timestamp", &[], FieldKind::Basic(BasicType::UInt64), None),
    ///     FieldDef::new("q", &[], FieldKind::Basic(BasicType::Float), Some(4)),
    /// ];
    /// let schema = Schema::build("vehicle_attitude", &FIELDS);
    /// assert_eq!(schema.format_text(), "vehicle_attitude:uint64_t timestamp;float[4] q;");
    /// assert_eq!(schema.layout().size(), 24);
    /// ```
    pub fn build(name: &'static str, fields: &'static [FieldDef]) -> Schema {
        let mut formats: Vec<Format> = Vec::new();
        let mut own = Vec::with_capacity(fields.len());
        for def in fields {
            let ty = match def.kind {
                FieldKind::Basic(b) => TypeName::Basic(b),
                FieldKind::Nested(schema) => {
                    let nested = schema();
                    for f in &nested.formats {
                        match formats.iter().find(|g| g.name == f.name) {
                            Some(g) if g != f => panic!(
                                "two nested types are named `{}` with different formats: `{g}` and `{f}`",
                                f.name
                            ),
                            Some(_) => {}
                            None => formats.push(f.clone()),
                        }
                    }
                    TypeName::Nested(nested.name().to_owned())
                }
            };
            own.push(Field {
                ty,
                array_len: def.array_len,
                name: def.name.to_owned(),
                span: Default::default(),
            });
        }
        let text = Format {
            name: name.to_owned(),
            fields: own,
        }
        .to_string();
        // Parsing the text back checks the names and gives the fields their spans.
        let format = match Format::parse(&text) {
            Ok(f) => f,
            Err(e) => panic!("invalid ULog binding `{text}`: {e}"),
        };
        if formats.iter().any(|f| f.name == format.name) {
            panic!("message `{name}` contains a nested type of the same name");
        }
        formats.push(format.clone());
        let layout = match Layout::resolve(name, &formats) {
            Ok(l) => Arc::new(l),
            Err(e) => panic!("invalid ULog binding `{text}`: {e}"),
        };
        Schema {
            fields,
            image_leaves: image_leaves(fields, &layout, 0),
            format,
            formats,
            layout,
            rust_name: name,
            named_after_struct: false,
            optional_slots: fields.iter().map(FieldDef::slots).sum(),
        }
    }

    /// The same schema, of the Rust type `rust_name`, whose ULog name was derived
    /// from that name (`named_after_struct`) or given.
    pub fn with_rust_name(mut self, rust_name: &'static str, named_after_struct: bool) -> Schema {
        self.rust_name = rust_name;
        self.named_after_struct = named_after_struct;
        self
    }

    /// The basic fields of the wire image, in the order of a plan's payload offsets.
    pub(crate) fn image_leaves(&self) -> &[ImageLeaf] {
        &self.image_leaves
    }

    /// The message name.
    pub fn name(&self) -> &str {
        &self.format.name
    }

    /// The binding's Rust type name (the message name for schemas built by hand).
    pub fn rust_name(&self) -> &'static str {
        self.rust_name
    }

    /// Whether the message name was derived from the Rust type's name rather than
    /// given (`#[ulog(name = …)]`).
    pub fn named_after_struct(&self) -> bool {
        self.named_after_struct
    }

    /// The fields as the binding declares them, in order.
    pub fn fields(&self) -> &'static [FieldDef] {
        self.fields
    }

    /// How many optional fields the binding has, its nested bindings' included.
    pub fn optional_slots(&self) -> usize {
        self.optional_slots
    }

    /// The message's own format.
    pub fn format(&self) -> &Format {
        &self.format
    }

    /// Every format the message needs, nested ones first, its own last: the `F`
    /// messages a writer emits.
    pub fn formats(&self) -> &[Format] {
        &self.formats
    }

    /// The laid-out format.
    pub fn layout(&self) -> &Arc<Layout> {
        &self.layout
    }

    /// The message's own format string, as in a ULog `F` message.
    pub fn format_text(&self) -> String {
        self.format.to_string()
    }

    /// Every format string, nested first, one per line.
    pub fn formats_text(&self) -> String {
        let lines: Vec<String> = self.formats.iter().map(|f| f.to_string()).collect();
        lines.join("\n")
    }
}

/// One basic field of a binding's wire image, in the order of a plan's payload
/// offsets (nested bindings' per element, padding left out).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ImageLeaf {
    /// Its offset in the image.
    pub at: usize,
    /// Its basic type.
    pub ty: BasicType,
    /// Its array length (`None` for one value).
    pub len: Option<usize>,
}

/// The [`ImageLeaf`]s of a layout whose fields are `defs`, from `base` of the image.
pub(crate) fn image_leaves(defs: &[FieldDef], layout: &Layout, base: usize) -> Vec<ImageLeaf> {
    let mut out = Vec::new();
    for (def, own) in defs.iter().zip(layout.fields()) {
        if own.is_padding() {
            continue;
        }
        match (def.kind(), &own.ty) {
            (FieldKind::Nested(nested), LayoutType::Nested(inner)) => {
                let schema = nested();
                for i in 0..own.array_len.unwrap_or(1) {
                    let at = base + own.offset + i * inner.size();
                    out.extend(image_leaves(schema.fields(), schema.layout(), at));
                }
            }
            (_, LayoutType::Basic(ty)) => out.push(ImageLeaf {
                at: base + own.offset,
                ty: *ty,
                len: own.array_len,
            }),
            // A schema's defs and layout come from one format.
            _ => {}
        }
    }
    out
}
