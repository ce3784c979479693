# bench_tools.sh — the benchmark's own tools, which nothing else would test until the owner's next long run:
# bench/subdivide.c and bench/decimate.c (built by CMake with the project's warnings), the mesh yardstick's
# scene for glint, bench/equal_error.sh on a tiny scene, bench/run.sh's options (it stops before building
# anything), bench/stats.bash's median and its interval, and bench/plot.sh on made-up data (where gnuplot is
# installed). Nothing here is timed.
# usage: bash tests/bench_tools.sh GLINT SOURCE_DIR SUBDIVIDE DECIMATE
source "$2/tests/cli/common.bash"
SUBDIVIDE=$3
DECIMATE=$4
BUNNY=$SRC/scenes/meshes/stanford-bunny/stanford-bunny.obj

# faces FILE / verts FILE: its `f` / `v` lines; indices_ok FILE: every face index names a vertex
faces() { grep -c '^f ' "$1"; }
verts() { grep -c '^v ' "$1"; }
indices_ok() { awk '/^v / { n++ } /^f / { for (i = 2; i <= NF; i++) if ($i < 1 || $i > n) bad++ } END { exit bad > 0 }' "$1"; }

# --- subdivide: a closed tetrahedron stays closed (V - E + F = 2) and quadruples its triangles per level
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n' >"$TMP/tet.obj"
"$SUBDIVIDE" "$TMP/tet.obj" "$TMP/tet2.obj" 2 2>"$TMP/err"
st=$?
check "subdivide: exit 0 ($(cat "$TMP/err"))" test "$st" -eq 0
check "subdivide: 4 x 16 triangles" test "$(faces "$TMP/tet2.obj")" -eq 64
# 64 triangles, 96 edges: a closed surface of genus 0 has 96 - 64 + 2 = 34 vertices
check "subdivide: 34 vertices, no edge midpoint made twice" test "$(verts "$TMP/tet2.obj")" -eq 34
check "subdivide: the header gives the counts run.sh reads" grep -q '^# .*: 34 vertices, 64 triangles$' "$TMP/tet2.obj"
check "subdivide: every index names a vertex" indices_ok "$TMP/tet2.obj"
"$SUBDIVIDE" "$TMP/tet.obj" "$TMP/x.obj" 7 2>"$TMP/err"
st=$?
check "subdivide: LEVELS 7 is a usage error" test "$st" -eq 2
check "subdivide: LEVELS 7 says why" grep -q 'LEVELS must be an integer in 0..6' "$TMP/err"
printf 'v 0 0 0\nf 1 2 3\n' >"$TMP/bad.obj"
"$SUBDIVIDE" "$TMP/bad.obj" "$TMP/x.obj" 1 2>"$TMP/err"
st=$?
check "subdivide: a bad index fails" test "$st" -eq 1
check "subdivide: a bad index is named with its line" grep -q "bad.obj:2: vertex index 2 out of range" "$TMP/err"
"$SUBDIVIDE" "$TMP/missing.obj" "$TMP/x.obj" 1 2>"$TMP/err"
st=$?
check "subdivide: a missing file fails" test "$st" -eq 1

# --- decimate: the bunny to about 10,000 triangles, deterministic, valid
"$DECIMATE" "$BUNNY" "$TMP/d1.obj" 10000 2>"$TMP/err"
st=$?
check "decimate: exit 0 ($(cat "$TMP/err"))" test "$st" -eq 0
n=$(faces "$TMP/d1.obj")
check "decimate: about 10,000 triangles (got $n)" test "$n" -ge 9000 -a "$n" -le 11000
check "decimate: the header gives the count" grep -q "^# .*: $(verts "$TMP/d1.obj") vertices, $n triangles$" "$TMP/d1.obj"
check "decimate: every index names a vertex" indices_ok "$TMP/d1.obj"
check "decimate: no degenerate triangle (two corners the same vertex)" \
    awk '/^f / && ($2 == $3 || $3 == $4 || $4 == $2) { bad++ } END { exit bad > 0 }' "$TMP/d1.obj"
