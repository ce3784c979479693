# discarded.sh — a render whose samples come out NaN warns on stderr even with --quiet, writes its image, and
# exits 1 when more than 1 % of the samples were dropped.
source "$2/tests/cli/common.bash"

# A focus distance of 1e38 overflows the camera's vectors: every sample under the sky is NaN.
printf '%s' '{"render":{"width":4,"height":3,"spp":2,"background":"sky"},"camera":{"type":"lookat","focus_distance":1e38},
"lights":[{"type":"ambient","intensity":1}]}' > "$TMP/nan.json"
run --quiet -o "$TMP/nan.ppm" "$TMP/nan.json"
check "all samples dropped: exit 1" test "$rc" -eq 1
check "the warning counts and shares them" \
    grep -qx "glint: warning: 24 of 24 samples (100.0 %) were NaN or infinite and were dropped" "$TMP/err"
check "the image is still written" test -s "$TMP/nan.ppm"

run --quiet -o "$TMP/ok.ppm" "$DATA/tiny.json"
check "a clean render exits 0" test "$rc" -eq 0
check "and warns about nothing" test ! -s "$TMP/err"
summary
