#!/usr/bin/env python3
"""Photons/s of the transport kernel, A/B: a base revision (A, e.g. the last landed main) against
the working tree (B), both built the same way (the `release` preset, the `mc_bench` and
`tocdlab` targets), run alternately (A B B A ...) on one machine in one go, so that the two
see the same load. Problems: the 2.5 mm skin slab of `mc_bench` (2 threads) and the composite
pin/skin/slide mesh of `tocdlab predict` at 1.5 mm (the paper preset, 2 threads). Prints, per
problem, each side's median and range and the ratio B/A of the medians, in wall-time photons/s
and (the slab) photons per CPU-second, which a shared machine disturbs less; whether the
composite's transmittance came out bit for bit the same on both sides, and their difference in
combined standard errors (a kernel that keeps each photon's random numbers and the tallies'
order gives the same bits unless its arithmetic rounds differently). docs/benchmarks.md.

  bench/mc/transport_ab.py --base REF [--rounds 3] [--slab-photons N] [--composite-photons N]
                           [--work build/ab] [--require RATIO]

Exit 1 when --require is given and a problem's wall-time ratio falls below it.
"""
import argparse
import json
import re
import shutil
import statistics
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
TARGETS = ["mc_bench", "tocdlab"]
# mc_bench's line for the skin slab at 2 threads; its rate in wall time and per CPU-second.
SLAB = re.compile(r"^\(a\) skin slab\s+tets\s+\d+ threads 2 .*?(\d+) photons/s .*?(\d+) photons per CPU-second")


def sh(cmd, cwd=None, quiet=False):
    print("$", " ".join(str(c) for c in cmd), file=sys.stderr)
    out = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE if quiet else sys.stderr, text=True)
    if out.returncode != 0:
        sys.exit(f"transport_ab: {' '.join(str(c) for c in cmd)} failed ({out.returncode})")
    return out.stdout


def source_of(base, work):
    """The base revision's files, unpacked from git (no checkout of the working tree moves)."""
    sha = sh(["git", "rev-parse", "--verify", f"{base}^{{commit}}"], cwd=REPO, quiet=True).strip()
    src = work / f"base-{sha[:12]}"
    if not (src / "CMakePresets.json").exists():
        shutil.rmtree(src, ignore_errors=True)
        src.mkdir(parents=True)
        with tempfile.TemporaryFile() as tar:
            subprocess.run(["git", "archive", "--format=tar", sha], cwd=REPO, stdout=tar, check=True)
            tar.seek(0)
            with tarfile.open(fileobj=tar) as t:
                t.extractall(src)
    return sha, src


def build(src):
    """The release preset's build of the two programs in the source's own build/release."""
    sh(["cmake", "--preset", "release"], cwd=src, quiet=True)
    sh(["cmake", "--build", "--preset", "release", "--target", *TARGETS], cwd=src)
    return src / "build" / "release" / "bin"


def slab(bin_dir, photons):
    text = sh([bin_dir / "mc_bench", "--photons", str(photons), "--threads", "2"], quiet=True)
    for line in text.splitlines():
        m = SLAB.match(line)
        if m:
            return float(m.group(1)), float(m.group(2))
    sys.exit(f"transport_ab: no 2-thread skin slab line in mc_bench's output:\n{text}")


def composite(bin_dir, photons):
    text = sh([bin_dir / "tocdlab", "-q", "predict", "--displacement", "1.5", "--mesh", "paper", "--photons",
               str(photons), "--threads", "2", "--json"], quiet=True)
    doc = json.loads(text)
    return doc["mc"]["photons_per_second"], (doc["T"], doc["T_se"])


def summary(name, a, b):
    ma, mb = statistics.median(a), statistics.median(b)
    print(f"{name:34s} A {ma:10.0f} [{min(a):.0f}, {max(a):.0f}]   B {mb:10.0f} [{min(b):.0f}, {max(b):.0f}]"
          f"   B/A {mb / ma:.3f}")
    return mb / ma


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", required=True, help="git revision of side A (e.g. origin/main)")
    ap.add_argument("--rounds", type=int, default=3, help="runs of each side per problem")
    ap.add_argument("--slab-photons", type=int, default=300000)
    ap.add_argument("--composite-photons", type=int, default=1000000)
    ap.add_argument("--work", type=Path, default=REPO / "build" / "ab", help="where side A is unpacked and built")
    ap.add_argument("--require", type=float, help="exit 1 when a wall-time ratio B/A is below this")
    a = ap.parse_args()
    if a.rounds < 1:
        sys.exit("transport_ab: --rounds must be at least 1")
    a.work.mkdir(parents=True, exist_ok=True)
    sha, src = source_of(a.base, a.work)
    bins = {"A": build(src), "B": build(REPO)}
    runs = {k: {"slab": [], "slab_cpu": [], "composite": [], "T": []} for k in bins}
    for r in range(a.rounds):
        for side in ("A", "B") if r % 2 == 0 else ("B", "A"):
            rate, cpu = slab(bins[side], a.slab_photons)
            runs[side]["slab"].append(rate)
            runs[side]["slab_cpu"].append(cpu)
            rate, t = composite(bins[side], a.composite_photons)
            runs[side]["composite"].append(rate)
            runs[side]["T"].append(t)
    print(f"A = {a.base} ({sha[:12]}), B = the working tree; {a.rounds} runs each, alternating; photons/s, median [range]")
    ratios = {
        "skin slab, 2 threads": summary("skin slab, 2 threads (wall)", runs["A"]["slab"], runs["B"]["slab"]),
        "composite 1.5 mm": summary("composite 1.5 mm, 2 threads (wall)", runs["A"]["composite"],
                                    runs["B"]["composite"]),
    }
    summary("skin slab, 2 threads (per CPU-s)", runs["A"]["slab_cpu"], runs["B"]["slab_cpu"])
    (ta, sa), (tb, sb) = runs["A"]["T"][0], runs["B"]["T"][0]
    same = len({t for t, _ in runs["A"]["T"] + runs["B"]["T"]}) == 1
    print(f"composite T: A {ta!r} +- {sa:.2g}, B {tb!r} +- {sb:.2g}: "
          f"{'the same bits in every run' if same else 'not the same bits'}; "
          f"B - A = {(tb - ta) / (sa * sa + sb * sb) ** 0.5:+.2f} combined SE")
    low = [k for k, v in ratios.items() if a.require is not None and v < a.require]
    if low:
        print(f"below the required {a.require}x: {', '.join(low)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
