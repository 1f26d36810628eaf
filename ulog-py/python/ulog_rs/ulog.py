"""``ULog``: pyulog's reader class, backed by ulog-core.

The compiled module reads the log and hands over byte strings and one packed row
array per topic; this module gives them pyulog's shape: info values decoded by the
type in their key, parameters by level and time, topics as ``Data`` objects whose
``data`` dict holds one numpy array per flattened field (views of the packed rows,
as pyulog's are).
"""

import collections
import os
import struct

import numpy as np

from . import _core
from ._core import ULogError
from ._types import _TYPES

_LEVELS = {
    ord("0"): "EMERGENCY",
    ord("1"): "ALERT",
    ord("2"): "CRITICAL",
    ord("3"): "ERROR",
    ord("4"): "WARNING",
    ord("5"): "NOTICE",
    ord("6"): "INFO",
    ord("7"): "DEBUG",
}

Finding = collections.namedtuple("Finding", ["what", "offset", "length", "is_damage"])
Finding.__doc__ = """What the reader found wrong in the log: a description, the byte
offset and length of the stretch, and whether it is damage (bytes that could not be
read as messages) rather than a note."""


UtcClock = collections.namedtuple("UtcClock", ["boot_us", "source"])
UtcClock.__doc__ = """The log's UTC clock: microseconds since the Unix epoch at boot
(timestamp 0), and its source (the GPS receiver's time, the median over its rows, or
information key ``boot_time_utc_us``)."""

Event = collections.namedtuple(
    "Event",
    ["timestamp", "id", "sequence", "level", "external_level", "name", "group", "text",
     "description", "is_message"],
)
Event.__doc__ = """A PX4 event decoded with the metadata the log embeds: ``level`` 0
(emergency) … 7 (debug); ``is_message``: shown as a message by PX4's tools (the
``default`` group below the protocol level)."""


class TopicNotFound(KeyError, IndexError):
    """No topic of that name and instance. A ``KeyError`` and, as pyulog's
    ``get_dataset`` raises ``IndexError``, an ``IndexError`` too."""

    def __str__(self):
        return str(self.args[0]) if self.args else ""


class _Decoder:
    """Decodes keys, values and texts as pyulog does, strictly or not."""

    def __init__(self, strict):
        self.errors = "strict" if strict else "ignore"
        self.corrupt = False
        # Key bytes → (type, name, how to read the value): a log repeats its keys
        # (the parts of a multi-information message, thousands in a PX4 log).
        self._keys = {}

    def text(self, raw):
        return str(raw, "utf-8", self.errors)

    def key_value(self, key, raw):
        """``(type, name, value)`` of an information or parameter message, or
        ``None`` for one pyulog counts as corruption (a key without a type)."""
        known = self._keys.get(key)
        if known is None:
            parts = self.text(key).split(" ")
            if len(parts) < 2:
                self.corrupt = True
                return None
            type_str, name = parts[0], parts[1]
            if type_str.startswith("char["):
                read = str
            elif type_str in _TYPES:
                read = struct.Struct("<" + _TYPES[type_str][0]).unpack
            else:
                read = None
            known = self._keys[key] = (type_str, name, read)
        type_str, name, read = known
        if read is None:
            return type_str, name, raw
        if read is str:
            return type_str, name, self.text(raw)
        try:
            (value,) = read(raw)
        except struct.error:
            self.corrupt = True
            return None
        return type_str, name, value


class MessageFormat:
    """A format: its ``name`` and ``fields``, a list of ``(type, array_size, name)``
    (``array_size`` 0 for a field that is not an array)."""

    def __init__(self, name, fields):
        self.name = name
        self.fields = [tuple(f) for f in fields]

    def __eq__(self, other):
        if not isinstance(other, MessageFormat):
            return NotImplemented
        return self.name == other.name and self.fields == other.fields

    def __repr__(self):
        return "MessageFormat({!r}, {!r})".format(self.name, self.fields)


class _Level:
    def log_level_str(self):
        """The level's name (``ERROR``, ``INFO`` …), ``UNKNOWN`` for another byte."""
        return _LEVELS.get(self.log_level, "UNKNOWN")


