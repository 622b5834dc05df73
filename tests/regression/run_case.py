#!/usr/bin/env python3
"""Run one regression case of tests/regression/ and compare its output with the stored reference.

Usage:
  run_case.py --tocdlab EXE --case-dir tests/regression/<case> --work-dir DIR

A case is a folder with
  case.json       what to run and how to compare (below);
  reference.json  the output as the code produced it when the reference was stored, less the
                  values the case ignores;
  README.md       what the case pins and why its tolerances are what they are;
  and any input files the command reads (named relative to the case folder).

case.json:
  {
    "args": ["predict", "--displacement", "0.75", ..., "--json"],
    "copy": {"sample-cache": "cache"},
    "runs": [{"args_extra": ["--threads", "1"]}, {"args_extra": ["--threads", "2"]}],
    "rules": [
      {"path": "*.seconds", "ignore": true},
      {"path": "compare.steps.*.load_N", "rel": 0.05, "abs": 0.002},
      ...
    ]
  }
  In "args", "{case}" stands for the case folder and "{work}" for the run's work directory (the
  command's current directory). "copy" copies files or folders of the case folder into each
  run's work directory before the run (case path: work path). Every
  entry of "runs" (default: one run with no extra arguments) is run and compared with the one
  reference: a case that lists two thread counts proves its answer does not depend on them.
  Standard output must be one JSON document.

Comparison: values are addressed by dotted paths ("compare.steps.3.load_N": list entries by
their index); a rule's "path" is a glob over that path (fnmatch: "*" also crosses dots). The
first rule that matches a value decides: "ignore" drops it (from the output and from the
reference); "abs" and/or "rel" accept |out - ref| <= max(abs, rel * |ref|) for numbers;
"factor" accepts a positive number within that factor of a positive reference either way
(ref / factor <= out <= ref * factor: for scale statistics such as a standard error, whose
uncertainty is a fraction of itself in both directions); with
no rule a value must be equal, numbers bit for bit (the JSON writer prints the shortest text
that reads back as the same double, so equal text is equal bits). Keys present on one side
only, list lengths and types must match too.

Updating the references: with TOCD_REGRESSION_UPDATE=1 in the environment the first run's
output (less the ignored values) is written to reference.json instead of being compared, and
the test passes; the other runs are still compared with it (docs/building.md, "Regression
cases").
"""

import argparse
import fnmatch
import json
import math
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path


