//! [`AlignStream`]: an alignment made in one pass over the log in file order, from any
//! `Read`, holding only the rows its methods still need.

use std::collections::VecDeque;
use std::io::Read;
use std::sync::Arc;

use super::aligned::{Aligned, AlignedError};
use super::interp::Lerp;
use super::{choose, AlignError, AlignOptions, Choice, Grid, Method, Row};
use crate::access::lookup::{LookupError, TopicNotFound};
use crate::definitions::Subscription;
use crate::error::ReadError;
use crate::finding::Finding;
use crate::log::message::Message;
use crate::log::span::JUMP_US;
use crate::pass::stream::StreamReader;
use crate::read::{TimestampField, Unwrapper};
use crate::typed::error::TypedError;
use crate::typed::TypedErrorKind;
use ulog_format::Layout;

/// The horizon a one-pass alignment waits for a topic's next row by default: 10 s.
pub const DEFAULT_HORIZON_US: u64 = 10_000_000;

/// One topic instance a one-pass alignment reads, and how its value at a step is
/// found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Track {
    /// The topic's name.
    pub topic: String,
    /// Its instance.
    pub multi_id: u8,
    /// How its value at a step is found.
    pub method: Method,
}

impl Track {
    /// Topic `topic`, instance `multi_id`, by `method`.
    pub fn new(topic: &str, multi_id: u8, method: Method) -> Track {
        Track {
            topic: topic.to_owned(),
            multi_id,
            method,
        }
    }
}

/// The options of a one-pass alignment: the alignment's own (tolerance, window), and
/// how long it waits for a topic's next row.
#[derive(Debug, Clone, PartialEq)]
pub struct StreamOptions {
    /// Tolerance and window, as for the indexed alignment.
    pub align: AlignOptions,
    /// A step is decided at the latest when the pass has met a step this many
    /// microseconds after it ([`AlignStream`] says when a step is decided). `u64::MAX`: wait for every
    /// topic's next row however far (memory then grows while a topic is silent).
    pub horizon_us: u64,
    /// The window's times ([`AlignOptions::start_us`], [`AlignOptions::end_us`]) are
    /// microseconds since the log's start as its header gives it, not boot times (a
    /// pass knows no more of the log's span at its start).
    pub window_from_start: bool,
}

impl Default for StreamOptions {
    fn default() -> StreamOptions {
        StreamOptions {
            align: AlignOptions::default(),
            horizon_us: DEFAULT_HORIZON_US,
            window_from_start: false,
        }
    }
}

/// Why a one-pass alignment stopped.
#[derive(Debug)]
#[non_exhaustive]
pub enum StreamError {
    /// The log could not be read (not a ULog, a read that failed).
    Read(ReadError),
    /// The alignment cannot be made (a topic the log does not have, a grid topic
    /// without a timestamp, a bad rate or tolerance).
    Align(AlignError),
    /// Fields of an [`Aligned`] struct that do not fit the log, all of them.
    Aligned(AlignedError),
}

impl core::fmt::Display for StreamError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            StreamError::Read(e) => write!(f, "{e}"),
            StreamError::Align(e) => write!(f, "{e}"),
            StreamError::Aligned(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for StreamError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            StreamError::Read(e) => Some(e),
            StreamError::Align(e) => Some(e),
            StreamError::Aligned(e) => Some(e),
        }
    }
}

impl From<ReadError> for StreamError {
    fn from(e: ReadError) -> StreamError {
        StreamError::Read(e)
    }
}

impl From<AlignError> for StreamError {
    fn from(e: AlignError) -> StreamError {
        StreamError::Align(e)
    }
}

/// What a one-pass alignment met of one topic that makes its values differ from the
/// indexed alignment's, and what it held.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TrackReport {
    /// Rows met after a step they would change was handed out (a step at or after
    /// their time, or, for a row that comes back in time, one after the row before
    /// it): that step does not see them.
    pub late_rows: u64,
    /// The byte offset of the first such row's message.
    pub first_late_offset: Option<u64>,
    /// Steps decided by the horizon before the topic's next row came (`nearest` and
    /// `linear`, counted when that row came): their value is the one after the
    /// topic's last row, where the indexed alignment may take the next row.
    pub early_steps: u64,
    /// Rows without a timestamp, shorter than the format, or of a later subscription
    /// of another format: not read.
    pub left_out: u64,
    /// The most rows of the topic held at once.
    pub held_rows_peak: usize,
}

