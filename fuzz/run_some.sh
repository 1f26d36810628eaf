#!/usr/bin/env bash
# Runs the named fuzz targets one after another for SECONDS each:
#   fuzz/run_some.sh SECONDS target...
# Appends each run's final status line to fuzz/logs/summary.txt.
set -uo pipefail
cd "$(dirname "$0")"
seconds=$1
shift
mkdir -p logs
for t in "$@"; do
    mkdir -p "corpus/$t"
    start=$(date +%s)
    RUSTC_BOOTSTRAP=1 cargo fuzz run -O "$t" "corpus/$t" -- \
        -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=131072 -timeout=10 \
        > "logs/$t.$start.log" 2>&1
    status=$?
    echo "$t: exit $status, $(( $(date +%s) - start )) s, $(grep -E '^#[0-9]+' "logs/$t.$start.log" | tail -1)" >> logs/summary.txt
done
