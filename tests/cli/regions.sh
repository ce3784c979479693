# regions.sh — --region renders part of the image, glint merge assembles the parts: a 4 x 3 split merges into
# exactly the full render's PNG; overlaps, gaps, foreign files and bad regions are errors with exact messages.
source "$2/tests/cli/common.bash"

HINT="Try 'glint --help' for more information."
SCENE=$DATA/tiny-path.json
SIZE=(--width 40 --height 30)

run -q "${SIZE[@]}" "$SCENE" -o "$TMP/full.png"
check "the full render succeeds" test "$rc" -eq 0

# Columns and rows cut across the 16-pixel tiles; the parts are listed out of order.
xs=(0 7 17 33 40)
ys=(0 5 16 30)
parts=()
for j in 2 0 1; do
    for i in 3 1 0 2; do
        region="${xs[i]},${ys[j]},${xs[i + 1]},${ys[j + 1]}"
        run -q "${SIZE[@]}" --region "$region" "$SCENE" -o "$TMP/part-$i-$j.png"
        check "--region $region succeeds" test "$rc" -eq 0
        parts+=("$TMP/part-$i-$j.png")
    done
done
check "the 12 parts are images of their regions' sizes" \
    test "$(be32 "$TMP/part-1-2.png" 16) $(be32 "$TMP/part-1-2.png" 20)" = "10 14"
check "a part records its region" grep -qa 'glint:region.7,16,17,30,40,30' "$TMP/part-1-2.png"
check "a full render records none" test "$(grep -ca 'glint:region' "$TMP/full.png")" -eq 0

run merge "$TMP/merged.png" "${parts[@]}"
check "merge of the 12 parts succeeds silently" test "$rc" -eq 0 -a ! -s "$TMP/err"
check "the merged PNG is the full render's, byte for byte" cmp -s "$TMP/merged.png" "$TMP/full.png"
run -q "${SIZE[@]}" "$SCENE" -o "$TMP/full.ppm"
run merge "$TMP/merged.ppm" "${parts[@]}"
check "merge to PPM gives the full render's PPM" cmp -s "$TMP/merged.ppm" "$TMP/full.ppm"

# The same with independent samples, and with adaptive sampling (64 spp, threshold 0.05): a 2 x 2 split across the
# tiles, on 1 and 3 threads, merges into the full render's PNG.
for opts in "--sampler independent" "--spp 64 --noise-threshold 0.05" "--sampler independent --spp 64 --noise-threshold 0.05"; do
    # shellcheck disable=SC2086 # the options are words
    run -q "${SIZE[@]}" $opts --threads 2 "$SCENE" -o "$TMP/full2.png"
    few=()
    for region in 0,0,17,13 17,0,40,13 0,13,17,30 17,13,40,30; do
        # shellcheck disable=SC2086
        run -q "${SIZE[@]}" $opts --threads $(( ${#few[@]} % 2 * 2 + 1 )) --region "$region" "$SCENE" \
            -o "$TMP/few-${#few[@]}.png"
        few+=("$TMP/few-${#few[@]}.png")
    done
    run merge "$TMP/merged2.png" "${few[@]}"
    check "$opts: the merged parts are the full render" cmp -s "$TMP/merged2.png" "$TMP/full2.png"
done

# A region written as PPM holds its pixels alone.
run -q "${SIZE[@]}" --region 7,5,17,16 "$SCENE" -o "$TMP/part.ppm"
check "a PPM region has the region's size" test "$(head -c 9 "$TMP/part.ppm" | tr '\n' ' ')" = "P6 10 11 "

# Overlaps, gaps, foreign files: exit 2, exact messages, no image written.
rm -f "$TMP/bad.png"
expect 2 "glint: $TMP/part-0-0.png: overlaps $TMP/part-0-0.png at pixel (0, 0)" \
    merge "$TMP/bad.png" "${parts[@]}" "$TMP/part-0-0.png"
run -q "${SIZE[@]}" --region 5,3,9,6 "$SCENE" -o "$TMP/across.png"
expect 2 "glint: $TMP/across.png: overlaps $TMP/part-0-0.png at pixel (5, 3)" \
    merge "$TMP/bad.png" "${parts[@]}" "$TMP/across.png"
expect 2 "glint: no part covers pixel (7, 0) of the 40x30 image (50 pixels missing)" \
    merge "$TMP/bad.png" "${parts[@]:0:5}" "${parts[@]:6}"
run -q --width 41 --height 30 --region 0,0,7,5 "$SCENE" -o "$TMP/other.png"
expect 2 "glint: $TMP/other.png: a region of a 41x30 image, but ${parts[0]} is of a 40x30 image" \
    merge "$TMP/bad.png" "${parts[@]}" "$TMP/other.png"
expect 2 "glint: $TMP/full.png: no glint:region chunk, expected a PNG written by glint with --region" \
    merge "$TMP/bad.png" "$TMP/full.png"
expect 2 "glint: $TMP/part.ppm: a PPM, which has no room for where a region lies, expected a PNG, OpenEXR or PFM file written by glint with --region" \
    merge "$TMP/bad.png" "$TMP/part.ppm"
expect 2 "glint: $TMP/none.png: cannot read: No such file or directory" merge "$TMP/bad.png" "$TMP/none.png"
expect 2 "glint: $TMP/bad.pfm: ${parts[0]} is an 8-bit PNG part: its bytes are display-encoded, not linear light, so 8-bit parts merge to .png or .ppm alone (render .exr or .pfm parts for a float merge)" \
    merge "$TMP/bad.pfm" "${parts[@]}"
check "no image is written after an error" test ! -e "$TMP/bad.png" -a ! -e "$TMP/bad.pfm"
expect 2 "glint: merge: expected OUT and at least one PART: glint merge OUT PART...
$HINT" merge "$TMP/bad.png"

# --region usage errors.
expect 2 "glint: --region: '1,2,3' is not X0,Y0,X1,Y1, expected four non-negative integers separated by commas" \
    --region 1,2,3 "$SCENE"
expect 2 "glint: --region: '-1,0,4,4' is not X0,Y0,X1,Y1, expected four non-negative integers separated by commas" \
    --region=-1,0,4,4 "$SCENE"
expect 2 "glint: --region: '0,0,4,4,' is not X0,Y0,X1,Y1, expected four non-negative integers separated by commas" \
    --region 0,0,4,4, "$SCENE"
expect 2 "glint: --region: ' 0,0,4,4' is not X0,Y0,X1,Y1, expected four non-negative integers separated by commas" \
    --region " 0,0,4,4" "$SCENE"
expect 2 "glint: --region: 4,0,4,4 is empty, expected X0 < X1 and Y0 < Y1" --region 4,0,4,4 "$SCENE"
expect 2 "glint: --region: 0,0,25,16 is not inside the 24x16 image, expected 0 <= X0 < X1 <= 24 and 0 <= Y0 < Y1 <= 16" \
    --region 0,0,25,16 -o "$TMP/bad.png" "$SCENE"
expect 2 "glint: --region: 0,0,2147483647,16 is not inside the 24x16 image, expected 0 <= X0 < X1 <= 24 and 0 <= Y0 < Y1 <= 16" \
    --region 0,0,99999999999,16 -o "$TMP/bad.png" "$SCENE"
expect 2 "glint: option '--region' needs a value
$HINT" "$SCENE" --region

run --help
check "--help documents --region" grep -q -- "--region X0,Y0,X1,Y1" "$TMP/out"
check "--help documents glint merge" grep -q -- "glint merge OUT PART" "$TMP/out"

summary
