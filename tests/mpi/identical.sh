# identical.sh — glint-mpi on 1, 2 and 3 ranks (1 or 2 threads each) renders every scene of scenes/, at a small
# size, to exactly glint's image: the PFM (each pixel's linear mean as a float) and a PNG; a region too.
source "$3/tests/mpi/common.bash"

# 3x2 tiles with a clipped edge; passes of 16 and 2 samples, so that running sums travel between ranks.
SIZE=(--width 40 --height 24 --spp 18)
SCENES=("$SRC"/scenes/*.json)
# Under the sanitizers Open MPI takes seconds to start and end: three scenes (Whitted, path tracer with
# meshes, environment map) stand for the others there.
[[ -n ${GLINT_SANITIZE:-} ]] && SCENES=("$SRC"/scenes/{paper,cornell-box-obj,envmap-spheres}.json)
i=0
for scene in "${SCENES[@]}"; do
    name=$(basename "$scene" .json)
    "$GLINT" -q "${SIZE[@]}" "$scene" -o "$TMP/$name.pfm"
    for np in 1 2 3; do
        threads=$(((np + i) % 2 + 1))
        "${MPIRUN[@]}" -np $np "$GLINT_MPI" -q "${SIZE[@]}" --threads $threads "$scene" -o "$TMP/$name-$np.pfm" \
            2>"$TMP/err"
        check "$name, $np ranks x $threads threads: exit 0, nothing said: $(cat "$TMP/err")" test $? -eq 0 -a ! -s "$TMP/err"
        check "$name, $np ranks x $threads threads: glint's PFM" cmp -s "$TMP/$name.pfm" "$TMP/$name-$np.pfm"
    done
    i=$((i + 1))
done

# A scene on standard input: rank 0 reads it and sends it to the others.
"$GLINT" -q "${SIZE[@]}" - <"$DATA/tiny-path.json" -o "$TMP/stdin.pfm"
"${MPIRUN[@]}" -np 3 "$GLINT_MPI" -q "${SIZE[@]}" --threads 1 - <"$DATA/tiny-path.json" -o "$TMP/stdin-3.pfm"
check "a scene on standard input, 3 ranks: exit 0" test $? -eq 0
check "a scene on standard input, 3 ranks: glint's PFM" cmp -s "$TMP/stdin.pfm" "$TMP/stdin-3.pfm"

# A time limit ends the render after a whole pass: the image of the samples per pixel reached, exactly.
"${MPIRUN[@]}" -np 2 "$GLINT_MPI" --threads 1 --spp 1000000 --time-limit 1 "$DATA/tiny-path.json" \
    -o "$TMP/limited.pfm" 2>"$TMP/err"
check "--time-limit 1: exit 0" test $? -eq 0
spp=$(sed -n 's/^glint-mpi: time limit of 1 s reached: \([0-9]*\) of 1000000 samples per pixel rendered$/\1/p' "$TMP/err")
check "--time-limit 1: says how many samples per pixel ($spp)" test -n "$spp"
"$GLINT" -q --spp "${spp:-1}" "$DATA/tiny-path.json" -o "$TMP/limited-glint.pfm"
check "--time-limit 1: glint's image at $spp samples per pixel" cmp -s "$TMP/limited.pfm" "$TMP/limited-glint.pfm"

# A region of a PNG (its glint:region chunk included), with the statistics lines.
ARGS=(--width 64 --height 40 --spp 40 --region 5,3,37,29 "$SRC/scenes/cornell-box.json") # passes of 16, 16, 8
"$GLINT" -q "${ARGS[@]}" -o "$TMP/region.png"
"${MPIRUN[@]}" -np 3 "$GLINT_MPI" --threads 1 "${ARGS[@]}" -o "$TMP/region-3.png" 2>"$TMP/err"
check "region on 3 ranks: exit 0" test $? -eq 0
check "region on 3 ranks: glint's PNG" cmp -s "$TMP/region.png" "$TMP/region-3.png"
check "the statistics line" grep -q '^glint-mpi: .* s wall, .* Mrays/s (3 threads)' "$TMP/err"
check "the shares of the 3 ranks" grep -Eq '^glint-mpi: 3 ranks; .* 0: [0-9]+ units, .* 1: .* 2: [0-9]+ units' "$TMP/err"
check "the traffic of rank 0" grep -Eq '^glint-mpi: traffic of rank 0: [0-9]+ messages' "$TMP/err"
units=$(grep -o '[0-9]* units' "$TMP/err" | awk '{ n += $1 } END { print n }')
check "the shares add up to every tile pass: 3x2 tiles x 3 passes = 18 (got $units)" test "$units" = 18

summary
