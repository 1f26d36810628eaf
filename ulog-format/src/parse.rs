//! The grammar of format strings: `name:type[N] field;type field;…`.
//!
//! Message and type names use `a-z A-Z 0-9 _ - /`; field names `a-z A-Z 0-9 _`.
//! A type is a basic type ([`BasicType`]) or the name of another format, which may be
//! defined later in the log. Errors carry the byte span of the offending text so that
//! the derive macros can point at the exact column.

use core::fmt;

use crate::basic::BasicType;
use crate::error::{FormatError, FormatErrorKind};
use crate::span::Span;

/// The type of a field: basic, or the name of another (nested) format.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum TypeName {
    /// One of the twelve basic types.
    Basic(BasicType),
    /// The name of another format.
    Nested(String),
}

impl TypeName {
    /// The type as written in a format string.
    pub fn as_str(&self) -> &str {
        match self {
            TypeName::Basic(b) => b.name(),
            TypeName::Nested(n) => n,
        }
    }
}

impl fmt::Display for TypeName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One field of a format: `type name` or `type[len] name`. Fields compare (and hash)
/// by type, array length and name; where they stood in their text does not count.
#[derive(Debug, Clone)]
pub struct Field {
    /// The field's type.
    pub ty: TypeName,
    /// The array length, for `type[len] name`.
    pub array_len: Option<usize>,
    /// The field name.
    pub name: String,
    /// Where the field stands in the text it was parsed from.
    pub span: Span,
}

impl PartialEq for Field {
    fn eq(&self, other: &Field) -> bool {
        self.ty == other.ty && self.array_len == other.array_len && self.name == other.name
    }
}

impl Eq for Field {}

impl std::hash::Hash for Field {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.ty.hash(state);
        self.array_len.hash(state);
        self.name.hash(state);
    }
}

impl Field {
    /// Whether this is a padding field (`_padding…`), never shown as a value.
    pub fn is_padding(&self) -> bool {
        crate::is_padding_name(&self.name)
    }
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.array_len {
            Some(n) => write!(f, "{}[{}] {}", self.ty, n, self.name),
            None => write!(f, "{} {}", self.ty, self.name),
        }
    }
}

/// A parsed format definition: a message name and its fields, in order.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Format {
    /// The message name.
    pub name: String,
    /// The fields, in the order they are laid out.
    pub fields: Vec<Field>,
}

const MAX_ARRAY_LEN: usize = 65535;

fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '/'
}

fn is_field_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

impl Format {
    /// Parses a format string, returning its first error.
    ///
    /// ```
    /// use ulog_format::{Format, TypeName, BasicType};
    /// let f = Format::parse("vehicle_attitude:uint64_t timestamp;float[4] q;").unwrap();
    /// assert_eq!(f.name, "vehicle_attitude");
    /// assert_eq!(f.fields[1].ty, TypeName::Basic(BasicType::Float));
    /// assert_eq!(f.fields[1].array_len, Some(4));
    /// let err = Format::parse("bad:uint64_t timestamp;float[x] q;").unwrap_err();
    /// assert_eq!(err.span.start, 28);
    /// ```
    pub fn parse(text: &str) -> Result<Format, FormatError> {
        Format::parse_all(text).map_err(|mut errors| errors.swap_remove(0))
    }

    /// Parses a format given as bytes (as stored in a log).
    pub fn parse_bytes(bytes: &[u8]) -> Result<Format, FormatError> {
        match core::str::from_utf8(bytes) {
            Ok(text) => Format::parse(text),
            Err(e) => Err(FormatError {
                kind: FormatErrorKind::NotUtf8,
                span: Span::new(e.valid_up_to(), e.valid_up_to() + 1),
            }),
        }
    }

    /// Parses a format string, returning every error found (never an empty list).
    pub fn parse_all(text: &str) -> Result<Format, Vec<FormatError>> {
        let mut errors = Vec::new();
        let Some(colon) = text.find(':') else {
            return Err(vec![FormatError {
                kind: FormatErrorKind::MissingColon,
                span: Span::new(0, text.len()),
            }]);
        };
        let name = &text[..colon];
        check_type_name(name, 0, &mut errors);
        if BasicType::from_name(name).is_some() {
            errors.push(FormatError {
                kind: FormatErrorKind::NameIsBasicType,
                span: Span::new(0, colon),
            });
        }
        let mut fields: Vec<Field> = Vec::new();
        let mut pos = colon + 1;
        for part in text[colon + 1..].split(';') {
            let start = pos;
            pos += part.len() + 1;
            if part.is_empty() {
                continue;
            }
            match parse_field_at(part, start, is_field_name_char) {
                Ok(field) => {
                    if fields.iter().any(|f| f.name == field.name) {
                        errors.push(FormatError {
                            kind: FormatErrorKind::DuplicateField(field.name.clone()),
                            span: field.span,
                        });
                    }
                    fields.push(field);
                }
                Err(mut e) => errors.append(&mut e),
            }
        }
        if fields.is_empty() && errors.is_empty() {
            errors.push(FormatError {
                kind: FormatErrorKind::NoFields,
                span: Span::new(colon, text.len()),
            });
        }
        if errors.is_empty() {
            Ok(Format {
                name: name.to_owned(),
                fields,
            })
        } else {
            Err(errors)
        }
    }

