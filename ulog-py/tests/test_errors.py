"""Errors reach Python as exceptions of this library's kinds, with its messages;
a panic in the Rust code is an exception too, never an abort."""

import pytest

import ulog_rs
from ulog_rs import _core


def test_a_file_that_is_not_ulog_is_a_value_error(tmp_path):
    path = tmp_path / "notes.txt"
    path.write_bytes(b"these are not the bytes of a flight log\n" * 4)
    with pytest.raises(ulog_rs.ULogError) as e:
        ulog_rs.ULog(str(path))
    assert isinstance(e.value, ValueError)
    assert "ULog" in str(e.value) or "magic" in str(e.value), str(e.value)


def test_a_missing_file_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError) as e:
        ulog_rs.ULog(str(tmp_path / "missing.ulg"))
    assert "missing.ulg" in str(e.value)


def test_an_unknown_topic_is_a_key_error_and_an_index_error(sample_log):
    log = ulog_rs.ULog(str(sample_log))
    name = log.data_list[0].name
    with pytest.raises(KeyError):
        log.get_dataset(name + "x")
    with pytest.raises(IndexError) as e:
        log.get_dataset(name + "x")
    assert "did you mean {!r}".format(name) in str(e.value)
    with pytest.raises(ulog_rs.TopicNotFound) as e:
        log.get_dataset(name, 9)
    assert "no instance 9" in str(e.value)


def test_a_panic_becomes_an_exception():
    with pytest.raises(ulog_rs.InternalError) as e:
        _core._panic_for_tests()
    assert isinstance(e.value, RuntimeError)
    assert "panicked" in str(e.value)


def test_strict_strings_raise_as_pyulogs_do(tmp_path):
    from conftest import OWN

    # A logged string of a log of the repository's corpus, one byte made not UTF-8.
    for path in sorted(OWN.glob("*.ulg")):
        texts = [m.message for m in ulog_rs.ULog(str(path)).logged_messages if len(m.message) > 4]
        if texts:
            break
    assert texts, "a log of tests/corpus has logged strings"
    data = bytearray(path.read_bytes())
    at = data.find(texts[0].encode("utf-8"))
    data[at + 1] = 0xFF
    bad = tmp_path / "bad_text.ulg"
    bad.write_bytes(bytes(data))
    lenient = ulog_rs.ULog(str(bad))
    assert texts[0][0] + texts[0][2:] in [m.message for m in lenient.logged_messages]
    with pytest.raises(UnicodeDecodeError):
        ulog_rs.ULog(str(bad), disable_str_exceptions=False)
