# checkpoint.sh — --checkpoint and --resume through the program: a render stopped by SIGINT at a random moment
# and resumed (on another thread count, stopped again by SIGTERM, resumed again) writes the uninterrupted render's
# PFM and PNG byte for byte; no temporary file is left; a checkpoint of another render, a truncated or foreign
# file is refused with exit 2 and no image; a checkpoint never replaces the image or the scene.
source "$2/tests/cli/common.bash"

SCENE=$DATA/tiny-path.json
SIZE=(--width 96 --height 64 --spp 1024)
CKP=$TMP/render.ckp

# Stopped by SIGINT somewhere in its first 0.2-0.7 s (of about 1.5 s on one core).
delay=0.$((2 + RANDOM % 6))
"$GLINT" -q "$SCENE" "${SIZE[@]}" --threads 2 --checkpoint "$CKP" -o "$TMP/part.pfm" &
pid=$!
wait_caught $pid INT
sleep "$delay"
kill -INT $pid
wait_for $pid
rc=$?
[[ $rc -eq 0 ]] && echo "note: the render ended before SIGINT came ($delay s); the resume has nothing to do"
check "SIGINT after $delay s: exit 130 (got $rc)" test $rc -eq 130 -o $rc -eq 0
check "SIGINT: the checkpoint is written" test -s "$CKP"
check "SIGINT: no temporary file" no_temp_files "$TMP"
check "SIGINT: the partial image is written too" test -s "$TMP/part.pfm"

# The resume, on one thread, stopped again by SIGTERM; then resumed on two threads to the end.
"$GLINT" -q "$SCENE" "${SIZE[@]}" --threads 1 --resume "$CKP" -o "$TMP/part2.pfm" &
pid=$!
wait_caught $pid TERM
sleep 0.2
kill -TERM $pid
wait_for $pid
rc=$?
check "resume stopped by SIGTERM: exit 143 (got $rc)" test $rc -eq 143 -o $rc -eq 0
check "resume stopped by SIGTERM: no temporary file" no_temp_files "$TMP"
run -q "$SCENE" "${SIZE[@]}" --threads 2 --resume "$CKP" -o "$TMP/resumed.pfm"
check "resumed: exit 0 (got $rc)" test $rc -eq 0
run "$SCENE" "${SIZE[@]}" --threads 1 --resume "$CKP" -o "$TMP/resumed.png"
check "resumed again to a PNG: exit 0 (got $rc)" test $rc -eq 0
check "a complete checkpoint resumes with no sample to render" grep -q ' 0\.000 Msamples/s\| 0 samples' "$TMP/err"

run -q "$SCENE" "${SIZE[@]}" --threads 2 -o "$TMP/whole.pfm"
run -q "$SCENE" "${SIZE[@]}" --threads 2 -o "$TMP/whole.png"
check "resumed PFM = uninterrupted PFM, byte for byte" cmp -s "$TMP/resumed.pfm" "$TMP/whole.pfm"
check "resumed PNG = uninterrupted PNG, byte for byte" cmp -s "$TMP/resumed.png" "$TMP/whole.png"

# Refused: another seed, another size, another scene, a truncated file, a file that is no checkpoint. Exit 2,
# the message, and no image.
expect 2 "glint: $CKP: checkpoint of another render: it was made for $SCENE with seed 3, this render has seed 4; only --spp may change on resuming" \
    -q "$SCENE" "${SIZE[@]}" --seed 4 --resume "$CKP" -o "$TMP/refused.png"
check "refused: no image" test ! -e "$TMP/refused.png"
expect 2 "glint: $CKP: checkpoint of another render: it was made for $SCENE with size 96x64, this render has size 64x64; only --spp may change on resuming" \
    -q "$SCENE" --width 64 --height 64 --spp 1024 --resume "$CKP" -o "$TMP/refused.png"
sed 's/"fuzz": 0.2/"fuzz": 0.3/' "$SCENE" >"$TMP/other.json"
expect 2 "glint: $CKP: checkpoint of another scene: it was made for $SCENE, and this render's scene $TMP/other.json or a file it reads (mesh, material library, texture, environment map) is not the same" \
    -q "$TMP/other.json" "${SIZE[@]}" --resume "$CKP" -o "$TMP/refused.png"
head -c 1000 "$CKP" >"$TMP/cut.ckp"
expect 2 "glint: $TMP/cut.ckp: truncated checkpoint: 1000 bytes, expected $(size "$CKP")" \
    -q "$SCENE" "${SIZE[@]}" --resume "$TMP/cut.ckp" -o "$TMP/refused.png"
expect 2 "glint: $TMP/whole.png: not a glint checkpoint (no GLINTCKP signature), expected a file written by glint's --checkpoint" \
    -q "$SCENE" "${SIZE[@]}" --resume "$TMP/whole.png" -o "$TMP/refused.png"
expect 2 "glint: $TMP/none.ckp: cannot open the checkpoint: No such file or directory, expected a file written by glint's --checkpoint" \
    -q "$SCENE" "${SIZE[@]}" --resume "$TMP/none.ckp" -o "$TMP/refused.png"
check "refused: still no image" test ! -e "$TMP/refused.png"
check "refused: the checkpoint is unchanged" cmp -s <(head -c 1000 "$CKP") "$TMP/cut.ckp"

# A checkpoint may not replace the image or the scene; the flags need a file name.
expect 2 "glint: --checkpoint: $TMP/x.png: cannot write: it is the output image, which would be lost" \
    -q "$SCENE" --checkpoint "$TMP/x.png" -o "$TMP/x.png"
cp "$SCENE" "$TMP/scene.json"
expect 2 "glint: --checkpoint: $TMP/scene.json: cannot write: it is the scene file, which would be lost" \
    -q "$TMP/scene.json" --checkpoint "$TMP/scene.json" -o "$TMP/x.png"
expect 2 "glint: --resume: empty file name, expected a checkpoint file name" -q "$SCENE" --resume ""
expect 1 "glint: $TMP/missing/a.ckp: cannot write: No such file or directory" \
    -q "$SCENE" --checkpoint "$TMP/missing/a.ckp" -o "$TMP/x.png"
check "nothing written for refused checkpoints" test ! -e "$TMP/x.png"

run --help
check "--help documents --checkpoint and --resume" grep -q -- '--checkpoint FILE.*--resume FILE' <(tr '\n' ' ' <"$TMP/out")

summary
