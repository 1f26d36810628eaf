"""`python -m ulog_rs.spark` converts logs on Spark (local[2]) into the dataset `ulog
parquet` writes: the same files, table by table and row by row (read by pyarrow), byte
for byte; again, it skips every log; from s3:// prefixes (moto's S3 server) the same
but for `logs.path`. A Python worker killed mid-run (Spark retries its task) and a run
killed with SIGKILL then run again both leave that dataset; a second conversion
into a dataset being written refuses clearly. The README's fleet queries in Spark SQL
answer what DuckDB's answer."""

import json
import math
import os
import pathlib
import re
import shutil
import signal
import subprocess
import sys
import threading
import time

import pytest

pq = pytest.importorskip("pyarrow.parquet")
import ulog_rs.spark

from conftest import ROOT, corpus_logs, dataset_files, missing, table_rows, ulog_binary, upload

try:
    import pyspark  # noqa: F401
except ImportError:
    pyspark = None


def need_spark():
    if pyspark is None:
        missing("pyspark is not installed (pip install './ulog-py[spark]'; Java 17 or newer)")
    if shutil.which("java") is None:
        missing("java is not installed (Spark runs on Java 17 or newer)")


LOGS = corpus_logs()


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The dataset `ulog parquet` writes from the corpus."""
    exe = ulog_binary()
    if exe is None:
        missing("the `ulog` binary (cargo build -p ulog-cli) is not built")
    out = tmp_path_factory.mktemp("reference") / "dataset"
    subprocess.run([str(exe), "parquet", *map(str, LOGS), "-o", str(out)], check=True,
                   capture_output=True)
    return out


def spark_cli(*args, **kw):
    return subprocess.Popen(
        [sys.executable, "-m", "ulog_rs.spark", *map(str, args)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kw,
    )


def assert_same_dataset(ours, theirs, ignore_path=False):
    """Table by table and row by row (pyarrow), then byte for byte."""
    assert dataset_files(ours) == dataset_files(theirs)
    assert len(dataset_files(ours)) > 4 * len(LOGS)
    for rel in dataset_files(ours):
        a, b = pq.read_table(pathlib.Path(ours) / rel), pq.read_table(pathlib.Path(theirs) / rel)
        assert a.schema == b.schema, rel
        ra, rb = table_rows(a), table_rows(b)
        if ignore_path and rel == "logs.parquet":
            ra = [{**r, "path": None} for r in ra]
            rb = [{**r, "path": None} for r in rb]
        assert ra == rb, rel
        if not (ignore_path and rel == "logs.parquet"):
            assert (pathlib.Path(ours) / rel).read_bytes() == (pathlib.Path(theirs) / rel).read_bytes(), rel


def consistent(dataset):
    """Every log of logs.parquet that has topics has its files; no file lacks its log."""
    dataset = pathlib.Path(dataset)
    listed = {}
    if (dataset / "logs.parquet").exists():
        t = pq.read_table(dataset / "logs.parquet")
        listed = dict(zip(t.column("log_id").to_pylist(), t.column("topics").to_pylist()))
    files = {}
    for p in dataset.glob("*/*.parquet"):
        if not p.parent.name.startswith("_"):
            files.setdefault(p.stem, []).append(p)
    without = [i for i, n in listed.items() if n and i not in files]
    orphans = [i for i in files if i not in listed]
    return without, orphans


def test_the_spark_conversion_writes_what_ulog_parquet_writes(tmp_path, reference):
    need_spark()
    ours = tmp_path / "ours"
    run = spark_cli(*LOGS, "-o", ours, "--master", "local[2]")
    out, err = run.communicate(timeout=900)
    assert run.returncode == 0, err
    assert out.count("Adding ") == len(LOGS), out
    assert_same_dataset(ours, reference)
    assert not (ours / "_staging").exists()

    again = spark_cli(*LOGS, "-o", ours, "--master", "local[2]")
    out, err = again.communicate(timeout=900)
    assert again.returncode == 0, err
    assert out.count("Skipping ") == len(LOGS), out
    assert_same_dataset(ours, reference)


def test_the_spark_conversion_reads_s3_prefixes(tmp_path, reference, s3_server):
    need_spark()
    upload("fleet", "logs", LOGS)
    ours = tmp_path / "from_s3"
    run = spark_cli("s3://fleet/logs/", "-o", ours, "--master", "local[2]")
    out, err = run.communicate(timeout=900)
    assert run.returncode == 0, err
    assert_same_dataset(ours, reference, ignore_path=True)
    paths = sorted(pq.read_table(ours / "logs.parquet").column("path").to_pylist())
    assert paths == sorted("s3://fleet/logs/" + p.name for p in LOGS)


def python_workers():
    """The pids of Spark's Python workers (and their daemon) of this machine."""
    pids = []
    for entry in pathlib.Path("/proc").iterdir():
        if not entry.name.isdigit() or int(entry.name) == os.getpid():
            continue
        try:
            cmdline = (entry / "cmdline").read_bytes()
        except OSError:
            continue
        if b"pyspark.daemon" in cmdline or b"pyspark.worker" in cmdline:
            pids.append(int(entry.name))
    return pids


