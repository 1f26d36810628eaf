//! The export of a whole log in one pass over its bytes: each data message's row is
//! copied into its topic's buffer as the pass goes by, and a buffer is written out as
//! a row group when it is full, or when the rows held by all topics together pass
//! [`Options::buffer_bytes`] (the largest buffer goes first). The memory is then that
//! budget and the row groups being written, whatever the size of the log; the log is
//! read once, in file order, from any [`Source`].
//!
//! Row groups are written on [`Options::threads`] threads while the pass goes on; a
//! topic's row groups are written in the order they were cut, whichever thread
//! encodes them, so the files do not depend on the number of threads.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{sync_channel, Receiver};
use std::sync::{Arc, Condvar, Mutex};

use crate::access::lookup::{LookupError, TopicNotFound};
use crate::definitions::Subscription;
use crate::log::ulog::ULog;
use crate::log::utc::UtcClock;
use crate::pass::source::{drive_keeping, Source};
use crate::pass::visit::Hand;

use super::arrow::TopicTable;
use super::error::{ExportError, ExportErrorKind};
use super::files::{
    leaves, properties, write_error, Export, Skipped, Written, ROW_GROUP_BYTES, WIDE_LEAVES,
};
use super::lazy_file::LazyFile;
use super::leaves::LeafWriter;
use super::lock::partial_name;
use super::metadata::{json, Facts};
use super::rows::Rows;
use super::{name_of, Options, METADATA_FILE};

type Result<T, E = ExportError> = core::result::Result<T, E>;

/// The smallest row group cut when the rows held pass the budget; fewer rows are put
/// aside in a file instead, until they make one. On the two ≈300 MB logs (zstd), 1, 2,
/// 4, 8 and 16 MiB gave files 1.48/1.22, 1.30/1.13, 1.16/1.08, 1.09/1.04 and 1.04/1.02
/// times flight-review-rs's size, and peaks of 122/124, 139/152, 163/168, 271/221 and
/// 282/299 MB, when a topic's rows were one growing buffer, not blocks (the larger row
/// groups came with more memory held by the allocator; see bench/README.md).
const MIN_GROUP_BYTES: usize = 4 << 20;

/// Bytes of the log framed between two calls of the progress callback.
const PROGRESS_STEP: u64 = 8 << 20;

/// A topic instance's Parquet file (in a dataset, a topic's: its instances share
/// it), written one row group at a time in the order the groups were cut (`next`: the
/// number of the group whose turn it is).
struct TopicFile {
    /// Where it is written until the export is done.
    partial: PathBuf,
    /// The file errors name: where it goes when the export is done (but for a second
    /// subscription of one name and instance, named after its msg_id at the end).
    shown: PathBuf,
    state: Mutex<FileState>,
    turn: Condvar,
    /// Row groups cut for it so far (by the pass, or after it for wide tables).
    cut: std::sync::atomic::AtomicU64,
}

struct FileState {
    writer: Option<LeafWriter<BufWriter<LazyFile>>>,
    next: u64,
}

/// A row group to write: `rows` holds its rows, [`TopicTable::needed`] bytes each (one
/// byte, unread, for a table whose columns read none: `char[0]` fields).
struct Group {
    table: Arc<TopicTable>,
    file: Arc<TopicFile>,
    number: u64,
    rows: Rows,
}

/// A topic instance with data, as the pass meets it.
enum Slot {
    /// Not met yet.
    Unseen,
    /// Not among [`Options::topics`].
    Unselected,
    /// Cannot be exported (listed in [`Export::skipped`]).
    Skipped,
    /// Being exported.
    Open(Box<Open>),
}

struct Open {
    /// The topic instance (the table of a wide one is built from it when written).
    sub: Subscription,
    /// The table, but for wide tables (built again when they are written: it holds
    /// some hundred bytes per column).
    table: Option<Arc<TopicTable>>,
    /// The bytes of each row the columns read ([`TopicTable::needed`]).
    needed: usize,
    file: Arc<TopicFile>,
    /// Rows held, after those in `spill`.
    buffer: Rows,
    /// Rows put aside in a file when the rows held by all topics passed the budget
    /// and this topic, holding the most, had too few for a row group of
    /// [`MIN_GROUP_BYTES`]; they come before `buffer`'s, and the next row group is cut
    /// from both (small row groups compress worse: see [`MIN_GROUP_BYTES`]).
    spill: Spill,
    /// A wide table (more than [`WIDE_LEAVES`] leaf columns): all its rows go to the
    /// spill file, written out as Parquet after the pass, one wide table at a time
    /// (see [`write_wide`]).
    wide: bool,
    /// Bytes of a full row group.
    group_bytes: usize,
}

