# gallery.sh — the README's gallery is what tools/gallery.sh makes: every committed PNG of docs/gallery/ equals,
# byte for byte, the render of its scene at the size and sample count the script gives (skipped under the
# sanitizers, where the seventeen renders take many minutes).
source "$2/tests/cli/common.bash"

if grep -qa __asan_init "$GLINT"; then
    echo "skipped: glint is built with AddressSanitizer"
    summary
    exit 0
fi
# Without assimp (an optional dependency) the glTF picture cannot be made: the others are checked.
"$GLINT" -q --width 8 --height 8 --spp 1 "$SRC/scenes/gltf-boxes.json" -o "$TMP/probe.ppm" 2>"$TMP/err"
expected=18
if grep -q "built without it" "$TMP/err"; then
    echo "note: glint was built without assimp; scenes/gltf-*.json are not rendered"
    expected=17
fi
GLINT_GALLERY_SKIP_GLTF=$((18 - expected)) bash "$SRC/tools/gallery.sh" "$GLINT" "$TMP/gallery" || fail "tools/gallery.sh failed"
count=0
for png in "$TMP"/gallery/*.png; do
    name=$(basename "$png")
    check "docs/gallery/$name is what tools/gallery.sh makes" cmp -s "$png" "$SRC/docs/gallery/$name"
    count=$((count + 1))
done
check "the script made all $expected pictures (made $count)" test "$count" -eq "$expected"
summary