"$DECIMATE" "$BUNNY" "$TMP/d2.obj" 10000 2>/dev/null
check "decimate: the same bytes twice" cmp -s "$TMP/d1.obj" "$TMP/d2.obj"
"$DECIMATE" "$TMP/tet.obj" "$TMP/x.obj" 4 2>"$TMP/err"
st=$?
check "decimate: as many triangles as the input is a usage error" test "$st" -eq 2
"$DECIMATE" "$TMP/tet.obj" "$TMP/x.obj" 0 2>"$TMP/err"
st=$?
check "decimate: 0 triangles is a usage error" test "$st" -eq 2

# --- the mesh yardstick's scene, for glint: it renders (its camera and objects are checked against the
# yardstick's by bench/run.sh's image means, where the yardstick is)
run -q --width 8 --height 6 --spp 1 "$SRC/bench/scenes/bunny-yardstick.json" -o "$TMP/y.pfm"
check "bench/scenes/bunny-yardstick.json renders (exit $rc: $(head -c 300 "$TMP/err"))" test "$rc" -eq 0
sed "s|\"file\": \"[^\"]*\"|\"file\": \"$TMP/d1.obj\"|" "$SRC/bench/scenes/bunny-yardstick.json" >"$TMP/y10k.json"
run -q --width 8 --height 6 --spp 1 "$TMP/y10k.json" -o "$TMP/y10k.pfm"
check "the yardstick's scene with the decimated bunny renders (exit $rc: $(head -c 300 "$TMP/err"))" test "$rc" -eq 0