/// What a one-pass alignment did ([`AlignStream::summary`]).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct StreamSummary {
    /// Steps handed out.
    pub steps: u64,
    /// Per topic read, in the order given.
    pub tracks: Vec<TrackReport>,
    /// Rows of the grid topic met after a later step was handed out, or more than the
    /// horizon behind the latest row read: left out.
    pub late_steps: u64,
    /// The byte offset of the first such row's message.
    pub first_late_step_offset: Option<u64>,
    /// The most steps waiting at once.
    pub pending_peak: usize,
    /// The most rows held at once, every topic together.
    pub held_rows_peak: usize,
    /// The most payload bytes held at once, every topic together.
    pub held_bytes_peak: usize,
    /// Damage the pass stepped over (as [`ULog::findings`](crate::ULog::findings)
    /// reports it).
    pub findings: Vec<Finding>,
}

impl StreamSummary {
    /// Whether the steps and values are exactly the indexed alignment's: nothing came
    /// late and no step was decided early.
    pub fn is_exact(&self) -> bool {
        self.late_steps == 0
            && self
                .tracks
                .iter()
                .all(|t| t.late_rows == 0 && t.early_steps == 0)
    }
}

/// A step of a one-pass alignment: its time, and each topic's row at it, in the order
/// the topics were given (read fields from it with a [`FieldReader`](crate::FieldReader)
/// of the topic's [layout](AlignStream::layouts)).
#[derive(Debug, Clone, PartialEq)]
pub struct StreamStep<'s> {
    /// Boot microseconds.
    pub time: u64,
    /// Each topic's row at the step; `None`: absent.
    pub rows: Vec<Option<Row<'s>>>,
}

/// A topic read: what is wanted, its subscription once met, and its rows held.
struct TrackState {
    want: Track,
    /// Its format's layout, once known.
    layout: Option<Arc<Layout>>,
    /// Its subscription, once met.
    sub: Option<Arc<Subscription>>,
    unwrap: Unwrapper,
    min_size: usize,
    lerp: Lerp,
    /// Rows from the last at or before the oldest waiting step on, in time order
    /// (file order among equal times).
    rows: VecDeque<(u64, Vec<u8>)>,
    /// The msg_id its rows came with last (or its subscription's).
    msg_id: Option<u16>,
    /// The latest time of its rows read.
    max_seen: Option<u64>,
    /// Unsubscribed: no row is to come (until it is subscribed again).
    closed: bool,
    /// Steps handed out by the horizon without a row after them since the last row.
    undecided: u64,
    report: TrackReport,
}

impl TrackState {
    /// Takes `layout` as the topic's: how its rows are read.
    fn set_layout(&mut self, layout: Arc<Layout>) {
        self.unwrap = Unwrapper::new(TimestampField::of(&layout));
        self.min_size = layout.min_size();
        if self.want.method == Method::Linear {
            self.lerp = Lerp::new(&layout);
        }
        self.layout = Some(layout);
    }

    /// Whether the topic's value at `t` is decided without the horizon.
    fn settled(&self, t: u64) -> bool {
        self.closed || self.rows.back().is_some_and(|(last, _)| *last > t)
    }
}

/// The steps: a topic's rows, or a rate.
enum Steps {
    Topic {
        name: String,
        multi_id: u8,
        sub: Option<Arc<Subscription>>,
        unwrap: Unwrapper,
    },
    Rate {
        period: f64,
        start: Option<u64>,
        next: u64,
    },
}

/// What a subscription is to the alignment: the grid's, and which tracks'.
#[derive(Debug, Clone, Default)]
struct Roles {
    grid: bool,
    tracks: Vec<usize>,
}

