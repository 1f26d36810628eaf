"""Beyond pyulog: PX4 events decoded (against pyulog's PX4Events), the UTC clock
(against the GPS rows pyulog reads), units, findings."""

import re

import numpy as np
import pytest

pyulog = pytest.importorskip("pyulog")
from pyulog.px4_events import PX4Events

import ulog_rs

from conftest import corpus_logs, missing

LOGS = corpus_logs()


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_events_are_pyulogs(path):
    theirs = pyulog.ULog(str(path))
    px4 = PX4Events()
    px4.set_default_json_definitions_cb(lambda already: None)  # the log's own only
    want = px4.get_logged_events(theirs)
    ours = ulog_rs.ULog(str(path)).events
    levels = ("EMERGENCY", "ALERT", "CRITICAL", "ERROR", "WARNING", "NOTICE", "INFO", "DEBUG")
    # An event of a log without metadata: we add its raw arguments to pyulog's text.
    unknown = re.compile(r"^(\[Unknown event with ID \d+), arguments: [0-9a-f ]*\]$")
    got = [(int(e.timestamp), levels[e.level], unknown.sub(r"\1]", e.text))
           for e in ours if e.is_message]
    assert got == [(int(t), level, text) for t, level, text in want]


def test_some_corpus_log_has_events():
    # The repository's own logs have none; the full corpus has PX4 event logs.
    if not any(ulog_rs.ULog(str(p)).events for p in LOGS):
        missing("no log with PX4 events here: the full corpus has them")


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_events_decoded_when_asked_survive_copies_and_pickles(path):
    # The events are decoded at first use, from a Rust object a copy or a pickle
    # cannot take: those decode them first. Each copy has pyulog's events.
    import copy
    import pickle

    theirs = PX4Events()
    theirs.set_default_json_definitions_cb(lambda already: None)
    want = [(int(t), text) for t, _, text in theirs.get_logged_events(pyulog.ULog(str(path)))]
    unknown = re.compile(r"^(\[Unknown event with ID \d+), arguments: [0-9a-f ]*\]$")
    for make in (copy.deepcopy, copy.copy, lambda u: pickle.loads(pickle.dumps(u))):
        ours = make(ulog_rs.ULog(str(path)))
        got = [(int(e.timestamp), unknown.sub(r"\1]", e.text)) for e in ours.events if e.is_message]
        assert got == want


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_the_utc_clock_is_the_gps_rows_median(path):
    ours = ulog_rs.ULog(str(path))
    theirs = pyulog.ULog(str(path))
    if ours.utc is None or not ours.utc.source.startswith("gps"):
        return
    topic = ours.utc.source.split()[1]
    gps = theirs.get_dataset(topic)
    utc = gps.data["time_utc_usec"].astype(np.int64)
    t = gps.data["timestamp"].astype(np.int64)
    ok = utc > 1_000_000_000_000_000  # a time after 2001
    median = np.median(utc[ok] - t[ok])
    assert abs(ours.utc.boot_us - median) <= 1_000_000, (ours.utc, median)
    stamp = ours.to_utc(t[ok][:1])[0]
    assert abs((stamp - utc[ok][:1].astype("datetime64[us]")[0]) / np.timedelta64(1, "s")) < 1


def test_some_corpus_log_has_a_utc_clock():
    if not any(ulog_rs.ULog(str(p)).utc is not None for p in LOGS):
        missing("no log with a UTC time here: the full corpus has them")


def test_units_follow_px4_names():
    for p in LOGS:
        log = ulog_rs.ULog(str(p))
        for d in log.data_list:
            units = d.units
            assert set(units) <= {f.field_name for f in d.field_data}
            for name, unit in units.items():
                if name.endswith("_m_s2") or "_m_s2[" in name:
                    assert unit == "m/s²", (d.name, name)


def test_findings_name_the_damage_of_a_damaged_log():
    damaged = [p for p in LOGS if pyulog.ULog(str(p)).file_corruption]
    if not damaged:
        missing("no damaged log here: the full corpus has them")
    for p in damaged:
        log = ulog_rs.ULog(str(p))
        assert log.file_corruption
        assert any(f.is_damage and f.length > 0 for f in log.findings), p.name
