"""ulog_rs.convert writes the dataset `ulog parquet LOGS -o DATASET` writes: the same
files byte for byte, the same log ids (read back by pyarrow); converting again skips
every log."""

import os
import pathlib
import subprocess

import pytest

pq = pytest.importorskip("pyarrow.parquet")
import ulog_rs

from conftest import OWN, missing, table_rows, ulog_binary


def files(root):
    return sorted(p.relative_to(root) for p in root.rglob("*.parquet"))


def test_convert_writes_what_ulog_parquet_writes(tmp_path):
    exe = ulog_binary()
    if exe is None:
        missing("the `ulog` binary (cargo build -p ulog-cli) is not built")
    logs = sorted(OWN.glob("*.ulg"))
    ours, theirs = tmp_path / "ours", tmp_path / "theirs"
    done = ulog_rs.convert([str(OWN)], ours)
    assert [d.status for d in done] == ["written"] * len(logs)
    assert [pathlib.Path(d.path).name for d in done] == [p.name for p in logs]
    subprocess.run([str(exe), "parquet", *map(str, logs), "-o", str(theirs)], check=True,
                   capture_output=True)
    assert files(ours) == files(theirs)
    assert len(files(ours)) > 4 * len(logs)
    # The same logs by the same paths: the same files byte for byte (the dataset's
    # files do not depend on the order logs are added in, or the threads).
    for rel in files(ours):
        assert (ours / rel).read_bytes() == (theirs / rel).read_bytes(), rel
        assert pq.read_metadata(ours / rel).num_columns > 0, rel  # a Parquet file pyarrow reads
    ids = sorted(d.log_id for d in done)
    assert ids == sorted(pq.read_table(theirs / "logs.parquet").column("log_id").to_pylist())

    again = ulog_rs.convert(logs, ours)
    assert [d.status for d in again] == ["present"] * len(logs)
    assert files(ours) == files(theirs)


def test_a_log_that_fails_is_reported_and_the_others_written(tmp_path):
    bad = tmp_path / "not_a_log.ulg"
    bad.write_bytes(b"not a log at all" * 10)
    good = sorted(OWN.glob("*.ulg"))[0]
    done = ulog_rs.convert([good, bad], tmp_path / "ds")
    assert [d.status for d in done] == ["written", "failed"]
    assert "ULog" in done[1].error or "magic" in done[1].error, done[1].error
    assert (tmp_path / "ds" / "logs.parquet").exists()


def test_an_input_that_names_nothing_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError):
        ulog_rs.convert([tmp_path / "nothing*.ulg"], tmp_path / "ds")


def test_convert_in_the_fleet_layout_writes_what_ulog_parquet_writes(tmp_path):
    exe = ulog_binary()
    if exe is None:
        missing("the `ulog` binary (cargo build -p ulog-cli) is not built")
    logs = sorted(OWN.glob("*.ulg"))
    ours, theirs = tmp_path / "ours", tmp_path / "theirs"
    done = ulog_rs.convert(logs, ours, layout="fleet", partition_by=["vehicle", "month"],
                           file_size_mb=1)
    assert [d.status for d in done] == ["written"] * len(logs)
    subprocess.run([str(exe), "parquet", *map(str, logs), "-o", str(theirs), "--layout", "fleet",
                    "--partition-by", "vehicle,month", "--file-size", "1"],
                   check=True, capture_output=True)
    assert files(ours) == files(theirs)
    for rel in files(ours):
        assert (ours / rel).read_bytes() == (theirs / rel).read_bytes(), rel
    # Topic files in partition folders, logs named in their metadata; pyarrow reads
    # the folders as Hive partitions.
    topic = [rel for rel in files(ours) if len(rel.parts) == 4]
    assert topic and all(rel.parts[1].startswith("vehicle=") and rel.parts[2].startswith("month=")
                         for rel in topic)
    ids = set()
    for rel in topic:
        meta = pq.read_metadata(ours / rel).metadata
        ids.update(meta[b"ulog.log_ids"].decode().split(","))
    assert ids <= {d.log_id for d in done} and len(ids) > 1
    ds = pytest.importorskip("pyarrow.dataset")
    folder = ours / topic[0].parts[0]
    table = ds.dataset(folder, format="parquet", partitioning="hive").to_table()
    assert {"vehicle", "month", "log_id"} <= set(table.column_names)

    # The dataset keeps its layout: another is refused, none asked keeps it.
    with pytest.raises(ulog_rs.ULogError, match="layout"):
        ulog_rs.convert(logs, ours, layout="file-per-log")
    assert [d.status for d in ulog_rs.convert(logs, ours)] == ["present"] * len(logs)


def test_compacting_merges_small_files_as_ulog_parquet_compact_does(tmp_path):
    exe = ulog_binary()
    if exe is None:
        missing("the `ulog` binary (cargo build -p ulog-cli) is not built")
    logs = sorted(OWN.glob("*.ulg"))
    ours, theirs, whole = tmp_path / "ours", tmp_path / "theirs", tmp_path / "whole"
    # A log at a time (a file per topic and log), then compacted.
    driver = tmp_path / "driver"
    for log in logs:
        ulog_rs.convert([log], ours, layout="fleet", partition_by=[])
        ulog_rs.convert([log], driver, layout="fleet", partition_by=[])
        subprocess.run([str(exe), "parquet", str(log), "-o", str(theirs), "--layout", "fleet",
                        "--partition-by", "none"], check=True, capture_output=True)
    before = files(ours)
    assert ulog_rs.convert([], ours, compact=True) == []
    subprocess.run([str(exe), "parquet", "--compact", "-o", str(theirs)], check=True,
                   capture_output=True)
    # A Spark driver's writer (`python -m ulog_rs.spark --compact`) compacts at its end.
    ulog_rs._core.DatasetWriter(str(driver), compact=True).finish()
    assert files(ours) == files(theirs) == files(driver)
    for rel in files(ours):
        assert (ours / rel).read_bytes() == (theirs / rel).read_bytes(), rel
        assert (driver / rel).read_bytes() == (theirs / rel).read_bytes(), rel
    assert len(files(ours)) < len(before)
    # The rows of one conversion of every log, in the same files and order.
    ulog_rs.convert(logs, whole, layout="fleet", partition_by=[])
    assert files(ours) == files(whole)
    for rel in files(ours):
        if len(rel.parts) > 1 and not rel.parts[0].startswith("_"):
            mine, one = pq.read_table(ours / rel), pq.read_table(whole / rel)
            assert mine.schema.equals(one.schema, check_metadata=True), rel
            assert pq.read_metadata(ours / rel).metadata == pq.read_metadata(whole / rel).metadata
            assert table_rows(mine) == table_rows(one), rel
    with pytest.raises(FileNotFoundError, match="no dataset to compact"):
        ulog_rs.convert([], tmp_path / "none", compact=True)
    with pytest.raises(ulog_rs.ULogError, match="file per topic and log"):
        ulog_rs.convert(logs[:1], tmp_path / "flat", compact=True)


@pytest.mark.parametrize("kwargs", [
    {"layout": "tiles"},
    {"layout": "fleet", "partition_by": ["day"]},
    {"layout": "fleet", "partition_by": ["month", "month"]},
    {"layout": "fleet", "file_size_mb": 0},
    {"partition_by": ["month"]},
])
def test_a_wrong_layout_is_a_value_error(tmp_path, kwargs):
    with pytest.raises(ValueError):
        ulog_rs.convert(sorted(OWN.glob("*.ulg"))[:1], tmp_path / "ds", **kwargs)
    assert not (tmp_path / "ds" / "logs.parquet").exists()
