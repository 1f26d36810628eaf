//! The typed writer.
//!
//! [`LogWriter`] writes the definitions section: information, parameters, defaults and
//! formats (its subscriptions are queued); [`LogWriter::start_data`] turns it into a
//! [`DataWriter`] for the data section. Formats therefore cannot be written in the
//! data section, and a handle of one type cannot write a value of another: both are
//! compile errors. What only shows at run time (a payload of the wrong size for a raw
//! subscription, a format the definitions did not declare, a message over 65,535
//! bytes) is an error, and nothing malformed is written.

use std::collections::HashMap;
use std::io::Write;
use std::marker::PhantomData;
use std::sync::Arc;

use ulog_format::{Format, Layout, Limits, Resolver};
use zerocopy::IntoBytes;

use crate::bytes::SYNC_MAGIC;
use crate::framing::is_text_byte;
use crate::log::message::LogLevel;
use crate::typed::message::ULogMessage;
use crate::typed::{FieldKind, IsWritable, WireField};
use crate::write::error::{WriteError, WriteErrorKind};
use crate::write::raw::RawWriter;

type Result<T, E = WriteError> = core::result::Result<T, E>;

/// Options of a [`LogWriter`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WriterOptions {
    /// Write a sync message after every this many bytes of the data section, so that a
    /// reader can resynchronise after damage (`None`: only when [`DataWriter::sync`] is
    /// called). Default: 65,536.
    pub sync_interval: Option<u64>,
}

impl Default for WriterOptions {
    fn default() -> WriterOptions {
        WriterOptions {
            sync_interval: Some(65_536),
        }
    }
}

/// A subscription of binding `T`: [`DataWriter::write`] takes only `T` values with it.
#[derive(Debug)]
pub struct TopicHandle<T> {
    msg_id: u16,
    multi_id: u8,
    ty: PhantomData<fn(&T)>,
}

impl<T> Clone for TopicHandle<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for TopicHandle<T> {}

impl<T> TopicHandle<T> {
    /// The msg_id of the subscription.
    pub fn msg_id(&self) -> u16 {
        self.msg_id
    }

    /// The instance.
    pub fn multi_id(&self) -> u8 {
        self.multi_id
    }
}

/// An untyped subscription: payloads given as bytes, checked against its layout.
#[derive(Debug, Clone)]
pub struct RawTopicHandle {
    msg_id: u16,
    layout: Arc<Layout>,
}

impl RawTopicHandle {
    /// The msg_id of the subscription.
    pub fn msg_id(&self) -> u16 {
        self.msg_id
    }

    /// The layout payloads must fit (full size, or without trailing padding).
    pub fn layout(&self) -> &Arc<Layout> {
        &self.layout
    }
}

/// A value of an information or multi-information message: any basic type, arrays of
/// them, and strings (`char[N]`).
pub trait InfoValue {
    /// The key's type part (`uint32_t`, `float[3]`, `char[5]`).
    fn type_name(&self) -> Result<String>;
    /// The value bytes.
    fn bytes(&self) -> Vec<u8>;
}

impl<T: WireField> InfoValue for T {
    fn type_name(&self) -> Result<String> {
        match T::KIND {
            FieldKind::Basic(b) => Ok(match T::COUNT {
                Some(n) => format!("{}[{n}]", b.name()),
                None => b.name().to_owned(),
            }),
            FieldKind::Nested(s) => Err(WriteError::new(
                WriteErrorKind::InvalidInfoValue {
                    what: format!("binding `{}`", s().name()),
                },
                None,
            )),
        }
    }

    fn bytes(&self) -> Vec<u8> {
        self.to_wire().as_bytes().to_vec()
    }
}

impl<T: WireField> InfoValue for [T] {
    fn type_name(&self) -> Result<String> {
        match (T::KIND, T::COUNT) {
            (FieldKind::Basic(b), None) => Ok(format!("{}[{}]", b.name(), self.len())),
            _ => Err(WriteError::new(
                WriteErrorKind::InvalidInfoValue {
                    what: "an array of strings or bindings".to_owned(),
                },
                None,
            )),
        }
    }

    fn bytes(&self) -> Vec<u8> {
        self.iter()
            .flat_map(|v| v.to_wire().as_bytes().to_vec())
            .collect()
    }
}

impl<T: WireField, const N: usize> InfoValue for [T; N] {
    fn type_name(&self) -> Result<String> {
        self[..].type_name()
    }

