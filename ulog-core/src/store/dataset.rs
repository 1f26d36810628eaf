//! [`RemoteDataset`]: a [`Dataset`] in object storage, written through a local
//! staging folder and published object by object, the table of logs last.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use super::error::{StoreError, StoreErrorKind};
use super::remote::Remote;
use crate::export::lock::Owner;
use crate::export::{
    Dataset, Options, ANALYSIS_FILE, FLIGHTS_FILE, FORMATS_FILE, LOCK_FILE, LOGS_FILE,
    MESSAGES_FILE, PARAMETERS_FILE, SCHEMAS_DIR,
};
use crate::export::{ExportError, ExportErrorKind};

type Result<T, E = StoreError> = core::result::Result<T, E>;

/// The tables a dataset writes again whole at each conversion, the table of logs last.
const TABLES: [&str; 6] = [
    PARAMETERS_FILE,
    MESSAGES_FILE,
    FORMATS_FILE,
    ANALYSIS_FILE,
    FLIGHTS_FILE,
    LOGS_FILE,
];

/// A [`Dataset`] under an `s3://` prefix, the same files as a local one.
///
/// S3 has no rename, and no way to make several objects appear at once; what it
/// has is that one `PUT` (or one multipart upload, at its completion) makes an object
/// appear whole or not at all, and that a `PUT` with `If-None-Match: *` fails when the
/// object exists. So:
///
/// - **the table of logs is the commit.** A conversion writes into a local staging
///   folder ([`RemoteDataset::dataset`]: the local [`Dataset`], with the tables read
///   back from the store), then uploads each new topic file, then the other tables,
///   and [`LOGS_FILE`] last. A log is in the dataset once `logs.parquet` lists it, and
///   by then every file and row of it is in place; a reader that starts from
///   `logs.parquet` (or joins on it) never sees half a log. Each table is replaced by
///   one `PUT`, so no reader sees half a file either.
/// - **one conversion at a time:** [`RemoteDataset::open`] creates the object
///   [`LOCK_FILE`] under the prefix with `If-None-Match: *` (naming its process and
///   machine) and removes it when done; another conversion meanwhile gets
///   [`StoreErrorKind::Busy`]. A lock whose owner is known to be gone (a process of
///   this machine that no longer runs) is taken over.
/// - **a conversion that died** (killed between its topic files and its
///   `logs.parquet`) leaves topic files of logs that `logs.parquet` does not list:
///   the next [`RemoteDataset::open`] removes them, and those logs are converted again
///   when next given (their files are the same byte for byte).
pub struct RemoteDataset {
    remote: Remote,
    staging: PathBuf,
    dataset: Option<Dataset>,
    lock: Remote,
    removed: usize,
}

/// What [`RemoteDataset::finish`] uploaded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub struct Published {
    /// Objects written (new topic files and the tables).
    pub objects: usize,
    /// Their bytes.
    pub bytes: u64,
}

