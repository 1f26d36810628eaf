//! `ULogMessage`: a Rust type bound to a ULog message format.

use ulog_format::{Layout, LeafKind};
use zerocopy::{FromZeros, IntoBytes};

use super::schema::Schema;
use super::wire::{IsWritable, Present, WireField};
use crate::audited::WireImage;
use crate::value::{LogText, Value};

/// A Rust struct bound to a ULog message: its name, its format and the nested
/// formats it needs, and the conversion from and to payload bytes.
///
/// Derive it (`#[derive(ULogMessage)]`, feature `derive`) rather than implementing it
/// by hand. Read logs through [`ULog::read`](crate::ULog::read) or a
/// [`Plan`](super::Plan), which check a log's format against the type once and then
/// decode each payload.
pub trait ULogMessage: WireField {
    /// The ULog message name (`vehicle_attitude`).
    const NAME: &'static str;

    /// The topic's names in other firmware, tried in order after [`NAME`](Self::NAME)
    /// wherever a binding finds its topic by name (`ULog::read`, `read_instances`,
    /// `scan_topics`, the topic enums): `#[ulog(alias = "vehicle_gps_position")]`
    /// on a binding named `sensor_gps`. A log that has topics under two of the names
    /// is read under the first of them it has.
    const ALIASES: &'static [&'static str] = &[];

    /// [`NAME`](Self::NAME), then [`ALIASES`](Self::ALIASES).
    fn names() -> impl Iterator<Item = &'static str> {
        core::iter::once(Self::NAME).chain(Self::ALIASES.iter().copied())
    }

    /// The format, nested formats and layout of the binding, built on first use.
    fn schema() -> &'static Schema;

    /// The binding's layout.
    fn layout() -> &'static Layout {
        Self::schema().layout()
    }

    /// A value with every byte zero (numbers 0, `false`, empty strings, optional
    /// fields `Some(0)`).
    fn zeroed() -> Self {
        Self::from_wire(&<Self::Wire as FromZeros>::new_zeroed(), Present::ALL)
    }

    /// The length of an encoded payload: the full size without trailing padding,
    /// which PX4 does not write.
    fn encoded_len() -> usize {
        Self::layout().min_size()
    }

    /// Appends the payload bytes of `self` (without trailing padding) to `out`.
    ///
    /// A binding with `Option` fields cannot be encoded (`None` has no bytes): its
    /// `Writability` is `HasOptionFields`, not `Writable` (see [`IsWritable`]).
    fn encode_into(&self, out: &mut Vec<u8>)
    where
        <Self as WireField>::Writability: IsWritable,
    {
        let wire = self.to_wire();
        let bytes = wire.as_bytes();
        out.extend_from_slice(&bytes[..Self::encoded_len().min(bytes.len())]);
    }

    /// The payload bytes of `self`, without trailing padding (as
    /// [`encode_into`](ULogMessage::encode_into)).
    fn encode(&self) -> Vec<u8>
    where
        <Self as WireField>::Writability: IsWritable,
    {
        let mut out = Vec::with_capacity(Self::encoded_len());
        self.encode_into(&mut out);
        out
    }

    /// Calls `f` with the path and value of every leaf field, padding left out, in
    /// the binding's order: the fields the reader's
    /// [`Topic::fields`](crate::Topic::fields) names (`timestamp`, `q[0]`,
    /// `esc[3].esc_rpm`; a `char[N]` is one [`Value::Str`] of all `N` bytes). An
    /// `Option` field that is `None` is left out.
    ///
    /// ```
    /// # #[cfg(feature = "derive")] {
    /// use ulog_core::ULogMessage;
    ///
    /// #[derive(ULogMessage)]
    /// #[ulog(crate = "ulog_core")]
    /// struct Sensor { timestamp: u64, xyz: [f32; 2], _padding0: [u8; 3], ok: bool }
    ///
    /// let s = Sensor { timestamp: 5, xyz: [1.5, -2.0], _padding0: [0; 3], ok: true };
    /// let mut columns = Vec::new();
    /// s.visit_fields(&mut |path, value| columns.push(format!("{path}={value}")));
    /// assert_eq!(columns, ["timestamp=5", "xyz[0]=1.5", "xyz[1]=-2.0", "ok=true"]);
    /// # }
    /// ```
    fn visit_fields(&self, f: &mut dyn FnMut(&str, Value<'_>)) {
        let mut path = String::new();
        self.visit_fields_at(&mut path, f);
    }

    /// [`visit_fields`](ULogMessage::visit_fields) with every path after `path` and a
    /// dot (generated code overrides it: for bindings whose values may lack fields, and
    /// for bindings of known formats, which walk their wire image in one function).
    #[doc(hidden)]
    fn visit_fields_at(&self, path: &mut String, f: &mut dyn FnMut(&str, Value<'_>)) {
        // The wire image read as the reader reads a payload: the same leaves, paths
        // and values by construction.
        let wire = self.to_wire();
        visit_image(Self::layout(), wire.as_bytes(), path, f);
    }
}

/// Calls `f` with the path (after `path` and a dot) and value of every value leaf of
/// `layout` in `image`, an image of the layout.
pub(crate) fn visit_image(
    layout: &Layout,
    image: &[u8],
    path: &mut String,
    f: &mut dyn FnMut(&str, Value<'_>),
) {
    let base = path.len();
    for leaf in layout.columns() {
        if base > 0 {
            path.push('.');
        }
        path.push_str(&leaf.path);
        let bytes = &image[leaf.offset..];
        let value = match leaf.kind {
            LeafKind::String => Value::Str(LogText(&bytes[..leaf.count])),
            _ => Value::read_scalar(leaf.ty, bytes),
        };
        f(path, value);
        path.truncate(base);
    }
}

/// Something done with each binding of a generated module, by type: the module that
/// `ulog_module!` emits has a `visit_bindings` function that calls
/// [`visit`](BindingVisitor::visit) once per struct, so that code can go over a
/// log's whole schema without naming each type.
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use ulog_core::typed::BindingVisitor;
/// use ulog_core::ULogMessage;
///
/// #[derive(ULogMessage)]
/// #[ulog(crate = "ulog_core")]
/// struct Cpuload { timestamp: u64, load: f32 }
///
/// struct Sizes(Vec<(&'static str, usize)>);
/// impl BindingVisitor for Sizes {
///     fn visit<T: ULogMessage>(&mut self) {
///         self.0.push((T::NAME, T::layout().size()));
///     }
/// }
/// let mut sizes = Sizes(Vec::new());
/// sizes.visit::<Cpuload>();
/// assert_eq!(sizes.0, [("cpuload", 12)]);
/// # }
/// ```
pub trait BindingVisitor {
    /// Called once per binding type `T`.
    fn visit<T: ULogMessage>(&mut self);
}

/// [`BindingVisitor`] for the bindings of a module generated with views
/// (`ulog_module!(views; …)`, `ulog codegen --views`): its `visit_views` function
/// calls [`visit`](ViewVisitor::visit) once per struct, each one payloads can be
/// borrowed as ([`TypedRows::views`](crate::TypedRows::views)).
pub trait ViewVisitor {
    /// Called once per binding type `T`.
    fn visit<T: ULogMessage + WireImage>(&mut self);
}
