# faults.sh — what ends a glint-mpi job, and how: a scene that one rank cannot read ends every rank with that
# rank's message (no hang, no image); a bad scene or flag is said once; Ctrl-C to mpirun, or a signal to one
# rank, writes the image of the passes completed so far; a rank killed mid-render ends the job.
source "$3/tests/mpi/common.bash"

# rank_pid MPIRUN_PID RANK: the process id of that rank (Open MPI names its rank in its environment).
rank_pid() {
    local p
    for _ in $(seq 100); do
        for p in $(pgrep -P "$1"); do
            if tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$2"; then
                echo "$p"
                return
            fi
        done
        sleep 0.1
    done
}

# started FILE: waits (up to 30 s) until rank 0 has said that the render began, then half a second more.
started() {
    for _ in $(seq 300); do
        grep -q '^glint-mpi: rendering' "$1" && break
        sleep 0.1
    done
    sleep 0.5
}

# A scene file that is not the same on every node: rank 0 reads a good one, ranks 1 and 2 (started in another
# working directory, as on a node whose disk differs) a broken one, then none at all.
mkdir -p "$TMP/a" "$TMP/b"
cp "$DATA/tiny.json" "$TMP/a/scene.json"
printf '{\n  "render": {"width": 4,,}\n}\n' >"$TMP/b/scene.json"
per_node() {
    "${MPIRUN[@]}" -np 1 --wdir "$TMP/a" "$GLINT_MPI" -o "$TMP/one.png" scene.json : \
        -np 2 --wdir "$TMP/b" "$GLINT_MPI" -o "$TMP/one.png" scene.json >"$TMP/out" 2>"$TMP/err" &
    wait_for $! 300
    rc=$?
}
per_node
check "a bad scene on ranks 1 and 2: the job ends, not zero (got $rc)" test $rc -ne 0 -a $rc -ne 255
check "a bad scene on ranks 1 and 2: rank 1's message, once" \
    test "$(grep -c "^glint-mpi: rank 1 ([^)]*): scene.json:2:25: expected a key in double quotes, got ','$" \
        "$TMP/err")" -eq 1
check "a bad scene on ranks 1 and 2: nothing else from glint-mpi" test "$(grep -c glint-mpi "$TMP/err")" -eq 1
check "a bad scene on ranks 1 and 2: no image" test ! -e "$TMP/one.png"
rm "$TMP/b/scene.json"
per_node
check "no scene on ranks 1 and 2: the job ends, not zero (got $rc)" test $rc -ne 0 -a $rc -ne 255
check "no scene on ranks 1 and 2: rank 1's message" \
    grep -q "^glint-mpi: rank 1 ([^)]*): scene.json: cannot open: No such file or directory$" "$TMP/err"
check "no scene on ranks 1 and 2: no image" test ! -e "$TMP/one.png"

# A scene that is bad everywhere, or a bad flag: the message once, from rank 0, and exit status 2.
printf '{\n  "render": {"width": 4,,}\n}\n' >"$TMP/bad.json"
"${MPIRUN[@]}" -np 3 "$GLINT_MPI" -o "$TMP/bad.png" "$TMP/bad.json" >"$TMP/out" 2>"$TMP/err"
rc=$?
check "a bad scene on every rank: exit 2 (got $rc)" test $rc -eq 2
check "a bad scene on every rank: said once, as glint says it" \
    test "$(grep -c glint-mpi "$TMP/err")" -eq 1 -a \
    "$(grep glint-mpi "$TMP/err")" == "glint-mpi: $TMP/bad.json:2:25: expected a key in double quotes, got ','"
"${MPIRUN[@]}" -np 2 "$GLINT_MPI" --spp 0 "$DATA/tiny.json" >"$TMP/out" 2>"$TMP/err"
rc=$?
check "--spp 0: exit 2 (got $rc)" test $rc -eq 2
check "--spp 0: glint's message, once" test "$(grep -c 'glint-mpi' "$TMP/err")" -eq 1 -a \
    "$(grep -c "^glint-mpi: --spp: 0 is out of range, expected an integer in \[1, 1000000\]$" "$TMP/err")" -eq 1
