"""What the pandas checks of docs/database.md share: the example they run, and how they fail.

The checks (check_pandas_views.py, check_pandas_server.py) import this from their own folder.
"""
import os
import re
import sys


def fail(message):
    """Exits 1 with `message` on stderr, named by the check that runs."""
    check = os.path.splitext(os.path.basename(sys.argv[0]))[0]
    print(f"{check}: {message}", file=sys.stderr)
    sys.exit(1)


def run_example(markdown_path, marker, scope):
    """Runs the python block after <!-- marker --> in the markdown file, as written, in `scope`."""
    text = open(markdown_path, encoding="utf-8").read()
    m = re.search(rf"<!-- {re.escape(marker)} -->\s*```python\n(.*?)```", text, re.S)
    if not m:
        fail(f"{markdown_path}: no python block after <!-- {marker} -->")
    exec(compile(m.group(1), markdown_path, "exec"), scope)
    return scope


def check_tables(scope, n_steps, measured_column):
    """The example's tables as both checks expect them: `power_W` in UTC order, `steps` numbered
    1..n_steps with `measured_column` given for each, and `wide` with a power column."""
    if not scope["power_W"].index.is_monotonic_increasing:
        fail("power readings are not in UTC order")
    steps = scope["steps"]
    if list(steps["step"]) != list(range(1, n_steps + 1)):
        fail(f"steps {list(steps['step'])}, expected 1..{n_steps}")
    if steps[measured_column].isna().any():
        fail(f"a completed step has no {measured_column}")
    if "power" not in scope["wide"].columns:
        fail(f"wide table columns {list(scope['wide'].columns)}")
