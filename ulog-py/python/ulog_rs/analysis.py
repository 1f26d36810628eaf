"""``ulog_rs.analyze``: what happened in a flight, by the code ``ulog analyze`` runs."""

import json
import os

from . import _core


def analyze(source, spectra=True, step_response=True):
    """The flight analysis of a log (a path, or the log's bytes): PX4 Flight Review
    v2's diagnostics (``battery_brownout``, ``ekf_failure``, ``gps_interference``,
    ``motor_failure``, ``rc_loss``), flight statistics, battery, GPS quality,
    vibration with the spectra's dominant frequencies, and the rate controllers' step
    responses. The same code and the same values as ``ulog analyze --json``, as a dict::

        flight = ulog_rs.analyze("flight.ulg")
        for d in flight["diagnostics"]:
            print(d["severity"], d["id"], d["timestamp_us"], d["summary"])
        print(flight["vibration"]["status"], flight["stats"]["max_tilt_deg"])

    :param spectra: compute the IMU's and controllers' spectra (dominant frequencies)
    :param step_response: compute the rate controllers' step responses
    :raises FileNotFoundError: no such file
    :raises ULogError: not a log this library can read
    """
    if not isinstance(source, (bytes, bytearray)):
        source = os.fspath(source)
    elif isinstance(source, bytearray):
        source = bytes(source)
    return json.loads(_core.analyze_json(source, spectra, step_response))
