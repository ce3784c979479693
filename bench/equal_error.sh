#!/usr/bin/env bash
# bench/equal_error.sh — how much sooner does one glint binary reach a clean image than another? Renders one
# scene with both at several sample counts and seeds, alternately (A, B, A, B, ...) on one pinned thread, measures
# each image's RMSE against a common reference (B at many samples, another seed) and prints, per binary, the mean
# render time and the RMS error at each sample count, then A's time over B's at equal error: A's time-error curve
# (a least-squares line of log error against log time) read at each of B's points, geometric mean. Above 1 means B
# reaches the same error sooner. Per sample speed (ab.sh) misses what a better sampler gives; this measures both.
#
# usage: bash bench/equal_error.sh A_BINARY B_BINARY SCENE [--spp LIST] [--seeds N] [--ref-spp N]
#                                  [--out DIR] [-- GLINT ARGS]
#   --spp LIST    comma-separated sample counts of the measured renders (default 16,64)
#   --seeds N     renders per binary and sample count, seeds 1..N (default 5)
#   --ref-spp N   the reference's samples per pixel, B on every CPU, seed 1000 (default 2048)
#   --out DIR     keep the images and the table there (default: a temporary directory, removed)
#   GLINT ARGS    passed to every render (e.g. --width 200 --height 200)
# The error is over every pixel and channel of the linear PFM images; the reference's own noise is not removed
# (at 2,048 samples it is small against 16-64). Quote the table with the date, both commits and the machine.
{ # one compound command, read whole before it runs (as bench/run.sh): an edit during a run cannot change it
set -euo pipefail
usage() { sed -n '9,16p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 3 ] || usage
A=$1 B=$2 SCENE=$3
shift 3
SPP=16,64 SEEDS=5 REF_SPP=2048 KEEP=
while [ $# -gt 0 ]; do
    case $1 in
    --spp) SPP=${2:?--spp needs a list}; shift 2 ;;
    --seeds) SEEDS=${2:?--seeds needs a number}; shift 2 ;;
    --ref-spp) REF_SPP=${2:?--ref-spp needs a number}; shift 2 ;;
    --out) KEEP=${2:?--out needs a directory}; shift 2 ;;
    --) shift; break ;;
    *) echo "equal_error.sh: unknown option $1" >&2; usage ;;
    esac
done
ARGS=("$@")
for n in $(echo "$SPP" | tr , ' ') "$SEEDS" "$REF_SPP"; do
    [[ $n =~ ^[1-9][0-9]*$ ]] || { echo "equal_error.sh: '$n' is not a positive whole number" >&2; exit 2; }
done
for bin in "$A" "$B"; do [ -x "$bin" ] || { echo "equal_error.sh: $bin is not an executable" >&2; exit 2; }; done
[ -f "$SCENE" ] || { echo "equal_error.sh: no scene file $SCENE" >&2; exit 2; }
if [ -n "$KEEP" ]; then
    mkdir -p "$KEEP"
    OUT=$KEEP
else
    OUT=$(mktemp -d "${TMPDIR:-/tmp}/glint-ee.XXXXXX")
    trap 'rm -rf "$OUT"' EXIT
fi
PIN=()
command -v taskset >/dev/null && [ "$(nproc)" -gt 1 ] && PIN=(taskset -c 1)

# render BINARY IMAGE SPP SEED THREADS: one render; prints its wall time from glint's statistics line.
render() {
    local line
    line=$("${PIN[@]}" "$1" "$SCENE" "${ARGS[@]}" --spp "$3" --seed "$4" --threads "$5" -o "$2" 2>&1 >/dev/null |
        grep ' s wall' | tail -1) || { echo "equal_error.sh: $1 failed on $SCENE" >&2; exit 1; }
    echo "$line" | sed -n 's/^glint: \([0-9.]*\) s wall.*/\1/p'
}

# floats PFM: its pixel values, one per line (a colour PFM: 3 a pixel; little-endian, as glint writes).
floats() { od -An -v -f -w4 -j "$(head -n 3 "$1" | wc -c)" "$1"; }

# rmse PFM: its RMS difference from the reference, over every pixel and channel.
rmse() { paste <(floats "$1") "$OUT/ref.values" | awk '{ d = $1 - $2; s += d * d; n++ } END { printf "%.6g\n", sqrt(s / n) }'; }

echo "equal_error.sh: the reference, $REF_SPP spp on $(nproc) threads ..." >&2
PIN_SAVED=("${PIN[@]}")
PIN=()
render "$B" "$OUT/ref.pfm" "$REF_SPP" 1000 0 >/dev/null
PIN=("${PIN_SAVED[@]}")
floats "$OUT/ref.pfm" >"$OUT/ref.values"
: >"$OUT/points"
for spp in $(echo "$SPP" | tr , ' '); do
    for ((seed = 1; seed <= SEEDS; seed++)); do
        echo "equal_error.sh: $spp spp, seed $seed of $SEEDS ..." >&2
        for which in A B; do
            bin=$A
            [ $which = B ] && bin=$B
            t=$(render "$bin" "$OUT/$which-$spp-$seed.pfm" "$spp" "$seed" 1)
            echo "$which $spp $seed $t $(rmse "$OUT/$which-$spp-$seed.pfm")" >>"$OUT/points"
        done
    done
done
# Per binary and sample count: mean time, RMS of the errors. Then A's curve, log e = c + k log t, read at B's
# errors: t_A = exp((log e_B - c) / k), and the geometric mean of t_A / t_B.
awk '{ k = $1 " " $2; t[k] += $4; e[k] += $5 * $5; n[k]++ }
     END { for (k in t) print k, t[k] / n[k], sqrt(e[k] / n[k]) }' "$OUT/points" | sort -k1,1 -k2,2n >"$OUT/table"
{
    echo "| binary | spp | render s (mean) | RMSE |"
    echo "|---|---:|---:|---:|"
    awk '{ printf "| %s | %d | %.4f | %.5g |\n", $1, $2, $3, $4 }' "$OUT/table"
    awk '$3 <= 0 { zero = 1 }
         $1 == "A" && $3 > 0 { x = log($3); y = log($4); n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
         $1 == "B" && $3 > 0 { bt[++m] = $3; be[m] = $4 }
         END {
             if (zero) { print "\n(no ratio: a render took less than the statistics line'"'"'s millisecond; render more)"; exit }
             if (n < 2) { print "\n(no ratio: A needs two sample counts for its curve)"; exit }
             k = (n * sxy - sx * sy) / (n * sxx - sx * sx); c = (sy - k * sx) / n
             for (i = 1; i <= m; i++) { ta = exp((log(be[i]) - c) / k); g += log(ta / bt[i]) }
             printf "\nA: error ~ time^%.3f; A'"'"'s time / B'"'"'s at equal error (geometric mean over B'"'"'s %d points): %.3f\n", k, m, exp(g / m)
         }' "$OUT/table"
} | tee "$OUT/result.md"
exit 0
}
