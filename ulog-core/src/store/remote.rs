//! [`Remote`]: one object (or prefix) in S3 or behind HTTP(S), and [`RemoteReader`],
//! its bytes read in order by ranged requests.

use std::collections::HashMap;
use std::io::Read;
use std::path::Path as FsPath;
use std::sync::{Arc, Mutex, OnceLock};

use futures::TryStreamExt;
use object_store::path::Path as Key;
use object_store::{ObjectStore, PutMode, PutOptions, PutPayload};
use tokio::runtime::Runtime;
use tokio::task::JoinHandle;

use super::error::{StoreError, StoreErrorKind};
use crate::LogFile;

type Result<T, E = StoreError> = core::result::Result<T, E>;

/// The bytes a [`RemoteReader`] holds ahead of the caller, in blocks of 1 MiB: 8
/// MiB, so that a command that stops early has fetched at most that much (and what the
/// connection's buffers held) past where it stopped.
pub const AHEAD: u64 = 8 << 20;

/// The blocks a [`RemoteReader`] hands over: 1 MiB, gathered from the response's frames
/// (16 KiB and less), so that the caller waits on the runtime once per block.
const BLOCK: usize = 1 << 20;

/// The bytes of a [`RemoteReader`]'s first request: 1 MiB, which holds the header
/// and the definitions of real logs (a read of those alone, such as `ulog cut`'s
/// look at the header, fetches little more).
pub const FIRST_CHUNK: u64 = 1 << 20;

/// Where a log (or a dataset) is: a local path or an object in storage.
#[derive(Debug, Clone)]
pub enum Location {
    /// A path of this machine.
    Local(std::path::PathBuf),
    /// An object (or prefix) in S3 or behind HTTP(S).
    Remote(Remote),
}

impl Location {
    /// `text` as a location: `s3://BUCKET/KEY`, `https://HOST/PATH` and
    /// `http://HOST/PATH` are [`Remote`]; anything else is a local path.
    ///
    /// An S3 location takes its credentials, region and endpoint from the standard
    /// AWS environment (`AWS_ACCESS_KEY_ID`, `AWS_SECRET_ACCESS_KEY`,
    /// `AWS_SESSION_TOKEN`, `AWS_REGION` or `AWS_DEFAULT_REGION`, `AWS_ENDPOINT_URL`
    /// for an S3-compatible server; an `http://` endpoint is then allowed) and from
    /// nothing else.
    ///
    /// ```
    /// use ulog_core::store::Location;
    /// assert!(matches!(Location::parse("flight.ulg")?, Location::Local(_)));
    /// let Location::Remote(r) = Location::parse("s3://fleet/2026/flight.ulg")? else {
    ///     unreachable!()
    /// };
    /// assert_eq!(r.url(), "s3://fleet/2026/flight.ulg");
    /// # Ok::<(), ulog_core::store::StoreError>(())
    /// ```
    pub fn parse(text: &str) -> Result<Location> {
        if Remote::is_url(text) {
            Remote::parse(text).map(Location::Remote)
        } else {
            Ok(Location::Local(text.into()))
        }
    }
}

/// One object, or a prefix of objects, in S3 or behind HTTP(S).
#[derive(Clone)]
pub struct Remote {
    /// The store of the bucket (S3) or of the host (HTTP), shared by every object of it.
    store: Arc<dyn ObjectStore>,
    /// `s3://bucket` or `https://host:port`, without a trailing `/`.
    base: String,
    key: Key,
}

impl core::fmt::Debug for Remote {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "Remote({})", self.url())
    }
}

impl Remote {
    /// Whether `text` is a URL of a store ([`Location::parse`]).
    pub fn is_url(text: &str) -> bool {
        ["s3://", "https://", "http://"]
            .iter()
            .any(|p| text.len() > p.len() && text[..p.len()].eq_ignore_ascii_case(p))
    }

    /// `text` as a remote location ([`Location::parse`]).
    pub fn parse(text: &str) -> Result<Remote> {
        let bad = || StoreError::new(StoreErrorKind::BadUrl, text);
        let (scheme, rest) = text.split_once("://").ok_or_else(bad)?;
        let scheme = scheme.to_ascii_lowercase();
        let (authority, path) = rest.split_once('/').unwrap_or((rest, ""));
        if authority.is_empty() || authority.contains(['?', '#', ' ']) {
            return Err(bad());
        }
        let base = format!("{scheme}://{authority}");
        let store = store_of(&scheme, authority, &base)?;
        let key = Key::from_url_path(path).map_err(|_| bad())?;
        Ok(Remote { store, base, key })
    }

