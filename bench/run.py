#!/usr/bin/env python3
"""The benchmark harness: builds the programs and the big logs, runs every workload of
ours and of the peers as a whole process N times, and writes a table (median wall time,
MB/s, messages/s, peak RSS, ratios, targets met or missed, the machine).

    bench/run                 # full run on the two ~300 MB logs -> BENCHMARKS.md
    bench/run --smoke         # one run on a small corpus log, table to a temp file

Inputs: the shared corpus is found via $ULOG_CORPUS or ../shared/corpus (relative to
the repository root); the big logs are built with ../shared/tools/make_big.py
($ULOG_BENCH_TOOLS overrides the tools directory) into bench/data/ ($ULOG_BENCH_DATA
overrides) when absent. Peers: yule_log and px4-ulog are built from crates.io by the
bench crate; pyulog (`pip install pyulog==1.3.0`) runs `ULog(path)` and `ulog2csv`;
ulog_cpp, px4-ulog master and flight-review-rs are built from the peers folder
($ULOG_PEERS or ../shared/peers) by source_peers.py, each skipped with a line saying why
when it cannot be.
Wall time and peak RSS come from wait4() on each process. No timing is asserted.
"""

import argparse
import re
import atexit
import datetime
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import source_peers

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BENCH = os.path.join(ROOT, "bench")
# The heading of the part of BENCHMARKS.md written by hand, kept as it is by a run.
BY_HAND = "## Measured by hand"

# The two ~300 MB logs of the targets: (base log in the corpus, repeats, cached name).
BIG = [
    ("sample_px4_events.ulg", 200, "sample_px4_events_x200.ulg"),
    ("log_61_2024-2-6-16-27-02.ulg", 90, "log_61_x90.ulg"),
]
SMOKE_LOG = "sample_px4_events.ulg"
WRITE_MESSAGES = 5_000_000
SMOKE_WRITE_MESSAGES = 100_000
# A program whose first run takes longer than this runs at most SLOW_RUNS times.
SLOW_SECONDS = 30.0
SLOW_RUNS = 3
# GNU time (`-f %M`), for the peak RSS of each program alone (see run_once).
GNU_TIME = "/usr/bin/time" if sys.platform.startswith("linux") and os.access("/usr/bin/time", os.X_OK) else None


def log(msg):
    print(msg, file=sys.stderr, flush=True)


def corpus_dir():
    env = os.environ.get("ULOG_CORPUS")
    path = env if env else os.path.join(ROOT, "..", "shared", "corpus")
    return os.path.normpath(path)


def tools_dir():
    env = os.environ.get("ULOG_BENCH_TOOLS")
    path = env if env else os.path.join(ROOT, "..", "shared", "tools")
    return os.path.normpath(path)


def data_dir():
    env = os.environ.get("ULOG_BENCH_DATA")
    return os.path.abspath(env) if env else os.path.join(BENCH, "data")


def target_dir(default):
    env = os.environ.get("CARGO_TARGET_DIR")
    return os.path.abspath(env) if env else default


def build(peers, profile):
    """Builds the bench programs and the `ulog` CLI with cargo profile `profile` (release;
    the smoke run takes `test`, whose dependencies `cargo test` has built already);
    returns their paths."""
    cmd = ["cargo", "build", "--profile", profile, "--manifest-path", os.path.join(BENCH, "Cargo.toml")]
    if not peers:
        cmd.append("--no-default-features")
    log("== " + " ".join(cmd))
    subprocess.run(cmd, check=True, cwd=ROOT)
    cmd = ["cargo", "build", "--profile", profile, "-p", "ulog-cli"]
    log("== " + " ".join(cmd))
    subprocess.run(cmd, check=True, cwd=ROOT)
    return built_programs(peers, profile)


def build_baseline(tree, profile):
    """Builds `ours` and the `ulog` CLI of another checkout of this repository (an
    earlier commit, e.g. from `git worktree add`) in that checkout's own target
    directories; returns their paths."""
    tree = os.path.abspath(tree)
    env = dict(os.environ)
    env.pop("CARGO_TARGET_DIR", None)
    for cmd in (["cargo", "build", "--profile", profile, "--no-default-features", "--bin", "ours",
                 "--manifest-path", os.path.join(tree, "bench", "Cargo.toml")],
                ["cargo", "build", "--profile", profile, "-p", "ulog-cli"]):
        log("== (baseline) " + " ".join(cmd))
        subprocess.run(cmd, check=True, cwd=tree, env=env)
    sub = "debug" if profile == "test" else profile
    return {
        "ours": os.path.join(tree, "bench", "target", sub, "ours"),
        "ulog": os.path.join(tree, "target", sub, "ulog"),
    }


def with_baseline(progs, bins, base):
    """After each of our programs, the same command run with the baseline's binary."""
    out = []
    for p in progs:
        out.append(p)
        if not p.impl.startswith("ours") or not p.baseline:
            continue
        swap = {bins["ours"]: base["ours"], bins["ulog"]: base["ulog"]}
        if not any(a in swap for a in p.argv):
            continue
        argv = [swap.get(a, a) for a in p.argv]
        out.append(Program(p.workload, "baseline " + p.impl, argv, p.out_dir, p.msgs_from_output,
                           "the same, built from the baseline checkout", versus=p.impl,
                           statuses=p.statuses))
    return out


def built_programs(peers, profile):
    """Where the programs built with `profile` are."""
    # Cargo puts the test profile's programs in `debug`, beside the dev profile's.
    sub = "debug" if profile == "test" else profile
    bench_bin = os.path.join(target_dir(os.path.join(BENCH, "target")), sub)
    cli_bin = os.path.join(target_dir(os.path.join(ROOT, "target")), sub)
    return {
        "ours": os.path.join(bench_bin, "ours"),
        "floor": os.path.join(bench_bin, "floor"),
        "peers": os.path.join(bench_bin, "peers") if peers else None,
        "ulog": os.path.join(cli_bin, "ulog"),
    }


