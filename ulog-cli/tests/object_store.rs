//! Logs read from, and datasets written to, object storage: a real S3-compatible
//! server (moto's, from PyPI) started on 127.0.0.1 by each test, logs put into it with
//! boto3, and datasets read back with pyarrow's S3 filesystem; never a mock of the
//! client.
//!
//! - Every way a command reads a log (whole, one pass, twice, the first bytes, a
//!   stream) reads `s3://` and `http://` URLs as it reads the file: the same output,
//!   byte for byte, but for the name.
//! - `ulog parquet s3://…/ -o s3://…` writes the dataset `ulog parquet` writes
//!   locally: the same files, the same rows (but `logs.path`, the URL), read back by
//!   pyarrow; converting again skips every log; two conversions at once both land.
//! - A conversion killed at any point, then run again, leaves a consistent dataset:
//!   every log `logs.parquet` lists has its topic files, and no topic file lacks its
//!   row; a lock left by a dead process is taken over.
//! - A missing object, a missing prefix, and an unreachable server are clear errors.

mod common;

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value as Json;

/// An S3-compatible server (moto) on a free port of 127.0.0.1, stopped when dropped.
struct S3Server {
    child: Child,
    endpoint: String,
    /// The authority that signed the certificate of a server started with TLS
    /// ([`S3Server::start_tls`]).
    cert: Option<PathBuf>,
}

impl S3Server {
    fn start() -> S3Server {
        S3Server::start_with(None)
    }

    /// A server that speaks HTTPS only, with a certificate for 127.0.0.1 made in
    /// `dir` by an authority its clients are told to trust (`SSL_CERT_FILE`,
    /// `AWS_CA_BUNDLE`).
    fn start_tls(dir: &Path) -> S3Server {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/s3_check.py");
        let made = Command::new("python3")
            .arg(script)
            .arg("tls-cert")
            .arg(dir)
            .status()
            .expect("run python3");
        assert!(made.success(), "no certificate made");
        S3Server::start_with(Some(dir))
    }

    fn start_with(tls: Option<&Path>) -> S3Server {
        let port = TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        let mut command = Command::new("python3");
        command.args([
            "-m",
            "moto.server",
            "-H",
            "127.0.0.1",
            "-p",
            &port.to_string(),
        ]);
        if let Some(dir) = tls {
            command
                .arg("-c")
                .arg(dir.join("cert.pem"))
                .arg("-k")
                .arg(dir.join("key.pem"));
        }
        let child = command
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start moto's server");
        let scheme = if tls.is_some() { "https" } else { "http" };
        let server = S3Server {
            child,
            endpoint: format!("{scheme}://127.0.0.1:{port}"),
            cert: tls.map(|d| d.join("ca.pem")),
        };
        let start = Instant::now();
        while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "moto's server did not start"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
        server
    }

    /// The standard AWS environment that points at this server (and trusts its
    /// certificate).
    fn env(&self) -> Vec<(&'static str, String)> {
        let mut env = vec![
            ("AWS_ENDPOINT_URL", self.endpoint.clone()),
            ("AWS_ACCESS_KEY_ID", "testing".to_owned()),
            ("AWS_SECRET_ACCESS_KEY", "testing".to_owned()),
            ("AWS_DEFAULT_REGION", "us-east-1".to_owned()),
        ];
        if let Some(cert) = &self.cert {
            let cert = cert.display().to_string();
            env.push(("SSL_CERT_FILE", cert.clone()));
            env.push(("AWS_CA_BUNDLE", cert));
        }
        env
    }

    fn command(&self, program: &str) -> Command {
        let mut c = Command::new(program);
        c.envs(self.env());
        c
    }

    fn ulog<I, S>(&self, args: I) -> Output
    where
        I: IntoIterator<Item = S>,
        S: AsRef<std::ffi::OsStr>,
    {
        self.command(env!("CARGO_BIN_EXE_ulog"))
            .args(args)
            .output()
            .expect("run ulog")
    }