/// Where the pass writes.
pub(super) enum Layout<'a, T> {
    /// A log's folder: `<topic>_<multi_id>.parquet` per topic instance and
    /// [`METADATA_FILE`].
    Log,
    /// A dataset: `<topic>/<log_id>.parquet` per topic ([`Options::log_id`]), its
    /// instances in one file; the log's own rows of the dataset's tables are made by
    /// the function (from the log kept without its data, what the pass learnt of the
    /// data, and the log's UTC clock) and returned, not written.
    Dataset(&'a TablesOf<'a, T>),
}

/// What makes a log's rows of a dataset's tables ([`Layout::Dataset`]).
pub(super) type TablesOf<'a, T> = dyn Fn(&ULog<'_>, &Facts<'_>, Option<UtcClock>) -> Result<T> + 'a;

/// Writes a log to `dir` (created when missing): every selected topic instance with
/// data to its own Parquet file, named by [`super::file_name`], and the metadata file
/// [`METADATA_FILE`](super::METADATA_FILE). Files of those names already there are replaced; other files in
/// `dir` are left as they are.
///
/// The log is read once, in file order, from any [`Source`]: a file or reader
/// ([`Source::file`], [`Source::reader`]) is read in chunks and never held whole;
/// each topic's rows are held until a row group of them is full (16 MiB of payload or
/// [`Options::row_group_rows`]), or until the rows held by all topics pass
/// [`Options::buffer_bytes`], when the topic holding the most is written out. Row
/// groups are encoded on [`Options::threads`] threads while the log is read, each
/// topic's in the order they were cut: the files are the same whatever the source
/// and the number of threads.
///
/// A topic whose format cannot be laid out, or that has no field with values, is left
/// out and listed in [`Export::skipped`]. Errors: a log that cannot be read, a topic
/// of [`Options::topics`] that is not in the log (unless
/// [`Options::skip_missing_topics`]), and failures to write. Files are written under
/// temporary names of this export's own and renamed when the whole log is done: after
/// an error, no file of this export is left in `dir` (a file of the same name that a
/// rename had already replaced is gone too), and the folders it made are removed when
/// empty. Two exports of a log into one folder at once do not share a temporary file:
/// each file is whole, from one or the other.
///
/// ```
/// use ulog_core::export::{self, Options};
/// let bytes = ulog_core::testing::sample_log();
/// let dir = std::env::temp_dir().join(format!("ulog-doc-{}", std::process::id()));
/// let written = export::write_parquet(&bytes, &dir, &Options::default())?;
/// assert!(written.files.iter().any(|f| f.path.ends_with("battery_status_1.parquet")));
/// assert!(written.metadata.ends_with("metadata.json"));
/// # std::fs::remove_dir_all(&dir).unwrap();
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_parquet<'s>(
    source: impl Into<Source<'s>>,
    dir: &Path,
    options: &Options,
) -> Result<Export> {
    export::<()>(source.into(), dir, options, Layout::Log, |_| {}).map(|(e, _)| e)
}

/// [`write_parquet`], calling `progress` with the byte offset in the log that the pass
/// has reached, every 8 MiB or so (to show progress; the bytes after the last call are
/// read too, without one).
pub fn write_parquet_with<'s>(
    source: impl Into<Source<'s>>,
    dir: &Path,
    options: &Options,
    progress: impl FnMut(u64),
) -> Result<Export> {
    export::<()>(source.into(), dir, options, Layout::Log, progress).map(|(e, _)| e)
}