/// An alignment made in one pass over the log in file order, from any `Read`, holding
/// only the rows its methods still need: [`next_step`](AlignStream::next_step) hands
/// out the steps one by one.
///
/// The indexed alignment ([`ULog::align`](crate::ULog::align)) finds each topic's rows
/// by time first, so it needs the whole log (or the topics read) at hand. This one
/// reads the messages as they come and hands out a step as soon as every topic's value
/// at it is decided; it holds the steps not yet decided and, per topic, its rows from
/// the last one at or before the oldest such step on. PX4's logger writes a row a
/// moment after its time, so both stay a few hundred milliseconds of the log deep.
///
/// # When a step is decided
///
/// A topic's value at step `t` is decided when the pass has met one of:
///
/// - a row of the topic after `t` (its rows come in time order, so none at or before
///   `t` is still to come);
/// - the topic's unsubscription, or the end of the log;
/// - a step more than the horizon ([`StreamOptions::horizon_us`], 10 s by default)
///   after `t` (the latest time of any row read, grid or topic): a topic
///   that stops logging, or logs seldom, holds nothing up beyond that.
///
/// The values are then those of the indexed alignment, by the same rules ([the
/// module](crate::align)), except where the pass reports it ([`StreamSummary`]): rows met
/// after a step at or after their time was handed out (a stale row written long after
/// its time; [`TrackReport::late_rows`]), which that step does not see, and steps
/// decided by the horizon before the topic's next row came, for `nearest` and `linear`
/// ([`TrackReport::early_steps`]): their value is what it would be after the topic's
/// last row. Rows of the grid topic met after a later step was handed out, or more
/// than the horizon behind the latest row read, are left out
/// ([`StreamSummary::late_steps`]). Rows that come back in time after a step they
/// would change was handed out count as late rows too. A log in which none of these is reported gives
/// exactly the indexed alignment's steps and values.
///
/// # Differences from the indexed alignment, by design
///
/// - A topic is named with its instance (the indexed one's selection without an
///   instance takes the lowest the log has, which a pass knows only at its end).
/// - A rate's steps start at the log's start as its header gives it (for a header
///   without one, the first row read) and end at the last row of the topics read (the
///   indexed one ends at the log's span end, which takes every topic).
/// - A topic not yet subscribed (PX4 subscribes a topic when it is first published)
///   has no rows yet: its steps wait for it as for any topic's next row, up to the
///   horizon. One never subscribed in the whole log is an error at the end, after the
///   steps (the indexed alignment refuses it before any).
///
/// ```
/// use ulog_core::align::{AlignStream, Grid, Method, StreamOptions, Track};
/// # let bytes = ulog_core::testing::sample_log();
/// let tracks = vec![
///     Track::new("vehicle_attitude", 0, Method::Previous),
///     Track::new("battery_status", 0, Method::Linear),
/// ];
/// let grid = Grid::topic("vehicle_attitude", 0);
/// let mut stream = AlignStream::new(&bytes[..], &grid, tracks, StreamOptions::default())?;
/// // The topics' layouts, to read fields with (or to decode rows with a binding:
/// // `ulog_core::typed::Plan::<T>::new(&layout)?.decode(row.bytes())`).
/// let battery = stream.layouts()?[1].clone();
/// let voltage = ulog_core::FieldReader::all(&battery)
///     .into_iter()
///     .find(|f| f.path() == "voltage_v")
///     .unwrap();
/// let mut steps = 0;
/// while let Some(step) = stream.next_step()? {
///     if let Some(row) = &step.rows[1] {
///         assert!(voltage.read_f64(row.bytes()).unwrap() > 10.0);
///     }
///     steps += 1;
/// }
/// // The same steps as the indexed alignment, from a pass that held a few rows.
/// let log = ulog_core::ULog::parse(&bytes)?;
/// let indexed = log.align(&grid, &Default::default())?;
/// assert_eq!(steps, indexed.times().len());
/// let summary = stream.summary();
/// assert!(summary.is_exact());
/// assert!(summary.held_rows_peak < 100);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct AlignStream<R> {
    reader: StreamReader<R>,
    steps: Steps,
    tracks: Vec<TrackState>,
    options: StreamOptions,
    /// Steps waiting to be decided, non-decreasing.
    pending: VecDeque<u64>,
    /// The latest step time met (grid rows, or for a rate the latest row read).
    watermark: Option<u64>,
    /// A row met that jumped far ahead of the watermark: its time.
    jump: Option<u64>,
    /// The last step handed out.
    emitted: Option<u64>,
    ended: bool,
    /// Ended at the window's end, before the log's.
    stopped_early: bool,
    /// The roles of each subscription (by index), found when first met.
    roles: Vec<Option<Arc<Roles>>>,
    /// Payload buffers of rows let go, used again.
    free: Vec<Vec<u8>>,
    /// The payload of the message being read.
    scratch: Vec<u8>,
    held_rows: usize,
    held_bytes: usize,
    summary: StreamSummary,
}

