//! Several topics on one time base: the steps of one topic's rows or of a fixed rate,
//! and at each step the value of each topic by a [`Method`].
//!
//! ```
//! # #[cfg(feature = "derive")] {
//! use ulog_core::align::{AlignOptions, Grid, Method};
//!
//! #[derive(ulog_core::ULogMessage, Debug)]
//! #[ulog(crate = "ulog_core")]
//! struct VehicleAttitude { timestamp: u64, q: [f32; 4] }
//! #[derive(ulog_core::ULogMessage, Debug)]
//! #[ulog(crate = "ulog_core")]
//! struct BatteryStatus { timestamp: u64, voltage_v: f32 }
//!
//! let bytes = ulog_core::testing::sample_log();
//! let log = ulog_core::ULog::parse(&bytes).unwrap();
//! // The attitude's rows are the steps; the battery as it was at each.
//! let steps = log.align(&Grid::topic("vehicle_attitude", 0), &AlignOptions::default()).unwrap();
//! let attitude = steps.topic::<VehicleAttitude>(0, Method::Previous).unwrap();
//! let battery = steps.topic::<BatteryStatus>(0, Method::Linear).unwrap();
//! for ((t, att), bat) in steps.times().iter().zip(attitude).zip(battery) {
//!     let att = att.unwrap(); // the step's own row
//!     if let Some(bat) = bat {
//!         assert!(bat.voltage_v > 10.0, "at {t}: {att:?}");
//!     }
//! }
//! # }
//! ```
//!
//! The rules, one for every front end (`ulog align`, the Python package):
//!
//! - **Steps** ([`Grid`]): the timestamps of one topic instance's rows in time order
//!   (equal ones kept), or a fixed rate from the log's [span](crate::ULog::span) start
//!   (`start + round(k · 10⁶ / hz)` µs, while not after the span's end); both within
//!   the window `[start, end)` of [`AlignOptions`] when it is given.
//! - **[`Method::Previous`]**: the last row at or before the step; among rows of equal
//!   timestamps the last in file order (`pandas.merge_asof(direction="backward")`).
//! - **[`Method::Nearest`]**: the closer of that row and the first after the step; the
//!   earlier on a tie.
//! - **[`Method::Linear`]**: between the rows around the step, `float` and `double`
//!   fields interpolated linearly (`numpy.interp`), quaternions (a `q[4]` of `float`s,
//!   PX4's `w, x, y, z`) by spherical linear interpolation along the shorter arc,
//!   integers, booleans, enums and strings taken from the earlier row (never
//!   interpolated), the `timestamp` field too. A step with no row after it (after the
//!   topic's last row) or none before has no value.
//! - **Absent** (`None`): no row by the method, or the row further from the step than
//!   the tolerance ([`AlignOptions::tolerance_us`]; for `Linear`, either of the two).
//!   Never an invented value.
//!
//! A topic's rows are found once, by time (12 bytes per row: its timestamp and
//! index); the values stay in the log's payloads and are decoded step by step.
//!
//! **In one pass**: [`AlignStream`] makes the same alignment reading the log once in
//! file order, from any `Read` (a file, a pipe, a log larger than memory), holding only
//! the steps not yet decided and the rows their methods still need (in PX4 logs, about
//! the horizon, 10 s of the log, at most); where its values could differ from these (a
//! row written long after its time, a topic silent for longer than the horizon) it says so
//! ([`StreamSummary`]). [`AlignedStream`] reads an [`Aligned`] struct that way.
//!
//! # Time
//!
//! Every time here is a boot time in microseconds, as the rows' `timestamp` fields
//! hold it (narrow version 0 timestamps unwrapped). Seconds since the start of the
//! log are a boot time by the log's [span](crate::ULog::span):
//! [`TimeSpan::at`](crate::read::TimeSpan::at) (and back,
//! [`TimeSpan::seconds`](crate::read::TimeSpan::seconds)). Windows are half open,
//! `[start, end)`. To seek and take windows:
//!
//! - one topic: its [`TimeIndex`] ([`Topic::time_index`]), built once in O(n), then
//!   a time or a window in O(log n);
//! - several topics on one time base: the window of [`AlignOptions`], and
//!   [`AlignedSteps::seek`] (a struct of topics, [`Aligned`]);
//! - several topics by time, row by row: [`ULog::time_ordered`] and
//!   [`TimeOrdered::seek`];
//! - a pass over a stream: [`ScanOptions::window_us`](crate::ScanOptions::window_us)
//!   on [`scan_topics`](crate::scan_topics).

