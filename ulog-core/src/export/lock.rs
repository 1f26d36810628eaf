//! One writer of a dataset at a time ([`DatasetLock`]), and temporary names that no
//! two writers share ([`partial_name`]).
//!
//! A dataset's tables are read, added to and written again whole by each conversion,
//! and a log's topic files are named by its id: two conversions into one folder at
//! once would each write the tables without the other's logs, and two of the same log
//! would write the same files. So a [`Dataset`](super::Dataset) is held by one
//! conversion from [`open`](super::Dataset::open) to
//! [`finish`](super::Dataset::finish): a lock file in the folder, made with
//! `create_new` (which the file system makes atomic), naming its owner. A lock left by
//! a conversion that died (killed, a crash, a power loss) is taken over where that can
//! be known: on Linux, when its owner, a process of this machine, is gone (its process
//! id no longer runs, or runs a process started at another time). Elsewhere, or for an
//! owner on another machine (a shared folder), it stays until removed, and the error
//! says which file to remove. An OS lock (`flock`) would go with its process by itself,
//! but the standard library has one only since Rust 1.89 (the workspace builds with
//! 1.81), and it is unreliable on network file systems, where a lock file is not.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::error::{ExportError, ExportErrorKind};

type Result<T, E = ExportError> = core::result::Result<T, E>;

/// The lock file of a dataset, in its folder.
pub const LOCK_FILE: &str = ".ulog-dataset.lock";

/// A dataset's lock, held until dropped (which removes the file).
#[derive(Debug)]
pub(super) struct DatasetLock {
    path: PathBuf,
}

/// Who holds a lock, as its file says.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Owner {
    pid: u32,
    host: String,
    /// When the process started, in clock ticks since boot (Linux), if known.
    start: Option<u64>,
}

impl Owner {
    pub(crate) fn me() -> Owner {
        let pid = std::process::id();
        Owner {
            pid,
            host: host(),
            start: started(pid),
        }
    }

    pub(crate) fn text(&self) -> String {
        let mut s = format!("pid {}\nhost {}\n", self.pid, self.host);
        if let Some(t) = self.start {
            s.push_str(&format!("start {t}\n"));
        }
        s
    }

    pub(crate) fn parse(text: &str) -> Option<Owner> {
        let mut owner = Owner {
            pid: 0,
            host: String::new(),
            start: None,
        };
        let mut pid = None;
        for line in text.lines() {
            match line.split_once(' ') {
                Some(("pid", v)) => pid = v.parse().ok(),
                Some(("host", v)) => owner.host = v.to_owned(),
                Some(("start", v)) => owner.start = v.parse().ok(),
                _ => {}
            }
        }
        owner.pid = pid?;
        Some(owner)
    }

    /// Whether the owner is known to be gone: a process of this machine that no
    /// longer runs (Linux only: elsewhere nothing is known).
    pub(crate) fn is_gone(&self) -> bool {
        if self.host != host() || !Path::new("/proc/self").exists() {
            return false;
        }
        match started(self.pid) {
            None => true,
            // The process id taken again by a later process.
            Some(now) => self.start.is_some_and(|then| then != now),
        }
    }
}

impl core::fmt::Display for Owner {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "process {} on {}", self.pid, self.host)
    }
}

/// This machine's name, as the lock file records it.
fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .or_else(|| std::env::var("COMPUTERNAME").ok())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .map(|h| h.trim().to_owned())
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "an unnamed machine".to_owned())
}

/// When process `pid` started (Linux: field 22 of `/proc/PID/stat`, clock ticks since
/// boot); `None` when there is no such process (or no `/proc`).
fn started(pid: u32) -> Option<u64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // The fields after the command name, which is in parentheses and may hold spaces.
    let (_, rest) = stat.rsplit_once(')')?;
    rest.split_whitespace().nth(19)?.parse().ok()
}

/// How long a lock file may stay without an owner written in it (made, not yet
/// written) before it is taken for one a writer left behind.
const UNWRITTEN_GRACE: std::time::Duration = std::time::Duration::from_secs(10);