    /// The field with this name.
    pub fn field(&self, name: &str) -> Option<&Field> {
        self.fields.iter().find(|f| f.name == name)
    }

    /// The names of the nested formats this format uses directly.
    pub fn nested_types(&self) -> impl Iterator<Item = &str> {
        self.fields.iter().filter_map(|f| match &f.ty {
            TypeName::Nested(n) => Some(n.as_str()),
            TypeName::Basic(_) => None,
        })
    }
}

impl fmt::Display for Format {
    /// The canonical format string, as a ULog `F` message holds it.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:", self.name)?;
        for field in &self.fields {
            write!(f, "{field};")?;
        }
        Ok(())
    }
}

/// Parses one field (`type name` or `type[len] name`), as in the key of an
/// information or parameter message.
///
/// ```
/// let f = ulog_format::parse_field("char[5] sys_name").unwrap();
/// assert_eq!((f.name.as_str(), f.array_len), ("sys_name", Some(5)));
/// ```
pub fn parse_field(text: &str) -> Result<Field, FormatError> {
    parse_field_at(text, 0, is_field_name_char).map_err(|mut e| e.swap_remove(0))
}

/// Parses the key of an information, multi-information or parameter message: a field
/// whose name may also hold `-` and `/` (`char[76] perf_counter_preflight-00`).
///
/// ```
/// let f = ulog_format::parse_key("char[0] perf_top-23").unwrap();
/// assert_eq!((f.name.as_str(), f.array_len), ("perf_top-23", Some(0)));
/// assert!(ulog_format::parse_field("char[0] perf_top-23").is_err());
/// ```
pub fn parse_key(text: &str) -> Result<Field, FormatError> {
    parse_field_at(text, 0, is_name_char).map_err(|mut e| e.swap_remove(0))
}

/// Parses a key as real logs write it: [`parse_key`]'s grammar, except that the name
/// may hold any character but a control character, spaces included (PX4 writes
/// `char[11] Build Date`). The type still follows the grammar, so the value can be
/// read by it.
///
/// ```
/// let f = ulog_format::parse_key_as_written("char[11] Build Date").unwrap();
/// assert_eq!((f.name.as_str(), f.array_len), ("Build Date", Some(11)));
/// assert!(ulog_format::parse_key("char[11] Build Date").is_err());
/// assert!(ulog_format::parse_key_as_written("char[11] Build\nDate").is_err());
/// ```
pub fn parse_key_as_written(text: &str) -> Result<Field, FormatError> {
    parse_field_at(text, 0, |c| !c.is_control()).map_err(|mut e| e.swap_remove(0))
}

fn check_type_name(name: &str, offset: usize, errors: &mut Vec<FormatError>) {
    if name.is_empty() {
        errors.push(FormatError {
            kind: FormatErrorKind::EmptyName,
            span: Span::new(offset, offset),
        });
    }
    if let Some((i, c)) = name.char_indices().find(|&(_, c)| !is_name_char(c)) {
        errors.push(FormatError {
            kind: FormatErrorKind::InvalidNameChar(c),
            span: Span::new(offset + i, offset + i + c.len_utf8()),
        });
    }
}

