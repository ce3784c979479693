#!/usr/bin/env bash
# bench/run.sh — glint's benchmark suite: one command that builds glint in release mode, runs every
# benchmark of docs/benchmarks.md, prints a table and keeps it in bench/results/.
#
# usage: bash bench/run.sh [--quick] [--runs N] [--only LIST] [--threads LIST] [--mesh-spp N]
#                          [--mesh-max N] [--no-embree] [--no-plots] [--glint PATH]
#                          [--meshyard-meshes LIST] [--cycles-scenes LIST]
#   --quick       fewer samples and runs (the Howard scenes at 10 spp instead of 100, the mesh
#                 yardstick at 4 spp instead of 16, 3 runs)
#   --runs N      runs per measurement (alternating pairs against a yardstick); the tables show
#                 medians (default 5, quick 3)
#   --only LIST   comma-separated sections: rtiow, howard, paper, scaling, mesh, meshyard,
#                 meshscale, cycles (default: all)
#   --threads LIST  comma-separated thread counts for rtiow and meshyard (default: 1 and the
#                 number of online CPUs); counts above it are run and marked oversubscribed
#   --mesh-spp N  samples per pixel of the meshyard and meshscale renders (400x300, depth 50)
#   --mesh-max N  meshscale's largest mesh, in triangles (default 5000000: 10k to 4.4M;
#                 20000000 adds the bunny subdivided four times, 17.8M triangles, about 800 MB
#                 of OBJ in bench/work/ and several GB of memory)
#   --no-embree   skip the Embree-based yardsticks even when they are found
#   --no-plots    do not draw the SVG plots (bench/plot.sh, gnuplot)
#   --glint PATH  measure this binary instead of building one
#   --meshyard-meshes LIST  comma-separated meshes of the meshyard section (default bunny, bunny1m, dragon,
#                 engine, engine-2m: bench/meshes/README.md)
#   --cycles-scenes LIST  comma-separated scene files (relative to the repository) of the cycles section
#                 (default scenes/cornell-box.json; envmap-bunny and bench/scenes/many-lights.json also work)
# Environment: CMAKE_BUILD_PARALLEL_LEVEL for the build; GLINT_BENCH_BUILD for the build directory.
# The yardsticks are separate tools, not part of this repository: GLINT_EMBREE_PROBE names the
# embree-probe's run_book1.sh (rtiow), GLINT_EMBREE_MESH the embree-mesh directory (its run.sh,
# scene_args.sh; meshyard, and the Embree rows of meshscale), GLINT_CYCLES_YARDSTICK the cycles-yardstick
# directory (its run_cornell.sh, with Debian's blender and python3-numpy: the cycles section, equal-error time
# against Blender's Cycles). Without them the suite runs and says which yardstick was skipped.
# Results: bench/results/DATE-COMMIT[-quick].md, and beside it a directory of the same name with the
# data files (.dat) and their plots (.svg) when a section wrote data.

# The whole script is one compound command, which bash reads to its end before it runs any of it: an edit to this
# file during a long run cannot change what the run does next (bash reads a plain script as it goes; a run once
# died of an edit).
{
set -euo pipefail
export LC_ALL=C # decimal points in awk, printf and EPOCHREALTIME

ROOT=$(cd "$(dirname "$0")/.." && pwd)
SECTIONS=rtiow,howard,paper,scaling,mesh,meshyard,meshscale,cycles
QUICK=0 RUNS='' ONLY=$SECTIONS EMBREE=1 PLOTS=1 GLINT='' THREADS='' MESH_SPP='' MESH_MAX=5000000
CYCLES_SCENES=scenes/cornell-box.json MESHYARD_MESHES=bunny,bunny1m,dragon,engine,engine-2m
usage_error() { echo "bench/run.sh: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
    case "$1" in
    --quick) QUICK=1 ;;
    --runs) RUNS=${2:?--runs needs a number}; shift ;;
    --only) ONLY=${2:?--only needs a list}; shift ;;
    --threads) THREADS=${2:?--threads needs a list}; shift ;;
    --mesh-spp) MESH_SPP=${2:?--mesh-spp needs a number}; shift ;;
    --mesh-max) MESH_MAX=${2:?--mesh-max needs a number}; shift ;;
    --no-embree) EMBREE=0 ;;
    --no-plots) PLOTS=0 ;;
    --glint) GLINT=${2:?--glint needs a path}; shift ;;
    --cycles-scenes) CYCLES_SCENES=${2:?--cycles-scenes needs a list}; shift ;;
    --meshyard-meshes) MESHYARD_MESHES=${2:?--meshyard-meshes needs a list}; shift ;;
    -h | --help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;;
    *) usage_error "unknown option '$1' (try --help)" ;;
    esac
    shift
done
posint() { case "$1" in '' | *[!0-9]* | 0*) return 1 ;; *) return 0 ;; esac; }
[ -n "$RUNS" ] || RUNS=$([ $QUICK = 1 ] && echo 3 || echo 5)
[ -n "$MESH_SPP" ] || MESH_SPP=$([ $QUICK = 1 ] && echo 4 || echo 16)
posint "$RUNS" || usage_error "--runs must be a positive integer"
posint "$MESH_SPP" || usage_error "--mesh-spp must be a positive integer"
posint "$MESH_MAX" || usage_error "--mesh-max must be a positive integer"
for s in ${ONLY//,/ }; do
    case ",$SECTIONS," in *",$s,"*) ;; *) usage_error "--only: unknown section '$s' (sections: $SECTIONS)" ;; esac
done
want() { case ",$ONLY," in *",$1,"*) return 0 ;; *) return 1 ;; esac; }

NPROC=$(getconf _NPROCESSORS_ONLN 2>/dev/null || nproc)
[ -n "$THREADS" ] || THREADS=1,$NPROC
THREAD_LIST=''
for t in ${THREADS//,/ }; do
    if ! posint "$t" || [ "$t" -gt 256 ]; then usage_error "--threads: '$t' is not a thread count in 1..256"; fi
    case " $THREAD_LIST " in *" $t "*) ;; *) THREAD_LIST="$THREAD_LIST $t" ;; esac
done
[ -n "$THREAD_LIST" ] || usage_error "--threads needs at least one thread count"
WORK=$(mktemp -d "${TMPDIR:-/tmp}/glint-bench.XXXXXX")
trap 'rm -rf "$WORK"' EXIT

# --- build -------------------------------------------------------------------------------------------
if [ -z "$GLINT" ]; then
    BUILD=${GLINT_BENCH_BUILD:-$ROOT/build-bench}
    echo "building glint (Release) in $BUILD ..." >&2
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >"$WORK/cmake.log" 2>&1 || { cat "$WORK/cmake.log" >&2; exit 1; }
    cmake --build "$BUILD" --target glint >>"$WORK/cmake.log" 2>&1 || { cat "$WORK/cmake.log" >&2; exit 1; }
    GLINT=$BUILD/glint