    fn bytes(&self) -> Vec<u8> {
        self[..].bytes()
    }
}

impl InfoValue for str {
    fn type_name(&self) -> Result<String> {
        Ok(format!("char[{}]", self.len()))
    }

    fn bytes(&self) -> Vec<u8> {
        self.as_bytes().to_vec()
    }
}

/// A parameter value: ULog parameters are `int32_t` or `float`.
pub trait ParamValue: InfoValue + sealed::Sealed {}
impl ParamValue for i32 {}
impl ParamValue for f32 {}

mod sealed {
    pub trait Sealed {}
    impl Sealed for i32 {}
    impl Sealed for f32 {}
}

/// Which defaults a default parameter is (bits of `default_types`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DefaultTypes(pub u8);

impl DefaultTypes {
    /// The system-wide default (bit 0).
    pub const SYSTEM: DefaultTypes = DefaultTypes(1);
    /// The default of the current configuration, e.g. the airframe (bit 1).
    pub const CURRENT_SETUP: DefaultTypes = DefaultTypes(2);
    /// Both.
    pub const BOTH: DefaultTypes = DefaultTypes(3);
}

fn key_message(prefix: &[u8], name: &str, value: &(impl InfoValue + ?Sized)) -> Result<Vec<u8>> {
    let valid = !name.is_empty()
        && name
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'/'));
    if !valid {
        return Err(WriteError::new(
            WriteErrorKind::InvalidName(name.to_owned()),
            None,
        ));
    }
    let key = format!("{} {name}", value.type_name()?);
    let key_len = u8::try_from(key.len()).map_err(|_| {
        WriteError::new(
            WriteErrorKind::MessageTooLarge {
                msg_type: b'I',
                size: key.len(),
            },
            None,
        )
    })?;
    let mut p = prefix.to_vec();
    p.push(key_len);
    p.extend_from_slice(key.as_bytes());
    p.extend_from_slice(&value.bytes());
    Ok(p)
}

/// What both sections share: the output, formats and subscriptions.
struct Core<W: Write> {
    out: RawWriter<W>,
    formats: HashMap<String, Format>,
    resolver: Resolver,
    next_msg_id: u16,
    options: WriterOptions,
    last_sync: u64,
}

impl<W: Write> Core<W> {
    fn add_formats(&mut self, layout: &Layout, pending: &mut Vec<Vec<u8>>) -> Result<()> {
        for f in layout.formats() {
            match self.formats.get(&f.name) {
                Some(known) if known.fields == f.fields => {}
                Some(_) => {
                    return Err(WriteError::new(
                        WriteErrorKind::FormatConflict {
                            name: f.name.clone(),
                        },
                        Some(self.out.position()),
                    ))
                }
                None => {
                    pending.push(f.to_string().into_bytes());
                    self.formats.insert(f.name.clone(), f.clone());
                    self.resolver.clear();
                }
            }
        }
        Ok(())
    }

    fn new_msg_id(&mut self) -> Result<u16> {
        let id = self.next_msg_id;
        self.next_msg_id = id.checked_add(1).ok_or_else(|| {
            WriteError::new(WriteErrorKind::MsgIdsExhausted, Some(self.out.position()))
        })?;
        Ok(id)
    }

    fn layout_of(&mut self, name: &str) -> Result<Arc<Layout>> {
        let at = Some(self.out.position());
        if !self.formats.contains_key(name) {
            let name = name.to_owned();
            return Err(WriteError::new(
                WriteErrorKind::FormatNotDeclared { name },
                at,
            ));
        }
        self.resolver.resolve(name, &self.formats).map_err(|error| {
            let name = name.to_owned();
            WriteError::new(WriteErrorKind::NoLayout { name, error }, at)
        })
    }

    fn subscription(&mut self, multi_id: u8, msg_id: u16, name: &str) -> Result<()> {
        self.out
            .message(b'A', &[&[multi_id], &msg_id.to_le_bytes(), name.as_bytes()])
    }
}