fn parse_field_at(
    part: &str,
    offset: usize,
    name_char: fn(char) -> bool,
) -> Result<Field, Vec<FormatError>> {
    let mut errors = Vec::new();
    let err = |kind, start: usize, end: usize| FormatError {
        kind,
        span: Span::new(offset + start, offset + end),
    };
    let trimmed_start = part.len() - part.trim_start().len();
    let body = part.trim();
    let body_start = trimmed_start;
    let Some(space) = body.find(' ') else {
        return Err(vec![err(
            if body.is_empty() {
                FormatErrorKind::EmptyType
            } else {
                FormatErrorKind::MissingFieldName
            },
            body_start,
            body_start + body.len(),
        )]);
    };
    let type_text = &body[..space];
    let name = body[space..].trim_start();
    let name_start = body_start + body.len() - name.len();

    let (type_name, array_len) = match type_text.find('[') {
        Some(open) => {
            let inner = &type_text[open + 1..];
            let len = inner
                .strip_suffix(']')
                .and_then(|digits| {
                    if digits.bytes().all(|b| b.is_ascii_digit()) {
                        digits.parse::<usize>().ok()
                    } else {
                        None
                    }
                })
                .filter(|&n| n <= MAX_ARRAY_LEN);
            if len.is_none() {
                errors.push(err(
                    FormatErrorKind::BadArrayLength,
                    body_start + open,
                    body_start + type_text.len(),
                ));
            }
            (&type_text[..open], len)
        }
        None => (type_text, None),
    };
    if type_name.is_empty() {
        errors.push(err(
            FormatErrorKind::EmptyType,
            body_start,
            body_start + type_text.len(),
        ));
    }
    let ty = match BasicType::from_name(type_name) {
        Some(b) => TypeName::Basic(b),
        None => {
            check_type_name(type_name, offset + body_start, &mut errors);
            TypeName::Nested(type_name.to_owned())
        }
    };
    if let Some((i, c)) = name.char_indices().find(|&(_, c)| !name_char(c)) {
        errors.push(err(
            FormatErrorKind::InvalidFieldNameChar(c),
            name_start + i,
            name_start + i + c.len_utf8(),
        ));
    }
    if errors.is_empty() {
        Ok(Field {
            ty,
            array_len,
            name: name.to_owned(),
            span: Span::new(offset + body_start, offset + body_start + body.len()),
        })
    } else {
        Err(errors)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_nested_arrays_and_padding() {
        let f = Format::parse(
            "esc_status:uint64_t timestamp;uint8_t esc_count;uint8_t[7] _padding0;esc_report[8] esc;",
        )
        .unwrap();
        assert_eq!(f.fields.len(), 4);
        assert!(f.fields[2].is_padding());
        assert_eq!(f.fields[3].ty, TypeName::Nested("esc_report".into()));
        assert_eq!(f.fields[3].array_len, Some(8));
        assert_eq!(f.nested_types().collect::<Vec<_>>(), ["esc_report"]);
    }

    #[test]
    fn display_gives_back_the_canonical_text() {
        let text = "a/b-c:uint64_t timestamp;char[10] name;x[2] xs;";
        assert_eq!(Format::parse(text).unwrap().to_string(), text);
    }

    #[test]
    fn equality_ignores_where_fields_stood() {
        assert_eq!(
            Format::parse("m:uint8_t a;").unwrap(),
            Format::parse("m:uint8_t  a;").unwrap()
        );
    }

    #[test]
    fn last_semicolon_is_optional() {
        let f = Format::parse("m:uint8_t a;int16_t b").unwrap();
        assert_eq!(f.fields[1].name, "b");
    }

    #[test]
    fn reports_every_error_with_its_column() {
        let text = "m:uint8_t a;float[-] b;int8_t a;c$ d;uint8_t e!";
        let errors = Format::parse_all(text).unwrap_err();
        let kinds: Vec<_> = errors
            .iter()
            .map(|e| (e.kind.clone(), e.span.start))
            .collect();
        assert_eq!(
            kinds,
            vec![
                (FormatErrorKind::BadArrayLength, 17),
                (FormatErrorKind::DuplicateField("a".into()), 23),
                (FormatErrorKind::InvalidNameChar('$'), 33),
                (FormatErrorKind::InvalidFieldNameChar('!'), 46),
            ]
        );
    }

    #[test]
    fn structural_errors() {
        let kind = |t: &str| Format::parse(t).unwrap_err().kind;
        assert_eq!(kind("no colon here"), FormatErrorKind::MissingColon);
        assert_eq!(kind(":uint8_t a;"), FormatErrorKind::EmptyName);
        assert_eq!(kind("float:uint8_t a;"), FormatErrorKind::NameIsBasicType);
        assert_eq!(kind("m:"), FormatErrorKind::NoFields);
        assert_eq!(kind("m:;;"), FormatErrorKind::NoFields);
        assert_eq!(kind("m:uint8_t;"), FormatErrorKind::MissingFieldName);
        assert_eq!(kind("m:uint8_t[70000] a;"), FormatErrorKind::BadArrayLength);
        // Zero-length arrays occur in real logs (`char[0]` information values).
        assert_eq!(parse_field("char[0] empty").unwrap().array_len, Some(0));
        assert_eq!(kind("m:uint8_t[3 a;"), FormatErrorKind::BadArrayLength);
        assert_eq!(kind("m:[3] a;"), FormatErrorKind::EmptyType);
        assert_eq!(
            Format::parse_bytes(b"m:uint8_t \xff;").unwrap_err().kind,
            FormatErrorKind::NotUtf8
        );
    }

    #[test]
    fn info_keys_parse_as_fields() {
        let f = parse_field("uint32_t ver_sw_release").unwrap();
        assert_eq!(f.ty, TypeName::Basic(BasicType::UInt32));
        assert!(parse_field("nospace").is_err());
    }
}