fi
[ -x "$GLINT" ] || { echo "bench/run.sh: no glint binary at $GLINT" >&2; exit 1; }

PROBE=${GLINT_EMBREE_PROBE:-}
[ $EMBREE = 1 ] && [ -f "$PROBE" ] || PROBE=
MESHYARD=${GLINT_EMBREE_MESH:-}
[ $EMBREE = 1 ] && [ -f "$MESHYARD/run.sh" ] && [ -f "$MESHYARD/scene_args.sh" ] || MESHYARD=
MESHYARD_BUILD=${TMPDIR:-/tmp}/glint-embree-mesh # where the yardstick's run.sh builds its renderer (its README)

# --- helpers -----------------------------------------------------------------------------------------
# median of the numbers on stdin
# shellcheck source=stats.bash
source "$ROOT/bench/stats.bash" # median, median_interval

now() { echo "${EPOCHREALTIME:-$(date +%s.%N)}"; }

# timed PEAKFILE CMD...: runs CMD (after the PIN prefix, see pin_for) and writes "peak_kb N" to PEAKFILE: the
# process's peak resident set size by GNU time's %M (getrusage's ru_maxrss), or nan without /usr/bin/time.
timed() {
    local peak=$1; shift
    if [ -x /usr/bin/time ]; then
        "${PIN[@]}" /usr/bin/time -f 'peak_kb %M' -o "$peak" "$@"
    else
        echo "peak_kb nan" >"$peak"
        "${PIN[@]}" "$@"
    fi
}

# pin_for THREADS: PIN becomes the prefix that pins a one-thread render to the last online CPU (so that it
# does not migrate between cores; both renderers of a pair on the same CPU), or nothing.
PIN=()
pin_for() {
    PIN=()
    if [ "$1" = 1 ] && [ "$NPROC" -gt 1 ] && command -v taskset >/dev/null && taskset -c $((NPROC - 1)) true 2>/dev/null; then
        PIN=(taskset -c $((NPROC - 1)))
    fi
}

# glint_stats STDERRFILE: "wall mrays build_ms" from glint's statistics line.
glint_stats() {
    local line; line=$(grep '^glint: .* s wall' "$1" | tail -n 1)
    [ -n "$line" ] || return 1
    local wall mrays build
    wall=$(echo "$line" | sed -n 's/^glint: \([0-9.]*\) s wall.*/\1/p')
    mrays=$(echo "$line" | sed -n 's/.* \([0-9.]*\) Mrays\/s.*/\1/p')
    build=$(echo "$line" | sed -n 's/.*build \([0-9.]*\) \(m\{0,1\}\)s.*/\1 \2/p' | awk '{ print ($2 == "m") ? $1 : $1 * 1000 }')
    echo "$wall $mrays ${build:-nan}"
}

# glint_run OUTFILE ARGS...: one render; appends "wall mrays build_ms peak_kb" to OUTFILE.
# Times come from glint's statistics line (wall time of the render including the BVH build; Mrays/s over the
# render loop alone, as the Embree yardstick counts).
glint_run() {
    local out=$1; shift
    local err=$WORK/stderr stats
    local -a PIN=() # these sections have always run unpinned: their results stay comparable
    timed "$WORK/time" "$GLINT" "$@" -o "$WORK/image.ppm" 2>"$err" >/dev/null || { echo "glint failed: $GLINT $*" >&2; cat "$err" >&2; exit 1; }
    stats=$(glint_stats "$err") || { echo "no statistics line from: $GLINT $*" >&2; cat "$err" >&2; exit 1; }
    echo "$stats $(awk '{ print $2 }' "$WORK/time")" >>"$out"
}

# glint_measure OUTFILE IMAGE ARGS...: one render, pinned as pin_for chose; appends "process_s wall mrays
# build_ms peak_kb": the process's wall time (scene and OBJ read, build, render, image written) before
# glint_run's four figures.
glint_measure() {
    local out=$1 image=$2; shift 2
    local err=$WORK/stderr stats t0 t1
    t0=$(now)
    timed "$WORK/time" "$GLINT" "$@" -o "$image" 2>"$err" >/dev/null || { echo "glint failed: $GLINT $*" >&2; cat "$err" >&2; exit 1; }
    t1=$(now)
    stats=$(glint_stats "$err") || { echo "no statistics line from: $GLINT $*" >&2; cat "$err" >&2; exit 1; }
    echo "$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.4f", b - a }') $stats $(awk '{ print $2 }' "$WORK/time")" >>"$out"
}

# embree_run OUTFILE SPP THREADS: one render of the yardstick; appends "wall mrays".
embree_run() {
    local line
    line=$(bash "$PROBE" "$2" "$3" "$WORK/embree.ppm" 2>/dev/null | tail -n 1) || { echo "embree probe failed" >&2; exit 1; }
    echo "$line" | sed -n 's/^rays=[0-9]* seconds=\([0-9.]*\) mrays_per_s=\([0-9.]*\).*/\1 \2/p' >>"$1"
}

# yard_fields OUTFILE PROCESS_S: from the mesh yardstick's line in $WORK/yout, appends "process_s load_s
# build_s render_s mrays peak_kb mean_r mean_g mean_b".
yard_fields() {
    local line; line=$(grep '^embree-mesh:' "$WORK/yout" | tail -n 1)
    [ -n "$line" ] || { echo "no result line from the mesh yardstick" >&2; cat "$WORK/yout" "$WORK/yerr" >&2; exit 1; }
    local f v out="$2"
    for f in load_s build_s render_s Mrays_s; do
        v=$(echo "$line" | sed -n "s/.* $f=\([0-9.]*\).*/\1/p")
        out="$out ${v:-nan}"
    done
    out="$out $(awk '{ print $2 }' "$WORK/time") $(echo "$line" | sed -n 's/.* mean=\([^ ]*\).*/\1/p' | tr , ' ')"
    echo "$out" >>"$1"
}

# meshyard_run OUTFILE NAME SPP THREADS IMAGE: one render of the mesh yardstick's run.sh (bunny or bunny1m),
# pinned as pin_for chose; appends yard_fields' figures, with the wall time of run.sh as process_s.
meshyard_run() {
    local t0 t1
    t0=$(now)
    timed "$WORK/time" bash "$MESHYARD/run.sh" "$2" "$3" "$4" "$5" >"$WORK/yout" 2>"$WORK/yerr" ||
        { echo "the mesh yardstick failed: run.sh $2 $3 $4" >&2; cat "$WORK/yerr" >&2; exit 1; }
    t1=$(now)
    yard_fields "$1" "$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.4f", b - a }')"
}

