"""ULog.align against pandas and numpy on pyulog's arrays: `previous` is
`merge_asof(direction="backward")`, `nearest` `merge_asof(direction="nearest")`,
`linear` `numpy.interp` per float column; with a tolerance; and a rate grid."""

import numpy as np
import pytest

pyulog = pytest.importorskip("pyulog")
pd = pytest.importorskip("pandas")
import ulog_rs

from conftest import corpus_logs

LOGS = corpus_logs()


def pair(log):
    """The topic with most rows (the steps) and another with rows and numbers."""
    by_rows = sorted(log.data_list, key=lambda d: (-len(d.data["timestamp"]), d.name, d.multi_id))
    on = by_rows[0]
    for d in reversed(by_rows[1:]):
        if len(d.data["timestamp"]) >= 2 and d.name != on.name:
            return on, d
    return None, None


def expected(on, other, direction, tolerance=None):
    left = pd.DataFrame({"step": on.data["timestamp"].astype(np.int64)})
    fields = [f.field_name for f in other.field_data
              if f.type_str != "char" and "_padding" not in f.field_name]
    right = pd.DataFrame({f: other.data[f] for f in fields})
    right["t_right"] = other.data["timestamp"].astype(np.int64)
    right = right.sort_values("t_right", kind="stable")
    kw = {} if tolerance is None else {"tolerance": tolerance}
    merged = pd.merge_asof(left, right, left_on="step", right_on="t_right",
                           direction=direction, **kw)
    return merged, fields


def label(d):
    return d.name if d.multi_id == 0 else "{}:{}".format(d.name, d.multi_id)


@pytest.mark.parametrize("direction,tolerance", [("backward", None), ("backward", 2000), ("nearest", None)])
@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_previous_and_nearest_are_merge_asof(path, direction, tolerance):
    theirs = pyulog.ULog(str(path))
    if theirs.file_corruption:
        pytest.skip("damaged: we recover rows pyulog loses, so its arrays are not ours")
    on, other = pair(theirs)
    if on is None:
        pytest.skip("no two topics with rows")
    method = "previous" if direction == "backward" else "nearest"
    got = ulog_rs.ULog(str(path)).align(
        [label(other)], on=label(on), method=method,
        tolerance=None if tolerance is None else tolerance / 1e6,
    )
    want, fields = expected(on, other, direction, tolerance)
    assert np.array_equal(got["timestamp"].astype(np.int64), want["step"].to_numpy())
    absent = want["t_right"].isna().to_numpy()
    for f in fields:
        column = got["{}.{}".format(label(other), f)]
        assert np.array_equal(np.ma.getmaskarray(column), absent), f
        have = np.ma.getdata(column)[~absent]
        exp = want[f].to_numpy()[~absent].astype(other.data[f].dtype)
        if other.data[f].dtype == np.int8 and have.dtype == np.bool_:
            exp = exp.astype(bool)
        assert have.astype(exp.dtype).tobytes() == exp.tobytes(), f


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_linear_is_numpy_interp(path):
    theirs = pyulog.ULog(str(path))
    if theirs.file_corruption:
        pytest.skip("damaged: we recover rows pyulog loses, so its arrays are not ours")
    on, other = pair(theirs)
    if on is None:
        pytest.skip("no two topics with rows")
    got = ulog_rs.ULog(str(path)).align([label(other)], on=label(on), method="linear")
    t = got["timestamp"].astype(np.float64)
    xp = other.data["timestamp"].astype(np.float64)
    inside = (t >= xp[0]) & (t <= xp[-1])
    for f in other.field_data:
        if f.type_str not in ("float", "double") or (f.field_name.startswith("q[") and "q[3]" in
                                                      {g.field_name for g in other.field_data}):
            continue
        fp = other.data[f.field_name].astype(np.float64)
        if not np.all(np.isfinite(fp)) or np.any(np.diff(xp) <= 0):
            continue
        column = got["{}.{}".format(label(other), f.field_name)]
        have = np.ma.getdata(column)[inside].astype(np.float64)
        want = np.interp(t[inside], xp, fp)
        tol = 4 * np.finfo(np.float32 if f.type_str == "float" else np.float64).eps
        assert np.allclose(have, want, rtol=tol, atol=tol * np.max(np.abs(fp) + 1)), f.field_name
        assert np.all(np.ma.getmaskarray(column)[~inside]), f.field_name


def test_a_rate_grid_and_pandas_frame(sample_log):
    log = ulog_rs.ULog(str(sample_log))
    name = log.data_list[0].name
    got = log.align([name], rate=10.0)
    steps = got["timestamp"].astype(np.int64)
    assert len(steps) > 1 and np.all(np.diff(steps) == 100_000)
    frame = got.to_pandas()
    assert list(frame.columns) == list(got)
    assert frame.shape[0] == len(steps)


def test_unknown_names_and_bad_options_raise(sample_log):
    log = ulog_rs.ULog(str(sample_log))
    name = log.data_list[0].name
    with pytest.raises(ulog_rs.ULogError) as e:
        log.align([name + "x"], rate=1.0)
    assert name in str(e.value)
    with pytest.raises(ulog_rs.ULogError):
        log.align([name], rate=1.0, method="cubic")
    with pytest.raises(ulog_rs.ULogError):
        log.align([name])
    with pytest.raises(ulog_rs.ULogError):
        log.align([name], rate=1.0, tolerance=-1)
