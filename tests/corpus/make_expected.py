#!/usr/bin/env python3
"""Writes what pyulog makes of each log of this folder into expected/<stem>/: the
reference outputs the tests compare our reader, bindings and exports with.

Usage (from the repository root, with pyulog 1.3.0 installed):
    python3 tests/corpus/make_expected.py [FILE.ulg ...]

Without arguments it remakes expected/ for every file in files/. Outputs:
- summary.json: versions, flags, appended offsets, corruption flag, first and last
  timestamps, information and multi-information, initial, changed and default
  parameters, logged and tagged messages, dropouts, formats, what pyulog printed, and
  per topic instance (name, multi_id) its msg_id, row count, first and last timestamp
  and column names.
- csv/<stem>_<topic>_<multi_id>.csv: every row, timestamp first, then the fields in
  format order as pyulog names them (arrays `name[i]`, nested `outer.inner`), every
  field whose name contains `_padding` left out, values as numpy prints them.
"""
import contextlib
import io
import json
import os
import sys

from pyulog import ULog

HERE = os.path.dirname(os.path.abspath(__file__))


def plain(v):
    """A JSON value for something pyulog holds."""
    if hasattr(v, "item"):
        v = v.item()
    if isinstance(v, (bytes, bytearray)):
        return v.decode("utf-8", "replace")
    if isinstance(v, float) and (v != v or v in (float("inf"), float("-inf"))):
        return str(v)
    if isinstance(v, (list, tuple)):
        return [plain(x) for x in v]
    if isinstance(v, dict):
        return {str(k): plain(x) for k, x in v.items()}
    return v


def columns(data):
    """The columns of one topic instance: timestamp first, padding left out."""
    names = [f.field_name for f in data.field_data if "_padding" not in f.field_name]
    if "timestamp" in names:
        names.remove("timestamp")
        names.insert(0, "timestamp")
    return names


def summary(ulog, printed):
    topics = []
    for d in sorted(ulog.data_list, key=lambda d: (d.name, d.multi_id)):
        ts = d.data.get("timestamp")
        rows = len(ts) if ts is not None else 0
        topics.append({
            "name": d.name,
            "multi_id": d.multi_id,
            "msg_id": d.msg_id,
            "rows": rows,
            "first_timestamp": int(ts[0]) if rows else None,
            "last_timestamp": int(ts[-1]) if rows else None,
            "columns": columns(d),
        })
    return {
        "file_version": ulog._file_version,
        "start_timestamp": ulog.start_timestamp,
        "last_timestamp": ulog.last_timestamp,
        "file_corruption": ulog.file_corruption,
        "compat_flags": list(ulog._compat_flags),
        "incompat_flags": list(ulog._incompat_flags),
        "appended_offsets": list(ulog._appended_offsets),
        "has_data_appended": int(ulog.has_data_appended),
        "info": plain(ulog.msg_info_dict),
        "info_multi": plain(ulog.msg_info_multiple_dict),
        "initial_parameters": plain(ulog.initial_parameters),
        "changed_parameters": plain(ulog.changed_parameters),
        "default_parameters": {
            name: plain(ulog.get_default_parameters(bit))
            for bit, name in ((0, "system"), (1, "current_setup"))
            if ulog.get_default_parameters(bit)
        },
        "logged_messages": [[m.log_level, m.timestamp, m.message] for m in ulog.logged_messages],
        "logged_messages_tagged": {
            str(tag): [[m.log_level, m.timestamp, m.message] for m in msgs]
            for tag, msgs in ulog.logged_messages_tagged.items()
        },
        "dropouts": [[d.timestamp, d.duration] for d in ulog.dropouts],
        "formats": {
            name: [[t, n, f] for (t, n, f) in fmt.fields]
            for name, fmt in ulog.message_formats.items()
        },
        "pyulog_printed": [line for line in printed.splitlines() if line],
        "topics": topics,
    }


def write_csv(ulog, stem, out_dir):
    os.makedirs(out_dir, exist_ok=True)
    for d in ulog.data_list:
        names = columns(d)
        path = os.path.join(out_dir, f"{stem}_{d.name}_{d.multi_id}.csv")
        with open(path, "w", newline="\n") as f:
            f.write(",".join(names) + "\n")
            cols = [d.data[n] for n in names]
            for i in range(len(cols[0]) if cols else 0):
                f.write(",".join(str(c[i]) for c in cols) + "\n")


def make(path):
    stem = os.path.splitext(os.path.basename(path))[0]
    out = os.path.join(HERE, "expected", stem)
    printed = io.StringIO()
    # pyulog prints its complaints about a log to stdout: they are part of the summary.
    with contextlib.redirect_stdout(printed):
        ulog = ULog(path)
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(summary(ulog, printed.getvalue()), f, indent=1, sort_keys=True)
        f.write("\n")
    write_csv(ulog, stem, os.path.join(out, "csv"))


def main():
    files = sys.argv[1:] or sorted(
        os.path.join(HERE, "files", n) for n in os.listdir(os.path.join(HERE, "files"))
        if n.endswith(".ulg")
    )
    for path in files:
        make(path)
        print(f"expected/{os.path.splitext(os.path.basename(path))[0]}")


if __name__ == "__main__":
    main()