/// Writes the log of `source` to `dir` (see [`write_parquet`]).
pub(super) fn export<T>(
    source: Source<'_>,
    dir: &Path,
    options: &Options,
    layout: Layout<'_, T>,
    mut progress: impl FnMut(u64),
) -> Result<(Export, Option<T>)> {
    let dataset = match layout {
        Layout::Dataset(tables) => Some(tables),
        Layout::Log => None,
    };
    // The folders this export makes, innermost first: removed again after an error.
    let made: Vec<PathBuf> = dir
        .ancestors()
        .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
        .map(Path::to_owned)
        .collect();
    std::fs::create_dir_all(dir).map_err(|e| ExportError::io(e, dir))?;
    let failure: Mutex<Option<ExportError>> = Mutex::new(None);
    let failed = AtomicBool::new(false);
    let fail = |e: ExportError| {
        let mut first = failure.lock().unwrap_or_else(|p| p.into_inner());
        first.get_or_insert(e);
        failed.store(true, Ordering::Relaxed);
    };
    let write = |group: Group| {
        if let Err(e) = write_group(group, options) {
            fail(e);
        }
    };

    let mut slots: Vec<Slot> = Vec::new();
    // A dataset's files, by topic name (its instances share one).
    let mut files: HashMap<PathBuf, (String, Arc<TopicFile>)> = HashMap::new();
    let mut rows: Vec<usize> = Vec::new();
    let mut skipped = Vec::new();
    let mut buffered = 0usize;
    let budget = options.buffer_bytes.max(1);
    let mut reported = 0u64;

    // A dataset's log is analysed in the same pass, for its tables of diagnostics and
    // flight statistics (the spectra and step responses are left to `ulog analyze`).
    let mut analyzer = dataset.is_some().then(|| {
        crate::analysis::FlightAnalyzer::new(
            &crate::analysis::AnalyzeOptions::default()
                .spectra(false)
                .step_response(false),
        )
    });
    let threads = options.threads.max(1);
    // One group waits for a free thread: the pass goes on while the threads are busy
    // (handing over only to a free thread was 0.92x as fast on 2 cores, for the same
    // peak memory: BENCHMARKS.md).
    let (send, receive) = sync_channel::<Group>(1);
    let receive = Mutex::new(receive);
    let scanned = std::thread::scope(|s| {
        let mut workers = Vec::new();
        if threads > 1 {
            for _ in 0..threads {
                let receive = &receive;
                let write = &write;
                let worker = std::thread::Builder::new()
                    .name("ulog parquet".to_owned())
                    .spawn_scoped(s, move || take_groups(receive, write));
                match worker {
                    Ok(w) => workers.push(w),
                    // Fewer threads: the groups are written by those there are, or
                    // on this thread.
                    Err(_) => break,
                }
            }
        }
        let to_workers = |group: Group| {
            if let Err(std::sync::mpsc::SendError(group)) = send.send(group) {
                write(group);
            }
        };
        let hand: &dyn Fn(Group) = if workers.is_empty() {
            &write
        } else {
            &to_workers
        };
        // A row group of the rows put aside and those held.
        let cut = |slot: &mut Open, buffered: &mut usize| {
            *buffered -= slot.buffer.bytes();
            let held = slot.buffer.take();
            let rows = match slot.spill.take(held.stride()) {
                Ok(mut rows) if !rows.is_empty() => {
                    rows.append(held);
                    rows
                }
                Ok(_) => held,
                Err(e) => return fail(e),
            };
            let Some(table) = &slot.table else {
                return;
            };
            hand(Group {
                table: table.clone(),
                file: slot.file.clone(),
                number: slot.file.cut.fetch_add(1, Ordering::Relaxed),
                rows,
            });
        };
        // The rows held, put aside.
        let put_aside = |slot: &mut Open, buffered: &mut usize| {
            *buffered -= slot.buffer.bytes();
            // Their memory goes too: the budget counts the rows held.
            let held = slot.buffer.take();
            if let Err(e) = slot.spill.append(&held) {
                fail(e);
            }
        };
        // Everything but the data kept as the pass goes (a log of its own, with the
        // times, GPS times and events the data gives it).
        let result = drive_keeping(source, true, &[], None, &mut |r: crate::DataRecord<'_>| {
            let i = r.topic.index();
            if slots.len() <= i {
                slots.resize_with(i + 1, || Slot::Unseen);
                rows.resize(i + 1, 0);
            }
            if matches!(slots[i], Slot::Unseen) {
                slots[i] = open(
                    r.topic,
                    dir,
                    options,
                    dataset.is_some(),
                    &mut files,
                    &mut skipped,
                );
            }
            rows[i] += 1;
            if let Some(a) = analyzer.as_mut() {
                a.push(r.topic, r.payload);
            }
            if r.offset >= reported + PROGRESS_STEP {
                reported = r.offset;
                progress(reported);
            }
            let Slot::Open(slot) = &mut slots[i] else {
                return Hand::Next;
            };
            let needed = slot.needed;
            let Some(row) = r.payload.get(..needed) else {
                fail(
                    ExportError::new(ExportErrorKind::ShortPayload {
                        topic: slot.sub.name().to_owned(),
                        needed,
                        found: r.payload.len(),
                    })
                    .at(r.offset),
                );
                return Hand::Stop;
            };
            slot.buffer.push(if needed == 0 { &[0] } else { row });
            buffered += needed.max(1);
            if slot.wide {
                if slot.buffer.bytes() >= slot.group_bytes {
                    put_aside(slot, &mut buffered);
                }
            } else if slot.buffer.bytes() + slot.spill.bytes >= slot.group_bytes {
                cut(slot, &mut buffered);
            }
            if buffered > budget {
                let largest = slots
                    .iter_mut()
                    .filter_map(|s| match s {
                        Slot::Open(o) => Some(o),
                        _ => None,
                    })
                    .max_by_key(|o| o.buffer.bytes());
                if let Some(slot) = largest {
                    let enough = MIN_GROUP_BYTES.min(slot.group_bytes);
                    if !slot.wide && slot.buffer.bytes() + slot.spill.bytes >= enough {
                        cut(slot, &mut buffered);
                    } else {
                        put_aside(slot, &mut buffered);
                    }
                }
            }
            if failed.load(Ordering::Relaxed) {
                Hand::Stop
            } else {
                Hand::Next
            }
        });
        if result.is_ok() && !failed.load(Ordering::Relaxed) {
            for slot in &mut slots {
                if let Slot::Open(slot) = slot {
                    if slot.wide {
                        put_aside(slot, &mut buffered);
                    } else if !slot.buffer.is_empty() || slot.spill.bytes > 0 {
                        cut(slot, &mut buffered);
                    }
                }
            }
        }
        drop(send);
        crate::parallel::join_all(workers);
        result
    });

    let opened: Vec<&mut Open> = slots
        .iter_mut()
        .filter_map(|s| match s {
            Slot::Open(o) => Some(&mut **o),
            _ => None,
        })
        .collect();
    let mut opened = opened;
    let metadata = match dataset {
        Some(_) => dir.join(super::LOGS_FILE),
        None => dir.join(METADATA_FILE),
    };
    let metadata_partial = dir.join(partial_name(METADATA_FILE));
    let done = (|| {
        let summary = scanned.map_err(ExportError::read)?;
        if let Some(e) = failure.lock().unwrap_or_else(|p| p.into_inner()).take() {
            return Err(e);
        }
        // A file's footer once the last of its tables is in (in a dataset, a topic's
        // instances share the file), and right then: a wide table's writer holds
        // hundreds of MB of column metadata until its footer.
        for i in 0..opened.len() {
            write_wide(opened[i], options)?;
            // Made only by topics that put rows aside.
            let _ = std::fs::remove_file(&opened[i].spill.path);
            if !opened[i + 1..]
                .iter()
                .any(|o| Arc::ptr_eq(&o.file, &opened[i].file))
            {
                close(&opened[i].file)?;
            }
        }
        // Everything but the data, as a log of its own.
        let Some(kept) = &summary.metadata else {
            unreachable!("a keeping pass keeps the metadata")
        };
        let log = kept.log().map_err(ExportError::read)?;
        let missing = missing_topics(&log, options)?;
        rows.resize(log.subscriptions().len(), 0);
        #[cfg(feature = "events")]
        let events = log
            .topic("event", 0)
            .ok()
            .map(|_| kept.events(&crate::events::EventOptions::default()));
        let flight = analyzer.take().map(|a| a.finish());
        let facts = Facts {
            last_timestamp: kept.last_timestamp(),
            findings: &summary.findings,
            rows: &rows[..log.subscriptions().len()],
            #[cfg(feature = "events")]
            events: events.as_ref(),
            flight: flight.as_ref(),
        };
        let tables = match dataset {
            Some(tables_of) => Some(tables_of(&log, &facts, kept.utc())?),
            None => {
                std::fs::write(&metadata_partial, json(&log, &facts))
                    .map_err(|e| ExportError::io(e, &metadata))?;
                None
            }
        };
        let files = rename(&opened, &rows, dir, dataset.is_some())?;
        if dataset.is_none() {
            if let Err(e) = std::fs::rename(&metadata_partial, &metadata) {
                for done in &files {
                    let _ = std::fs::remove_file(&done.path);
                }
                return Err(ExportError::io(e, &metadata));
            }
        }
        skipped.sort_by(|a: &Skipped, b: &Skipped| {
            (&a.topic, a.multi_id).cmp(&(&b.topic, b.multi_id))
        });
        let export = Export {
            files,
            skipped: std::mem::take(&mut skipped),
            missing_topics: missing,
            metadata,
        };
        Ok((export, tables))
    })();
    if done.is_err() {
        let _ = std::fs::remove_file(&metadata_partial);
        for slot in &opened {
            let _ = std::fs::remove_file(&slot.file.partial);
            let _ = std::fs::remove_file(&slot.spill.path);
        }
        // A dataset's topic folders stay, empty or not: another log being added at
        // the same time may be about to write into one.
        for folder in &made {
            // Only when nothing else came into it meanwhile.
            let _ = std::fs::remove_dir(folder);
        }
    }
    done
}