# meshyard_direct OUTFILE OBJ SPP IMAGE [THREADS]: the mesh yardstick's renderer (built by its run.sh) on its
# bunny scene with OBJ in place of the bunny, on THREADS threads (default 1), pinned as pin_for chose; appends
# yard_fields' figures.
meshyard_direct() {
    local t0 t1 args
    # shellcheck disable=SC2207 # the yardstick's arguments, split as its run.sh splits them
    args=($(bash "$MESHYARD/scene_args.sh" bunny | sed "s|--mesh [^ ]*|--mesh $2|"))
    t0=$(now)
    timed "$WORK/time" "$MESHYARD_BUILD/render_mesh" -w 400 -h 300 -s "$3" -d 50 -t "${5:-1}" "${args[@]}" -o "$4" \
        >"$WORK/yout" 2>"$WORK/yerr" || { echo "the mesh yardstick failed on $2" >&2; cat "$WORK/yerr" >&2; exit 1; }
    t1=$(now)
    yard_fields "$1" "$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.4f", b - a }')"
}

# pfm_means FILE: the mean of each channel of a little-endian colour PFM, "r g b".
pfm_means() {
    od -An -v -f -w12 -j "$(head -n 3 "$1" | wc -c)" "$1" |
        awk '{ r += $1; g += $2; b += $3; n++ } END { printf "%.6f %.6f %.6f\n", r / n, g / n, b / n }'
}

# data FILE ROW...: appends the ROWs to the data file FILE (saved beside the results), after a "# columns"
# line when the file is new.
DATA=$WORK/data
mkdir -p "$DATA"
data() {
    local f=$DATA/$1; shift
    if [ ! -s "$f" ]; then
        case $f in # the columns of each data file (bench/plot.sh reads them by position)
        */speedup.dat) echo "# bench renderer threads oversubscribed mrays speedup" ;;
        */versus.dat) echo "# case glint_mrays embree_mrays glint_over_embree" ;;
        */meshyard.dat) echo "# scene triangles threads oversubscribed embree_mrays glint_mrays glint_over_embree" \
            "embree_build_s glint_build_s embree_load_build_render_s glint_process_s embree_runsh_s process_embree_over_glint" ;;
        */meshscale.dat) echo "# mesh triangles renderer ns_per_ray build_s load_s peak_rss_mb bytes_per_triangle" ;;
        */cycles.dat) echo "# scene threads renderer spp render_s wall_s rmse rmse_corrected" ;;
        esac >"$f"
    fi
    printf '%s\n' "$@" >>"$f"
}

# tlabel THREADS: the thread count as the tables show it; oversub THREADS: 1 when above the online CPUs.
tlabel() { if [ "$1" -gt "$NPROC" ]; then echo "$1 (oversubscribed)"; else echo "$1"; fi; }
oversub() { if [ "$1" -gt "$NPROC" ]; then echo 1; else echo 0; fi; }

col() { awk -v c="$2" '{ print $c }' "$1" | median; }
# ratio A B: A / B to two decimals, or "-" when either is not a number (nan: not measured) or B is not
# positive; dratio prints nan instead of "-", for the data files.
ratio() { awk -v a="$1" -v b="$2" -v none="${3:--}" 'BEGIN { num = "^[-+]?[0-9]*[.]?[0-9]+([eE][-+]?[0-9]+)?$"
    if (a ~ num && b ~ num && b + 0 > 0) printf "%.2f", a / b; else printf "%s", none }'; }
dratio() { ratio "$1" "$2" nan; }
# fmt FORMAT VALUE: VALUE printed with FORMAT when it is a number, as it is otherwise (nan, -)
fmt() { awk -v f="$1" -v v="$2" 'BEGIN { if (v ~ /^[-+]?[0-9]*[.]?[0-9]+([eE][-+]?[0-9]+)?$/) printf f, v; else printf "%s", v }'; }

TABLE=$WORK/table.md
emit() { printf '%s\n' "$*" | tee -a "$TABLE"; }

COMMIT=$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)
git -C "$ROOT" diff --quiet HEAD -- 2>/dev/null || COMMIT="$COMMIT+dirty"
CPU=$(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | sed 's/.*: //' || uname -m)
DATE=$(date -u +%Y-%m-%dT%H:%M:%SZ)
emit "# glint benchmarks"
emit ""
emit "- date: $DATE"
emit "- commit: $COMMIT"
emit "- CPU: $CPU, $NPROC online CPUs"
emit "- compiler: $(${CC:-cc} --version 2>/dev/null | head -n 1)"
emit "- mode: $([ $QUICK = 1 ] && echo quick || echo full), $RUNS runs per measurement, medians"
emit "- threads (rtiow, meshyard):$THREAD_LIST; mesh sections: $MESH_SPP spp, meshscale up to $MESH_MAX triangles"
emit ""

# --- 1. rtiow-final against the Embree-based renderer -----------------------------------------------
if want rtiow; then
    emit "## rtiow-final, 400x225, 10 spp, depth 50 (487 spheres)"
    emit ""
    [ -n "$PROBE" ] || emit "(Embree yardstick skipped: GLINT_EMBREE_PROBE names no run_book1.sh, or --no-embree.)"
    emit "| renderer | threads | wall s | Mrays/s | glint / Embree | peak RSS MB |"
    emit "|---|---:|---:|---:|---:|---:|"
    declare -A rg=() re=()
    for t in $THREAD_LIST; do
        : >"$WORK/g$t"; : >"$WORK/e$t"
        for _ in $(seq "$RUNS"); do # alternating runs, so that both see the same machine state
            glint_run "$WORK/g$t" "$ROOT/scenes/rtiow-final.json" --width 400 --height 225 --spp 10 --depth 50 --threads "$t"
            [ -z "$PROBE" ] || embree_run "$WORK/e$t" 10 "$t"
        done
        gm=$(col "$WORK/g$t" 2)
        em=$([ -n "$PROBE" ] && col "$WORK/e$t" 2 || echo nan)
        rg[$t]=$gm re[$t]=$em
        emit "| glint | $(tlabel "$t") | $(col "$WORK/g$t" 1) | $gm | $(ratio "$gm" "$em") | $(awk -v k="$(col "$WORK/g$t" 4)" 'BEGIN { printf "%.1f", k / 1024 }') |"
        [ -z "$PROBE" ] || emit "| Embree 3 (user geometry) | $(tlabel "$t") | $(col "$WORK/e$t" 1) | $em | | |"
        data versus.dat "rtiow-final/${t}t $gm $em $(dratio "$gm" "$em")"
    done
    if [ -n "${rg[1]:-}" ]; then
        emit ""
        for t in $THREAD_LIST; do
            data speedup.dat "rtiow-final glint $t $(oversub "$t") ${rg[$t]} $(dratio "${rg[$t]}" "${rg[1]}")"
            [ -z "$PROBE" ] || data speedup.dat "rtiow-final embree-probe $t $(oversub "$t") ${re[$t]} $(dratio "${re[$t]}" "${re[1]}")"
            [ "$t" = 1 ] || emit "glint's own speedup on $(tlabel "$t") threads: $(ratio "${rg[$t]}" "${rg[1]}")x$([ -z "$PROBE" ] || echo "; the probe's: $(ratio "${re[$t]}" "${re[1]}")x")"
        done
    fi
    emit ""