mod aligned;
mod interp;
mod ordered;
mod select;
mod stream;
mod time_index;

#[doc(hidden)]
pub use aligned::{__Check, __Decode, __Layouts, __Next, __Plans, __decode};
pub use aligned::{Aligned, AlignedError, AlignedField, AlignedSteps};
pub use ordered::TimeOrdered;
pub use select::{SelectedColumns, Selection, SelectionError};
pub use stream::{
    AlignStream, AlignedStream, StreamError, StreamOptions, StreamStep, StreamSummary, Track,
    TrackReport, DEFAULT_HORIZON_US,
};
pub use time_index::TimeIndex;
/// The derive of [`Aligned`] (feature `derive`).
#[cfg(feature = "derive")]
pub use ulog_derive::Aligned;

use std::sync::Arc;

use crate::access::field::FieldReader;
use crate::access::lookup::LookupError;
use crate::access::topic::Topic;
use crate::log::ulog::ULog;
use crate::typed::error::TypedError;
use crate::typed::message::ULogMessage;
use crate::typed::plan::Plan;
use crate::value::Value;

use interp::Lerp;
use time_index::Cursor;

/// How a topic's value at a step is found (see the [module](self) for the rules).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Method {
    /// The last row at or before the step.
    #[default]
    Previous,
    /// The row nearest to the step.
    Nearest,
    /// Interpolated between the rows around the step (floats; quaternions by slerp).
    Linear,
}

impl core::str::FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Method, String> {
        match s {
            "previous" => Ok(Method::Previous),
            "nearest" => Ok(Method::Nearest),
            "linear" => Ok(Method::Linear),
            other => Err(format!(
                "unknown method `{other}` (previous, nearest or linear)"
            )),
        }
    }
}

/// The steps of an alignment.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Grid {
    /// The rows of one topic instance.
    Topic {
        /// Its name.
        name: String,
        /// Its instance.
        multi_id: u8,
    },
    /// A fixed rate, in steps per second, from the log's span start.
    Rate(f64),
}

impl Grid {
    /// The rows of topic `name`, instance `multi_id`.
    pub fn topic(name: &str, multi_id: u8) -> Grid {
        Grid::Topic {
            name: name.to_owned(),
            multi_id,
        }
    }
}

/// What an alignment keeps besides its steps.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AlignOptions {
    /// A value further from its step than this many microseconds is absent.
    pub tolerance_us: Option<u64>,
    /// Steps at or after this boot time (µs).
    pub start_us: Option<u64>,
    /// Steps before this boot time (µs).
    pub end_us: Option<u64>,
}

impl AlignOptions {
    /// Values at most `us` microseconds from their step.
    pub fn tolerance_us(mut self, us: u64) -> AlignOptions {
        self.tolerance_us = Some(us);
        self
    }

    /// Steps in `[start, end)`, boot microseconds (either open).
    pub fn window_us(mut self, start: Option<u64>, end: Option<u64>) -> AlignOptions {
        self.start_us = start;
        self.end_us = end;
        self
    }

