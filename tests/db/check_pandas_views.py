#!/usr/bin/env python3
"""Runs the pandas example of docs/database.md as written and checks what it read.

  check_pandas_views.py DATABASE_MD DB RUN_ID UTC_NS STEPS
      the example's `power_W` holds a reading at UTC_NS (ns since the epoch, a sample recorded
      after a resume), and `steps` has STEPS rows numbered from 1
Exits 1 with a message on stderr at the first failed check.
"""
import sys

import pandas as pd

from docs_example import check_tables, fail, run_example


def main():
    doc, db_path, run_id, utc_ns, n_steps = sys.argv[1:6]
    scope = run_example(doc, "pandas-example", {"db_path": db_path, "run_id": int(run_id)})
    power = scope["power_W"]
    when = pd.Timestamp(int(utc_ns), unit="ns", tz="UTC")
    if when not in power.index:
        near = power.index[power.index.get_indexer([when], method="nearest")[0]]
        fail(f"no power reading at {when}; nearest {near} ({(near - when).total_seconds()} s off)")
    if abs(float(power.loc[when]) - 9e-4) > 1e-15:
        fail(f"power at {when} is {power.loc[when]}, not 9e-4")
    check_tables(scope, int(n_steps), "measured_T_se")
    print(f"check_pandas_views: power at {when} = {power.loc[when]}, {len(scope['steps'])} measured step(s)")


if __name__ == "__main__":
    main()
