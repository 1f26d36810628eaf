#!/usr/bin/env bash
# Diffs `ulog info|messages|params|csv` with pyulog's scripts (ulog_info,
# ulog_messages, ulog_params, ulog2csv) on every log of the corpus.
#
#   ulog-cli/tests/compare_with_pyulog.sh [CORPUS_DIR]
#
# CORPUS_DIR defaults to $ULOG_CORPUS, then ../shared/corpus beside the workspace.
# Needs pyulog (pip install pyulog==1.3.0); skips when it is not installed.
# Exit status: 0 when every output matches apart from the deliberate differences
# below, 1 otherwise.
#
# Deliberate differences, not counted as failures:
# - `ulog info` prints what the reader found after the ulog_info part (from the line
#   `File version:` on); it is cut before diffing.
# - pyulog prints parse warnings on stdout (`Warning: no subscription found ...`);
#   they are dropped from its output.
# - In logs with corruption mid-stream, this reader recovers data messages that pyulog
#   skips while it looks for the next sync message: those files may have extra rows
#   (and `ulog info` higher counts). They are checked to hold every pyulog row, in
#   order, and nothing else differs.
# - `ulog messages` is compared with ulog_messages itself (`--no-tagged`, since
#   ulog_messages prints no tagged strings; `--profile dev`, the profile pyulog decodes
#   events with) on logs that embed event metadata. On PX4 logs with events but no
#   metadata, ulog_messages downloads PX4's metadata (or, offline, drops the events)
#   where `ulog messages` prints them by id: those are compared with pyulog's logged
#   strings in ulog_messages' layout, and a difference is reported as expected.
set -u

here="$(cd "$(dirname "$0")" && pwd)"
workspace="$(cd "$here/../.." && pwd)"
corpus="${1:-${ULOG_CORPUS:-$workspace/../shared/corpus}}"

if ! command -v ulog_info >/dev/null || ! python3 -c 'import pyulog' 2>/dev/null; then
    echo "SKIPPED: pyulog is not installed (pip install pyulog==1.3.0)"
    exit 0
fi
if [ ! -d "$corpus/files" ]; then
    echo "SKIPPED: no corpus at $corpus"
    exit 0
fi

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$workspace/target}"
cargo build --quiet --release -p ulog-cli --manifest-path "$workspace/Cargo.toml" || exit 1
ulog="$CARGO_TARGET_DIR/release/ulog"

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Logs where recovered rows are expected (damage in the middle of the data).
recovers_rows() {
    "$ulog" info --json "$1" | python3 -c '
import json, sys
d = json.load(sys.stdin)
sys.exit(0 if d["corrupted"] else 1)'
}

failures=0
checks=0
no_py_warnings() { grep -v '^Warning: no subscription found'; }
report() { # name status detail
    checks=$((checks + 1))
    case "$2" in
        ok) ;;
        known) echo "  $1: differs as expected ($3)" ;;
        *) echo "  $1: DIFFERS"; echo "$3" | head -20 | sed 's/^/    /'; failures=$((failures + 1)) ;;
    esac
}

