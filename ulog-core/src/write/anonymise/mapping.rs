//! The two mappers an anonymising [`Edit`](crate::Edit) runs: one over data payloads,
//! one over the messages that hold values besides data.

use std::collections::HashMap;
use std::sync::Arc;

use ulog_format::{parse_key_as_written, BasicType, Field, LeafKind, TypeName};

use super::detect::{command, named_pairs, Command, KeyRole, Pair, Survey};
use super::rotation::{read_raw, to_degrees, write, Rotation};
use super::text::Texts;
use crate::definitions::Subscription;

/// Where a topic's positions, GPS times and strings are.
#[derive(Debug, Clone, Default)]
struct Plan {
    pairs: Vec<Pair>,
    command: Option<Command>,
    /// `time_utc_usec` leaves.
    times: Vec<usize>,
    /// `char[N]` fields: offset and size.
    strings: Vec<(usize, usize)>,
}

impl Plan {
    fn of(sub: &Subscription, survey: &Survey) -> Plan {
        let mut plan = Plan::default();
        let Ok(layout) = sub.layout() else {
            return plan;
        };
        plan.pairs = named_pairs(sub.name(), layout)
            .into_iter()
            .map(|(p, _, _)| p)
            .collect();
        plan.command = command(sub.name(), layout);
        let leaf = |path: &str| {
            layout
                .columns()
                .find(|l| l.path == path && l.kind == LeafKind::Scalar)
                .map(|l| (l.offset, l.ty))
        };
        for found in survey.topics.get(sub.name()).into_iter().flatten() {
            if let (Some(lat), Some(lon)) = (leaf(&found.lat), leaf(&found.lon)) {
                let pair = Pair {
                    lat,
                    lon,
                    unit: found.unit,
                };
                if !plan.pairs.contains(&pair) {
                    plan.pairs.push(pair);
                }
            }
        }
        for l in layout.columns() {
            let last = l.path.rsplit('.').next().unwrap_or(&l.path);
            match l.kind {
                LeafKind::Scalar
                    if last == "time_utc_usec"
                        && matches!(l.ty, BasicType::UInt64 | BasicType::Int64) =>
                {
                    plan.times.push(l.offset)
                }
                LeafKind::String => plan.strings.push((l.offset, l.count)),
                _ => {}
            }
        }
        plan
    }
}

/// Moves the positions of data payloads, zeroes their GPS times, edits their strings.
pub(super) struct Payloads {
    survey: Arc<Survey>,
    rotation: Option<Rotation>,
    texts: Arc<Texts>,
    plans: HashMap<usize, Plan>,
    /// Rows of the `event` topic (as logged) whose message shows a date or a time,
    /// with the argument bytes that make it (zeroed).
    dated_events: HashMap<Vec<u8>, Vec<usize>>,
}

impl Payloads {
    pub(super) fn new(
        survey: Arc<Survey>,
        texts: Arc<Texts>,
        dated_events: HashMap<Vec<u8>, Vec<usize>>,
    ) -> Payloads {
        Payloads {
            rotation: texts.rotation,
            survey,
            texts,
            plans: HashMap::new(),
            dated_events,
        }
    }

    pub(super) fn map(&mut self, sub: &Subscription, payload: &mut [u8]) {
        let survey = &self.survey;
        let plan = self
            .plans
            .entry(sub.index())
            .or_insert_with(|| Plan::of(sub, survey));
        if !self.dated_events.is_empty() && sub.name() == "event" && sub.multi_id() == 0 {
            if let Some(bytes) = self.dated_events.get(&payload[..]) {
                for &j in bytes {
                    payload[j] = 0;
                }
            }
        }
        if let Some(rotation) = &self.rotation {
            let command = plan.command.filter(|c| c.read(payload).is_some());
            for pair in plan.pairs.iter().chain(command.as_ref().map(|c| &c.pair)) {
                let Some((lat, lon)) = pair.read(payload) else {
                    continue;
                };
                let (x, y) = rotation.apply(lat, lon);
                write(&mut payload[pair.lat.0..], pair.lat.1, pair.unit, x);
                write(&mut payload[pair.lon.0..], pair.lon.1, pair.unit, y);
            }
        }
        if self.texts.zero_utc {
            for &offset in &plan.times {
                if let Some(bytes) = payload.get_mut(offset..offset + 8) {
                    bytes.fill(0);
                }
            }
        }
        for &(offset, size) in &plan.strings {
            let Some(field) = payload.get_mut(offset..offset + size) else {
                continue;
            };
            let len = field.iter().position(|&b| b == 0).unwrap_or(size);
            if let Some(text) = self.texts.edit(&field[..len], true) {
                if text.len() == len {
                    field[..len].copy_from_slice(&text);
                }
            }
        }
    }
}