class MessageLogging(_Level):
    """A logged string: ``log_level`` (the byte as logged), ``timestamp``,
    ``message``."""

    def __init__(self, log_level, timestamp, message):
        self.log_level = log_level
        self.timestamp = timestamp
        self.message = message

    def __eq__(self, other):
        if not isinstance(other, MessageLogging):
            return NotImplemented
        return (self.log_level, self.timestamp, self.message) == (
            other.log_level,
            other.timestamp,
            other.message,
        )


class MessageLoggingTagged(_Level):
    """A tagged logged string: ``log_level``, ``tag``, ``timestamp``, ``message``."""

    def __init__(self, log_level, tag, timestamp, message):
        self.log_level = log_level
        self.tag = tag
        self.timestamp = timestamp
        self.message = message

    def __eq__(self, other):
        if not isinstance(other, MessageLoggingTagged):
            return NotImplemented
        return (self.log_level, self.tag, self.timestamp, self.message) == (
            other.log_level,
            other.tag,
            other.timestamp,
            other.message,
        )


class MessageDropout:
    """A dropout: ``duration`` in milliseconds at ``timestamp`` (the latest data
    timestamp before it)."""

    def __init__(self, duration, timestamp):
        self.duration = duration
        self.timestamp = timestamp

    def __eq__(self, other):
        if not isinstance(other, MessageDropout):
            return NotImplemented
        return (self.duration, self.timestamp) == (other.duration, other.timestamp)


class _FieldData:
    """A flattened field: ``field_name`` (``q[0]``, ``esc[3].esc_rpm``) and
    ``type_str`` (``float``, ``uint64_t`` …)."""

    def __init__(self, field_name, type_str):
        self.field_name = field_name
        self.type_str = type_str

    def __eq__(self, other):
        if not isinstance(other, _FieldData):
            return NotImplemented
        return (self.field_name, self.type_str) == (other.field_name, other.type_str)

    def __repr__(self):
        return "_FieldData({!r}, {!r})".format(self.field_name, self.type_str)


class Data:
    """One topic instance: ``name``, ``multi_id``, ``msg_id``, ``field_data`` (the
    flattened fields), ``timestamp_idx`` and ``data``, a dict of one numpy array per
    field (writable views of the packed rows, like pyulog's)."""

    def __init__(self, topic, source=None):
        # Where the log was read from (a path or its bytes), for `to_arrow`.
        self._source = source
        self.multi_id = topic["multi_id"]
        self.msg_id = topic["msg_id"]
        self.name = topic["name"]
        self.field_data = [_FieldData(n, t) for n, t in topic["fields"]]
        self.timestamp_idx = topic["timestamp_idx"]
        dtype = np.dtype([(n, "<" + np.dtype(_TYPES[t][2]).str[1:]) for n, t in topic["fields"]])
        rows = topic["rows"].view(dtype)
        self.data = {name: rows[name] for name in dtype.names}

    def __eq__(self, other):
        if not isinstance(other, Data):
            return NotImplemented
        if self.data.keys() != other.data.keys():
            return False
        for a, b in zip(self.data.values(), other.data.values()):
            if not np.array_equal(a, b, equal_nan=True):
                return False
        return (
            self.multi_id == other.multi_id
            and self.msg_id == other.msg_id
            and self.name == other.name
            and self.field_data == other.field_data
            and self.timestamp_idx == other.timestamp_idx
        )

    def to_arrow(self):
        """The topic as a ``pyarrow.RecordBatch`` with the log's types: nested types
        as structs, arrays as fixed-size lists, ``char[N]`` as strings, padding left
        out (the tables of ``ulog parquet``). Read from the log again, so in-place
        changes of ``data`` are not in it. Needs pyarrow (``pip install
        ulog-rs[arrow]``)."""
        import pyarrow

        (capsules,) = _core.arrow_batches(self._source, [(self.name, self.multi_id)])
        return pyarrow.record_batch(_ArrowBatch(*capsules))

    @property
    def units(self):
        """Field name → unit (``m/s``, ``rad``, ``V`` …) for the fields whose PX4 name
        says one (the rule of ``ulog_core::units``)."""
        units = {}
        for f in self.field_data:
            unit = _core.unit_of(self.name, f.field_name)
            if unit is not None:
                units[f.field_name] = unit
        return units

    def to_pandas(self):
        """The topic as a ``pandas.DataFrame``: one column per field of ``data``
        (pyulog's flattened names and dtypes), in ``field_data``'s order."""
        import pandas

        return pandas.DataFrame({f.field_name: self.data[f.field_name] for f in self.field_data})

    def to_polars(self):
        """The topic as a ``polars.DataFrame``: one column per field of ``data``
        (pyulog's flattened names and dtypes), in ``field_data``'s order."""
        import polars

        return polars.DataFrame({f.field_name: self.data[f.field_name] for f in self.field_data})

    def list_value_changes(self, field_name):
        """``(timestamp, value)`` wherever ``field_name`` changes, from the first row
        with a non-zero timestamp on (rows stamped 0 are left out), as pyulog's."""
        t = self.data["timestamp"]
        x = self.data[field_name]
        keep = t != 0
        t, x = t[keep], x[keep]
        if len(t) == 0:
            return []
        changes = np.where(x[:-1] != x[1:])[0] + 1
        return [(t[0], x[0])] + list(zip(t[changes], x[changes]))


