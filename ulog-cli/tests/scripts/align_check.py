"""Checks a table of `ulog align --on GRID` against pandas and numpy on pyulog's data.

python3 align_check.py LOG TABLE.csv GRID METHOD TOLERANCE_US|- COUNTS TOPIC...

COUNTS is a JSON object of the rows our reader has of each topic (instance 0): where
pyulog has other rows (a damaged log of which we recover rows pyulog loses), the
comparison would be of different data, and the log is reported as skipped.

- previous: `pandas.merge_asof(direction="backward", allow_exact_matches=True)` of the
  grid's timestamps on each topic's rows (stably sorted by timestamp, so that the last
  written of equal timestamps is the one found), with `tolerance` when given;
- nearest: the same with `direction="nearest"`;
- linear: `numpy.interp` of every float/double column over the topic's rows, within
  the topic's first and last timestamps (empty cells outside); integer and boolean
  columns as `previous`. Quaternion columns (`q[0..3]`) are interpolated by slerp, not
  per column, and are left to the library's own tests; steps whose next row shares its
  timestamp with another row (where `numpy.interp` is undefined) are left out, counted.

Every cell of the table is compared: integers exactly, floats as float32/float64 of
the topic's type (linear within 2 ulps of numpy's float64 result rounded to the
type), absent cells where pandas finds no row. Prints a JSON summary; exits 1 with the
first difference.
"""

import csv
import json
import sys

import numpy as np
import pandas as pd
from pyulog import ULog


def fail(msg):
    print(msg, file=sys.stderr)
    sys.exit(1)


def main():
    log, table, grid, method, tolerance, counts, *topics = sys.argv[1:]
    tolerance = None if tolerance == "-" else int(tolerance)
    counts = json.loads(counts)
    ulog = ULog(log, [grid] + topics)
    for d in ulog.data_list:
        if d.multi_id == 0 and d.name in counts and len(d.data["timestamp"]) != counts[d.name]:
            print(json.dumps({"skipped": f"{d.name}: pyulog has {len(d.data['timestamp'])} rows, "
                              f"we have {counts[d.name]}"}))
            return

    def lowest(name):
        found = [d for d in ulog.data_list if d.name == name]
        if not found:
            fail(f"pyulog finds no topic {name}")
        return min(found, key=lambda d: d.multi_id)

    with open(table, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    ours = {name: [r[i] for r in body] for i, name in enumerate(header)}
    steps = np.array([int(v) for v in ours["timestamp"]], dtype=np.int64)

    g = lowest(grid)
    expected_steps = np.sort(g.data["timestamp"].astype(np.int64), kind="stable")
    if not np.array_equal(steps, expected_steps):
        fail(f"steps differ from {grid}'s timestamps")

    checked = {"steps": int(len(steps)), "columns": 0, "cells": 0, "absent": 0,
               "left_out_duplicate_times": 0, "quaternion_columns_left_out": 0}
    left = pd.DataFrame({"timestamp": steps})
    for name in topics:
        d = lowest(name)
        ts = d.data["timestamp"].astype(np.int64)
        order = np.argsort(ts, kind="stable")
        right = pd.DataFrame({"timestamp": ts[order], "_row": np.arange(len(ts))})
        direction = "nearest" if method == "nearest" else "backward"
        kwargs = {"tolerance": tolerance} if tolerance is not None else {}
        merged = pd.merge_asof(left, right, on="timestamp", direction=direction,
                               allow_exact_matches=True, **kwargs)
        picked = merged["_row"].to_numpy()
        sorted_ts = ts[order]
        first, last = (sorted_ts[0], sorted_ts[-1]) if len(ts) else (0, -1)
        # For linear: the step inside the topic's rows, and the next row's time.
        inside = (steps >= first) & (steps <= last)
        nxt = np.searchsorted(sorted_ts, steps, side="right")
        dup_next = np.zeros(len(steps), dtype=bool)
        if len(ts):
            counts = pd.Series(sorted_ts).value_counts()
            dups = set(counts[counts > 1].index.tolist())
            on_row = np.isin(steps, sorted_ts)
            dup_next = np.array([(not o) and i < len(sorted_ts) and sorted_ts[i] in dups
                                 for i, o in zip(nxt, on_row)], dtype=bool)

        for field in d.data:
            col = f"{name}.{field}"
            if col not in ours:
                continue
            cells = ours[col]
            values = d.data[field][order]
            is_float = values.dtype.kind == "f"
            quaternion = field.startswith("q[") or ".q[" in field
            if method == "linear" and quaternion and is_float:
                checked["quaternion_columns_left_out"] += 1
                continue
            checked["columns"] += 1
            for k, cell in enumerate(cells):
                if method == "linear":
                    if not inside[k]:
                        if cell != "":
                            fail(f"{col} at step {steps[k]}: {cell!r}, outside the topic's rows")
                        checked["absent"] += 1
                        continue
                    if dup_next[k]:
                        checked["left_out_duplicate_times"] += 1
                        continue
                    row = picked[k]
                    if is_float:
                        x = _interp(steps[k], sorted_ts, values, nxt[k], row)
                        _float_equal(col, steps[k], cell, x, values.dtype, ulps=2)
                    else:
                        _exact(col, steps[k], cell, values[int(row)])
                    checked["cells"] += 1
                    continue
                row = picked[k]
                if np.isnan(row):
                    if cell != "":
                        fail(f"{col} at step {steps[k]}: {cell!r} where pandas finds no row")
                    checked["absent"] += 1
                    continue
                v = values[int(row)]
                if is_float:
                    _float_equal(col, steps[k], cell, float(v), values.dtype, ulps=0)
                else:
                    _exact(col, steps[k], cell, v)
                checked["cells"] += 1
    print(json.dumps(checked))


def _interp(t, sorted_ts, values, nxt, row):
    """numpy.interp at t between the last row at or before t (`row`) and the next."""
    i = int(row)
    if sorted_ts[i] == t or nxt >= len(sorted_ts):
        return float(values[i])
    xp = np.array([sorted_ts[i], sorted_ts[nxt]], dtype=np.float64)
    fp = np.array([values[i], values[nxt]], dtype=np.float64)
    return float(np.interp(float(t), xp, fp))


def _exact(col, t, cell, v):
    if cell == "":
        fail(f"{col} at step {t}: empty where pandas finds {v!r}")
    if int(cell) != int(v):
        fail(f"{col} at step {t}: {cell} where pandas finds {v!r}")


def _float_equal(col, t, cell, x, dtype, ulps):
    if cell == "":
        fail(f"{col} at step {t}: empty where pandas/numpy find {x!r}")
    ty = np.float32 if dtype == np.float32 else np.float64
    ours = ty(float(cell))
    want = ty(x)
    if np.isnan(ours) and np.isnan(want):
        return
    if ours == want:
        return
    if ulps and np.isfinite(want):
        gap = abs(int(np.array(ours, ty).view(np.int32 if ty == np.float32 else np.int64))
                  - int(np.array(want, ty).view(np.int32 if ty == np.float32 else np.int64)))
        if gap <= ulps and np.sign(ours) == np.sign(want):
            return
    fail(f"{col} at step {t}: {cell} where pandas/numpy find {want!r}")


if __name__ == "__main__":
    main()
