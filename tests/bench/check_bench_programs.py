#!/usr/bin/env python3
"""Run every benchmark docs/benchmarks.md documents, briefly, and check what it prints.

Usage: check_bench_programs.py --source-dir SRC --bin-dir DIR --work-dir DIR

The page's table names each program and how to run it. Each is run here with small arguments
(seconds, not minutes) and its output is read back: the figures the page says it prints are
there and hold together (regions that add up to the mesh, no sample lost, the published law
fitting its own data best). How fast they are is never checked: a timed test on a loaded CI
machine fails for reasons that have nothing to do with the code, and a program whose exit
status is a verdict on speed (db_bench, tester_poll_bench) may say "below target" here.
The A/B scripts build another revision and run minutes of Monte Carlo: their --help is run
and must accept every option the page shows for them. A program the page names that is
neither built nor in bench/ fails the check, as does a built benchmark the page leaves out.

identify_bench records on the default simulated sample from the user's sample cache (ctest's
default_sample fixture prepares it), as the page's figure was measured.
"""

import argparse
import re
import shutil
import subprocess
import sys
from pathlib import Path

failures = []


def fail(program, why, output=""):
    tail = "\n".join(output.strip().splitlines()[-8:])
    failures.append(f"{program}: {why}" + (f"\n    last lines:\n    {tail}" if tail else ""))


def run(program, args, ok_exits=(0,), timeout=300, cwd=None):
    """stdout of `args`, or None (and a failure of `program`) on an exit status not in ok_exits."""
    p = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout,
                       cwd=cwd)
    if p.returncode not in ok_exits:
        fail(program, f"exit {p.returncode}", p.stderr)
        return None
    return p.stdout


def documented_rows(source):
    """(program, run-it cell) of every row of docs/benchmarks.md's table of programs."""
    rows = []
    for line in (source / "docs" / "benchmarks.md").read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 4 or not cells[0].startswith("`"):
            continue
        rows.append((cells[0].strip("`"), cells[2]))
    return rows


def numbers_after(label, text):
    return [float(x) for x in re.findall(re.escape(label) + r"\s*([-+0-9.eE]+)", text)]


def check_mc_bench(bin_dir, work):
    out = run("mc_bench", [str(bin_dir / "mc_bench"), "--photons", "2000", "--threads", "1"])
    if out is None:
        return
    lines = [l for l in out.splitlines() if l.startswith("(")]
    slab = any(l.startswith("(a) skin slab ") for l in lines)
    between = any(l.startswith("(b) air / skin / glass") for l in lines)
    if not slab or not between:
        return fail("mc_bench", "no line for the skin slab or the slab between air and glass", out)
    for l in lines:
        rate = numbers_after("photons", l)
        t, r, side = (numbers_after(k, l) for k in (" T", " R", "side"))
        if not rate or not t or not r or not side:
            return fail("mc_bench", f"a figure is missing: {l}")
        # Weights leave by the bottom, the top or the side: T + R + side is at most 1 (the rest is absorbed).
        if not (0 < t[0] < 1 and 0 < r[0] < 1 and 0 <= side[0] and t[0] + r[0] + side[0] <= 1 + 1e-9):
            return fail("mc_bench", f"T, R and side do not hold together: {l}")


def check_fe_bench(bin_dir, work):
    out = run("fe_bench", [str(bin_dir / "fe_bench")])
    if out is None:
        return
    ratio = numbers_after("plane stress / axisymmetric CPU time:", out)
    if not ratio or not ratio[0] > 0:
        return fail("fe_bench", "no CPU-time ratio of plane stress to axisymmetric", out)
    # The published case's load at 1.5 mm, reached in steps and straight: the same solution of
    # the same equilibrium, so the same force to the Newton tolerance (they printed 0.22788 and
    # 0.22786 N; 0.1 % allows the different load paths' last iterate).
    forces = [float(f) for f in re.findall(r"d = 1\.500 mm\s+F = ([0-9.]+) N", out)]
    if len(forces) < 3:
        return fail("fe_bench", "fewer than three forces at 1.5 mm", out)
    if abs(forces[0] - forces[1]) > 1e-3 * forces[0]:
        return fail("fe_bench", f"the 1.5 mm force in steps ({forces[0]}) and straight ({forces[1]}) differ",
                    out)