/// Writes the header and the definitions section.
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use ulog_core::{LogWriter, ULogMessage};
///
/// #[derive(ULogMessage)]
/// #[ulog(crate = "ulog_core")]
/// struct Cpuload { timestamp: u64, load: f32, ram_usage: f32 }
///
/// let mut w = LogWriter::new(Vec::new(), 0).unwrap();
/// w.info("sys_name", "PX4").unwrap();
/// let cpu = w.subscribe::<Cpuload>(0).unwrap();
/// let mut data = w.start_data().unwrap();
/// data.write(&cpu, &Cpuload { timestamp: 1, load: 0.5, ram_usage: 0.25 }).unwrap();
/// let bytes = data.finish().unwrap();
///
/// let log = ulog_core::ULog::parse(&bytes).unwrap();
/// assert_eq!(log.read::<Cpuload>(0).unwrap().iter().next().unwrap().unwrap().load, 0.5);
/// # }
/// ```
pub struct LogWriter<W: Write> {
    core: Core<W>,
    start_timestamp: u64,
    definitions: Vec<(u8, Vec<u8>)>,
    queued: Vec<(u8, u16, String)>,
    has_defaults: bool,
}

impl<W: Write> LogWriter<W> {
    /// A version-1 log starting at `start_timestamp` (microseconds), with default
    /// options.
    pub fn new(out: W, start_timestamp: u64) -> Result<LogWriter<W>> {
        LogWriter::with_options(out, start_timestamp, WriterOptions::default())
    }

    /// A version-1 log with these options.
    pub fn with_options(
        out: W,
        start_timestamp: u64,
        options: WriterOptions,
    ) -> Result<LogWriter<W>> {
        Ok(LogWriter {
            core: Core {
                out: RawWriter::new(out),
                formats: HashMap::new(),
                resolver: Resolver::new(Limits::default()),
                next_msg_id: 0,
                options,
                last_sync: 0,
            },
            start_timestamp,
            definitions: Vec::new(),
            queued: Vec::new(),
            has_defaults: false,
        })
    }

    /// An information message: `value` is a number, bool, array of them, or `str`.
    pub fn info<V: InfoValue + ?Sized>(&mut self, name: &str, value: &V) -> Result<&mut Self> {
        self.definitions
            .push((b'I', key_message(&[], name, value)?));
        Ok(self)
    }

    /// A multi-information message; `continued` joins it to the previous one of `name`.
    pub fn multi_info<V: InfoValue + ?Sized>(
        &mut self,
        name: &str,
        value: &V,
        continued: bool,
    ) -> Result<&mut Self> {
        let m = key_message(&[u8::from(continued)], name, value)?;
        self.definitions.push((b'M', m));
        Ok(self)
    }

    /// A parameter's value when logging starts.
    pub fn param<V: ParamValue>(&mut self, name: &str, value: V) -> Result<&mut Self> {
        self.definitions
            .push((b'P', key_message(&[], name, &value)?));
        Ok(self)
    }

    /// A default parameter (sets the DEFAULT_PARAMETERS flag).
    pub fn default_param<V: ParamValue>(
        &mut self,
        name: &str,
        value: V,
        types: DefaultTypes,
    ) -> Result<&mut Self> {
        self.definitions
            .push((b'Q', key_message(&[types.0], name, &value)?));
        self.has_defaults = true;
        Ok(self)
    }

    /// A format given as text (for tools that copy or edit logs).
    pub fn format(&mut self, text: &str) -> Result<&mut Self> {
        let f = Format::parse(text)
            .map_err(|e| WriteError::new(WriteErrorKind::InvalidFormat(e), None))?;
        match self.core.formats.get(&f.name) {
            Some(k) if k.fields == f.fields => {}
            Some(_) => {
                return Err(WriteError::new(
                    WriteErrorKind::FormatConflict { name: f.name },
                    None,
                ))
            }
            None => {
                self.definitions.push((b'F', f.to_string().into_bytes()));
                self.core.formats.insert(f.name.clone(), f);
                self.core.resolver.clear();
            }
        }
        Ok(self)
    }

    /// Subscribes binding `T` (instance `multi_id`): writes its format and every nested
    /// format it needs (each once) and assigns a msg_id. The subscription message
    /// itself opens the data section.
    pub fn subscribe<T>(&mut self, multi_id: u8) -> Result<TopicHandle<T>>
    where
        T: ULogMessage,
        T::Writability: IsWritable,
    {
        let mut pending = Vec::new();
        self.core.add_formats(T::layout(), &mut pending)?;
        self.definitions
            .extend(pending.into_iter().map(|p| (b'F', p)));
        let msg_id = self.core.new_msg_id()?;
        self.queued.push((multi_id, msg_id, T::NAME.to_owned()));
        Ok(TopicHandle {
            msg_id,
            multi_id,
            ty: PhantomData,
        })
    }

