# discarded.sh — a render whose samples come out NaN warns on stderr even with --quiet, writes its image, and
# exits 1 when more than 1 % of the samples were dropped.
source "$2/tests/cli/common.bash"

# Two point lights of intensity 3e38 on one surface: their sum overflows, and every sample is infinite.
# (Scenes whose geometry or camera would overflow are rejected at load; light intensities are not bounded.)
printf '%s' '{"render":{"width":4,"height":3,"spp":2},"camera":{"type":"lookat","lookfrom":[0,0,3],"lookat":[0,0,0]},
"objects":[{"type":"sphere","center":[0,0,0],"radius":10,"material":{"type":"lambertian","albedo":0.5}}],
"lights":[{"type":"point","intensity":3e38,"position":[0,0,2]},{"type":"point","intensity":3e38,"position":[0,0,2.5]}]}' > "$TMP/nan.json"
run --quiet -o "$TMP/nan.ppm" "$TMP/nan.json"
check "all samples dropped: exit 1" test "$rc" -eq 1
check "the warning counts and shares them" \
    grep -qx "glint: warning: 24 of 24 samples (100.0 %) were NaN or infinite and were dropped" "$TMP/err"
check "the image is still written" test -s "$TMP/nan.ppm"

run --quiet -o "$TMP/ok.ppm" "$DATA/tiny.json"
check "a clean render exits 0" test "$rc" -eq 0
check "and warns about nothing" test ! -s "$TMP/err"
summary
