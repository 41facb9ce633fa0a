#!/usr/bin/env bash
# The ASAT scene's cascade at the default step against a step four times
# finer (docs/benchmarks.md, "Convergence of the ASAT cascade"): for seeds
# 1 to SEEDS, the time at which `scenarios/asat.ron` first has 10 000 bodies
# or more, at dt = 1 and at dt = 1/4 (its interceptor fired at the same
# time, update 100 and update 400). Each run is capped at 10 200 bodies
# (`max_bodies`): a shatter is refused only past 10 102, so the run is the
# uncapped one until it passes 10 000, and it stays cheap after. The two
# steps of a seed run side by side, one thread each. Prints each seed and
# the medians; about 10 minutes for 8 seeds on 2 cores.
#   bash benches/asat_convergence.sh [KESSLER] [SEEDS]
set -euo pipefail
kessler="${1:-target/release/kessler}"
seeds="${2:-8}"
root="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"
# An interrupted run (Ctrl-C, a kill) leaves no simulation behind: the run
# in the background ignores Ctrl-C, so the exit stops it.
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT
trap 'exit 130' INT TERM
# asat.ron for SEED at step DT, its interceptor at update FIRE, in FILE.
edited() {
    local seed=$1 dt=$2 fire=$3 file=$4
    sed -e "s/seed: 1,/seed: $seed, max_bodies: 10200,/" -e "s/time_step: 1.0,/time_step: $dt,/" \
        -e "s/Fire(update: 100,/Fire(update: $fire,/" "$root/scenarios/asat.ron" >"$file"
    for made in "max_bodies: 10200" "time_step: $dt," "Fire(update: $fire,"; do
        if ! grep -qF "$made" "$file"; then
            echo "scenarios/asat.ron no longer reads as this script expects (no \`$made\` after the edit)" >&2
            return 2
        fi
    done
}
# The time (update × dt) of the first timeline row with 10 000 bodies or
# more, "never" if none, for SEED at step DT, its interceptor at FIRE,
# over STEPS updates with a row every EVERY.
passes() {
    local seed=$1 dt=$2 fire=$3 steps=$4 every=$5
    local file="$work/s${seed}_dt${dt}"
    edited "$seed" "$dt" "$fire" "$file.ron"
    # (Its progress bar, which would cross the other run's, kept for an error.)
    "$kessler" headless "$file.ron" --steps "$steps" --timeline "$file.csv" --every "$every" \
        --mode sequential >/dev/null 2>"$file.err" || { tail -n 1 "$file.err" >&2; return 1; }
    awk -F, -v dt="$dt" 'NR > 1 && $2 >= 10000 { print $1 * dt; found = 1; exit }
        END { if (!found) print "never" }' "$file.csv" >"$file.time"
}
# The edits first, once, so that a changed scenario says so in one line.
edited 1 1.0 100 "$work/check.ron" && edited 1 0.25 400 "$work/check.ron" || exit 2
echo "seed,dt_1,dt_1/4"
for seed in $(seq "$seeds"); do
    passes "$seed" 1.0 100 20000 1 &
    coarse=$!
    passes "$seed" 0.25 400 80000 4
    wait "$coarse"
    echo "$seed,$(cat "$work/s${seed}_dt1.0.time"),$(cat "$work/s${seed}_dt0.25.time")" | tee -a "$work/table.csv"
done
awk -F, '{ a[NR] = $2; b[NR] = $3; if ($2 == "never" || $3 == "never") never++ }
    function median(v, k, i, j, t, s) {
        k = 0; for (i in v) s[++k] = v[i]
        for (i = 1; i <= k; i++) for (j = i + 1; j <= k; j++) if (s[j] < s[i]) { t = s[i]; s[i] = s[j]; s[j] = t }
        return k % 2 ? s[(k + 1) / 2] : (s[k / 2] + s[k / 2 + 1]) / 2
    }
    END {
        if (never) { print "a run never passed 10 000 bodies: no median"; exit 1 }
        ma = median(a); mb = median(b); printf "median,%s,%s\nratio,%.3f\n", ma, mb, ma / mb
    }' "$work/table.csv"
