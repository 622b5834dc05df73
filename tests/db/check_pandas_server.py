#!/usr/bin/env python3
"""Runs the server pandas example of docs/database.md as written and checks what it read.

  check_pandas_server.py DATABASE_MD DB_URI RUN_ID SAMPLES STEPS
      the example's `series` has SAMPLES rows, `steps` STEPS rows numbered from 1, and
      `power_W` is in UTC order
Exits 1 with a message on stderr at the first failed check.
"""
import sys

from docs_example import check_tables, fail, run_example


def main():
    doc, db_uri, run_id, n_samples, n_steps = sys.argv[1:6]
    scope = run_example(doc, "pandas-server-example", {"db_uri": db_uri, "run_id": int(run_id)})
    if len(scope["series"]) != int(n_samples):
        fail(f"series has {len(scope['series'])} rows, expected {n_samples}")
    check_tables(scope, int(n_steps), "measured_T")
    print(f"check_pandas_server: {len(scope['series'])} samples, {len(scope['steps'])} measured step(s)")


if __name__ == "__main__":
    main()