fi

# --- 2. Howard's protocol ----------------------------------------------------------------------------
if want howard; then
    HSPP=$([ $QUICK = 1 ] && echo 10 || echo 100)
    emit "## Howard's protocol: five scenes, 720x405, $HSPP spp, depth 50"
    emit ""
    emit "| scene | wall s, 1 thread | Mrays/s | wall s, $NPROC threads | Mrays/s | speedup |"
    emit "|---|---:|---:|---:|---:|---:|"
    for scene in default lambertian metal dielectric hollow-sphere; do
        f=$ROOT/scenes/howard-$scene.json
        : >"$WORK/h1"; : >"$WORK/hn"
        for _ in $(seq "$RUNS"); do
            glint_run "$WORK/h1" "$f" --width 720 --height 405 --spp "$HSPP" --depth 50 --threads 1
            glint_run "$WORK/hn" "$f" --width 720 --height 405 --spp "$HSPP" --depth 50 --threads "$NPROC"
        done
        w1=$(col "$WORK/h1" 1) wn=$(col "$WORK/hn" 1)
        emit "| $scene | $w1 | $(col "$WORK/h1" 2) | $wn | $(col "$WORK/hn" 2) | $(ratio "$w1" "$wn") |"
        # (Howard's speedup: wall times, one thread over all threads)
        data speedup.dat "howard-$scene glint 1 0 $(col "$WORK/h1" 2) 1.00"
        [ "$NPROC" = 1 ] || data speedup.dat "howard-$scene glint $NPROC 0 $(col "$WORK/hn" 2) $(dratio "$w1" "$wn")"
    done
    emit ""
fi

# --- 3. the paper's scene ----------------------------------------------------------------------------
if want paper; then
    emit "## The paper's scene (Whitted), 768x768"
    emit ""
    emit "| threads | wall s | Mrays/s |"
    emit "|---:|---:|---:|"
    for t in 1 $([ "$NPROC" -gt 1 ] && echo "$NPROC"); do
        : >"$WORK/p$t"
        for _ in $(seq "$RUNS"); do glint_run "$WORK/p$t" "$ROOT/scenes/paper.json" --threads "$t"; done
        emit "| $t | $(col "$WORK/p$t" 1) | $(col "$WORK/p$t" 2) |"
    done
    emit ""
fi

# --- 4. scaling with the number of spheres -----------------------------------------------------------
# N random spheres in a 100^3 cube, radius sqrt(6400/N): the expected number of spheres a ray crosses
# (the optical depth) is the same for every N, so the cost per ray shows the structure, not the scene.
gen_spheres() {
    awk -v n="$1" 'BEGIN {
        s = 12345; r = sqrt(6400 / n)
        printf "{\"render\": {\"width\": 320, \"height\": 180, \"spp\": 4, \"max_depth\": 8, \"integrator\": \"path\", \"background\": \"sky\", \"output\": \"gamma2\"},\n"
        printf " \"camera\": {\"type\": \"lookat\", \"lookfrom\": [0, 0, -140], \"lookat\": [0, 0, 0], \"vfov\": 45},\n"
        printf " \"materials\": {\"m\": {\"type\": \"lambertian\", \"albedo\": [0.7, 0.6, 0.5]}},\n \"objects\": [\n"
        for (i = 0; i < n; i++) {
            # Park-Miller minimal standard generator: exact in double, the same in every awk
            s = (s * 48271) % 2147483647; x = s / 2147483647 * 100 - 50
            s = (s * 48271) % 2147483647; y = s / 2147483647 * 100 - 50
            s = (s * 48271) % 2147483647; z = s / 2147483647 * 100 - 50
            printf "  {\"type\": \"sphere\", \"center\": [%.4f, %.4f, %.4f], \"radius\": %.5f, \"material\": \"m\"}%s\n", x, y, z, r, (i + 1 < n) ? "," : ""
        }
        printf " ]}\n"
    }'
}
if want scaling; then
    SIZES="1000 10000 100000 1000000"
    emit "## Scaling: N random spheres, 320x180, 4 spp, depth 8, 1 thread"
    emit ""
    emit "| spheres | accel | build ms | trace s | Mrays/s | ns/ray | ns/ray vs 1,000 | peak RSS MB |"
    emit "|---:|---|---:|---:|---:|---:|---:|---:|"
    declare -A base
    for n in $SIZES; do
        gen_spheres "$n" >"$WORK/spheres-$n.json"
        for accel in bvh bvh2 none; do
            [ $accel = none ] && [ "$n" -gt 1000 ] && continue # brute force: quadratic, only as a reference
            : >"$WORK/s"
            for _ in $(seq "$RUNS"); do glint_run "$WORK/s" "$WORK/spheres-$n.json" --threads 1 --accel $accel; done
            # Tracing alone: glint's wall time includes the build, which grows as N log N; its Mrays/s is
            # already over the render loop alone (wall less the build).
            awk '{ t = $1 - $3 / 1000; if (t > 0) print t, $2 }' "$WORK/s" >"$WORK/st"
            mr=$(col "$WORK/st" 2)
            ns=$(awk -v m="$mr" 'BEGIN { if (m > 0) printf "%.1f", 1000 / m; else print "nan" }')
            [ "$n" = 1000 ] && base[$accel]=$ns
            emit "| $n | $accel | $(col "$WORK/s" 3) | $(col "$WORK/st" 1) | $(awk -v m="$mr" 'BEGIN { printf "%.3g", m }') | $ns | $(ratio "$ns" "${base[$accel]}") | $(awk -v k="$(col "$WORK/s" 4)" 'BEGIN { printf "%.1f", k / 1024 }') |"
        done
        rm -f "$WORK/spheres-$n.json"
    done
    emit ""
fi

# --- meshes for sections 5 to 7 ----------------------------------------------------------------------
MESH_SRC=$ROOT/scenes/meshes/stanford-bunny/stanford-bunny.obj

# mesh_tool NAME: builds bench/NAME.c (with bench/mesh_io.c) into the work directory once; prints its path.
mesh_tool() {
    local bin=$WORK/$1
    if [ ! -x "$bin" ]; then
        ${CC:-cc} -O2 -std=c17 -D_POSIX_C_SOURCE=200809L -o "$bin" "$ROOT/bench/$1.c" "$ROOT/bench/mesh_io.c" -lm >&2 || return 1
    fi
    echo "$bin"
}

