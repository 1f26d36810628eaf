//! The points of each field to plot: (seconds since log start, value).

use ulog_core::read::{FieldShape, TimeSpan, Unwrapper};
use ulog_core::{FieldReader, LookupError, Topic, ULog};

use super::spec::FieldSpec;
use crate::failure::Failure;
use ulog_core::units::unit_of;

/// One line of the plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// `topic.field` (with `:N` when the log has several instances of the topic).
    pub label: String,
    /// The unit, when the field's name says it.
    pub unit: Option<&'static str>,
    /// (seconds since log start, value), in time order; NaN and infinite values left out.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// The label with its unit: `vehicle_local_position.z [m]`.
    pub fn legend(&self) -> String {
        match self.unit {
            Some(u) => format!("{} [{u}]", self.label),
            None => self.label.clone(),
        }
    }
}

/// The series `spec` names in `log` (one per element when the field is a whole array),
/// on the time axis of the log's span (seconds since its start; rows made before
/// logging began at 0, stray ones left out: `TimeSpan`). Unknown names fail with the
/// closest name the log has.
pub fn read(
    log: &ULog<'_>,
    file: &str,
    spec: &FieldSpec,
    span: &TimeSpan,
) -> Result<Vec<Series>, Failure> {
    let topic = find_topic(log, file, spec)?;
    let several = log.topic_instances(topic.name()).len() > 1;
    let topic_label = if several || spec.instance.is_some() {
        format!("{}:{}", topic.name(), topic.multi_id())
    } else {
        topic.name().to_owned()
    };
    let reader = topic.field(&spec.field).map_err(|e| match e {
        LookupError::Field { .. } => match group_member(&topic, &spec.field) {
            Some(member) => Failure::unknown_name(
                file,
                format!(
                    "topic `{}`: `{}` is a group of fields, not a number: name one, e.g. `{member}`",
                    topic.name(),
                    spec.field
                ),
            ),
            None => Failure::unknown_name(file, &e),
        },
        _ => Failure::about(file, &e),
    })?;
    let readers: Vec<(String, FieldReader)> = match reader.shape() {
        FieldShape::Scalar => vec![(spec.field.clone(), reader)],
        FieldShape::Array(n) => (0..n)
            .map(|i| {
                let path = format!("{}[{i}]", spec.field);
                topic
                    .field(&path)
                    .map(|r| (path, r))
                    .map_err(|e| Failure::about(file, &e))
            })
            .collect::<Result<_, _>>()?,
        FieldShape::String(_) => {
            return Err(Failure::about(
                file,
                format!("`{spec}` is text (char[]), not a number: it cannot be plotted"),
            ))
        }
    };
    if topic.timestamp_field().is_none() {
        return Err(Failure::about(
            file,
            format!(
                "topic `{}` has no timestamp field: nothing to put on the time axis",
                topic.name()
            ),
        ));
    }
    let mut series: Vec<Series> = readers
        .iter()
        .map(|(path, _)| Series {
            label: format!("{topic_label}.{path}"),
            unit: unit_of(topic.name(), path),
            points: Vec::with_capacity(topic.len()),
        })
        .collect();
    let mut clock = Unwrapper::new(topic.timestamp_field());
    for payload in topic.payloads() {
        let Some(t) = clock.push(payload).and_then(|t| span.axis_time(t)) else {
            continue;
        };
        let x = span.seconds(t);
        for (s, (_, r)) in series.iter_mut().zip(&readers) {
            if let Some(y) = r.read_f64(payload).filter(|y| y.is_finite()) {
                s.points.push((x, y));
            }
        }
    }
    for s in &mut series {
        // Data messages are in file order; a topic's timestamps should rise, but a
        // damaged or reordered log may break that.
        if !s.points.windows(2).all(|w| w[0].0 <= w[1].0) {
            s.points.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
    }
    Ok(series)
}

/// The topic instance `spec` names: its `:N`, or the lowest instance the log has.
fn find_topic<'l, 'a>(
    log: &'l ULog<'a>,
    file: &str,
    spec: &FieldSpec,
) -> Result<Topic<'l, 'a>, Failure> {
    let found = match spec.instance {
        Some(n) => log.topic(&spec.topic, n),
        None => match log.topic_instances(&spec.topic).first() {
            Some(t) => Ok(*t),
            None => log.topic(&spec.topic, 0),
        },
    };
    // The library's error says which instances the topic has, or the closest names.
    found.map_err(|e| Failure::unknown_name(file, &e))
}

/// The first column inside `path` when `path` names a nested struct or an array of
/// them (`esc` → `esc[0].esc_count`).
fn group_member(topic: &Topic<'_, '_>, path: &str) -> Option<String> {
    let fields = topic.fields().ok()?;
    fields
        .iter()
        .map(|c| c.path())
        .find(|c| {
            c.strip_prefix(path)
                .is_some_and(|rest| rest.starts_with('.') || rest.starts_with('['))
        })
        .map(str::to_owned)
}