    /// `tests/scripts/s3_check.py` with `args`: its stdout.
    fn script<I, S>(&self, args: I) -> Vec<u8>
    where
        I: IntoIterator<Item = S>,
        S: AsRef<std::ffi::OsStr>,
    {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scripts/s3_check.py");
        let out = self
            .command("python3")
            .arg(script)
            .args(args)
            .output()
            .expect("run python3");
        assert!(
            out.status.success(),
            "s3_check.py failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        out.stdout
    }

    fn json<I, S>(&self, args: I) -> Json
    where
        I: IntoIterator<Item = S>,
        S: AsRef<std::ffi::OsStr>,
    {
        serde_json::from_slice(&self.script(args)).expect("json")
    }

    /// Puts `logs` into `s3://bucket/prefix/` (readable without credentials too, for
    /// the `http://` URLs, when `public`).
    fn upload(&self, bucket: &str, prefix: &str, logs: &[PathBuf], public: bool) {
        let mut args: Vec<std::ffi::OsString> = vec!["upload".into(), bucket.into(), prefix.into()];
        if public {
            args.push("--public".into());
        }
        args.extend(logs.iter().map(|p| p.as_os_str().to_owned()));
        self.script(args);
    }
}

impl Drop for S3Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn logs() -> Vec<PathBuf> {
    common::corpus_logs(&common::corpus())
        .into_iter()
        .map(|(_, p)| p)
        .collect()
}

fn named(stem: &str) -> PathBuf {
    common::corpus().join("files").join(format!("{stem}.ulg"))
}

fn ok(out: &Output, what: &str) {
    assert!(
        out.status.success(),
        "{what}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
#[cfg_attr(
    not(s3_server),
    ignore = "needs python3 with moto[server], boto3 and pyarrow (pip install 'moto[server]' boto3 pyarrow)"
)]
fn every_way_of_reading_a_log_reads_s3_and_http_urls_as_files() {
    let server = S3Server::start();
    let all = logs();
    server.upload("fleet", "logs", &all, true);
    let scratch = common::scratch("object_store_commands");

    // Commands whose stdout is the output: the name of the log replaced.
    for log in &all {
        let name = log.file_name().unwrap().to_string_lossy().into_owned();
        let path = log.display().to_string();
        for url in [
            format!("s3://fleet/logs/{name}"),
            format!("{}/fleet/logs/{name}", server.endpoint),
        ] {
            for command in [
                &["info"][..],
                &["messages"],
                &["params"],
                &["check"],
                &["dump"],
            ] {
                let here = server.ulog(command.iter().copied().chain([path.as_str()]));
                let there = server.ulog(command.iter().copied().chain([url.as_str()]));
                assert_eq!(
                    here.status.code(),
                    there.status.code(),
                    "{command:?} {url}: {}",
                    String::from_utf8_lossy(&there.stderr)
                );
                let there_text = String::from_utf8_lossy(&there.stdout).replace(&url, &path);
                assert!(
                    String::from_utf8_lossy(&here.stdout) == there_text,
                    "{command:?} {url}: the output differs from the file's"
                );
            }
        }
    }

    // Commands that write files: the same bytes. Every way `ulog` reads a log: whole
    // (csv, anonymise, codegen), one pass kept (kml, align), twice (analyze), the first
    // bytes then a pass (cut), a stream (mcap, align --one-pass), per-log Parquet.
    for stem in ["sample_appended_multiple", "esc_status_log"] {
        let log = named(stem);
        let url = format!("s3://fleet/logs/{stem}.ulg");
        let mut commands: Vec<&[&str]> = vec![
            &["csv", "{LOG}", "-o", "{OUT}"],
            &["anonymise", "{LOG}", "-o", "{OUT}/a.ulg"],
            &["codegen", "{LOG}", "-o", "{OUT}/bindings.rs"],
            &[
                "align",
                "{LOG}",
                "vehicle_attitude",
                "--rate",
                "20",
                "-o",
                "{OUT}/a.csv",
            ],
            &[
                "align",
                "{LOG}",
                "vehicle_attitude",
                "--rate",
                "20",
                "--one-pass",
                "-o",
                "{OUT}/b.csv",
            ],
            &[
                "cut",
                "{LOG}",
                "--start",
                "1",
                "--end",
                "5",
                "-o",
                "{OUT}/cut.ulg",
            ],
            &["mcap", "{LOG}", "-o", "{OUT}/log.mcap"],
            &["parquet", "{LOG}", "--per-log", "-o", "{OUT}"],
        ];
        if stem == "esc_status_log" {
            // The one of the two with a GPS track.
            commands.push(&["kml", "{LOG}", "-o", "{OUT}/track.kml"]);
        }
        for command in commands {
            let mut outputs = Vec::new();
            for (i, input) in [log.display().to_string(), url.clone()].iter().enumerate() {
                let out_dir = scratch.join(format!("{stem}-{}-{i}", command[0]));
                std::fs::create_dir_all(&out_dir).unwrap();
                let args: Vec<String> = command
                    .iter()
                    .map(|a| {
                        a.replace("{LOG}", input)
                            .replace("{OUT}", &out_dir.display().to_string())
                    })
                    .collect();
                ok(&server.ulog(&args), &format!("{args:?}"));
                outputs.push(common::files(&out_dir));
            }
            assert!(!outputs[0].is_empty(), "{command:?} wrote nothing");
            let (here, there) = (&outputs[0], &outputs[1]);
            assert_eq!(
                here.keys().collect::<Vec<_>>(),
                there.keys().collect::<Vec<_>>(),
                "{command:?} {stem}"
            );
            for (rel, bytes) in here {
                // The per-log metadata and the KML name their source.
                let there_bytes = String::from_utf8_lossy(&there[rel])
                    .replace(&url, &log.display().to_string())
                    .into_bytes();
                assert!(
                    *bytes == there[rel] || *bytes == there_bytes,
                    "{command:?} {stem}: {} differs",
                    rel.display()
                );
            }
        }
        // analyze: the same findings (the JSON names its file).
        let here = server.ulog(["analyze", "--json", &log.display().to_string()]);
        let there = server.ulog(["analyze", "--json", &url]);
        ok(&there, "analyze");
        assert_eq!(
            String::from_utf8_lossy(&here.stdout),
            String::from_utf8_lossy(&there.stdout).replace(&url, &log.display().to_string())
        );
    }

    // Clear errors: a missing object, a missing prefix, a server not there.
    let missing = server.ulog(["info", "s3://fleet/logs/nope.ulg"]);
    assert_eq!(missing.status.code(), Some(3));
    let text = String::from_utf8_lossy(&missing.stderr);
    assert!(
        text.contains("s3://fleet/logs/nope.ulg") && text.contains("no such object"),
        "{text}"
    );
    let none = server.ulog(["parquet", "s3://fleet/nothing/", "-o", "x"]);
    assert_eq!(none.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&none.stderr).contains("no .ulg or .ulog objects below it"));
    let port = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let closed = Command::new(env!("CARGO_BIN_EXE_ulog"))
        .args(["info", "s3://fleet/logs/powers.ulg"])
        .envs(server.env())
        .env("AWS_ENDPOINT_URL", format!("http://127.0.0.1:{port}"))
        .env("AWS_MAX_RETRIES", "0")
        .output()
        .unwrap();
    assert_eq!(closed.status.code(), Some(3));
    assert!(String::from_utf8_lossy(&closed.stderr).contains("s3://fleet/logs/powers.ulg: "));
}

