//! `ulog_rs._core`: the compiled half of the `ulog_rs` Python package.
//!
//! The package's `ULog` class (in `python/ulog_rs/`) gives pyulog's API; this module
//! reads the log with ulog-core, without holding the GIL, and hands the result over
//! as plain Python values: byte strings for keys and values (decoded in Python as
//! pyulog decodes them) and one writable `uint8` numpy array of packed rows per topic,
//! made from the Rust vector without a copy.

#![allow(unsafe_code)] // pyo3's macros expand to FFI code

mod aligned;
mod arrow;
mod convert;
mod loaded;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

use numpy::IntoPyArray;
use pyo3::exceptions::{
    PyFileNotFoundError, PyOSError, PyPermissionError, PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use ulog_core::read::ReadErrorKind;
use ulog_core::{LogFile, ReadError, ULog};

use crate::loaded::{LoadError, Loaded, Request};

pyo3::create_exception!(
    _core,
    ULogError,
    PyValueError,
    "The file is not a ULog log this library can read (the message says what and where)."
);
pyo3::create_exception!(
    _core,
    InternalError,
    PyRuntimeError,
    "A bug in ulog-rs: Rust code panicked. Please report it with the log."
);

/// Where the log's bytes come from.
enum Input<'py> {
    Path(PathBuf),
    Bytes(Bound<'py, PyBytes>),
}

impl<'py> Input<'py> {
    /// The log's bytes (`bytes`) or its path (`str`, `os.PathLike`).
    fn of(source: &Bound<'py, PyAny>) -> PyResult<Input<'py>> {
        Ok(match source.cast::<PyBytes>() {
            Ok(b) => Input::Bytes(b.clone()),
            Err(_) => Input::Path(source.extract()?),
        })
    }

    /// `f` of the log parsed whole (a file mapped, not copied).
    fn parsed<T>(&self, f: impl FnOnce(&ULog<'_>) -> PyResult<T>) -> PyResult<T> {
        match self {
            Input::Bytes(b) => f(&ULog::parse(b.as_bytes()).map_err(read_error)?),
            Input::Path(path) => {
                let file = LogFile::open(path).map_err(read_error)?;
                f(&file.parse().map_err(read_error)?)
            }
        }
    }
}

/// The Python exception for a read error: an I/O error is an `OSError` subclass
/// (`FileNotFoundError` for a missing file), anything else `ULogError`.
fn read_error(e: ReadError) -> PyErr {
    let message = e.to_string();
    match e.kind() {
        ReadErrorKind::Io(std::io::ErrorKind::NotFound) => PyFileNotFoundError::new_err(message),
        ReadErrorKind::Io(std::io::ErrorKind::PermissionDenied) => {
            PyPermissionError::new_err(message)
        }
        ReadErrorKind::Io(_) => PyOSError::new_err(message),
        _ => ULogError::new_err(message),
    }
}

fn load_error(e: LoadError) -> PyErr {
    match e {
        LoadError::Read(e) => read_error(e),
        LoadError::Changed => ULogError::new_err(
            "the file changed while it was read (a logger still writing it?): read it again",
        ),
    }
}

/// Runs `f`, turning a panic into `InternalError` (never an abort or a
/// `BaseException` that `except Exception` would miss).
fn guarded<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_owned());
            Err(InternalError::new_err(format!(
                "ulog-rs panicked (a bug, please report it): {what}"
            )))
        }
    }
}

/// Reads a log: `source` is a path (`str` or `os.PathLike`) or the log's bytes;
/// `names` keeps only those topics (with `within`, those whose name is part of one
/// of them); `header_only` reads the definitions alone; `share_from` (for tests) is
/// the size from which two passes share the topics (16 MiB).
/// Returns a dict of plain values (see `ulog_rs.ULog` for what each becomes).
#[pyfunction]
#[pyo3(signature = (source, names=None, header_only=false, within=false, share_from=None))]
fn load<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    names: Option<Vec<String>>,
    header_only: bool,
    within: bool,
    share_from: Option<u64>,
) -> PyResult<Bound<'py, PyDict>> {
    let input = Input::of(source)?;
    // Two passes share the topics of a large log (see `loaded::load`).
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get().min(2));
    let request = Request {
        names,
        header_only,
        within,
        share_from: share_from.unwrap_or(loaded::SHARE_FROM),
    };
    let loaded = guarded(|| {
        match &input {
            Input::Path(path) => {
                py.detach(|| loaded::load(loaded::Input::Path(path), &request, threads))
            }
            Input::Bytes(b) => {
                let bytes = b.as_bytes();
                py.detach(|| loaded::load(loaded::Input::Bytes(bytes), &request, threads))
            }
        }
        .map_err(load_error)
    })?;
    guarded(|| to_python(py, loaded))
}

