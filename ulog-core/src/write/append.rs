//! Appending data to an existing log (crash dumps), as the spec describes: set the
//! DATA_APPENDED incompatibility bit, set the first free appended offset to the
//! current length of the file, then append data-section messages.

use std::collections::HashMap;
use std::io::{Read, Seek, SeekFrom, Write};
use std::sync::Arc;

use crate::access::lookup::TopicNotFound;
use crate::bytes::{HEADER_SIZE, MESSAGE_HEADER_SIZE};
use crate::definitions::Subscription;
use crate::log::message::Message;
use crate::log::ulog::ULog;
use crate::typed::message::ULogMessage;
use crate::typed::IsWritable;
use crate::write::error::{WriteError, WriteErrorKind};
use crate::write::writer::{DataWriter, TopicHandle, WriterOptions};

/// A data-section writer positioned at the end of an existing log, after
/// [`append`](crate::append) marked the log as having data appended there.
pub struct Appender<F: Write> {
    data: DataWriter<F>,
    subscriptions: Vec<Arc<Subscription>>,
}

impl<F: Write> Appender<F> {
    /// The subscriptions the log had.
    pub fn subscriptions(&self) -> &[Arc<Subscription>] {
        &self.subscriptions
    }

    /// The writer of the appended data section: values of the handles, logged
    /// strings, parameter changes, dropouts.
    pub fn writer(&mut self) -> &mut DataWriter<F> {
        &mut self.data
    }

    /// Subscribes binding `T` (instance `multi_id`) anew in the appended section,
    /// under a msg_id of its own. The log must declare `T`'s formats, exactly
    /// (formats cannot be written in the data section).
    ///
    /// Every reader reads what follows: this reader as a continuation of the log's
    /// own subscription of the topic instance when it has one with the same format
    /// (one topic instance); pyulog 1.3 as a second data set of the same name and
    /// instance. Prefer it to [`Appender::continue_topic`].
    pub fn subscribe<T>(&mut self, multi_id: u8) -> Result<TopicHandle<T>, WriteError>
    where
        T: ULogMessage,
        T::Writability: IsWritable,
    {
        self.data.subscribe::<T>(multi_id)
    }

    /// A handle writing `T` values under the msg_id of the log's existing
    /// subscription of `T::NAME` instance `multi_id`, whose format must be exactly
    /// `T`'s. No subscription message is written.
    ///
    /// The spec lets appended data continue subscriptions made before it, and this
    /// reader reads them; but pyulog 1.3 forgets every subscription at an appended
    /// offset, so it drops these messages and reports the log corrupt. Use
    /// [`Appender::subscribe`] for logs that pyulog (and tools built on it, such as
    /// Flight Review) must read.
    pub fn continue_topic<T>(&mut self, multi_id: u8) -> Result<TopicHandle<T>, WriteError>
    where
        T: ULogMessage,
        T::Writability: IsWritable,
    {
        let at = Some(self.data.position());
        let sub = self
            .subscriptions
            .iter()
            .find(|s| s.name() == T::NAME && s.multi_id() == multi_id)
            .ok_or_else(|| {
                let mut instances: Vec<u8> = self
                    .subscriptions
                    .iter()
                    .filter(|s| s.name() == T::NAME)
                    .map(|s| s.multi_id())
                    .collect();
                instances.sort_unstable();
                instances.dedup();
                let missing = TopicNotFound {
                    name: T::NAME.to_owned(),
                    multi_id: Some(multi_id),
                    instances,
                    closest: Vec::new(),
                    aliases: Vec::new(),
                };
                WriteError::new(WriteErrorKind::TopicNotFound(missing), at)
            })?;
        match sub.layout() {
            Ok(l) if **l == *T::layout() => Ok(self.data.existing(sub.msg_id(), multi_id)),
            Ok(l) => Err(WriteError::new(
                WriteErrorKind::LayoutDiffers {
                    topic: T::NAME.to_owned(),
                    binding: T::layout().format().to_string(),
                    log: l.format().to_string(),
                },
                at,
            )),
            Err(error) => Err(WriteError::new(
                WriteErrorKind::NoLayout {
                    name: T::NAME.to_owned(),
                    error: error.clone(),
                },
                at,
            )),
        }
    }