    /// Subscribes a format given by name (declared with [`LogWriter::format`]).
    pub fn subscribe_raw(&mut self, name: &str, multi_id: u8) -> Result<RawTopicHandle> {
        let layout = self.core.layout_of(name)?;
        let msg_id = self.core.new_msg_id()?;
        self.queued.push((multi_id, msg_id, name.to_owned()));
        Ok(RawTopicHandle { msg_id, layout })
    }

    /// Writes the header and definitions, and opens the data section.
    pub fn start_data(mut self) -> Result<DataWriter<W>> {
        let out = &mut self.core.out;
        out.header(1, self.start_timestamp)?;
        let compat = [u8::from(self.has_defaults), 0, 0, 0, 0, 0, 0, 0];
        out.message(b'B', &[&compat, &[0; 8], &[0; 24]])?;
        for (t, p) in &self.definitions {
            out.message(*t, &[p])?;
        }
        let mut data = DataWriter {
            core: self.core,
            buf: Vec::with_capacity(1024),
        };
        for (multi_id, msg_id, name) in std::mem::take(&mut self.queued) {
            data.core.subscription(multi_id, msg_id, &name)?;
        }
        data.core.last_sync = data.core.out.position();
        Ok(data)
    }
}

/// Writes the data section (see [`LogWriter::start_data`]).
pub struct DataWriter<W: Write> {
    core: Core<W>,
    buf: Vec<u8>,
}

impl<W: Write> DataWriter<W> {
    pub(crate) fn continue_at(
        out: W,
        offset: u64,
        formats: HashMap<String, Format>,
        next_msg_id: u16,
        options: WriterOptions,
    ) -> DataWriter<W> {
        DataWriter {
            core: Core {
                out: RawWriter::at_offset(out, offset),
                formats,
                resolver: Resolver::new(Limits::default()),
                next_msg_id,
                options,
                last_sync: offset,
            },
            buf: Vec::with_capacity(1024),
        }
    }

    /// The file offset of the next message.
    pub fn position(&self) -> u64 {
        self.core.out.position()
    }

    /// Subscribes binding `T` in the data section. Its formats must have been
    /// written in the definitions section (formats cannot be written here).
    pub fn subscribe<T>(&mut self, multi_id: u8) -> Result<TopicHandle<T>>
    where
        T: ULogMessage,
        T::Writability: IsWritable,
    {
        for f in T::layout().formats() {
            if self.core.formats.get(&f.name).map(|k| &k.fields) != Some(&f.fields) {
                return Err(WriteError::new(
                    WriteErrorKind::FormatNotDeclared {
                        name: f.name.clone(),
                    },
                    Some(self.position()),
                ));
            }
        }
        let msg_id = self.core.new_msg_id()?;
        self.core.subscription(multi_id, msg_id, T::NAME)?;
        Ok(TopicHandle {
            msg_id,
            multi_id,
            ty: PhantomData,
        })
    }

    /// Subscribes a format given by name, in the data section.
    pub fn subscribe_raw(&mut self, name: &str, multi_id: u8) -> Result<RawTopicHandle> {
        let layout = self.core.layout_of(name)?;
        let msg_id = self.core.new_msg_id()?;
        self.core.subscription(multi_id, msg_id, name)?;
        Ok(RawTopicHandle { msg_id, layout })
    }

    pub(crate) fn existing<T: ULogMessage>(&mut self, msg_id: u16, multi_id: u8) -> TopicHandle<T> {
        TopicHandle {
            msg_id,
            multi_id,
            ty: PhantomData,
        }
    }

    /// Writes a value of the handle's type, its trailing padding left out as PX4 does.
    pub fn write<T: ULogMessage>(&mut self, handle: &TopicHandle<T>, value: &T) -> Result<()> {
        let id = handle.msg_id.to_le_bytes();
        let wire = value.to_wire();
        let bytes = wire.as_bytes();
        let len = T::encoded_len().min(bytes.len());
        self.core.out.message(b'D', &[&id, &bytes[..len]])?;
        self.after_data()
    }

