//! [`LazyFile`]: a file that is open only while it is written to.

use std::fs::File;
use std::io::{self, Write};
use std::path::PathBuf;

/// A file written in order, opened when bytes come and closed again by
/// [`LazyFile::release`]: an export has a file per topic being written all through the
/// pass (hundreds for a PX4 log, times the logs converted at once), which held open
/// would pass the usual limit of 1,024 open files. The first open creates (or
/// truncates) the file; later ones append.
#[derive(Debug)]
pub(super) struct LazyFile {
    path: PathBuf,
    file: Option<File>,
    created: bool,
}

impl LazyFile {
    pub(super) fn new(path: PathBuf) -> LazyFile {
        LazyFile {
            path,
            file: None,
            created: false,
        }
    }

    /// Closes the file until the next write (the caller flushed what it buffers).
    pub(super) fn release(&mut self) {
        self.file = None;
    }

    fn open(&mut self) -> io::Result<&mut File> {
        if self.file.is_none() {
            let mut options = File::options();
            if self.created {
                options.append(true);
            } else {
                options.write(true).create(true).truncate(true);
            }
            self.file = Some(options.open(&self.path)?);
            self.created = true;
        }
        Ok(self.file.as_mut().expect("just opened"))
    }
}

impl Write for LazyFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.open()?.write(buf)
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.open()?.write_all(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        match &mut self.file {
            Some(f) => f.flush(),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_land_in_order_across_releases_and_the_first_open_truncates() {
        let path = std::env::temp_dir().join(format!("ulog-lazy-{}", std::process::id()));
        std::fs::write(&path, b"old contents, longer than the new").unwrap();
        let mut f = LazyFile::new(path.clone());
        f.write_all(b"ab").unwrap();
        f.release();
        f.release();
        f.write_all(b"cd").unwrap();
        f.flush().unwrap();
        f.release();
        f.write_all(b"e").unwrap();
        drop(f);
        assert_eq!(std::fs::read(&path).unwrap(), b"abcde");
        std::fs::remove_file(&path).unwrap();
    }
}