# bench_mesh NAME: prints the path of the mesh NAME, generating bench/work/NAME.obj (git-ignored) when it is
# missing or older than its tool or the bunny. bunny is the Stanford bunny itself (69,451 triangles);
# bunny-10k the bunny simplified by bench/decimate.c to about 10,000 triangles; bunny-278k, bunny-1m,
# bunny-4m and bunny-18m the bunny subdivided 4:1 by bench/subdivide.c once to four times.
bench_mesh() {
    local name=$1 tool arg obj bin src
    case $name in
    bunny) echo "$MESH_SRC"; return 0 ;;
    dragon) yard_mesh "$name" "$ROOT/bench/meshes/stanford-dragon/dragon_vrip.ply.gz"; return ;;
    engine) yard_mesh "$name" "$ROOT/bench/meshes/2cylinder-engine/2CylinderEngine.glb"; return ;;
    engine-2m) # the engine subdivided 4:1 twice
        src=$(bench_mesh engine) || return 1
        obj=$ROOT/bench/work/$name.obj
        if [ ! -s "$obj" ] || [ "$ROOT/bench/subdivide.c" -nt "$obj" ] || [ "$src" -nt "$obj" ]; then
            echo "generating $obj ..." >&2
            bin=$(mesh_tool subdivide) || return 1
            "$bin" "$src" "$WORK/$name.obj" 2 >&2 || return 1
            mv "$WORK/$name.obj" "$obj"
        fi
        echo "$obj"; return 0 ;;
    bunny-10k) tool=decimate arg=10000 ;;
    bunny-278k) tool=subdivide arg=1 ;;
    bunny-1m) tool=subdivide arg=2 ;;
    bunny-4m) tool=subdivide arg=3 ;;
    bunny-18m) tool=subdivide arg=4 ;;
    *) echo "bench/run.sh: no mesh named $name" >&2; return 1 ;;
    esac
    obj=$ROOT/bench/work/$name.obj
    if [ ! -s "$obj" ] || [ "$ROOT/bench/$tool.c" -nt "$obj" ] || [ "$ROOT/bench/mesh_io.c" -nt "$obj" ] ||
        [ "$ROOT/bench/mesh_io.h" -nt "$obj" ] || [ "$MESH_SRC" -nt "$obj" ]; then
        echo "generating $obj ..." >&2
        mkdir -p "$ROOT/bench/work"
        bin=$(mesh_tool $tool) || return 1
        # written in the work directory (removed on exit) and moved into place: no partial mesh is left behind
        "$bin" "$MESH_SRC" "$WORK/$name.obj" "$arg" >&2 || return 1
        mv "$WORK/$name.obj" "$obj"
    fi
    echo "$obj"
}

# yard_mesh NAME SOURCE: prints the path of bench/work/NAME.obj, SOURCE (bench/meshes/) in the bunny's place
# (bench/yard_meshes.py), generating it when it is missing or older than its source or the script.
yard_mesh() {
    local obj=$ROOT/bench/work/$1.obj
    if [ ! -s "$obj" ] || [ "$2" -nt "$obj" ] || [ "$ROOT/bench/yard_meshes.py" -nt "$obj" ]; then
        echo "generating $obj ..." >&2
        mkdir -p "$ROOT/bench/work"
        python3 "$ROOT/bench/yard_meshes.py" "$2" "$MESH_SRC" "$WORK/$1.obj" >&2 || return 1
        mv "$WORK/$1.obj" "$obj"
    fi
    echo "$obj"
}

# mesh_triangles OBJ: its number of triangles (from the tools' first line, else its `f` lines: triangles only).
mesh_triangles() {
    local n; n=$(sed -n '1s/.* \([0-9]*\) triangles$/\1/p' "$1")
    [ -n "$n" ] || n=$(grep -c '^f ' "$1")
    echo "$n"
}

# --- 5. a mesh of over a million triangles -----------------------------------------------------------
# The Stanford bunny subdivided 4:1 twice by bench/subdivide.c (1,111,216 triangles), generated into
# bench/work/ (git-ignored) rather than committed, and regenerated when the tool or the bunny changes;
# the original bunny (69,451 triangles) is measured the same way for comparison. glint's statistics line
# gives the render time (BVH build included) and the build time; the OBJ load (reading the file, smooth
# normals) is the process's wall time minus that render time.
mesh_bench() {
    local dir=$ROOT/bench/work src=$MESH_SRC obj
    obj=$(bench_mesh bunny-1m) || exit 1
    emit "## A mesh of over a million triangles: the bunny subdivided twice, 320x240, 16 spp, depth 8"
    emit ""
    emit "| mesh | triangles | threads | OBJ load s | BVH build s | render s | Mrays/s | peak RSS MB |"
    emit "|---|---:|---:|---:|---:|---:|---:|---:|"
    local name file tris
    for name in bunny bunny-1m; do
        if [ $name = bunny ]; then file=$src tris=69451; else file=$obj tris=$(mesh_triangles "$obj"); fi
        # bunny.json's view, with a plain ground (no texture lookups) so that the time goes to the mesh
        cat >"$dir/$name.json" <<JSON
{"render": {"width": 320, "height": 240, "spp": 16, "max_depth": 8, "integrator": "path", "background": "sky", "output": "gamma2"},
 "camera": {"type": "lookat", "lookfrom": [0.6, 1.6, 4.2], "lookat": [-0.1, 0.75, 0], "vfov": 30},
 "materials": {"ground": {"type": "lambertian", "albedo": 0.5}, "clay": {"type": "lambertian", "albedo": [0.75, 0.6, 0.45]}},
 "objects": [
  {"type": "quad", "q": [-50, 0, 50], "u": [100, 0, 0], "v": [0, 0, -100], "material": "ground"},
  {"type": "mesh", "file": "$file", "material": "clay", "transform": [{"scale": 10}, {"translate": [0.17, -0.33, 0]}]}
 ]}
JSON
        for t in 1 $([ "$NPROC" -gt 1 ] && echo "$NPROC"); do
            : >"$WORK/m$t"; : >"$WORK/mt$t"
            for _ in $(seq "$RUNS"); do
                local t0 t1
                t0=$(date +%s.%N)
                glint_run "$WORK/m$t" "$dir/$name.json" --threads "$t"
                t1=$(date +%s.%N)
                awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f\n", b - a }' >>"$WORK/mt$t"
            done
            # columns: process wall, render wall (build included), Mrays/s, build ms, peak KB
            paste -d ' ' "$WORK/mt$t" "$WORK/m$t" | awk '{ printf "%.3f %.3f %.3f\n", $1 - $2, $4 / 1000, $2 - $4 / 1000 }' >"$WORK/ml$t"
            emit "| $name | $tris | $t | $(col "$WORK/ml$t" 1) | $(col "$WORK/ml$t" 2) | $(col "$WORK/ml$t" 3) | $(col "$WORK/m$t" 2) | $(awk -v k="$(col "$WORK/m$t" 4)" 'BEGIN { printf "%.1f", k / 1024 }') |"
        done
    done
    emit ""
}
if want mesh; then mesh_bench; fi

