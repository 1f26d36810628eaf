"""``ulog_rs.convert``: logs into one Parquet dataset, the one ``ulog parquet LOGS -o
DATASET`` writes (same tables, rows and ``log_id``s; a log the dataset has already is
skipped), by the same code (ulog-core's ``Dataset``)."""

import collections
import glob
import os

from . import _core

Converted = collections.namedtuple("Converted", ["path", "log_id", "status", "rows", "error"])
Converted.__doc__ = """What became of one log: ``status`` is ``written``, ``present`` (the
dataset had it: nothing written) or ``failed`` (``error`` says why; the log left
nothing of its own)."""

_URL_SCHEMES = ("s3://", "https://", "http://")


def is_url(text):
    """Whether ``text`` names an object of a store (``s3://``, ``https://``,
    ``http://``) rather than a local path."""
    return isinstance(text, str) and text.lower().startswith(_URL_SCHEMES)


def find_logs(inputs):
    """The logs of ``inputs``, each with its size: glob patterns expanded, then each
    path as the ``ulog`` commands take it (``LogFile::find``: a file, or the
    ``.ulg``/``.ulog`` files of a directory and its subdirectories); an ``s3://`` URL
    names the object, or every log below it as a prefix; an ``http(s)://`` URL one
    object."""
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    found = []
    for item in inputs:
        item = os.fspath(item)
        if is_url(item):
            found.extend(_core.find_logs(item))
            continue
        matches = [item] if os.path.exists(item) else sorted(glob.glob(item, recursive=True))
        if not matches:
            raise FileNotFoundError("{}: no such file, directory or matching path".format(item))
        for path in matches:
            logs = _core.find_logs(path)
            if not logs:
                raise FileNotFoundError(
                    "{}: no .ulg or .ulog files in this directory or its subdirectories".format(path)
                )
            found.extend(logs)
    return found


def _logs(inputs):
    return [path for path, _ in find_logs(inputs)]


def convert(inputs, output, topics=None, compression="zstd", threads=None, layout=None,
            partition_by=None, file_size_mb=None, compact=False):
    """Converts logs (paths, directories, glob patterns, ``s3://`` objects or
    prefixes, ``http(s)://`` objects) into the Parquet dataset in the folder (or under
    the ``s3://`` prefix) ``output`` (made if missing; a dataset there is added to),
    several logs at once on up to ``threads`` threads (default: every core). S3
    credentials and endpoint come from the standard AWS environment.

    :param topics: only these topics (a log with none of them is skipped)
    :param compression: ``"zstd"`` (``ulog parquet``'s default), ``"snappy"`` or
        ``"none"``
    :param layout: how a new dataset lays out its topic files: ``"file-per-log"``
        (the default) or ``"fleet"`` (a topic's rows of many logs per file, in
        partition folders; ``ulog parquet --layout fleet``); an existing dataset keeps
        its own, and another is an error
    :param partition_by: the fleet layout's partition folders, outermost first:
        ``"month"`` (default), ``"vehicle"``; ``[]`` for none
    :param file_size_mb: the fleet layout's file size (default 128)
    :param compact: in the fleet layout, also merge each partition's files smaller than
        half the file size (left by conversions of a few logs at a time) into files of
        about that size (``ulog parquet --compact``); with no inputs, only that
    :returns: one ``Converted`` per log, in the order found
    :raises FileNotFoundError: an input that names nothing
    :raises ULogError: the dataset cannot be opened or its tables written
    """
    logs = _logs(inputs)
    if compact and not logs and not is_url(output) and not os.path.exists(
            os.path.join(os.fspath(output), "logs.parquet")):
        raise FileNotFoundError("{}: no dataset to compact here (no logs.parquet)".format(output))
    if compression not in ("zstd", "snappy", "none"):
        raise ValueError("compression {!r}: one of 'zstd', 'snappy', 'none'".format(compression))
    topics = None if topics is None else [topics] if isinstance(topics, str) else list(topics)
    output = output if is_url(output) else os.fspath(output)
    partition_by = None if partition_by is None else (
        [partition_by] if isinstance(partition_by, str) else list(partition_by))
    done = _core.convert_logs(logs, output, topics, compression, threads, [], layout,
                              partition_by, file_size_mb, compact)
    return [Converted(*d) for d in done]
