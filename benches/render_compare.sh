#!/usr/bin/env bash
# Frame time of the two drawing methods over body counts (the thesis
# compared drawing each cube on its own against instancing).
#
#   benches/render_compare.sh [OUT.csv] [COUNTS...]
#
# Runs `kessler run --paused --frames 120` per method and count, so only
# rendering is measured (the simulation is paused), and writes
# `method,bodies,frames,mean_ms,median_ms,p95_ms`. Without a display it runs
# under xvfb-run (Mesa's software Vulkan); set KESSLER to choose the binary
# (default: target/release/kessler, built if missing).
set -euo pipefail
cd "$(dirname "$0")/.."

out="${1:-render-compare.csv}"
shift || true
counts=("$@")
if [ ${#counts[@]} -eq 0 ]; then counts=(1000 10000 100000); fi
if [ -e "$out" ]; then
    echo "render_compare: $out already exists; choose another name" >&2
    exit 2
fi

bin="${KESSLER:-target/release/kessler}"
if [ ! -x "$bin" ]; then cargo build --release; fi
wrap=()
if [ -z "${DISPLAY:-}" ]; then wrap=(xvfb-run -a -s "-screen 0 1280x800x24"); fi
settings="$(mktemp -d)/settings.ron"
echo "()" > "$settings"

echo "method,bodies,frames,mean_ms,median_ms,p95_ms" > "$out"
for count in "${counts[@]}"; do
    for method in instanced meshes; do
        line=$("${wrap[@]}" "$bin" run --paused --frames 120 --render "$method" --bodies "$count" \
            --settings "$settings" 2>/dev/null | grep '^frames ')
        # frames 110 (after 10 warm-up), bodies N, render M: mean A ms, median B ms, p95 C ms (F FPS); U updates (R per second)
        frames=$(sed -E 's/^frames ([0-9]+).*/\1/' <<<"$line")
        mean=$(sed -E 's/.*mean ([0-9.]+) ms.*/\1/' <<<"$line")
        median=$(sed -E 's/.*median ([0-9.]+) ms.*/\1/' <<<"$line")
        p95=$(sed -E 's/.*p95 ([0-9.]+) ms.*/\1/' <<<"$line")
        echo "$method,$count,$frames,$mean,$median,$p95" | tee -a "$out"
    done
done
