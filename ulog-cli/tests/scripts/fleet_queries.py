"""Runs the README's seven "Fleet analysis" queries over a dataset, with DuckDB and, for
three of them, DataFusion, and prints the answers as JSON for ulog-cli/tests/fleet.rs
to check against the ulog reader.

Usage: fleet_queries.py README.md DATASET
"""
import json
import math
import os
import re
import sys

import datafusion
import duckdb


def readme_queries(readme):
    text = open(readme, encoding="utf-8").read()
    start = text.index("\n## Fleet analysis")
    end = text.find("\n## ", start + 1)
    section = text[start:end if end >= 0 else len(text)]
    return re.findall(r"```sql\n(.*?)```", section, re.S)


def plain(value):
    if isinstance(value, float) and math.isnan(value):
        return "NaN"
    return value


def rows(relation):
    return [[plain(v) for v in row] for row in relation.fetchall()]


def main():
    readme, dataset = sys.argv[1], sys.argv[2]
    queries = [q.replace("DATASET", dataset) for q in readme_queries(readme)]
    assert len(queries) == 7, f"the README has {len(queries)} queries, not 7"
    con = duckdb.connect()
    out = {"duckdb": [rows(con.sql(q)) for q in queries]}

    # Rows per topic and log, over every topic folder.
    counts = []
    for topic in sorted(os.listdir(dataset)):
        folder = os.path.join(dataset, topic)
        if not os.path.isdir(folder):
            continue
        pattern = os.path.join(folder, "**", "*.parquet").replace("'", "''")
        for log_id, n in con.sql(
            f"SELECT log_id, count(*) FROM read_parquet('{pattern}', union_by_name = true) "
            "GROUP BY log_id"
        ).fetchall():
            counts.append([topic, log_id, n])
    out["counts"] = counts
    out["logs"] = rows(con.sql(
        f"SELECT log_id, path, sha256 FROM '{dataset}/logs.parquet' ORDER BY log_id"))

    # DataFusion: questions 1, 2 and 5, as the README shows it registering tables.
    ctx = datafusion.SessionContext()
    ctx.register_parquet("logs", os.path.join(dataset, "logs.parquet"))
    ctx.register_parquet(
        "vehicle_local_position", os.path.join(dataset, "vehicle_local_position") + "/")

    def df(sql):
        table = ctx.sql(sql).to_arrow_table()
        columns = [table.column(i).to_pylist() for i in range(table.num_columns)]
        return [[plain(v) for v in row] for row in zip(*columns)]

    out["datafusion"] = {
        "1": df("SELECT coalesce(sys_uuid, ver_hw) AS vehicle, ver_sw_release AS firmware, "
                "count(*) AS flights FROM logs GROUP BY 1, 2 ORDER BY 1, 2"),
        "2": df("SELECT log_id, max(-z) FROM vehicle_local_position "
                "WHERE NOT isnan(z) GROUP BY log_id ORDER BY log_id"),
        "5": df("SELECT path, truncated, corrupt_bytes, findings FROM logs "
                "WHERE damaged OR truncated ORDER BY path"),
    }
    json.dump(out, sys.stdout)


main()
