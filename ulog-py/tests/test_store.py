"""ulog_rs reads logs from S3 and writes datasets there (moto's S3 server on
127.0.0.1, boto3 to put the logs, pyarrow's S3 filesystem to read the dataset back):
`ulog_rs.convert("s3://…/", "s3://…")` writes the dataset it writes locally."""

import os
import pathlib

import pytest

pq = pytest.importorskip("pyarrow.parquet")
pafs = pytest.importorskip("pyarrow.fs")
import ulog_rs
from ulog_rs.convert import find_logs

from conftest import OWN, dataset_files, table_rows, upload


def s3fs():
    endpoint = os.environ["AWS_ENDPOINT_URL"].split("://", 1)
    return pafs.S3FileSystem(endpoint_override=endpoint[1], scheme=endpoint[0],
                             access_key="testing", secret_key="testing", region="us-east-1")


def test_convert_reads_and_writes_s3(tmp_path, s3_server):
    logs = sorted(OWN.glob("*.ulg"))
    upload("pybucket", "logs", logs)
    found = find_logs("s3://pybucket/logs/")
    assert [u for u, _ in found] == ["s3://pybucket/logs/" + p.name for p in logs]
    assert [s for _, s in found] == [p.stat().st_size for p in logs]

    done = ulog_rs.convert("s3://pybucket/logs/", "s3://pybucket/ds")
    assert [d.status for d in done] == ["written"] * len(logs)
    local = tmp_path / "local"
    ulog_rs.convert(logs, local)
    fs = s3fs()
    for rel in dataset_files(local):
        there = pq.read_table("pybucket/ds/" + rel, filesystem=fs)
        here = pq.read_table(local / rel)
        if rel == "logs.parquet":
            assert sorted(there.column("path").to_pylist()) == sorted(
                "s3://pybucket/logs/" + p.name for p in logs)
            there, here = there.drop_columns(["path"]), here.drop_columns(["path"])
        assert table_rows(there) == table_rows(here), rel
    remote = sorted(
        i.path[len("pybucket/ds/"):]
        for i in fs.get_file_info(pafs.FileSelector("pybucket/ds", recursive=True))
        if i.type == pafs.FileType.File
    )
    assert remote == dataset_files(local)

    again = ulog_rs.convert("s3://pybucket/logs/", "s3://pybucket/ds")
    assert [d.status for d in again] == ["present"] * len(logs)


def test_a_missing_object_is_file_not_found(s3_server):
    upload("pybucket", "logs", sorted(OWN.glob("*.ulg"))[:1])
    with pytest.raises(FileNotFoundError, match="s3://pybucket/nothing"):
        ulog_rs.convert("s3://pybucket/nothing/", pathlib.Path("unused"))
