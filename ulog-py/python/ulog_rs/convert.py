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

def _logs(inputs):
    """The log files of `inputs`: glob patterns expanded, then each path as the
    ``ulog`` commands take it (``LogFile::find``: a file, or the ``.ulg``/``.ulog``
    files of a directory and its subdirectories)."""
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    found = []
    for item in inputs:
        item = os.fspath(item)
        matches = [item] if os.path.exists(item) else sorted(glob.glob(item, recursive=True))
        if not matches:
            raise FileNotFoundError("{}: no such file, directory or matching path".format(item))
        for path in matches:
            logs = _core.find_logs(path)
            if not logs:
                raise FileNotFoundError(
                    "{}: no .ulg or .ulog files in this directory or its subdirectories".format(path)
                )
            found.extend(os.fspath(p) for p, _ in logs)
    return found


def convert(inputs, output, topics=None, compression="zstd", threads=None):
    """Converts logs (paths, directories, glob patterns) into the Parquet dataset in
    the folder ``output`` (made if missing; a dataset there is added to), several logs
    at once on up to ``threads`` threads (default: every core).

    :param topics: only these topics (a log with none of them is skipped)
    :param compression: ``"zstd"`` (``ulog parquet``'s default), ``"snappy"`` or
        ``"none"``
    :returns: one ``Converted`` per log, in the order found
    :raises FileNotFoundError: an input that names nothing
    :raises ULogError: the dataset cannot be opened or its tables written
    """
    logs = _logs(inputs)
    if compression not in ("zstd", "snappy", "none"):
        raise ValueError("compression {!r}: one of 'zstd', 'snappy', 'none'".format(compression))
    topics = None if topics is None else [topics] if isinstance(topics, str) else list(topics)
    done = _core.convert_logs(logs, os.fspath(output), topics, compression, threads)
    return [Converted(*d) for d in done]
