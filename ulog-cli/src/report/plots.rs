//! Reading the standard plots' lines ([`super::spec`]) of a log through generic field
//! access: each group's topic found in the metadata, its lines thinned as the second
//! pass hands its rows ([`super::pass`]).

use serde::Serialize;
use ulog_core::read::{TimeSpan, Unwrapper};
use ulog_core::{FieldReader, Topic, ULog};

use super::pass::{Routes, Rows};
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

/// A standard plot being read: per group the log has, its topic and its table.
pub struct Pending {
    spec: &'static PlotSpec,
    groups: Vec<(String, GroupRows)>,
}

/// The standard plots, to be read: `rows` has each subscription's data messages.
pub fn standard(log: &ULog<'_>, rows: &[usize], span: &TimeSpan) -> Vec<Pending> {
    PLOTS
        .iter()
        .map(|spec| Pending {
            spec,
            groups: spec
                .groups
                .iter()
                .filter_map(|group| {
                    let (topic, lines) = find(log, rows, group)?;
                    let table = GroupRows::new(&topic, rows, lines, span);
                    Some((topic.name().to_owned(), table))
                })
                .collect(),
        })
        .collect()
}

/// Whether no standard plot has a topic to read.
pub fn none_found(pending: &[Pending]) -> bool {
    pending.iter().all(|p| p.groups.is_empty())
}

/// Has the second pass hand the plots' topics' rows to them.
pub fn route<'c>(pending: &'c mut [Pending], routes: &mut Routes<'c>) {
    for (_, table) in pending.iter_mut().flat_map(|p| p.groups.iter_mut()) {
        routes.add(table.sub, table);
    }
}

/// The standard plots the log has data for, and a note for each other one.
pub fn finish_standard(pending: Vec<Pending>) -> (Vec<Plot>, Vec<Missing>) {
    let mut plots = Vec::new();
    let mut missing = Vec::new();
    for Pending { spec, groups } in pending {
        let mut plot = Plot {
            id: spec.id.to_owned(),
            title: spec.title.to_owned(),
            unit: spec.unit.to_owned(),
            sources: Vec::new(),
            tables: Vec::new(),
        };
        for (topic, rows) in groups {
            let mut table = rows.finish();
            if spec.drop_zero {
                table.drop_zero_lines();
            }
            if table.labels.is_empty() || table.is_blank() {
                continue;
            }
            plot.sources.push(topic);
            plot.tables.push(table);
        }
        if plot.tables.is_empty() {
            missing.push(Missing {
                title: spec.title.to_owned(),
                needs: needs(spec),
            });
        } else {
            plots.push(plot);
        }
    }
    (plots, missing)
}

/// The topics a plot is drawn from: `a or b, c`.
fn needs(spec: &PlotSpec) -> String {
    let groups: Vec<String> = spec.groups.iter().map(|g| g.topics.join(" or ")).collect();
    groups.join(", ")
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
    rows: &[usize],
    group: &Group,
) -> Option<(Topic<'l, 'a>, Vec<(String, Reader)>)> {
    for name in group.topics {
        let Some(topic) = log.topic_instances(name).first().copied() else {
            continue;
        };
        if topic.timestamp_field().is_none() || count(rows, &topic) == 0 {
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

/// The data messages of `topic`, as the first pass counted them.
fn count(rows: &[usize], topic: &Topic<'_, '_>) -> usize {
    rows.get(topic.subscription().index()).copied().unwrap_or(0)
}

/// The rows of one topic as the lines' values, thinned as they come.
pub struct GroupRows {
    sub: usize,
    readers: Vec<Reader>,
    builder: Builder,
    clock: Unwrapper,
    row: Vec<f32>,
}

impl GroupRows {
    fn new(
        topic: &Topic<'_, '_>,
        rows: &[usize],
        lines: Vec<(String, Reader)>,
        span: &TimeSpan,
    ) -> GroupRows {
        let (labels, readers): (Vec<String>, Vec<Reader>) = lines.into_iter().unzip();
        GroupRows {
            sub: topic.subscription().index(),
            builder: Builder::new(labels, count(rows, topic), span),
            clock: Unwrapper::new(topic.timestamp_field()),
            row: vec![0f32; readers.len()],
            readers,
        }
    }

    fn finish(self) -> Table {
        self.builder.finish()
    }
}

impl Rows for GroupRows {
    fn push(&mut self, payload: &[u8]) {
        let Some(t) = self.clock.push(payload) else {
            return;
        };
        for (v, r) in self.row.iter_mut().zip(&self.readers) {
            *v = r.read(payload);
        }
        self.builder.push(t, &self.row);
    }
}

/// A plot of one topic of a log without the standard plots' topics, being read.
pub struct PendingTopic {
    name: String,
    id: String,
    rows: GroupRows,
}

/// Every topic with its numeric scalar fields (at most `fields` each), for a log that
/// has none of the standard plots' topics (not PX4's), to be read.
pub fn every_topic(
    log: &ULog<'_>,
    rows: &[usize],
    span: &TimeSpan,
    fields: usize,
) -> Vec<PendingTopic> {
    let mut plots = Vec::new();
    for topic in log.topics() {
        if count(rows, &topic) == 0 || topic.timestamp_field().is_none() {
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
        plots.push(PendingTopic {
            name: format!("{}:{}", topic.name(), topic.multi_id()),
            id: format!("topic_{}_{}", topic.name(), topic.multi_id()),
            rows: GroupRows::new(&topic, rows, lines, span),
        });
    }
    plots
}

/// Has the second pass hand every topic's rows to its plot.
pub fn route_topics<'c>(pending: &'c mut [PendingTopic], routes: &mut Routes<'c>) {
    for p in pending {
        routes.add(p.rows.sub, &mut p.rows);
    }
}

/// The plots of every topic with a value.
pub fn finish_topics(pending: Vec<PendingTopic>) -> Vec<Plot> {
    pending
        .into_iter()
        .filter_map(|p| {
            let table = p.rows.finish();
            (!table.is_blank()).then(|| Plot {
                id: p.id,
                title: p.name.clone(),
                unit: String::new(),
                sources: vec![p.name],
                tables: vec![table],
            })
        })
        .collect()
}
