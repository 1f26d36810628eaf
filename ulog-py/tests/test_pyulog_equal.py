"""ulog_rs.ULog against pyulog 1.3 on every log of the corpora: every public
attribute equal, every data array of the same dtype and bit for bit the same.

Where pyulog reports corruption, the logs differ by design: our reader resynchronises
where pyulog skips, so each topic's rows are a superset of pyulog's (pyulog's, in
order, are among ours) and the parameter changes and dropouts after the damage may
carry a later "latest timestamp"."""

import io

import numpy as np
import pytest

pyulog = pytest.importorskip("pyulog")
import ulog_rs

from conftest import corpus_logs

LOGS = corpus_logs()


def same_array(a, b):
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def rows_of(d):
    """Each row of a Data as bytes, pyulog's or ours."""
    names = [f.field_name for f in d.field_data]
    table = np.rec.fromarrays([d.data[n] for n in names], names=names) if names else []
    return [r.tobytes() for r in table]


def is_subsequence(small, big):
    it = iter(big)
    return all(any(x == y for y in it) for x in small)


def assert_data_equal(ours, theirs, what):
    assert (ours.name, ours.multi_id, ours.msg_id) == (theirs.name, theirs.multi_id, theirs.msg_id), what
    assert [(f.field_name, f.type_str) for f in ours.field_data] == [
        (f.field_name, f.type_str) for f in theirs.field_data
    ], what
    assert ours.timestamp_idx == theirs.timestamp_idx, what
    assert list(ours.data) == list(theirs.data), what
    for key in theirs.data:
        assert same_array(ours.data[key], theirs.data[key]), "{}: {}".format(what, key)


def assert_same_metadata(ours, theirs, what, damaged):
    assert ours.start_timestamp == theirs.start_timestamp, what
    assert ours.file_corruption == theirs.file_corruption, what
    assert ours.msg_info_dict == theirs.msg_info_dict, what
    assert ours.msg_info_dict_types == theirs._msg_info_dict_types, what
    assert ours.msg_info_multiple_dict == theirs.msg_info_multiple_dict, what
    assert ours.initial_parameters == theirs.initial_parameters, what
    for kind in (0, 1, 2):
        assert ours.get_default_parameters(kind) == theirs.get_default_parameters(kind), what
    assert list(ours.message_formats) == list(theirs.message_formats), what
    for name, fmt in theirs.message_formats.items():
        assert (ours.message_formats[name].name, ours.message_formats[name].fields) == (fmt.name, fmt.fields), what
    assert ours.has_data_appended == theirs.has_data_appended, what
    assert ours.has_default_parameters == theirs.has_default_parameters, what
    assert ours.get_version_info() == theirs.get_version_info(), what
    assert ours.get_version_info_str() == theirs.get_version_info_str(), what
    assert [(m.log_level, m.timestamp, m.message, m.log_level_str()) for m in ours.logged_messages] == [
        (m.log_level, m.timestamp, m.message, m.log_level_str()) for m in theirs.logged_messages
    ], what
    assert {
        tag: [(m.log_level, m.tag, m.timestamp, m.message) for m in ms]
        for tag, ms in ours.logged_messages_tagged.items()
    } == {
        tag: [(m.log_level, m.tag, m.timestamp, m.message) for m in ms]
        for tag, ms in theirs.logged_messages_tagged.items()
    }, what
    if damaged:
        assert [c[1:] for c in ours.changed_parameters] == [c[1:] for c in theirs.changed_parameters], what
        assert [d.duration for d in ours.dropouts] == [d.duration for d in theirs.dropouts], what
        assert ours.last_timestamp >= theirs.last_timestamp, what
    else:
        assert ours.changed_parameters == theirs.changed_parameters, what
        assert [(d.duration, d.timestamp) for d in ours.dropouts] == [
            (d.duration, d.timestamp) for d in theirs.dropouts
        ], what
        assert ours.last_timestamp == theirs.last_timestamp, what