/// What the pass does with a topic instance met for the first time; in a dataset
/// (`dataset`), its file is that of its topic in `files`, made on first use.
fn open(
    sub: &Subscription,
    dir: &Path,
    options: &Options,
    dataset: bool,
    files: &mut HashMap<PathBuf, (String, Arc<TopicFile>)>,
    skipped: &mut Vec<Skipped>,
) -> Slot {
    if let Some(names) = &options.topics {
        if !names.iter().any(|n| n == sub.name()) {
            return Slot::Unselected;
        }
    }
    let table = match TopicTable::new(sub, options).and_then(|t| {
        if t.schema.fields().is_empty() {
            Err(ExportError::new(ExportErrorKind::NoValues {
                topic: sub.name().to_owned(),
            })
            .at(sub.offset()))
        } else {
            Ok(t)
        }
    }) {
        Ok(table) => table,
        Err(error) => {
            skipped.push(Skipped {
                topic: sub.name().to_owned(),
                multi_id: sub.multi_id(),
                error,
            });
            return Slot::Skipped;
        }
    };
    let wide = leaves(table.schema.fields()) > WIDE_LEAVES;
    let row_size = sub.layout().map_or(1, |l| l.size().max(1));
    let group_rows = options
        .row_group_rows
        .clamp(1, (ROW_GROUP_BYTES / row_size).max(1));
    // A dataset's files: `<topic>/<log_id>.parquet`, the folder named by the naming
    // rule; a log's: `<topic>_<multi_id>.parquet`, named when the pass is done (the
    // rule looks at all its topics' names), written meanwhile under the folder name.
    let folder_name = crate::naming::folder_name(sub.name());
    let (folder, stem) = match (&options.log_id, dataset) {
        (Some(log_id), true) => (dir.join(folder_name.as_ref()), log_id.clone()),
        _ => (
            dir.to_owned(),
            name_of(&folder_name, sub.multi_id())
                .trim_end_matches(".parquet")
                .to_owned(),
        ),
    };
    let new_file = || {
        Arc::new(TopicFile {
            partial: folder.join(partial_name(&format!("{stem}.parquet"))),
            shown: folder.join(format!("{stem}.parquet")),
            state: Mutex::new(FileState {
                writer: None,
                next: 0,
            }),
            turn: Condvar::new(),
            cut: Default::default(),
        })
    };
    let file = if dataset {
        if let Err(error) = std::fs::create_dir_all(&folder) {
            skipped.push(Skipped {
                topic: sub.name().to_owned(),
                multi_id: sub.multi_id(),
                error: ExportError::io(error, &folder),
            });
            return Slot::Skipped;
        }
        let (name, file) = files
            .entry(folder.clone())
            .or_insert_with(|| (sub.name().to_owned(), new_file()));
        if name != sub.name() {
            // Two names of one hash (the naming rule makes every other pair distinct).
            skipped.push(Skipped {
                topic: sub.name().to_owned(),
                multi_id: sub.multi_id(),
                error: ExportError::new(ExportErrorKind::Dataset {
                    what: format!(
                        "topics `{name}` and `{}` would share the folder {}",
                        sub.name(),
                        folder.display()
                    ),
                }),
            });
            return Slot::Skipped;
        }
        file.clone()
    } else {
        new_file()
    };
    Slot::Open(Box::new(Open {
        sub: sub.clone(),
        group_bytes: group_rows * table.needed().max(1),
        needed: table.needed(),
        buffer: Rows::new(table.needed()),
        table: (!wide).then(|| Arc::new(table)),
        file,
        spill: Spill {
            path: folder.join(partial_name(&format!("{stem}.{}.rows", sub.index()))),
            file: None,
            bytes: 0,
        },
        wide,
    }))
}