    /// The options as `ulog align` and the Python package take them, in seconds: a
    /// tolerance, and a window `[start, end)` in seconds since the start of `log`'s
    /// [span](ULog::span) (rounded to the microsecond).
    ///
    /// ```
    /// # let bytes = ulog_core::testing::sample_log();
    /// # let log = ulog_core::ULog::parse(&bytes)?;
    /// use ulog_core::align::AlignOptions;
    /// let o = AlignOptions::in_seconds(&log, Some(0.01), Some(1.0), None)?;
    /// assert_eq!(o.tolerance_us, Some(10_000));
    /// assert_eq!(o.start_us, Some(log.span().start() + 1_000_000));
    /// assert!(AlignOptions::in_seconds(&log, Some(-1.0), None, None).is_err());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn in_seconds(
        log: &ULog<'_>,
        tolerance: Option<f64>,
        start: Option<f64>,
        end: Option<f64>,
    ) -> Result<AlignOptions, AlignError> {
        let mut options = AlignOptions::since_start(tolerance, None, None)?;
        let span = log.span();
        options.start_us = start.map(|s| span.at(s));
        options.end_us = end.map(|s| span.at(s));
        Ok(options)
    }

    /// The same options with the window in microseconds since the log's start, as a
    /// [one-pass alignment](AlignStream) takes it
    /// ([`StreamOptions::window_from_start`]): a pass knows the start only as the
    /// header gives it. Times before the start are the start.
    pub fn since_start(
        tolerance: Option<f64>,
        start: Option<f64>,
        end: Option<f64>,
    ) -> Result<AlignOptions, AlignError> {
        if let Some(t) = tolerance {
            if !(t >= 0.0 && t.is_finite()) {
                return Err(AlignError::Tolerance(t));
            }
        }
        let us = |s: f64| (s * 1e6).round().max(0.0) as u64;
        Ok(AlignOptions {
            tolerance_us: tolerance.map(us),
            start_us: start.map(us),
            end_us: end.map(us),
        })
    }
}

/// Why an alignment cannot be made.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum AlignError {
    /// The grid's topic is not in the log, or has no layout.
    Lookup(LookupError),
    /// The grid's topic has no timestamp field to step on.
    NoTimestamp(String),
    /// A rate that is not a positive number of steps per second.
    Rate(f64),
    /// A tolerance that is not a number of seconds, 0 or more.
    Tolerance(f64),
    /// Steps asked of a field (`topic.field`): steps are a topic's rows.
    GridField(String),
}

impl core::fmt::Display for AlignError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            AlignError::Lookup(e) => write!(f, "{e}"),
            AlignError::NoTimestamp(t) => {
                write!(f, "topic `{t}` has no timestamp field to align on")
            }
            AlignError::Rate(r) => write!(f, "rate {r}: steps per second must be more than 0"),
            AlignError::Tolerance(t) => write!(f, "tolerance {t}: seconds must be 0 or more"),
            AlignError::GridField(s) => write!(
                f,
                "`{s}`: the steps are a topic's rows (`TOPIC` or `TOPIC:N`), not a field"
            ),
        }
    }
}

impl std::error::Error for AlignError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            AlignError::Lookup(e) => Some(e),
            _ => None,
        }
    }
}

impl From<LookupError> for AlignError {
    fn from(e: LookupError) -> AlignError {
        AlignError::Lookup(e)
    }
}

/// The steps of an alignment over a log, to take topics' values at
/// ([`ULog::align`]).
#[derive(Debug, Clone)]
pub struct Alignment<'l, 'a> {
    log: &'l ULog<'a>,
    times: Vec<u64>,
    tolerance: Option<u64>,
}

impl<'a> ULog<'a> {
    /// The steps of `grid` within the window of `options`, to take topics' values at
    /// ([`Alignment::topic`], [`Alignment::field`]; the [`align`](crate::align)
    /// module has the rules).
    pub fn align(
        &self,
        grid: &Grid,
        options: &AlignOptions,
    ) -> Result<Alignment<'_, 'a>, AlignError> {
        let start = options.start_us.unwrap_or(0);
        let end = options.end_us.unwrap_or(u64::MAX);
        let times: Vec<u64> = match grid {
            Grid::Topic { name, multi_id } => {
                let topic = self.topic(name, *multi_id)?;
                if topic.timestamp_field().is_none() {
                    return Err(AlignError::NoTimestamp(name.clone()));
                }
                TimeIndex::of(&topic, |_| true)
                    .times
                    .into_iter()
                    .filter(|t| (start..end).contains(t))
                    .collect()
            }
            &Grid::Rate(hz) => {
                if !(hz > 0.0 && hz.is_finite()) {
                    return Err(AlignError::Rate(hz));
                }
                let span = self.span();
                let period = 1e6 / hz;
                (0u64..)
                    .map(|k| span.start() + (k as f64 * period).round() as u64)
                    .take_while(|&t| t <= span.end())
                    .filter(|t| (start..end).contains(t))
                    .collect()
            }
        };
        Ok(Alignment {
            log: self,
            times,
            tolerance: options.tolerance_us,
        })
    }
}

