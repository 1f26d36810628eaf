//! What to put on a time base, by name: a [`Selection`] (`topic[:N][.field]`, as `ulog
//! align` and `ulog_rs.ULog.align` take it) and the columns it names
//! ([`ULog::select_columns`]), named and ordered as `ulog csv` names and orders them.

use ulog_format::Layout;

use super::{AlignError, Grid, Method, Track};
use crate::access::field::FieldReader;
use crate::access::lookup::LookupError;
use crate::access::topic::{field_in, Topic};
use crate::log::ulog::ULog;

/// A topic instance and, optionally, one field of it: `topic`, `topic:N`,
/// `topic.field`, `topic:N.field[2].x`.
///
/// ```
/// use ulog_core::align::Selection;
/// let s: Selection = "esc_status:1.esc[2].esc_rpm".parse()?;
/// assert_eq!((s.topic.as_str(), s.instance, s.field.as_deref()),
///            ("esc_status", Some(1), Some("esc[2].esc_rpm")));
/// assert!("x:300".parse::<Selection>().is_err());
/// # Ok::<(), ulog_core::align::SelectionError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Selection {
    /// The topic's name.
    pub topic: String,
    /// Its instance; `None`: the lowest the log has.
    pub instance: Option<u8>,
    /// A field path (a value, an array, a nested type); `None`: every field.
    pub field: Option<String>,
}

/// A selection that does not parse: the text and what is wrong with it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SelectionError {
    /// The text as given.
    pub text: String,
    /// What is wrong.
    pub what: &'static str,
}

impl core::fmt::Display for SelectionError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "`{}`: {}", self.text, self.what)
    }
}

impl std::error::Error for SelectionError {}

impl core::str::FromStr for Selection {
    type Err = SelectionError;

    fn from_str(s: &str) -> Result<Selection, SelectionError> {
        let s = s.trim();
        let err = |what| SelectionError {
            text: s.to_owned(),
            what,
        };
        let (topic, field) = match s.split_once('.') {
            Some((t, f)) if !f.is_empty() => (t, Some(f.to_owned())),
            Some(_) => return Err(err("names no field after the `.`")),
            None => (s, None),
        };
        let (topic, instance) = match topic.split_once(':') {
            Some((t, n)) => {
                let n = n
                    .parse::<u8>()
                    .map_err(|_| err("the instance after `:` must be a number from 0 to 255"))?;
                (t, Some(n))
            }
            None => (topic, None),
        };
        if topic.is_empty() {
            return Err(err("names no topic"));
        }
        Ok(Selection {
            topic: topic.to_owned(),
            instance,
            field,
        })
    }
}

impl Selection {
    /// The topic instance of `log` it names (without an instance, the lowest the log
    /// has).
    pub fn topic<'l, 'a>(&self, log: &'l ULog<'a>) -> Result<Topic<'l, 'a>, LookupError> {
        match self.instance {
            Some(n) => log.topic(&self.topic, n),
            None => match log
                .topic_instances(&self.topic)
                .into_iter()
                .min_by_key(|t| t.multi_id())
            {
                Some(t) => Ok(t),
                None => log.topic(&self.topic, 0),
            },
        }
    }
}

impl Selection {
    /// The steps of this selection's topic instance's rows (`--on TOPIC`); a field
    /// is refused.
    pub fn grid(&self, log: &ULog<'_>) -> Result<Grid, AlignError> {
        if self.field.is_some() {
            let text = match self.instance {
                Some(n) => format!("{}:{n}.{}", self.topic, self.field.as_deref().unwrap_or("")),
                None => format!("{}.{}", self.topic, self.field.as_deref().unwrap_or("")),
            };
            return Err(AlignError::GridField(text));
        }
        let topic = self.topic(log)?;
        Ok(Grid::topic(topic.name(), topic.multi_id()))
    }
}

/// The columns of one topic instance that selections name: `(path, reader)`, the
/// paths as `ulog csv` names its columns (`q[0]`, `esc[2].esc_rpm`; a `char[N]` as one
/// text column), `timestamp` first when the whole topic is named.
#[derive(Debug, Clone)]
pub struct SelectedColumns<'l, 'a> {
    /// The topic instance.
    pub topic: Topic<'l, 'a>,
    /// Its columns, in the order named.
    pub columns: Vec<(String, FieldReader)>,
}

