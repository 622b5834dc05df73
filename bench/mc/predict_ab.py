#!/usr/bin/env python3
"""One `tocdlab predict` step, A/B: the set-up share and the transmission of a base revision (A)
against the working tree (B), both built as bench/mc/transport_ab.py builds them (or side A
given as a program already built, --a-bin).

Set-up share: `predict --displacement 1.25 --photons 1000000 --json`, run alternately (A B B A
...), with share = (FE + mesh + preparation) / Monte Carlo seconds from the output's own timers.

Equivalence (--steps): T and the side loss at every step of the demo protocol (0 to 1.5 mm in
seven steps, 2.5 mm skin) and the glass-only baseline, under the threshold and the graded
optics, at --eq-photons photons, A with seed 11 and B with seed 12: independent estimates, so
that their difference over the combined standard error is what a change of geometry or mesh
may move. Prints each difference in combined standard errors and the count beyond 2.

  bench/mc/predict_ab.py (--base REF | --a-bin PATH) [--rounds 3] [--steps] [--eq-photons N]
"""
import argparse
import json
import statistics
import sys
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import transport_ab  # noqa: E402  (its command runner, and its unpacking and building of a revision)



def demo_steps_mm():
    """The demo protocol's displacements: a list, or an even range {from, to, count}."""
    with open(transport_ab.REPO / "protocols" / "demo.toml", "rb") as f:
        d = tomllib.load(f)["steps"]["displacements_mm"]
    if isinstance(d, list):
        return [float(x) for x in d]
    n = int(d["count"])
    return [d["from"] + (d["to"] - d["from"]) * k / (n - 1) for k in range(n)]


def predict(binary, *args):
    cmd = [binary, "-q", "predict", "--threads", "2", "--json", *args]
    return json.loads(transport_ab.sh([str(c) for c in cmd], quiet=True))


def share_run(binary):
    d = predict(binary, "--displacement", "1.25", "--photons", "1000000")
    m = d["mesh_stats"]
    setup = d["fe_seconds"] + m["mesh_seconds"] + m["prepare_seconds"]
    return {"share": setup / d["mc_seconds"], "setup": setup, "mc": d["mc_seconds"], "T": d["T"],
            "T_se": d["T_se"], "tets": m["tets"]}


def cases():
    yield "glass only", ["--baseline"]
    for optics in ("threshold", "graded"):
        for d in demo_steps_mm():
            yield f"{optics} {d:.2f} mm", ["--optics", optics, "--displacement", d]


def z(a, b, key):
    return (b[key] - a[key]) / (a[key + "_se"] ** 2 + b[key + "_se"] ** 2) ** 0.5


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    side_a = ap.add_mutually_exclusive_group(required=True)
    side_a.add_argument("--base", help="git revision of side A, unpacked and built under --work")
    side_a.add_argument("--a-bin", type=Path, help="side A's tocdlab, already built")
    ap.add_argument("--b-bin", type=Path, help="side B's tocdlab (default: the working tree's release build, built first)")
    ap.add_argument("--rounds", type=int, default=3, help="set-up share runs of each side")
    ap.add_argument("--steps", action="store_true", help="also compare T and side loss at every demo step")
    ap.add_argument("--eq-photons", type=int, default=1000000)
    ap.add_argument("--work", type=Path, default=transport_ab.REPO / "build" / "ab")
    a = ap.parse_args()
    if a.rounds < 1:
        sys.exit("predict_ab: --rounds must be at least 1")
    if a.base:
        a.work.mkdir(parents=True, exist_ok=True)
        _, src = transport_ab.source_of(a.base, a.work)
        a.a_bin = transport_ab.build(src) / "tocdlab"
    if a.b_bin is None:
        a.b_bin = transport_ab.build(transport_ab.REPO) / "tocdlab"
    bins = {"A": a.a_bin, "B": a.b_bin}
    runs = {"A": [], "B": []}
    for r in range(a.rounds):
        for side in ("A", "B") if r % 2 == 0 else ("B", "A"):
            runs[side].append(share_run(bins[side]))
            x = runs[side][-1]
            print(f"{side}: set-up {x['setup']:.2f} s, Monte Carlo {x['mc']:.2f} s, share {100 * x['share']:.1f} %, "
                  f"T {x['T']:.5f} +- {x['T_se']:.5f}, {x['tets']} tets", file=sys.stderr)
    for side in ("A", "B"):
        s = [100 * x["share"] for x in runs[side]]
        print(f"{side}: set-up share median {statistics.median(s):.1f} % [{min(s):.1f}, {max(s):.1f}], "
              f"tets {runs[side][0]['tets']}, T {runs[side][0]['T']:.5f} +- {runs[side][0]['T_se']:.5f}")
    if not a.steps:
        return 0
    beyond = 0
    total = 0
    print(f"{'case':22s} {'T A':>9s} {'T B':>9s} {'z(T)':>6s} {'side A':>8s} {'side B':>8s} {'z(side)':>7s}")
    for name, args in cases():
        ra = predict(bins["A"], *args, "--photons", a.eq_photons, "--seed", 11)
        rb = predict(bins["B"], *args, "--photons", a.eq_photons, "--seed", 12)
        zt, zs = z(ra, rb, "T"), z(ra, rb, "side_loss")
        beyond += (abs(zt) > 2) + (abs(zs) > 2)
        total += 2
        print(f"{name:22s} {ra['T']:9.5f} {rb['T']:9.5f} {zt:+6.2f} {ra['side_loss']:8.5f} {rb['side_loss']:8.5f} "
              f"{zs:+7.2f}", flush=True)
    print(f"{beyond} of {total} differences beyond 2 combined standard errors "
          f"(about {0.0455 * total:.1f} expected by chance alone)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