impl<'l, 'a> Alignment<'l, 'a> {
    /// The steps, boot microseconds, non-decreasing.
    pub fn times(&self) -> &[u64] {
        &self.times
    }

    /// The row of topic `name`, instance `multi_id`, at each step by `method`: the
    /// general form the others build on (one `Option<Row>` per step; read any field
    /// of it with a [`FieldReader`] of the topic).
    pub fn rows(
        &self,
        name: &str,
        multi_id: u8,
        method: Method,
    ) -> Result<Rows<'_, 'a>, LookupError> {
        let topic = self.log.topic(name, multi_id)?;
        Ok(Rows::new(self, topic, method))
    }

    /// The value of binding `T`'s topic (instance `multi_id`, found by its name or
    /// aliases) at each step, by `method`: one `Option<T>` per step. The binding is
    /// checked against the log's format once (a [`TypedError`] lists every
    /// difference); rows whose payload is shorter than the format are left out
    /// ([`Samples::left_out`]).
    pub fn topic<T: ULogMessage>(
        &self,
        multi_id: u8,
        method: Method,
    ) -> Result<Samples<'_, 'a, T>, TypedError> {
        let read = self.log.read::<T>(multi_id)?;
        let rows = Rows::new(self, read.topic(), method);
        Ok(Samples {
            rows,
            decoder: Decoder::Typed(read.plan().clone()),
        })
    }

    /// The value of field `path` (`q[0]`, `esc[2].esc_rpm`, as `ulog csv` names
    /// columns) of topic `name`, instance `multi_id`, at each step by `method`.
    pub fn field(
        &self,
        name: &str,
        multi_id: u8,
        path: &str,
        method: Method,
    ) -> Result<Samples<'_, 'a, Value<'a>>, LookupError> {
        let topic = self.log.topic(name, multi_id)?;
        let reader = topic.field(path)?;
        Ok(Samples {
            rows: Rows::new(self, topic, method),
            decoder: Decoder::Field(reader),
        })
    }
}

/// A topic's row at a step ([`Rows`]): one of the log's rows, or one interpolated
/// between two ([`Method::Linear`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Row<'a> {
    /// One of the log's rows, as logged.
    Logged(&'a [u8]),
    /// Interpolated: the payload, its `float`s, `double`s and quaternions between
    /// those of two rows, the rest the earlier row's.
    Between {
        /// The interpolated payload.
        bytes: Vec<u8>,
        /// The earlier of the two rows.
        earlier: &'a [u8],
    },
}

impl<'a> Row<'a> {
    /// The payload: the row's, or the interpolated one.
    pub fn bytes(&self) -> &[u8] {
        match self {
            Row::Logged(p) => p,
            Row::Between { bytes, .. } => bytes,
        }
    }

    /// The logged row the values that are not interpolated come from (the row
    /// itself, or the earlier of the two).
    pub fn earlier(&self) -> &'a [u8] {
        match self {
            Row::Logged(p) | Row::Between { earlier: p, .. } => p,
        }
    }
}

/// A topic's rows at the steps of an [`Alignment`]: an iterator of one `Option<Row>`
/// per step ([`Alignment::rows`]).
#[derive(Debug, Clone)]
pub struct Rows<'s, 'a> {
    times: &'s [u64],
    step: usize,
    topic: Topic<'s, 'a>,
    /// Shared by the rows [`Rows::from_step`] gives: found once per topic.
    series: Arc<TimeIndex>,
    cursor: Cursor,
    method: Method,
    tolerance: Option<u64>,
    lerp: Lerp,
    left_out: usize,
}