def walk(value, path=""):
    """Yields (path, value) of every leaf of a JSON value."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield from walk(v, f"{path}.{k}" if path else str(k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from walk(v, f"{path}.{i}" if path else str(i))
    else:
        yield path, value


def rule_for(path, rules):
    for r in rules:
        if fnmatch.fnmatchcase(path, r["path"]):
            return r
    return None


def strip_ignored(value, rules, path=""):
    """The value less every entry an "ignore" rule matches."""
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            p = f"{path}.{k}" if path else str(k)
            r = rule_for(p, rules)
            if r and r.get("ignore"):
                continue
            out[k] = strip_ignored(v, rules, p)
        return out
    if isinstance(value, list):
        return [strip_ignored(v, rules, f"{path}.{i}" if path else str(i)) for i, v in enumerate(value)]
    return value


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def compare(out, ref, rules, path="", problems=None):
    """Appends to `problems` one line per difference; returns the list."""
    if problems is None:
        problems = []
    where = path or "(document)"
    if isinstance(ref, dict) and isinstance(out, dict):
        for k in ref:
            p = f"{path}.{k}" if path else str(k)
            if k not in out:
                problems.append(f"{p}: missing from the output")
            else:
                compare(out[k], ref[k], rules, p, problems)
        for k in out:
            if k not in ref:
                p = f"{path}.{k}" if path else str(k)
                problems.append(f"{p}: not in the reference (value {json.dumps(out[k])[:80]})")
        return problems
    if isinstance(ref, list) and isinstance(out, list):
        if len(ref) != len(out):
            problems.append(f"{where}: {len(out)} entries, the reference has {len(ref)}")
        for i, (o, r) in enumerate(zip(out, ref)):
            compare(o, r, rules, f"{path}.{i}" if path else str(i), problems)
        return problems
    if is_number(ref) and is_number(out):
        rule = rule_for(path, rules)
        if out == ref:
            return problems
        if rule and "factor" in rule:
            f = rule["factor"]
            if ref > 0 and math.isfinite(out) and ref / f <= out <= ref * f:
                return problems
            problems.append(f"{path}: {out!r}, reference {ref!r} (not within a factor {f:g} of it)")
        elif rule and ("abs" in rule or "rel" in rule):
            tol = max(rule.get("abs", 0.0), rule.get("rel", 0.0) * abs(ref))
            if math.isfinite(out) and abs(out - ref) <= tol:
                return problems
            problems.append(f"{path}: {out!r}, reference {ref!r} (|difference| {abs(out - ref):.3g} > "
                            f"tolerance {tol:.3g})")
        else:
            problems.append(f"{path}: {out!r}, reference {ref!r} (must be equal bit for bit)")
        return problems
    if out != ref:
        problems.append(f"{where}: {json.dumps(out)[:80]}, reference {json.dumps(ref)[:80]}")
    return problems


def substitute(args, case_dir, work_dir):
    return [a.replace("{case}", str(case_dir)).replace("{work}", str(work_dir)) for a in args]


def run_once(exe, args, work_dir):
    t0 = time.monotonic()
    p = subprocess.run([exe, *args], cwd=work_dir, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True)
    seconds = time.monotonic() - t0
    if p.returncode != 0:
        sys.stderr.write(p.stderr[-4000:])
        raise SystemExit(f"tocdlab {' '.join(args)}: exit status {p.returncode}")
    try:
        return json.loads(p.stdout), seconds
    except json.JSONDecodeError as e:
        sys.stderr.write(p.stdout[-2000:])
        raise SystemExit(f"tocdlab {' '.join(args)}: standard output is not one JSON document ({e})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tocdlab", required=True)
    ap.add_argument("--case-dir", required=True, type=Path)
    ap.add_argument("--work-dir", required=True, type=Path)
    a = ap.parse_args()

    case = json.loads((a.case_dir / "case.json").read_text())
    rules = case.get("rules", [])
    reference_path = a.case_dir / "reference.json"
    update = os.environ.get("TOCD_REGRESSION_UPDATE", "") not in ("", "0")

    if a.work_dir.exists():
        shutil.rmtree(a.work_dir)
    a.work_dir.mkdir(parents=True)

    reference = None
    if not update:
        if not reference_path.exists():
            raise SystemExit(f"{reference_path}: no reference (TOCD_REGRESSION_UPDATE=1 writes it)")
        reference = json.loads(reference_path.read_text())

    failed = False
    for k, run in enumerate(case.get("runs", [{}])):
        run_dir = a.work_dir / f"run{k}"
        run_dir.mkdir()
        for src, dst in case.get("copy", {}).items():
            if (a.case_dir / src).is_dir():
                shutil.copytree(a.case_dir / src, run_dir / dst)
            else:
                shutil.copy2(a.case_dir / src, run_dir / dst)
        args = substitute(case["args"] + run.get("args_extra", []), a.case_dir.resolve(), run_dir)
        out, seconds = run_once(a.tocdlab, args, run_dir)
        out = strip_ignored(out, rules)
        label = " ".join(run.get("args_extra", [])) or "as stored"
        if reference is None:
            reference_path.write_text(json.dumps(out, indent=2, sort_keys=True) + "\n")
            reference = out
            print(f"run {k} ({label}, {seconds:.1f} s): wrote {reference_path}")
            continue
        problems = compare(out, reference, rules)
        if problems:
            failed = True
            print(f"run {k} ({label}, {seconds:.1f} s): {len(problems)} difference(s) from {reference_path}:")
            for line in problems[:40]:
                print(f"  {line}")
            if len(problems) > 40:
                print(f"  ... and {len(problems) - 40} more")
        else:
            print(f"run {k} ({label}, {seconds:.1f} s): matches {reference_path.name}")
    if failed:
        print("If the change is intended, rewrite the references with TOCD_REGRESSION_UPDATE=1 "
              "(docs/building.md, \"Regression cases\") and say why in the commit.")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