    /// Flushes and gives the file back.
    pub fn finish(self) -> Result<F, WriteError> {
        self.data.finish()
    }
}

/// Opens `file` (a complete or cut-off log) for appending: patches its flag bits and
/// returns a writer at its end. The log must have a flag bits message with a free
/// appended offset.
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use std::io::Cursor;
/// use ulog_core::write::WriterOptions;
///
/// #[derive(ulog_core::ULogMessage)]
/// #[ulog(crate = "ulog_core")]
/// struct BatteryStatus {
///     timestamp: u64,
///     voltage_v: f32,
///     remaining: f32,
///     cell_count: u8,
///     _padding0: [u8; 7],
/// }
///
/// let mut file = Cursor::new(ulog_core::testing::sample_log());
/// let mut appender = ulog_core::append(&mut file, WriterOptions::default()).unwrap();
/// let battery = appender.subscribe::<BatteryStatus>(0).unwrap();
/// let crash = BatteryStatus {
///     timestamp: 20_000_000, voltage_v: 9.9, remaining: 0.01, cell_count: 4, _padding0: [0; 7],
/// };
/// appender.writer().write(&battery, &crash).unwrap();
/// appender.finish().unwrap();
///
/// let bytes = file.into_inner();
/// let log = ulog_core::ULog::parse(&bytes).unwrap();
/// let last = log.read::<BatteryStatus>(0).unwrap().iter().last().unwrap().unwrap();
/// assert_eq!(last.voltage_v, 9.9);
/// # }
/// ```
pub fn append<F: Read + Write + Seek>(
    mut file: F,
    options: WriterOptions,
) -> Result<Appender<F>, WriteError> {
    let io = |e: std::io::Error| WriteError::io(e, None);
    file.seek(SeekFrom::Start(0)).map_err(io)?;
    let mut bytes = Vec::new();
    file.read_to_end(&mut bytes).map_err(io)?;
    let len = bytes.len() as u64;
    let log = ULog::parse(&bytes).map_err(WriteError::unreadable)?;
    let flags_at = (HEADER_SIZE + MESSAGE_HEADER_SIZE) as u64;
    let fb = log
        .flag_bits()
        .copied()
        .ok_or_else(|| WriteError::new(WriteErrorKind::NoFlagBits, Some(flags_at)))?;
    let slot = fb
        .appended_offsets
        .iter()
        .position(|&o| o == 0)
        .ok_or_else(|| {
            WriteError::new(WriteErrorKind::NoFreeAppendedOffset, Some(flags_at + 16))
        })?;
    let formats: HashMap<_, _> = log
        .formats()
        .into_iter()
        .map(|f| (f.name.clone(), f.clone()))
        .collect();
    let subscriptions = log.subscriptions().to_vec();
    // Every msg_id an `A` message used, also those whose subscription continued
    // another: the new ones come after all of them.
    let mut max_id = None;
    for m in log.messages().flatten() {
        if let Message::Subscribe { msg_id, .. } = m.message {
            max_id = max_id.max(Some(msg_id));
        }
    }
    let next_msg_id = max_id.map_or(0, |m: u16| m.saturating_add(1));
    drop(log);

    file.seek(SeekFrom::Start(flags_at + 8)).map_err(io)?;
    file.write_all(&[fb.incompat_flags[0] | 1]).map_err(io)?;
    file.seek(SeekFrom::Start(flags_at + 16 + 8 * slot as u64))
        .map_err(io)?;
    file.write_all(&len.to_le_bytes()).map_err(io)?;
    file.seek(SeekFrom::Start(len)).map_err(io)?;
    Ok(Appender {
        data: DataWriter::continue_at(file, len, formats, next_msg_id, options),
        subscriptions,
    })
}