impl<R: Read> AlignStream<R> {
    /// An alignment of `tracks` on `grid` over the log `src` (a file, a pipe, a
    /// socket: read in chunks of 64 KiB as the steps are asked for). A bad rate or
    /// tolerance is an error here; a topic the log lacks, at the end of the pass.
    pub fn new(
        src: R,
        grid: &Grid,
        tracks: Vec<Track>,
        options: StreamOptions,
    ) -> Result<AlignStream<R>, AlignError> {
        let steps = match grid {
            Grid::Topic { name, multi_id } => Steps::Topic {
                name: name.clone(),
                multi_id: *multi_id,
                sub: None,
                unwrap: Unwrapper::new(None),
            },
            &Grid::Rate(hz) => {
                if !(hz > 0.0 && hz.is_finite()) {
                    return Err(AlignError::Rate(hz));
                }
                Steps::Rate {
                    period: 1e6 / hz,
                    start: None,
                    next: 0,
                }
            }
        };
        let tracks = tracks
            .into_iter()
            .map(|want| TrackState {
                want,
                layout: None,
                sub: None,
                unwrap: Unwrapper::new(None),
                min_size: 0,
                lerp: Lerp::default(),
                rows: VecDeque::new(),
                msg_id: None,
                max_seen: None,
                closed: false,
                undecided: 0,
                report: TrackReport::default(),
            })
            .collect();
        Ok(AlignStream {
            reader: StreamReader::new(src),
            steps,
            tracks,
            options,
            pending: VecDeque::new(),
            watermark: None,
            jump: None,
            emitted: None,
            ended: false,
            stopped_early: false,
            roles: Vec::new(),
            free: Vec::new(),
            scratch: Vec::new(),
            held_rows: 0,
            held_bytes: 0,
            summary: StreamSummary::default(),
        })
    }

    /// The layout of each topic read, in the order given (to read fields of its rows
    /// with), reading on until every one's format is defined (in the log's
    /// definitions, before its data, as PX4 writes them); an error if the log ends
    /// first.
    pub fn layouts(&mut self) -> Result<Vec<Arc<Layout>>, StreamError> {
        self.find_layouts()?;
        if self.tracks.iter().any(|t| t.layout.is_none()) {
            return Err(self.missing().into());
        }
        Ok(self
            .tracks
            .iter()
            .filter_map(|t| t.layout.clone())
            .collect())
    }

    /// Reads on until every topic's format is defined, or the log ends.
    fn find_layouts(&mut self) -> Result<(), StreamError> {
        loop {
            for tr in &mut self.tracks {
                if tr.layout.is_none() {
                    if let Some(Ok(layout)) = self.reader.state().layout_of(&tr.want.topic) {
                        tr.set_layout(layout);
                    }
                }
            }
            if self.ended || self.tracks.iter().all(|t| t.layout.is_some()) {
                return Ok(());
            }
            self.read_one()?;
        }
    }

