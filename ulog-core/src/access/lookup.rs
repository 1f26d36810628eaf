//! [`LookupError`]: a topic or field asked for by name that the log does not have,
//! or a topic that cannot be decoded at all.

use core::fmt;

use ulog_format::LayoutError;

use crate::definitions::Subscription;
use crate::log::ulog::ULog;

/// A topic name (and instance) that is not in the log: what the log has instead.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TopicNotFound {
    /// The name asked for.
    pub name: String,
    /// The instance asked for (`None`: any).
    pub multi_id: Option<u8>,
    /// The instances the log has of `name`, in increasing order (empty: no topic of
    /// that name at all).
    pub instances: Vec<u8>,
    /// The log's topic names closest to `name`, closest first (when the name is not in
    /// the log and some are close).
    pub closest: Vec<String>,
    /// The other names looked for, none of which the log has either (a binding's
    /// [aliases](crate::ULogMessage::ALIASES)).
    pub aliases: Vec<String>,
}

impl TopicNotFound {
    /// What the log has instead of topic `name` (instance `multi_id`).
    pub(crate) fn in_log(log: &ULog<'_>, name: &str, multi_id: Option<u8>) -> TopicNotFound {
        TopicNotFound::in_subscriptions(log.subscriptions(), name, multi_id)
    }

    /// What `topics` (a log's subscriptions, or those a pass has met) have instead of
    /// topic `name` (instance `multi_id`).
    pub(crate) fn in_subscriptions(
        topics: &[std::sync::Arc<Subscription>],
        name: &str,
        multi_id: Option<u8>,
    ) -> TopicNotFound {
        let mut instances: Vec<u8> = topics
            .iter()
            .filter(|t| t.name() == name)
            .map(|t| t.multi_id())
            .collect();
        instances.sort_unstable();
        instances.dedup();
        let closest = if instances.is_empty() {
            crate::suggest::closest_n(name, topics.iter().map(|t| t.name()), 3)
        } else {
            Vec::new()
        };
        TopicNotFound {
            name: name.to_owned(),
            multi_id,
            instances,
            closest,
            aliases: Vec::new(),
        }
    }
}

impl TopicNotFound {
    /// A name that none of a log's `names` is: the closest of them.
    pub(crate) fn among<'n>(name: &str, names: impl Iterator<Item = &'n str>) -> TopicNotFound {
        TopicNotFound {
            name: name.to_owned(),
            multi_id: None,
            instances: Vec::new(),
            closest: crate::suggest::closest_n(name, names, 3),
            aliases: Vec::new(),
        }
    }
}

impl fmt::Display for TopicNotFound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.instances.is_empty() {
            let have: Vec<String> = self.instances.iter().map(u8::to_string).collect();
            let id = self.multi_id.map_or(String::new(), |m| format!(" {m}"));
            return write!(
                f,
                "topic `{}` has no instance{id} (its instances: {})",
                self.name,
                have.join(", ")
            );
        }
        write!(f, "no topic `{}`", self.name)?;
        for alias in &self.aliases {
            write!(f, " or `{alias}`")?;
        }
        write!(f, " in the log")?;
        match self.closest.as_slice() {
            [] => Ok(()),
            [one] => write!(f, " (did you mean `{one}`?)"),
            many => {
                let names: Vec<String> = many.iter().map(|n| format!("`{n}`")).collect();
                write!(f, " (closest: {})", names.join(", "))
            }
        }
    }
}

/// The fields of a topic a field error lists at most (a message stays one line).
const FIELDS_LISTED: usize = 12;

/// A topic or field that is not in the log, or a topic whose format cannot be laid
/// out. Matchable; new kinds may be added.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum LookupError {
    /// No topic of that name (or no instance of that number).
    Topic(TopicNotFound),
    /// The topic has no field at that path (padding and nested formats are not
    /// fields to read: their leaves are).
    Field {
        /// The topic.
        topic: String,
        /// The path asked for.
        path: String,
        /// The closest field path of the topic, if any is close.
        closest: Option<String>,
        /// When none is close: the topic's own fields (padding left out, arrays as
        /// `q[4]`, nested types by their field's name), for the message to list.
        fields: Vec<String>,
    },
    /// The topic's format could not be laid out (an unknown nested type, a cycle, a
    /// limit), so its data cannot be decoded.
    Layout {
        /// The topic.
        topic: String,
        /// Its instance.
        multi_id: u8,
        /// Byte offset of its subscription.
        position: u64,
        /// Why.
        error: LayoutError,
    },
}

impl LookupError {
    /// The error of a topic without a layout.
    pub(crate) fn layout(topic: &Subscription, error: &LayoutError) -> LookupError {
        LookupError::Layout {
            topic: topic.name().to_owned(),
            multi_id: topic.multi_id(),
            position: topic.offset(),
            error: error.clone(),
        }
    }

    /// The byte offset it is about, where there is one.
    pub fn position(&self) -> Option<u64> {
        match self {
            LookupError::Layout { position, .. } => Some(*position),
            LookupError::Topic(_) | LookupError::Field { .. } => None,
        }
    }
}

impl fmt::Display for LookupError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LookupError::Topic(t) => write!(f, "{t}"),
            LookupError::Field {
                topic,
                path,
                closest,
                fields,
            } => {
                write!(f, "topic `{topic}` has no field `{path}`")?;
                match (closest, fields.as_slice()) {
                    (Some(c), _) => write!(f, " (did you mean `{c}`?)"),
                    (None, []) => Ok(()),
                    (None, all) => {
                        let shown: Vec<String> = all
                            .iter()
                            .take(FIELDS_LISTED)
                            .map(|n| format!("`{n}`"))
                            .collect();
                        write!(f, " (its fields: {}", shown.join(", "))?;
                        match all.len().checked_sub(FIELDS_LISTED) {
                            Some(more) if more > 0 => write!(f, " and {more} more)"),
                            _ => write!(f, ")"),
                        }
                    }
                }
            }
            LookupError::Layout {
                topic,
                multi_id,
                position,
                error,
            } => write!(
                f,
                "topic `{topic}` instance {multi_id} (subscribed at byte {position}) cannot be decoded: {error}"
            ),
        }
    }
}

impl std::error::Error for LookupError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            LookupError::Layout { error, .. } => Some(error),
            _ => None,
        }
    }
}
