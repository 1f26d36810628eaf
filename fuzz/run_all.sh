#!/usr/bin/env bash
# Runs every fuzz target for SECONDS each (default 60), one after another, and prints
# each run's final line (executions, coverage) to fuzz/logs/. A crash stops that target
# and leaves its input in fuzz/artifacts/<target>/.
set -uo pipefail
cd "$(dirname "$0")"
seconds=${1:-60}
mkdir -p logs
for t in reader chunked columns grammar typed roundtrip messages; do
    mkdir -p "corpus/$t"
    RUSTC_BOOTSTRAP=1 cargo fuzz run -O "$t" "corpus/$t" -- \
        -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=131072 -timeout=10 \
        > "logs/$t.log" 2>&1
    echo "$t: exit $? $(grep -E '^#[0-9]+' "logs/$t.log" | tail -1)"
done