/// The Arrow record batch of each of `topics` (`(name, multi_id)`) of the log at
/// `source` (a path or bytes), as `(schema, array)` capsules of Arrow's C data
/// interface, `None` for a topic the log does not have.
#[pyfunction]
fn arrow_batches<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    topics: Vec<(String, u8)>,
) -> PyResult<Vec<Option<arrow::Capsules<'py>>>> {
    let input = Input::of(source)?;
    guarded(|| input.parsed(|log| arrow::batches(py, log, &topics)))
}

/// Several topics of the log at `source` on one time base (see `ULog.align`):
/// `(times, [(column, values, present)])`.
#[pyfunction]
#[pyo3(signature = (source, selections, on=None, rate=None, method="previous", tolerance=None, start=None, end=None))]
#[allow(clippy::too_many_arguments)] // Python's keyword arguments
fn align<'py>(
    py: Python<'py>,
    source: &Bound<'py, PyAny>,
    selections: Vec<String>,
    on: Option<String>,
    rate: Option<f64>,
    method: &str,
    tolerance: Option<f64>,
    start: Option<f64>,
    end: Option<f64>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyList>)> {
    let request = aligned::Request {
        selections,
        on,
        rate,
        method: method.to_owned(),
        tolerance,
        start,
        end,
    };
    let input = Input::of(source)?;
    guarded(|| input.parsed(|log| aligned::align(py, log, &request)))
}

/// Converts the logs at `logs` into the Parquet dataset `output` (see
/// `ulog_rs.convert`); returns one `(path, log_id, status, rows, error)` per log.
#[pyfunction]
#[pyo3(signature = (logs, output, topics=None, compression="zstd", threads=None, present=Vec::new(), layout=None, partition_by=None, file_size_mb=None, compact=false))]
#[allow(clippy::too_many_arguments)]
fn convert_logs(
    py: Python<'_>,
    logs: Vec<String>,
    output: String,
    topics: Option<Vec<String>>,
    compression: &str,
    threads: Option<usize>,
    present: Vec<String>,
    layout: Option<&str>,
    partition_by: Option<Vec<String>>,
    file_size_mb: Option<u64>,
    compact: bool,
) -> PyResult<Vec<convert::Outcome>> {
    let layout = convert::layout_of(layout, partition_by, file_size_mb)?;
    let options = convert::options(topics, compression, layout, compact);
    let threads =
        threads.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    guarded(|| py.detach(|| convert::convert(&logs, &output, &options, threads, present)))
}

/// The flight analysis of a log (`ulog_core::analysis::analyze`, the code `ulog
/// analyze` runs) as the JSON text `ulog analyze --json` prints for it (without its
/// `file`): a path is read once in chunks, bytes from memory.
#[pyfunction]
#[pyo3(signature = (source, spectra=true, step_response=true))]
fn analyze_json(
    py: Python<'_>,
    source: &Bound<'_, PyAny>,
    spectra: bool,
    step_response: bool,
) -> PyResult<String> {
    let options = ulog_core::analysis::AnalyzeOptions::default()
        .spectra(spectra)
        .step_response(step_response);
    let input = Input::of(source)?;
    guarded(|| {
        let flight = match &input {
            Input::Bytes(b) => {
                let bytes = b.as_bytes();
                py.detach(|| ulog_core::analysis::analyze(bytes, &options))
            }
            Input::Path(path) => {
                py.detach(|| ulog_core::analysis::analyze(ulog_core::Source::file(path), &options))
            }
        }
        .map_err(read_error)?;
        Ok(flight.json())
    })
}

/// The logs `input` names (`ulog_core::LogFile::find`): the file, or the `.ulg` and
/// `.ulog` files of a directory and its subdirectories, sorted; for an `s3://` URL the
/// object, or every log below it as a prefix (`ulog_core::store::Remote::find_logs`);
/// `[(path or URL, size)]`.
#[pyfunction]
fn find_logs(py: Python<'_>, input: String) -> PyResult<Vec<(String, u64)>> {
    use ulog_core::store::Remote;
    guarded(|| {
        if Remote::is_url(&input) {
            let remote = Remote::parse(&input).map_err(|e| convert::store_error(&e))?;
            let found = py
                .detach(|| remote.find_logs())
                .map_err(|e| convert::store_error(&e))?;
            return Ok(found.into_iter().map(|(r, size)| (r.url(), size)).collect());
        }
        let found = LogFile::find(&input).map_err(read_error)?;
        Ok(found
            .into_iter()
            .map(|(p, size)| (p.to_string_lossy().into_owned(), size))
            .collect())
    })
}

/// The unit of field `path` of `topic` by PX4's naming (`ulog_core::units::unit_of`),
/// or `None`.
#[pyfunction]
fn unit_of(topic: &str, path: &str) -> Option<&'static str> {
    ulog_core::units::unit_of(topic, path)
}

/// The candidate closest to `name` by edit distance (the library's one rule for
/// "did you mean"), or `None` when none is close.
#[pyfunction]
fn closest(name: &str, candidates: Vec<String>) -> Option<String> {
    ulog_core::format::suggest::closest(name, candidates.iter().map(String::as_str))
}

