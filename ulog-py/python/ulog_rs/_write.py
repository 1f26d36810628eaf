"""``ULog.write_ulog``: a log as it is in memory, written back as a ULog file.

What pyulog's ``write_ulog`` writes: the header, flag bits without DATA_APPENDED,
formats, information, multi-information, initial and default parameters, the
subscriptions by msg_id, then the data section (data rows by msg_id, logged strings,
tagged strings, dropouts, parameter changes, in that order) sorted by timestamp, ties
kept in that order. Rows are packed from the current ``data`` arrays with numpy, one
message per row, instead of one ``struct.pack`` per value.
"""

import struct

import numpy as np

from ._types import _TYPES

_MAGIC = b"ULog\x01\x12\x35"


def _message(msg_type, payload):
    return struct.pack("<HB", len(payload), ord(msg_type)) + payload


def _value_bytes(type_str, value):
    if isinstance(value, (bytes, bytearray)):
        return bytes(value)
    if type_str.startswith("char["):
        return value.encode("utf-8")
    return struct.pack("<" + _TYPES[type_str][0], value)


def _key_value(type_str, name, value):
    key = "{} {}".format(type_str, name).encode("utf-8")
    return struct.pack("<B", len(key)) + key + _value_bytes(type_str, value)


def _param(name, value):
    if isinstance(value, int):
        return _key_value("int32_t", name, value)
    if isinstance(value, float):
        return _key_value("float", name, value)
    raise TypeError("parameter {!r}: a value of type {} is neither int nor float".format(name, type(value).__name__))


def _rows(data_set):
    """The data messages of one topic, as one bytes object, and their sizes and
    timestamps."""
    fields = [(f.field_name, "<" + np.dtype(_TYPES[f.type_str][2]).str[1:]) for f in data_set.field_data]
    row = np.dtype(fields)
    msg = np.dtype([("size", "<u2"), ("type", "u1"), ("msg_id", "<u2"), ("row", row)])
    n = len(data_set.data[data_set.field_data[0].field_name])
    out = np.zeros(n, dtype=msg)
    out["size"] = 2 + row.itemsize
    out["type"] = ord("D")
    out["msg_id"] = data_set.msg_id
    for name, _ in fields:
        out["row"][name] = data_set.data[name]
    stamps = data_set.data.get("timestamp")
    if stamps is None:
        stamps = np.zeros(n, dtype=np.uint64)
    return out.tobytes(), msg.itemsize, stamps


def write_ulog(log, f):
    """Writes ``log`` (a ``ulog_rs.ULog``) to the binary file object ``f``."""
    f.write(_MAGIC + struct.pack("<BQ", log._file_version, log._start_timestamp))
    incompat = list(log._incompat_flags)
    incompat[0] &= 0xFE
    f.write(_message("B", struct.pack("<8B8B3Q", *log._compat_flags, *incompat, 0, 0, 0)))
    for fmt in log._message_formats.values():
        text = fmt.name + ":" + "".join(
            ("{}[{}] {};".format(t, n, name) if n > 0 else "{} {};".format(t, name))
            for t, n, name in fmt.fields
        )
        f.write(_message("F", text.encode("utf-8")))
    for name, value in log._msg_info_dict.items():
        f.write(_message("I", _key_value(log._msg_info_dict_types[name], name, value)))
    for name, entries in log._msg_info_multiple_dict.items():
        type_str = log._msg_info_multiple_dict_types[name]
        for entry in entries:
            for i, value in enumerate(entry):
                f.write(_message("M", struct.pack("<B", i > 0) + _key_value(type_str, name, value)))
    for name, value in log._initial_parameters.items():
        f.write(_message("P", _param(name, value)))
    for bit, params in log._default_parameters.items():
        for name, value in params.items():
            f.write(_message("Q", struct.pack("<B", 1 << bit) + _param(name, value)))
    by_id = sorted(log._data_list, key=lambda d: d.msg_id)
    for d in by_id:
        f.write(_message("A", struct.pack("<BH", d.multi_id, d.msg_id) + d.name.encode("utf-8")))

    # The data section: (timestamps, messages) in pyulog's order, then one stable sort.
    stamps, blobs = [], []
    for d in by_id:
        data, size, t = _rows(d)
        stamps.append(np.asarray(t, dtype=np.uint64))
        blobs.extend(data[i : i + size] for i in range(0, len(data), size))
    others = []
    for m in log._logged_messages:
        others.append((m.timestamp, _message("L", struct.pack("<BQ", m.log_level, m.timestamp) + m.message.encode("utf-8"))))
    for messages in log._logged_messages_tagged.values():
        for m in messages:
            payload = struct.pack("<BHQ", m.log_level, m.tag, m.timestamp) + m.message.encode("utf-8")
            others.append((m.timestamp, _message("C", payload)))
    for d in log._dropouts:
        others.append((d.timestamp, _message("O", struct.pack("<H", d.duration))))
    for timestamp, name, value in log._changed_parameters:
        others.append((timestamp, _message("P", _param(name, value))))
    stamps.append(np.array([t for t, _ in others], dtype=np.uint64))
    blobs.extend(b for _, b in others)
    order = np.argsort(np.concatenate(stamps), kind="stable")
    f.write(b"".join(blobs[i] for i in order))
