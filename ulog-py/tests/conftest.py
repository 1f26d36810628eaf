"""Where the tests find logs: the repository's own corpus (tests/corpus/files, on
every clone) and the full corpus when there is one ($ULOG_CORPUS, or ../shared/corpus
beside the workspace, as the Rust tests look for it)."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
# CI has everything: a test that would skip for want of something fails there.
REQUIRE_ALL = os.environ.get("ULOG_REQUIRE_ALL_TESTS") == "1"


def missing(reason):
    """Skips the test for want of `reason`, or fails it where CI requires all."""
    (pytest.fail if REQUIRE_ALL else pytest.skip)(reason)
OWN = ROOT / "tests" / "corpus" / "files"


def ulog_binary():
    """The `ulog` binary cargo built (debug, else release), else one on the PATH."""
    import shutil

    for profile in ("debug", "release"):
        exe = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / profile / "ulog"
        if exe.exists():
            return exe
    return shutil.which("ulog")


def full_corpus():
    env = os.environ.get("ULOG_CORPUS")
    path = pathlib.Path(env) if env else ROOT.parent / "shared" / "corpus"
    return path if (path / "files").is_dir() else None


def corpus_logs():
    """Every log of both corpora, by file name (the full corpus wins a tie)."""
    logs = {p.name: p for p in OWN.glob("*.ulg")}
    full = full_corpus()
    if full is not None:
        logs.update({p.name: p for p in (full / "files").glob("*.ulg")})
    return [logs[k] for k in sorted(logs)]


def pytest_report_header(config):
    full = full_corpus()
    return "ulog_rs tests: {} logs ({})".format(
        len(corpus_logs()), "full corpus" if full else "the repository's own corpus only"
    )


@pytest.fixture
def sample_log():
    return OWN / "sample_appended_multiple.ulg"


@pytest.fixture(scope="module")
def s3_server():
    """A real S3-compatible server (moto's, from PyPI) on a free port of 127.0.0.1, with
    the standard AWS environment pointing at it; yields its endpoint URL."""
    import socket
    import subprocess
    import sys
    import time

    try:
        import boto3  # noqa: F401
        import moto.server  # noqa: F401
    except ImportError:
        missing("moto[server] and boto3 (an S3 server on 127.0.0.1) are not installed")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = subprocess.Popen(
        [sys.executable, "-m", "moto.server", "-H", "127.0.0.1", "-p", str(port)],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )
    endpoint = "http://127.0.0.1:{}".format(port)
    env = {
        "AWS_ENDPOINT_URL": endpoint, "AWS_ACCESS_KEY_ID": "testing",
        "AWS_SECRET_ACCESS_KEY": "testing", "AWS_DEFAULT_REGION": "us-east-1",
    }
    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)
    try:
        deadline = time.time() + 60
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                assert time.time() < deadline, "moto's server did not start"
                time.sleep(0.1)
        yield endpoint
    finally:
        server.kill()
        server.wait()
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def upload(bucket, prefix, paths):
    """Puts `paths` into s3://bucket/prefix/ with boto3 (the server of `s3_server`)."""
    import boto3

    client = boto3.client("s3", endpoint_url=os.environ["AWS_ENDPOINT_URL"])
    try:
        client.create_bucket(Bucket=bucket)
    except client.exceptions.BucketAlreadyOwnedByYou:
        pass
    for p in paths:
        client.upload_file(str(p), bucket, "{}/{}".format(prefix, pathlib.Path(p).name))


def table_rows(table):
    """A pyarrow table's rows as dicts, NaN made comparable (NaN != NaN)."""

    def plain(v):
        if isinstance(v, float) and v != v:
            return "NaN"
        if isinstance(v, list):
            return [plain(x) for x in v]
        if isinstance(v, dict):
            return {k: plain(x) for k, x in v.items()}
        return v

    return [plain(r) for r in table.to_pylist()]


def dataset_files(root):
    """The files of a dataset folder by relative path (a Spark run's staging left out)."""
    root = pathlib.Path(root)
    return sorted(
        p.relative_to(root).as_posix() for p in root.rglob("*")
        if p.is_file() and not p.relative_to(root).as_posix().startswith("_staging/")
    )