    /// Writes a payload given as bytes: its length must be the format's full size or
    /// the size without trailing padding.
    pub fn write_raw(&mut self, handle: &RawTopicHandle, payload: &[u8]) -> Result<()> {
        let l = &handle.layout;
        if !l.accepts_len(payload.len()) {
            return Err(WriteError::new(
                WriteErrorKind::PayloadSize {
                    topic: l.name().to_owned(),
                    expected: (l.size(), l.min_size()),
                    found: payload.len(),
                },
                Some(self.position()),
            ));
        }
        self.core
            .out
            .message(b'D', &[&handle.msg_id.to_le_bytes(), payload])?;
        self.after_data()
    }

    fn after_data(&mut self) -> Result<()> {
        if let Some(every) = self.core.options.sync_interval {
            if self.position() - self.core.last_sync >= every {
                self.sync()?;
            }
        }
        Ok(())
    }

    /// Ends a subscription.
    pub fn unsubscribe(&mut self, msg_id: u16) -> Result<()> {
        self.core.out.message(b'R', &[&msg_id.to_le_bytes()])
    }

    /// A logged string (`L`).
    ///
    /// An error, and nothing written, for text holding a control character other than
    /// tab, line feed, carriage return and escape ([`WriteErrorKind::ControlCharacter`]):
    /// readers may take such a message for corruption (this one does when the byte is
    /// among the text's first 128), so it is refused wherever it is.
    pub fn log(&mut self, level: LogLevel, timestamp: u64, text: &str) -> Result<()> {
        self.check_text(text)?;
        let l = [b'0' + level as u8];
        self.core
            .out
            .message(b'L', &[&l, &timestamp.to_le_bytes(), text.as_bytes()])
    }

    /// A tagged logged string (`C`); text as for [`DataWriter::log`].
    pub fn tagged_log(
        &mut self,
        level: LogLevel,
        tag: u16,
        timestamp: u64,
        text: &str,
    ) -> Result<()> {
        self.check_text(text)?;
        let l = [b'0' + level as u8];
        self.core.out.message(
            b'C',
            &[
                &l,
                &tag.to_le_bytes(),
                &timestamp.to_le_bytes(),
                text.as_bytes(),
            ],
        )
    }

    /// Refuses text that readers would take for corruption (see [`DataWriter::log`]).
    fn check_text(&self, text: &str) -> Result<()> {
        match text.bytes().enumerate().find(|&(_, b)| !is_text_byte(b)) {
            None => Ok(()),
            Some((at, byte)) => Err(WriteError::new(
                WriteErrorKind::ControlCharacter { at, byte },
                Some(self.position()),
            )),
        }
    }

    /// A parameter change.
    pub fn param<V: ParamValue>(&mut self, name: &str, value: V) -> Result<()> {
        self.buf = key_message(&[], name, &value)?;
        self.core.out.message(b'P', &[&self.buf])
    }

    /// A default parameter in the data section.
    pub fn default_param<V: ParamValue>(
        &mut self,
        name: &str,
        value: V,
        types: DefaultTypes,
    ) -> Result<()> {
        self.buf = key_message(&[types.0], name, &value)?;
        self.core.out.message(b'Q', &[&self.buf])
    }

    /// Information in the data section.
    pub fn info<V: InfoValue + ?Sized>(&mut self, name: &str, value: &V) -> Result<()> {
        self.buf = key_message(&[], name, value)?;
        self.core.out.message(b'I', &[&self.buf])
    }

    /// Multi-information in the data section.
    pub fn multi_info<V: InfoValue + ?Sized>(
        &mut self,
        name: &str,
        value: &V,
        continued: bool,
    ) -> Result<()> {
        self.buf = key_message(&[u8::from(continued)], name, value)?;
        self.core.out.message(b'M', &[&self.buf])
    }

    /// A dropout of `duration_ms`.
    pub fn dropout(&mut self, duration_ms: u16) -> Result<()> {
        self.core.out.message(b'O', &[&duration_ms.to_le_bytes()])
    }

    /// A sync message.
    pub fn sync(&mut self) -> Result<()> {
        self.core.out.message(b'S', &[&SYNC_MAGIC])?;
        self.core.last_sync = self.position();
        Ok(())
    }

    /// Makes every message written so far reach the file.
    pub fn flush(&mut self) -> Result<()> {
        self.core.out.flush()
    }

    /// Flushes and gives the output back.
    pub fn finish(self) -> Result<W> {
        self.core.out.into_inner()
    }
}