impl DatasetLock {
    /// Takes the lock of the dataset in `dir`, taking over one whose owner is gone; an
    /// error of kind [`ExportErrorKind::Busy`] when another conversion holds it.
    pub(super) fn take(dir: &Path) -> Result<DatasetLock> {
        let path = dir.join(LOCK_FILE);
        let me = Owner::me();
        // Twice at most: once more after taking over a lock left behind.
        for _ in 0..2 {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut file) => {
                    let lock = DatasetLock { path };
                    file.write_all(me.text().as_bytes())
                        .and_then(|()| file.sync_all())
                        .map_err(|e| ExportError::io(e, &lock.path))?;
                    return Ok(lock);
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let text = std::fs::read_to_string(&path).unwrap_or_default();
                    let owner = Owner::parse(&text);
                    let left = match &owner {
                        Some(owner) => owner.is_gone(),
                        // Made and not written: a writer that died at that moment, or
                        // one writing right now.
                        None => std::fs::metadata(&path)
                            .and_then(|m| m.modified())
                            .ok()
                            .and_then(|t| t.elapsed().ok())
                            .is_some_and(|age| age > UNWRITTEN_GRACE),
                    };
                    if !left {
                        return Err(ExportError::new(ExportErrorKind::Busy {
                            owner: owner
                                .map_or_else(|| "another process".to_owned(), |o| o.to_string()),
                            lock: path.clone(),
                        }));
                    }
                    // Gone already if another writer took it over first.
                    let _ = std::fs::remove_file(&path);
                }
                Err(e) => return Err(ExportError::io(e, &path)),
            }
        }
        Err(ExportError::new(ExportErrorKind::Busy {
            owner: "another process".to_owned(),
            lock: path,
        }))
    }

    /// Removes the temporary files that a writer of the dataset left behind (they end
    /// in `.partial`), in its folder and the topics' folders: only its holder writes
    /// there.
    pub(super) fn clear_leftovers(&self, dir: &Path) {
        let partial = |p: &Path| p.extension().is_some_and(|e| e == "partial");
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if kind.is_file() && partial(&path) {
                let _ = std::fs::remove_file(&path);
            } else if kind.is_dir() {
                clear_partials(&path);
            }
        }
    }
}

/// Removes the temporary files in the topic folder `dir` and its partition folders
/// (`<key>=<value>/`, the fleet layout).
fn clear_partials(dir: &Path) {
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let path = entry.path();
        let Ok(kind) = entry.file_type() else {
            continue;
        };
        if kind.is_file() && path.extension().is_some_and(|e| e == "partial") {
            let _ = std::fs::remove_file(&path);
        } else if kind.is_dir() && entry.file_name().to_string_lossy().contains('=') {
            clear_partials(&path);
        }
    }
}

impl Drop for DatasetLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// `base` with a suffix of its own, `.<pid>-<n>.partial`: the temporary name of a
/// file being written, which no other writer (another thread, another process) uses.
pub(super) fn partial_name(base: &str) -> String {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    format!("{base}.{}-{n}.partial", std::process::id())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("ulog-lock-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn one_holder_at_a_time_and_the_file_goes_with_it() {
        let dir = scratch("one");
        let lock = DatasetLock::take(&dir).unwrap();
        let text = std::fs::read_to_string(dir.join(LOCK_FILE)).unwrap();
        assert_eq!(Owner::parse(&text), Some(Owner::me()));
        let busy = DatasetLock::take(&dir).unwrap_err();
        match busy.kind() {
            ExportErrorKind::Busy { owner, lock } => {
                assert!(owner.contains(&std::process::id().to_string()), "{owner}");
                assert_eq!(lock, &dir.join(LOCK_FILE));
            }
            other => panic!("{other:?}"),
        }
        assert!(busy.to_string().contains(LOCK_FILE), "{busy}");
        drop(lock);
        assert!(!dir.join(LOCK_FILE).exists());
        DatasetLock::take(&dir).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A lock whose owner is gone is taken over where that can be known (Linux), and
    /// kept otherwise.
    #[test]
    fn a_lock_left_behind_is_taken_over_when_its_owner_is_gone() {
        let dir = scratch("left");
        // A process that ran and ended: its id names no process now, or a later one.
        let mut child = std::process::Command::new(std::env::current_exe().unwrap())
            .arg("--list")
            .stdout(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let pid = child.id();
        let start = started(pid);
        child.wait().unwrap();
        let gone = Owner {
            pid,
            host: host(),
            start,
        };
        std::fs::write(dir.join(LOCK_FILE), gone.text()).unwrap();
        let taken = DatasetLock::take(&dir);
        if cfg!(target_os = "linux") {
            taken.unwrap();
        } else {
            assert!(matches!(
                taken.unwrap_err().kind(),
                ExportErrorKind::Busy { .. }
            ));
        }
        // One of another machine is never taken over.
        let _ = std::fs::remove_file(dir.join(LOCK_FILE));
        let elsewhere = Owner {
            host: format!("not-{}", host()),
            ..gone
        };
        std::fs::write(dir.join(LOCK_FILE), elsewhere.text()).unwrap();
        assert!(matches!(
            DatasetLock::take(&dir).unwrap_err().kind(),
            ExportErrorKind::Busy { .. }
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn partial_names_differ() {
        let a = partial_name("x.parquet");
        let b = partial_name("x.parquet");
        assert_ne!(a, b);
        assert!(
            a.starts_with("x.parquet.") && a.ends_with(".partial"),
            "{a}"
        );
    }
}