    /// The next step, or `None` after the last.
    pub fn next_step(&mut self) -> Result<Option<StreamStep<'_>>, StreamError> {
        // The rows the step handed out last borrowed are let go now: later steps
        // are not before it.
        if let Some(t) = self.emitted {
            self.trim(t);
        }
        let t = loop {
            if let Some(&t) = self.pending.front() {
                if self.decided(t) {
                    break t;
                }
            }
            if self.ended && self.pending.is_empty() {
                // A topic never subscribed is not in the log (its steps so far had it
                // absent, as they would have had before its first row).
                if !self.stopped_early && !self.all_subscribed() {
                    return Err(self.missing().into());
                }
                return Ok(None);
            }
            self.read_one()?;
        };
        self.pending.pop_front();
        self.emitted = Some(t);
        self.summary.steps += 1;
        let by_horizon = !self.ended;
        let tolerance = self.options.align.tolerance_us;
        let mut rows = Vec::with_capacity(self.tracks.len());
        for tr in &mut self.tracks {
            let after = tr.rows.partition_point(|(rt, _)| *rt <= t);
            let before = after.checked_sub(1);
            let after = (after < tr.rows.len()).then_some(after);
            // Counted when a row comes after all (a topic subscribed again).
            if after.is_none() && by_horizon && tr.want.method != Method::Previous {
                tr.undecided += 1;
            }
            let choice = choose(
                tr.want.method,
                tolerance,
                tr.lerp.is_empty(),
                t,
                before.map(|i| tr.rows[i].0),
                after.map(|i| tr.rows[i].0),
            );
            rows.push((choice, before, after));
        }
        let steps = rows
            .into_iter()
            .zip(&self.tracks)
            .map(|((choice, before, after), tr)| {
                let payload = |i: Option<usize>| i.map(|i| tr.rows[i].1.as_slice());
                Some(match choice? {
                    Choice::Before => Row::Logged(payload(before)?),
                    Choice::After => Row::Logged(payload(after)?),
                    Choice::Between(w) => {
                        let (earlier, later) = (payload(before)?, payload(after)?);
                        let mut bytes = Vec::with_capacity(earlier.len());
                        tr.lerp.between(earlier, later, w, &mut bytes);
                        Row::Between { bytes, earlier }
                    }
                })
            })
            .collect();
        Ok(Some(StreamStep {
            time: t,
            rows: steps,
        }))
    }

    /// What the pass met and held so far (after the last step: all of it).
    pub fn summary(&self) -> StreamSummary {
        let mut s = self.summary.clone();
        s.tracks = self.tracks.iter().map(|t| t.report.clone()).collect();
        s.findings = self.reader.state().findings().to_vec();
        s
    }

    /// Whether every topic read (and the grid's) was subscribed.
    fn all_subscribed(&self) -> bool {
        let grid = match &self.steps {
            Steps::Topic { sub, .. } => sub.is_some(),
            Steps::Rate { .. } => true,
        };
        grid && self.tracks.iter().all(|t| t.sub.is_some())
    }

    /// The error for the first topic never subscribed.
    fn missing(&self) -> AlignError {
        let subs = self.reader.state().subscriptions();
        let not_found = |name: &str, n: u8| {
            LookupError::Topic(TopicNotFound::in_subscriptions(subs, name, Some(n)))
        };
        if let Steps::Topic {
            name,
            multi_id,
            sub: None,
            ..
        } = &self.steps
        {
            return AlignError::Lookup(not_found(name, *multi_id));
        }
        match self.tracks.iter().find(|t| t.sub.is_none()) {
            Some(t) => AlignError::Lookup(not_found(&t.want.topic, t.want.multi_id)),
            None => AlignError::Lookup(not_found("", 0)),
        }
    }

    /// Moves the latest step time met on to `t`, unless `t` jumps more than
    /// [`JUMP_US`](crate::read::JUMP_US) ahead of it and the row before did not (the
    /// span's rule: a timestamp of another clock, or garbage, decides no step and makes
    /// no rate's steps).
    fn advance(&mut self, t: u64) {
        match self.watermark {
            Some(w) if t <= w => {}
            Some(w) if t - w > JUMP_US && self.jump.map_or(true, |j| t < j) => {
                self.jump = Some(t);
            }
            _ => {
                self.watermark = Some(t);
                self.jump = None;
            }
        }
    }

    /// Whether step time `t` is in the window.
    fn in_window(&self, t: u64) -> bool {
        let a = &self.options.align;
        let base = self.window_base();
        a.start_us.map_or(true, |s| t >= base.saturating_add(s))
            && a.end_us.map_or(true, |e| t < base.saturating_add(e))
    }

    /// Whether every topic's value at step `t` is decided.
    fn decided(&self, t: u64) -> bool {
        let horizon = self
            .watermark
            .is_some_and(|w| w.saturating_sub(t) > self.options.horizon_us);
        self.ended || horizon || self.tracks.iter().all(|tr| tr.settled(t))
    }

    /// Lets go of each topic's rows before the last one at or before `t`.
    fn trim(&mut self, t: u64) {
        for tr in &mut self.tracks {
            while tr.rows.len() >= 2 && tr.rows[1].0 <= t {
                if let Some((_, p)) = tr.rows.pop_front() {
                    self.held_rows -= 1;
                    self.held_bytes -= p.len();
                    self.free.push(p);
                }
            }
        }
    }

    /// Reads one message and takes what it holds for the alignment.
    fn read_one(&mut self) -> Result<(), StreamError> {
        let Some(m) = self.reader.next_message()? else {
            self.ended = true;
            // A rate's last steps: up to the last row read.
            self.rate_steps();
            return Ok(());
        };
        let offset = m.offset;
        let msg_id = match m.message {
            Message::Data { msg_id, .. } => msg_id,
            Message::Subscribe { msg_id, .. } => {
                // Bound when subscribed, not at the first row: a topic that logs
                // seldom must not hold the steps up until it does.
                if let Some(sub) = self.reader.state().subscription(msg_id).cloned() {
                    // A topic subscribed again (framing keeps it one subscription):
                    // rows are to come again.
                    let roles = self.roles_of(&sub)?;
                    for &k in &roles.tracks {
                        self.tracks[k].closed = false;
                        self.tracks[k].msg_id = Some(msg_id);
                    }
                }
                return Ok(());
            }
            Message::Unsubscribe { msg_id } => {
                // (The reader has let go of the msg_id by now: the tracks know theirs.)
                for tr in &mut self.tracks {
                    if tr.msg_id == Some(msg_id) {
                        tr.closed = true;
                    }
                }
                return Ok(());
            }
            _ => return Ok(()),
        };
        let Some(i) = self.reader.state().subscription(msg_id).map(|s| s.index()) else {
            return Ok(());
        };
        let roles = match self.roles.get(i) {
            Some(Some(roles)) => roles.clone(),
            _ => {
                let Some(sub) = self.reader.state().subscription(msg_id).cloned() else {
                    return Ok(());
                };
                self.roles_of(&sub)?
            }
        };
        if !roles.grid && roles.tracks.is_empty() {
            return Ok(());
        }
        // The payload, out of the reader's buffer (which the next read reuses).
        let mut payload = core::mem::take(&mut self.scratch);
        payload.clear();
        if let Some(Message::Data { payload: p, .. }) =
            self.reader.state().current().map(|m| m.message)
        {
            payload.extend_from_slice(p);
        }
        if roles.grid {
            self.grid_row(offset, &payload);
        }
        for &k in &roles.tracks {
            self.tracks[k].msg_id = Some(msg_id);
            self.tracks[k].closed = false;
            self.track_row(k, offset, &payload);
        }
        self.scratch = payload;
        self.rate_steps();
        if self.pending.is_empty() {
            // No step waits: the rows before the earliest a step still to come may
            // have are let go, and past the window's end the pass stops.
            if let Some(floor) = self.floor() {
                self.trim(floor);
                let end = self.end_us();
                let done = match self.steps {
                    Steps::Topic { .. } => end.is_some_and(|e| floor >= e),
                    Steps::Rate { .. } => {
                        end.is_some_and(|e| self.watermark.is_some_and(|w| w >= e))
                    }
                };
                if done {
                    self.ended = true;
                    self.stopped_early = true;
                }
            }
        }
        Ok(())
    }

    /// The earliest time a step still to come may have: not before the last one
    /// handed out, the window's start, or the pass's clock less the horizon (a grid row
    /// further behind is late).
    fn floor(&self) -> Option<u64> {
        let base = self.window_base();
        let start = self.options.align.start_us.map(|s| base.saturating_add(s));
        let clock = self
            .watermark
            .filter(|_| self.options.horizon_us != u64::MAX)
            .map(|w| w.saturating_sub(self.options.horizon_us));
        [self.emitted, start, clock].into_iter().flatten().max()
    }

    /// The window's end as a boot time, if it has one.
    fn end_us(&self) -> Option<u64> {
        let base = self.window_base();
        self.options.align.end_us.map(|e| base.saturating_add(e))
    }

    /// What the window's times count from: the header's start, or boot.
    fn window_base(&self) -> u64 {
        match self.options.window_from_start {
            true => self.reader.state().header().map_or(0, |h| h.timestamp),
            false => 0,
        }
    }

    /// What subscription `sub` is to the alignment, bound when first met.
    fn roles_of(&mut self, sub: &Arc<Subscription>) -> Result<Arc<Roles>, AlignError> {
        let i = sub.index();
        if let Some(Some(roles)) = self.roles.get(i) {
            return Ok(roles.clone());
        }
        let roles = Arc::new(self.bind(sub)?);
        if self.roles.len() <= i {
            self.roles.resize(i + 1, None);
        }
        self.roles[i] = Some(roles.clone());
        Ok(roles)
    }

    /// Binds the grid and tracks that subscription `sub` is (by topic name and
    /// instance; a later subscription of the same topic instance in another format is
    /// none of them).
    fn bind(&mut self, sub: &Arc<Subscription>) -> Result<Roles, AlignError> {
        let mut roles = Roles::default();
        let same_format = |bound: &Option<Arc<Subscription>>| match bound {
            None => true,
            Some(b) => match (b.layout(), sub.layout()) {
                (Ok(x), Ok(y)) => Arc::ptr_eq(x, y) || x == y,
                _ => false,
            },
        };
        if let Steps::Topic {
            name,
            multi_id,
            sub: bound,
            unwrap,
        } = &mut self.steps
        {
            if sub.name() == name && sub.multi_id() == *multi_id && same_format(bound) {
                if bound.is_none() {
                    let Some(ts) = sub.timestamp_field() else {
                        return Err(AlignError::NoTimestamp(name.clone()));
                    };
                    *unwrap = Unwrapper::new(Some(ts));
                    *bound = Some(sub.clone());
                }
                roles.grid = true;
            }
        }
        for (k, tr) in self.tracks.iter_mut().enumerate() {
            if sub.name() != tr.want.topic || sub.multi_id() != tr.want.multi_id {
                continue;
            }
            let layout = match sub.layout() {
                Ok(l) => l,
                // A subscription of the topic that cannot be laid out: an error if it
                // is the first, else rows of another format, left out.
                Err(e) if tr.sub.is_none() => {
                    return Err(AlignError::Lookup(LookupError::layout(sub, e)));
                }
                Err(_) => continue,
            };
            match &tr.layout {
                None => tr.set_layout(layout.clone()),
                Some(l) if Arc::ptr_eq(l, layout) || **l == **layout => {}
                Some(_) => continue,
            }
            tr.sub.get_or_insert_with(|| sub.clone());
            tr.closed = false;
            tr.msg_id = Some(sub.msg_id());
            roles.tracks.push(k);
        }
        Ok(roles)
    }

    /// A row of the grid topic: a step at its time (in the window).
    fn grid_row(&mut self, offset: u64, payload: &[u8]) {
        // Every row with a timestamp is a step, as in the indexed alignment.
        let Steps::Topic { unwrap, .. } = &mut self.steps else {
            return;
        };
        let Some(t) = unwrap.push(payload) else {
            return;
        };
        // A step more than the horizon behind the pass: its topics' rows may be gone.
        let behind = self
            .watermark
            .is_some_and(|w| w.saturating_sub(t) > self.options.horizon_us);
        self.advance(t);
        if !self.in_window(t) {
            return;
        }
        if behind || self.emitted.is_some_and(|e| t < e) {
            self.summary.late_steps += 1;
            self.summary.first_late_step_offset.get_or_insert(offset);
            return;
        }
        let at = self.pending.partition_point(|&p| p <= t);
        self.pending.insert(at, t);
        self.summary.pending_peak = self.summary.pending_peak.max(self.pending.len());
    }

    /// A row of track `k`: held in time order.
    fn track_row(&mut self, k: usize, offset: u64, payload: &[u8]) {
        let tr = &mut self.tracks[k];
        if payload.len() < tr.min_size {
            tr.report.left_out += 1;
            return;
        }
        let Some(t) = tr.unwrap.push(payload) else {
            tr.report.left_out += 1;
            return;
        };
        // Where it goes among the rows held (after those of equal time), and the
        // time of the row before it there.
        let at = tr.rows.partition_point(|(rt, _)| *rt <= t);
        let before = at.checked_sub(1).map(|i| tr.rows[i].0);
        let goes_back = tr.max_seen.is_some_and(|m| t < m);
        // A step handed out at or after its time did not see it; nor, for a row that
        // comes back in time, did a step handed out after the row before it (its
        // nearest or next row may have been this one).
        let missed = self
            .emitted
            .is_some_and(|e| t <= e || goes_back && before.map_or(true, |b| e > b));
        if missed {
            tr.report.late_rows += 1;
            tr.report.first_late_offset.get_or_insert(offset);
        }
        tr.max_seen = Some(tr.max_seen.map_or(t, |m| m.max(t)));
        tr.report.early_steps += core::mem::take(&mut tr.undecided);
        let mut buf = self.free.pop().unwrap_or_default();
        buf.clear();
        buf.extend_from_slice(payload);
        self.held_rows += 1;
        self.held_bytes += buf.len();
        tr.rows.insert(at, (t, buf));
        tr.report.held_rows_peak = tr.report.held_rows_peak.max(tr.rows.len());
        // Every topic's rows move the pass's clock on, the grid's and the others'.
        self.advance(t);
        self.summary.held_rows_peak = self.summary.held_rows_peak.max(self.held_rows);
        self.summary.held_bytes_peak = self.summary.held_bytes_peak.max(self.held_bytes);
    }

    /// A rate's steps up to the latest row read (all of them at the end).
    fn rate_steps(&mut self) {
        let Steps::Rate {
            period,
            start,
            next,
        } = &mut self.steps
        else {
            return;
        };
        let Some(w) = self.watermark else { return };
        let s = *start.get_or_insert_with(|| {
            match self.reader.state().header().map(|h| h.timestamp) {
                Some(t) if t > 0 => t,
                // A header without a time: the first row read.
                _ => w,
            }
        });
        let mut steps = Vec::new();
        loop {
            let t = s + (*next as f64 * *period).round() as u64;
            if t > w {
                break;
            }
            *next += 1;
            steps.push(t);
        }
        for t in steps {
            if self.in_window(t) {
                self.pending.push_back(t);
            }
        }
        self.summary.pending_peak = self.summary.pending_peak.max(self.pending.len());
    }
}

