// What the tests of a package can check, for its build script (`include!`d by
// `tests/build.rs` and `ulog-cli/build.rs`, so that both follow one rule).
//
// The corpus of real logs: the folder `$ULOG_CORPUS` names (absolute, or relative to
// the package), else the full shared corpus beside the workspace (`../shared/corpus`),
// else the repository's own five logs (`tests/corpus`). It reaches the tests as
// `ULOG_TESTS_CORPUS`; `cfg(full_corpus)` is set unless it is the repository's own
// (tests that need a log only the full corpus has are `ignore`d then). `cfg(pyulog)`
// is set where `python3` can import pyulog (tests that run it are `ignore`d
// otherwise; install it, then touch the build script to rebuild them),
// `cfg(simplekml)` where it can import simplekml too (pyulog's `ulog2kml`), and
// `cfg(mcap_readers)` where it can import `mcap`, `mcap_ros2`, `rosbags` and
// `jsonschema`, `cfg(query_engines)` where it can import `duckdb`, `datafusion` and `xxhash`
// (which run the README's fleet queries), `cfg(pandas)` where it can import pyulog,
// `pandas` and `numpy` (which `ulog align` is checked with), `cfg(pyarrow)` where it can
// import `pyarrow` (which reads the Parquet tables of `ulog align`), `cfg(s3_server)` where it
// can import moto's server, boto3 and pyarrow (an S3 server on 127.0.0.1, for object storage); `cfg(chromium)` where `/usr/bin/chromium`
// exists and `node` can require `playwright-core` from `target/node` of the workspace
// (`.ci/run` installs it; the reports' browser tests are `ignore`d otherwise);
// `cfg(flight_review)` where flight-review-rs's `ulog-convert` is built
// (`$ULOG_FLIGHT_REVIEW`, else where `python3 bench/source_peers.py flight-review`
// builds it), reaching the tests as `ULOG_TESTS_FLIGHT_REVIEW`. With
// `ULOG_REQUIRE_ALL_TESTS` set (CI, which has both), a missing corpus or pyulog fails
// the build instead, so that no test is ignored there.

/// Probes the corpus and pyulog for the package whose build script this is; `shared`
/// and `own` are the two corpus folders relative to the package. Returns the corpus.
fn probe(shared: &str, own: &str) -> std::path::PathBuf {
    use std::path::Path;
    println!(
        "cargo::rustc-check-cfg=cfg(full_corpus, pyulog, simplekml, mcap_readers, query_engines, pandas, pyarrow, s3_server, chromium, flight_review)"
    );
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=../tests/probe.rs");
    println!("cargo::rerun-if-env-changed=ULOG_CORPUS");
    println!("cargo::rerun-if-env-changed=ULOG_REQUIRE_ALL_TESTS");
    let require = std::env::var_os("ULOG_REQUIRE_ALL_TESTS").is_some();
    let manifest = std::env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR");
    let manifest = Path::new(&manifest);
    let corpus = match std::env::var_os("ULOG_CORPUS") {
        Some(dir) => manifest.join(dir),
        None if manifest.join(shared).join("files").is_dir() => manifest.join(shared),
        None => manifest.join(own),
    };
    let corpus = corpus
        .canonicalize()
        .unwrap_or_else(|e| panic!("the corpus of real logs {}: {e}", corpus.display()));
    let own = manifest.join(own).canonicalize().expect("tests/corpus");
    if corpus != own {
        println!("cargo::rustc-cfg=full_corpus");
    } else if require {
        panic!(
            "ULOG_REQUIRE_ALL_TESTS is set but the full corpus is absent \
             (../shared/corpus beside the workspace, or $ULOG_CORPUS)"
        );
    }
    println!("cargo::rustc-env=ULOG_TESTS_CORPUS={}", corpus.display());
    println!("cargo::rerun-if-changed={}", corpus.join("files").display());
    // The Python packages the tests check our output with: pyulog, the reference
    // reader; simplekml, which pyulog's `ulog2kml` writes its KML with; Foxglove's
    // MCAP readers (`mcap`, `mcap-ros2-support`), `rosbags` and `jsonschema`, which read
    // and validate the MCAP files and ROS 2 bags we write; DuckDB and DataFusion, which
    // query the Parquet datasets we write; pyarrow, which reads the Parquet tables of
    // `ulog align`.
    let packages = [
        ("pyulog", "pyulog", "pyulog"),
        ("simplekml", "pyulog, simplekml", "simplekml"),
        (
            "mcap_readers",
            "mcap, mcap_ros2, rosbags, jsonschema",
            "mcap, mcap-ros2-support, rosbags or jsonschema",
        ),
        ("query_engines", "duckdb, datafusion, xxhash", "duckdb, datafusion or xxhash"),
        ("pandas", "pyulog, pandas, numpy", "pandas or numpy"),
        ("pyarrow", "pyarrow", "pyarrow"),
        (
            "s3_server",
            "moto.server, boto3, pyarrow.fs",
            "moto[server] or boto3 (the S3 server and client of the object-storage tests)",
        ),
    ];
    for (cfg, imports, what) in packages {
        let found = std::process::Command::new("python3")
            .args(["-c", &format!("import {imports}")])
            .output()
            .is_ok_and(|o| o.status.success());
        if found {
            println!("cargo::rustc-cfg={cfg}");
        } else if require {
            panic!("ULOG_REQUIRE_ALL_TESTS is set but python3 cannot import {what}");
        }
    }
    // Headless Chromium driven by playwright-core (npm) with the system's browser, for
    // the reports' page checks.
    let node_path = manifest.join("../target/node/node_modules");
    println!(
        "cargo::rustc-env=ULOG_TESTS_NODE_PATH={}",
        node_path.display()
    );
    let found = Path::new("/usr/bin/chromium").exists()
        && std::process::Command::new("node")
            .args(["-e", "require('playwright-core')"])
            .env("NODE_PATH", &node_path)
            .output()
            .is_ok_and(|o| o.status.success());
    if found {
        println!("cargo::rustc-cfg=chromium");
    } else if require {
        panic!(
            "ULOG_REQUIRE_ALL_TESTS is set but /usr/bin/chromium or playwright-core \
             (npm install --prefix target/node playwright-core) is missing"
        );
    }
    // flight-review-rs (PX4 Flight Review v2's converter), the diagnostics' oracle.
    println!("cargo::rerun-if-env-changed=ULOG_FLIGHT_REVIEW");
    let peer = match std::env::var_os("ULOG_FLIGHT_REVIEW") {
        Some(exe) => std::path::PathBuf::from(exe),
        None => {
            let built = "peers/flight-review/target/release/ulog-convert";
            let target = std::env::var_os("CARGO_TARGET_DIR")
                .map(std::path::PathBuf::from)
                .filter(|t| t.join(built).is_file())
                .unwrap_or_else(|| manifest.join("../bench/target"));
            target.join(built)
        }
    };
    println!("cargo::rerun-if-changed={}", peer.display());
    if peer.is_file() {
        println!("cargo::rustc-cfg=flight_review");
        println!("cargo::rustc-env=ULOG_TESTS_FLIGHT_REVIEW={}", peer.display());
    } else if require {
        panic!(
            "ULOG_REQUIRE_ALL_TESTS is set but flight-review-rs's ulog-convert is not built \
             ({}; python3 bench/source_peers.py flight-review builds it)",
            peer.display()
        );
    }
    corpus
}
