#!/usr/bin/env python3
"""Reading a log from S3 against reading it from a file: `ulog info`, `ulog messages`,
`ulog cut` and `ulog parquet` of one log, local and `s3://`, against moto's S3 server
on 127.0.0.1 (started here), with boto3's one GET of the whole object beside them.

Usage (from the repository root, after `cargo build --release -p ulog-cli`):

    python3 bench/s3_read.py LOG [--runs 3]

Needs `moto[server]` and `boto3`. The server is Python, on the same machine: the
figures say what this library adds to what the server costs, not what S3 costs.
Prints a Markdown table (bench/README.md keeps the last one).
"""
import argparse
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def timed(cmd, env, runs):
    times = []
    for _ in range(runs):
        t = time.monotonic()
        subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        times.append(time.monotonic() - t)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("log")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--ulog", default=os.path.join(
        os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target")), "release", "ulog"))
    args = ap.parse_args()
    import boto3

    port = free_port()
    server = subprocess.Popen([sys.executable, "-m", "moto.server", "-p", str(port)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    work = tempfile.mkdtemp(prefix="ulog-s3-read-")
    try:
        env = dict(os.environ, AWS_ENDPOINT_URL=f"http://127.0.0.1:{port}",
                   AWS_ACCESS_KEY_ID="bench", AWS_SECRET_ACCESS_KEY="bench",
                   AWS_REGION="us-east-1")
        os.environ.update(env)
        client = boto3.client("s3")
        for _ in range(50):
            try:
                client.create_bucket(Bucket="bench")
                break
            except Exception:
                time.sleep(0.2)
        client.upload_file(args.log, "bench", "log.ulg")
        url = "s3://bench/log.ulg"

        def one_get():
            t = time.monotonic()
            client.get_object(Bucket="bench", Key="log.ulg")["Body"].read()
            return time.monotonic() - t

        get = statistics.median(one_get() for _ in range(args.runs))
        out = os.path.join(work, "out")
        rows = []
        for name, cmd in [
            ("info", [args.ulog, "info", "{}"]),
            ("messages", [args.ulog, "messages", "{}"]),
            ("cut --end 5", [args.ulog, "cut", "{}", "--end", "5", "-o", os.path.join(work, "cut.ulg")]),
            ("parquet", ["sh", "-c", f"rm -rf {out} && {args.ulog} parquet {{}} -o {out}"]),
        ]:
            local = [c.replace("{}", args.log) for c in cmd]
            remote = [c.replace("{}", url) for c in cmd]
            a, b = timed(local, env, args.runs), timed(remote, env, args.runs)
            rows.append((name, a, b))
        size = os.path.getsize(args.log)
        print(f"{os.path.basename(args.log)} ({size / 1e6:.0f} MB), moto's server on 127.0.0.1, "
              f"median of {args.runs} runs; boto3's one GET of the object: {get:.2f} s.\n")
        print("| `ulog` | local file s | `s3://` s | ratio |")
        print("|---|---|---|---|")
        for name, a, b in rows:
            print(f"| {name} | {a:.2f} | {b:.2f} | {b / a:.1f}× |")
    finally:
        server.terminate()
        server.wait()
        shutil.rmtree(work, ignore_errors=True)


main()
