#!/usr/bin/env bash
# bench/run.sh — glint's benchmark suite: one command that builds glint in release mode, runs every
# benchmark of docs/benchmarks.md, prints a table and keeps it in bench/results/.
#
# usage: bash bench/run.sh [--quick] [--runs N] [--only LIST] [--no-embree] [--glint PATH]
#   --quick      fewer samples and runs (the Howard scenes at 10 spp instead of 100, 3 runs)
#   --runs N     runs per measurement; the table shows medians (default 5, quick 3)
#   --only LIST  comma-separated sections: rtiow, howard, paper, scaling, mesh (default: all)
#   --no-embree  skip the Embree-based yardstick even when its script exists
#   --glint PATH measure this binary instead of building one
# Environment: CMAKE_BUILD_PARALLEL_LEVEL for the build; GLINT_BENCH_BUILD for the build directory.
# The yardstick is the embree-probe's run_book1.sh (a separate tool, not part of this repository):
# GLINT_EMBREE_PROBE names it. Without it the suite runs and says the yardstick was skipped.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
QUICK=0 RUNS='' ONLY=rtiow,howard,paper,scaling,mesh EMBREE=1 GLINT=''
while [ $# -gt 0 ]; do
    case "$1" in
    --quick) QUICK=1 ;;
    --runs) RUNS=${2:?--runs needs a number}; shift ;;
    --only) ONLY=${2:?--only needs a list}; shift ;;
    --no-embree) EMBREE=0 ;;
    --glint) GLINT=${2:?--glint needs a path}; shift ;;
    -h | --help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bench/run.sh: unknown option '$1' (try --help)" >&2; exit 2 ;;
    esac
    shift
done
[ -n "$RUNS" ] || RUNS=$([ $QUICK = 1 ] && echo 3 || echo 5)
case "$RUNS" in '' | *[!0-9]* | 0) echo "bench/run.sh: --runs must be a positive integer" >&2; exit 2 ;; esac
want() { case ",$ONLY," in *",$1,"*) return 0 ;; *) return 1 ;; esac; }

NPROC=$(getconf _NPROCESSORS_ONLN 2>/dev/null || nproc)
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

# --- helpers -----------------------------------------------------------------------------------------
# median of the numbers on stdin
median() { sort -g | awk '{ v[NR] = $1 } END { if (NR == 0) print "nan"; else if (NR % 2) print v[(NR + 1) / 2]; else printf "%.4g\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# glint_run OUTFILE ARGS...: one render; appends "wall mrays build_ms peak_kb" to OUTFILE.
# Times come from glint's statistics line (wall time of the render including the BVH build; Mrays/s over the
# render loop alone, as the Embree yardstick counts).
glint_run() {
    local out=$1; shift
    local err=$WORK/stderr
    if [ -x /usr/bin/time ]; then
        /usr/bin/time -f 'peak_kb %M' -o "$WORK/time" "$GLINT" "$@" -o "$WORK/image.ppm" 2>"$err" >/dev/null ||
            { echo "glint failed: $GLINT $*" >&2; cat "$err" >&2; exit 1; }
    else
        "$GLINT" "$@" -o "$WORK/image.ppm" 2>"$err" >/dev/null || { echo "glint failed: $GLINT $*" >&2; cat "$err" >&2; exit 1; }
        echo "peak_kb nan" >"$WORK/time"
    fi
    local line; line=$(grep '^glint: .* s wall' "$err" | tail -n 1)
    [ -n "$line" ] || { echo "no statistics line from: $GLINT $*" >&2; cat "$err" >&2; exit 1; }
    local wall mrays build
    wall=$(echo "$line" | sed -n 's/^glint: \([0-9.]*\) s wall.*/\1/p')
    mrays=$(echo "$line" | sed -n 's/.* \([0-9.]*\) Mrays\/s.*/\1/p')
    build=$(echo "$line" | sed -n 's/.*build \([0-9.]*\) \(m\{0,1\}\)s.*/\1 \2/p' | awk '{ print ($2 == "m") ? $1 : $1 * 1000 }')
    echo "$wall $mrays ${build:-nan} $(awk '{ print $2 }' "$WORK/time")" >>"$out"
}

# embree_run OUTFILE SPP THREADS: one render of the yardstick; appends "wall mrays".
embree_run() {
    local line
    line=$(bash "$PROBE" "$2" "$3" "$WORK/embree.ppm" 2>/dev/null | tail -n 1) || { echo "embree probe failed" >&2; exit 1; }
    echo "$line" | sed -n 's/^rays=[0-9]* seconds=\([0-9.]*\) mrays_per_s=\([0-9.]*\).*/\1 \2/p' >>"$1"
}

col() { awk -v c="$2" '{ print $c }' "$1" | median; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b > 0 && a == a) printf "%.2f", a / b; else print "-" }'; }

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
emit ""

