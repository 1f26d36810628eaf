"""pyulog's own scripts (ulog_info, ulog_params, ulog_messages, ulog2csv) run on
ulog_rs.ULog print and write exactly what they do on pyulog.ULog: porting a script
is changing its import."""

import contextlib
import io
import re
import sys

import pytest

pyulog = pytest.importorskip("pyulog")
from pyulog import info, messages, params, ulog2csv

import ulog_rs

from conftest import corpus_logs

LOGS = corpus_logs()
PYULOG_WARNINGS = ("Warning: no subscription found", "File corruption detected")
SCRIPTS = {
    "ulog_info": (info, ["-v"]),
    "ulog_params": (params, ["-t"]),
    "ulog_params_defaults": (params, ["-d", "system"]),
    "ulog_messages": (messages, []),
}


def run(module, argv, reader, monkeypatch):
    """stdout of `module.main()` with `argv`, reading with `reader`."""
    monkeypatch.setattr(module, "ULog", reader)
    monkeypatch.setattr(sys, "argv", ["script"] + argv)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        try:
            module.main()
        except Exception as e:  # the same refusal, e.g. no default parameters
            return "raised {}: {}".format(type(e).__name__, e)
    return out.getvalue()


@pytest.mark.parametrize("script", sorted(SCRIPTS))
@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_a_script_prints_the_same(script, path, monkeypatch):
    module, flags = SCRIPTS[script]
    theirs = run(module, [str(path)] + flags, pyulog.ULog, monkeypatch)
    ours = run(module, [str(path)] + flags, ulog_rs.ULog, monkeypatch)
    # pyulog's reader prints its own warnings about damage while it reads; ulog_rs
    # prints nothing (`findings` says what is damaged, and where).
    theirs = "".join(l for l in theirs.splitlines(True) if not l.startswith(PYULOG_WARNINGS))
    if pyulog.ULog(str(path)).file_corruption and script == "ulog_info":
        # The rows recovered from damage change the table's counts and the
        # duration; every other line is the same.
        table = re.compile(r"^ \S+ \(\d+, \d+\) +\d+ +\d+$|^Logging start time")
        ours_kept = [l for l in ours.splitlines() if not table.match(l)]
        theirs_kept = [l for l in theirs.splitlines() if not table.match(l)]
        assert ours_kept == theirs_kept
        assert len(ours.splitlines()) >= len(theirs.splitlines())
        return
    assert ours == theirs


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_ulog2csv_writes_the_same_files(path, tmp_path, monkeypatch):
    outs = {}
    for who, reader in (("pyulog", pyulog.ULog), ("ulog_rs", ulog_rs.ULog)):
        out = tmp_path / who
        out.mkdir()
        monkeypatch.setattr(ulog2csv, "ULog", reader)
        ulog2csv.convert_ulog2csv(str(path), None, str(out), ",", None, None)
        outs[who] = {p.name: p.read_bytes() for p in sorted(out.iterdir())}
    if not pyulog.ULog(str(path)).file_corruption:
        assert list(outs["ulog_rs"]) == list(outs["pyulog"])
        assert outs["ulog_rs"] == outs["pyulog"]
        return
    # A damaged log: every file pyulog writes is ours too, its header the same and
    # its lines, in order, among ours (we recover rows pyulog skips).
    assert set(outs["pyulog"]) <= set(outs["ulog_rs"])
    for name, theirs in outs["pyulog"].items():
        t, o = theirs.splitlines(), outs["ulog_rs"][name].splitlines()
        assert o[0] == t[0], name
        it = iter(o[1:])
        assert all(any(a == b for b in it) for a in t[1:]), name
