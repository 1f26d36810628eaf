"""Logs converted on a Spark cluster into the dataset ``ulog parquet`` writes::

    python -m ulog_rs.spark INPUT... -o DATASET [--master URL] [-m TOPICS]

or from Python, with a session of your own: ``ulog_rs.spark.convert(inputs, output,
spark=session)``.

How: the driver lists the logs (paths, directories, globs, ``s3://`` prefixes) and
opens the dataset, holding its lock for the whole run; one Spark task per log (largest
first) converts it on an executor, with the same code as ``ulog parquet``, into a
staging dataset of its own under ``DATASET/_staging/`` (a folder query engines
skip); the driver then absorbs each staging dataset (its topic files moved into place,
its rows of the tables taken) and writes the tables, ``logs.parquet`` last. So the
dataset is the one ``ulog parquet`` writes from the same logs: same tables and rows,
same ``log_id``s, logs it has already skipped (their ids reach the executors, which
skip a log after hashing it).

Why not Spark's ``binaryFile`` source: it would carry each log's bytes through the JVM
into Python (a copy of every log, and a 2 GB limit per row), and reading ``s3://``
would need Hadoop's S3A jars on the cluster. A task here gets the log's path or URL
and reads it itself, from a shared file system or from S3 by ranged requests
(``object_store``), with the standard AWS environment.

The dataset must be a folder that the driver and every executor reach (one machine,
or a shared file system). A task that fails (an executor lost) is retried by Spark
into a new staging folder; what the lost attempt left there is removed at the end. A
run that dies leaves the dataset as it was before it (plus staging files, removed by
the next run, and topic files of logs ``logs.parquet`` does not list, which the next
run removes when it opens the dataset).
"""

import argparse
import os
import shutil
import sys
import uuid

from . import _core
from .convert import Converted, find_logs, is_url

STAGING = "_staging"

_RESULT = "index long, path string, log_id string, status string, rows long, error string, staging string"


def _convert_task(staging_root, topics, compression, present):
    """The function each task runs over its Arrow batches of ``(index, path)``."""

    def run(batches):
        import pyarrow as pa

        from ulog_rs import _core as core

        for batch in batches:
            for index, path in zip(batch.column("index").to_pylist(), batch.column("path").to_pylist()):
                staging = os.path.join(staging_root, uuid.uuid4().hex)
                try:
                    [(_, log_id, status, rows, error)] = core.convert_logs(
                        [path], staging, topics, compression, 1, present.value
                    )
                except Exception as e:  # a dataset that cannot be written: the log's failure
                    log_id, status, rows, error = None, "failed", 0, "{}: {}".format(type(e).__name__, e)
                yield pa.RecordBatch.from_pylist(
                    [dict(index=index, path=path, log_id=log_id, status=status, rows=rows, error=error,
                          staging=staging)],
                    schema=pa.schema(
                        [("index", pa.int64()), ("path", pa.string()), ("log_id", pa.string()),
                         ("status", pa.string()), ("rows", pa.int64()), ("error", pa.string()),
                         ("staging", pa.string())]
                    ),
                )

    return run


def convert(inputs, output, spark=None, topics=None, compression="zstd", master=None,
            layout=None, partition_by=None, file_size_mb=None, compact=False):
    """Converts logs on Spark into the Parquet dataset in the folder ``output``.

    :param inputs: paths, directories, glob patterns, ``s3://`` objects or prefixes
    :param spark: a ``SparkSession`` (default: one made for the run, on ``master``,
        default ``local[*]``, and stopped after)
    :param topics: only these topics; ``compression``, ``layout``, ``partition_by``,
        ``file_size_mb``: as ``ulog_rs.convert`` (in the fleet layout, the executors
        convert each log into a staging dataset and the driver compacts their files);
        ``compact``: as ``ulog_rs.convert``, done by the driver at the end
    :returns: one ``Converted`` per log, in the order found
    """
    if is_url(os.fspath(output)):
        raise ValueError(
            "{}: the Spark conversion writes to a folder the driver and every executor reach; "
            "write a dataset to S3 with `ulog parquet` or ulog_rs.convert".format(output)
        )
    if compression not in ("zstd", "snappy", "none"):
        raise ValueError("compression {!r}: one of 'zstd', 'snappy', 'none'".format(compression))
    topics = None if topics is None else [topics] if isinstance(topics, str) else list(topics)
    output = os.path.abspath(os.fspath(output))
    logs = find_logs(inputs)
    partition_by = None if partition_by is None else (
        [partition_by] if isinstance(partition_by, str) else list(partition_by))
    writer = _core.DatasetWriter(output, topics, compression, layout, partition_by, file_size_mb,
                                 compact)
    staging_root = os.path.join(output, STAGING)
    try:
        # Left by a run that died: this run holds the lock now.
        shutil.rmtree(staging_root, ignore_errors=True)
        own = spark is None
        if own:
            from pyspark.sql import SparkSession

            # The executors' Python is this one (with ulog_rs), unless the user says.
            os.environ.setdefault("PYSPARK_PYTHON", sys.executable)
            spark = (
                SparkSession.builder.master(master or "local[*]")
                .appName("ulog_rs.spark")
                .config("spark.ui.enabled", "false")
                .getOrCreate()
            )
        try:
            done = _run(spark, logs, staging_root, topics, compression, writer.log_ids())
        finally:
            if own:
                spark.stop()
        results = []
        for path, _ in logs:
            row = done[path]
            status, log_id, rows, error = row["status"], row["log_id"], row["rows"], row["error"]
            if status == "written":
                absorbed = writer.absorb(row["staging"])
                if absorbed and absorbed[0][1] == "present":
                    status, rows = "present", 0
            results.append(Converted(path, log_id, status, rows, error))
        writer.finish()
        return results
    except BaseException:
        writer.abandon()
        raise
    finally:
        shutil.rmtree(staging_root, ignore_errors=True)