impl RemoteDataset {
    /// The dataset under `remote` (made if missing), locked for this conversion,
    /// its tables read back into a local staging folder, and the files a conversion
    /// that died left behind removed.
    pub fn open(remote: Remote, options: &Options) -> Result<RemoteDataset> {
        if options.compact {
            // Merging reads and rewrites the topic files, which are not staged here.
            let what = "compaction rewrites topic files in place: compact a local copy of \
                        the dataset, or convert into a local folder"
                .to_owned();
            return Err(StoreError::export(
                ExportError::new(ExportErrorKind::Dataset { what }),
                remote.url(),
            ));
        }
        let lock = remote.join(LOCK_FILE);
        take_lock(&remote, &lock)?;
        let mut staged = RemoteDataset {
            staging: staging_dir(),
            remote,
            dataset: None,
            lock,
            removed: 0,
        };
        let url = staged.remote.url();
        std::fs::create_dir_all(&staged.staging).map_err(|e| StoreError::io(e, &url))?;
        for table in TABLES {
            let object = staged.remote.join(table);
            match object.download(&staged.staging.join(table)) {
                Ok(_) => {}
                Err(e) if *e.kind() == StoreErrorKind::NotFound => {
                    let _ = std::fs::remove_file(staged.staging.join(table));
                }
                Err(e) => return Err(e),
            }
        }
        // The topics' union schemas, which the conversion widens with its logs'.
        let schemas = staged.remote.join(SCHEMAS_DIR);
        for (object, _) in schemas.list()? {
            let Some(rel) = object.relative_to(&staged.remote) else {
                continue;
            };
            let to = staged.staging.join(&rel);
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent).map_err(|e| StoreError::io(e, object.url()))?;
            }
            object.download(&to)?;
        }
        let dataset =
            Dataset::open(&staged.staging, options).map_err(|e| StoreError::export(e, &url))?;
        staged.removed = remove_unlisted(&staged.remote, &dataset)?;
        staged.dataset = Some(dataset);
        Ok(staged)
    }

    /// The local dataset logs are added to ([`Dataset::add`]); its folder is the
    /// staging folder, uploaded by [`RemoteDataset::finish`].
    pub fn dataset(&self) -> &Dataset {
        self.dataset
            .as_ref()
            .expect("a RemoteDataset has its dataset until finished")
    }

    /// The dataset's URL.
    pub fn url(&self) -> String {
        self.remote.url()
    }

    /// Topic files of logs `logs.parquet` did not list (left by a conversion that
    /// died) that [`RemoteDataset::open`] removed.
    pub fn removed_leftovers(&self) -> usize {
        self.removed
    }

    /// Writes the tables, uploads the new topic files, then the tables with
    /// [`LOGS_FILE`] last, and releases the lock.
    pub fn finish(mut self) -> Result<Published> {
        let url = self.remote.url();
        let dataset = self.dataset.take().expect("finished once");
        dataset.finish().map_err(|e| StoreError::export(e, &url))?;
        let mut files = Vec::new();
        walk(&self.staging, &self.staging, &mut files).map_err(|e| StoreError::io(e, &url))?;
        let (tables, topics): (Vec<_>, Vec<_>) = files
            .into_iter()
            .partition(|rel| TABLES.contains(&rel.as_str()));
        let mut published = upload(&self.remote, &self.staging, &topics)?;
        // The tables after the files they list; `logs.parquet` last.
        for table in TABLES.iter().filter(|t| tables.iter().any(|r| r == *t)) {
            let more = upload(&self.remote, &self.staging, &[table.to_string()])?;
            published.objects += more.objects;
            published.bytes += more.bytes;
        }
        Ok(published)
    }
}

impl Drop for RemoteDataset {
    fn drop(&mut self) {
        drop(self.dataset.take());
        let _ = std::fs::remove_dir_all(&self.staging);
        let _ = self.lock.delete();
    }
}

/// Creates `lock` (only if absent), taking over one whose owner is gone.
fn take_lock(remote: &Remote, lock: &Remote) -> Result<()> {
    let me = Owner::me().text().into_bytes();
    for _ in 0..2 {
        if lock.put_new(me.clone())? {
            return Ok(());
        }
        let text = match lock.get() {
            Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
            // Removed meanwhile: try again.
            Err(e) if *e.kind() == StoreErrorKind::NotFound => continue,
            Err(e) => return Err(e),
        };
        match Owner::parse(&text) {
            Some(owner) if owner.is_gone() => lock.delete()?,
            owner => {
                let owner = owner.map_or_else(|| "unknown".to_owned(), |o| o.to_string());
                return Err(StoreError::new(
                    StoreErrorKind::Busy { owner },
                    remote.url(),
                ));
            }
        }
    }
    let owner = "unknown (its lock came back at once)".to_owned();
    Err(StoreError::new(
        StoreErrorKind::Busy { owner },
        remote.url(),
    ))
}

