//! `ulog_rs.convert`: logs into one Parquet dataset, by the code `ulog parquet` runs
//! for each log (`ulog_core::export::Dataset`: open, add each log, finish), with
//! `ulog parquet`'s defaults (zstd, nested columns), so that the dataset is the one
//! the command writes from the same logs.

use std::path::PathBuf;

use ulog_core::export::{Added, Compression, Dataset, ExportError, Options};

/// What became of one log: `(path, log_id, status, rows, error)`, the status
/// `written`, `present` (the dataset had it) or `failed`.
pub type Outcome = (String, Option<String>, &'static str, usize, Option<String>);

/// Converts `logs` into the dataset at `output` on up to `threads` threads (largest
/// logs first): each log that fails is reported and leaves nothing of its own; the
/// dataset's tables are written once all are done. `topics`: only these (a log
/// that has none of them is skipped); `compression`: `zstd`, `snappy` or `none`.
pub fn convert(
    logs: &[PathBuf],
    output: &PathBuf,
    topics: Option<Vec<String>>,
    compression: &str,
    threads: usize,
) -> Result<Vec<Outcome>, ExportError> {
    let options = Options {
        topics,
        compression: match compression {
            "snappy" => Compression::Snappy,
            "none" => Compression::Uncompressed,
            _ => Compression::Zstd,
        },
        skip_missing_topics: true,
        ..Options::default()
    };
    let dataset = Dataset::open(output, &options)?;
    let sizes: Vec<u64> = logs
        .iter()
        .map(|p| std::fs::metadata(p).map_or(0, |m| m.len()))
        .collect();
    let done = ulog_core::parallel::largest_first(&sizes, threads.max(1), |i| {
        Ok::<_, core::convert::Infallible>(dataset.add(&logs[i], None, |_| {}))
    });
    let outcomes = logs
        .iter()
        .zip(done)
        .map(|(path, result)| {
            let shown = path.display().to_string();
            match result {
                Some(Ok(Ok(Added::Written { log_id, export }))) => {
                    let rows = export.files.iter().map(|w| w.rows).sum();
                    (shown, Some(log_id), "written", rows, None)
                }
                Some(Ok(Ok(Added::Present { log_id }))) => {
                    (shown, Some(log_id), "present", 0, None)
                }
                Some(Ok(Ok(_))) => (shown, None, "present", 0, None),
                Some(Ok(Err(e))) => (shown, None, "failed", 0, Some(e.to_string())),
                Some(Err(never)) => match never {},
                None => (shown, None, "failed", 0, Some("not converted".to_owned())),
            }
        })
        .collect();
    dataset.finish()?;
    Ok(outcomes)
}