/// A one-pass alignment of a struct of topics ([`Aligned`], `#[derive(Aligned)]`):
/// each step the struct, each field its topic's value by its method, decoded by its
/// binding. The fields' bindings are checked against the log's formats once, before
/// the first step, every field that does not fit reported together.
///
/// The topics are the bindings' names (their aliases are not tried: a pass cannot
/// look for a topic again).
///
/// ```
/// # #[cfg(feature = "derive")] {
/// use ulog_core::align::{Aligned, AlignedStream, Grid, StreamOptions};
/// use ulog_core::ULogMessage;
///
/// #[derive(ULogMessage)]
/// # #[ulog(crate = "ulog_core")]
/// struct VehicleAttitude { timestamp: u64, q: [f32; 4] }
/// #[derive(ULogMessage)]
/// # #[ulog(crate = "ulog_core")]
/// struct BatteryStatus { timestamp: u64, voltage_v: f32 }
///
/// #[derive(Aligned)]
/// # #[ulog(crate = "ulog_core")]
/// struct Now {
///     attitude: Option<VehicleAttitude>,
///     #[ulog(method = "linear")]
///     battery: Option<BatteryStatus>,
/// }
///
/// # let bytes = ulog_core::testing::sample_log();
/// let grid = Grid::topic("vehicle_attitude", 0);
/// let mut steps = AlignedStream::<_, Now>::new(&bytes[..], &grid, StreamOptions::default())?;
/// while let Some((t, now)) = steps.next_step()? {
///     assert_eq!(now.attitude.unwrap().timestamp, t);
///     if let Some(b) = now.battery {
///         assert!(b.voltage_v > 10.0);
///     }
/// }
/// # }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct AlignedStream<R, S> {
    stream: AlignStream<R>,
    decode: super::aligned::__Decode<S>,
}

