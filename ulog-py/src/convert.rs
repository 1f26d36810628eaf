//! `ulog_rs.convert`: logs into one Parquet dataset, by the code `ulog parquet` runs
//! for each log (`ulog_core::export::Dataset`: open, add each log, finish), with
//! `ulog parquet`'s defaults (zstd, nested columns), so that the dataset is the one
//! the command writes from the same logs; and `DatasetWriter`, the dataset held open
//! by a Spark driver while executors convert into staging datasets it absorbs.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;
use ulog_core::export::{
    Added, Compression, Dataset, DatasetLayout, ExportError, ExportErrorKind, LogPath, Options,
};
use ulog_core::store::{Downloaded, Remote, RemoteDataset, StoreError, StoreErrorKind};

use crate::{guarded, ULogError};

/// What became of one log: `(path, log_id, status, rows, error)`, the status
/// `written`, `present` (the dataset had it) or `failed`.
pub type Outcome = (String, Option<String>, &'static str, usize, Option<String>);

/// The options of a dataset as `ulog parquet` sets them: `topics` only (a log that
/// has none of them is skipped); `compression`: `zstd`, `snappy` or `none`; `compact`:
/// the fleet layout's small files merged at the end (`ulog parquet --compact`).
pub fn options(
    topics: Option<Vec<String>>,
    compression: &str,
    layout: Option<DatasetLayout>,
    compact: bool,
) -> Options {
    Options {
        layout,
        compact,
        topics,
        compression: match compression {
            "snappy" => Compression::Snappy,
            "none" => Compression::Uncompressed,
            _ => Compression::Zstd,
        },
        skip_missing_topics: true,
        ..Options::default()
    }
}

/// The dataset layout of `ulog_rs.convert`'s `layout` (`"file-per-log"`, `"fleet"`),
/// `partition_by` (`"month"`, `"vehicle"`; default month) and `file_size_mb` (default
/// 128), as `ulog parquet --layout … --partition-by … --file-size …` take them.
pub fn layout_of(
    layout: Option<&str>,
    partition_by: Option<Vec<String>>,
    file_size_mb: Option<u64>,
) -> PyResult<Option<DatasetLayout>> {
    let keys: Option<Vec<&str>> = partition_by
        .as_ref()
        .map(|keys| keys.iter().map(String::as_str).collect());
    DatasetLayout::from_names(layout, keys.as_deref(), file_size_mb).map_err(PyValueError::new_err)
}

/// The Python error of an export: a file that cannot be read or written is an
/// `OSError`, anything else a `ULogError`.
pub fn export_error(e: &ExportError) -> PyErr {
    match e.kind() {
        ExportErrorKind::Io(_) => PyOSError::new_err(e.to_string()),
        _ => ULogError::new_err(e.to_string()),
    }
}

/// The Python error of a request to object storage.
pub fn store_error(e: &StoreError) -> PyErr {
    match e.kind() {
        StoreErrorKind::NotFound => PyFileNotFoundError::new_err(e.to_string()),
        StoreErrorKind::Export | StoreErrorKind::BadUrl => ULogError::new_err(e.to_string()),
        _ => PyOSError::new_err(e.to_string()),
    }
}

/// Where a dataset is written: a folder, or an `s3://` prefix.
enum Target {
    Local(Dataset),
    Remote(RemoteDataset),
}

impl Target {
    fn open(output: &str, options: &Options) -> PyResult<Target> {
        if Remote::is_url(output) {
            let remote = Remote::parse(output).map_err(|e| store_error(&e))?;
            RemoteDataset::open(remote, options)
                .map(Target::Remote)
                .map_err(|e| store_error(&e))
        } else {
            Dataset::open(output, options)
                .map(Target::Local)
                .map_err(|e| export_error(&e))
        }
    }

    fn dataset(&self) -> &Dataset {
        match self {
            Target::Local(d) => d,
            Target::Remote(r) => r.dataset(),
        }
    }

    fn finish(self) -> PyResult<()> {
        match self {
            Target::Local(d) => d.finish().map(|_| ()).map_err(|e| export_error(&e)),
            Target::Remote(r) => r.finish().map(|_| ()).map_err(|e| store_error(&e)),
        }
    }
}

/// Adds the log `log` (a path, or an `s3://`/`http(s)://` URL, copied to a temporary
/// file first: it is hashed, then read again) to `dataset`; a failure as its text.
fn add(dataset: &Dataset, log: &str) -> Result<Added, String> {
    if Remote::is_url(log) {
        let remote = Remote::parse(log).map_err(|e| e.to_string())?;
        let downloaded = Downloaded::new(&remote).map_err(|e| e.to_string())?;
        dataset
            .add(
                LogPath::named(downloaded.path(), downloaded.url()),
                None,
                |_| {},
            )
            .map_err(|e| e.to_string())
    } else {
        dataset
            .add(Path::new(log), None, |_| {})
            .map_err(|e| e.to_string())
    }
}

/// Converts `logs` (paths or URLs) into the dataset at `output` (a folder or an
/// `s3://` prefix) on up to `threads` threads (largest logs first): each log that
/// fails is reported and leaves nothing of its own; the dataset's tables are written
/// once all are done. `present`: ids of logs to skip as if the dataset had them (a
/// Spark executor's staging dataset, whose target has them).
pub fn convert(
    logs: &[String],
    output: &str,
    options: &Options,
    threads: usize,
    present: Vec<String>,
) -> PyResult<Vec<Outcome>> {
    let target = Target::open(output, options)?;
    let dataset = target.dataset();
    dataset.assume_present(present);
    let sizes: Vec<u64> = logs
        .iter()
        .map(|p| std::fs::metadata(p).map_or(0, |m| m.len()))
        .collect();
    let done = ulog_core::parallel::largest_first(&sizes, threads.max(1), |i| {
        Ok::<_, core::convert::Infallible>(add(dataset, &logs[i]))
    });
    let outcomes = logs
        .iter()
        .zip(done)
        .map(|(shown, result)| {
            let shown = shown.clone();
            match result {
                Some(Ok(Ok(Added::Written { log_id, export }))) => {
                    let rows = export.files.iter().map(|w| w.rows).sum();
                    (shown, Some(log_id), "written", rows, None)
                }
                Some(Ok(Ok(Added::Present { log_id }))) => {
                    (shown, Some(log_id), "present", 0, None)
                }
                Some(Ok(Ok(_))) => (shown, None, "present", 0, None),
                Some(Ok(Err(e))) => (shown, None, "failed", 0, Some(e)),
                Some(Err(never)) => match never {},
                None => (shown, None, "failed", 0, Some("not converted".to_owned())),
            }
        })
        .collect();
    target.finish()?;
    Ok(outcomes)
}

/// A dataset held open (and locked) while logs converted elsewhere are absorbed into
/// it: what `ulog_rs.spark` does on the driver (`ulog_core::export::Dataset`:
/// `open`, `absorb` per executor's staging dataset, `finish`).
#[pyclass(module = "ulog_rs._core")]
pub struct DatasetWriter {
    dataset: Mutex<Option<Dataset>>,
    dir: PathBuf,
}

impl DatasetWriter {
    fn with<T>(&self, f: impl FnOnce(&Dataset) -> PyResult<T>) -> PyResult<T> {
        let held = self.dataset.lock().unwrap_or_else(|p| p.into_inner());
        match held.as_ref() {
            Some(d) => f(d),
            None => Err(ULogError::new_err(format!(
                "{}: the dataset was finished",
                self.dir.display()
            ))),
        }
    }
}

#[pymethods]
impl DatasetWriter {
    /// Opens (and locks) the dataset in the folder `output`, with the options of
    /// `ulog_rs.convert`.
    #[new]
    #[pyo3(signature = (output, topics=None, compression="zstd", layout=None, partition_by=None, file_size_mb=None, compact=false))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        output: PathBuf,
        topics: Option<Vec<String>>,
        compression: &str,
        layout: Option<&str>,
        partition_by: Option<Vec<String>>,
        file_size_mb: Option<u64>,
        compact: bool,
    ) -> PyResult<DatasetWriter> {
        let layout = layout_of(layout, partition_by, file_size_mb)?;
        let options = options(topics, compression, layout, compact);
        let dataset = guarded(|| {
            py.detach(|| Dataset::open(&output, &options))
                .map_err(|e| export_error(&e))
        })?;
        Ok(DatasetWriter {
            dataset: Mutex::new(Some(dataset)),
            dir: output,
        })
    }

    /// The ids of the logs the dataset has, sorted.
    fn log_ids(&self) -> PyResult<Vec<String>> {
        self.with(|d| Ok(d.log_ids()))
    }

    /// Takes the logs of the finished dataset in the folder `staging`: their files
    /// moved here, their rows kept for `finish`; `[(log_id, status, files)]`, the
    /// status `moved` or `present`.
    fn absorb(
        &self,
        py: Python<'_>,
        staging: PathBuf,
    ) -> PyResult<Vec<(String, &'static str, usize)>> {
        self.with(|d| {
            guarded(|| {
                let added = py
                    .detach(|| d.absorb(&staging))
                    .map_err(|e| export_error(&e))?;
                Ok(added
                    .into_iter()
                    .filter_map(|a| match a {
                        Added::Moved { log_id, files } => Some((log_id, "moved", files)),
                        Added::Present { log_id } => Some((log_id, "present", 0)),
                        Added::Written { log_id, .. } => Some((log_id, "moved", 0)),
                        _ => None,
                    })
                    .collect())
            })
        })
    }

    /// Writes the tables (the table of logs last) and releases the lock; the number
    /// of logs in the dataset.
    fn finish(&self, py: Python<'_>) -> PyResult<usize> {
        let taken = self
            .dataset
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take();
        let Some(dataset) = taken else {
            return Err(ULogError::new_err(format!(
                "{}: the dataset was finished",
                self.dir.display()
            )));
        };
        let logs = dataset.len();
        guarded(|| py.detach(|| dataset.finish()).map_err(|e| export_error(&e)))?;
        Ok(logs)
    }

    /// Releases the lock without writing the tables (the files of logs absorbed stay,
    /// and are removed by the next conversion: the table of logs does not list them).
    fn abandon(&self) {
        drop(
            self.dataset
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .take(),
        );
    }
}