# --- 6. the mesh yardstick: glint against Embree 3's built-in triangles ------------------------------
# The embree-mesh yardstick (GLINT_EMBREE_MESH) renders the bunny and the bunny subdivided twice on a ground
# quad, 400x300, depth 50, with glint's path-integrator semantics; bench/scenes/bunny-yardstick.json is the
# same scene for glint. For bunny1m glint reads the very OBJ file the yardstick reads (which its run.sh
# writes): the same bytes to parse. The meshes of other character (bench/meshes/: a dense scan, a CAD mesh of
# long thin triangles, that mesh subdivided into tiny coplanar ones) stand in the bunny's place in the same
# scene, one OBJ file for both. Pairs alternate A B, B A, A B, ...; one-thread runs of both are pinned to one CPU.
meshyard_bench() {
    local spp=$MESH_SPP scene name t
    emit "## The mesh yardstick: glint against Embree 3's triangles, 400x300, $spp spp, depth 50"
    emit ""
    if [ -z "$MESHYARD" ]; then
        emit "(skipped: GLINT_EMBREE_MESH names no embree-mesh directory with run.sh and scene_args.sh, or --no-embree.)"
        emit ""
        return 0
    fi
    emit "| scene | triangles | threads | Embree Mrays/s | glint Mrays/s | glint / Embree | the median's interval | the pairs' range | Embree build s | glint build s | Embree load+build+render s | glint process s | whole process, Embree / glint | Embree run.sh s |"
    emit "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    declare -A mg=() me=()
    local notes=()
    for name in ${MESHYARD_MESHES//,/ }; do
        # Warm-up, not timed: builds the yardstick, writes its bunny1m.obj and glint's scene of it the first
        # time (a minute: Python), the other meshes' OBJ files, and brings the mesh into the page cache for both
        # renderers.
        echo "meshyard: $name, warm-up ..." >&2
        PIN=()
        meshyard_run "$WORK/warm" bunny 1 "$NPROC" "$WORK/warm.pfm" # builds the yardstick's renderer
        local obj=''
        case $name in
        bunny) scene=$ROOT/bench/scenes/bunny-yardstick.json obj=$MESH_SRC ;;
        bunny1m)
            meshyard_run "$WORK/warm" bunny1m 1 "$NPROC" "$WORK/warm.pfm"
            [ -s "$MESHYARD_BUILD/bunny1m.obj" ] || { echo "bench/run.sh: the yardstick wrote no $MESHYARD_BUILD/bunny1m.obj" >&2; exit 1; }
            obj=$MESHYARD_BUILD/bunny1m.obj ;;
        *) # a mesh of bench/meshes/ in the bunny's place: both renderers read the same OBJ file
            obj=$(bench_mesh "$name") || exit 1
            meshyard_direct "$WORK/warm" "$obj" 1 "$WORK/warm.pfm" "$NPROC" ;;
        esac
        if [ $name != bunny ]; then
            scene=$WORK/$name.json
            sed "s|\"file\": \"[^\"]*\"|\"file\": \"$obj\"|" "$ROOT/bench/scenes/bunny-yardstick.json" >"$scene"
        fi
        glint_measure "$WORK/warm" "$WORK/warm.pfm" "$scene" --spp 1 --threads "$NPROC"
        local tris; tris=$(mesh_triangles "$obj")
        local first=''
        for t in $THREAD_LIST; do
            pin_for "$t"
            : >"$WORK/yg"; : >"$WORK/ye"
            for i in $(seq "$RUNS"); do
                echo "meshyard: $name, $t thread(s), pair $i of $RUNS" >&2
                # A B, then B A, ...: each renderer follows the other as often as itself, so what one run leaves
                # behind (free huge pages, the caches) weighs on both alike.
                local order='glint embree'
                [ $((i % 2)) -eq 0 ] && order='embree glint'
                local who
                for who in $order; do
                    if [ $who = glint ]; then
                        glint_measure "$WORK/yg" "$WORK/glint.pfm" "$scene" --spp "$spp" --threads "$t"
                    else
                        case $name in
                        bunny | bunny1m) meshyard_run "$WORK/ye" "$name" "$spp" "$t" "$WORK/embree.pfm" ;;
                        *) meshyard_direct "$WORK/ye" "$obj" "$spp" "$WORK/embree.pfm" "$t" ;;
                        esac
                    fi
                done
            done
            # glint: process render mrays build_ms peak_kb; Embree: process load build render mrays peak_kb r g b
            paste -d ' ' "$WORK/yg" "$WORK/ye" >"$WORK/ypairs"
            local gm em ratio interval range pratio lbr
            gm=$(col "$WORK/yg" 3) em=$(col "$WORK/ye" 5)
            mg[$name.$t]=$gm me[$name.$t]=$em
            ratio=$(awk '$10 > 0 { print $3 / $10 }' "$WORK/ypairs" | median)
            # Where the median may lie, by the scatter of the pairs (stats.bash), and the lowest and highest pair's
            # ratio: on a shared machine they can lie 30 % apart.
            interval=$(awk '$10 > 0 { print $3 / $10 }' "$WORK/ypairs" | median_interval)
            range=$(awk '$10 > 0 { print $3 / $10 }' "$WORK/ypairs" | sort -g |
                awk 'NR == 1 { lo = $1 } { hi = $1 } END { if (NR) printf "%.3f-%.3f", lo, hi; else print "nan" }')
            pratio=$(awk '$1 > 0 { print ($7 + $8 + $9) / $1 }' "$WORK/ypairs" | median)
            lbr=$(awk '{ print $2 + $3 + $4 }' "$WORK/ye" | median)
            local gb eb gp er
            gb=$(awk '{ print $4 / 1000 }' "$WORK/yg" | median) eb=$(col "$WORK/ye" 3)
            gp=$(col "$WORK/yg" 1) er=$(col "$WORK/ye" 1)
            emit "| $name | $tris | $(tlabel "$t") | $(fmt %.2f "$em") | $(fmt %.2f "$gm") | $(fmt %.3f "$ratio") | $interval | $range | $(fmt %.3f "$eb") | $(fmt %.3f "$gb") | $(fmt %.3f "$lbr") | $(fmt %.3f "$gp") | $(fmt %.3f "$pratio") | $(fmt %.3f "$er") |"
            data meshyard.dat "$name $tris $t $(oversub "$t") $em $gm $ratio $eb $gb $lbr $gp $er $pratio"
            data versus.dat "$name/${t}t $gm $em $ratio"
            # Fairness: the two images must be the same scene. glint's image is the same for any thread count,
            # so one comparison per scene (its means against the yardstick's own, printed with its result).
            if [ -z "$first" ]; then
                first=$t
                local gmeans emeans
                gmeans=$(pfm_means "$WORK/glint.pfm")
                emeans=$(tail -n 1 "$WORK/ye" | awk '{ print $7, $8, $9 }')
                notes+=("$(echo "$gmeans $emeans" | awk -v n="$name" -v s="$spp" '{
                    worst = 0; line = ""
                    for (c = 1; c <= 3; c++) { d = ($c / $(c + 3) - 1) * 100; line = line sprintf(" %+.3f%%", d); if (d < 0) d = -d; if (d > worst) worst = d }
                    printf "%s: the image means (R G B) of glint against Embree:%s at %d spp", n, line, s
                    if (worst > 1) printf " -- MORE THAN 1%%: the two renders are not the same scene, their times do not compare"
                }')")
            fi
        done
    done
    emit ""
    for t in $THREAD_LIST; do
        for name in ${MESHYARD_MESHES//,/ }; do
            data speedup.dat "$name glint $t $(oversub "$t") ${mg[$name.$t]} $(dratio "${mg[$name.$t]}" "${mg[$name.1]:-nan}")" \
                "$name embree-mesh $t $(oversub "$t") ${me[$name.$t]} $(dratio "${me[$name.$t]}" "${me[$name.1]:-nan}")"
        done
    done
    local n
    for n in "${notes[@]}"; do emit "- $n"; done
    emit "- Mrays/s: rays per second of the render loop (build excluded), medians of $RUNS alternating runs; glint / Embree: the median of the per-pair ratios; the median's interval: between the k-th lowest and the k-th highest pair's ratio, which holds the true median with the probability in brackets (at least 90 %, whatever the scatter's distribution)."
    emit "- whole process: Embree's load_s + build_s + render_s (OBJ read and normals, BVH build, render loop) against glint's process wall time (scene and OBJ read, build, render, image written), per pair, median; Embree run.sh s is the wall time of its run.sh (a make check, a sed and the renderer)."
    emit ""
}
if want meshyard; then meshyard_bench; fi

