# trace.sh — --trace FILE.json: a Chrome trace-event timeline that parses as JSON and holds the thread names, one
# event per tile pass, the BVH build and the image write, on 1 and 2 threads; the same image bytes with or without
# it; a stopped render's trace; the files it refuses to write (before rendering), and nothing left behind.
# The JSON checks need python3 (tests/cli/trace_check.py; .ci/run installs it).
source "$2/tests/cli/common.bash"
CHECK_TRACE=(python3 "$SRC/tests/cli/trace_check.py")

PATHS=$DATA/tiny-path.json
SIZE=(--width 64 --height 40 --spp 40) # 4 x 3 tiles of 16x16; passes of 16, 16 and 8 samples

run --quiet "${SIZE[@]}" --threads 2 -o "$TMP/plain.png" "$PATHS"
check "a render without --trace exits 0" test "$rc" -eq 0
for threads in 1 2; do
    run --quiet "${SIZE[@]}" --threads $threads --trace "$TMP/t$threads.json" -o "$TMP/traced$threads.png" "$PATHS"
    check "--trace on $threads thread(s): exit 0 (got $rc)" test "$rc" -eq 0
    check "--trace on $threads thread(s): nothing printed with --quiet" test ! -s "$TMP/err"
    check "--trace on $threads thread(s): the trace holds every tile pass and the stages" \
        "${CHECK_TRACE[@]}" "$TMP/t$threads.json" 12 3 $threads
    check "--trace on $threads thread(s): the same image bytes as without it" \
        cmp -s "$TMP/plain.png" "$TMP/traced$threads.png"
done
check "the trace is a JSON object of traceEvents" test "$(head -c 16 "$TMP/t1.json")" == '{"traceEvents":['

# A mesh: its reading is an event of its own, on the main row.
run --quiet --trace "$TMP/mesh.json" -o "$TMP/mesh.png" "$DATA/warn.json"
check "--trace with a mesh: exit 0" test "$rc" -eq 0
check "--trace with a mesh: an \"OBJ read\" event naming the file" \
    python3 -c 'import json, sys; e = [e for e in json.load(open(sys.argv[1]))["traceEvents"] if e["name"] == "OBJ read"]
sys.exit(not (len(e) == 1 and e[0]["args"]["file"].endswith("warn.obj")))' "$TMP/mesh.json"

# A checkpointed render records its checkpoint writes (one after each pass but the last, and the final one).
run --quiet "${SIZE[@]}" --threads 2 --checkpoint "$TMP/c.ckp" --trace "$TMP/ckp.json" -o "$TMP/ckp.png" "$PATHS"
check "--trace with --checkpoint: exit 0" test "$rc" -eq 0
check "--trace with --checkpoint: the same image bytes" cmp -s "$TMP/plain.png" "$TMP/ckp.png"
check "--trace with --checkpoint: 3 checkpoint writes" \
    python3 -c 'import json, sys
sys.exit(sum(e["name"] == "checkpoint write" for e in json.load(open(sys.argv[1]))["traceEvents"]) != 3)' "$TMP/ckp.json"

# A stopped render writes its image and then its trace, where the stopped tile and the unfinished pass say so.
"$GLINT" --quiet --threads 2 --width 16 --height 16 --spp 1000000 --trace "$TMP/stopped.json" \
    -o "$TMP/stopped.png" "$DATA/tiny.json" 2>"$TMP/err" &
pid=$!
wait_caught $pid INT
sleep 0.5
kill -INT $pid
wait_for $pid
rc=$?
check "SIGINT with --trace: exit 130 (got $rc)" test $rc -eq 130
check "SIGINT with --trace: the image is written" test -s "$TMP/stopped.png"
check "SIGINT with --trace: the trace shows the stopped render" \
    "${CHECK_TRACE[@]}" "$TMP/stopped.json" 1 0 2 stopped

# Refused before anything is rendered or written: no image, no trace.
expect 2 "glint: --trace: '' is not a file name, expected the JSON file to write the trace to" --trace "" "$PATHS"
expect 2 "glint: --trace: '-' is not a file name, expected the JSON file to write the trace to" --trace - "$PATHS"
expect 2 "glint: option '--trace' needs a value
Try 'glint --help' for more information." "$PATHS" --trace
mkdir "$TMP/refused"
cd "$TMP/refused" || exit 1
expect 1 "glint: --trace: no/t.json: cannot write: No such file or directory" --trace no/t.json -o x.png "$PATHS"
: >ro.json
chmod a-w ro.json
expect 1 "glint: --trace: ro.json: cannot write: the file is read-only" --trace ro.json -o x.png "$PATHS"
expect 2 "glint: --trace: x.png: cannot write: it is the output image, which would be lost" --trace x.png -o x.png "$PATHS"
cp "$PATHS" scene.json
expect 2 "glint: --trace: scene.json: cannot write: it is the scene file, which would be lost" \
    --trace scene.json -o x.png scene.json
expect 2 "glint: --trace: c.ckp: cannot write: it is the checkpoint, which would be lost" \
    --trace c.ckp --checkpoint c.ckp -o x.png scene.json
cp "$DATA/warn.json" "$DATA/warn.obj" .
expect 2 "glint: --trace: warn.obj: cannot write: the scene reads it (a mesh, texture or environment map), which would be lost" \
    -q --trace warn.obj -o x.png warn.json
check "refused: no image, and the read-only file is untouched" test ! -e x.png -a ! -s ro.json
cd "$TMP" || exit 1
check "no temporary file is left" no_temp_files "$TMP"
# tools/trace_plot.py draws it: a box per tile pass, a row label per thread.
check "tools/trace_plot.py draws the trace as an SVG" python3 "$SRC/tools/trace_plot.py" "$TMP/t2.json" "$TMP/t2.svg"
check "the drawing has a box per tile pass and the rows' names" test "$(grep -c '^<rect.*<title>tile ' "$TMP/t2.svg")" -eq 36 -a \
    "$(grep -c '>worker 1</text>' "$TMP/t2.svg")" -eq 1
check "--help lists --trace" bash -c "'$GLINT' --help | grep -q -- '--trace FILE'"

summary
