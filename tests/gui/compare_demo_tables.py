#!/usr/bin/env python3
"""The two demos measure one sample: the step tables of `tocdlab demo` and of
`tocdlab-gui --demo` (same seed, same default sample) must agree within their noise.

Usage: compare_demo_tables.py TOCDLAB CLI_DB GUI_DB

Runs `TOCDLAB -q demo --db CLI_DB --photons 2000 --clock-factor 2` (the window demo's photons
and seed; the window's demo recorded GUI_DB before), then compares the last run of each.

Per completed step, from each database's `measurements` view:
- measured T: the difference must lie within 4 combined standard errors of the two means
  (measured_T_se: SE of the mean power over the recording window / baseline) plus the
  clearing that the simulated sample does over one sampling interval of the meter (the two
  recording windows may start one 0.1 s meter reading apart; the sample clears by at most
  0.016 in 4 s, docs/demo.md, so 0.0004 per reading);
- load: within 4 combined standard errors plus 1 % (the load relaxes during the hold; the
  windows are the same in simulated time to within a reading);
- predicted T: within 4 combined Monte Carlo standard errors (predicted_T_se).
Four standard errors: over 7 steps x 3 quantities a false alarm has odds below 1e-3.
"""
import math
import sqlite3
import subprocess
import sys


def table(path):
    con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    rows = con.execute(
        "SELECT step, displacement_mm, load_N, measured_T, measured_T_se, predicted_T, predicted_T_se "
        "FROM measurements WHERE run_id = (SELECT max(run_id) FROM measurements) ORDER BY step").fetchall()
    con.close()
    return {r[0]: r[1:] for r in rows}


def main():
    tocdlab, cli_db, gui_db = sys.argv[1:4]
    # --no-identify: the window's demo does not identify; the step tables are what is compared.
    demo = [tocdlab, "-q", "demo", "--db", cli_db, "--photons", "2000", "--clock-factor", "2", "--no-identify"]
    done = subprocess.run(demo, stdout=subprocess.DEVNULL)
    if done.returncode != 0:
        print(f"compare_demo_tables: {' '.join(demo)} exited {done.returncode}", file=sys.stderr)
        return 1
    cli, gui = table(cli_db), table(gui_db)
    problems = []
    if sorted(cli) != sorted(gui) or len(cli) != 7:
        problems.append(f"steps differ: cli {sorted(cli)}, gui {sorted(gui)} (want 7 each)")
    for step in sorted(set(cli) & set(gui)):
        d1, load1, t1, se1, p1, pse1 = cli[step]
        d2, load2, t2, se2, p2, pse2 = gui[step]
        if None in (t1, t2, se1, se2, p1, p2, pse1, pse2, load1, load2):
            problems.append(f"step {step}: a value is missing (cli {cli[step]}, gui {gui[step]})")
            continue
        lines = [("measured T", t1, t2, 4 * math.hypot(se1, se2) + 4e-4),
                 ("predicted T", p1, p2, 4 * math.hypot(pse1, pse2)),
                 ("load (N)", load1, load2, 0.01 * max(abs(load1), abs(load2)) + 1e-4)]
        for name, a, b, limit in lines:
            verdict = "ok" if abs(a - b) <= limit else "DIFFERENT"
            print(f"step {step} ({d1:.3f} mm): {name}: cli {a:.5g}, gui {b:.5g}, |diff| {abs(a - b):.3g} "
                  f"<= {limit:.3g}: {verdict}")
            if verdict != "ok":
                problems.append(f"step {step}: {name} cli {a:.5g} vs gui {b:.5g} (limit {limit:.3g})")
    for p in problems:
        print("compare_demo_tables:", p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