# glint's options that the ranks do not carry are refused, not ignored.
for flag in "--aov depth" --preview "--checkpoint $TMP/c.ckp" "--resume $TMP/c.ckp" "--trace $TMP/t.json"; do
    # shellcheck disable=SC2086 # the flag and its value are two words
    "${MPIRUN[@]}" -np 2 "$GLINT_MPI" $flag -o "$TMP/x.exr" "$DATA/tiny.json" >"$TMP/out" 2>"$TMP/err"
    rc=$?
    check "$flag: exit 2 (got $rc)" test $rc -eq 2
    check "$flag: refused once, by name" test "$(grep -c "^glint-mpi: ${flag%% *} is not supported by glint-mpi (use glint)$" "$TMP/err")" -eq 1
done
# Adaptive sampling's counts and half-buffers are not in the ranks' messages either: a threshold is refused.
"${MPIRUN[@]}" -np 2 "$GLINT_MPI" --noise-threshold 0.01 -o "$TMP/x.pfm" "$DATA/tiny-path.json" >"$TMP/out" 2>"$TMP/err"
rc=$?
check "--noise-threshold: exit 2 (got $rc)" test $rc -eq 2
check "--noise-threshold: refused once" test "$(grep -c 'adaptive sampling .* is not supported by glint-mpi' "$TMP/err")" -eq 1
"${MPIRUN[@]}" -np 2 "$GLINT_MPI" --help >"$TMP/out" 2>"$TMP/err"
check "--help: exit 0, once, naming mpirun" test $? -eq 0 -a "$(grep -c '^usage: mpirun' "$TMP/out")" -eq 1

# A render far too long to finish (16x16 pixels, a million samples each) on two ranks of one thread.
LONG=(--threads 1 --width 16 --height 16 --spp 1000000 "$DATA/tiny.json")
# stopped NAME: checks the image $TMP/NAME.ppm and the messages in $TMP/err-NAME of a stopped render.
stopped() {
    local out=$TMP/$1.ppm
    check "$1: the image is written" test -s "$out"
    check "$1: a complete 16x16 P6" test "$(head -c 13 "$out" | tr '\n' ' ')" == "P6 16 16 255 " -a \
        "$(stat -c %s "$out")" -eq $((13 + 16 * 16 * 3))
    # The background is (0.2, 0.3, 0.5): a partial image is not black.
    check "$1: the image holds rendered samples" test "$(tail -c 768 "$out" | tr -d '\0' | wc -c)" -gt 0
    check "$1: says it was interrupted" grep -q '^glint-mpi: interrupted; writing the .* samples per pixel' \
        "$TMP/err-$1"
    check "$1: no temporary file left" test -z "$(ls -A "$TMP" | grep '\.tmp-')"
}

# Ctrl-C to mpirun: Open MPI sends SIGTERM to every rank (and SIGKILL a second later).
"${MPIRUN[@]}" -np 2 "$GLINT_MPI" "${LONG[@]}" -o "$TMP/ctrl-c.ppm" 2>"$TMP/err-ctrl-c" &
pid=$!
started "$TMP/err-ctrl-c"
kill -INT $pid
wait_for $pid 300
rc=$?
check "Ctrl-C to mpirun: the job ends, not zero (got $rc)" test $rc -ne 0 -a $rc -ne 255
stopped ctrl-c

# SIGTERM to rank 1 alone: it tells rank 0, which stops every rank and writes the image; exit 143.
"${MPIRUN[@]}" -np 2 "$GLINT_MPI" "${LONG[@]}" -o "$TMP/term.ppm" 2>"$TMP/err-term" &
pid=$!
started "$TMP/err-term"
kill -TERM "$(rank_pid $pid 1)"
wait_for $pid 300
rc=$?
check "SIGTERM to rank 1: exit 143 (got $rc)" test $rc -eq 143
stopped term
check "SIGTERM to rank 1: rank 0 says where the stop came from" \
    grep -q '^glint-mpi: rank 1 was stopped by signal 15$' "$TMP/err-term"

# A rank killed mid-render: the launcher notices and ends the job (rank 0 still writes what it has).
"${MPIRUN[@]}" -np 3 "$GLINT_MPI" "${LONG[@]}" -o "$TMP/killed.ppm" 2>"$TMP/err-killed" &
pid=$!
started "$TMP/err-killed"
kill -KILL "$(rank_pid $pid 2)"
wait_for $pid 300
rc=$?
check "rank 2 killed: the job ends, not zero (got $rc)" test $rc -ne 0 -a $rc -ne 255
check "rank 2 killed: the launcher says so" grep -q 'exited on signal 9' "$TMP/err-killed"

summary
