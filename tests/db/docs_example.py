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
