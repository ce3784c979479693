# threads.sh — every scene of scenes/ renders the same bytes on one thread and on two (at a small size and
# sample count, so that the whole set takes seconds): the promise each new feature must keep. And the default
# thread count honours the CPU affinity mask (taskset).
source "$2/tests/cli/common.bash"

# Scenes of glTF models (gltf-*.json) need assimp, an optional dependency: skipped where glint was built without it.
"$GLINT" -q --width 8 --height 8 --spp 1 "$SRC/scenes/gltf-boxes.json" -o "$TMP/probe.ppm" 2>"$TMP/err"
grep -q "built without it" "$TMP/err" && no_assimp=1 || no_assimp=0
for scene in "$SRC"/scenes/*.json; do
    name=$(basename "$scene" .json)
    [[ $no_assimp == 1 && $name == gltf-* ]] && continue
    for threads in 1 2; do
        run -q --width 40 --height 24 --spp 3 --threads $threads "$scene" -o "$TMP/$name-$threads.pfm"
        check "$name on $threads thread(s): exit 0 (got $rc: $(head -c 300 "$TMP/err"))" test "$rc" -eq 0
    done
    check "$name: the same bytes on 1 and 2 threads" cmp -s "$TMP/$name-1.pfm" "$TMP/$name-2.pfm"
done

# The default thread count is the CPUs glint may run on: under taskset -c 0, one thread, as glint-mpi counts.
if command -v taskset >/dev/null && taskset -c 0 true 2>/dev/null; then
    taskset -c 0 "$GLINT" --width 8 --height 8 --spp 1 "$SRC/scenes/paper.json" -o "$TMP/one.ppm" 2>"$TMP/err"
    check "under taskset -c 0 the default is 1 thread: $(cat "$TMP/err")" grep -q "(1 thread)" "$TMP/err"
    taskset -c 0 "$GLINT" --help >"$TMP/out" 2>&1
    check "--help says 1 CPU here under taskset -c 0" grep -q "may run on (1 here)" "$TMP/out"
else
    echo "note: no taskset here, the affinity default is not tested"
fi
summary