    /// The URL, as [`Location::parse`] takes it.
    pub fn url(&self) -> String {
        match self.key.as_ref() {
            "" => self.base.clone(),
            key => format!("{}/{key}", self.base),
        }
    }

    /// The object's name: the last part of its key.
    pub fn name(&self) -> &str {
        self.key.filename().unwrap_or("")
    }

    /// The object `relative` below this prefix (`a/b` below `s3://x/d` is `s3://x/d/a/b`).
    pub fn join(&self, relative: &str) -> Remote {
        let mut key = self.key.as_ref().trim_end_matches('/').to_owned();
        for part in relative.split('/').filter(|p| !p.is_empty()) {
            if !key.is_empty() {
                key.push('/');
            }
            key.push_str(part);
        }
        Remote {
            store: self.store.clone(),
            base: self.base.clone(),
            key: Key::from(key),
        }
    }

    /// The object's size, by one `HEAD` request.
    pub fn size(&self) -> Result<u64> {
        let (store, key) = self.parts();
        let meta = block_on(async move { store.head(&key).await }).map_err(|e| self.error(e))?;
        Ok(meta.size)
    }

    /// Whether the object exists.
    pub fn exists(&self) -> Result<bool> {
        match self.size() {
            Ok(_) => Ok(true),
            Err(e) if *e.kind() == StoreErrorKind::NotFound => Ok(false),
            Err(e) => Err(e),
        }
    }

    /// The object's bytes in order, as the caller reads them: [`FIRST_CHUNK`] by a
    /// ranged request, then the rest by one more, whose response is read as the
    /// caller goes, [`AHEAD`] bytes ahead of it at most (one request, not one per
    /// chunk: each costs a round trip, and some servers a copy of the object). A pass
    /// that stops early (a header read, `ulog align --end`) does not fetch the rest.
    /// Nothing is asked before the first read (then the object's size, by a `HEAD`);
    /// a failed request, or a response that ends early, is the read's
    /// [`std::io::Error`], whose source is the [`StoreError`].
    pub fn reader(&self) -> RemoteReader {
        RemoteReader {
            remote: self.clone(),
            size: None,
            fetch: Fetch::First(None),
            received: 0,
            current: ::bytes::Bytes::new(),
            used: 0,
        }
    }

    /// The whole object in memory, as a [`LogFile`] named by the URL (what commands
    /// that parse a log whole read).
    pub fn fetch(&self) -> Result<LogFile> {
        let size = self.size()?;
        let mut bytes = Vec::with_capacity(usize::try_from(size).unwrap_or(0));
        self.reader()
            .read_to_end(&mut bytes)
            .map_err(|e| StoreError::io(e, self.url()))?;
        Ok(LogFile::from_bytes(bytes, self.url()))
    }

    /// Copies the object to the local file `to`, in chunks (never held whole).
    pub fn download(&self, to: &FsPath) -> Result<u64> {
        // A missing object is said as such (not as a failed read).
        self.size()?;
        let mut reader = self.reader();
        let mut file = std::fs::File::create(to).map_err(|e| StoreError::io(e, self.url()))?;
        std::io::copy(&mut reader, &mut file).map_err(|e| StoreError::io(e, self.url()))
    }

    /// The objects below this prefix, each with its size, sorted by key.
    pub fn list(&self) -> Result<Vec<(Remote, u64)>> {
        let (store, key) = self.parts();
        let found: Vec<_> = block_on(async move {
            let prefix = (!key.as_ref().is_empty()).then_some(&key);
            store.list(prefix).try_collect::<Vec<_>>().await
        })
        .map_err(|e| self.error(e))?;
        let mut objects: Vec<(Remote, u64)> = found
            .into_iter()
            .map(|m| {
                let remote = Remote {
                    store: self.store.clone(),
                    base: self.base.clone(),
                    key: m.location,
                };
                (remote, m.size)
            })
            .collect();
        objects.sort_by(|a, b| a.0.key.as_ref().cmp(b.0.key.as_ref()));
        Ok(objects)
    }