impl<'s, 'a> Rows<'s, 'a> {
    fn new(steps: &'s Alignment<'_, 'a>, topic: Topic<'s, 'a>, method: Method) -> Rows<'s, 'a> {
        let size = topic.layout().map(|l| l.min_size()).ok();
        let fits = |p: &[u8]| size.is_some_and(|min| p.len() >= min);
        let series = Arc::new(TimeIndex::of(&topic, fits));
        let left_out = topic.len() - series.len();
        let lerp = match (method, topic.layout()) {
            (Method::Linear, Ok(layout)) => Lerp::new(layout),
            _ => Lerp::default(),
        };
        let cursor = match steps.times.first() {
            Some(&t) => Cursor::seek(&series, t.saturating_sub(1)),
            None => Cursor::default(),
        };
        Rows {
            times: &steps.times,
            step: 0,
            topic,
            series,
            cursor,
            method,
            tolerance: steps.tolerance,
            lerp,
            left_out,
        }
    }

    /// The topic instance read.
    pub fn topic(&self) -> &Topic<'s, 'a> {
        &self.topic
    }

    /// The same topic's rows from step `step` of the alignment on, whatever steps
    /// these rows have reached: to take the steps in parts (on several threads), each
    /// part `rows.from_step(start).take(len)`. The topic's rows are not found again.
    ///
    /// ```
    /// # let bytes = ulog_core::testing::sample_log();
    /// # let log = ulog_core::ULog::parse(&bytes)?;
    /// use ulog_core::align::{AlignOptions, Grid, Method};
    /// let steps = log.align(&Grid::Rate(50.0), &AlignOptions::default())?;
    /// let rows = steps.rows("vehicle_attitude", 0, Method::Linear)?;
    /// let whole: Vec<_> = rows.clone().collect();
    /// let parts: Vec<_> = [0, 7].iter().flat_map(|&k| rows.from_step(k).take(7)).collect();
    /// assert_eq!(whole[..14], parts[..]);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_step(&self, step: usize) -> Rows<'s, 'a> {
        let cursor = match self.times.get(step) {
            Some(&t) => Cursor::seek(&self.series, t.saturating_sub(1)),
            None => Cursor::default(),
        };
        Rows {
            step,
            cursor,
            ..self.clone()
        }
    }

    /// How many of its rows were left out: rows without a timestamp, and rows whose
    /// payload is shorter than the format (damage the reader reports as findings).
    pub fn left_out(&self) -> usize {
        self.left_out
    }

    /// Repositions at step `step` (an index into [`Alignment::times`]): the next item
    /// is that step's row; a binary search over the topic's rows.
    pub fn seek_step(&mut self, step: usize) {
        self.step = step.min(self.times.len());
        self.cursor = match self.times.get(self.step) {
            Some(&t) => Cursor::seek(&self.series, t.saturating_sub(1)),
            None => Cursor::default(),
        };
    }

    /// The row (position in the series) the method picks at `t`, or the two rows and
    /// the fraction between them to interpolate at.
    fn pick(&mut self, t: u64) -> Option<Pick> {
        let (before, after) = self.cursor.around(&self.series, t);
        let times = &self.series.times;
        let choice = choose(
            self.method,
            self.tolerance,
            self.lerp.is_empty(),
            t,
            before.map(|i| times[i]),
            after.map(|i| times[i]),
        )?;
        Some(match choice {
            Choice::Before => Pick::Row(before?),
            Choice::After => Pick::Row(after?),
            Choice::Between(w) => Pick::Between(before?, after?, w),
        })
    }

    /// The payload of series position `i`.
    fn payload(&self, i: usize) -> &'a [u8] {
        let row = self.series.rows[i] as usize;
        self.topic.payload(row).unwrap_or_default()
    }
}

/// What a method takes at a step, of the last row at or before it and the first after
/// it ([`choose`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Choice {
    /// The row at or before the step.
    Before,
    /// The row after it.
    After,
    /// Interpolated at this fraction from the row before to the row after.
    Between(f64),
}