def big_inputs():
    files = os.path.join(corpus_dir(), "files")
    make_big = os.path.join(tools_dir(), "make_big.py")
    out_dir = data_dir()
    os.makedirs(out_dir, exist_ok=True)
    paths = []
    for base, repeats, name in BIG:
        out = os.path.join(out_dir, name)
        if not os.path.exists(out):
            src = os.path.join(files, base)
            for need in (src, make_big):
                if not os.path.exists(need):
                    sys.exit(f"run: {need} is missing (set ULOG_CORPUS / ULOG_BENCH_TOOLS)")
            log(f"== building {name}: {base} x {repeats}")
            subprocess.run([sys.executable, make_big, src, str(repeats), out + ".tmp"], check=True)
            os.replace(out + ".tmp", out)
        paths.append((f"{base} x {repeats}", out))
    return paths


def smoke_inputs():
    src = os.path.join(corpus_dir(), "files", SMOKE_LOG)
    if os.path.exists(src):
        return [(SMOKE_LOG, src)]
    # Without the corpus: the examples' committed reference log.
    ref = os.path.join(ROOT, "examples", "data", "reference.ulg")
    return [("examples/data/reference.ulg", ref)]


def settle_page_cache(path):
    """Drops `path` from the page cache and reads it back sequentially in 1 MiB reads."""
    fd = os.open(path, os.O_RDONLY)
    try:
        if hasattr(os, "posix_fadvise"):
            os.posix_fadvise(fd, 0, 0, os.POSIX_FADV_DONTNEED)
        while os.read(fd, 1 << 20):
            pass
    finally:
        os.close(fd)


def have_pyulog():
    try:
        import pyulog  # noqa: F401
    except ImportError:
        return False
    return True


def have_ulog_rs():
    try:
        import ulog_rs  # noqa: F401
    except ImportError:
        return False
    return True


# The topic the Python rows load alone (message_name_filter_list): in every BIG log.
ONE_TOPIC = "vehicle_attitude"


def python_loads(reader, module, path):
    """The Python rows of one reader: every topic, one topic, and pandas frames of
    every topic."""
    run = [sys.executable, "-c"]
    return [
        Program("columnar load", f"{reader} ULog(path)",
                run + [f"import sys; from {module} import ULog; ULog(sys.argv[1])", path],
                note="Python process, numpy columns"),
        Program("columnar load", f"{reader} ULog(path, [{ONE_TOPIC}])",
                run + [f"import sys; from {module} import ULog; ULog(sys.argv[1], [sys.argv[2]])",
                       path, ONE_TOPIC],
                note="message_name_filter_list of one topic"),
        Program("columnar load", f"{reader} ULog(path) + pandas frames",
                run + [f"import sys, pandas; from {module} import ULog\n"
                       "for d in ULog(sys.argv[1]).data_list: pandas.DataFrame(d.data)", path],
                note="a pandas.DataFrame of every topic"),
    ]


# The topics `ulog align` puts on one time base (in every BIG log), the first the
# steps: what a user would look at together (attitude, position, battery).
ALIGN_TOPICS = ["vehicle_attitude", "vehicle_local_position", "battery_status"]

# `ulog align LOG TOPICS --on FIRST -o OUT` with pyulog and pandas: the steps are the
# first topic's timestamps (stably sorted), each topic's columns `topic.field` the
# last row at or before each step.
PANDAS_ALIGN = """
import sys
import pandas as pd
from pyulog import ULog
path, out, *topics = sys.argv[1:]
data = {d.name: d.data for d in ULog(path, topics).data_list if d.multi_id == 0}
table = pd.DataFrame({"timestamp": data[topics[0]]["timestamp"]}).sort_values(
    "timestamp", kind="stable", ignore_index=True)
for t in topics:
    right = pd.DataFrame(data[t]).sort_values("timestamp", kind="stable", ignore_index=True)
    right.columns = [f"{t}.{c}" for c in right.columns]
    table = pd.merge_asof(table, right, left_on="timestamp", right_on=f"{t}.timestamp",
                          direction="backward")
table.to_csv(out, index=False)
"""


def have_pandas():
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return have_pyulog()


def ulog2csv_cmd():
    exe = shutil.which("ulog2csv")
    if exe:
        return [exe]
    if have_pyulog():
        return [sys.executable, "-c", "import sys; from pyulog.ulog2csv import main; sys.exit(main())"]
    return None