    /// The logs this location names, each with its size, as [`LogFile::find`] finds
    /// them in a folder: the object itself, whatever its name, when it exists; else
    /// every `.ulg`/`.ulog` object (any case) below it as a prefix, sorted. Over HTTP,
    /// which cannot list, only the object itself.
    pub fn find_logs(&self) -> Result<Vec<(Remote, u64)>> {
        if !self.key.as_ref().is_empty() {
            match self.size() {
                Ok(size) => return Ok(vec![(self.clone(), size)]),
                Err(e) if *e.kind() == StoreErrorKind::NotFound && self.is_s3() => {}
                Err(e) => return Err(e),
            }
        }
        if !self.is_s3() {
            return Err(StoreError::new(StoreErrorKind::NotFound, self.url()));
        }
        let logs: Vec<_> = self
            .list()?
            .into_iter()
            .filter(|(r, _)| LogFile::is_log_name(FsPath::new(r.name())))
            .collect();
        if logs.is_empty() {
            return Err(StoreError::new(StoreErrorKind::NotFound, self.url()));
        }
        Ok(logs)
    }

    /// Writes `bytes` as the object, replacing any: one `PUT`, which a reader sees
    /// whole or not at all.
    pub fn put(&self, bytes: Vec<u8>) -> Result<()> {
        let (store, key) = self.parts();
        block_on(async move { store.put(&key, PutPayload::from(bytes)).await })
            .map(|_| ())
            .map_err(|e| self.error(e))
    }

    /// Writes `bytes` as the object only if there is none (`If-None-Match: *`):
    /// `Ok(false)` when one exists already.
    pub fn put_new(&self, bytes: Vec<u8>) -> Result<bool> {
        let options = PutOptions::from(PutMode::Create);
        let (store, key) = self.parts();
        match block_on(async move { store.put_opts(&key, PutPayload::from(bytes), options).await })
        {
            Ok(_) => Ok(true),
            Err(object_store::Error::AlreadyExists { .. })
            | Err(object_store::Error::Precondition { .. }) => Ok(false),
            Err(e) => Err(self.error(e)),
        }
    }

    /// The object's bytes, whole (small objects: a lock, a table).
    pub fn get(&self) -> Result<Vec<u8>> {
        let (store, key) = self.parts();
        let fetched = block_on(async move {
            let got = store.get(&key).await?;
            got.bytes().await
        });
        fetched.map(|b| b.to_vec()).map_err(|e| self.error(e))
    }

    /// Removes the object (nothing when there is none).
    pub fn delete(&self) -> Result<()> {
        let (store, key) = self.parts();
        match block_on(async move { store.delete(&key).await }) {
            Ok(()) | Err(object_store::Error::NotFound { .. }) => Ok(()),
            Err(e) => Err(self.error(e)),
        }
    }

    /// The key below `prefix`'s key (`None` when it is not below it).
    pub(crate) fn relative_to(&self, prefix: &Remote) -> Option<String> {
        let key = self.key.as_ref();
        let base = prefix.key.as_ref().trim_end_matches('/');
        if base.is_empty() {
            return Some(key.to_owned());
        }
        key.strip_prefix(base)?.strip_prefix('/').map(str::to_owned)
    }

    /// The store and the key, for a request that runs on the runtime.
    fn parts(&self) -> (Arc<dyn ObjectStore>, Key) {
        (self.store.clone(), self.key.clone())
    }

    fn is_s3(&self) -> bool {
        self.base.starts_with("s3://")
    }

    fn error(&self, e: object_store::Error) -> StoreError {
        StoreError::request(e, self.url())
    }
}

/// The bytes of a [`Remote`] in order ([`Remote::reader`]): a [`Read`] that a pass
/// ([`Source::reader`](crate::Source::reader)) reads like a file.
pub struct RemoteReader {
    remote: Remote,
    /// The object's size, from a `HEAD` at the first read.
    size: Option<u64>,
    fetch: Fetch,
    /// The bytes received so far.
    received: u64,
    current: ::bytes::Bytes,
    /// The bytes of `current` read.
    used: usize,
}

/// What a [`RemoteReader`] has asked for.
enum Fetch {
    /// The first chunk's request (once the size is known).
    First(Option<JoinHandle<Result<::bytes::Bytes, object_store::Error>>>),
    /// The rest's response, read into blocks by a task of the runtime.
    Rest {
        blocks: Arc<tokio::sync::Mutex<Blocks>>,
        task: JoinHandle<()>,
    },
}

