#!/usr/bin/env python3
"""Loads a ULog file with pyulog and prints what it read as JSON, for the tests that
check that pyulog accepts the logs our writer writes.

Usage: pyulog_dump.py FILE.ulg [--only TOPIC ...]  (with --only: the data of those
topics alone, as pyulog's message_name_filter_list reads it)
"""
import contextlib
import json
import sys

from pyulog import ULog


def plain(v):
    if hasattr(v, "item"):
        v = v.item()
    if isinstance(v, float) and v != v:
        return "nan"
    if isinstance(v, float) and v in (float("inf"), float("-inf")):
        return str(v)
    if isinstance(v, (bytes, bytearray)):
        return v.decode("utf-8", "replace")
    return v


def main():
    # pyulog prints its complaints about a log to stdout; stdout is for the JSON.
    with contextlib.redirect_stdout(sys.stderr):
        only = sys.argv[3:] if sys.argv[2:3] == ["--only"] else None
        ulog = ULog(sys.argv[1], only)
    out = {
        "corrupt": bool(ulog.file_corruption),
        "info": {k: plain(v) for k, v in ulog.msg_info_dict.items()},
        "info_multi": {k: [[plain(p) for p in e] for e in v]
                       for k, v in ulog.msg_info_multiple_dict.items()},
        "params": {k: plain(v) for k, v in ulog.initial_parameters.items()},
        "changed": [[t, n, plain(v)] for t, n, v in ulog.changed_parameters],
        "logged": [[m.log_level, m.timestamp, m.message] for m in ulog.logged_messages],
        "tagged": {str(tag): [[m.log_level, m.timestamp, m.message] for m in msgs]
                   for tag, msgs in ulog.logged_messages_tagged.items()},
        "dropouts": [[d.timestamp, d.duration] for d in ulog.dropouts],
        "topics": {},
        "datasets": [],
    }
    for d in ulog.data_list:
        cols = {}
        for f in d.field_data:
            cols[f.field_name] = [plain(v) for v in d.data[f.field_name]]
        out["topics"]["%s/%d" % (d.name, d.multi_id)] = cols
        out["datasets"].append([d.name, d.multi_id, cols])
    json.dump(out, sys.stdout)


if __name__ == "__main__":
    main()