def _run(spark, logs, staging_root, topics, compression, present):
    """One task per log, largest first: ``{path: result row}``."""
    order = sorted(range(len(logs)), key=lambda i: (-logs[i][1], i))
    rows = [(i, logs[i][0]) for i in order]
    if not rows:
        return {}
    context = spark.sparkContext
    frame = spark.createDataFrame(context.parallelize(rows, len(rows)), "index long, path string")
    task = _convert_task(staging_root, topics, compression, context.broadcast(list(present)))
    collected = frame.mapInArrow(task, _RESULT).collect()
    done = {}
    for r in collected:
        # A path given twice is converted once per task: the first result stands.
        done.setdefault(r["path"], r.asDict())
    return done


TABLES = ("logs", "parameters", "messages", "formats", "analysis", "flights")


def register(spark, dataset, topics=None):
    """Makes temporary views of a dataset in ``spark``: one per table (``logs``,
    ``parameters``, ``messages``, ``formats``, ``analysis``, ``flights``) and one per
    topic (or per name of ``topics``), named by its folder, read through the topic's
    union schema (``_schemas/<topic>.parquet``) so that the files of every firmware
    version read as one table: a field a version lacks is NULL there, and a field
    whose type changed is read as the wider type; in the fleet layout, the partition
    folders are columns too (``month``, ``vehicle``). Sets ``spark.sql.caseSensitive``
    (field names are case-sensitive in ULog). Returns the views' names.

    ``dataset`` is a folder (or any path Spark reads: ``hdfs://``, ``s3a://``…, where
    the cluster has their connectors; the topics are then those of ``topics``)."""
    dataset = os.fspath(dataset).rstrip("/")
    # ULog field names are case-sensitive, and PX4 renamed some by case alone
    # (`system_power.hipower_5V_oc` → `hipower_5v_oc`): a union has both.
    spark.conf.set("spark.sql.caseSensitive", "true")
    names = []
    local = "://" not in dataset
    for table in TABLES:
        path = "{}/{}.parquet".format(dataset, table)
        if local and not os.path.exists(path):
            continue
        spark.read.parquet(path).createOrReplaceTempView(table)
        names.append(table)
    if topics is None:
        schemas = os.path.join(dataset, "_schemas")
        topics = sorted(n[: -len(".parquet")] for n in os.listdir(schemas) if n.endswith(".parquet")) \
            if local and os.path.isdir(schemas) else []
    for topic in topics:
        schema = spark.read.parquet("{}/_schemas/{}.parquet".format(dataset, topic)).schema
        spark.read.schema(schema).parquet("{}/{}".format(dataset, topic)).createOrReplaceTempView(topic)
        names.append(topic)
    return names


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python -m ulog_rs.spark",
        description="Convert ULog logs on Spark into the Parquet dataset `ulog parquet` writes.",
    )
    parser.add_argument("inputs", nargs="+", metavar="INPUT",
                        help="logs, directories, glob patterns or s3:// prefixes")
    parser.add_argument("-o", "--output", required=True, metavar="DATASET",
                        help="the dataset's folder, reachable by the driver and every executor")
    parser.add_argument("--master", help="Spark master URL (default: local[*])")
    parser.add_argument("-m", "--messages", metavar="TOPICS", help="only these topics (comma-separated)")
    parser.add_argument("--compression", default="zstd", choices=["zstd", "snappy", "none"])
    parser.add_argument("--layout", choices=["file-per-log", "fleet"],
                        help="a new dataset's layout, as `ulog parquet --layout`")
    parser.add_argument("--partition-by", metavar="KEYS",
                        help="the fleet layout's partition folders: month, vehicle, none")
    parser.add_argument("--file-size", type=int, metavar="MB", help="the fleet layout's file size")
    parser.add_argument("--compact", action="store_true",
                        help="also merge the fleet layout's small files, as `ulog parquet --compact`")
    args = parser.parse_args(argv)
    topics = [t for t in args.messages.split(",") if t] if args.messages else None
    partition_by = None
    if args.partition_by is not None:
        partition_by = [k for k in args.partition_by.split(",") if k and k != "none"]
    try:
        done = convert(args.inputs, args.output, topics=topics, compression=args.compression,
                       master=args.master, layout=args.layout, partition_by=partition_by,
                       file_size_mb=args.file_size, compact=args.compact)
    except (OSError, ValueError) as e:
        print("ulog_rs.spark: {}".format(e), file=sys.stderr)
        return 3 if isinstance(e, OSError) else 2
    failed = 0
    for d in done:
        if d.status == "written":
            print("Adding {} as {} ({} rows)".format(d.path, d.log_id, d.rows))
        elif d.status == "present":
            print("Skipping {}: the dataset has it already ({})".format(d.path, d.log_id))
        else:
            failed += 1
            print("ulog_rs.spark: {}: {}".format(d.path, d.error), file=sys.stderr)
    print("Writing {} ({} logs converted, {} skipped, {} failed)".format(
        args.output, sum(d.status == "written" for d in done),
        sum(d.status == "present" for d in done), failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
