"""pyulog's own test suite, run against ulog_rs: every case that tests pyulog's
public API, with `pyulog.ULog` replaced by `ulog_rs.ULog` everywhere pyulog's
modules look it up.

The suite is pyulog's (BSD-3-Clause), not part of this repository: it is taken from
$ULOG_PYULOG_TESTS or the full corpus's peers (../shared/peers/pyulog-tests beside
the workspace). Left out, as they test pyulog's internals: test_db.py and
test_migration.py (pyulog's SQLite database), test_px4.py (its database-backed
PX4ULog), the cases that name sample_appended.ulg (not in the corpus), and
test_messages_cli, whose expected output is of a later pyulog than 1.3.0 (it fails
on pyulog 1.3.0 itself: its `ulog_messages` prints no milliseconds)."""

import os
import pathlib
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT, corpus_logs, full_corpus, missing

PATCH = '''
import sys
import pyulog, pyulog.core
import ulog_rs

pyulog.ULog = ulog_rs.ULog
pyulog.core.ULog = ulog_rs.ULog
for name, module in list(sys.modules.items()):
    if name.startswith("pyulog.") and hasattr(module, "ULog"):
        module.ULog = ulog_rs.ULog
'''

SUITES = ["test_ulog.py", "test_cli.py", "test_extract_message.py", "test_px4_events.py"]


def suite_dir():
    """$ULOG_PYULOG_TESTS, or pyulog-tests/test in the peers beside the full corpus
    (../shared/peers, or beside $ULOG_CORPUS)."""
    env = os.environ.get("ULOG_PYULOG_TESTS")
    candidates = [pathlib.Path(env)] if env else []
    corpus = full_corpus()
    if corpus is not None:
        candidates.append(corpus.parent / "peers" / "pyulog-tests" / "test")
    candidates.append(ROOT.parent / "shared" / "peers" / "pyulog-tests" / "test")
    return next((p for p in candidates if p.is_dir()), None)


def test_pyulogs_own_suite_passes_on_ulog_rs(tmp_path):
    src = suite_dir()
    if src is None:
        missing("pyulog's test suite is not beside the workspace ($ULOG_PYULOG_TESTS)")
    work = tmp_path / "pyulog-tests"
    shutil.copytree(src, work)
    logs = {p.name: p for p in corpus_logs()}
    for name in {p.stem for p in work.glob("*.txt")} | {
        "sample", "sample_appended_multiple", "sample_log_small",
        "sample_logging_tagged_and_default_params", "sample_px4_events",
    }:
        for stem in (name, name.rsplit("_", 1)[0]):
            if stem + ".ulg" in logs:
                shutil.copy(logs[stem + ".ulg"], work / (stem + ".ulg"))
    (work / "conftest.py").write_text(PATCH)
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *SUITES,
         "-k", "not (sample_appended and not sample_appended_multiple) and not test_messages_cli"],
        cwd=work, capture_output=True, text=True,
    )
    print(run.stdout[-4000:], run.stderr[-2000:])
    assert run.returncode == 0, run.stdout[-4000:]
