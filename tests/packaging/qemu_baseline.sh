#!/usr/bin/env bash
# Runs tocdlab on an emulated Nehalem (x86-64-v2, no AVX) with qemu-user and checks that the
# answers agree with the same binary run natively: the baseline code runs on the oldest CPU
# the package supports, and the kernels' run-time dispatch (AVX-512/AVX2 here, the baseline
# clone under qemu) changes no physics.
#   qemu_baseline.sh TOCDLAB EXAMPLES_DIR quick|full
# quick (the dev test suite): mc and fe. full (the packaging stage): mc, fe and predict.
# Monte Carlo runs agree when |T_qemu - T_native| <= 3 sqrt(se_qemu^2 + se_native^2), the
# printed standard errors; the FE force when it agrees to 1e-6 relative (the clones round
# alike, only libm's own CPU variants may differ in the last bits).
set -euo pipefail
bin=$1 examples=$2 mode=$3
qemu=(qemu-x86_64 -cpu Nehalem)
if ! command -v qemu-x86_64 >/dev/null; then
  echo "qemu_baseline: qemu-x86_64 not found (apt-get install qemu-user)" >&2
  exit 1
fi
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"

# The first number after "KEY": in a JSON file.
json_number() { sed -n "s/^ *\"$1\": \([-0-9.eE+]*\),\{0,1\}\$/\1/p" "$2" | head -n 1; }

# run NAME ARGS...: native and emulated runs of `tocdlab ARGS... --json`, timed.
run() {
  local name=$1
  shift
  "$bin" "$@" --json >"$name.native.json"
  local t0=$SECONDS
  "${qemu[@]}" "$bin" "$@" --json >"$name.qemu.json"
  echo "qemu_baseline: $name under qemu -cpu Nehalem: $((SECONDS - t0)) s"
}

# mc_agrees NAME KEY: the Monte Carlo estimate KEY (with KEY_se) of both runs.
mc_agrees() {
  local n q ns qs
  n=$(json_number "$2" "$1.native.json") ns=$(json_number "$2_se" "$1.native.json")
  q=$(json_number "$2" "$1.qemu.json") qs=$(json_number "$2_se" "$1.qemu.json")
  awk -v n="$n" -v q="$q" -v ns="$ns" -v qs="$qs" -v name="$1" 'BEGIN {
    if (n == "" || q == "" || !(ns > 0)) { print "qemu_baseline: " name ": no estimate"; exit 1 }
    d = q - n; if (d < 0) d = -d
    lim = 3 * sqrt(ns * ns + qs * qs)
    printf "qemu_baseline: %s T native %.9g +- %.3g, qemu %.9g +- %.3g: |diff| %.3g <= %.3g%s\n",
           name, n, ns, q, qs, d, lim, (d == 0 ? " (bit-identical)" : "")
    exit !(d <= lim)
  }'
}

run mc -q mc --slab 10x10x2.5 --slab-cells 8 --optics "$examples/optics/skin-on-glass-633nm.toml" \
  --photons 2000 --threads 2
mc_agrees mc transmittance

run fe -q fe --displacement 0.25 --refine 0.3
n=$(json_number force_N fe.native.json) q=$(json_number force_N fe.qemu.json)
awk -v n="$n" -v q="$q" 'BEGIN {
  d = q - n; if (d < 0) d = -d
  printf "qemu_baseline: fe force native %.12g N, qemu %.12g N: relative diff %.3g <= 1e-6\n", n, q, d / n
  exit !(n > 0 && d <= 1e-6 * n)
}'

if [ "$mode" = full ]; then
  run predict -q predict --photons 1000 --threads 2 --displacement 0.3 --max-edge 2 --tip-edge 0.5
  mc_agrees predict T
fi
echo "qemu_baseline: ok"