#[test]
#[cfg_attr(
    not(s3_server),
    ignore = "needs python3 with moto[server], boto3 and pyarrow (pip install 'moto[server]' boto3 pyarrow)"
)]
fn a_dataset_written_to_s3_is_the_local_one_as_pyarrow_reads_it() {
    let server = S3Server::start();
    let all = logs();
    let (first, rest) = all.split_at(all.len() / 2);
    server.upload("fleet", "logs", &all, false);
    let scratch = common::scratch("object_store_dataset");
    let local = scratch.join("local");
    ok(
        &server.ulog(
            ["parquet".as_ref(), "-o".as_ref(), local.as_os_str()]
                .into_iter()
                .chain(all.iter().map(|p| p.as_os_str())),
        ),
        "local dataset",
    );

    // Half the logs from the bucket, then all of them from the bucket and one path:
    // the second adds only what the first lacked.
    let urls = |logs: &[PathBuf]| -> Vec<String> {
        logs.iter()
            .map(|p| {
                format!(
                    "s3://fleet/logs/{}",
                    p.file_name().unwrap().to_string_lossy()
                )
            })
            .collect()
    };
    let mut args = vec!["parquet".to_owned(), "-o".into(), "s3://fleet/ds".into()];
    args.extend(urls(first));
    ok(&server.ulog(&args), "first half");
    let second = server.ulog(["parquet", "s3://fleet/logs/", "-o", "s3://fleet/ds"]);
    ok(&second, "all");
    let said = String::from_utf8_lossy(&second.stdout);
    assert_eq!(said.matches("Skipping").count(), first.len(), "{said}");
    assert_eq!(said.matches("Adding").count(), rest.len(), "{said}");

    let compared = server.json(["compare", "fleet", "ds", &local.display().to_string()]);
    assert_eq!(compared["remote_only"], Json::Array(vec![]), "{compared}");
    assert_eq!(compared["local_only"], Json::Array(vec![]), "{compared}");
    assert_eq!(compared["differ"], Json::Array(vec![]), "{compared}");
    assert_eq!(
        compared["compared"].as_u64(),
        Some(common::files(&local).len() as u64)
    );
    // logs.path names each log's URL.
    let mut paths: Vec<String> = compared["paths"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_str().unwrap().to_owned())
        .collect();
    paths.sort();
    let mut want = urls(&all);
    want.sort();
    assert_eq!(paths, want);

    // Nothing but the dataset's files is left in the bucket.
    let keys: Vec<String> =
        serde_json::from_slice(&server.script(["keys", "fleet", "ds/"])).unwrap();
    assert!(
        !keys
            .iter()
            .any(|k| k.contains(".lock") || k.contains("partial")),
        "{keys:?}"
    );

    // Two conversions at once into a new prefix: the second waits, both land.
    let spawn = |logs: &[String]| {
        server
            .command(env!("CARGO_BIN_EXE_ulog"))
            .args(["parquet", "-o", "s3://fleet/both"])
            .args(logs)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let a = spawn(&urls(first));
    let b = spawn(&urls(rest));
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    ok(&a, "first of two at once");
    ok(&b, "second of two at once");
    let state = server.json(["consistent", "fleet", "both"]);
    assert_eq!(
        state["logs"].as_array().unwrap().len(),
        all.len(),
        "{state}"
    );
    assert_eq!(state["without_files"], Json::Array(vec![]));
    assert_eq!(state["files_without_log"], Json::Array(vec![]));
    assert_eq!(state["lock"], Json::Bool(false));
}

#[test]
#[cfg_attr(
    not(s3_server),
    ignore = "needs python3 with moto[server], boto3 and pyarrow (pip install 'moto[server]' boto3 pyarrow)"
)]
fn logs_are_read_over_https_and_the_servers_certificate_is_checked() {
    let scratch = common::scratch("object_store_tls");
    let server = S3Server::start_tls(&scratch);
    assert!(server.endpoint.starts_with("https://"));
    let log = named("sample_appended_multiple");
    server.upload("secure", "logs", std::slice::from_ref(&log), true);
    let path = log.display().to_string();
    let name = log.file_name().unwrap().to_string_lossy().into_owned();
    let here = server.ulog(["info", path.as_str()]);
    ok(&here, "info of the file");
    let urls = [
        format!("s3://secure/logs/{name}"),
        format!("{}/secure/logs/{name}", server.endpoint),
    ];
    for url in &urls {
        let there = server.ulog(["info", url.as_str()]);
        ok(&there, url);
        let text = String::from_utf8_lossy(&there.stdout).replace(url.as_str(), &path);
        assert_eq!(text, String::from_utf8_lossy(&here.stdout), "{url}");
    }
    // A dataset written over TLS.
    let out = server.ulog(["parquet", urls[0].as_str(), "-o", "s3://secure/ds"]);
    ok(&out, "parquet over TLS");
    let keys: Vec<String> =
        serde_json::from_slice(&server.script(["keys", "secure", "ds/"])).unwrap();
    assert!(keys.iter().any(|k| k == "ds/logs.parquet"), "{keys:?}");

    // Without the certificate trusted, the server is refused: an error, not a read.
    for url in &urls {
        let refused = Command::new(env!("CARGO_BIN_EXE_ulog"))
            .envs(
                server
                    .env()
                    .into_iter()
                    .filter(|(k, _)| !k.ends_with("CERT_FILE")),
            )
            .args(["info", url.as_str()])
            .output()
            .expect("run ulog");
        assert!(
            !refused.status.success(),
            "{url} read without trusting its certificate"
        );
        let said = String::from_utf8_lossy(&refused.stderr);
        assert!(said.starts_with(&format!("ulog: {url}: ")), "{said}");
    }
}

