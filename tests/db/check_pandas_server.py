#!/usr/bin/env python3
"""Runs the server pandas example of docs/database.md as written and checks what it read.

  check_pandas_server.py DATABASE_MD DB_URI RUN_ID SAMPLES STEPS
      the example's `series` has SAMPLES rows, `steps` STEPS rows numbered from 1, and
      `power_W` is in UTC order
Exits 1 with a message on stderr at the first failed check.
"""
import sys

from docs_example import fail, run_example


def main():
    doc, db_uri, run_id, n_samples, n_steps = sys.argv[1:6]
    scope = run_example(doc, "pandas-server-example", {"db_uri": db_uri, "run_id": int(run_id)})
    if len(scope["series"]) != int(n_samples):
        fail(f"series has {len(scope['series'])} rows, expected {n_samples}")
    steps = scope["steps"]
    if list(steps["step"]) != list(range(1, int(n_steps) + 1)):
        fail(f"steps {list(steps['step'])}, expected 1..{n_steps}")
    if steps["measured_T"].isna().any():
        fail("a completed step has no measured_T")
    if not scope["power_W"].index.is_monotonic_increasing:
        fail("power readings are not in UTC order")
    if "power" not in scope["wide"].columns:
        fail(f"wide table columns {list(scope['wide'].columns)}")
    print(f"check_pandas_server: {len(scope['series'])} samples, {len(steps)} measured step(s)")


if __name__ == "__main__":
    main()