type Blocks = tokio::sync::mpsc::Receiver<Result<::bytes::Bytes, object_store::Error>>;

impl RemoteReader {
    /// The object's size, once read (after the first read).
    pub fn size(&self) -> Option<u64> {
        self.size
    }

    /// Asks for the bytes from `start` to the end, read by a task into blocks.
    fn ask_rest(&mut self, start: u64, size: u64) {
        let store = self.remote.store.clone();
        let key = self.remote.key.clone();
        let (sender, blocks) =
            tokio::sync::mpsc::channel(usize::try_from(AHEAD).unwrap_or(1) / BLOCK);
        let task = runtime().spawn(async move {
            let options = object_store::GetOptions {
                range: Some(object_store::GetRange::Bounded(start..size)),
                ..Default::default()
            };
            let mut stream = match store.get_opts(&key, options).await {
                Ok(response) => response.into_stream(),
                Err(e) => {
                    let _ = sender.send(Err(e)).await;
                    return;
                }
            };
            let mut block = ::bytes::BytesMut::new();
            while let Some(frame) = futures::StreamExt::next(&mut stream).await {
                match frame {
                    Ok(frame) => {
                        block.extend_from_slice(&frame);
                        if block.len() >= BLOCK
                            && sender.send(Ok(block.split().freeze())).await.is_err()
                        {
                            return; // The reader is gone.
                        }
                    }
                    Err(e) => {
                        let _ = sender.send(Err(e)).await;
                        return;
                    }
                }
            }
            if !block.is_empty() {
                let _ = sender.send(Ok(block.freeze())).await;
            }
        });
        self.fetch = Fetch::Rest {
            blocks: Arc::new(tokio::sync::Mutex::new(blocks)),
            task,
        };
    }

    /// The next bytes: `None` at the end of the object.
    fn next_bytes(&mut self) -> std::io::Result<Option<::bytes::Bytes>> {
        let size = self.size.unwrap_or(0);
        if self.received >= size {
            return Ok(None);
        }
        let got = match &mut self.fetch {
            Fetch::First(first) => {
                let first = first.take().unwrap_or_else(|| {
                    let store = self.remote.store.clone();
                    let key = self.remote.key.clone();
                    let range = 0..FIRST_CHUNK.min(size);
                    runtime().spawn(async move { store.get_range(&key, range).await })
                });
                let got = block_on(first).map_err(std::io::Error::other)?;
                let got = got.map_err(|e| std::io::Error::from(self.remote.error(e)))?;
                // The rest asked for at once, while the caller reads this.
                let end = self.received + got.len() as u64;
                if end < size {
                    self.ask_rest(end, size);
                }
                Some(got)
            }
            Fetch::Rest { blocks, .. } => {
                let blocks = blocks.clone();
                block_on(async move { blocks.lock().await.recv().await })
                    .transpose()
                    .map_err(|e| std::io::Error::from(self.remote.error(e)))?
            }
        };
        match got {
            Some(bytes) if !bytes.is_empty() => {
                self.received += bytes.len() as u64;
                Ok(Some(bytes))
            }
            _ => {
                let short = std::io::Error::new(
                    std::io::ErrorKind::UnexpectedEof,
                    format!(
                        "the response ended at byte {} of the object's {size}",
                        self.received
                    ),
                );
                Err(StoreError::io(short, self.remote.url()).into())
            }
        }
    }
}

impl Read for RemoteReader {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.size.is_none() {
            self.size = Some(self.remote.size()?);
        }
        if self.used == self.current.len() {
            match self.next_bytes()? {
                Some(bytes) => {
                    self.current = bytes;
                    self.used = 0;
                }
                None => return Ok(0),
            }
        }
        let n = buf.len().min(self.current.len() - self.used);
        buf[..n].copy_from_slice(&self.current[self.used..self.used + n]);
        self.used += n;
        Ok(n)
    }
}

impl Drop for RemoteReader {
    fn drop(&mut self) {
        // The response not read is dropped with its connection.
        match &self.fetch {
            Fetch::First(Some(first)) => first.abort(),
            Fetch::Rest { task, .. } => task.abort(),
            Fetch::First(None) => {}
        }
    }
}

