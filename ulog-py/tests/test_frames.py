"""Beyond pyulog: each topic as a pyarrow RecordBatch (the log's types, nested types
as structs, arrays as fixed-size lists), a pandas and a polars DataFrame. Checked
against pyulog's arrays: every value pyulog reads is the same in each."""

import re

import numpy as np
import pytest

pyulog = pytest.importorskip("pyulog")
pa = pytest.importorskip("pyarrow")
pc = pytest.importorskip("pyarrow.compute")
import ulog_rs

from conftest import OWN

LOGS = sorted(OWN.glob("*.ulg"))
PART = re.compile(r"([A-Za-z0-9_]+)|\[(\d+)\]")


def leaf(batch, path):
    """The values of pyulog's flattened column `path` (`esc[3].esc_rpm`) in an
    Arrow record batch of nested structs and fixed-size lists."""
    parts = PART.findall(path)
    column = batch.column(parts[0][0])
    for name, index in parts[1:]:
        column = pc.list_element(column, int(index)) if index else pc.struct_field(column, name)
    return column


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_to_arrow_holds_every_value_pyulog_reads(path):
    ours, theirs = ulog_rs.ULog(str(path)), pyulog.ULog(str(path))
    batches = ours.to_arrow()
    assert set(batches) == {(d.name, d.multi_id) for d in ours.data_list}
    for d in theirs.data_list:
        batch = batches[(d.name, d.multi_id)]
        assert batch.num_rows == len(d.data["timestamp"]), d.name
        one = ours.get_dataset(d.name, d.multi_id).to_arrow()
        assert one.schema.equals(batch.schema) and one.num_rows == batch.num_rows, d.name
        chars = {f.field_name for f in d.field_data if f.type_str == "char"}
        checked = 0
        for f in d.field_data:
            name = f.field_name
            if "_padding" in name or name in chars:
                continue  # padding is not a value; char[N] is one string column
            got = leaf(batch, name).to_numpy(zero_copy_only=False)
            want = d.data[name]
            if f.type_str == "bool":
                want = want.astype(bool)
            assert got.dtype == want.dtype, (d.name, name, got.dtype, want.dtype)
            assert got.tobytes() == want.tobytes(), (d.name, name)
            checked += 1
        assert checked > 0, d.name


@pytest.mark.parametrize("path", LOGS, ids=[p.stem for p in LOGS])
def test_pandas_and_polars_frames_hold_pyulogs_columns(path):
    pytest.importorskip("pandas")
    pytest.importorskip("polars")
    theirs = pyulog.ULog(str(path))
    for d in ulog_rs.ULog(str(path)).data_list:
        t = theirs.get_dataset(d.name, d.multi_id)
        names = [f.field_name for f in t.field_data]
        pdf, plf = d.to_pandas(), d.to_polars()
        assert list(pdf.columns) == names and plf.columns == names
        for n in names:
            assert pdf[n].to_numpy().tobytes() == t.data[n].tobytes(), (d.name, n)
            assert plf[n].to_numpy().tobytes() == t.data[n].tobytes(), (d.name, n)
