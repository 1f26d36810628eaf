"""Checks the Parquet table of `ulog align` against the CSV table of the same command,
read by pyarrow and Python's csv module.

python3 align_parquet_check.py TABLE.csv TABLE.parquet FLAT_DIR

FLAT_DIR holds `ulog parquet --flatten` of the same topics (`<topic>_<N>.parquet`):
each column `topic.field` of the table must have the type of column `field` there
(nested padding, which that export leaves out, is a `uint8`).

- the same column names in the same order; `timestamp` is `uint64` and not nullable,
  every other column nullable;
- the same number of rows, and every cell: a null where the CSV cell is empty and
  only there; integers equal; booleans `0`/`1`; floats the same value of the column's
  type (bit for bit; `nan` where the value is NaN); text as the CSV writes it (the
  bytes as lossy UTF-8, trailing NULs kept) from Parquet's (Latin-1, trailing NULs
  removed).

Prints a JSON summary; exits 1 with the first difference.
"""

import csv
import json
import os
import re
import struct
import sys

import pyarrow as pa
import pyarrow.parquet as pq


def fail(msg):
    print(msg, file=sys.stderr)
    sys.exit(1)


def flat_type(flat_dir, column, cache):
    """The type of `column` (`topic.field`, `topic:N.field`) in the flattened export."""
    topic, field = column.split(".", 1)
    name, _, instance = topic.partition(":")
    path = os.path.join(flat_dir, f"{name}_{instance or 0}.parquet")
    if path not in cache:
        cache[path] = pq.read_schema(path)
    schema = cache[path]
    if field in schema.names:
        return schema.field(field).type
    if re.search(r"(^|\.)_padding", field):
        return pa.uint8()
    fail(f"{column}: no column {field} in {path}")


def same_float(cell, value, t):
    """Whether the CSV text `cell` reads as `value`, a float of Arrow type `t`."""
    fmt = "<f" if t == pa.float32() else "<d"
    ours = struct.unpack(fmt, struct.pack(fmt, float(cell)))[0]
    if ours != ours or value != value:
        return ours != ours and value != value
    return struct.pack(fmt, ours) == struct.pack(fmt, value)


def main():
    table_csv, table_parquet, flat_dir = sys.argv[1:]
    with open(table_csv, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    table = pq.read_table(table_parquet)
    schema = table.schema
    if schema.names != header:
        fail(f"columns differ:\n{schema.names}\n{header}")
    if table.num_rows != len(body):
        fail(f"{table.num_rows} rows in Parquet, {len(body)} in CSV")
    ts = schema.field("timestamp")
    if ts.type != pa.uint64() or ts.nullable:
        fail(f"timestamp: {ts.type}, nullable {ts.nullable}")

    summary = {"rows": len(body), "columns": len(header), "cells": 0, "nulls": 0,
               "types": {}}
    cache = {}
    for k, name in enumerate(header):
        field = schema.field(name)
        t = field.type
        if k > 0:
            if not field.nullable:
                fail(f"{name}: not nullable")
            want = flat_type(flat_dir, name, cache)
            if t != want:
                fail(f"{name}: {t}, the flattened export has {want}")
        summary["types"][str(t)] = summary["types"].get(str(t), 0) + 1
        values = table.column(name).to_pylist()
        for i, (row, value) in enumerate(zip(body, values)):
            cell = row[k]
            at = f"{name} at row {i + 1}"
            if value is None:
                if cell != "":
                    fail(f"{at}: null in Parquet, {cell!r} in CSV")
                summary["nulls"] += 1
                continue
            if cell == "":
                fail(f"{at}: {value!r} in Parquet, empty in CSV")
            if pa.types.is_floating(t):
                ok = same_float(cell, value, t)
            elif pa.types.is_boolean(t):
                ok = cell == ("1" if value else "0")
            elif pa.types.is_integer(t):
                ok = int(cell) == value
            elif pa.types.is_string(t):
                ok = value.encode("latin-1").decode("utf-8", "replace") == cell.rstrip("\0")
            else:
                fail(f"{name}: unexpected type {t}")
            if not ok:
                fail(f"{at}: {value!r} in Parquet, {cell!r} in CSV")
            summary["cells"] += 1
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
