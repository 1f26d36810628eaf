//! Definitions and subscriptions: the schema a log declares as it goes (formats, then
//! subscriptions with their layouts), kept by framing, which needs it to judge data
//! messages, and handed on to every reader without a copy.

mod subscription;
pub(crate) mod timestamp;

use std::collections::HashMap;
use std::sync::Arc;

use ulog_format::{Format, Layout, LayoutError, Limits, Resolver};

use crate::bytes::u16_at;
use crate::finding::FindingKind;

pub use subscription::Subscription;

/// No subscription (in [`IdEntry::sub`]).
pub(crate) const NO_SUB: u32 = u32::MAX;
/// Payload size (after the msg_id) standing for "any": a subscription whose format
/// has no layout cannot have its data messages' sizes checked.
const ANY_SIZE: u32 = u32::MAX;

/// A msg_id's current subscription ([`NO_SUB`] when there is none) and the payload
/// sizes (after the msg_id) its data messages may have: the full layout size, or the
/// size without trailing padding.
#[derive(Clone, Copy)]
pub(crate) struct IdEntry {
    pub sub: u32,
    full: u32,
    min: u32,
}

impl IdEntry {
    const NONE: IdEntry = IdEntry {
        sub: NO_SUB,
        full: ANY_SIZE,
        min: ANY_SIZE,
    };

    /// Whether a data message of this msg_id may have `n` payload bytes after the
    /// msg_id.
    #[inline]
    pub fn accepts(&self, n: usize) -> bool {
        self.full == ANY_SIZE || n == self.full as usize || n == self.min as usize
    }

    /// The sizes it accepts: full, and without trailing padding.
    pub fn sizes(&self) -> (usize, usize) {
        (self.full as usize, self.min as usize)
    }
}

/// The formats and subscriptions declared so far.
///
/// Cloning is cheap: everything is shared until one of the copies changes it, so that
/// framing can be copied at every message (to see what a reader would make of the
/// file cut there).
#[derive(Clone)]
pub(crate) struct Definitions {
    formats: Arc<HashMap<String, Format>>,
    resolver: Arc<Resolver>,
    subs: Arc<Vec<Arc<Subscription>>>,
    /// What a data message of each msg_id belongs to, with the sizes it may have.
    by_id: Arc<Vec<IdEntry>>,
    /// Subscriptions by (name, multi_id), so that a repeated `A` finds its own in
    /// constant time.
    by_key: Arc<HashMap<(String, u8), Vec<u32>>>,
}

impl Definitions {
    pub fn new() -> Definitions {
        Definitions {
            formats: Arc::default(),
            resolver: Arc::new(Resolver::new(Limits::default())),
            subs: Arc::default(),
            by_id: Arc::new(vec![IdEntry::NONE; 1 << 16]),
            by_key: Arc::default(),
        }
    }

    /// The entry of `msg_id`.
    #[inline(always)]
    pub fn entry(&self, msg_id: u16) -> IdEntry {
        self.by_id[msg_id as usize]
    }

    /// The table of entries by msg_id (for framing's plain-data loop).
    #[inline(always)]
    pub fn entries(&self) -> &[IdEntry] {
        &self.by_id
    }

    /// The subscription a data message of `msg_id` belongs to now.
    pub fn sub_index(&self, msg_id: u16) -> Option<u32> {
        let i = self.by_id[msg_id as usize].sub;
        (i != NO_SUB).then_some(i)
    }

    /// Every subscription, in the order of their first `A` messages.
    #[inline(always)]
    pub fn subscriptions(&self) -> &[Arc<Subscription>] {
        &self.subs
    }

    /// Takes the subscriptions (shared with copies of this table, if any are left).
    pub fn take_subscriptions(&mut self) -> Vec<Arc<Subscription>> {
        let subs = std::mem::take(&mut self.subs);
        Arc::try_unwrap(subs).unwrap_or_else(|shared| (*shared).clone())
    }

    /// Takes the formats.
    pub fn take_formats(&mut self) -> HashMap<String, Format> {
        let formats = std::mem::take(&mut self.formats);
        Arc::try_unwrap(formats).unwrap_or_else(|shared| (*shared).clone())
    }