# pyulog's logged strings in ulog_messages' layout, without events.
py_messages() {
    python3 - "$1" <<'EOF'
import sys
from pyulog import ULog
u = ULog(sys.argv[1], ['event'], True)
msgs = [(m.timestamp, m.log_level_str(), m.message) for m in u.logged_messages]
if u.msg_info_dict.get('sys_name', '') == 'PX4':
    msgs.sort(key=lambda m: m[0])
for t, level, text in msgs:
    total_ms = int(t / 1000)
    m1, s1 = divmod(total_ms // 1000, 60)
    h1, m1 = divmod(m1, 60)
    print("{:d}:{:02d}:{:02d}.{:03d} {:}: {:}".format(h1, m1, s1, total_ms % 1000, level, text))
EOF
}

# Compares two CSV folders; with `rows`, extra rows on our side are allowed if every
# pyulog row is there, in order.
compare_csv() {
    python3 - "$1" "$2" "$3" <<'EOF'
import os, sys
ours, theirs, mode = sys.argv[1], sys.argv[2], sys.argv[3]
problems, extra = [], 0
a_files, b_files = set(os.listdir(ours)), set(os.listdir(theirs))
for f in sorted(a_files ^ b_files):
    problems.append(f"only in {'ours' if f in a_files else 'pyulog'}: {f}")
for f in sorted(a_files & b_files):
    a = open(os.path.join(ours, f), encoding='utf-8').read().split('\n')
    b = open(os.path.join(theirs, f), encoding='utf-8').read().split('\n')
    if a == b:
        continue
    if mode == 'rows':
        i = 0
        for line in a:
            if i < len(b) and line == b[i]:
                i += 1
            else:
                extra += 1
        if i == len(b):
            continue
    problems.append(f"{f} differs")
for p in problems[:20]:
    print(p)
if extra:
    print(f"EXTRA {extra}")
sys.exit(1 if problems else 0)
EOF
}

for f in "$corpus"/files/*.ulg; do
    stem="$(basename "$f" .ulg)"
    echo "$stem"
    known=no
    recovers_rows "$f" && known=yes

    for v in "" "-v"; do
        diff_out="$(diff <(ulog_info $v "$f" 2>&1 | no_py_warnings) \
                         <("$ulog" info $v "$f" 2>&1 | awk '/^File version: /{exit} {print}' | sed '$d'))"
        if [ -z "$diff_out" ]; then report "info $v" ok
        elif [ $known = yes ] && ! echo "$diff_out" | grep '^[<>]' | grep -qv '^[<>]  [^ ].*([0-9]*, [0-9]*) '; then
            report "info $v" known "topic row counts (recovered rows)"
        else report "info $v" bad "$diff_out"; fi
    done

    if grep -q metadata_events "$f"; then
        diff_out="$(diff <(python3 -c 'import sys
from pyulog.messages import main
sys.argv = ["ulog_messages", sys.argv[1]]
main()' "$f" 2>&1 | no_py_warnings) <("$ulog" messages --no-tagged --profile dev "$f" 2>/dev/null))"
        [ -z "$diff_out" ] && report messages ok || report messages bad "$diff_out"
    else
        diff_out="$(diff <(py_messages "$f" 2>&1 | no_py_warnings) <("$ulog" messages --no-tagged "$f" 2>/dev/null))"
        if [ -z "$diff_out" ]; then report messages ok
        elif python3 -c 'import sys; from pyulog import ULog; u = ULog(sys.argv[1]); sys.exit(0 if any(d.name == "event" for d in u.data_list) else 1)' "$f" 2>/dev/null; then
            report messages known "events without metadata, printed by id"
        else report messages bad "$diff_out"; fi
    fi

    for opts in "" "-t" "-i" "-i -t" "-f octave" "-i -f octave" "-f qgc" "-l ;" \
                "-d system" "-d current_setup" "-d system -f octave" "-d current_setup -t"; do
        py_out="$(ulog_params $opts "$f" 2>/dev/null | no_py_warnings; exit "${PIPESTATUS[0]}")"; py_rc=$?
        our_out="$("$ulog" params $opts "$f" 2>/dev/null)"; our_rc=$?
        if [ $py_rc -ne 0 ] && [ $our_rc -ne 0 ]; then report "params $opts" ok
        elif [ "$py_out" = "$our_out" ] && [ $py_rc -eq $our_rc ]; then report "params $opts" ok
        else report "params $opts" bad "$(diff <(echo "$py_out") <(echo "$our_out"); echo "exit: pyulog $py_rc, ulog $our_rc")"; fi
    done

    mkdir -p "$tmp/$stem/py" "$tmp/$stem/ours"
    ulog2csv -o "$tmp/$stem/py" "$f" >/dev/null 2>&1
    "$ulog" csv -o "$tmp/$stem/ours" "$f" >/dev/null
    mode=exact; [ $known = yes ] && mode=rows
    if out="$(compare_csv "$tmp/$stem/ours" "$tmp/$stem/py" $mode)"; then
        if echo "$out" | grep -q '^EXTRA'; then
            report csv known "$(echo "$out" | sed 's/EXTRA/extra rows recovered:/')"
        else report csv ok; fi
    else report csv bad "$out"; fi
    rm -rf "${tmp:?}/$stem"
done

echo "$checks checks, $failures failures"
[ $failures -eq 0 ]
