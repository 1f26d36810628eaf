"""``ulog_rs.analyze``: the flight analysis, its figures checked against pyulog's
rows computed here with numpy (not by this library)."""

import math

import numpy as np
import pytest

import ulog_rs

from conftest import corpus_logs

pyulog = pytest.importorskip("pyulog")

LOGS = corpus_logs()


def datasets(log, name):
    return [d for d in log.data_list if d.name == name]


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_figures_are_pyulogs_rows_computed_with_numpy(path):
    flight = ulog_rs.analyze(path)
    assert ulog_rs.analyze(path.read_bytes()) == flight, "bytes and path agree"
    try:
        log = pyulog.ULog(str(path))
    except Exception as e:  # pyulog cannot read some damaged logs
        pytest.skip("pyulog cannot read it: {}".format(e))
    # Vibration: the mean and peak of accel_vibration_metric over every IMU's rows.
    vibe = [d.data["accel_vibration_metric"] for d in datasets(log, "vehicle_imu_status")
            if "accel_vibration_metric" in d.data]
    if vibe:
        v = np.concatenate(vibe).astype(np.float64)
        v = v[np.isfinite(v) & (v >= 0)]
        assert flight["vibration"]["accel_vibe_mean"] == pytest.approx(float(v.mean()), rel=1e-9)
        assert flight["vibration"]["accel_vibe_max"] == pytest.approx(float(v.max()), rel=1e-6)
    else:
        assert flight["vibration"]["status"] == "unknown"
    # Battery: instance 0's lowest voltage above 0.
    bat = [d for d in datasets(log, "battery_status") if d.multi_id == 0]
    if bat and "voltage_v" in bat[0].data:
        v = bat[0].data["voltage_v"]
        v = v[np.isfinite(v) & (v > 0)]
        expected = float(v.min()) if len(v) else None
        assert flight["battery"]["min_voltage_v"] == pytest.approx(expected)
    # Tilt: the largest angle between the body's z axis and the vertical, from the
    # quaternion of instance 0.
    att = [d for d in datasets(log, "vehicle_attitude") if d.multi_id == 0]
    if att and "q[0]" in att[0].data:
        w, x, y, z = (att[0].data["q[%d]" % i].astype(np.float64) for i in range(4))
        roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
        pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1, 1))
        tilt = np.degrees(np.nanmax(np.arccos(np.clip(np.cos(roll) * np.cos(pitch), -1, 1))))
        assert flight["stats"]["max_tilt_deg"] == pytest.approx(float(tilt), abs=1e-3)
    # Distance: the 3D path of instance 0 of the local position, every finite row.
    pos = [d for d in datasets(log, "vehicle_local_position") if d.multi_id == 0]
    if pos:
        p = np.stack([pos[0].data[k] for k in ("x", "y", "z")], axis=1).astype(np.float64)
        p = p[np.isfinite(p).all(axis=1)]
        steps = np.diff(p.astype(np.float32), axis=0).astype(np.float64)
        total = float(np.sqrt((steps ** 2).sum(axis=1)).sum()) if len(p) > 1 else 0.0
        assert flight["stats"]["total_distance_m"] == pytest.approx(total, rel=1e-5, abs=1e-6)
    # Every diagnostic has Flight Review v2's keys.
    for d in flight["diagnostics"]:
        assert set(d) == {"id", "severity", "timestamp_us", "end_timestamp_us", "summary",
                          "evidence"}
    for value in flight["stats"].values():
        assert value is None or math.isfinite(value)


def test_options_leave_out_the_signals():
    path = LOGS[0]
    flight = ulog_rs.analyze(path, spectra=False, step_response=False)
    assert flight["vibration"]["spectra"] == []
    assert flight["step_response"] == []


def test_a_missing_file_and_bytes_that_are_no_log_are_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        ulog_rs.analyze(tmp_path / "nope.ulg")
    with pytest.raises(ulog_rs.ULogError):
        ulog_rs.analyze(b"not a log at all")