/// A parsed key-value message: where its key and value start in the payload.
struct KeyMessage {
    /// Bytes before the key length byte.
    head: usize,
    field: Field,
}

impl KeyMessage {
    fn parse(msg_type: u8, payload: &[u8]) -> Option<KeyMessage> {
        let head = match msg_type {
            b'I' | b'P' => 0,
            b'M' | b'Q' => 1,
            _ => return None,
        };
        let key_len = usize::from(*payload.get(head)?);
        let key = payload.get(head + 1..head + 1 + key_len)?;
        let field = parse_key_as_written(std::str::from_utf8(key).ok()?).ok()?;
        Some(KeyMessage { head, field })
    }

    fn value_start(&self, payload: &[u8]) -> usize {
        self.head + 1 + usize::from(payload[self.head])
    }

    /// The scalar number the message holds.
    fn number(&self, payload: &[u8]) -> Option<(BasicType, f64)> {
        match (&self.field.ty, self.field.array_len) {
            (TypeName::Basic(ty), None) => {
                Some((*ty, read_raw(&payload[self.value_start(payload)..], *ty)?))
            }
            _ => None,
        }
    }

    fn is_text(&self) -> bool {
        matches!(self.field.ty, TypeName::Basic(BasicType::Char))
    }

    /// The payload with the value `text` (a `char[N]` key rewritten for its length).
    fn with_text(&self, payload: &[u8], text: &[u8]) -> Option<Vec<u8>> {
        let key = format!("char[{}] {}", text.len(), self.field.name);
        let mut out = payload[..self.head].to_vec();
        out.push(u8::try_from(key.len()).ok()?);
        out.extend_from_slice(key.as_bytes());
        out.extend_from_slice(text);
        Some(out)
    }
}

/// Moves the positions of parameters, default parameters and information values, and
/// edits the text of information, multi-information and logged strings.
pub(super) struct Messages {
    survey: Arc<Survey>,
    texts: Arc<Texts>,
    /// Each parameter's value as last written (before moving), for its partner.
    current: HashMap<String, f64>,
    /// Default values: (default types, name) → value.
    defaults: HashMap<(u8, String), f64>,
    /// Numeric information values.
    info: HashMap<String, f64>,
    /// Each multi-information key's parts as edited, and how many were met.
    multi: HashMap<String, (Parts, usize)>,
}

/// The parts of a multi-information key's text, in order: each edited one's new
/// bytes (`None` where it stays).
type Parts = Vec<Option<Vec<u8>>>;

