#!/usr/bin/env bash
# bench/ab.sh — is one glint binary faster than another? Runs them alternately (A, B, B, A, A, B, ...) on one
# render, so both see the same machine state, and prints the median of the per-pair ratios of their render
# loop's Mrays/s (B over A: above 1 means B is faster). An A/A run gives about 1.000; single pairs scatter
# by several percent on a shared machine, so use tens of pairs to resolve a 1-2% difference. Beside the ratio, the
# interval that holds the true median ratio with at least 90 % probability (stats.bash's median_interval): a
# difference is resolved when it leaves out 1.
#
# usage: bash bench/ab.sh A_BINARY B_BINARY [PAIRS] [-- GLINT ARGS]
#   default render: scenes/rtiow-final.json at 200x112, 10 spp, one thread; one-thread renders are pinned
#   AB_RATE=Msamples compares samples per second instead (binaries whose paths trace different rays per sample:
#   then the time to the same image, where Mrays/s would credit the extra rays)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
A=${1:?usage: ab.sh A_BINARY B_BINARY [PAIRS] [-- GLINT ARGS]}
B=${2:?usage: ab.sh A_BINARY B_BINARY [PAIRS] [-- GLINT ARGS]}
shift 2
PAIRS=21
if [ $# -gt 0 ] && [ "$1" != "--" ]; then PAIRS=$1; shift; fi
[ $# -gt 0 ] && [ "$1" = "--" ] && shift
ARGS=("$@")
[ ${#ARGS[@]} -gt 0 ] || ARGS=("$ROOT/scenes/rtiow-final.json" --width 200 --height 112 --spp 10 --threads 1)
# One-thread renders are pinned to CPU 1 (when taskset exists), so that they do not migrate between cores.
PIN=()
for ((i = 0; i + 1 < ${#ARGS[@]}; i++)); do
    if [ "${ARGS[i]}" = --threads ] && [ "${ARGS[i + 1]}" = 1 ] && command -v taskset >/dev/null && [ "$(nproc)" -gt 1 ]; then
        PIN=(taskset -c 1)
    fi
done
OUT=$(mktemp -d "${TMPDIR:-/tmp}/glint-ab.XXXXXX")
trap 'rm -rf "$OUT"' EXIT

RATE=${AB_RATE:-Mrays}
case $RATE in Mrays | Msamples) ;; *) echo "ab.sh: AB_RATE is Mrays or Msamples, not $RATE" >&2; exit 2 ;; esac
# mrays BINARY: the Mrays/s (or Msamples/s) of one render, from glint's statistics line.
mrays() {
    "${PIN[@]}" "$1" "${ARGS[@]}" -o "$OUT/image.ppm" 2>&1 >/dev/null | sed -n "s/.* \([0-9.]*\) $RATE\/s.*/\1/p" | tail -1
}
# shellcheck source=stats.bash
source "$ROOT/bench/stats.bash" # median, median_interval

for ((i = 0; i < PAIRS; i++)); do
    # A B, then B A: each binary follows the other as often as itself (a run leaves the caches behind it).
    if ((i % 2 == 0)); then a=$(mrays "$A") b=$(mrays "$B"); else b=$(mrays "$B") a=$(mrays "$A"); fi
    [ -n "$a" ] && [ -n "$b" ] || { echo "ab.sh: a run printed no statistics line" >&2; exit 1; }
    echo "$a $b" >>"$OUT/pairs"
done
awk '{ print $2 / $1 }' "$OUT/pairs" | median >"$OUT/ratio"
printf 'A %s %s/s, B %s %s/s (medians of %d alternating pairs); median B/A ratio %.3f, its interval %s\n' \
    "$(cut -d' ' -f1 "$OUT/pairs" | median)" "$RATE" "$(cut -d' ' -f2 "$OUT/pairs" | median)" "$RATE" "$PAIRS" "$(cat "$OUT/ratio")" \
    "$(awk '{ print $2 / $1 }' "$OUT/pairs" | median_interval)"
