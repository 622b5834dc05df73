#!/usr/bin/env bash
# Strong scaling of the Monte Carlo from 1 to N ranks (default 2), one thread per rank:
#   bench/parallel/strong_scaling.sh [BUILD_DIR] [RANKS] [PHOTONS]
# Prints each run's figures and the parallel efficiency t1 / (N tN).
set -euo pipefail
build=${1:-build/dev}
ranks=${2:-2}
photons=${3:-1000000}
bench="$build/bin/mpi_scaling_bench"
[ -x "$bench" ] || { echo "strong_scaling: $bench not built (configure with -DTOCD_WITH_MPI=ON)" >&2; exit 2; }
root=()
if [ "$(id -u)" -eq 0 ]; then root=(--allow-run-as-root); fi
export OMPI_MCA_btl_vader_single_copy_mechanism=none
wall() { grep -o 'wall [0-9.]*' <<<"$1" | cut -d' ' -f2; }
one=$(mpirun "${root[@]}" -n 1 --bind-to core "$bench" --photons "$photons" --threads 1)
echo "$one"
many=$(mpirun "${root[@]}" -n "$ranks" --bind-to core "$bench" --photons "$photons" --threads 1)
echo "$many"
awk -v t1="$(wall "$one")" -v tn="$(wall "$many")" -v n="$ranks" \
  'BEGIN { printf "strong scaling 1 -> %d ranks: speed-up %.3f, parallel efficiency %.1f %%\n", n, t1 / tn, 100 * t1 / (n * tn) }'