def test_a_python_worker_lost_mid_run_is_retried_into_the_same_dataset(tmp_path, reference):
    need_spark()
    if not pathlib.Path("/proc").is_dir():
        missing("/proc (to find Spark's Python workers) is Linux's")
    from pyspark.sql import SparkSession

    os.environ.setdefault("PYSPARK_PYTHON", sys.executable)
    # local[2, 4]: two threads, a task tried up to four times (Spark's retry, which a
    # cluster has for a lost executor).
    spark = (SparkSession.builder.master("local[2,4]").appName("ulog_rs.spark test")
             .config("spark.ui.enabled", "false").getOrCreate())
    ours = tmp_path / "lost"
    killed = []

    def kill_when_staging():
        deadline = time.time() + 300
        while time.time() < deadline and not killed:
            staging = ours / "_staging"
            if staging.is_dir() and any(staging.iterdir()):
                for pid in python_workers():
                    try:
                        os.kill(pid, signal.SIGKILL)
                        killed.append(pid)
                    except ProcessLookupError:
                        pass
            time.sleep(0.02)

    killer = threading.Thread(target=kill_when_staging)
    killer.start()
    try:
        done = ulog_rs.spark.convert(LOGS, ours, spark=spark)
    finally:
        killed.append(None)  # stops the killer if the run ended first
        killer.join()
        spark.stop()
    assert [p for p in killed if p is not None], "no Python worker was running to kill"
    assert [d.status for d in done] == ["written"] * len(LOGS)
    assert_same_dataset(ours, reference)


def test_a_run_killed_then_run_again_leaves_a_consistent_dataset(tmp_path, reference):
    need_spark()
    ours = tmp_path / "killed"
    run = spark_cli(*LOGS, "-o", ours, "--master", "local[2]", start_new_session=True)
    # Killed once some logs are staged or moved (SIGKILL to the driver, its JVM and
    # its workers: the whole process group).
    deadline = time.time() + 300
    while time.time() < deadline and run.poll() is None:
        staging = ours / "_staging"
        if staging.is_dir() and len(list(staging.iterdir())) >= 2:
            break
        time.sleep(0.02)
    os.killpg(run.pid, signal.SIGKILL)
    run.communicate()
    without, _ = consistent(ours)
    assert without == []
    again = spark_cli(*LOGS, "-o", ours, "--master", "local[2]")
    out, err = again.communicate(timeout=900)
    assert again.returncode == 0, err
    assert consistent(ours) == ([], [])
    assert_same_dataset(ours, reference)


def test_a_second_conversion_into_a_dataset_being_written_refuses_clearly(tmp_path):
    ours = tmp_path / "busy"
    holder = ulog_rs._core.DatasetWriter(str(ours))
    try:
        with pytest.raises(ulog_rs.ULogError, match="being written by another conversion"):
            ulog_rs.spark.convert(LOGS[:1], ours)
        assert not (ours / "logs.parquet").exists()
    finally:
        holder.abandon()
    assert not (ours / ".ulog-dataset.lock").exists()


