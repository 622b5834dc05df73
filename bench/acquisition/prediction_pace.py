#!/usr/bin/env python3
"""Whether a recording's predictions keep pace with the rig: runs `tocdlab demo` at clock
factor 1 (real time, default photons) and prints, per step, how long after its recording
ended its prediction was stored, and how much earlier than the next step's recording end
(the margin; negative: the prediction was late). Also the stage times the prediction stored
(FE, mesh, Monte Carlo) and the fewest readings a recording window held, as a share of what
the protocol asks. docs/benchmarks.md.

  bench/acquisition/prediction_pace.py [--tocdlab build/release/bin/tocdlab] [demo options...]
"""
import argparse
import sqlite3
import subprocess
import sys
import tempfile
from pathlib import Path

# A step's prediction is stored at created_utc_ns (wall clock); the step's times are on the
# run's monotonic clock, which the run's anchor ties to the wall clock (clock factor 1).
PACE = """
SELECT s.step_index + 1, s.target_displacement_mm,
       (p.created_utc_ns - r.wall_anchor_utc_ns + r.monotonic_anchor_ns - s.recorded_to_t_ns) / 1e9,
       (LEAD(s.recorded_to_t_ns) OVER (ORDER BY s.step_index)
        - (p.created_utc_ns - r.wall_anchor_utc_ns + r.monotonic_anchor_ns)) / 1e9,
       p.fe_seconds, p.mesh_seconds, p.mc_seconds
FROM steps s JOIN runs r ON r.id = s.run_id
LEFT JOIN predictions p ON p.run_id = s.run_id AND p.step_index = s.step_index
WHERE s.run_id = 1 ORDER BY s.step_index
"""

# The fewest readings a recording window held, over every channel with a nominal rate, as a
# share of rate x window.
READINGS = """
SELECT MIN(st.n / (c.nominal_rate_Hz * (s.recorded_to_t_ns - s.recorded_from_t_ns) / 1e9))
FROM steps s JOIN step_channel_stats st ON st.step_id = s.id JOIN channels c ON c.id = st.channel_id
WHERE s.run_id = 1 AND c.nominal_rate_Hz > 0
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tocdlab", default="build/release/bin/tocdlab")
    a, demo_args = ap.parse_known_args()
    with tempfile.TemporaryDirectory() as work:
        db = Path(work) / "pace.db"
        cmd = [a.tocdlab, "demo", "--db", str(db), "--clock-factor", "1", "--no-identify", *demo_args]
        print("running:", " ".join(cmd), file=sys.stderr)
        done = subprocess.run(cmd, stdout=subprocess.DEVNULL)
        if done.returncode != 0:
            sys.exit(f"prediction_pace: tocdlab demo failed ({done.returncode})")
        con = sqlite3.connect(db)
        rows = con.execute(PACE).fetchall()
        fewest = con.execute(READINGS).fetchone()[0]
    print("step  d_mm   stored_after_s  margin_s   fe_s  mesh_s    mc_s")
    late = 0
    for step, d, after, margin, fe, mesh, mc in rows:
        if after is None:
            print(f"{step:4d}  {d:4.2f}   no prediction")
            late += 1
            continue
        late += margin is not None and margin < 0
        m = f"{margin:8.2f}" if margin is not None else "    last"
        print(f"{step:4d}  {d:4.2f}   {after:14.2f}  {m}  {fe:5.2f}  {mesh:6.2f}  {mc:6.2f}")
    print(f"steps whose prediction was stored after the next step's recording ended: {late}")
    print(f"fewest readings in a recording window: {fewest:.4f} of the protocol's rate x window")
    return 1 if late else 0


if __name__ == "__main__":
    sys.exit(main())
