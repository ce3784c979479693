# aov.sh — --aov: the usage errors (unknown names, an output that cannot hold AOVs), the PFM files beside a .pfm
# output (their headers, the colour unchanged, the same bytes for any thread count), and AOVs in an .exr output.
source "$2/tests/cli/common.bash"

PATHS=$DATA/tiny-path.json # 24x16, 4 spp

expect 2 "glint: --aov: unknown AOV 'speed' in 'albedo,speed', expected a comma-separated list of albedo, normal, depth and samples" \
    --aov albedo,speed -o "$TMP/x.exr" "$PATHS"
expect 2 "glint: --aov: unknown AOV '' in 'albedo,', expected a comma-separated list of albedo, normal, depth and samples" \
    --aov albedo, -o "$TMP/x.exr" "$PATHS"
expect 2 "glint: --aov: the output '$TMP/x.png' is not an .exr or .pfm file, expected an OpenEXR file (AOVs as channels) or a PFM (AOVs in files beside it)" \
    --aov depth -o "$TMP/x.png" "$PATHS"
expect 2 "glint: option '--aov' needs a value
Try 'glint --help' for more information." "$PATHS" --aov
check "no file is left by the usage errors" test -z "$(ls -A "$TMP" | grep -v '^out$\|^err$')"

# A PFM output: one file per AOV beside it; the colour is the same bytes as without --aov.
run --quiet -o "$TMP/plain.pfm" "$PATHS"
check "plain .pfm exits 0" test "$rc" -eq 0
run --quiet --aov albedo,normal,depth --threads 1 -o "$TMP/a.pfm" "$PATHS"
check "--aov with .pfm exits 0" test "$rc" -eq 0
check "the colour PFM does not change with --aov" cmp -s "$TMP/plain.pfm" "$TMP/a.pfm"
check "albedo PFM: RGB header" test "$(header "$TMP/a.albedo.pfm" 14)" == " P F \n 2 4 1 6 \n - 1 . 0 \n "
check "normal PFM: RGB header" test "$(header "$TMP/a.normal.pfm" 14)" == " P F \n 2 4 1 6 \n - 1 . 0 \n "
check "depth PFM: grey header" test "$(header "$TMP/a.depth.pfm" 14)" == " P f \n 2 4 1 6 \n - 1 . 0 \n "
check "albedo PFM size" test "$(size "$TMP/a.albedo.pfm")" -eq $((14 + 24 * 16 * 12))
check "depth PFM size" test "$(size "$TMP/a.depth.pfm")" -eq $((14 + 24 * 16 * 4))
run --quiet --aov depth,albedo,normal --threads 2 -o "$TMP/b.pfm" "$PATHS"
for aov in albedo normal depth; do
    check "$aov PFM: --threads 1 and 2 give identical files" cmp -s "$TMP/a.$aov.pfm" "$TMP/b.$aov.pfm"
done
# Only the AOVs asked for are written.
run --quiet --aov normal -o "$TMP/n.pfm" "$PATHS"
check "--aov normal writes n.normal.pfm" test -s "$TMP/n.normal.pfm"
check "--aov normal writes no albedo or depth file" test ! -e "$TMP/n.albedo.pfm" -a ! -e "$TMP/n.depth.pfm"
check "no temporary file is left" no_temp_files "$TMP"

# An AOV file that cannot be written is refused before the render, and nothing is written.
mkdir "$TMP/ro"
: >"$TMP/ro/c.depth.pfm"
chmod a-w "$TMP/ro/c.depth.pfm"
expect 1 "glint: $TMP/ro/c.depth.pfm: cannot write: the file is read-only" --quiet --aov depth -o "$TMP/ro/c.pfm" "$PATHS"
check "nothing written beside a refused AOV file" test ! -e "$TMP/ro/c.pfm"

# An EXR output holds them as channels: a larger file than the colour alone, the same for any thread count.
run --quiet -o "$TMP/plain.exr" "$PATHS"
run --quiet --aov albedo,normal,depth --threads 1 -o "$TMP/a.exr" "$PATHS"
check "--aov with .exr exits 0" test "$rc" -eq 0
check "the EXR with AOVs is larger" test "$(size "$TMP/a.exr")" -gt "$(size "$TMP/plain.exr")"
run --quiet --aov albedo,normal,depth --threads 2 -o "$TMP/b.exr" "$PATHS"
check "EXR with AOVs: --threads 1 and 2 give identical files" cmp -s "$TMP/a.exr" "$TMP/b.exr"
check "the EXR names its AOV channels" grep -q "albedo.R" "$TMP/a.exr"
check "--help lists --aov" bash -c "'$GLINT' --help | grep -q -- '--aov LIST'"
# Checkpoints keep the colour's sums only: with AOVs they are refused, before anything is rendered or written.
for flag in --checkpoint --resume; do
    expect 2 "glint: --aov cannot be combined with --checkpoint or --resume: checkpoints keep the colour's sums only" \
        -q --aov albedo $flag "$TMP/c.ckp" "$DATA/tiny.json" -o "$TMP/ck.exr"
    check "$flag with --aov: no image, no checkpoint" test ! -e "$TMP/ck.exr" -a ! -e "$TMP/c.ckp"
done

summary
