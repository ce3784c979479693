#!/usr/bin/env bash
# bench/instructions.sh — where glint's instructions go, against the Embree mesh yardstick: both renderers run the
# bunny scene (1 spp, one thread) under valgrind's callgrind, and the script prints the instructions each executes
# per ray in the closest-hit queries and in the rest of the render loop. Instruction counts are exact and the same
# on a busy machine, so they show whether a change removed work where timings scatter by several percent; they
# are not speed (a cache miss costs no instruction), which bench/ab.sh and bench/run.sh measure.
#
# usage: bash bench/instructions.sh [bunny|bunny1m]
# Needs valgrind and python3 (Debian packages of those names), and GLINT_EMBREE_MESH naming the embree-mesh
# directory (its run.sh and scene_args.sh; Debian's libembree-dev) for the Embree column; without it only glint
# is counted. valgrind does not decode AVX-512, so both are built for AVX2 (-march=haswell; Embree with
# isa=avx2), the ISA glint's SIMD traversal is written for.
set -euo pipefail
export LC_ALL=C
ROOT=$(cd "$(dirname "$0")/.." && pwd)
SCENE=${1:-bunny}
case "$SCENE" in bunny|bunny1m) ;; *) echo "usage: bash bench/instructions.sh [bunny|bunny1m]" >&2; exit 2 ;; esac
for tool in valgrind python3 cmake; do
    command -v "$tool" >/dev/null || { echo "bench/instructions.sh: needs $tool (apt-get install $tool)" >&2; exit 2; }
done
WORK=${TMPDIR:-/tmp}/glint-instructions
mkdir -p "$WORK"

# glint for AVX2, with line tables (the same optimisation as a release build otherwise)
cmake -S "$ROOT" -B "$WORK/glint-build" -DCMAKE_BUILD_TYPE=Release -DGLINT_NATIVE=OFF \
    -DCMAKE_C_FLAGS="-march=haswell -g" >/dev/null
cmake --build "$WORK/glint-build" -j "$(nproc)" --target glint >/dev/null
GLINT_SCENE=$ROOT/bench/scenes/bunny-yardstick.json

EMBREE=${GLINT_EMBREE_MESH:-}
if [ -n "$EMBREE" ] && [ -x "$EMBREE/run.sh" ] && [ -f "$EMBREE/scene_args.sh" ]; then
    # The yardstick's renderer as its run.sh builds it, but for AVX2; run.sh itself makes the 1.1M bunny's files.
    if [ "$SCENE" = bunny1m ]; then
        "$EMBREE/run.sh" bunny1m 1 1 "$WORK/warm.pfm" >/dev/null
        GLINT_SCENE=${TMPDIR:-/tmp}/glint-embree-mesh/bunny1m.json
    fi
    for f in render_mesh.c obj_load.c obj_load.h pt_math.h Makefile; do cp "$EMBREE/$f" "$WORK/"; done
    make -s -B -C "$WORK" render_mesh \
        CFLAGS="-std=c11 -O3 -march=haswell -ffp-contract=fast -fno-math-errno -Wall -Wextra -fopenmp -g" >&2
else
    EMBREE=''
    [ "$SCENE" = bunny ] || { echo "bench/instructions.sh: bunny1m needs GLINT_EMBREE_MESH (its run.sh makes the mesh)" >&2; exit 2; }
    echo "(Embree skipped: GLINT_EMBREE_MESH names no embree-mesh directory)" >&2
fi

echo "counting glint's instructions (a minute or more under valgrind)..." >&2
valgrind -q --tool=callgrind --callgrind-out-file="$WORK/glint.cg" --compress-strings=no \
    "$WORK/glint-build/glint" "$GLINT_SCENE" --spp 1 --threads 1 -q -o "$WORK/glint.pfm"
if [ -n "$EMBREE" ]; then
    echo "counting Embree's..." >&2
    # shellcheck disable=SC2046
    EMESH_EMBREE_CONFIG=isa=avx2 valgrind -q --tool=callgrind --callgrind-out-file="$WORK/embree.cg" \
        --compress-strings=no "$WORK/render_mesh" -w 400 -h 300 -s 1 -d 50 -t 1 \
        $("$EMBREE/scene_args.sh" "$SCENE") -o "$WORK/embree.pfm" >"$WORK/embree.out"
fi

# Inclusive instructions of the render loop and of the closest-hit queries, and the number of queries (calls),
# from callgrind's output: the render loop is glint's path_render_tile* / the yardstick's OpenMP region, the
# queries glint's closest_*, bvh_intersect_stream* and coherent_run / Embree's rtcIntersect1. A call of
# coherent_run traces a packet of neighbouring camera rays, so where it runs every one of the 400 x 300 camera rays
# is counted through it rather than by its calls.
python3 - "$WORK" "$SCENE" "$EMBREE" <<'EOF'
import re, sys
work, scene, embree = sys.argv[1], sys.argv[2], sys.argv[3]

def profile(path, is_render, is_query):
    """Self cost per function, and inclusive cost and call count of calls into each function."""
    self_cost, calls = {}, {}
    fn = cfn = None
    pending = None
    for line in open(path):
        if line.startswith('fn='):
            fn = line[3:].strip()
        elif line.startswith('cfn='):
            cfn = line[4:].strip()
        elif line.startswith('calls='):
            pending = int(line[6:].split()[0])
        elif line[:1].isdigit() or line[:1] in '+-*':
            parts = line.split()
            if len(parts) < 2:
                continue
            cost = int(parts[1])
            if pending is not None:  # the inclusive cost of the call just named
                c = calls.setdefault((fn, cfn), [0, 0])
                c[0] += pending
                c[1] += cost
                pending = None
            else:
                self_cost[fn] = self_cost.get(fn, 0) + cost
    # inclusive render cost: calls into render functions from outside them; queries: calls into query functions
    # from outside them
    render = sum(c[1] for (caller, callee), c in calls.items() if is_render(callee) and not is_render(caller))
    q = [c for (caller, callee), c in calls.items() if is_query(callee) and not is_query(caller)]
    packets = sum(c[0] for (caller, callee), c in calls.items()
                  if callee.startswith('coherent_run') and not is_query(caller))
    rays = sum(c[0] for (caller, callee), c in calls.items()
               if is_query(callee) and not is_query(caller) and not callee.startswith('coherent_run'))
    return render, sum(c[1] for c in q), rays + (400 * 300 if packets else 0)

rows = []
g = profile(f'{work}/glint.cg', lambda f: f is not None and f.startswith('path_render_tile'),
            lambda f: f is not None and re.match(r'(closest_(triangles|generic|spheres)|bvh_intersect_stream|coherent_run)', f))
rows.append(('glint', g))
if embree:
    e = profile(f'{work}/embree.cg', lambda f: f is not None and f.startswith('main._omp_fn'),
                lambda f: f == 'rtcIntersect1')
    rows.append(('Embree 3', e))
print(f'Instructions per ray, {scene} scene, 400x300, 1 spp, one thread (callgrind, AVX2 builds)')
print()
print('| renderer | rays | render loop | closest-hit queries | the rest |')
print('|---|---:|---:|---:|---:|')
for name, (render, query, n) in rows:
    if n == 0:
        sys.exit(f'bench/instructions.sh: no closest-hit query found in the {name} profile')
    print(f'| {name} | {n} | {render / n:.0f} | {query / n:.0f} | {(render - query) / n:.0f} |')
EOF