def assert_same(ours, theirs, what):
    damaged = theirs.file_corruption
    assert_same_metadata(ours, theirs, what, damaged)
    ours_by_key = {(d.name, d.multi_id): d for d in ours.data_list}
    theirs_keys = [(d.name, d.multi_id) for d in theirs.data_list]
    if not damaged:
        assert list(ours_by_key) == theirs_keys, what
        for o, t in zip(ours.data_list, theirs.data_list):
            assert_data_equal(o, t, "{} {}/{}".format(what, t.name, t.multi_id))
        return
    # A damaged log: pyulog's topics and rows are among ours.
    assert set(theirs_keys) <= set(ours_by_key), what
    for t in theirs.data_list:
        o = ours_by_key[(t.name, t.multi_id)]
        w = "{} {}/{}".format(what, t.name, t.multi_id)
        assert [(f.field_name, f.type_str) for f in o.field_data] == [
            (f.field_name, f.type_str) for f in t.field_data
        ], w
        assert all(o.data[k].dtype == t.data[k].dtype for k in t.data), w
        assert is_subsequence(rows_of(t), rows_of(o)), w


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_every_attribute_equals_pyulogs(path):
    assert_same(ulog_rs.ULog(str(path)), pyulog.ULog(str(path)), path.name)


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_a_filter_list_loads_what_pyulogs_does(path):
    full = pyulog.ULog(str(path))
    names = sorted({d.name for d in full.data_list})[::3][:4] + ["no_such_topic"]
    assert_same(
        ulog_rs.ULog(str(path), message_name_filter_list=names),
        pyulog.ULog(str(path), message_name_filter_list=names),
        path.name + " filtered",
    )


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_the_header_alone_equals_pyulogs(path):
    ours = ulog_rs.ULog(str(path), parse_header_only=True)
    theirs = pyulog.ULog(str(path), parse_header_only=True)
    assert ours.data_list == [] and theirs.data_list == []
    assert_same_metadata(ours, theirs, path.name + " header", damaged=False)


def test_a_file_object_and_a_path_read_the_same(sample_log):
    with open(sample_log, "rb") as f:
        from_file = ulog_rs.ULog(f)
        assert f.closed, "pyulog closes the file it was given, and so do we"
    from_bytes = ulog_rs.ULog(io.BytesIO(sample_log.read_bytes()))
    from_path = ulog_rs.ULog(sample_log)
    assert from_file == from_path == from_bytes
    assert_same(from_file, pyulog.ULog(str(sample_log)), "file object")


def test_data_arrays_are_writable_and_change_equality(sample_log):
    a, b = ulog_rs.ULog(str(sample_log)), ulog_rs.ULog(str(sample_log))
    assert a == b and a is not b
    a.data_list[0].data["timestamp"][0] += 1
    assert a != b


def test_list_value_changes_equals_pyulogs(sample_log):
    ours, theirs = ulog_rs.ULog(str(sample_log)), pyulog.ULog(str(sample_log))
    for o, t in zip(ours.data_list, theirs.data_list):
        for f in t.field_data[:6]:
            got = [(int(a), b.tobytes()) for a, b in o.list_value_changes(f.field_name)]
            want = [(int(a), b.tobytes()) for a, b in t.list_value_changes(f.field_name)]
            assert got == want, (t.name, f.field_name)


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_two_passes_sharing_the_topics_read_what_one_does(path):
    # A log of 16 MiB or more is read by two passes on two threads, each packing its
    # share of the topics; here every corpus log is, and must read as in one pass.
    from ulog_rs import _core

    one = _core.load(str(path))
    two = _core.load(str(path), share_from=0)
    assert one.keys() == two.keys()
    for key in one:
        if key == "events":
            assert one[key].decode() == two[key].decode()
        elif key != "topics":
            assert one[key] == two[key], key
    by_key = lambda raw: {(t["name"], t["multi_id"]): t for t in raw["topics"]}
    a, b = by_key(one), by_key(two)
    assert a.keys() == b.keys()
    for k in a:
        assert a[k]["fields"] == b[k]["fields"], k
        assert a[k]["rows"].tobytes() == b[k]["rows"].tobytes(), k