/// Removes the topic files of logs `dataset` lacks (in the fleet layout: whose first
/// log it lacks);
/// the number removed.
fn remove_unlisted(remote: &Remote, dataset: &Dataset) -> Result<usize> {
    let mut removed = 0;
    for (object, _) in remote.list()? {
        let Some(rel) = object.relative_to(remote) else {
            continue;
        };
        // `<topic>/<log_id>.parquet`, or in the fleet layout
        // `<topic>/<key>=<value>/…/<first log_id>.parquet`.
        let parts: Vec<&str> = rel.split('/').collect();
        let [topic, partitions @ .., file] = parts.as_slice() else {
            continue;
        };
        if topic.starts_with(['_', '.']) || partitions.iter().any(|p| !p.contains('=')) {
            continue;
        }
        let Some(id) = file.strip_suffix(".parquet") else {
            continue;
        };
        let is_id = id.len() == 16 && id.bytes().all(|b| b.is_ascii_hexdigit());
        if is_id && !dataset.contains(id) {
            object.delete()?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// Uploads the files `rels` of `staging` below `remote`, four at a time.
fn upload(remote: &Remote, staging: &Path, rels: &[String]) -> Result<Published> {
    let next = AtomicUsize::new(0);
    let results: Vec<Result<(usize, u64)>> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..4.min(rels.len()))
            .map(|_| {
                s.spawn(|| {
                    let (mut objects, mut bytes) = (0, 0u64);
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(rel) = rels.get(i) else {
                            return Ok((objects, bytes));
                        };
                        let object = remote.join(rel);
                        let data = std::fs::read(staging.join(rel))
                            .map_err(|e| StoreError::io(e, object.url()))?;
                        bytes += data.len() as u64;
                        object.put(data)?;
                        objects += 1;
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().expect("an upload thread does not panic"))
            .collect()
    });
    let mut published = Published {
        objects: 0,
        bytes: 0,
    };
    for r in results {
        let (objects, bytes) = r?;
        published.objects += objects;
        published.bytes += bytes;
    }
    Ok(published)
}

/// The files below `dir` as paths relative to `root` with `/`, sorted; the lock
/// and temporary files left out.
fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) -> std::io::Result<()> {
    let mut entries: Vec<_> = std::fs::read_dir(dir)?.collect::<std::io::Result<_>>()?;
    entries.sort_by_key(|e| e.file_name());
    for entry in entries {
        let path = entry.path();
        if entry.file_type()?.is_dir() {
            walk(root, &path, out)?;
            continue;
        }
        let name = entry.file_name().to_string_lossy().into_owned();
        if name == LOCK_FILE || name.ends_with(".partial") {
            continue;
        }
        let rel = path.strip_prefix(root).unwrap_or(&path);
        let parts: Vec<String> = rel
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        out.push(parts.join("/"));
    }
    out.sort();
    Ok(())
}

/// A new staging folder of this process.
fn staging_dir() -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let n = N.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!("ulog-staging-{}-{n}", std::process::id()))
}

/// A log of object storage copied to a local temporary file, to convert (a
/// conversion hashes a log, then reads it again); the file goes when it is dropped.
pub struct Downloaded {
    path: PathBuf,
    url: String,
}

impl Downloaded {
    /// Copies `remote` to a temporary file, in chunks.
    pub fn new(remote: &Remote) -> Result<Downloaded> {
        static N: AtomicUsize = AtomicUsize::new(0);
        let n = N.fetch_add(1, Ordering::Relaxed);
        let path = std::env::temp_dir().join(format!(
            "ulog-download-{}-{n}-{}",
            std::process::id(),
            remote.name()
        ));
        let downloaded = Downloaded {
            path,
            url: remote.url(),
        };
        remote.download(&downloaded.path)?;
        Ok(downloaded)
    }

    /// The local copy.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The URL it was copied from.
    pub fn url(&self) -> &str {
        &self.url
    }
}

impl Drop for Downloaded {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}
