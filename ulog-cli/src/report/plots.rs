//! Reading the standard plots' lines ([`super::spec`]) from a log through generic field
//! access: each group's topic once, its lines thinned as they are read.

use serde::Serialize;
use ulog_core::read::Unwrapper;
use ulog_core::{FieldReader, Topic, ULog};

use super::spec::{Group, PlotSpec, Value, PLOTS};
use super::table::{Builder, Table};

/// One plot of the page: tables of lines sharing a y axis.
#[derive(Debug, Serialize)]
pub struct Plot {
    /// The plot's id.
    pub id: String,
    /// Its heading.
    pub title: String,
    /// The unit of its y axis.
    pub unit: String,
    /// Where the lines come from (`topic`, or `topic:N`), for the caption.
    pub sources: Vec<String>,
    /// The tables, one per topic.
    pub tables: Vec<Table>,
}

/// A plot the log has no data for, with the topics it would need.
#[derive(Debug, Serialize)]
pub struct Missing {
    /// The plot's heading.
    pub title: String,
    /// What it would be drawn from.
    pub needs: String,
}

/// The standard plots the log has data for, and a note for each other one.
pub fn standard(log: &ULog<'_>, start_us: u64, end_us: u64) -> (Vec<Plot>, Vec<Missing>) {
    let mut plots = Vec::new();
    let mut missing = Vec::new();
    for spec in PLOTS {
        match read_plot(log, spec, start_us, end_us) {
            Some(p) => plots.push(p),
            None => missing.push(Missing {
                title: spec.title.to_owned(),
                needs: needs(spec),
            }),
        }
    }
    (plots, missing)
}

/// The topics a plot is drawn from: `a or b, c`.
fn needs(spec: &PlotSpec) -> String {
    let groups: Vec<String> = spec.groups.iter().map(|g| g.topics.join(" or ")).collect();
    groups.join(", ")
}

fn read_plot(log: &ULog<'_>, spec: &PlotSpec, start_us: u64, end_us: u64) -> Option<Plot> {
    let mut plot = Plot {
        id: spec.id.to_owned(),
        title: spec.title.to_owned(),
        unit: spec.unit.to_owned(),
        sources: Vec::new(),
        tables: Vec::new(),
    };
    for group in spec.groups {
        let Some((topic, lines)) = find(log, group) else {
            continue;
        };
        let mut table = read_group(&topic, lines, start_us, end_us);
        if spec.drop_zero {
            table.drop_zero_lines();
        }
        if table.labels.is_empty() || table.is_blank() {
            continue;
        }
        plot.sources.push(topic.name().to_owned());
        plot.tables.push(table);
    }
    (!plot.tables.is_empty()).then_some(plot)
}

/// How one line is read from a payload.
enum Reader {
    Field(FieldReader, f32),
    Norm([FieldReader; 3]),
}

impl Reader {
    fn read(&self, payload: &[u8]) -> f32 {
        let get = |r: &FieldReader| r.read_f64(payload).map_or(f32::NAN, |v| v as f32);
        match self {
            Reader::Field(r, k) => get(r) * k,
            Reader::Norm(rs) => rs.iter().map(|r| get(r).powi(2)).sum::<f32>().sqrt(),
        }
    }
}

/// The first topic of the group (lowest instance) with at least one of its lines, and
/// the lines it has.
fn find<'l, 'a>(
    log: &'l ULog<'a>,
    group: &Group,
) -> Option<(Topic<'l, 'a>, Vec<(String, Reader)>)> {
    for name in group.topics {
        let Some(topic) = log.topic_instances(name).first().copied() else {
            continue;
        };
        if topic.timestamp_field().is_none() || topic.is_empty() {
            continue;
        }
        let lines: Vec<(String, Reader)> = group
            .lines
            .iter()
            .filter_map(|line| {
                let reader = match &line.value {
                    Value::Field(fields) => fields
                        .iter()
                        .find_map(|(f, k)| Some(Reader::Field(topic.field(f).ok()?, *k)))?,
                    Value::Norm(triples) => triples.iter().find_map(|t| {
                        let [a, b, c] = t.map(|f| topic.field(f).ok());
                        Some(Reader::Norm([a?, b?, c?]))
                    })?,
                };
                Some((line.label.to_owned(), reader))
            })
            .collect();
        if !lines.is_empty() {
            return Some((topic, lines));
        }
    }
    None
}

/// Every row of `topic`, thinned, as the lines' values.
fn read_group(
    topic: &Topic<'_, '_>,
    lines: Vec<(String, Reader)>,
    start_us: u64,
    end_us: u64,
) -> Table {
    let (labels, readers): (Vec<String>, Vec<Reader>) = lines.into_iter().unzip();
    let mut builder = Builder::new(labels, topic.len(), start_us, end_us);
    let mut clock = Unwrapper::new(topic.timestamp_field());
    let mut row = vec![0f32; readers.len()];
    for payload in topic.payloads() {
        let Some(t) = clock.push(payload) else {
            continue;
        };
        for (v, r) in row.iter_mut().zip(&readers) {
            *v = r.read(payload);
        }
        builder.push(t, &row);
    }
    builder.finish()
}

/// Every topic with its numeric scalar fields (at most `fields` each), for a log that
/// has none of the standard plots' topics (not PX4's).
pub fn every_topic(log: &ULog<'_>, start_us: u64, end_us: u64, fields: usize) -> Vec<Plot> {
    let mut plots = Vec::new();
    for topic in log.topics() {
        if topic.is_empty() || topic.timestamp_field().is_none() {
            continue;
        }
        let Ok(columns) = topic.fields() else {
            continue;
        };
        let lines: Vec<(String, Reader)> = columns
            .iter()
            .map(|c| c.path())
            .filter(|p| *p != "timestamp" && !p.starts_with("_padding"))
            .filter_map(|p| {
                let r = topic.field(p).ok()?;
                matches!(r.shape(), ulog_core::read::FieldShape::Scalar)
                    .then(|| (p.to_owned(), Reader::Field(r, 1.0)))
            })
            .take(fields)
            .collect();
        if lines.is_empty() {
            continue;
        }
        let name = format!("{}:{}", topic.name(), topic.multi_id());
        let table = read_group(&topic, lines, start_us, end_us);
        if table.is_blank() {
            continue;
        }
        plots.push(Plot {
            id: format!("topic_{}_{}", topic.name(), topic.multi_id()),
            title: name.clone(),
            unit: String::new(),
            sources: vec![name],
            tables: vec![table],
        });
    }
    plots
}