def readme_queries(kind):
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    start = text.index("\n## Fleet analysis")
    end = text.find("\n## ", start + 1)
    section = text[start:end if end >= 0 else len(text)]
    return re.findall(r"```{}\n(.*?)```".format(kind), section, re.S)


def plain(v):
    """A value as both engines give it: NaN comparable, decimals (Spark's uint64) as
    int, times as UTC ISO text."""
    import datetime
    import decimal

    if isinstance(v, float) and math.isnan(v):
        return "NaN"
    if isinstance(v, decimal.Decimal):
        return int(v)
    if isinstance(v, datetime.datetime):
        if v.tzinfo is not None:
            v = v.astimezone(datetime.timezone.utc).replace(tzinfo=None)
        return v.isoformat()
    return v


def test_the_readmes_fleet_queries_in_spark_sql_answer_as_duckdb(tmp_path, reference):
    spark_sql_answers_as_duckdb(reference, reference)


def test_the_spark_conversion_in_the_fleet_layout_writes_what_ulog_parquet_writes(
        tmp_path, reference):
    """In the fleet layout the driver compacts what the executors converted: the files
    `ulog parquet --layout fleet` writes, byte for byte; Spark SQL reads the partition
    folders through `register` and answers the README's queries as DuckDB does over
    the file-per-log dataset."""
    need_spark()
    exe = ulog_binary()
    if exe is None:
        missing("the `ulog` binary (cargo build -p ulog-cli) is not built")
    layout = ["--layout", "fleet", "--partition-by", "month", "--file-size", "1"]
    theirs = tmp_path / "theirs"
    subprocess.run([str(exe), "parquet", *map(str, LOGS), "-o", str(theirs), *layout],
                   check=True, capture_output=True)
    ours = tmp_path / "ours"
    run = spark_cli(*LOGS, "-o", ours, "--master", "local[2]", *layout)
    out, err = run.communicate(timeout=900)
    assert run.returncode == 0, err
    assert dataset_files(ours) == dataset_files(theirs)
    assert any("/month=" in rel for rel in dataset_files(ours))
    for rel in dataset_files(ours):
        assert (ours / rel).read_bytes() == (theirs / rel).read_bytes(), rel
    assert not (ours / "_staging").exists() and not (ours / "_pending").exists()
    spark_sql_answers_as_duckdb(ours, reference)


def spark_sql_answers_as_duckdb(dataset, reference):
    """The README's Spark SQL queries over `dataset` answer what its DuckDB queries
    answer over `reference`."""
    need_spark()
    duckdb = pytest.importorskip("duckdb")
    from pyspark.sql import SparkSession

    duck = [q.replace("DATASET", str(reference)) for q in readme_queries("sql")]
    sparks = readme_queries("sql spark")
    assert len(duck) == 7 and len(sparks) == 7
    con = duckdb.connect()
    expected = [[[plain(v) for v in row] for row in con.sql(q).fetchall()] for q in duck]
    os.environ.setdefault("PYSPARK_PYTHON", sys.executable)
    spark = (SparkSession.builder.master("local[2]").appName("ulog_rs fleet queries")
             .config("spark.ui.enabled", "false")
             .config("spark.sql.session.timeZone", "UTC").getOrCreate())
    try:
        views = ulog_rs.spark.register(spark, dataset)
        assert {"logs", "vehicle_local_position", "battery_status"} <= set(views)
        got = [[[plain(v) for v in row] for row in spark.sql(q.rstrip().rstrip(";")).collect()]
               for q in sparks]
    finally:
        spark.stop()
    for i, (a, b) in enumerate(zip(got, expected), 1):
        assert a == b, "query {}: Spark {} DuckDB {}".format(i, json.dumps(a[:5], default=str),
                                                            json.dumps(b[:5], default=str))
    # Not vacuous: the queries over the corpus find rows.
    assert sum(len(rows) for rows in expected) > 10