impl Messages {
    pub(super) fn new(log: &crate::ULog<'_>, survey: Arc<Survey>, texts: Arc<Texts>) -> Messages {
        let number = |kv: &crate::log::message::KeyValue<'_>| -> Option<f64> {
            match (&kv.field.as_ref()?.ty, kv.field.as_ref()?.array_len) {
                (TypeName::Basic(ty), None) => read_raw(kv.raw, *ty),
                _ => None,
            }
        };
        let mut current = HashMap::new();
        for kv in log.initial_params() {
            if let Some(v) = number(kv) {
                current.insert(kv.name().into_owned(), v);
            }
        }
        let mut defaults = HashMap::new();
        for d in log.default_params() {
            if let Some(v) = number(&d.kv) {
                defaults.insert((d.default_types, d.kv.name().into_owned()), v);
            }
        }
        let info = log
            .info()
            .iter()
            .filter_map(|kv| Some((kv.name().into_owned(), number(kv)?)))
            .collect();
        // Multi-information text is split over messages: edited whole, with every
        // replacement as long as what it replaces, then cut where the parts were.
        let mut multi = HashMap::new();
        for m in log.multi_info() {
            let mut parts = Vec::new();
            for entry in &m.entries {
                let texts_of: Vec<&[u8]> = entry
                    .iter()
                    .map(|kv| match &kv.field {
                        Some(Field {
                            ty: TypeName::Basic(BasicType::Char),
                            ..
                        }) => kv.raw,
                        _ => &[][..],
                    })
                    .collect();
                let joined = texts_of.concat();
                match texts.edit(&joined, true) {
                    Some(edited) if edited.len() == joined.len() => {
                        let mut at = 0;
                        for t in &texts_of {
                            parts.push(Some(edited[at..at + t.len()].to_vec()));
                            at += t.len();
                        }
                    }
                    _ => parts.extend(texts_of.iter().map(|_| None)),
                }
            }
            multi.insert(m.name.clone(), (parts, 0));
        }
        Messages {
            survey,
            texts,
            current,
            defaults,
            info,
            multi,
        }
    }

    pub(super) fn map(&mut self, msg_type: u8, payload: &mut Vec<u8>) {
        match msg_type {
            b'L' | b'C' => {
                let start = if msg_type == b'L' { 9 } else { 11 };
                if let Some(text) = payload.get(start..).and_then(|t| self.texts.edit(t, false)) {
                    payload.truncate(start);
                    payload.extend_from_slice(&text);
                }
            }
            b'I' | b'M' | b'P' | b'Q' => {
                if let Some(key) = KeyMessage::parse(msg_type, payload) {
                    if let Some(new) = self.key_value(msg_type, &key, payload) {
                        *payload = new;
                    }
                }
            }
            _ => {}
        }
    }

    /// The new payload of a key-value message, if it changes.
    fn key_value(&mut self, msg_type: u8, key: &KeyMessage, payload: &[u8]) -> Option<Vec<u8>> {
        let name = &key.field.name;
        let start = key.value_start(payload);
        let value = &payload[start..];
        match msg_type {
            b'M' => {
                // Every part of the key counts, text or not: the edits are by part.
                let (parts, met) = self.multi.get_mut(name)?;
                let part = parts.get(*met).cloned().flatten();
                *met += 1;
                let part = part.filter(|p| key.is_text() && p.len() == value.len())?;
                return Some([&payload[..start], &part[..]].concat());
            }
            b'I' if key.is_text() => {
                let len = value.iter().position(|&b| b == 0).unwrap_or(value.len());
                let text = self.texts.edit(&value[..len], false)?;
                return key.with_text(payload, &[&text[..], &value[len..]].concat());
            }
            _ => {}
        }
        let (ty, v) = key.number(payload)?;
        if msg_type == b'P' {
            self.current.insert(name.clone(), v);
        }
        let roles = if msg_type == b'I' {
            &self.survey.info
        } else {
            &self.survey.params
        };
        let KeyRole {
            partner,
            latitude,
            unit,
        } = roles.get(name)?;
        let other = match msg_type {
            b'I' => self.info.get(partner).copied(),
            b'Q' => self
                .defaults
                .get(&(payload[0], partner.clone()))
                .or_else(|| self.current.get(partner))
                .copied(),
            _ => self.current.get(partner).copied(),
        }?;
        let (lat, lon) = if *latitude {
            (to_degrees(v, *unit), to_degrees(other, *unit))
        } else {
            (to_degrees(other, *unit), to_degrees(v, *unit))
        };
        if !super::places::valid(lat, lon) {
            return None;
        }
        let (x, y) = self.texts.rotation?.apply(lat, lon);
        let mut out = payload.to_vec();
        write(&mut out[start..], ty, *unit, if *latitude { x } else { y });
        Some(out)
    }
}