class _ArrowBatch:
    """A record batch from the Rust reader, as the PyCapsule protocol of Arrow's C
    data interface hands it over (pyarrow, polars and DuckDB read it)."""

    def __init__(self, schema, array):
        self._capsules = (schema, array)

    def __arrow_c_array__(self, requested_schema=None):
        return self._capsules


class Aligned(dict):
    """Columns on one time base (``ULog.align``): ``"timestamp"`` (the steps, boot
    microseconds) then ``"topic.field"`` → a ``numpy.ma.MaskedArray`` of the field's
    type, masked where the topic has no value at the step; ``char[N]`` fields as lists
    of str ("" where absent)."""

    def to_pandas(self):
        """A ``pandas.DataFrame`` with nullable columns (``pd.NA`` where absent)."""
        import pandas

        columns = {}
        for name, values in self.items():
            if isinstance(values, np.ma.MaskedArray):
                data, mask = np.ma.getdata(values), np.ma.getmaskarray(values)
                if data.dtype == np.bool_:
                    columns[name] = pandas.arrays.BooleanArray(data, mask)
                elif data.dtype.kind == "f":
                    columns[name] = pandas.arrays.FloatingArray(data, mask)
                else:
                    columns[name] = pandas.arrays.IntegerArray(data, mask)
            else:
                columns[name] = values
        return pandas.DataFrame(columns)


