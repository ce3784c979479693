#!/usr/bin/env bash
# bench/mpi.sh — what MPI costs glint on one machine, and the numbers for the model of many (docs/distributed.md).
# For a small and a large render it runs, alternately, R = `mpirun -np 2 glint-mpi --threads 1`,
# T2 = `glint --threads 2` and T1 = `glint --threads 1` (all on the same scene and options, so the same image),
# and prints the medians of the per-round ratios (like bench/ab.sh): R/T2 - 1 is the MPI overhead against one
# process with as many threads, T1/R the speed-up over one thread. Two times are compared: the program's own
# "wall" (its statistics line: frame build and render, after MPI has started) and the elapsed time of the whole
# command (mpirun's start-up and the scene's loading included). From glint-mpi's traffic line it prints the
# per-unit communication counters: bytes per unit, messages per second, rank 0's busy time per unit.
# Run it on a quiet machine with at least two cores; it takes about ROUNDS x (3 x small + 3 x large) seconds.
#
# usage: bash bench/mpi.sh [ROUNDS]      (default 11; BUILD=build-dir, SMALL="args", LARGE="args" override)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-$ROOT/build}
ROUNDS=${1:-11}
GLINT=$BUILD/glint
GLINT_MPI=$BUILD/glint-mpi
[ -x "$GLINT" ] && [ -x "$GLINT_MPI" ] || { echo "mpi.sh: build glint and glint-mpi in $BUILD first" >&2; exit 1; }
# About 0.2 s and 20 s with glint --threads 2 on the 2-core development machine: adjust to your machine so that
# the T2 times printed below come near those.
read -r -a SMALL <<<"${SMALL:-$ROOT/scenes/rtiow-final.json --width 200 --height 112 --spp 8}"
read -r -a LARGE <<<"${LARGE:-$ROOT/scenes/rtiow-final.json --width 640 --height 360 --spp 96}"
MPIRUN=(mpirun -np 2)
[ "$(id -u)" = 0 ] && MPIRUN+=(--allow-run-as-root)
OUT=$(mktemp -d "${TMPDIR:-/tmp}/glint-mpi-bench.XXXXXX")
trap 'rm -rf "$OUT"' EXIT

# shellcheck source=stats.bash
source "$ROOT/bench/stats.bash" # median, median_interval

# timed NAME COMMAND...: runs it; appends "its wall, the elapsed time" to $OUT/NAME, keeps its stderr.
timed() {
    local name=$1
    shift
    local t0 t1
    t0=$(date +%s.%N)
    "$@" -o "$OUT/image.ppm" 2>"$OUT/err" >/dev/null
    t1=$(date +%s.%N)
    local wall
    wall=$(sed -n 's/^glint[-a-z]*: \([0-9.]*\) s wall.*/\1/p' "$OUT/err" | tail -1)
    [ -n "$wall" ] || { echo "mpi.sh: $name printed no statistics line:" >&2; cat "$OUT/err" >&2; exit 1; }
    echo "$wall $(echo "$t1 - $t0" | bc -l)" >>"$OUT/$name"
}

for size in small large; do
    if [ $size = small ]; then ARGS=("${SMALL[@]}"); else ARGS=("${LARGE[@]}"); fi
    for ((i = 0; i < ROUNDS; i++)); do
        timed "$size-mpi" "${MPIRUN[@]}" "$GLINT_MPI" --threads 1 "${ARGS[@]}"
        grep '^glint-mpi: traffic' "$OUT/err" >>"$OUT/$size-traffic"
        timed "$size-t2" "$GLINT" --threads 2 "${ARGS[@]}"
        timed "$size-t1" "$GLINT" --threads 1 "${ARGS[@]}"
    done
    echo "== $size render: ${ARGS[*]} ($ROUNDS rounds)"
    for col in 1 2; do
        what=$([ $col = 1 ] && echo "program wall" || echo "elapsed, mpirun included")
        paste -d' ' <(cut -d' ' -f$col "$OUT/$size-mpi") <(cut -d' ' -f$col "$OUT/$size-t2") \
            <(cut -d' ' -f$col "$OUT/$size-t1") >"$OUT/rounds"
        printf '  %-26s R %.3f s, T2 %.3f s, T1 %.3f s; MPI overhead R/T2-1 = %+.1f %%; speed-up T1/R = %.2f\n' \
            "$what:" "$(cut -d' ' -f1 "$OUT/rounds" | median)" "$(cut -d' ' -f2 "$OUT/rounds" | median)" \
            "$(cut -d' ' -f3 "$OUT/rounds" | median)" \
            "$(awk '{ print 100 * ($1 / $2 - 1) }' "$OUT/rounds" | median)" \
            "$(awk '{ print $3 / $1 }' "$OUT/rounds" | median)"
    done
    # glint-mpi: traffic of rank 0: M messages (X/s), ... B bytes per unit rendered elsewhere (...); busy ..., U us per unit
    printf '  per unit (medians): %.0f bytes per unit rendered elsewhere, %.0f messages/s, %.1f us of rank 0 per unit\n' \
        "$(sed -n 's/.*, \([0-9.]*\) bytes per unit.*/\1/p' "$OUT/$size-traffic" | median)" \
        "$(sed -n 's/.* messages (\([0-9.]*\)\/s).*/\1/p' "$OUT/$size-traffic" | median)" \
        "$(sed -n 's/.*, \([0-9.]*\) us per unit.*/\1/p' "$OUT/$size-traffic" | median)"
    tail -1 "$OUT/$size-traffic" | sed 's/^/  last run: /'
done