/// The runtime every request runs on: two worker threads, made at the first request.
/// Callers block on it from their own threads (a pass, a conversion's threads).
fn runtime() -> &'static Runtime {
    static RUNTIME: OnceLock<Runtime> = OnceLock::new();
    RUNTIME.get_or_init(|| {
        tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .thread_name("ulog-store")
            .enable_all()
            .build()
            .expect("a Tokio runtime can be made")
    })
}

/// Runs `f` on the runtime and waits for it on this thread: from any thread, one of
/// another async runtime's included (whose thread it then blocks), where a
/// `Runtime::block_on` would panic.
pub(crate) fn block_on<F>(f: F) -> F::Output
where
    F: core::future::Future + Send + 'static,
    F::Output: Send + 'static,
{
    let (sender, receiver) = std::sync::mpsc::sync_channel(1);
    runtime().spawn(async move {
        let _ = sender.send(f.await);
    });
    receiver
        .recv()
        .expect("the runtime's threads run every request to its end")
}

/// The store of `base` (`s3://bucket`, `https://host`), made once per process.
fn store_of(scheme: &str, authority: &str, base: &str) -> Result<Arc<dyn ObjectStore>> {
    static STORES: OnceLock<Mutex<HashMap<String, Arc<dyn ObjectStore>>>> = OnceLock::new();
    let mut stores = STORES
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|p| p.into_inner());
    if let Some(store) = stores.get(base) {
        return Ok(store.clone());
    }
    let failed = |e: object_store::Error| StoreError::request(e, base);
    let store: Arc<dyn ObjectStore> = match scheme {
        "s3" => {
            let mut builder =
                object_store::aws::AmazonS3Builder::from_env().with_bucket_name(authority);
            // An endpoint the environment names over plain HTTP (an S3-compatible
            // server on this machine or network) is one the user chose.
            let endpoint = std::env::var("AWS_ENDPOINT_URL")
                .or_else(|_| std::env::var("AWS_ENDPOINT"))
                .unwrap_or_default();
            if endpoint.to_ascii_lowercase().starts_with("http://") {
                builder = builder.with_allow_http(true);
            }
            Arc::new(builder.build().map_err(failed)?)
        }
        "http" | "https" => {
            let options = object_store::ClientOptions::new().with_allow_http(scheme == "http");
            Arc::new(
                object_store::http::HttpBuilder::new()
                    .with_url(base)
                    .with_client_options(options)
                    .build()
                    .map_err(failed)?,
            )
        }
        _ => return Err(StoreError::new(StoreErrorKind::BadUrl, base)),
    };
    stores.insert(base.to_owned(), store.clone());
    Ok(store)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn urls_and_paths_are_told_apart() {
        assert!(matches!(Location::parse("a/b.ulg"), Ok(Location::Local(_))));
        let Ok(Location::Remote(r)) = Location::parse("S3://fleet/a/b.ulg") else {
            panic!("an s3 URL")
        };
        assert_eq!(
            (r.url(), r.name()),
            ("s3://fleet/a/b.ulg".to_owned(), "b.ulg")
        );
        assert_eq!(r.join("x/y").url(), "s3://fleet/a/b.ulg/x/y");
        assert!(Remote::parse("s3:///key").is_err());
    }

    /// A request made from inside another async runtime (a user's) blocks that thread
    /// until it is answered, instead of panicking as `Runtime::block_on` would; a
    /// server that is not there is an error, not a panic.
    #[test]
    fn requests_work_from_inside_another_runtime() {
        let theirs = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("a runtime");
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        let result = theirs.block_on(async move {
            Remote::parse(&format!("http://127.0.0.1:{port}/x.ulg"))
                .expect("an http URL")
                .size()
        });
        let e = result.expect_err("nothing listens there");
        assert_eq!(*e.kind(), StoreErrorKind::Request);
        assert!(e
            .to_string()
            .starts_with(&format!("http://127.0.0.1:{port}/x.ulg: ")));
    }

    /// An HTTP server on 127.0.0.1 serving one object of `size` bytes (byte `i` is
    /// `i % 251`), `HEAD` and ranged `GET`s, a connection each; a `GET`'s response
    /// stops after `cut` bytes of its body if given (a connection lost). Counts the
    /// body bytes it managed to send.
    fn serve(size: u64, cut: Option<u64>) -> (String, Arc<std::sync::atomic::AtomicU64>) {
        use std::io::{BufRead, BufReader, Write};
        let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("a port");
        let url = format!("http://{}/log.ulg", listener.local_addr().expect("addr"));
        let sent = Arc::new(std::sync::atomic::AtomicU64::new(0));
        let counted = sent.clone();
        std::thread::spawn(move || {
            for stream in listener.incoming().flatten() {
                let sent = counted.clone();
                std::thread::spawn(move || {
                    let mut reader = BufReader::new(stream.try_clone().expect("clone"));
                    let mut stream = stream;
                    let (mut head, mut range) = (false, None);
                    let mut line = String::new();
                    while reader.read_line(&mut line).is_ok_and(|n| n > 0) {
                        let l = line.trim_end().to_ascii_lowercase();
                        if l.is_empty() {
                            break;
                        }
                        head |= l.starts_with("head ");
                        if let Some(r) = l.strip_prefix("range: bytes=") {
                            let (a, b) = r.split_once('-').expect("a-b");
                            let a: u64 = a.parse().expect("start");
                            let b: u64 = b.parse().map_or(size - 1, |b: u64| b.min(size - 1));
                            range = Some((a, b));
                        }
                        line.clear();
                    }
                    let (a, b) = range.unwrap_or((0, size - 1));
                    let status = if range.is_some() {
                        "206 Partial Content"
                    } else {
                        "200 OK"
                    };
                    let header = format!(
                        "HTTP/1.1 {status}\r\nContent-Length: {}\r\nContent-Range: bytes {a}-{b}/{size}\r\nAccept-Ranges: bytes\r\nConnection: close\r\n\r\n",
                        if head { size } else { b - a + 1 }
                    );
                    if stream.write_all(header.as_bytes()).is_err() || head {
                        return;
                    }
                    let end = cut.map_or(b + 1, |c| (a + c).min(b + 1));
                    let mut at = a;
                    while at < end {
                        let n = (end - at).min(64 << 10);
                        let body: Vec<u8> = (at..at + n).map(|i| (i % 251) as u8).collect();
                        if stream.write_all(&body).is_err() {
                            return; // The client closed the connection.
                        }
                        sent.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
                        at += n;
                    }
                });
            }
        });
        (url, sent)
    }

    #[test]
    fn a_reader_reads_the_object_in_order_and_stops_fetching_when_dropped() {
        let size = 48 << 20;
        let (url, sent) = serve(size, None);
        let remote = Remote::parse(&url).expect("an http URL");
        let mut all = Vec::new();
        remote.reader().read_to_end(&mut all).expect("read");
        assert_eq!(all.len() as u64, size);
        assert!(all.iter().enumerate().all(|(i, b)| *b == (i % 251) as u8));

        // A reader dropped after 2 MiB: the server sends the first chunk, what the
        // reader holds ahead and what the connection buffers, not the rest. (Of a
        // larger object: on a loaded machine the connection took 25 MB of 48 MB before
        // the drop reached it, in one CI run.)
        let size = 256 << 20;
        let (url, sent_early) = serve(size, None);
        let mut reader = Remote::parse(&url).expect("url").reader();
        let mut first = vec![0; 2 << 20];
        reader.read_exact(&mut first).expect("2 MiB");
        std::thread::sleep(std::time::Duration::from_millis(300));
        drop(reader);
        std::thread::sleep(std::time::Duration::from_millis(300));
        let early = sent_early.load(std::sync::atomic::Ordering::Relaxed);
        assert!(early < size / 4, "{early} of {size} bytes sent");
        assert!(sent.load(std::sync::atomic::Ordering::Relaxed) >= 48 << 20);
    }

    #[test]
    fn a_response_that_ends_early_is_an_error_not_a_short_object() {
        let size = 4 << 20;
        let (url, _) = serve(size, Some(1 << 20));
        let mut all = Vec::new();
        let e = Remote::parse(&url)
            .expect("url")
            .reader()
            .read_to_end(&mut all)
            .expect_err("the object is cut short");
        assert!(all.len() < size as usize);
        // reqwest's error for a body shorter than its length, or ours for a response
        // that ends early without one.
        let text = e.to_string();
        assert!(
            text.contains("body") || text.contains("ended at byte"),
            "{text}"
        );
    }
}