/// A writing thread: takes groups until the pass hangs up.
fn take_groups(receive: &Mutex<Receiver<Group>>, write: &(dyn Fn(Group) + Sync)) {
    loop {
        let group = {
            let receive = receive.lock().unwrap_or_else(|p| p.into_inner());
            receive.recv()
        };
        match group {
            Ok(group) => write(group),
            Err(_) => return,
        }
    }
}

/// Encodes a row group and appends it to its file, once the groups before it are in:
/// column by column, so that it holds its rows and one column's values.
fn write_group(group: Group, options: &Options) -> Result<()> {
    let Group {
        table,
        file,
        number,
        rows,
    } = group;
    let mut turn = Turn::wait(&file, number);
    let writer = match &mut turn.state.writer {
        Some(w) => w,
        None => {
            let schema = Arc::new(arrow_schema::Schema::new(table.schema.fields().clone()));
            let out = BufWriter::with_capacity(FILE_BUFFER, LazyFile::new(file.partial.clone()));
            let w = LeafWriter::try_new(out, schema, properties(&table, options))
                .map_err(|e| write_error(&file.shown, e))?;
            turn.state.writer.insert(w)
        }
    };
    // The rows were cut to the bytes the columns need: none is short.
    writer
        .write_columns(rows.len(), |i| {
            table
                .column_of_rows(i, &rows)
                .map_err(|e| parquet::errors::ParquetError::External(Box::new(e)))
        })
        .map_err(|e| write_error(&file.shown, e))?;
    // The file is closed until its next group.
    let out = writer.out_mut();
    out.flush().map_err(|e| ExportError::io(e, &file.shown))?;
    out.get_mut().release();
    Ok(())
}