/// Panics: what `ulog_rs` does with a panic in its Rust code, for the tests.
#[pyfunction]
fn _panic_for_tests() -> PyResult<()> {
    guarded(|| panic!("a panic raised on purpose by _panic_for_tests"))
}

fn bytes<'py>(py: Python<'py>, b: &[u8]) -> Bound<'py, PyBytes> {
    PyBytes::new(py, b)
}

fn key_raws<'py>(py: Python<'py>, kvs: &[(Vec<u8>, Vec<u8>)]) -> PyResult<Bound<'py, PyList>> {
    PyList::new(py, kvs.iter().map(|(k, v)| (bytes(py, k), bytes(py, v))))
}

fn to_python(py: Python<'_>, l: Loaded) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("version", l.version)?;
    d.set_item("start_timestamp", l.start_timestamp)?;
    d.set_item("last_timestamp", l.last_timestamp)?;
    d.set_item("compat_flags", l.compat_flags.to_vec())?;
    d.set_item("incompat_flags", l.incompat_flags.to_vec())?;
    d.set_item("appended_offsets", l.appended_offsets)?;
    d.set_item("formats", l.formats)?;
    d.set_item("info", key_raws(py, &l.info)?)?;
    let multi = PyList::empty(py);
    for entries in &l.info_multiple {
        let e = PyList::empty(py);
        for parts in entries {
            e.append(key_raws(py, parts)?)?;
        }
        multi.append(e)?;
    }
    d.set_item("info_multiple", multi)?;
    d.set_item("initial_parameters", key_raws(py, &l.initial_parameters)?)?;
    d.set_item(
        "changed_parameters",
        PyList::new(
            py,
            l.changed_parameters
                .iter()
                .map(|(t, k, v)| (*t, bytes(py, k), bytes(py, v))),
        )?,
    )?;
    d.set_item(
        "default_parameters",
        PyList::new(
            py,
            l.default_parameters
                .iter()
                .map(|(bits, k, v)| (*bits, bytes(py, k), bytes(py, v))),
        )?,
    )?;
    d.set_item(
        "logged_messages",
        PyList::new(
            py,
            l.logged_messages
                .iter()
                .map(|(level, tag, t, text)| (*level, *tag, *t, bytes(py, text))),
        )?,
    )?;
    d.set_item("dropouts", l.dropouts)?;
    d.set_item("corrupt", l.corrupt)?;
    d.set_item("findings", l.findings)?;
    let topics = PyList::empty(py);
    for t in l.topics {
        let td = PyDict::new(py);
        td.set_item("name", t.name)?;
        td.set_item("multi_id", t.multi_id)?;
        td.set_item("msg_id", t.msg_id)?;
        td.set_item("fields", t.fields)?;
        td.set_item("timestamp_idx", t.timestamp_idx)?;
        td.set_item("itemsize", t.itemsize)?;
        td.set_item("rows", t.rows.into_pyarray(py))?;
        topics.append(td)?;
    }
    d.set_item("topics", topics)?;
    d.set_item("utc", l.utc)?;
    d.set_item("events", PendingEvents { events: l.events })?;
    Ok(d)
}

/// A log's PX4 events, decoded when `decode` is first called (`ULog.events`).
#[pyclass(frozen)]
struct PendingEvents {
    events: loaded::Events,
}

#[pymethods]
impl PendingEvents {
    /// The events: `(timestamp, id, sequence, level, external level, name, group,
    /// text, description, is_message)` each.
    fn decode(&self, py: Python<'_>) -> PyResult<Vec<loaded::EventRow>> {
        guarded(|| Ok(py.detach(|| self.events.decode())))
    }

    /// Equal to other events still to decode, or to a list of decoded ones, that
    /// decode to the same (pyulog's tests compare every attribute of two logs).
    fn __eq__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<bool> {
        let theirs = match other.cast::<PendingEvents>() {
            Ok(pending) => pending.get().decode(py)?,
            Err(_) => match other.extract::<Vec<loaded::EventRow>>() {
                Ok(decoded) => decoded,
                Err(_) => return Ok(false),
            },
        };
        Ok(self.decode(py)? == theirs)
    }
}

/// The `ulog_rs._core` module.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(closest, m)?)?;
    m.add_function(wrap_pyfunction!(unit_of, m)?)?;
    m.add_function(wrap_pyfunction!(find_logs, m)?)?;
    m.add_function(wrap_pyfunction!(convert_logs, m)?)?;
    m.add_class::<convert::DatasetWriter>()?;
    m.add_function(wrap_pyfunction!(analyze_json, m)?)?;
    m.add_function(wrap_pyfunction!(align, m)?)?;
    m.add_function(wrap_pyfunction!(arrow_batches, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_tests, m)?)?;
    m.add("ULogError", m.py().get_type::<ULogError>())?;
    m.add("InternalError", m.py().get_type::<InternalError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