class ULog:
    """A ULog log read into memory, with pyulog's API.

    :param log_file: a path (``str`` or ``os.PathLike``) or a readable binary file
        object (read from where it stands, then closed, as pyulog does)
    :param message_name_filter_list: topic names to load; ``None`` loads every topic
    :param disable_str_exceptions: decode texts leniently (``True``, pyulog's
        default) or raise ``UnicodeDecodeError``
    :param parse_header_only: read only the definitions section
    :raises ULogError: (a ``ValueError``) the file is not a ULog log
    :raises OSError: the file cannot be read (``FileNotFoundError`` …)
    """

    Data = Data
    MessageFormat = MessageFormat
    MessageLogging = MessageLogging
    MessageLoggingTagged = MessageLoggingTagged
    MessageDropout = MessageDropout

    def __init__(
        self,
        log_file,
        message_name_filter_list=None,
        disable_str_exceptions=True,
        parse_header_only=False,
    ):
        self._file_corrupt = False
        self._file_version = 0
        self._start_timestamp = 0
        self._last_timestamp = 0
        self._compat_flags = [0] * 8
        self._incompat_flags = [0] * 8
        self._appended_offsets = []
        self._msg_info_dict = {}
        self._msg_info_dict_types = {}
        self._msg_info_multiple_dict = {}
        self._msg_info_multiple_dict_types = {}
        self._initial_parameters = {}
        self._default_parameters = {}
        self._changed_parameters = []
        self._message_formats = {}
        self._logged_messages = []
        self._logged_messages_tagged = {}
        self._dropouts = []
        self._data_list = []
        self._findings = []
        self._utc = None
        self._events = []
        if log_file is not None:
            self._load(log_file, message_name_filter_list, disable_str_exceptions, parse_header_only)

    def _load(self, log_file, names, disable_str_exceptions, header_only):
        if isinstance(log_file, (str, os.PathLike)):
            source = os.fspath(log_file)
        else:
            source = log_file.read()
            log_file.close()
        # pyulog tests `name in message_name_filter_list`: a list keeps the topics
        # it names, a string (as pyulog's extract_message passes) those whose name
        # is part of it.
        within = isinstance(names, str)
        if names is not None:
            names = [names] if within else list(names)
        raw = _core.load(source, names, header_only, within)
        dec = _Decoder(strict=not disable_str_exceptions)

        self._file_version = raw["version"]
        self._start_timestamp = raw["start_timestamp"]
        self._last_timestamp = raw["last_timestamp"]
        self._compat_flags = list(raw["compat_flags"])
        self._incompat_flags = list(raw["incompat_flags"])
        self._appended_offsets = raw["appended_offsets"]
        for name, fields in raw["formats"]:
            self._message_formats[name] = MessageFormat(name, fields)
        for key, value in raw["info"]:
            kv = dec.key_value(key, value)
            if kv is not None:
                self._msg_info_dict[kv[1]] = kv[2]
                self._msg_info_dict_types[kv[1]] = kv[0]
        for entries in raw["info_multiple"]:
            lists = []
            for parts in entries:
                values = [dec.key_value(k, v) for k, v in parts]
                values = [v for v in values if v is not None]
                if values:
                    lists.append([v[2] for v in values])
                    name, type_str = values[0][1], values[0][0]
            if lists:
                self._msg_info_multiple_dict[name] = lists
                self._msg_info_multiple_dict_types.setdefault(name, type_str)
        for key, value in raw["initial_parameters"]:
            kv = dec.key_value(key, value)
            if kv is not None:
                self._initial_parameters[kv[1]] = kv[2]
        for bits, key, value in raw["default_parameters"]:
            kv = dec.key_value(key, value)
            if kv is None:
                continue
            for bit in range(8):
                if bits & (1 << bit):
                    self._default_parameters.setdefault(bit, {})[kv[1]] = kv[2]
        for timestamp, key, value in raw["changed_parameters"]:
            kv = dec.key_value(key, value)
            if kv is not None:
                self._changed_parameters.append((timestamp, kv[1], kv[2]))
        for level, tag, timestamp, text in raw["logged_messages"]:
            message = dec.text(text)
            if tag is None:
                self._logged_messages.append(MessageLogging(level, timestamp, message))
            else:
                self._logged_messages_tagged.setdefault(tag, []).append(
                    MessageLoggingTagged(level, tag, timestamp, message)
                )
        self._dropouts = [MessageDropout(d, t) for t, d in raw["dropouts"]]
        self._data_list = sorted(
            (Data(t, source) for t in raw["topics"] if t["fields"]), key=lambda d: (d.name, d.multi_id)
        )
        self._findings = [Finding(*f) for f in raw["findings"]]
        self._utc = UtcClock(*raw["utc"]) if raw.get("utc") else None
        # Decoded when first asked for (most loads never are).
        self._events = raw.get("events", [])
        self._file_corrupt = bool(raw["corrupt"] or dec.corrupt)

    # pyulog's public API

    @staticmethod
    def get_field_size(type_str):
        """The size in bytes of a basic type (``'int8_t'`` … ``'double'``)."""
        return _TYPES[type_str][1]

    @property
    def start_timestamp(self):
        """The timestamp of the log's start (its header), in microseconds."""
        return self._start_timestamp

    @property
    def last_timestamp(self):
        """The latest timestamp of the loaded topics' rows (the start if none)."""
        return self._last_timestamp

    @property
    def msg_info_dict(self):
        """Information messages: name → value (decoded by the type in the key)."""
        return self._msg_info_dict

    @property
    def msg_info_dict_types(self):
        """Information messages: name → type (``char[40]``, ``uint32_t`` …)."""
        return self._msg_info_dict_types

    @property
    def msg_info_multiple_dict(self):
        """Multi-information messages: name → list of entries, each the list of
        its continued parts' values."""
        return self._msg_info_multiple_dict

    @property
    def initial_parameters(self):
        """Parameters of the definitions section: name → value."""
        return self._initial_parameters

    def get_default_parameters(self, default_type):
        """Default parameters of one kind (0: system, 1: current setup): name →
        value (only those the log holds)."""
        return self._default_parameters.get(default_type, {})

    @property
    def changed_parameters(self):
        """Parameter changes in the data section: ``(timestamp, name, value)``, the
        timestamp the latest of the loaded topics' rows before the change."""
        return self._changed_parameters

    @property
    def message_formats(self):
        """Formats: name → ``MessageFormat``, in file order."""
        return self._message_formats

    @property
    def logged_messages(self):
        """Logged strings (``MessageLogging``), in file order."""
        return self._logged_messages

    @property
    def logged_messages_tagged(self):
        """Tagged logged strings: tag → list of ``MessageLoggingTagged``."""
        return self._logged_messages_tagged

    @property
    def dropouts(self):
        """Dropouts (``MessageDropout``), in file order."""
        return self._dropouts

    @property
    def data_list(self):
        """The topic instances with rows (``Data``), sorted by name and instance."""
        return self._data_list

    @property
    def has_data_appended(self):
        """Non-zero when the DATA_APPENDED flag is set (an ``int``, as pyulog's)."""
        return self._incompat_flags[0] & 0x1

    @property
    def file_corruption(self):
        """Whether the reader found damage (``findings`` says what and where)."""
        return self._file_corrupt

    @property
    def has_default_parameters(self):
        """Non-zero when the DEFAULT_PARAMETERS flag is set (an ``int``)."""
        return self._compat_flags[0] & 0x1

    def get_dataset(self, name, multi_instance=0):
        """The ``Data`` of topic ``name``, instance ``multi_instance``.

        :raises TopicNotFound: (a ``KeyError`` and an ``IndexError``) no such topic
            instance with rows
        """
        for d in self._data_list:
            if d.name == name and d.multi_id == multi_instance:
                return d
        instances = sorted(d.multi_id for d in self._data_list if d.name == name)
        if instances:
            raise TopicNotFound(
                "topic {!r} has no instance {} (it has {})".format(
                    name, multi_instance, ", ".join(map(str, instances))
                )
            )
        close = _core.closest(name, sorted({d.name for d in self._data_list}))
        hint = " (did you mean {!r}?)".format(close) if close else ""
        raise TopicNotFound("no topic {!r} with rows in the log{}".format(name, hint))

    def get_version_info(self, key_name="ver_sw_release"):
        """``(major, minor, patch, type)`` of a release-version information message,
        or ``None``."""
        if key_name not in self._msg_info_dict:
            return None
        v = self._msg_info_dict[key_name]
        return ((v >> 24) & 0xFF, (v >> 16) & 0xFF, (v >> 8) & 0xFF, v & 0xFF)

    def get_version_info_str(self, key_name="ver_sw_release"):
        """``v1.14.0``, ``v1.4.2 (RC)`` …; ``None`` when absent or a development
        version."""
        v = self.get_version_info(key_name)
        if v is None or v[3] < 64:
            return None
        kind = " (alpha)" if v[3] < 128 else " (beta)" if v[3] < 192 else " (RC)" if v[3] < 255 else ""
        return "v{}.{}.{}{}".format(v[0], v[1], v[2], kind)

    def write_ulog(self, log_file):
        """Writes the log as it now is in memory (data arrays included) to a path or
        a writable binary file object, as pyulog does: definitions, subscriptions,
        then the data section ordered by timestamp."""
        from ._write import write_ulog

        if isinstance(log_file, (str, os.PathLike)):
            with open(log_file, "wb") as f:
                write_ulog(self, f)
        else:
            write_ulog(self, log_file)

    # Beyond pyulog

    def to_arrow(self, names=None):
        """Record batches of the topics with rows (or of those named), read in one
        pass: ``{(name, multi_id): pyarrow.RecordBatch}`` (see ``Data.to_arrow``)."""
        import pyarrow

        keys = [(d.name, d.multi_id) for d in self._data_list if names is None or d.name in names]
        batches = _core.arrow_batches(self._data_list[0]._source, keys) if keys else []
        return {k: pyarrow.record_batch(_ArrowBatch(*b)) for k, b in zip(keys, batches) if b is not None}

    def align(self, selections, on=None, rate=None, method="previous", tolerance=None,
              start=None, end=None):
        """Several topics on one time base (``ulog_core::align``, as ``ulog align``).

        :param selections: topics (``"battery_status"``: every field) or fields
            (``"vehicle_attitude.q[0]"``, ``"esc_status:1.esc[2].esc_rpm"``)
        :param on: step on the rows of this topic (``"TOPIC"`` or ``"TOPIC:N"``) …
        :param rate: … or at this many steps per second from the log's start
        :param method: ``"previous"`` (the last row at or before the step: pandas'
            ``merge_asof(direction="backward")``), ``"nearest"`` or ``"linear"``
            (floats interpolated, ``q[4]`` by slerp, other types from the earlier row)
        :param tolerance: seconds beyond which a row is no value at a step
        :param start: steps from this time (seconds since the log's start) …
        :param end: … and before this one
        :returns: ``Aligned``
        :raises ULogError: an unknown topic or field (with the closest), a bad option
        """
        if isinstance(selections, str):
            selections = [selections]
        if not self._data_list:
            raise ULogError("the log has no topic with rows to align")
        times, columns = _core.align(
            self._data_list[0]._source, list(selections), on, rate, method, tolerance, start, end
        )
        out = Aligned(timestamp=times)
        for name, values, present in columns:
            if isinstance(values, list):
                out[name] = values
            else:
                out[name] = np.ma.MaskedArray(values, mask=~present)
        return out

    @property
    def utc(self):
        """The log's ``UtcClock``, or ``None`` (no GPS time and no
        ``boot_time_utc_us``)."""
        return self._utc

    def to_utc(self, timestamps):
        """Boot-relative timestamps (µs; one or an array) as UTC ``numpy.datetime64``
        (µs precision). Raises ``ValueError`` when the log has no UTC clock."""
        if self._utc is None:
            raise ValueError("the log has no UTC clock (no GPS time, no boot_time_utc_us)")
        t = np.asarray(timestamps).astype(np.int64) + self._utc.boot_us
        return t.astype("datetime64[us]")

    @property
    def events(self):
        """The PX4 events of the log's ``event`` topic, decoded (``Event``)."""
        if not isinstance(self._events, list):
            self._events = [Event(*e) for e in self._events.decode()]
        return self._events

    @property
    def findings(self):
        """What the reader found wrong, with byte offsets (``Finding`` tuples)."""
        return self._findings

    def __eq__(self, other):
        if not isinstance(other, ULog):
            return NotImplemented
        return all(
            getattr(self, k) == getattr(other, k)
            for k in (
                "_file_corrupt",
                "_file_version",
                "_start_timestamp",
                "_last_timestamp",
                "_compat_flags",
                "_incompat_flags",
                "_appended_offsets",
                "_msg_info_dict",
                "_msg_info_dict_types",
                "_msg_info_multiple_dict",
                "_initial_parameters",
                "_default_parameters",
                "_changed_parameters",
                "_message_formats",
                "_logged_messages",
                "_logged_messages_tagged",
                "_dropouts",
                "_data_list",
            )
        )

    __hash__ = None

    def __getstate__(self):
        # The events still to decode are a Rust object: decoded for a copy or a
        # pickle.
        self.events
        return self.__dict__