/// A file's turn: held from when the groups before this one are in until it is
/// dropped, which gives the turn to the next group, after a failure or a panic too
/// (the export then fails as a whole; its threads must not wait for ever).
struct Turn<'f> {
    file: &'f TopicFile,
    state: std::sync::MutexGuard<'f, FileState>,
}

impl<'f> Turn<'f> {
    fn wait(file: &'f TopicFile, number: u64) -> Turn<'f> {
        let mut state = file.state.lock().unwrap_or_else(|p| p.into_inner());
        while state.next != number {
            state = file.turn.wait(state).unwrap_or_else(|p| p.into_inner());
        }
        Turn { file, state }
    }
}

impl Drop for Turn<'_> {
    fn drop(&mut self) {
        self.state.next += 1;
        self.file.turn.notify_all();
    }
}

/// The write buffer of each file being written.
const FILE_BUFFER: usize = 64 << 10;

/// Writes a file's footer.
fn close(file: &TopicFile) -> Result<()> {
    let writer = file
        .state
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .writer
        .take();
    match writer {
        Some(w) => w.close().map_err(|e| write_error(&file.shown, e)),
        None => Ok(()),
    }
}

/// The names of [`Options::topics`] that the log does not have: an error, unless
/// [`Options::skip_missing_topics`] and the log has some of them.
fn missing_topics(log: &ULog<'_>, options: &Options) -> Result<Vec<LookupError>> {
    let Some(names) = &options.topics else {
        return Ok(Vec::new());
    };
    let missing: Vec<LookupError> = names
        .iter()
        .filter(|n| log.subscriptions().iter().all(|s| s.name() != n.as_str()))
        .map(|n| LookupError::Topic(TopicNotFound::in_log(log, n, None)))
        .collect();
    match missing.first() {
        Some(first) if !options.skip_missing_topics || missing.len() == names.len() => {
            Err(first.clone().into())
        }
        _ => Ok(missing),
    }
}

