# interrupt.sh — SIGINT, SIGTERM and SIGHUP stop a long render: exit 130/143/129, a complete-size image of the
# samples rendered so far, no temporary file left; a second SIGINT aborts without leaving anything half-written;
# a stop while the scene is read (from a FIFO or a pipe that never ends) ends the program within a second.
source "$2/tests/cli/common.bash"

# A render far too long to finish (16x16 pixels, a million samples each), stopped half a second after its
# handlers are installed.
LONG=(--width 16 --height 16 --spp 1000000 "$DATA/tiny.json")

for sig in INT TERM HUP; do
    status=$((128 + $(kill -l $sig)))
    out=$TMP/stopped-$sig.ppm
    "$GLINT" -o "$out" "${LONG[@]}" 2>"$TMP/err-$sig" &
    pid=$!
    wait_caught $pid $sig
    sleep 0.5
    kill -$sig $pid
    wait_for $pid
    rc=$?
    check "SIG$sig: exit $status (got $rc)" test $rc -eq $status
    check "SIG$sig: image written" test -s "$out"
    check "SIG$sig: complete-size P6" test "$(header "$out" 13)" == " P 6 \n 1 6 1 6 \n 2 5 5 \n "
    check "SIG$sig: image size" test "$(size "$out")" -eq $((13 + 16 * 16 * 3))
    # The background is (0.2, 0.3, 0.5): a partial image is not black.
    check "SIG$sig: the image holds rendered samples" test "$(tail -c 768 "$out" | tr -d '\0' | wc -c)" -gt 0
    check "SIG$sig: says it was interrupted" grep -q 'interrupted' "$TMP/err-$sig"
    check "SIG$sig: statistics line" grep -q 'Mrays/s' "$TMP/err-$sig"
done

# A PNG too, and --quiet stays quiet.
"$GLINT" --quiet -o "$TMP/stopped.png" "${LONG[@]}" 2>"$TMP/err-png" &
pid=$!
wait_caught $pid INT
sleep 0.5
kill -INT $pid
wait_for $pid
rc=$?
check "SIGINT with .png: exit 130 (got $rc)" test $rc -eq 130
check "SIGINT with .png: PNG signature" test "$(od -An -tx1 -N 8 "$TMP/stopped.png" | tr -d ' \n')" == 89504e470d0a1a0a
check "SIGINT with .png: size" test "$(be32 "$TMP/stopped.png" 16)x$(be32 "$TMP/stopped.png" 20)" == 16x16
check "SIGINT with --quiet: nothing printed" test ! -s "$TMP/err-png"

# Two SIGINTs at once: the second may abort at once. Either way nothing half-written is left: no
# temporary file, and an image, if there is one, is complete.
"$GLINT" --quiet -o "$TMP/twice.ppm" "${LONG[@]}" 2>/dev/null &
pid=$!
wait_caught $pid INT
sleep 0.5
kill -INT $pid
kill -INT $pid
wait_for $pid
rc=$?
check "two SIGINTs: exit 130 (got $rc)" test $rc -eq 130
if [[ -e $TMP/twice.ppm ]]; then
    check "two SIGINTs: a complete image" test "$(size "$TMP/twice.ppm")" -eq $((13 + 16 * 16 * 3))
fi

# A stop while the scene is being read: the read may never end (a FIFO no one writes, a pipe from a slow
# command), so the program must end within a second, say so (unless --quiet) and write nothing.
# stop_loading SIG SOURCE ARGS...: glint ARGS reads its scene from SOURCE (a FIFO, or "pipe": a pipe from a
# command that prints nothing for 5 s, its own output kept off the test's) and gets SIG 0.3 s after it catches
# it. $rc: its status, or 255 if it still runs a second after; its stderr in $TMP/err-load.
stop_loading() {
    local sig=$1 source=$2
    shift 2
    if [[ $source == pipe ]]; then
        sleep 5 2>/dev/null | "$GLINT" "$@" - 2>"$TMP/err-load" &
    else
        "$GLINT" "$@" "$source" 2>"$TMP/err-load" &
    fi
    local pid=$!
    wait_caught $pid "$sig"
    sleep 0.3
    kill -"$sig" $pid
    wait_for $pid 10
    rc=$?
}

mkfifo "$TMP/fifo.json"
for sig in INT TERM HUP; do
    status=$((128 + $(kill -l $sig)))
    stop_loading $sig "$TMP/fifo.json" -o "$TMP/fifo.png"
    check "SIG$sig while opening a FIFO: exit $status within a second (got $rc)" test $rc -eq $status
    check "SIG$sig while opening a FIFO: says so" test "$(cat "$TMP/err-load")" == "glint: interrupted while loading the scene"
    check "SIG$sig while opening a FIFO: no image" test ! -e "$TMP/fifo.png"
done
stop_loading INT pipe -o "$TMP/pipe.png"
check "SIGINT while reading a pipe: exit 130 within a second (got $rc)" test $rc -eq 130
check "SIGINT while reading a pipe: says so" test "$(cat "$TMP/err-load")" == "glint: interrupted while loading the scene"
check "SIGINT while reading a pipe: no image" test ! -e "$TMP/pipe.png"
stop_loading TERM pipe --quiet -o "$TMP/pipe.png"
check "SIGTERM while reading a pipe, --quiet: exit 143 within a second (got $rc)" test $rc -eq 143
check "SIGTERM while reading a pipe, --quiet: nothing printed" test ! -s "$TMP/err-load"

check "no temporary files left" no_temp_files "$TMP"
summary
