"""In-process load times of ulog_rs.ULog against pyulog.ULog on one log, measured in
the same run: the median of N calls each (after one warm-up call that brings the file
into the page cache), every topic and one topic, and their ratios.

    python ulog-py/bench/load.py LOG.ulg [--runs 5] [--topic vehicle_attitude]

The whole-process rows (interpreter start and imports included, peak RSS) are
bench/run's ("columnar load", ulog_rs and pyulog rows)."""

import argparse
import statistics
import time


def median_time(fn, runs):
    fn()
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log")
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--topic", default="vehicle_attitude")
    args = ap.parse_args()
    import pyulog
    import ulog_rs

    rows = []
    for what, kwargs, limit in (("every topic", {}, 0.05), (args.topic, {"message_name_filter_list": [args.topic]}, 0.02)):
        ours = median_time(lambda: ulog_rs.ULog(args.log, **kwargs), args.runs)
        theirs = median_time(lambda: pyulog.ULog(args.log, **kwargs), max(1, args.runs // 2))
        rows.append((what, ours, theirs, ours / theirs, limit))
    print("| load | ulog_rs s | pyulog 1.3 s | ratio | target |")
    print("| --- | --- | --- | --- | --- |")
    for what, ours, theirs, ratio, limit in rows:
        met = "met" if ratio <= limit else "**missed**"
        print(f"| {what} | {ours:.3f} | {theirs:.3f} | {ratio:.3f}× | ≤ {limit}× ({met}) |")


if __name__ == "__main__":
    main()
