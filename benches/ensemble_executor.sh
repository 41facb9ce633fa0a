#!/usr/bin/env bash
# The local executor against its ideal (docs/benchmarks.md, "Ensembles"):
# 16 one-thread members of the cascade scene run by `kessler ensemble` on
# this machine's hardware threads, against the ideal, one member's time
# alone × 16 ÷ hardware threads. Interleaved: the ensemble, then one of its
# members run again alone, ROUNDS times; prints each round and the median
# ratio.
#   bash benches/ensemble_executor.sh [KESSLER] [ROUNDS]
set -euo pipefail
kessler="${1:-target/release/kessler}"
rounds="${2:-3}"
threads="$(nproc)"
root="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cat >"$work/e.ron" <<RON
Ensemble(scenario: "$root/scenarios/cascade.ron", steps: 4000, every: 100, members: 16, seed: 3, threads: 1)
RON
now() { date +%s.%N; }
ratios=()
for round in $(seq "$rounds"); do
    start="$(now)"
    "$kessler" ensemble "$work/e.ron" --out "$work/run$round" >/dev/null 2>&1
    all="$(awk -v a="$start" -v b="$(now)" 'BEGIN { print b - a }')"
    # Member 0 again, alone: from its process's start to its exit.
    start="$(now)"
    "$kessler" ensemble member "$work/run$round" 0 >/dev/null
    lone="$(awk -v a="$start" -v b="$(now)" 'BEGIN { print b - a }')"
    ratio="$(awk -v all="$all" -v lone="$lone" -v t="$threads" 'BEGIN { print all / (lone * 16 / t) }')"
    ratios+=("$ratio")
    awk -v r="$round" -v all="$all" -v lone="$lone" -v t="$threads" -v q="$ratio" 'BEGIN {
        printf "round %d: 16 members on %d threads %.3f s; one member alone %.3f s; ideal %.3f s; ratio %.3f\n", r, t, all, lone, lone * 16 / t, q }'
done
printf '%s\n' "${ratios[@]}" | sort -g | awk '{ a[NR] = $1 } END { printf "median ratio: %.3f\n", a[int((NR + 1) / 2)] }'
