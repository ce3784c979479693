#!/usr/bin/env bash
# bench/preview.sh — what does the preview window cost the render? Under a virtual X server (Xvfb, which then
# draws the window on the same cores), runs one render alternately without and with --preview, and prints the
# median of the per-pair ratios of the render loop's Mrays/s (with over without: 0.97 means the window cost
# 3 %). The window converts a frame at most every 0.2 s and for at most ~2 % of one core; Xvfb's drawing is
# counted too. Single pairs scatter by several percent on a shared machine: use tens of pairs.
#
# usage: bash bench/preview.sh [GLINT_BINARY] [PAIRS] [-- GLINT ARGS]
#   default: build/glint, 15 pairs, scenes/rtiow-final.json at 640x360, 16 spp, all threads
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
GLINT=$ROOT/build/glint
if [ $# -gt 0 ] && [ "$1" != "--" ]; then GLINT=$1; shift; fi
PAIRS=15
if [ $# -gt 0 ] && [ "$1" != "--" ]; then PAIRS=$1; shift; fi
[ $# -gt 0 ] && [ "$1" = "--" ] && shift
ARGS=("$@")
[ ${#ARGS[@]} -gt 0 ] || ARGS=("$ROOT/scenes/rtiow-final.json" --width 640 --height 360 --spp 16)
command -v Xvfb >/dev/null || { echo "preview.sh: Xvfb is not installed (Debian: xvfb)" >&2; exit 1; }
OUT=$(mktemp -d "${TMPDIR:-/tmp}/glint-preview-bench.XXXXXX")
Xvfb -displayfd 3 -screen 0 1920x1080x24 -nolisten tcp 3>"$OUT/display" 2>"$OUT/xvfb.log" &
XVFB=$!
trap 'kill $XVFB 2>/dev/null; wait $XVFB 2>/dev/null; rm -rf "$OUT"' EXIT
for _ in $(seq 100); do [ -s "$OUT/display" ] && break; sleep 0.1; done
[ -s "$OUT/display" ] || { echo "preview.sh: Xvfb did not start" >&2; exit 1; }
export DISPLAY=:$(head -n 1 "$OUT/display")

# mrays [--preview]: the Mrays/s of one render. A finished preview keeps its window open (its statistics line
# is printed already): once that line is there, SIGINT ends the program.
mrays() {
    : >"$OUT/err"
    "$GLINT" "$@" "${ARGS[@]}" -o "$OUT/image.ppm" 2>"$OUT/err" >/dev/null &
    local pid=$!
    while kill -0 $pid 2>/dev/null && ! grep -q 'Mrays/s' "$OUT/err"; do sleep 0.05; done
    kill -INT $pid 2>/dev/null || true
    wait $pid 2>/dev/null || true
    if [ $# -gt 0 ] && grep -q 'rendering without a window' "$OUT/err"; then
        echo "preview.sh: glint opened no window: $(grep -m1 'preview' "$OUT/err")" >&2
        exit 1
    fi
    sed -n 's/.* \([0-9.]*\) Mrays\/s.*/\1/p' "$OUT/err" | tail -1
}
# shellcheck source=stats.bash
source "$ROOT/bench/stats.bash" # median, median_interval

for ((i = 0; i < PAIRS; i++)); do
    without=$(mrays) with=$(mrays --preview)
    [ -n "$without" ] && [ -n "$with" ] || { echo "preview.sh: a run printed no statistics line" >&2; exit 1; }
    echo "$without $with" >>"$OUT/pairs"
done
ratio=$(awk '{ print $2 / $1 }' "$OUT/pairs" | median)
printf 'without --preview: median %s Mrays/s\n' "$(awk '{ print $1 }' "$OUT/pairs" | median)"
printf 'with --preview:    median %s Mrays/s\n' "$(awk '{ print $2 }' "$OUT/pairs" | median)"
printf 'with / without:    %s (median of %d per-pair ratios)\n' "$ratio" "$PAIRS"