#[test]
#[cfg_attr(
    not(s3_server),
    ignore = "needs python3 with moto[server], boto3 and pyarrow (pip install 'moto[server]' boto3 pyarrow)"
)]
fn a_fleet_layout_dataset_written_to_s3_is_the_local_one() {
    let server = S3Server::start();
    let all = logs();
    server.upload("fleet", "logs", &all, false);
    let scratch = common::scratch("object_store_fleet_layout");
    let local = scratch.join("local");
    let layout = ["--layout", "fleet", "--partition-by", "vehicle,month"];
    let mut args: Vec<std::ffi::OsString> =
        vec!["parquet".into(), "-o".into(), local.clone().into()];
    args.extend(all.iter().map(|p| p.as_os_str().to_owned()));
    args.extend(layout.iter().map(|s| (*s).into()));
    ok(&server.ulog(&args), "local dataset");

    // A file left by a conversion that died (its first log not listed) is removed.
    let stray = "ds/vehicle_status/vehicle=x/month=2024-02/0123456789abcdef.parquet";
    server.script(["put", "fleet", stray, "PAR1"]);
    let mut args = vec!["parquet", "s3://fleet/logs/", "-o", "s3://fleet/ds"];
    args.extend(layout);
    ok(&server.ulog(&args), "s3 dataset");

    let compared = server.json(["compare", "fleet", "ds", &local.display().to_string()]);
    assert_eq!(compared["remote_only"], Json::Array(vec![]), "{compared}");
    assert_eq!(compared["local_only"], Json::Array(vec![]), "{compared}");
    assert_eq!(compared["differ"], Json::Array(vec![]), "{compared}");
    let files = common::files(&local);
    assert!(files
        .keys()
        .any(|p| p.to_string_lossy().contains("/month=")));
    assert_eq!(compared["compared"].as_u64(), Some(files.len() as u64));

    // The dataset keeps its layout: logs added to it without `--layout` go into new
    // partition files; another layout is refused.
    let other = server.ulog([
        "parquet",
        "s3://fleet/logs/",
        "-o",
        "s3://fleet/ds",
        "--layout",
        "file-per-log",
    ]);
    assert!(!other.status.success());
    let said = String::from_utf8_lossy(&other.stderr);
    assert!(said.contains("layout"), "{said}");

    // Compaction rewrites files in place: refused in a store, saying what to do.
    let compact = server.ulog(["parquet", "--compact", "-o", "s3://fleet/ds"]);
    assert!(!compact.status.success());
    let said = String::from_utf8_lossy(&compact.stderr);
    assert!(said.contains("compact a local copy"), "{said}");
}