def check_geometry_bench(bin_dir, work):
    out = run("geometry_bench", [str(bin_dir / "geometry_bench"), "fast"])
    if out is None:
        return
    rows = [l.split() for l in out.splitlines() if l.startswith("fast ")]
    if len(rows) < 2:
        return fail("geometry_bench", "no rows for the fast preset", out)
    for r in rows:
        # preset, case words..., tets, pin, slide, air, skin, compressed, max |dV|/V, seconds
        tets, regions = int(r[-8]), [int(x) for x in r[-7:-2]]
        if tets <= 0 or sum(regions) != tets:
            return fail("geometry_bench", f"the regions' tets do not add up to the mesh's: {' '.join(r)}")


def check_db_bench(bin_dir, work):
    db = work / "db_bench.sqlite"
    # Exit 1: below the speed target, a verdict this check does not make.
    out = run("db_bench", [str(bin_dir / "db_bench"), "0.5", str(db)], ok_exits=(0, 1))
    if out is None:
        return
    for section in ("drain:", "sustained:", "acquisition shape"):
        if section not in out:
            return fail("db_bench", f"no '{section}' section", out)
    dropped = re.findall(r"dropped (\d+)", out)
    if len(dropped) < 3 or any(d != "0" for d in dropped):
        return fail("db_bench", "a sample was dropped (or a section printed no count)", out)
    expected = re.search(r"(\d+) expected, (\d+) in file", out)
    if not expected or expected.group(1) != expected.group(2):
        return fail("db_bench", "the acquisition-shaped load did not reach the file whole", out)
    if db.exists():
        return fail("db_bench", "left its database behind")


def check_tester_poll_bench(bin_dir, work):
    # Exit 1: below 1000 readings/s.
    out = run("tester_poll_bench", [str(bin_dir / "tester_poll_bench"), "0.3"], ok_exits=(0, 1))
    if out is None:
        return
    readings = numbers_after("readings", out)
    lat = [numbers_after(k, out) for k in ("p50", "p95", "p99", "max")]
    if not readings or readings[0] <= 0 or not all(lat):
        return fail("tester_poll_bench", "no readings or no latency percentiles", out)
    p = [x[0] for x in lat]
    if not all(a <= b for a, b in zip(p, p[1:])):
        return fail("tester_poll_bench", f"latency percentiles out of order: {p}", out)


def check_fit_bench(bin_dir, work):
    out = run("fit_bench", [str(bin_dir / "fit_bench"), "2000"])
    if out is None:
        return
    fits = re.findall(r"fit (\S+)\s+[0-9.]+ s\s+\(rms ([0-9.eE+-]+) MPa, R\^2 [0-9.]+, (\w+)\)", out)
    if len(fits) < 6 or any(state != "converged" for _, _, state in fits):
        return fail("fit_bench", "fewer than six models, or one not converged", out)
    # The rows are the published law (three Ogden terms) with 0.5 % noise: ogden3 fits them best.
    rms = {model: float(r) for model, r, _ in fits}
    if min(rms, key=rms.get) != "ogden3":
        return fail("fit_bench", f"ogden3 is not the best fit of its own law's rows: {rms}", out)


def check_identify_bench(bin_dir, work):
    out = run("identify_bench", [str(bin_dir / "identify_bench"), "1000", "2"], cwd=work, timeout=600)
    if out is None:
        return
    m = re.search(r"identify the demo run: ([0-9.]+) s in all .*optics: [0-9.]+ s, "
                  r"(\d+) Monte Carlo runs at 1000 photons", out)
    if not m or int(m.group(2)) <= 0:
        return fail("identify_bench", "no total time or no Monte Carlo runs at 1000 photons", out)