/// The one rule of the methods (the [module](self) has it in words), for the indexed
/// alignment and the one-pass one alike: at step `t`, given the times of the last row
/// at or before it and of the first after it, and whether the format has anything to
/// interpolate (`nothing_to_lerp`).
pub(crate) fn choose(
    method: Method,
    tolerance: Option<u64>,
    nothing_to_lerp: bool,
    t: u64,
    before: Option<u64>,
    after: Option<u64>,
) -> Option<Choice> {
    let near = |d: u64| tolerance.map_or(true, |tol| d <= tol);
    let d_before = before.map(|b| t - b);
    let d_after = after.map(|a| a - t);
    match method {
        Method::Previous => near(d_before?).then_some(Choice::Before),
        Method::Nearest => {
            let (choice, d) = match (d_before, d_after) {
                (Some(b), Some(a)) if a < b => (Choice::After, a),
                (Some(b), _) => (Choice::Before, b),
                (None, Some(a)) => (Choice::After, a),
                (None, None) => return None,
            };
            near(d).then_some(choice)
        }
        Method::Linear => {
            let d = d_before?;
            if d == 0 || nothing_to_lerp && after.is_some() {
                // On a row, or nothing to interpolate: the earlier row (within the
                // span of the topic).
                return near(d).then_some(Choice::Before);
            }
            let da = d_after?;
            if !(near(d) && near(da)) {
                return None;
            }
            Some(Choice::Between(d as f64 / (d + da) as f64))
        }
    }
}

/// What [`Rows::pick`] found.
enum Pick {
    Row(usize),
    Between(usize, usize, f64),
}

impl<'s, 'a> Iterator for Rows<'s, 'a> {
    type Item = Option<Row<'a>>;
    fn next(&mut self) -> Option<Option<Row<'a>>> {
        let t = *self.times.get(self.step)?;
        self.step += 1;
        let row = match self.pick(t) {
            None => None,
            Some(Pick::Row(i)) => Some(Row::Logged(self.payload(i))),
            Some(Pick::Between(b, a, w)) => {
                let (earlier, later) = (self.payload(b), self.payload(a));
                let mut bytes = Vec::with_capacity(earlier.len());
                self.lerp.between(earlier, later, w, &mut bytes);
                Some(Row::Between { bytes, earlier })
            }
        };
        Some(row)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.times.len() - self.step;
        (n, Some(n))
    }
}

impl ExactSizeIterator for Rows<'_, '_> {}

/// How a [`Samples`] turns a row into its item.
enum Decoder<T> {
    Typed(Plan<T>),
    Field(FieldReader),
}

/// A topic's values at the steps of an [`Alignment`]: an iterator of one `Option`
/// per step ([`Alignment::topic`], [`Alignment::field`]).
pub struct Samples<'s, 'a, T> {
    rows: Rows<'s, 'a>,
    decoder: Decoder<T>,
}

impl<'s, 'a, T> Samples<'s, 'a, T> {
    /// The topic instance read.
    pub fn topic(&self) -> &Topic<'s, 'a> {
        self.rows.topic()
    }

    /// How many of its rows were left out ([`Rows::left_out`]).
    pub fn left_out(&self) -> usize {
        self.rows.left_out()
    }

    /// Repositions at step `step` ([`Rows::seek_step`]).
    pub fn seek_step(&mut self, step: usize) {
        self.rows.seek_step(step);
    }
}

impl<T: ULogMessage> Iterator for Samples<'_, '_, T> {
    type Item = Option<T>;
    fn next(&mut self) -> Option<Option<T>> {
        let row = self.rows.next()?;
        let Decoder::Typed(plan) = &self.decoder else {
            return Some(None);
        };
        Some(row.and_then(|r| plan.decode(r.bytes()).ok()))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.rows.size_hint()
    }
}

impl<'a> Iterator for Samples<'_, 'a, Value<'a>> {
    type Item = Option<Value<'a>>;
    fn next(&mut self) -> Option<Option<Value<'a>>> {
        let row = self.rows.next()?;
        let Decoder::Field(reader) = &self.decoder else {
            return Some(None);
        };
        Some(row.and_then(|r| match &r {
            Row::Logged(p) => reader.read(p),
            // Only floats and doubles change between rows (a quaternion's elements
            // by slerp): read those from the interpolated bytes, the rest from the
            // earlier row, which the value may borrow.
            Row::Between { bytes, earlier } => match reader.read(bytes) {
                Some(Value::F32(v)) => Some(Value::F32(v)),
                Some(Value::F64(v)) => Some(Value::F64(v)),
                _ => reader.read(earlier),
            },
        }))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.rows.size_hint()
    }
}
