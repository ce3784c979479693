# limits.sh — standard input is read up to the scene limit and no further, running out of memory exits 1
# with "out of memory", and output names as long as a file name may be are written.
source "$(dirname "$0")/common.bash" "$@"

# stdin_expect STATUS STDERR PRODUCER...: the producer's output piped into `glint - -o x.png`.
stdin_expect() {
    local status=$1 message=$2
    shift 2
    "$@" 2>/dev/null | "$GLINT" - -o "$TMP/x.png" >"$TMP/out" 2>"$TMP/err"
    rc=${PIPESTATUS[1]}
    local got
    got=$(cat "$TMP/err")
    if [[ $rc -eq $status && $got == "$message" ]]; then pass; else fail "$* | glint -: exit $rc (expected $status): $got"; fi
}

too_large="glint: standard input: the scene is larger than 268435456 bytes (256 MiB)"
# One byte over the limit, and an endless stream: refused after reading the limit and one byte more.
stdin_expect 2 "$too_large" head -c $((256 * 1024 * 1024 + 1)) /dev/zero
stdin_expect 2 "$too_large" cat /dev/zero
check "nothing written" test ! -e "$TMP/x.png"

# Out of memory while reading standard input: a resource failure (exit 1), not bad input. AddressSanitizer
# reserves terabytes of address space, so `ulimit -v` cannot be used in such builds.
if grep -qa __asan_init "$GLINT"; then
    echo "skipped the ulimit -v case: glint is built with AddressSanitizer"
else
    # The limit applies to glint only: the subshell limits itself, then runs it.
    head -c 200M /dev/zero | (ulimit -v 131072 && exec "$GLINT" - -o "$TMP/x.png") >"$TMP/out" 2>"$TMP/err"
    rc=${PIPESTATUS[1]}
    got=$(cat "$TMP/err")
    want="glint: standard input: out of memory while reading the scene"
    if [[ $rc -eq 1 && $got == "$want" ]]; then pass; else fail "ulimit -v: exit $rc (expected 1): $got"; fi
fi

# Output names up to NAME_MAX (255) bytes: the temporary file beside it must fit too.
for n in 244 255; do
    name=$(printf '%*s' $((n - 4)) '' | tr ' ' a).ppm
    run "$DATA/tiny.json" -q -o "$TMP/$name"
    check "an output name of $n bytes is written (exit $rc: $(cat "$TMP/err"))" test $rc -eq 0 -a -s "$TMP/$name"
    check "no temporary file left beside the $n-byte name" no_temp_files "$TMP"
done

summary
