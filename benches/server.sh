#!/usr/bin/env bash
# Measures on a server (many cores, perhaps a GPU, no display) what a
# 2-core machine cannot show (docs/benchmarks.md, "A server: 16 threads
# and an H200", was measured so):
#
#   threads  the core-count axis, up to every hardware thread (threads.ron)
#   pool     Kessler's pool beside Bevy's on every hardware thread
#            (pool.ron with its thread count raised)
#   render   the thesis's Tables 1-3, drawn offscreen (render.ron)
#   frames   its Table 5, drawn offscreen (frames.ron)
#
# usage: benches/server.sh KESSLER OUT_DIR [PART...]
#
# KESSLER is a release build with the window (`cargo build --release`);
# OUT_DIR must not exist yet. The configs that ran are written into
# OUT_DIR/configs: the shipped ones with `offscreen: true` on every drawing
# run (so no X server is needed) and pool's threads set to the machine's.
# The split calibration is made first, for this machine's thread count,
# under OUT_DIR/config (the user's own is left alone). Each part runs
# under its own time limit (PART_LIMIT seconds, default 900); one that
# fails or runs out does not stop the next, and the script then exits 1
# naming it. The logs are OUT_DIR/*.log.
set -u -o pipefail
usage="usage: benches/server.sh KESSLER OUT_DIR [PART...]  (PART: threads pool render frames)"
kessler=${1:?$usage}
given=$kessler
out=${2:?$usage}
shift 2
parts=${*:-threads pool render frames}
limit=${PART_LIMIT:-900}
benches=$(cd "$(dirname "$0")" && pwd)
scenarios=$(dirname "$benches")/scenarios

# KESSLER: a path, or a command on PATH.
if [ ! -x "$kessler" ]; then
    kessler=$(command -v "$kessler") || { echo "benches/server.sh: $given is not a program" >&2; exit 2; }
fi
kessler=$(realpath "$kessler")
for part in $parts; do
    case $part in
        threads | pool | render | frames) ;;
        *) echo "benches/server.sh: unknown part $part; $usage" >&2; exit 2 ;;
    esac
done
if [ -e "$out" ]; then
    echo "benches/server.sh: $out exists; give a new folder" >&2
    exit 2
fi
mkdir -p "$out/configs" "$out/config"
out=$(realpath "$out")
export XDG_CONFIG_HOME="$out/config"
threads=$(nproc)

# A shipped config made to run from OUT_DIR/configs: its scenario path made
# absolute (escaped for sed), then the edit given.
derive() {
    local to
    to=$(printf '%s' "$scenarios/" | sed 's/[\\|&]/\\&/g')
    sed -e "s|\"\\.\\./scenarios/|\"$to|" -e "$2" "$benches/$1.ron" >"$out/configs/$1.ron"
}
offscreen='/offscreen:/!s/method: \([A-Za-z]*\)/method: \1, offscreen: true/'
derive threads ''
derive pool "s/threads: [0-9]*/threads: $threads/"
derive render "$offscreen"
derive frames "$offscreen"

echo "== calibrate on $threads threads $(date -u +%T)"
if ! "$kessler" calibrate 2>&1 | tee "$out/calibrate.log"; then
    echo "benches/server.sh: the calibration failed (see $out/calibrate.log)" >&2
    exit 1
fi
failed=""
for part in $parts; do
    echo "== $part $(date -u +%T)"
    timeout "$limit" "$kessler" bench "$out/configs/$part.ron" --out "$out/$part.csv" \
        >"$out/$part.log" 2>&1
    status=$?
    echo "   exit $status $(date -u +%T); last lines:"
    tail -n 3 "$out/$part.log"
    [ "$status" -eq 0 ] || failed="$failed $part"
done
if [ -n "$failed" ]; then
    echo "benches/server.sh: failed or ran out of time:$failed (their logs are in $out)" >&2
    exit 1
fi