# --- 7. scaling with the number of triangles --------------------------------------------------------
# The bunny from about 10,000 triangles (simplified) to 4.4 million (or 17.8 million with --mesh-max),
# in the yardstick's scene, one thread, pinned: ns per ray, build time, OBJ load and peak memory per
# triangle, for glint and (with GLINT_EMBREE_MESH) Embree on the same OBJ file.
meshscale_bench() {
    local spp=$MESH_SPP
    emit "## Scaling with the number of triangles: the bunny from 10k to $([ "$MESH_MAX" -ge 17779456 ] && echo 17.8M || echo 4.4M) triangles, 400x300, $spp spp, depth 50, 1 thread"
    emit ""
    [ -n "$MESHYARD" ] || emit "(Embree rows skipped: GLINT_EMBREE_MESH names no embree-mesh directory, or --no-embree.)"
    if [ -n "$MESHYARD" ]; then # builds the yardstick's renderer, which its run.sh alone knows how to do
        PIN=()
        meshyard_run "$WORK/warm" bunny 1 1 "$WORK/warm.pfm"
    fi
    emit "| mesh | triangles | renderer | ns/ray | ns/ray vs the smallest | build s | OBJ load s | peak RSS MB | bytes/triangle |"
    emit "|---|---:|---|---:|---:|---:|---:|---:|---:|"
    local avail_kb skipped=() level name expect obj tris scene first_tris='' last_tris=''
    avail_kb=$(awk '/^MemAvailable:/ { print $2 }' /proc/meminfo 2>/dev/null || echo 0)
    declare -A base=() last=()
    pin_for 1
    for level in bunny-10k:10000 bunny:69451 bunny-278k:277804 bunny-1m:1111216 bunny-4m:4444864 bunny-18m:17779456; do
        name=${level%%:*} expect=${level#*:}
        if [ "$expect" -gt "$MESH_MAX" ]; then skipped+=("$name ($expect triangles: above --mesh-max)"); continue; fi
        # about 150 bytes per triangle for glint and more for Embree's spatial splits: 600 leaves room for both
        if [ "${avail_kb:-0}" -gt 0 ] && [ $((expect * 600 / 1024)) -gt "$avail_kb" ]; then
            skipped+=("$name ($expect triangles: more than the $((avail_kb / 1024)) MB available would hold)"); continue
        fi
        obj=$(bench_mesh "$name") || exit 1
        tris=$(mesh_triangles "$obj")
        scene=$WORK/scale.json
        sed "s|\"file\": \"[^\"]*\"|\"file\": \"$obj\"|" "$ROOT/bench/scenes/bunny-yardstick.json" >"$scene"
        cat "$obj" >/dev/null # into the page cache, so that the first run reads it as the others do
        : >"$WORK/sg"; : >"$WORK/se"
        for i in $(seq "$RUNS"); do
            echo "meshscale: $name ($tris triangles), run $i of $RUNS" >&2
            glint_measure "$WORK/sg" "$WORK/glint.pfm" "$scene" --spp "$spp" --threads 1
            [ -z "$MESHYARD" ] || meshyard_direct "$WORK/se" "$obj" "$spp" "$WORK/embree.pfm"
        done
        # per renderer: ns/ray build_s load_s peak_kb
        awk '{ printf "%s %s %s %s\n", ($3 > 0 ? 1000 / $3 : "nan"), $4 / 1000, $1 - $2, $5 }' "$WORK/sg" >"$WORK/sgr"
        [ -z "$MESHYARD" ] || awk '{ printf "%s %s %s %s\n", ($5 > 0 ? 1000 / $5 : "nan"), $3, $2, $6 }' "$WORK/se" >"$WORK/ser"
        local r f label ns build load peak
        for r in glint embree-mesh; do
            if [ $r = glint ]; then f=$WORK/sgr label=glint; else [ -n "$MESHYARD" ] || continue; f=$WORK/ser label="Embree 3"; fi
            ns=$(col "$f" 1) build=$(col "$f" 2) load=$(col "$f" 3) peak=$(col "$f" 4)
            [ -n "${base[$r]:-}" ] || base[$r]=$ns
            last[$r]=$ns
            local mb bpt
            mb=$(awk -v k="$peak" 'BEGIN { printf "%.1f", k / 1024 }')
            bpt=$(awk -v k="$peak" -v n="$tris" 'BEGIN { printf "%.0f", k * 1024 / n }')
            emit "| $name | $tris | $label | $(fmt %.1f "$ns") | $(ratio "$ns" "${base[$r]}") | $(fmt %.3f "$build") | $(fmt %.3f "$load") | $mb | $bpt |"
            data meshscale.dat "$name $tris $r $ns $build $load $mb $bpt"
        done
        last_tris=$tris
        [ -n "$first_tris" ] || first_tris=$tris
    done
    emit ""
    local s
    for s in "${skipped[@]}"; do emit "- skipped: $s"; done
    if [ -n "$first_tris" ] && [ "$first_tris" != "$last_tris" ]; then
        emit "- from $first_tris to $last_tris triangles ($(ratio "$last_tris" "$first_tris")x): ns/ray grows $(ratio "${last[glint]}" "${base[glint]}")x for glint$([ -z "$MESHYARD" ] || echo ", $(ratio "${last[embree-mesh]}" "${base[embree-mesh]}")x for Embree")."
    fi
    emit "- ns/ray: 1000 / Mrays/s of the render loop, one thread; build s: the BVH build (glint's statistics line, Embree's build_s); OBJ load s: glint's process wall time less its render (reading the scene and the OBJ, normals, the image written), Embree's load_s (OBJ read, normals); peak RSS: GNU time's %M (the process's maximum resident set size), so it includes the process's fixed few MB, which dominate bytes/triangle for the small meshes."
    emit "- bunny-10k is the bunny simplified by vertex clustering (bench/decimate.c); bunny is the original; the others are the bunny subdivided 4:1 (bench/subdivide.c): generated into bench/work/."
    emit ""
}
if want meshscale; then meshscale_bench; fi

# --- 8. equal error in less time: glint against Blender's Cycles ------------------------------------------
# The cycles-yardstick (GLINT_CYCLES_YARDSTICK) builds each scene in Blender with matched settings, renders
# references of both, and times both renderers at 8..256 spp, alternating, at each thread count; its analyze.py
# gives the RMSE of every image against the references and the time each renderer needs for the same RMSE. The
# ratio Cycles' time / glint's time at equal error (> 1: glint is faster to a clean image) is the figure.
cycles_bench() {
    local yard=${GLINT_CYCLES_YARDSTICK:-}
    emit "## Equal error in less time: glint against Blender's Cycles (CPU)"
    emit ""
    if [ ! -f "$yard/run_cornell.sh" ] || ! command -v "${BLENDER:-blender}" >/dev/null; then
        emit "(skipped: GLINT_CYCLES_YARDSTICK names no cycles-yardstick directory, or blender is not installed)"
        emit ""
        return
    fi
    local ref_spp ref_parts spp_list scene tag out t th
    ref_spp=$([ $QUICK = 1 ] && echo 256 || echo 1024)
    ref_parts=$([ $QUICK = 1 ] && echo 2 || echo 4)
    spp_list=$([ $QUICK = 1 ] && echo 8,32,128 || echo 8,16,32,64,128,256)
    emit "| scene | threads | equal-error ratio, render time (geometric mean over glint's spp) | the same, whole process | pooled ratio (k_cycles / k_glint) |"
    emit "|---|---:|---:|---:|---:|"
    for scene in ${CYCLES_SCENES//,/ }; do
        tag=$(basename "$scene" .json)
        out=$WORK/cycles-$tag
        mkdir -p "$out"
        echo "cycles: $tag: Blender scene, references ($ref_parts x $ref_spp spp each), timed runs ..." >&2
        local -a steps=(blend gref cref)
        for th in $THREAD_LIST; do steps+=("t$th"); done
        steps+=(report)
        GLINT=$(cd "$(dirname "$GLINT")" && pwd)/$(basename "$GLINT") SCENE=$ROOT/$scene OUT=$out LOCK=$WORK/cpu.lock W=200 H=200 REF_SPP=$ref_spp REF_PARTS=$ref_parts \
            CREF_PARTS=$ref_parts SPP=$spp_list TAG=$tag bash "$yard/run_cornell.sh" "${steps[@]}" >"$out/log" 2>&1 ||
            { echo "cycles: the yardstick failed on $scene" >&2; tail -n 20 "$out/log" >&2; exit 1; }
        local md=$out/$tag-report-bothref.md
        for th in $THREAD_LIST; do
            # The error measure: against each renderer's own reference, its noise removed (the first table).
            local line pooled
            line=$(grep -m 1 "^threads $th: geometric mean ratio" "$md" || true)
            pooled=$(grep -m 1 "^threads $th, error rmse_own_c: " "$md" | sed -n 's/.*ratio \([0-9.]*\).*/\1/p' || true)
            emit "| $tag | $th | $(echo "$line" | sed -n 's/.*render \([0-9.]*\),.*/\1/p') | $(echo "$line" | sed -n 's/.*wall \([0-9.]*\) .*/\1/p') | ${pooled:-nan} |"
        done
        # Every timed image: its render time and RMSE, for the plot of RMSE against time.
        awk -F'|' -v tag="$tag" 'NF == 15 && $2 ~ /[0-9]/ { gsub(/ /, ""); print tag, $2, $3, $4, $6, $5, $9, ($13 == "-" ? "nan" : $13) }' \
            "$md" | while read -r row; do data cycles.dat "$row"; done
        cp "$md" "$DATA/cycles-$tag-report.md"
    done
    emit ""
    emit "- 200x200 pixels, the scene's depth; glint and Cycles (Blender $("${BLENDER:-blender}" -v 2>/dev/null | head -n 1 | awk '{ print $2 }')) alternately at spp $spp_list; references: $ref_parts renders of $ref_spp spp of each, averaged. Error: RMSE against each renderer's own reference with the reference's noise removed; ratio = the time Cycles needs for glint's RMSE (log-log interpolation) / glint's time, geometric mean over glint's points. The yardstick's full report for each scene is kept beside the data (cycles-SCENE-report.md)."
    emit ""
}
if want cycles; then cycles_bench; fi

# --- results, data and plots -------------------------------------------------------------------------
mkdir -p "$ROOT/bench/results"
SUFFIX=''
[ $QUICK = 0 ] || SUFFIX=-quick # (not a $(... && ...) in the assignment: its failure would end the script under set -e)
NAME=$(date -u +%Y-%m-%d)-$COMMIT$SUFFIX
RESULT=$ROOT/bench/results/$NAME.md
if ls "$DATA"/*.dat >/dev/null 2>&1; then
    rm -rf "${RESULT%.md}"
    mkdir -p "${RESULT%.md}"
    cp "$DATA"/*.dat "${RESULT%.md}/"
    if ls "$DATA"/*-report.md >/dev/null 2>&1; then cp "$DATA"/*-report.md "${RESULT%.md}/"; fi
    emit "## Data and plots"
    emit ""
    if [ $PLOTS = 1 ] && command -v gnuplot >/dev/null; then
        bash "$ROOT/bench/plot.sh" "${RESULT%.md}" >&2 || { echo "bench/run.sh: bench/plot.sh failed" >&2; exit 1; }
        for f in "${RESULT%.md}"/*.svg; do emit "![$(basename "$f" .svg)]($NAME/$(basename "$f"))"; emit ""; done
    elif [ $PLOTS = 1 ]; then
        emit "(no plots: gnuplot is not installed; Debian: apt-get install gnuplot-nox, then bash bench/plot.sh bench/results/$NAME)"
    fi
    files=''
    for f in "${RESULT%.md}"/*.dat; do files="$files \`$NAME/$(basename "$f")\`"; done
    emit "Data files (redraw the plots with \`bash bench/plot.sh bench/results/$NAME\`):$files"
    emit ""
fi
cp "$TABLE" "$RESULT"
echo "saved $RESULT" >&2
exit 0
}