impl<'a> ULog<'a> {
    /// The columns `selections` name, grouped by topic instance in the order the
    /// instances are first named: every value leaf under a named field (an array's
    /// elements, a nested type's fields), or of the whole topic. An unknown topic or
    /// field is an error naming the closest the log has.
    pub fn select_columns<'l>(
        &'l self,
        selections: &[Selection],
    ) -> Result<Vec<SelectedColumns<'l, 'a>>, LookupError> {
        let mut out: Vec<SelectedColumns<'l, 'a>> = Vec::new();
        for s in selections {
            let topic = s.topic(self)?;
            let columns = columns_of(&topic, s.field.as_deref())?;
            match out
                .iter_mut()
                .find(|c| c.topic.name() == topic.name() && c.topic.multi_id() == topic.multi_id())
            {
                Some(c) => c.columns.extend(columns),
                None => out.push(SelectedColumns { topic, columns }),
            }
        }
        Ok(out)
    }
}

/// The columns of `field` of `topic` (every value leaf under it), or of every field
/// with `timestamp` first.
fn columns_of(
    topic: &Topic<'_, '_>,
    field: Option<&str>,
) -> Result<Vec<(String, FieldReader)>, LookupError> {
    columns_in(topic.name(), topic.layout()?, field)
}

/// [`columns_of`] in `layout`, the format of topic `name`.
fn columns_in(
    name: &str,
    layout: &Layout,
    field: Option<&str>,
) -> Result<Vec<(String, FieldReader)>, LookupError> {
    let under = |path: &str| match field {
        None => true,
        Some(f) => {
            path == f
                || path
                    .strip_prefix(f)
                    .is_some_and(|rest| rest.starts_with(['[', '.']))
        }
    };
    let mut paths: Vec<String> = layout
        .columns()
        .filter(|l| !l.path.starts_with("_padding") && under(&l.path))
        .map(|l| l.path.clone())
        .collect();
    if let Some(f) = field {
        if paths.is_empty() {
            // Not a value leaf: the reader's own error names the closest field.
            field_in(name, layout, f)?;
        }
    }
    if let Some(i) = paths.iter().position(|p| p == "timestamp") {
        let ts = paths.remove(i);
        paths.insert(0, ts);
    }
    paths
        .into_iter()
        .map(|p| field_in(name, layout, &p).map(|r| (p, r)))
        .collect()
}

impl Selection {
    /// The columns this selection names in `layout`, its topic's format (as
    /// [`AlignStream::layouts`](super::AlignStream::layouts) gives it), as
    /// [`ULog::select_columns`] names and orders them.
    pub fn columns(&self, layout: &Layout) -> Result<Vec<(String, FieldReader)>, LookupError> {
        columns_in(&self.topic, layout, self.field.as_deref())
    }

    /// The topic instance a [one-pass alignment](super::AlignStream) reads for this
    /// selection, by `method`: without an instance, instance 0 (a pass cannot know
    /// the lowest the log has before its end).
    pub fn track(&self, method: Method) -> Track {
        Track::new(&self.topic, self.instance.unwrap_or(0), method)
    }
}

#[cfg(test)]
mod tests {
    use super::Selection;

    #[test]
    fn topics_instances_and_fields() {
        let s: Selection = "esc_status:1.esc[2].esc_rpm".parse().unwrap();
        assert_eq!(
            (s.topic.as_str(), s.instance, s.field.as_deref()),
            ("esc_status", Some(1), Some("esc[2].esc_rpm"))
        );
        let s: Selection = " battery_status ".parse().unwrap();
        assert_eq!(
            (s.topic.as_str(), s.instance, s.field),
            ("battery_status", None, None)
        );
        for bad in ["x.", ":1.x", "x:300", "x:a", ""] {
            let e = bad.parse::<Selection>().unwrap_err();
            assert!(
                e.to_string().starts_with(&format!("`{}`", bad.trim())),
                "{e}"
            );
        }
    }
}
