"""Fast ULog reading for Python, backed by the Rust library ulog-core.

``ulog_rs.ULog`` is a drop-in for ``pyulog.ULog``: the same constructor, attributes
and methods, with the same values (numpy arrays of the same dtypes, bit for bit), read
many times faster. Porting a pyulog script is one line::

    from ulog_rs import ULog          # was: from pyulog import ULog

    log = ULog("flight.ulg", message_name_filter_list=["vehicle_attitude"])
    att = log.get_dataset("vehicle_attitude")
    print(att.data["timestamp"][:3], att.data["q[0]"][:3])

Where it differs from pyulog (documented in ``ulog-py/README.md``): a damaged log
keeps more of its rows (the reader resynchronises where pyulog skips), and
``file_corruption`` is backed by ``findings``, which say what is damaged and where.
"""

from ._core import InternalError, ULogError
from ._core import __version__
from .analysis import analyze
from .convert import Converted, convert
from .ulog import Aligned, Event, Finding, TopicNotFound, ULog, UtcClock

__all__ = [
    "ULog", "ULogError", "TopicNotFound", "InternalError", "Finding", "Event", "UtcClock",
    "convert", "Converted", "Aligned", "analyze", "__version__",
]
