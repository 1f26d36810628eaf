#!/usr/bin/env python3
"""A simulated fleet: the corpus logs repeated with new ids up to N logs, converted into
both dataset layouts (`ulog parquet`, and `ulog parquet --layout fleet`), also fed in
batches of `--batch` logs (a conversion each) and then compacted (`--compact`), with the
files each makes and DuckDB's times of the README's "Fleet analysis" queries over each.

Usage (from the repository root, after `cargo build --release -p ulog-cli`):

    python3 bench/fleet.py [--logs 2000] [--batch 100] [--corpus DIR] [--work DIR] [--runs 3]

Each copy is a corpus log with one logged string appended (`fleet copy <n>`, a valid
ULog message at the end of the file): a new file, so a new `log_id`, and the same
flights. The corpus is `$ULOG_CORPUS`, else `../shared/corpus/files`, else the
repository's `tests/corpus/files`. Needs the `duckdb` Python package. Prints a Markdown
table (bench/README.md keeps the last one).
"""
import argparse
import os
import re
import shutil
import statistics
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def corpus_dir(given):
    for d in (given, os.environ.get("ULOG_CORPUS"),
              os.path.join(ROOT, "..", "shared", "corpus", "files"),
              os.path.join(ROOT, "tests", "corpus", "files")):
        if d and os.path.isdir(d):
            return d
    sys.exit("no corpus found: pass --corpus DIR")


def logged_string(n):
    """A ULog logged-string message ('L'): level 6 (info), timestamp 0, text."""
    text = f"fleet copy {n}".encode()
    body = struct.pack("<BQ", ord("6"), 0) + text
    return struct.pack("<HB", len(body), ord("L")) + body


def make_fleet(corpus, count, out):
    logs = sorted(
        os.path.join(corpus, f) for f in os.listdir(corpus)
        if f.lower().endswith((".ulg", ".ulog")))
    os.makedirs(out, exist_ok=True)
    made = []
    for i in range(count):
        src = logs[i % len(logs)]
        dst = os.path.join(out, f"{i:05d}_{os.path.basename(src)}")
        with open(src, "rb") as f:
            data = f.read()
        with open(dst, "wb") as f:
            f.write(data + logged_string(i))
        made.append(dst)
    return made


def readme_queries():
    text = open(os.path.join(ROOT, "README.md"), encoding="utf-8").read()
    start = text.index("\n## Fleet analysis")
    end = text.find("\n## ", start + 1)
    return re.findall(r"```sql\n(.*?)```", text[start:end], re.S)


def files_of(dataset):
    count = size = 0
    for root, _, names in os.walk(dataset):
        for name in names:
            if name.endswith(".parquet"):
                count += 1
                size += os.path.getsize(os.path.join(root, name))
    return count, size


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--logs", type=int, default=2000)
    ap.add_argument("--corpus")
    ap.add_argument("--work")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--batch", type=int, default=100,
                    help="logs per conversion of the fleet fed in batches")
    ap.add_argument("--ulog", default=os.path.join(
        os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release", "ulog"))
    args = ap.parse_args()
    import duckdb

    work = args.work or tempfile.mkdtemp(prefix="ulog-fleet-")
    logs_dir = os.path.join(work, "logs")
    shutil.rmtree(logs_dir, ignore_errors=True)
    corpus = corpus_dir(args.corpus)
    made = make_fleet(corpus, args.logs, logs_dir)
    total = sum(os.path.getsize(p) for p in made)

    fleet = ["--layout", "fleet"]
    fed = os.path.join(work, "fed_in_batches")
    batches = [made[i:i + args.batch] for i in range(0, len(made), args.batch)]
    # Each row: its dataset, and the conversions that make it (timed together).
    layouts = {
        "file per log": ("file_per_log", [[logs_dir]]),
        "fleet (month)": ("fleet", [[logs_dir, *fleet]]),
        f"fleet, {len(batches)} conversions of {args.batch} logs": (
            fed, [[*batch, *fleet] for batch in batches]),
        "the same, then `--compact` (its time)": (fed, [["--compact"]]),
    }
    queries = readme_queries()
    rows = {}
    for name, (dataset, runs) in layouts.items():
        dataset = os.path.join(work, dataset)
        if runs[0] != ["--compact"]:
            shutil.rmtree(dataset, ignore_errors=True)
        start = time.monotonic()
        for run in runs:
            subprocess.run([args.ulog, "parquet", *run, "-o", dataset],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        took = time.monotonic() - start
        count, size = files_of(dataset)
        times = []
        for q in queries:
            sql = q.replace("DATASET", dataset)
            runs = []
            for _ in range(args.runs):
                con = duckdb.connect()
                t = time.monotonic()
                con.sql(sql).fetchall()
                runs.append(time.monotonic() - t)
                con.close()
            times.append(statistics.median(runs))
        rows[name] = (took, count, size, times)

    print(f"{args.logs} logs ({total / 1e9:.2f} GB; {len(os.listdir(corpus))} corpus "
          f"files repeated), `ulog parquet` ({args.ulog}), DuckDB {duckdb.__version__}, "
          f"median of {args.runs} runs per query, a new connection each.\n")
    head = ["layout", "convert s", "Parquet files", "MB"] + [f"Q{i + 1} s" for i in range(len(queries))]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for name, (took, count, size, times) in rows.items():
        cells = [name, f"{took:.1f}", str(count), f"{size / 1e6:.0f}"] + [f"{t:.3f}" for t in times]
        print("| " + " | ".join(cells) + " |")
    if not args.work:
        shutil.rmtree(work, ignore_errors=True)


main()