# --- 1. rtiow-final against the Embree-based renderer -----------------------------------------------
if want rtiow; then
    emit "## rtiow-final, 400x225, 10 spp, depth 50 (487 spheres)"
    emit ""
    [ -n "$PROBE" ] || emit "(Embree yardstick skipped: GLINT_EMBREE_PROBE names no run_book1.sh, or --no-embree.)"
    emit "| renderer | threads | wall s | Mrays/s | glint / Embree | peak RSS MB |"
    emit "|---|---:|---:|---:|---:|---:|"
    for t in 1 $([ "$NPROC" -gt 1 ] && echo "$NPROC"); do
        : >"$WORK/g$t"; : >"$WORK/e$t"
        for _ in $(seq "$RUNS"); do # alternating runs, so that both see the same machine state
            glint_run "$WORK/g$t" "$ROOT/scenes/rtiow-final.json" --width 400 --height 225 --spp 10 --depth 50 --threads "$t"
            [ -z "$PROBE" ] || embree_run "$WORK/e$t" 10 "$t"
        done
        gm=$(col "$WORK/g$t" 2)
        em=$([ -n "$PROBE" ] && col "$WORK/e$t" 2 || echo nan)
        emit "| glint | $t | $(col "$WORK/g$t" 1) | $gm | $(ratio "$gm" "$em") | $(awk -v k="$(col "$WORK/g$t" 4)" 'BEGIN { printf "%.1f", k / 1024 }') |"
        [ -z "$PROBE" ] || emit "| Embree 3 (user geometry) | $t | $(col "$WORK/e$t" 1) | $em | | |"
    done
    if [ "$NPROC" -gt 1 ]; then
        emit ""
        emit "glint's own speedup on $NPROC threads: $(ratio "$(col "$WORK/g$NPROC" 2)" "$(col "$WORK/g1" 2)")x"
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

# --- 5. a mesh of over a million triangles -----------------------------------------------------------
# The Stanford bunny subdivided 4:1 twice by bench/subdivide.c (1,111,216 triangles), generated into
# bench/work/ (git-ignored) rather than committed, and regenerated when the tool or the bunny changes;
# the original bunny (69,451 triangles) is measured the same way for comparison. glint's statistics line
# gives the render time (BVH build included) and the build time; the OBJ load (reading the file, smooth
# normals) is the process's wall time minus that render time.
mesh_bench() {
    local dir=$ROOT/bench/work src=$ROOT/scenes/meshes/stanford-bunny/stanford-bunny.obj
    local obj=$ROOT/bench/work/bunny-1m.obj
    mkdir -p "$dir"
    if [ ! -s "$obj" ] || [ "$ROOT/bench/subdivide.c" -nt "$obj" ] || [ "$src" -nt "$obj" ]; then
        echo "generating $obj ..." >&2
        ${CC:-cc} -O2 -std=c17 -D_POSIX_C_SOURCE=200809L -o "$WORK/subdivide" "$ROOT/bench/subdivide.c" || exit 1
        "$WORK/subdivide" "$src" "$obj.tmp" 2 || exit 1
        mv "$obj.tmp" "$obj"
    fi
    emit "## A mesh of over a million triangles: the bunny subdivided twice, 320x240, 16 spp, depth 8"
    emit ""
    emit "| mesh | triangles | threads | OBJ load s | BVH build s | render s | Mrays/s | peak RSS MB |"
    emit "|---|---:|---:|---:|---:|---:|---:|---:|"
    local name file tris
    for name in bunny bunny-1m; do
        if [ $name = bunny ]; then file=$src tris=69451; else file=$obj tris=$(sed -n '1s/.* \([0-9]*\) triangles$/\1/p' "$obj"); fi
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

mkdir -p "$ROOT/bench/results"
SUFFIX=''
[ $QUICK = 0 ] || SUFFIX=-quick # (not a $(... && ...) in the assignment: its failure would end the script under set -e)
RESULT=$ROOT/bench/results/$(date -u +%Y-%m-%d)-$COMMIT$SUFFIX.md
cp "$TABLE" "$RESULT"
echo "saved $RESULT" >&2