def check_poro_bench(bin_dir, work):
    out = run("poro_bench", [str(bin_dir / "poro_bench")], cwd=work)
    if out is None:
        return
    points = re.findall(r"t =\s*([0-9.]+) s\s+T = ([0-9.]+) \+- ([0-9.]+)\s+F = ([0-9.]+) N"
                        r"\s+water out ([-0-9.]+) mm3", out)
    if len(points) != 4:
        return fail("poro_bench", f"{len(points)} time points, not the 4 of a hold (0, 10, 30, 60 s)", out)
    force = [float(p[3]) for p in points]
    water = [float(p[4]) for p in points]
    if not all(0 < float(p[1]) < 1 for p in points):
        return fail("poro_bench", "a transmission outside (0, 1)", out)
    # A poroelastic hold at a fixed displacement: the pore pressure drains away, so the pin's
    # force falls and the water that has left only grows (Terzaghi's consolidation at a
    # fixed strain; docs/water.md).
    if not all(a > b for a, b in zip(force, force[1:])):
        return fail("poro_bench", f"the pin force does not relax during the hold: {force}", out)
    if not all(a < b for a, b in zip(water, water[1:])):
        return fail("poro_bench", f"the water out does not grow during the hold: {water}", out)


def check_strong_scaling(source, bin_dir, work):
    if not (bin_dir / "mpi_scaling_bench").exists() or not shutil.which("mpirun"):
        print("strong_scaling.sh: not run (no mpi_scaling_bench in this build, or no mpirun)")
        return
    script = source / "bench" / "parallel" / "strong_scaling.sh"
    out = run("strong_scaling.sh", ["bash", str(script), str(bin_dir.parent), "2", "20000"], cwd=work)
    if out is None:
        return
    if not re.search(r"strong scaling 1 -> 2 ranks: speed-up [0-9.]+, parallel efficiency [0-9.]+ %", out):
        return fail("strong_scaling.sh", "no speed-up and efficiency line", out)


def check_script_options(source, script, cell):
    """--help works and names every option the page shows for the script."""
    path = next(source.glob(f"bench/*/{script}"), None)
    if path is None:
        return fail(script, "not in bench/")
    out = run(f"{script} --help", [sys.executable, str(path), "--help"])
    if out is None:
        return
    for option in sorted(set(re.findall(r"--[a-z][a-z0-9-]*", cell))):
        if option not in out:
            fail(script, f"the page shows {option}, which its --help does not know", out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source-dir", required=True, type=Path)
    ap.add_argument("--bin-dir", required=True, type=Path)
    ap.add_argument("--work-dir", required=True, type=Path)
    a = ap.parse_args()
    a.source_dir, a.bin_dir, a.work_dir = (x.resolve() for x in (a.source_dir, a.bin_dir, a.work_dir))
    shutil.rmtree(a.work_dir, ignore_errors=True)
    a.work_dir.mkdir(parents=True)

    rows = documented_rows(a.source_dir)
    documented = {name for name, _ in rows}
    checks = {
        "mc_bench": check_mc_bench,
        "fe_bench": check_fe_bench,
        "geometry_bench": check_geometry_bench,
        "db_bench": check_db_bench,
        "tester_poll_bench": check_tester_poll_bench,
        "fit_bench": check_fit_bench,
        "identify_bench": check_identify_bench,
        "poro_bench": check_poro_bench,
    }
    for name, cell in rows:
        if name.endswith(".py"):
            check_script_options(a.source_dir, name, cell)
        elif name == "mpi_scaling_bench":
            check_strong_scaling(a.source_dir, a.bin_dir, a.work_dir)
        elif name in checks:
            if not (a.bin_dir / name).exists():
                fail(name, f"documented, not built in {a.bin_dir}")
            else:
                checks[name](a.bin_dir, a.work_dir)
        else:
            fail(name, "documented, but this check does not know how to run it")
    # Every built benchmark is on the page.
    for exe in sorted(a.bin_dir.glob("*_bench")):
        if exe.name not in documented:
            fail(exe.name, "built, but docs/benchmarks.md does not list it")
    if failures:
        print("\n".join(failures))
        print(f"{len(failures)} problem(s) with the documented benchmarks")
        return 1
    print(f"every documented benchmark ran as docs/benchmarks.md says ({len(rows)} programs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