impl<R: Read, S: Aligned> AlignedStream<R, S> {
    /// The steps of `grid` over the log `src`, as structs `S`: reads the log's
    /// definitions and checks every field's binding against its topic's format.
    pub fn new(src: R, grid: &Grid, options: StreamOptions) -> Result<Self, StreamError> {
        let tracks = S::FIELDS
            .iter()
            .map(|f| Track::new(f.topic, f.multi_id, f.method))
            .collect();
        let mut stream = AlignStream::new(src, grid, tracks, options)?;
        stream.find_layouts()?;
        let subs = stream.reader.state().subscriptions();
        let layouts: Vec<Result<Arc<Layout>, TypedError>> = stream
            .tracks
            .iter()
            .map(|t| match &t.layout {
                Some(l) => Ok(l.clone()),
                None => {
                    let missing =
                        TopicNotFound::in_subscriptions(subs, &t.want.topic, Some(t.want.multi_id));
                    let kind = TypedErrorKind::NotFound {
                        missing,
                        binding: None,
                        named_after_struct: false,
                    };
                    Err(TypedError::new(kind, None, None))
                }
            })
            .collect();
        let decode = S::__decoder(&layouts).map_err(StreamError::Aligned)?;
        Ok(AlignedStream { stream, decode })
    }

    /// The next step's time and struct, or `None` after the last.
    pub fn next_step(&mut self) -> Result<Option<(u64, S)>, StreamError> {
        let decode = &self.decode;
        Ok(self
            .stream
            .next_step()?
            .map(|step| (step.time, decode(&step.rows))))
    }

    /// What the pass met and held so far ([`AlignStream::summary`]).
    pub fn summary(&self) -> StreamSummary {
        self.stream.summary()
    }
}