def cli_has(ulog, sub):
    r = subprocess.run([ulog, sub, "--help"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return r.returncode == 0


class Program:
    """One whole-process command of a workload."""

    def __init__(self, workload, impl, argv, out_dir=False, msgs_from_output=False, note="",
                 versus=None, statuses=(0,), baseline=True):
        self.workload = workload
        # Exit statuses of a successful run (`ulog check`: 1 when the log has warnings).
        self.statuses = statuses
        # The implementation this row's ratio is taken against (default: the
        # workload's first `ours` row).
        self.versus = versus
        # Whether `--baseline` also runs it built from the baseline checkout (not for
        # options that checkout may predate).
        self.baseline = baseline
        self.impl = impl
        self.argv = argv  # a list; "{out}" is replaced by a fresh empty directory
        self.out_dir = out_dir
        self.msgs_from_output = msgs_from_output
        self.note = note


def run_once(p, scratch):
    """Runs `p` once: (wall seconds, peak RSS bytes, its key=value output)."""
    out = None
    argv = p.argv
    if p.out_dir:
        out = tempfile.mkdtemp(dir=scratch)
        argv = [a.replace("{out}", out) for a in argv]
    rss_file = None
    if GNU_TIME:
        # The peak RSS of a process forked from this Python process would start at
        # Python's own (Linux keeps the high-water mark across exec): GNU time is a
        # small parent whose report is the program's own.
        fd, rss_file = tempfile.mkstemp(dir=scratch)
        os.close(fd)
        argv = [GNU_TIME, "-f", "%M", "-o", rss_file] + argv
    with tempfile.TemporaryFile() as so, tempfile.TemporaryFile() as se:
        start = time.perf_counter()
        proc = subprocess.Popen(argv, stdout=so, stderr=se)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.perf_counter() - start
        proc.returncode = os.waitstatus_to_exitcode(status)
        so.seek(0)
        se.seek(0)
        stdout = so.read().decode(errors="replace")
        stderr = se.read().decode(errors="replace")
    # ru_maxrss is in KiB on Linux, bytes on macOS.
    rss = usage.ru_maxrss * (1 if sys.platform == "darwin" else 1024)
    if rss_file:
        with open(rss_file) as f:
            lines = f.read().split()
        os.remove(rss_file)
        if lines and lines[-1].isdigit():
            rss = int(lines[-1]) * 1024
    parquet_bytes = None
    if out:
        parquet_bytes = sum(os.path.getsize(os.path.join(d, f))
                            for d, _, files in os.walk(out) for f in files if f.endswith(".parquet"))
        shutil.rmtree(out, ignore_errors=True)
    if proc.returncode not in p.statuses:
        raise RuntimeError(
            f"{' '.join(argv)} exited with {proc.returncode}:\n{stderr[-2000:]}{stdout[-500:]}"
        )
    kv = {}
    for tok in stdout.split():
        if "=" in tok:
            k, v = tok.split("=", 1)
            kv[k] = v
    if parquet_bytes:
        kv["parquet_bytes"] = str(parquet_bytes)
    cpu = usage.ru_utime + usage.ru_stime
    return wall, rss, kv, cpu


def measure(progs, runs, scratch):
    """Runs every program of `progs` up to `runs` times, in rounds (each program once a
    round, in turn), so that a slow spell of the machine falls on all of them rather
    than on one program's runs: a list of results (None where a run failed), in order."""
    state = [{"walls": [], "cpus": [], "rsss": [], "kv": {}, "n": runs, "error": None} for _ in progs]
    for i in range(runs):
        for p, s in zip(progs, state):
            if s["error"] is not None or len(s["walls"]) >= s["n"]:
                continue
            try:
                wall, rss, kv, cpu = run_once(p, scratch)
            except Exception as e:  # a failing program is a row, and a failed run
                log(f"   {p.workload}: {p.impl}: FAILED: {e}")
                s["error"] = e
                continue
            s["walls"].append(wall)
            s["cpus"].append(cpu)
            s["rsss"].append(rss)
            s["kv"] = kv
            if i == 0 and wall > SLOW_SECONDS and s["n"] > SLOW_RUNS:
                s["n"] = SLOW_RUNS
        log(f"   round {i + 1} of {runs} done")
    results = []
    for p, s in zip(progs, state):
        if s["error"] is not None or not s["walls"]:
            results.append(None)
            continue
        r = {
            "runs": len(s["walls"]),
            "median": statistics.median(s["walls"]),
            "min": min(s["walls"]),
            "max": max(s["walls"]),
            "cpu": statistics.median(s["cpus"]),
            "rss": max(s["rsss"]),
            "kv": s["kv"],
        }
        log(f"   {p.workload}: {p.impl}: median {r['median']:.3f} s, "
            f"peak RSS {r['rss'] / 2**20:.1f} MiB ({r['runs']} runs)")
        results.append(r)
    return results


def log_duration(ulog, path):
    """The log's duration in seconds, from `ulog info` (None if it has no `cut`)."""
    if not cli_has(ulog, "cut"):
        return None
    text = subprocess.run([ulog, "info", path], capture_output=True, text=True).stdout
    m = re.search(r"duration: (\d+):(\d+):(\d+)", text)
    if not m:
        return None
    h, mi, se = (int(x) for x in m.groups())
    return h * 3600 + mi * 60 + se


def programs(bins, path, peers, pyulog_ok, ulog2csv, parquet, taskset, extra):
    b = bins
    pandas_ok = pyulog_ok and have_pandas()
    P = []
    P.append(Program("framing", "floor (header walk)", [b["floor"], path],
                     note="mmap, walk the 3-byte headers, count"))
    P.append(Program("framing", "ours", [b["ours"], "framing", path],
                     note="ULog::parse on a memory map"))
    P.append(Program("framing", "ours (scan, no index)", [b["ours"], "scan", path],
                     note="scan over a memory map: framing without the index (for reference)"))
    if "px4_master" in extra:
        P.append(Program("framing", "px4-ulog master (framing)", [extra["px4_master"], "framing", path],
                         versus="ours (scan, no index)",
                         note="LogParser::consume_bytes in 1 MiB reads, data messages counted; "
                              "ratio against ours (scan, no index)"))
    P.append(Program("generic decode", "ours (stream)", [b["ours"], "decode-stream", path],
                     note="scan of Source::file: read() in 256 KiB chunks, one pass"))
    P.append(Program("generic decode", "ours (stream, read ahead)", [b["ours"], "decode-ahead", path],
                     note="scan with read_ahead(true): the same, the next 1 MiB read on a second thread"))
    P.append(Program("generic decode", "ours (mmap)", [b["ours"], "decode-mmap", path],
                     note="scan over a memory map, one pass"))
    if peers:
        P.append(Program("generic decode", "px4-ulog 0.6 (stream)", [b["peers"], "px4-stream", path],
                         note="callback, every flattened field"))
        P.append(Program("generic decode", "yule_log 0.4 (raw)", [b["peers"], "yule-raw", path],
                         note="ULogParser, every field"))
    if "px4_master" in extra:
        P.append(Program("generic decode", "px4-ulog master (stream)", [extra["px4_master"], "stream", path],
                         note="the same code as px4-ulog 0.6 (stream), built against master"))
    if "ulog_cpp" in extra:
        P.append(Program("generic decode", "ulog_cpp (stream)", [extra["ulog_cpp"], "stream", path],
                         note="Reader + header-only DataContainer, fread 256 KiB; every field "
                              "(padding left out) read as a typed Value"))
    P.append(Program("typed decode", "ours (derive)", [b["ours"], "typed", path],
                     msgs_from_output=True,
                     note="sensor_combined + vehicle_attitude: scan_topics over a memory map"))
    P.append(Program("typed decode", "ours (derive, indexed)", [b["ours"], "typed-indexed", path],
                     msgs_from_output=True, note="the same through ULog::parse + ULog::read::<T>"))
    if peers:
        P.append(Program("typed decode", "yule_log 0.4 (derive)", [b["peers"], "yule-derive", path],
                         msgs_from_output=True, note="same two topics, same fields"))
    P.append(Program("columnar load", "ours (2 threads)", [b["ours"], "columns", path, "2"],
                     note="load_columns(Source::file, threads(2)): read(), no map; topics shared by 2 threads"))
    P.append(Program("columnar load", "ours (1 thread)", [b["ours"], "columns", path, "1"],
                     note="load_columns(Source::file, threads(1))"))
    P.append(Program("columnar load", "ours (indexed, 2 threads)",
                     [b["ours"], "columns-indexed", path, "2"],
                     note="ULog::parse on a memory map + load_columns(&log, threads(2))"))
    if peers:
        P.append(Program("columnar load", "px4-ulog 0.6 (full_parser)", [b["peers"], "px4-full", path],
                         note="full_parser::read_file"))
    if "ulog_cpp" in extra:
        P.append(Program("columnar load", "ulog_cpp (DataContainer)", [extra["ulog_cpp"], "load", path],
                         note="DataContainer(FullLog): every message kept (raw payloads, "
                              "decoded on access)"))
    if pyulog_ok:
        P.extend(python_loads("pyulog 1.3", "pyulog", path))
    if have_ulog_rs():
        P.extend(python_loads("ulog_rs", "ulog_rs", path))
    P.append(Program("CSV export", "ours (ulog csv)", [b["ulog"], "csv", path, "-o", "{out}", "--quiet"],
                     out_dir=True, note="one CSV per topic"))
    if taskset:
        P.append(Program("CSV export", "ours (ulog csv, 1 core)",
                         [taskset, "-c", "0", b["ulog"], "csv", path, "-o", "{out}", "--quiet"],
                         out_dir=True, note="taskset -c 0"))
    if ulog2csv:
        P.append(Program("CSV export", "pyulog 1.3 ulog2csv", ulog2csv + ["-o", "{out}", path],
                         out_dir=True, note="Python process"))
    P.append(Program("check", "ours (ulog check)", [b["ulog"], "check", path], statuses=(0, 1),
                     note="framing, every finding, exit 1 on warnings"))
    # The commands that need only the metadata: one pass in chunks, against the floor
    # of any reader that reads the file with read() in bounded memory.
    P.append(Program("metadata", "floor (header walk, read in chunks)", [b["floor"], path, "--chunks"],
                     note="read() in 1 MiB chunks into one buffer, walk the 3-byte headers, count"))
    P.append(Program("metadata", "ours (scan of a file, read ahead)", [b["ours"], "scan-file", path],
                     versus="floor (header walk, read in chunks)",
                     note="scan(Source::file, read_ahead): framing in chunks, nothing kept (the "
                          "breakdown of the rows below); ratio against the chunked floor"))
    P.append(Program("metadata", "ours (metadata pass)", [b["ours"], "metadata", path],
                     versus="floor (header walk, read in chunks)",
                     note="the same with keep_metadata(true): ulog info's pass without the "
                          "printing; ratio against the chunked floor"))
    P.append(Program("metadata", "ours (ulog info)", [b["ulog"], "info", path],
                     versus="floor (header walk, read in chunks)",
                     note="one pass in chunks (read ahead), metadata kept, rows counted; "
                          "ratio against the chunked floor"))
    # PX4 events decoded and merged with the logged strings, as ulog_messages prints them.
    P.append(Program("metadata", "ours (ulog messages)", [b["ulog"], "messages", path],
                     versus="floor (header walk, read in chunks)",
                     note="the same pass, events decoded with the log's metadata, merged with the "
                          "logged strings; ratio against the chunked floor"))
    if pyulog_ok:
        P.append(Program("events", "pyulog 1.3 ulog_messages",
                         [sys.executable, "-c",
                          "import sys; from pyulog.messages import main; "
                          "sys.argv = ['ulog_messages', sys.argv[1]]; main()", path],
                         versus="ours (ulog messages)",
                         note="Python process; reads only the event topic's data; "
                              "ratio against ours (ulog messages)"))
    # Editing: a tenth of the log, from its middle, against reading it whole.
    duration = log_duration(b["ulog"], path)
    if duration:
        P.append(Program("cut", "ours (ulog cut, middle 10 %)",
                         [b["ulog"], "cut", path, "-o", "{out}/cut.ulg",
                          "--start", f"{duration * 0.45:.3f}", "--end", f"{duration * 0.55:.3f}"],
                         out_dir=True, baseline=False, versus="ours (ulog info)",
                         note="all topics, 10 % of the time; ratio against ulog info (metadata)"))
    # Three topics on one time base, against `ulog csv -m` of the same three (the
    # issue's target: no slower than 1.5 times) and pyulog + pandas doing the same.
    if cli_has(b["ulog"], "align"):
        topics = ",".join(ALIGN_TOPICS)
        P.append(Program("align", "ours (ulog csv -m, the three topics)",
                         [b["ulog"], "csv", path, "-m", topics, "-o", "{out}", "--quiet"],
                         out_dir=True, baseline=False,
                         note=f"{', '.join(ALIGN_TOPICS)}: one CSV per topic"))
        P.append(Program("align", "ours (ulog align)",
                         [b["ulog"], "align", path, topics, "--on", ALIGN_TOPICS[0],
                          "-o", "{out}/aligned.csv"],
                         out_dir=True, baseline=False, versus="ours (ulog csv -m, the three topics)",
                         note=f"the three topics --on {ALIGN_TOPICS[0]} (previous), one CSV; "
                              "ratio against ulog csv -m"))
        if pandas_ok:
            P.append(Program("align", "pyulog 1.3 + pandas merge_asof",
                             [sys.executable, "-c", PANDAS_ALIGN, path, "{out}/aligned.csv",
                              *ALIGN_TOPICS],
                             out_dir=True, versus="ours (ulog align)",
                             note="ULog(path, topics), merge_asof(direction=\"backward\") of each "
                                  f"topic on {ALIGN_TOPICS[0]}'s timestamps, to_csv; ratio "
                                  "against ours (ulog align)"))
    # MCAP (ROS 2 CDR, zstd chunks): at least as fast as the CSV export.
    if cli_has(b["ulog"], "mcap"):
        P.append(Program("MCAP export", "ours (ulog mcap)",
                         [b["ulog"], "mcap", path, "-o", "{out}/log.mcap"],
                         out_dir=True, baseline=False,
                         note="CDR messages, ros2msg schemas, 1 MiB zstd chunks"))
    # The flight report (one HTML page): under 3 s per 300 MB of log (issue 28).
    if cli_has(b["ulog"], "report"):
        P.append(Program("report", "ours (ulog report)",
                         [b["ulog"], "report", path, "-o", "{out}/report.html"],
                         out_dir=True, baseline=False,
                         note="one HTML page: header, standard plots thinned, tables"))
    # The flight analysis (issue 47): one pass, at most 2 × ulog info, bounded memory;
    # flight-review-rs computes the same analysis (and its diagnostics) while it
    # writes metadata.json.
    if cli_has(b["ulog"], "analyze"):
        P.append(Program("flight analysis", "ours (ulog analyze)",
                         [b["ulog"], "analyze", "--json", path],
                         versus="ours (ulog info)",
                         note="diagnostics, statistics, spectra, step responses; ratio "
                              "against ulog info"))
        if "flight_review" in extra:
            P.append(Program("flight analysis", "flight-review-rs (ulog-convert --metadata-only)",
                             [extra["flight_review"], "--metadata-only", path, "{out}"],
                             out_dir=True, versus="ours (ulog analyze)",
                             note="metadata.json with its analysis and diagnostics; ratio "
                                  "against ours (ulog analyze)"))
    # Parquet export: run when the CLI was built with its `parquet` subcommand.
    if parquet:
        # Snappy, as the rows of earlier runs (the default is zstd since datasets).
        P.append(Program("Parquet export", "ours (ulog parquet)",
                         [b["ulog"], "parquet", path, "-o", "{out}", "--compression", "snappy"],
                         out_dir=True, note="--compression snappy"))
        if taskset:
            P.append(Program("Parquet export", "ours (ulog parquet, 1 core)",
                             [taskset, "-c", "0", b["ulog"], "parquet", path, "-o", "{out}",
                              "--compression", "snappy"],
                             out_dir=True, note="taskset -c 0, --compression snappy"))
        P.append(Program("Parquet export", "ours (ulog parquet, zstd)",
                         [b["ulog"], "parquet", path, "-o", "{out}", "--compression", "zstd"],
                         out_dir=True, note="--compression zstd (level 1)", baseline=False))
        # flight-review-rs writes flattened columns: this row is the one to compare.
        P.append(Program("Parquet export", "ours (ulog parquet, zstd, flat)",
                         [b["ulog"], "parquet", path, "-o", "{out}", "--compression", "zstd",
                          "--flatten"],
                         out_dir=True, note="--compression zstd --flatten (one column per value, "
                         "as flight-review-rs writes them)", baseline=False))
    if "flight_review" in extra:
        P.append(Program("Parquet export", "flight-review-rs (ulog-convert)",
                         [extra["flight_review"], path, "{out}"], out_dir=True,
                         versus="ours (ulog parquet, zstd, flat)" if parquet else None,
                         note="ZSTD Parquet (flattened columns) + metadata.json, rayon; "
                         "ratio against ours (zstd, flat)"))
    return P


def machine(note):
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    mem = ""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemTotal"):
                    mem = f"{int(line.split()[1]) / 1024 / 1024:.1f} GiB"
    except OSError:
        pass
    osname = platform.platform()
    try:
        with open("/etc/os-release") as f:
            for line in f:
                if line.startswith("PRETTY_NAME="):
                    osname = line.split("=", 1)[1].strip().strip('"') + f" (kernel {platform.release()})"
    except OSError:
        pass
    rustc = subprocess.run(["rustc", "-V"], capture_output=True, text=True).stdout.strip()
    pyver = platform.python_version()
    pyulog_ver = "not installed"
    try:
        from importlib.metadata import version

        pyulog_ver = version("pyulog")
    except Exception:
        pass
    rows = [
        ("CPU", cpu),
        ("Cores (logical)", str(os.cpu_count())),
        ("RAM", mem),
        ("OS", osname),
        ("rustc", rustc),
        ("Python / pyulog", f"{pyver} / {pyulog_ver}"),
        ("Date", datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")),
    ]
    if note:
        rows.append(("Note", note))
    return rows


def fmt_s(x):
    return f"{x:.3f}" if x < 10 else f"{x:.2f}"


def table(results, size, msgs):
    """Markdown rows for one input: time, throughput, RSS, ratio to ours."""
    lines = [
        "| workload | implementation | runs | median s | spread | CPU s | MB/s | M msg/s | peak RSS MiB | × ours (time) | how |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    ours_by_workload = {}
    by_impl = {(p.workload, p.impl): r["median"] for p, r in results if r}
    any_impl = {p.impl: r["median"] for p, r in results if r}
    for p, r in results:
        if r and p.impl.startswith("ours") and p.workload not in ours_by_workload:
            ours_by_workload[p.workload] = r["median"]
    for p, r in results:
        if r is None:
            lines.append(f"| {p.workload} | {p.impl} | – | failed | | | | | | | {p.note} |")
            continue
        t = r["median"]
        m = int(r["kv"].get("messages", 0)) if p.msgs_from_output else msgs
        ref = ours_by_workload.get(p.workload)
        ratio = f"{t / ref:.2f}" if ref and not p.impl.startswith("ours") else ""
        if p.versus and by_impl.get((p.workload, p.versus)):
            ratio = f"{t / by_impl[(p.workload, p.versus)]:.2f}"
        elif p.versus and any_impl.get(p.versus):
            # A row of another workload (each command runs once per input).
            ratio = f"{t / any_impl[p.versus]:.2f}"
        if p.workload == "framing" and p.impl.startswith("floor") and "framing" in ours_by_workload:
            ratio = f"{t / ours_by_workload['framing']:.2f}"
        note = p.note
        if "parquet_bytes" in r["kv"]:
            note = (note + "; " if note else "") + f"output {int(r['kv']['parquet_bytes']) / 1e6:,.1f} MB of Parquet"
        lines.append(
            f"| {p.workload} | {p.impl} | {r['runs']} | {fmt_s(t)} | {(r['max'] - r['min']) / t:.0%} | "
            f"{fmt_s(r['cpu'])} | {size / t / 1e6:,.0f} | "
            f"{m / t / 1e6:.1f} | {r['rss'] / 2**20:,.1f} | {ratio} | {note} |"
        )
    return lines


def targets(results, size):
    """(target, measured, met) for one input."""
    med = {p.impl: r for p, r in results if r}

    def t(impl):
        r = med.get(impl)
        return r["median"] if r else None

    def rss(impl):
        r = med.get(impl)
        return r["rss"] if r else None

    out = []

    def ratio(name, a, b, limit, le=True, unit="×"):
        if a is None or b is None:
            out.append((name, "not measured", None))
            return
        x = a / b
        ok = x <= limit if le else x >= limit
        out.append((name, f"{x:.3f}{unit}", ok))

    ratio("framing ≤ 1.5 × the floor", t("ours"), t("floor (header walk)"), 1.5)
    ratio("generic decode (stream) ≤ 0.5 × px4-ulog stream", t("ours (stream)"), t("px4-ulog 0.6 (stream)"), 0.5)
    ratio("generic decode (stream, read ahead on a 2nd thread) ≤ 0.5 × px4-ulog stream",
          t("ours (stream, read ahead)"), t("px4-ulog 0.6 (stream)"), 0.5)
    ratio("generic decode (mmap) ≤ 0.5 × px4-ulog stream", t("ours (mmap)"), t("px4-ulog 0.6 (stream)"), 0.5)
    ratio("typed decode ≤ 0.05 × yule_log derive", t("ours (derive)"), t("yule_log 0.4 (derive)"), 0.05)
    ratio("typed decode ≤ 2 × our framing", t("ours (derive)"), t("ours"), 2.0)
    ratio("columnar load ≤ 0.5 × px4-ulog full_parser", t("ours (2 threads)"), t("px4-ulog 0.6 (full_parser)"), 0.5)
    ratio("columnar load ≤ 0.05 × pyulog ULog(path)", t("ours (2 threads)"), t("pyulog 1.3 ULog(path)"), 0.05)
    ratio("columnar load peak RSS ≤ 1.2 × file size", rss("ours (2 threads)"), size, 1.2)
    ratio("Python: ulog_rs ULog(path) ≤ 0.05 × pyulog's", t("ulog_rs ULog(path)"),
          t("pyulog 1.3 ULog(path)"), 0.05)
    ratio(f"Python: ulog_rs ULog(path, [{ONE_TOPIC}]) ≤ 0.02 × pyulog's",
          t(f"ulog_rs ULog(path, [{ONE_TOPIC}])"), t(f"pyulog 1.3 ULog(path, [{ONE_TOPIC}])"), 0.02)
    ratio("Python: ulog_rs peak RSS ≤ pyulog's", rss("ulog_rs ULog(path)"),
          rss("pyulog 1.3 ULog(path)"), 1.0)
    streams = {n: rss(n) for n in ("ours (stream)", "ours (stream, read ahead)") if rss(n)}
    if streams:
        worst = max(streams, key=streams.get)
        r = streams[worst]
        out.append((f"streaming decode peak RSS ≤ 16 MiB (the larger of the stream rows: {worst})",
                    f"{r / 2**20:.1f} MiB", r <= 16 * 2**20))
    else:
        out.append(("streaming decode peak RSS ≤ 16 MiB", "not measured", None))
    ratio("CSV export ≥ 10 × faster than ulog2csv", t("pyulog 1.3 ulog2csv"), t("ours (ulog csv)"), 10, le=False)
    ratio("columnar load on 2 cores ≥ 1.6 × faster than on 1", t("ours (1 thread)"), t("ours (2 threads)"), 1.6, le=False)
    ratio("CSV export on 2 cores ≥ 1.6 × faster than on 1", t("ours (ulog csv, 1 core)"), t("ours (ulog csv)"), 1.6, le=False)
    # The memory bound of the reliability work: twice the input plus a fixed
    # allowance (tests/memory.rs in ulog-cli checks it on the inputs that broke it).
    bound = 2 * size + 320 * 2**20
    ratio("check peak RSS ≤ 2 × file size + 320 MiB", rss("ours (ulog check)"), bound, 1.0)
    if "ours (ulog parquet)" in med:
        ratio("Parquet export on 2 cores ≥ 1.6 × faster than on 1",
              t("ours (ulog parquet, 1 core)"), t("ours (ulog parquet)"), 1.6, le=False)
        ratio("Parquet export peak RSS ≤ 2 × file size + 320 MiB", rss("ours (ulog parquet)"), bound, 1.0)
        ratio("Parquet export peak RSS ≤ 0.5 × file size", rss("ours (ulog parquet)"), size, 0.5)
    # The peers built from source (source_peers.py).
    fr = "flight-review-rs (ulog-convert)"
    for ours, what in (("ours (ulog parquet, zstd, flat)", "flattened, as flight-review-rs writes"),
                       ("ours (ulog parquet, zstd)", "nested columns")):
        ratio(f"Parquet export (zstd, {what}) ≤ 0.33 × flight-review-rs ulog-convert",
              t(ours), t(fr), 0.33)
        a, b = out_bytes(med.get(ours)), out_bytes(med.get(fr))
        # The fleet issue's words: no larger than its files + 20 % (smaller files for
        # the same data are no miss).
        label = f"Parquet (zstd, {what}) files ≤ 1.2 × flight-review-rs's size"
        if a and b:
            out.append((label, f"{a / b:.3f}×", a / b <= 1.2))
        else:
            out.append((label, "not measured", None))
    ratio("generic decode (stream) ≤ 0.5 × ulog_cpp stream", t("ours (stream)"), t("ulog_cpp (stream)"), 0.5)
    ratio("columnar load ≤ 0.2 × ulog_cpp DataContainer load", t("ours (2 threads)"),
          t("ulog_cpp (DataContainer)"), 0.2)
    ratio("framing (scan, no index) ≤ px4-ulog master framing", t("ours (scan, no index)"),
          t("px4-ulog master (framing)"), 1.0)
    ratio("generic decode (stream) ≤ 0.5 × px4-ulog master stream", t("ours (stream)"),
          t("px4-ulog master (stream)"), 0.5)
    ratio("cutting 10 % of the log < reading it (ulog info)", t("ours (ulog cut, middle 10 %)"),
          t("ours (ulog info)"), 1.0)
    ratio("events (ulog messages) ≤ 0.1 × pyulog ulog_messages", t("ours (ulog messages)"),
          t("pyulog 1.3 ulog_messages"), 0.1)
    # The commands that need only the metadata read the log once in chunks (issue 48).
    chunked = "floor (header walk, read in chunks)"
    for cmd in ("info", "messages"):
        ratio(f"ulog {cmd} ≤ 1.3 × the floor read in chunks", t(f"ours (ulog {cmd})"), t(chunked), 1.3)
        ratio(f"ulog {cmd} peak RSS ≤ 32 MiB", rss(f"ours (ulog {cmd})"), 32 * 2**20, 1.0)
    ratio("MCAP export ≤ CSV export (ulog csv)", t("ours (ulog mcap)"), t("ours (ulog csv)"), 1.0)
    ratio("align ≤ 1.5 × csv -m (the same three topics)", t("ours (ulog align)"),
          t("ours (ulog csv -m, the three topics)"), 1.5)
    ratio("flight analysis (ulog analyze) ≤ 2 × ulog info", t("ours (ulog analyze)"),
          t("ours (ulog info)"), 2.0)
    ratio("flight analysis peak RSS ≤ 64 MiB", rss("ours (ulog analyze)"), 64 * 2**20, 1.0)
    ratio("flight analysis ≤ flight-review-rs ulog-convert --metadata-only",
          t("ours (ulog analyze)"), t("flight-review-rs (ulog-convert --metadata-only)"), 1.0)
    # Measured as a fraction of the time allowed for this log's size.
    ratio("flight report ≤ 3 s per 300 MB of log", t("ours (ulog report)"), 3.0 * size / 300e6, 1.0)
    # Bounded whatever the log's size: the report reads the log in passes of chunks.
    ratio("flight report peak RSS ≤ 64 MiB", rss("ours (ulog report)"), 64 * 2**20, 1.0)
    return out


def out_bytes(r):
    """Bytes of Parquet a program wrote (its last run), or None."""
    if not r or "parquet_bytes" not in r["kv"]:
        return None
    return int(r["kv"]["parquet_bytes"])


def kept_by_hand(path):
    """The lines of `path` from its BY_HAND heading on (none if it has none)."""
    try:
        with open(path) as f:
            lines = f.read().split("\n")
    except FileNotFoundError:
        return []
    for i, line in enumerate(lines):
        if line.strip() == BY_HAND:
            return lines[i:]
    return []


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--smoke", action="store_true",
                    help="one run on a small corpus log; table to a temp file unless --out")
    ap.add_argument("--runs", type=int, help="runs per program (default 5; 1 with --smoke)")
    ap.add_argument("--out", help="where to write the table (default BENCHMARKS.md at the root)")
    ap.add_argument("--no-peers", action="store_true", help="skip the peers (yule_log, px4-ulog, ulog_cpp, flight-review-rs); pyulog still runs")
    ap.add_argument("--no-build", action="store_true", help="use the programs already built")
    ap.add_argument("--note", default="", help="a note for the machine section (e.g. the machine was shared)")
    ap.add_argument("--baseline", metavar="DIR",
                    help="another checkout of this repository (e.g. `git worktree add DIR COMMIT`): "
                         "each of our programs also runs built from it, in the same rounds, "
                         "its ratio taken against ours")
    ap.add_argument("--only", metavar="REGEX",
                    help="run only the programs whose `workload: implementation` matches REGEX "
                         "(Python `re.search`), e.g. --only '^metadata'; the targets of the "
                         "others say `not measured`")
    ap.add_argument("inputs", nargs="*", help="logs to run on instead of the two big ones")
    args = ap.parse_args()

    runs = args.runs or (1 if args.smoke else 5)
    peers = not args.no_peers
    # The smoke run times nothing: programs of the test profile (which shares the
    # dependencies `cargo test` built) are enough, and quick to build.
    profile = "test" if args.smoke else "release"
    if args.no_build:
        bins = built_programs(peers, profile)
    else:
        bins = build(peers, profile)
    base = build_baseline(args.baseline, profile) if args.baseline else None
    extra, extra_skipped = ({}, ["peers from source: skipped (--no-peers)"])
    if peers:
        extra, extra_skipped = source_peers.build(
            ROOT, BENCH, os.path.join(target_dir(os.path.join(BENCH, "target")), "peers"), args.smoke)

    if args.inputs:
        inputs = [(os.path.basename(p), os.path.abspath(p)) for p in args.inputs]
    elif args.smoke:
        inputs = smoke_inputs()
    else:
        inputs = big_inputs()

    if args.out:
        out_path = os.path.abspath(args.out)
    elif args.smoke:
        out_path = os.path.join(tempfile.mkdtemp(prefix="ulog-bench-"), "BENCHMARKS.md")
    else:
        out_path = os.path.join(ROOT, "BENCHMARKS.md")

    pyulog_ok = have_pyulog()
    ulog2csv = ulog2csv_cmd()
    parquet = cli_has(bins["ulog"], "parquet")
    taskset = shutil.which("taskset") if (os.cpu_count() or 1) > 1 else None
    write_n = SMOKE_WRITE_MESSAGES if args.smoke else WRITE_MESSAGES
    scratch = tempfile.mkdtemp(prefix="ulog-bench-scratch-", dir=data_dir() if os.path.isdir(data_dir()) else None)
    # Removed however the run ends (a program failing, Ctrl-C), except when killed.
    atexit.register(shutil.rmtree, scratch, True)

    doc = [
        "# Benchmarks",
        "",
        "Written by `bench/run` (see [bench/README.md](bench/README.md)); every row is a whole "
        "process, run on the same input in the same session. *median s*: median wall time of "
        f"the runs (default {runs}; a program slower than {SLOW_SECONDS:.0f} s on its first run runs "
        f"at most {SLOW_RUNS} times), run in rounds: every program of an input once, in turn, then "
        "again, so that a slow spell of the machine falls on all of them; *spread*: (slowest − fastest run) / median, "
        "the run-to-run spread a difference must exceed to mean anything; *MB/s*: input bytes (10⁶) per second; *M msg/s*: messages of "
        "the file per second (for the typed workloads: the messages decoded); *CPU s*: median "
        "user + system time of the process (less sensitive than wall time to other load on "
        "the machine); *peak RSS*: "
        f"`ru_maxrss` of the process ({'reported by GNU time' if GNU_TIME else 'from wait4, which on Linux includes the Python parent at fork: about 30 MiB too high for small programs'}); *× ours*: the row's time over ours for the "
        "same workload (for the floor: floor / our framing). Before an input's runs, the file is dropped "
        "from the page cache and read back whole in 1 MiB reads, so that every program finds it "
        "cached in the same state (how the kernel holds a cached file changes the cost of "
        "mapping it).",
        "",
    ]
    if args.smoke:
        doc += ["**Smoke run** (one repetition on a small log): the figures mean nothing.", ""]
    doc += ["## Machine", "", "| | |", "|---|---|"]
    doc += [f"| {k} | {v} |" for k, v in machine(args.note)]
    doc.append("")
    if extra or extra_skipped:
        doc += ["Peers built from source (`bench/source_peers.py`, the peers folder): "
                + (", ".join(sorted(extra)) if extra else "none") + "."]
        doc += [f"- {why}" for why in extra_skipped]
        doc.append("")

    all_targets = []
    failures = 0
    for label, path in inputs:
        size = os.path.getsize(path)
        log(f"== input {label}: {size / 1e6:.1f} MB")
        # The same page-cache state for every input and run: the file is dropped from
        # the cache and read back whole in large reads (as a copy of the file leaves
        # it). How the cache holds a file changes the cost of mapping it (in large
        # folios, the floor's header walk is about 4 times faster than in small
        # pages), so programs that map the file are only comparable in one state.
        settle_page_cache(path)
        # Count the messages (our framing).
        msgs = int(run_once(Program("", "", [bins["ours"], "framing", path]), scratch)[2]["messages"])
        progs = programs(bins, path, peers, pyulog_ok, ulog2csv, parquet, taskset, extra)
        if args.only:
            progs = [p for p in progs if re.search(args.only, f"{p.workload}: {p.impl}")]
        if base:
            progs = with_baseline(progs, bins, base)
        measured = measure(progs, runs, scratch)
        failures += sum(1 for r in measured if r is None)
        results = list(zip(progs, measured))
        doc += [f"## {label}", "", f"{size / 1e6:,.1f} MB, {msgs:,} messages.", ""]
        doc += table(results, size, msgs)
        if not parquet:
            doc += ["", "Parquet export: skipped (this build's `ulog` has no `parquet` subcommand)."]
        if not pyulog_ok:
            doc += ["", "pyulog: not installed (`pip install pyulog==1.3.0`); its rows are missing."]
        doc.append("")
        all_targets.append((label, targets(results, size)))

    # Typed writing: input-independent.
    out_file = os.path.join(scratch, "written.ulg")
    wp = Program("typed writing", "ours (LogWriter)", [bins["ours"], "write", out_file, str(write_n)],
                 msgs_from_output=True, note=f"{write_n:,} sensor_combined rows to a file")
    if not args.only or re.search(args.only, f"{wp.workload}: {wp.impl}"):
        log("== typed writing")
        try:
            r = measure([wp], runs, scratch)[0]
        finally:
            if os.path.exists(out_file):
                os.remove(out_file)
        if r is None:
            failures += 1
            doc += ["## Typed writing", "", "failed", ""]
        else:
            written = int(r["kv"].get("bytes", 0))
            doc += [
                "## Typed writing",
                "",
                "| workload | implementation | runs | median s | CPU s | MB/s written | M msg/s | peak RSS MiB | how |",
                "|---|---|---:|---:|---:|---:|---:|---:|---|",
                f"| typed writing | ours (LogWriter) | {r['runs']} | {fmt_s(r['median'])} | {fmt_s(r['cpu'])} | "
                f"{written / r['median'] / 1e6:,.0f} | {write_n / r['median'] / 1e6:.1f} | "
                f"{r['rss'] / 2**20:.1f} | {wp.note} ({written / 1e6:.0f} MB) |",
                "",
            ]

    doc += ["## Targets", "",
            "The issue's targets (medians; ratios from this run). *met* / *missed*; "
            "*–* where a program of the ratio was not run. What the profiles of the "
            "targets missed on a 2-core machine show: [bench/README.md]"
            "(bench/README.md#the-targets-missed-on-a-2-core-machine).", ""]
    for label, ts in all_targets:
        doc += [f"### {label}", "", "| target | measured | |", "|---|---:|---|"]
        for name, value, ok in ts:
            mark = "–" if ok is None else ("met" if ok else "**missed**")
            doc.append(f"| {name} | {value} | {mark} |")
        doc.append("")

    # Figures this harness does not measure (criterion benchmarks run by hand) stay.
    doc += kept_by_hand(out_path)
    with open(out_path, "w") as f:
        f.write("\n".join(doc))
    log(f"== wrote {out_path}")
    if failures:
        log(f"run: {failures} program(s) failed")
        sys.exit(1)


if __name__ == "__main__":
    main()
