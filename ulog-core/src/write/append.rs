//! Appending data to an existing log (crash dumps), as the spec describes: set the
//! DATA_APPENDED incompatibility bit, set the first free appended offset to the
//! current length of the file, then append data-section messages.

use std::collections::HashMap;
use std::io::{Read, Seek, SeekFrom, Write};
use std::sync::Arc;

use ulog_format::Layout;

use crate::error::{Error, ErrorKind, Result};
use crate::read::framing::{HEADER_LEN, MSG_HEADER_LEN};
use crate::read::log::ULog;
use crate::typed::ULogMessage;
use crate::write::writer::{DataWriter, Handle, WriterOptions};

/// A subscription of the log being appended to.
#[derive(Debug, Clone)]
pub struct ExistingSubscription {
    /// Topic name.
    pub name: String,
    /// Instance.
    pub multi_id: u8,
    /// Its msg_id.
    pub msg_id: u16,
    /// Its layout, when the format resolves.
    pub layout: Option<Arc<Layout>>,
}

/// A data-section writer positioned at the end of an existing log.
pub struct Appender<F: Write> {
    /// The writer (data-section messages only).
    pub data: DataWriter<F>,
    subscriptions: Vec<ExistingSubscription>,
}

impl<F: Write> Appender<F> {
    /// The subscriptions the log had.
    pub fn subscriptions(&self) -> &[ExistingSubscription] {
        &self.subscriptions
    }

    /// A handle to write `T` values to the log's existing subscription of `T::NAME`
    /// instance `multi_id`, whose format must be exactly `T`'s.
    pub fn handle<T: ULogMessage>(&mut self, multi_id: u8) -> Result<Handle<T>> {
        let at = self.data.position();
        let sub = self
            .subscriptions
            .iter()
            .find(|s| s.name == T::NAME && s.multi_id == multi_id)
            .ok_or_else(|| {
                Error::new(
                    ErrorKind::TopicNotFound {
                        name: T::NAME.to_owned(),
                        suggestion: None,
                    },
                    at,
                )
            })?;
        match &sub.layout {
            Some(l) if **l == *T::layout() => {
                let id = sub.msg_id;
                Ok(self.data.existing(id, multi_id))
            }
            Some(l) => Err(Error::new(
                ErrorKind::LayoutDiffers {
                    topic: T::NAME.to_owned(),
                    binding: T::layout().format().to_string(),
                    log: l.format().to_string(),
                },
                at,
            )),
            None => Err(Error::new(
                ErrorKind::FormatUndefined(T::NAME.to_owned()),
                at,
            )),
        }
    }
}

/// Opens `file` (a complete or cut-off log) for appending: patches its flag bits and
/// returns a writer at its end. The log must have a flag bits message with a free
/// appended offset.
pub fn append<F: Read + Write + Seek>(mut file: F, options: WriterOptions) -> Result<Appender<F>> {
    let io = |e: std::io::Error| Error::new(ErrorKind::Io(e.to_string()), 0);
    file.seek(SeekFrom::Start(0)).map_err(io)?;
    let mut bytes = Vec::new();
    file.read_to_end(&mut bytes).map_err(io)?;
    let len = bytes.len() as u64;
    let log = ULog::parse(&bytes)?;
    let flags_at = (HEADER_LEN + MSG_HEADER_LEN) as u64;
    let fb = log
        .flag_bits()
        .copied()
        .ok_or_else(|| Error::new(ErrorKind::NoFlagBits, flags_at))?;
    let slot = fb
        .appended_offsets
        .iter()
        .position(|&o| o == 0)
        .ok_or_else(|| Error::new(ErrorKind::NoFreeAppendedOffset, flags_at + 16))?;
    let mut formats = HashMap::new();
    for f in log.formats() {
        formats.insert(f.name.clone(), f.clone());
    }
    let subscriptions: Vec<ExistingSubscription> = log
        .subscriptions()
        .iter()
        .enumerate()
        .map(|(i, _)| {
            let t = log.topic_at(i);
            ExistingSubscription {
                name: t.name().to_owned(),
                multi_id: t.multi_id(),
                msg_id: t.msg_id(),
                layout: t.layout().ok().cloned(),
            }
        })
        .collect();
    let mut max_id = None;
    for m in log.messages().flatten() {
        if let crate::Message::Subscribe { msg_id, .. } = m.message {
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
