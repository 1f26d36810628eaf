//! [`StoreError`]: what went wrong with an object in storage, and which.

use core::fmt;

/// Why a request to object storage failed. Matchable; new kinds may be added.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum StoreErrorKind {
    /// The text is not a location this crate reads (`s3://bucket/key`,
    /// `https://host/path`, `http://host/path`).
    BadUrl,
    /// No object at the location (nor, for a prefix, any log under it).
    NotFound,
    /// The store refused or failed the request (the `object_store` error is the
    /// [`source`](std::error::Error::source)): credentials, network, a server error.
    Request,
    /// Writing or reading the local staging copy failed (the `std::io::Error` is the
    /// [`source`](std::error::Error::source)).
    Io(std::io::ErrorKind),
    /// The dataset could not be written (the export's error is the
    /// [`source`](std::error::Error::source)).
    Export,
    /// Another conversion is writing the dataset (its lock object exists).
    Busy {
        /// Who holds the lock, as its object says (`process 1234 on hostname`).
        owner: String,
    },
}

/// A failed request: what, and the URL of the object it was about.
#[derive(Debug)]
pub struct StoreError {
    kind: StoreErrorKind,
    url: String,
    source: Option<Box<dyn std::error::Error + Send + Sync>>,
}

impl StoreError {
    pub(crate) fn new(kind: StoreErrorKind, url: impl Into<String>) -> StoreError {
        StoreError {
            kind,
            url: url.into(),
            source: None,
        }
    }

    /// An error of `object_store` about `url`: not found, or a failed request.
    pub(crate) fn request(e: object_store::Error, url: impl Into<String>) -> StoreError {
        let kind = match e {
            object_store::Error::NotFound { .. } => StoreErrorKind::NotFound,
            _ => StoreErrorKind::Request,
        };
        StoreError {
            kind,
            url: url.into(),
            source: Some(Box::new(e)),
        }
    }

    pub(crate) fn io(e: std::io::Error, url: impl Into<String>) -> StoreError {
        StoreError {
            kind: StoreErrorKind::Io(e.kind()),
            url: url.into(),
            source: Some(Box::new(e)),
        }
    }

    pub(crate) fn export(e: crate::export::ExportError, url: impl Into<String>) -> StoreError {
        StoreError {
            kind: StoreErrorKind::Export,
            url: url.into(),
            source: Some(Box::new(e)),
        }
    }

    /// What failed.
    pub fn kind(&self) -> &StoreErrorKind {
        &self.kind
    }

    /// The URL (or local path) of the object or dataset it was about.
    pub fn url(&self) -> &str {
        &self.url
    }
}

impl StoreError {
    /// What failed, without the URL (which [`Display`](fmt::Display) puts first).
    pub fn what(&self) -> String {
        match &self.kind {
            StoreErrorKind::BadUrl => "not a location to read (expected s3://BUCKET/KEY, \
                                       https://HOST/PATH or http://HOST/PATH)"
                .to_owned(),
            StoreErrorKind::NotFound => "no such object".to_owned(),
            StoreErrorKind::Busy { owner } => format!(
                "another conversion ({owner}) is writing the dataset (its lock object is {}/{})",
                self.url,
                crate::export::LOCK_FILE
            ),
            _ => match &self.source {
                Some(s) => one_line(&s.to_string()),
                None => "failed".to_owned(),
            },
        }
    }
}

impl fmt::Display for StoreError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.url, self.what())
    }
}

/// A [`StoreError`] inside an [`std::io::Error`]: what failed without the URL (the
/// reader's caller names the log), the error itself as the source.
#[derive(Debug)]
struct Detached(StoreError);

impl fmt::Display for Detached {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0.what())
    }
}

impl std::error::Error for Detached {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.0)
    }
}

/// `object_store`'s texts span lines (a server's XML body): one line of them.
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

impl std::error::Error for StoreError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.source
            .as_deref()
            .map(|s| s as &(dyn std::error::Error + 'static))
    }
}

impl From<StoreError> for std::io::Error {
    fn from(e: StoreError) -> std::io::Error {
        let kind = match e.kind {
            StoreErrorKind::NotFound => std::io::ErrorKind::NotFound,
            StoreErrorKind::Io(k) => k,
            _ => std::io::ErrorKind::Other,
        };
        std::io::Error::new(kind, Detached(e))
    }
}