# --- bench/yard_meshes.py: a PLY (ASCII, and binary gzip-compressed) and a glTF binary with node transforms, put in
# the bunny's place: the triangles fanned and counted, the largest extent the bunny's, standing on its lowest point
printf 'ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n2 0 0\n2 1 0\n0 1 0\n1 3 1\n4 0 1 2 3\n3 0 1 4\n' >"$TMP/quad.ply"
python3 "$SRC/bench/yard_meshes.py" "$TMP/quad.ply" "$BUNNY" "$TMP/quad.obj" 2>"$TMP/err"
st=$?
check "yard_meshes.py: an ASCII PLY (exit $st: $(cat "$TMP/err"))" test "$st" -eq 0
check "yard_meshes.py: the quad fanned, the header gives the count run.sh reads" grep -q ': 3 triangles$' "$TMP/quad.obj"
check "yard_meshes.py: 3 faces, every index names a vertex" test "$(faces "$TMP/quad.obj")" -eq 3 -a "$(indices_ok "$TMP/quad.obj"; echo $?)" -eq 0
# extents (x, y, z max - min) and lowest y of an OBJ file's vertices
extent() { awk '/^v / { for (k = 2; k <= 4; k++) { if (!(k in lo) || $k < lo[k]) lo[k] = $k; if (!(k in hi) || $k > hi[k]) hi[k] = $k } }
    END { e = 0; for (k = 2; k <= 4; k++) if (hi[k] - lo[k] > e) e = hi[k] - lo[k]; printf "%.5f %.5f\n", e, lo[3] }' "$1"; }
check "yard_meshes.py: the largest extent and the lowest point are the bunny's ($(extent "$TMP/quad.obj") against $(extent "$BUNNY"))" \
    test "$(extent "$TMP/quad.obj")" = "$(extent "$BUNNY")"
python3 - "$SRC/tests/data/models/quad-uv.ply" "$TMP/quad-bin.ply.gz" <<'PY'
import gzip, sys
gzip.open(sys.argv[2], "wb").write(open(sys.argv[1], "rb").read())
PY
python3 "$SRC/bench/yard_meshes.py" "$TMP/quad-bin.ply.gz" "$BUNNY" "$TMP/quad-bin.obj" 2>"$TMP/err"
st=$?
check "yard_meshes.py: a binary PLY, gzip-compressed (exit $st: $(cat "$TMP/err"))" test "$st" -eq 0 -a "$(faces "$TMP/quad-bin.obj")" -eq 2
python3 "$SRC/bench/yard_meshes.py" "$SRC/tests/data/models/deep-nodes.gltf" "$BUNNY" "$TMP/x.obj" 2>"$TMP/err"
st=$?
check "yard_meshes.py: a .gltf (not binary) is refused with a message" test "$st" -ne 0 -a -s "$TMP/err"
python3 "$SRC/bench/yard_meshes.py" "$SRC/bench/meshes/2cylinder-engine/2CylinderEngine.glb" "$BUNNY" "$TMP/engine.obj" 2>"$TMP/err"
st=$?
check "yard_meshes.py: the engine (GLB, 82 nodes) gives 121,496 triangles (exit $st: $(cat "$TMP/err"))" \
    grep -q ': 121496 triangles$' "$TMP/engine.obj"
check "yard_meshes.py: the engine's largest extent and lowest point are the bunny's" test "$(extent "$TMP/engine.obj")" = "$(extent "$BUNNY")"

# --- bench/run.sh: its options, checked before it builds or measures anything
bash "$SRC/bench/run.sh" --help >"$TMP/help" 2>&1
st=$?
check "run.sh --help: exit 0" test "$st" -eq 0
for word in meshyard meshscale --threads --mesh-spp --mesh-max --no-plots --meshyard-meshes GLINT_EMBREE_MESH GLINT_EMBREE_PROBE; do
    check "run.sh --help names $word" grep -q -- "$word" "$TMP/help"
done
for bad in "--only meshes" "--threads 0" "--threads 1,x" "--mesh-spp 0" "--mesh-max many" "--runs -1" "--bogus"; do
    # shellcheck disable=SC2086 # each case is an option and its value
    bash "$SRC/bench/run.sh" $bad >/dev/null 2>"$TMP/err"
    st=$?
    check "run.sh $bad: exit 2 with a message ($(cat "$TMP/err"))" test "$st" -eq 2 -a -s "$TMP/err"
done

# --- bench/instructions.sh: a scene it does not know is refused before anything is built (it needs valgrind to run)
bash "$SRC/bench/instructions.sh" rtiow >/dev/null 2>"$TMP/err"
st=$?
check "instructions.sh rtiow: exit 2 with its usage ($(cat "$TMP/err"))" test "$st" -eq 2 -a -s "$TMP/err"

# --- bench/equal_error.sh: the table and the ratio on a tiny scene (glint against itself), and its refusals
bash "$SRC/bench/equal_error.sh" "$GLINT" "$GLINT" "$SRC/tests/data/tiny-path.json" --spp 2,8 --seeds 2 --ref-spp 32 \
    --out "$TMP/ee" -- --width 160 --height 120 >"$TMP/ee.out" 2>"$TMP/err"
st=$?
check "equal_error.sh: exit 0 ($(tail -1 "$TMP/err"))" test "$st" -eq 0
check "equal_error.sh: a row per binary and sample count" test "$(grep -cE '^\| [AB] \| (2|8) \| [0-9.]+ \| [0-9.e-]+ \|$' "$TMP/ee.out")" -eq 4
check "equal_error.sh: the errors fall with the samples" awk '$2 == "A" && $4 == 2 { e2 = $8 } $2 == "A" && $4 == 8 { e8 = $8 } END { exit !(e8 < e2) }' "$TMP/ee.out"
check "equal_error.sh: the equal-error ratio" grep -qE "^A: error ~ time\^-[0-9.]+; .* [0-9.]+$" "$TMP/ee.out"
check "equal_error.sh: 2 seeds x 2 counts x 2 binaries and the reference" test "$(ls "$TMP/ee"/*.pfm | wc -l)" -eq 9
bash "$SRC/bench/equal_error.sh" "$GLINT" "$GLINT" "$SRC/tests/data/tiny-path.json" --spp 0 >/dev/null 2>"$TMP/err"
st=$?
check "equal_error.sh: --spp 0 is a usage error" test "$st" -eq 2
check "equal_error.sh: --spp 0 says why" grep -q "'0' is not a positive whole number" "$TMP/err"
bash "$SRC/bench/equal_error.sh" "$GLINT" "$TMP/none" "$SRC/tests/data/tiny-path.json" >/dev/null 2>"$TMP/err"
st=$?
check "equal_error.sh: a missing binary is a usage error" test "$st" -eq 2

# --- bench/plot.sh on made-up data
bash "$SRC/bench/plot.sh" >/dev/null 2>&1
st=$?
check "plot.sh without a directory: exit 2" test "$st" -eq 2
bash "$SRC/bench/plot.sh" "$TMP/none" >/dev/null 2>&1
st=$?
check "plot.sh on a missing directory: exit 2" test "$st" -eq 2

# --- stats.bash: the median and its distribution-free interval (order statistics of a binomial count)
source "$SRC/bench/stats.bash"
check "median of 3 1 2: 2" test "$(printf '3\n1\n2\n' | median)" = 2
check "median of 4 1 2 3: 2.5" test "$(printf '4\n1\n2\n3\n' | median)" = 2.5
check "median of nothing: nan" test "$(median </dev/null)" = nan
check "median_interval of 4 numbers: nan (not 90 %)" test "$(seq 4 | median_interval)" = nan
check "median_interval of 5: the extremes, 93 %" test "$(seq 5 | median_interval)" = "1.000-5.000 (93 %)"
check "median_interval of 9: 2nd to 8th, 96 %" test "$(seq 9 -1 1 | median_interval)" = "2.000-8.000 (96 %)"
check "median_interval of 11: 3rd to 9th, 93 %" test "$(seq 11 | median_interval)" = "3.000-9.000 (93 %)"
check "median_interval of 21: 7th to 15th, 92 %" test "$(seq 21 | median_interval)" = "7.000-15.000 (92 %)"
if command -v gnuplot >/dev/null; then
    mkdir "$TMP/run"
    printf '# bench renderer threads oversubscribed mrays speedup\nbunny glint 1 0 4.7 1.00\nbunny glint 2 0 8.1 1.72\nbunny embree-mesh 1 0 7.6 1.00\nbunny embree-mesh 2 0 13.9 1.83\nbunny glint 4 1 8.0 1.70\n' >"$TMP/run/speedup.dat"
    printf '# case glint_mrays embree_mrays glint_over_embree\nbunny/1t 4.7 7.6 0.63\nrtiow-final/1t 9.8 nan nan\n' >"$TMP/run/versus.dat"
    printf '# scene triangles threads oversubscribed embree_mrays glint_mrays glint_over_embree embree_build_s glint_build_s embree_load_build_render_s glint_process_s embree_runsh_s process_embree_over_glint\nbunny1m 1111216 2 0 8.07 4.75 0.62 0.9 0.6 2.1 2.4 2.2 0.88\n' >"$TMP/run/meshyard.dat"
    printf '# mesh triangles renderer ns_per_ray build_s load_s peak_rss_mb bytes_per_triangle\nbunny-10k 9979 glint 150 0.01 0.02 9.7 1020\nbunny 69451 glint 200 0.05 0.05 17 261\nbunny 69451 embree-mesh 130 0.1 0.02 17 262\n' >"$TMP/run/meshscale.dat"
    bash "$SRC/bench/plot.sh" "$TMP/run" 2>"$TMP/err"
    st=$?
    check "plot.sh: exit 0 ($(cat "$TMP/err"))" test "$st" -eq 0
    for svg in speedup mrays process scale-nsray scale-build scale-memory; do
        check "plot.sh wrote $svg.svg" grep -q '<svg' "$TMP/run/$svg.svg"
    done
    check "plot.sh: the run's name in the titles" grep -q '>run<' "$TMP/run/speedup.svg"
    check "plot.sh leaves no temporary file" test "$(find "${TMPDIR:-/tmp}" -maxdepth 1 -name 'glint-plot.*' -newer "$TMP/run/speedup.dat" | wc -l)" -eq 0
else
    echo "plot.sh's drawing not tested: gnuplot is not installed (Debian: gnuplot-nox)"
fi
summary