#[test]
#[cfg_attr(
    not(s3_server),
    ignore = "needs python3 with moto[server], boto3 and pyarrow (pip install 'moto[server]' boto3 pyarrow)"
)]
fn a_conversion_killed_at_any_point_then_run_again_leaves_a_consistent_dataset() {
    let server = S3Server::start();
    let all = logs();
    server.upload("fleet", "logs", &all, false);

    // A lock left by a process of this machine that is gone, and topic files of a
    // log the table of logs does not list (a conversion killed after its uploads):
    // taken over, and removed.
    let dead = Command::new("true").spawn().unwrap();
    let pid = dead.id();
    let mut dead = dead;
    dead.wait().unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_owned())
        .unwrap_or_default();
    if !host.is_empty() {
        server.script([
            "put",
            "fleet",
            "left/.ulog-dataset.lock",
            &format!("pid {pid}\nhost {host}\n"),
        ]);
    }
    server.script([
        "put",
        "fleet",
        "left/vehicle_status/0123456789abcdef.parquet",
        "x",
    ]);
    let started = Instant::now();
    let run = server.ulog(["parquet", "s3://fleet/logs/", "-o", "s3://fleet/left"]);
    let whole = started.elapsed();
    ok(&run, "over a dead lock and leftovers");
    assert!(String::from_utf8_lossy(&run.stderr).contains("removed 1 topic file"));
    let state = server.json(["consistent", "fleet", "left"]);
    assert_eq!(
        state["logs"].as_array().unwrap().len(),
        all.len(),
        "{state}"
    );
    assert_eq!(state["files_without_log"], Json::Array(vec![]), "{state}");
    assert_eq!(state["lock"], Json::Bool(false));

    // SIGKILL at several moments of a conversion (from its start to its uploads,
    // which come last, as fractions of how long a whole one took), then again to the
    // end: consistent at every step that can be seen.
    for (i, fraction) in [0.2, 0.5, 0.8, 0.9, 0.97].into_iter().enumerate() {
        let after_ms = (whole.as_secs_f64() * fraction * 1e3) as u64;
        let prefix = format!("killed{i}");
        let mut child = server
            .command(env!("CARGO_BIN_EXE_ulog"))
            .args([
                "parquet",
                "s3://fleet/logs/",
                "-o",
                &format!("s3://fleet/{prefix}"),
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(after_ms));
        let _ = child.kill();
        let _ = child.wait();
        let seen = server.json(["consistent", "fleet", &prefix]);
        assert_eq!(seen["without_files"], Json::Array(vec![]), "{seen}");
        // Whatever a reader sees, the logs it lists are whole.
        let again = server.ulog([
            "parquet",
            "s3://fleet/logs/",
            "-o",
            &format!("s3://fleet/{prefix}"),
        ]);
        ok(&again, "after a kill");
        let state = server.json(["consistent", "fleet", &prefix]);
        assert_eq!(
            state["logs"].as_array().unwrap().len(),
            all.len(),
            "{state}"
        );
        assert_eq!(state["without_files"], Json::Array(vec![]), "{state}");
        assert_eq!(state["files_without_log"], Json::Array(vec![]), "{state}");
        assert_eq!(state["lock"], Json::Bool(false), "{state}");
    }
}