    /// Every format's name.
    pub fn format_names(&self) -> impl Iterator<Item = &str> {
        self.formats.keys().map(String::as_str)
    }

    /// The names of the formats a topic `name` is laid out with: its own and the
    /// nested ones (its own only when it cannot be laid out); none when no format has
    /// that name.
    pub fn formats_of(&self, name: &str) -> Vec<String> {
        if !self.formats.contains_key(name) {
            return Vec::new();
        }
        match Resolver::new(Limits::default()).resolve(name, &*self.formats) {
            Ok(layout) => layout.formats().iter().map(|f| f.name.clone()).collect(),
            Err(_) => vec![name.to_owned()],
        }
    }

    /// The layout of format `name` as the formats stand now; `None` when no format
    /// has that name.
    pub fn layout_of(&self, name: &str) -> Option<Result<Arc<Layout>, LayoutError>> {
        if !self.formats.contains_key(name) {
            return None;
        }
        Some(Resolver::new(Limits::default()).resolve(name, &*self.formats))
    }

    /// A format (`F`) message's payload; what is wrong with it, if anything.
    pub fn format(&mut self, payload: &[u8]) -> Option<FindingKind> {
        let format = match Format::parse_bytes(payload) {
            Ok(f) => f,
            Err(e) => return Some(FindingKind::InvalidFormat(e)),
        };
        let mut finding = None;
        if let Some(old) = self.formats.get(&format.name) {
            if old.fields == format.fields {
                return None;
            }
            finding = Some(FindingKind::RedefinedFormat(format.name.clone()));
        }
        Arc::make_mut(&mut self.formats).insert(format.name.clone(), format);
        // A new format may complete one that could not be laid out before, and a
        // redefined one changes the layouts that use it.
        Arc::make_mut(&mut self.resolver).clear();
        finding
    }

    /// A subscription (`A`) message's payload (framing has checked that it holds a
    /// multi_id, a msg_id and a name); what is wrong with it, if anything.
    pub fn subscribe(&mut self, offset: u64, payload: &[u8]) -> Option<FindingKind> {
        let multi_id = payload[0];
        let msg_id = u16_at(payload, 1);
        let name = String::from_utf8_lossy(&payload[3..]).into_owned();
        let layout: Result<Arc<Layout>, LayoutError> =
            Arc::make_mut(&mut self.resolver).resolve(&name, &*self.formats);
        let key = (name, multi_id);
        let existing = self.by_key.get(&key).and_then(|ids| {
            ids.iter()
                .copied()
                .find(|&i| self.subs[i as usize].same_topic(&layout))
        });
        let mut finding = None;
        let index = match existing {
            Some(i) => i,
            None => {
                let (name, multi_id) = key.clone();
                finding = match &layout {
                    Err(_) if !self.formats.contains_key(&name) => {
                        Some(FindingKind::UnknownFormat(name.clone()))
                    }
                    Err(e) => Some(FindingKind::Layout(e.clone())),
                    Ok(_) => None,
                };
                let index = self.subs.len();
                let sub = Subscription::new(index, msg_id, multi_id, name, offset, layout);
                if finding.is_none() && sub.timestamp_field().is_none() {
                    finding = Some(FindingKind::NoTimestamp(sub.name().to_owned()));
                }
                Arc::make_mut(&mut self.subs).push(Arc::new(sub));
                let i = index as u32;
                Arc::make_mut(&mut self.by_key)
                    .entry(key)
                    .or_default()
                    .push(i);
                i
            }
        };
        if self.by_id[msg_id as usize].sub != index {
            let (full, min) = match self.subs[index as usize].layout() {
                Ok(l) => (l.size() as u32, l.min_size() as u32),
                Err(_) => (ANY_SIZE, ANY_SIZE),
            };
            Arc::make_mut(&mut self.by_id)[msg_id as usize] = IdEntry {
                sub: index,
                full,
                min,
            };
        }
        finding
    }

    /// An unsubscription (`R`): data messages of `msg_id` belong to nothing now.
    pub fn unsubscribe(&mut self, msg_id: u16) {
        if self.by_id[msg_id as usize].sub != NO_SUB {
            Arc::make_mut(&mut self.by_id)[msg_id as usize] = IdEntry::NONE;
        }
    }
}