/// Gives the files their names (sorted by topic name and instance; a second
/// subscription of one name and instance gets its msg_id in its name); `rows` is each
/// subscription's rows. In a dataset (`dataset`), a topic's instances share their file,
/// which is named once and counts the rows of all.
fn rename(opened: &[&mut Open], rows: &[usize], dir: &Path, dataset: bool) -> Result<Vec<Written>> {
    let mut order: Vec<&Open> = opened.iter().map(|o| &**o).collect();
    fn key(o: &Open) -> (&str, u8, usize) {
        (o.sub.name(), o.sub.multi_id(), o.sub.index())
    }
    order.sort_by(|a, b| key(a).cmp(&key(b)));
    let mut names = std::collections::HashSet::new();
    let parts = crate::naming::LogNames::new(order.iter().map(|o| o.sub.name()));
    let mut files: Vec<Written> = Vec::with_capacity(order.len());
    for slot in order {
        if dataset {
            if let Some(last) = files.last_mut() {
                if last.path == slot.file.shown {
                    last.rows += rows[slot.sub.index()];
                    continue;
                }
            }
        }
        let path = if dataset {
            slot.file.shown.clone()
        } else {
            let mut name = name_of(&parts.file_part(slot.sub.name()), slot.sub.multi_id());
            if !names.insert(name.clone()) {
                name = format!(
                    "{}_msg{}.parquet",
                    name.trim_end_matches(".parquet"),
                    slot.sub.msg_id()
                );
                names.insert(name.clone());
            }
            dir.join(name)
        };
        if let Err(e) = std::fs::rename(&slot.file.partial, &path) {
            // None of this export's files is left.
            for done in &files {
                let _ = std::fs::remove_file(&done.path);
            }
            return Err(ExportError::io(e, &path));
        }
        files.push(Written {
            topic: slot.sub.name().to_owned(),
            multi_id: slot.sub.multi_id(),
            path,
            rows: rows[slot.sub.index()],
        });
    }
    Ok(files)
}

/// Rows put aside in a file during the pass (the file is made when rows first come,
/// and emptied when they are taken back).
///
/// The rows of a wide table all go there: the Parquet writer of a wide table holds
/// some kilobytes of metadata per leaf column until its footer (about 240 MB for the
/// widest format, 65,535 one-byte fields), so wide tables are written one at a time,
/// after the pass, and not all held open while it goes on.
struct Spill {
    path: PathBuf,
    file: Option<BufWriter<LazyFile>>,
    /// Bytes in the file.
    bytes: usize,
}

impl Spill {
    fn append(&mut self, rows: &Rows) -> Result<()> {
        if rows.is_empty() {
            return Ok(());
        }
        let path = &self.path;
        let file = self.file.get_or_insert_with(|| {
            BufWriter::with_capacity(FILE_BUFFER, LazyFile::new(path.clone()))
        });
        rows.blocks()
            .try_for_each(|b| file.write_all(b))
            .and_then(|()| file.flush())
            .map_err(|e| ExportError::io(e, path))?;
        file.get_mut().release();
        self.bytes += rows.bytes();
        Ok(())
    }

    /// The rows of `stride` bytes in the file, which is emptied (the next rows start
    /// it again).
    fn take(&mut self, stride: usize) -> Result<Rows> {
        if self.file.take().is_none() {
            return Ok(Rows::new(stride));
        }
        let bytes = std::mem::take(&mut self.bytes);
        File::open(&self.path)
            .and_then(|mut f| Rows::read(&mut f, bytes, stride))
            .map_err(|e| ExportError::io(e, &self.path))
    }
}

/// Held while a wide table is written (several logs exported at once write theirs one
/// after another).
static WIDE_TABLE: Mutex<()> = Mutex::new(());

/// Writes the rows a wide table kept in its spill file as row groups, and removes the
/// spill file; nothing for other tables.
fn write_wide(slot: &mut Open, options: &Options) -> Result<()> {
    if !slot.wide || slot.spill.file.take().is_none() {
        return Ok(());
    }
    let path = slot.spill.path.clone();
    let _alone = WIDE_TABLE.lock().unwrap_or_else(|p| p.into_inner());
    let result = (|| {
        let table = Arc::new(TopicTable::new(&slot.sub, options)?);
        let mut file = File::open(&path).map_err(|e| ExportError::io(e, &path))?;
        let mut left = slot.spill.bytes;
        while left > 0 {
            let rows = Rows::read(&mut file, left.min(slot.group_bytes), slot.buffer.stride())
                .map_err(|e| ExportError::io(e, &path))?;
            left -= rows.bytes();
            write_group(
                Group {
                    table: table.clone(),
                    file: slot.file.clone(),
                    number: slot.file.cut.fetch_add(1, Ordering::Relaxed),
                    rows,
                },
                options,
            )?;
        }
        Ok(())
    })();
    slot.spill.bytes = 0;
    result
}
