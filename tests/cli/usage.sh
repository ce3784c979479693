# usage.sh — the command line: --help and --version, bad flags and values with their exact messages,
# missing scene files, unwritable or unknown outputs; exit status 0, 1 or 2 as documented.
source "$2/tests/cli/common.bash"

HINT="Try 'glint --help' for more information."

run --help
check "--help exits 0" test "$rc" -eq 0
check "--help prints to stdout only" test ! -s "$TMP/err"
for flag in --output --ascii-ppm --width --height --spp --depth --seed --threads --accel --sampler --noise-threshold \
    --quiet --help --version; do
    check "--help documents $flag" grep -q -- "$flag" "$TMP/out"
done
check "--help names the default output" grep -q 'paper.png' "$TMP/out"
check "--help documents the exit status on SIGINT" grep -q '130' "$TMP/out"
run -h
check "-h exits 0" test "$rc" -eq 0
run --version
check "--version exits 0" test "$rc" -eq 0
check "--version prints 'glint X.Y.Z'" grep -Eqx 'glint [0-9]+\.[0-9]+\.[0-9]+' "$TMP/out"

expect 2 "glint: no scene file given
$HINT"
expect 2 "glint: unknown option '--foo'
$HINT" --foo "$DATA/tiny.json"
expect 2 "glint: unknown option '-x'
$HINT" -x "$DATA/tiny.json"
expect 2 "glint: unknown option '-x'
$HINT" -qx "$DATA/tiny.json"
expect 2 "glint: --width: 'abc' is not an integer, expected an integer in [1, 16384]" --width abc "$DATA/tiny.json"
expect 2 "glint: --width: '12x' is not an integer, expected an integer in [1, 16384]" --width 12x "$DATA/tiny.json"
expect 2 "glint: --width: ' 12' is not an integer, expected an integer in [1, 16384]" --width " 12" "$DATA/tiny.json"
expect 2 "glint: --width: '' is not an integer, expected an integer in [1, 16384]" --width= "$DATA/tiny.json"
expect 2 "glint: --width: '1.5' is not an integer, expected an integer in [1, 16384]" --width 1.5 "$DATA/tiny.json"
expect 2 "glint: --width: 0 is out of range, expected an integer in [1, 16384]" --width 0 "$DATA/tiny.json"
expect 2 "glint: --height: 16385 is out of range, expected an integer in [1, 16384]" --height=16385 "$DATA/tiny.json"
expect 2 "glint: --width: 99999999999999999999999 is out of range, expected an integer in [1, 16384]" \
    --width 99999999999999999999999 "$DATA/tiny.json"
expect 2 "glint: --spp: -1 is out of range, expected an integer in [1, 1000000]" --spp -1 "$DATA/tiny.json"
expect 2 "glint: --depth: 10001 is out of range, expected an integer in [0, 10000]" --depth 10001 "$DATA/tiny.json"
expect 2 "glint: --seed: -1 is out of range, expected an integer in [0, 9007199254740992]" --seed -1 "$DATA/tiny.json"
expect 2 "glint: --threads: -1 is out of range, expected an integer in [0, 256]" --threads -1 "$DATA/tiny.json"
expect 2 "glint: --threads: 257 is out of range, expected an integer in [0, 256]" --threads 257 "$DATA/tiny.json"
expect 2 "glint: --accel: unknown structure 'kd', expected bvh, bvh2 or none" --accel kd "$DATA/tiny.json"
expect 2 "glint: --sampler: unknown sampler 'halton', expected sobol or independent" --sampler halton "$DATA/tiny.json"
expect 2 "glint: --noise-threshold: '-1' is not a number, expected a number in [0, 1000]" --noise-threshold -1 \
    "$DATA/tiny.json"
expect 2 "glint: --noise-threshold: 'nan' is not a number, expected a number in [0, 1000]" --noise-threshold nan \
    "$DATA/tiny.json"
expect 2 "glint: --noise-threshold: 1e4 is out of range, expected a number in [0, 1000]" --noise-threshold 1e4 \
    "$DATA/tiny.json"
# --sampler: the path tracer's images differ between the two, each the same as the scene's "sampler" says.
run --quiet --sampler independent --spp 4 -o "$TMP/ind.pfm" "$DATA/tiny-path.json"
run --quiet --spp 4 -o "$TMP/sob.pfm" "$DATA/tiny-path.json"
check "--sampler: sobol (the default) and independent differ" test "$(cmp -s "$TMP/ind.pfm" "$TMP/sob.pfm"; echo $?)" = 1
sed 's/"integrator": "path"/"integrator": "path", "sampler": "independent"/' "$DATA/tiny-path.json" >"$TMP/ind.json"
run --quiet --spp 4 -o "$TMP/ind2.pfm" "$TMP/ind.json"
check "--sampler independent is the scene's \"sampler\": \"independent\"" cmp -s "$TMP/ind.pfm" "$TMP/ind2.pfm"
# --noise-threshold: fewer samples, the count of each pixel in the samples AOV.
run --quiet --spp 64 --noise-threshold 0.05 --aov samples -o "$TMP/ad.pfm" "$DATA/tiny-path.json"
check "--noise-threshold --aov samples writes the counts" test "$rc" -eq 0 -a -s "$TMP/ad.samples.pfm"
# --time-limit ends after a whole pass: the image of the samples per pixel reached, exit 0, said on stderr.
run --time-limit 1 --spp 1000000 --width 8 --height 8 -o "$TMP/tl.pfm" "$DATA/tiny-path.json"
check "--time-limit: exit 0" test "$rc" -eq 0
spp_reached=$(sed -n 's/^glint: time limit of 1 s reached: \([0-9]*\) of 1000000 samples per pixel rendered$/\1/p' "$TMP/err")
check "--time-limit: says how far it got" test -n "$spp_reached"
run --quiet --spp "${spp_reached:-1}" --width 8 --height 8 -o "$TMP/tl-same.pfm" "$DATA/tiny-path.json"
check "--time-limit: the image of a render at that spp" cmp -s "$TMP/tl.pfm" "$TMP/tl-same.pfm"
expect 2 "glint: --time-limit: 0 is out of range, expected an integer in [1, 100000000]" --time-limit 0 "$DATA/tiny.json"
expect 2 "glint: --half: the output '$TMP/h.png' is not an .exr file" --half -o "$TMP/h.png" "$DATA/tiny.json"
run --quiet --half -o "$TMP/h.exr" "$DATA/tiny.json"
check "--half writes an EXR" test "$rc" -eq 0 -a "$(head -c 4 "$TMP/h.exr" | od -An -tx1 | tr -d ' ')" = 762f3101
expect 2 "glint: --output-encoding: unknown encoding 'gamma', expected linear, gamma2 or srgb" \
    --output-encoding gamma "$DATA/tiny.json"
# --output-encoding changes the 8-bit bytes and nothing else: srgb and linear differ, the PFM is the same.
run --quiet --output-encoding linear -o "$TMP/lin.ppm" "$DATA/tiny.json"
run --quiet --output-encoding srgb -o "$TMP/srgb.ppm" "$DATA/tiny.json"
check "--output-encoding: the encodings differ" test "$(cmp -s "$TMP/lin.ppm" "$TMP/srgb.ppm"; echo $?)" = 1
run --quiet --output-encoding linear -o "$TMP/lin.pfm" "$DATA/tiny.json"
run --quiet --output-encoding srgb -o "$TMP/srgb.pfm" "$DATA/tiny.json"
check "--output-encoding: the linear values are the same" cmp -s "$TMP/lin.pfm" "$TMP/srgb.pfm"
expect 2 "glint: option '--width' needs a value
$HINT" "$DATA/tiny.json" --width
expect 2 "glint: option '-o' needs a value
$HINT" "$DATA/tiny.json" -o
expect 2 "glint: option '-o' needs a value
$HINT" "$DATA/tiny.json" -qo
expect 2 "glint: option '--quiet' takes no value
$HINT" --quiet=yes "$DATA/tiny.json"
expect 2 "glint: unexpected argument 'b.json': only one scene file can be given
$HINT" a.json b.json
expect 2 "glint: --output: empty file name, expected an image file name or -" -o "" "$DATA/tiny.json"
expect 2 "glint: --ascii-ppm: the output '$TMP/a.png' is not a .ppm file (or -)" \
    --ascii-ppm -o "$TMP/a.png" "$DATA/tiny.json"

# Short options combine as getopt_long's do: -qo FILE, -qoFILE, -qh.
run -qh
check "-qh prints the help: exit 0" test "$rc" -eq 0
check "-qh prints the help" grep -q -- '--output' "$TMP/out"
run -qo "$TMP/combined.ppm" "$DATA/tiny.json"
check "-qo FILE: exit 0" test "$rc" -eq 0
check "-qo FILE: quiet" test ! -s "$TMP/err"
check "-qo FILE: the image written" test -s "$TMP/combined.ppm"
run "$DATA/tiny.json" -qo"$TMP/combined2.ppm"
check "SCENE -qoFILE: the image written, quietly" test "$rc" -eq 0 -a -s "$TMP/combined2.ppm" -a ! -s "$TMP/err"
check "-qo and -qoFILE: the same image" cmp -s "$TMP/combined.ppm" "$TMP/combined2.ppm"

# --threads 0 is every online CPU, as the library counts them (and as no --threads does).
cpus=$(getconf _NPROCESSORS_ONLN)
run --threads 0 -o "$TMP/threads0.ppm" "$DATA/tiny.json"
check "--threads 0: exit 0" test "$rc" -eq 0
check "--threads 0: all $cpus online CPUs" grep -q "($cpus thread" "$TMP/err"

# Outputs are checked before the scene is even read: no render is wasted on a typo.
expect 2 "glint: $TMP/x.jpg: unknown image format '.jpg', expected .png, .ppm, .pfm, .exr or .hdr (or - for PPM on standard output)" \
    -o "$TMP/x.jpg" "$DATA/tiny.json"
check "unknown extension: no file" test ! -e "$TMP/x.jpg"
expect 2 "glint: $TMP/noext: no file extension to choose the image format from, expected .png, .ppm, .pfm, .exr or .hdr (or - for PPM on standard output)" \
    -o "$TMP/noext" "$DATA/tiny.json"
expect 1 "glint: /nonexistent/dir/x.png: cannot write: No such file or directory" \
    -o /nonexistent/dir/x.png "$DATA/tiny.json"
check "unwritable output: no file" test ! -e /nonexistent/dir/x.png
mkdir "$TMP/dir.png"
expect 1 "glint: $TMP/dir.png: cannot write: Is a directory" -o "$TMP/dir.png" "$DATA/tiny.json"
if [[ $EUID -ne 0 ]]; then # root writes anywhere
    mkdir "$TMP/ro" && chmod 555 "$TMP/ro"
    expect 1 "glint: $TMP/ro/x.png: cannot write: Permission denied" -o "$TMP/ro/x.png" "$DATA/tiny.json"
fi
check "no temporary files left" no_temp_files "$TMP"

# Scene errors: exit 2, the scene file named first, no image written.
run -o "$TMP/missing.png" "$TMP/missing.json"
check "missing scene file exits 2" test "$rc" -eq 2
check "missing scene file is named" grep -q "^glint: $TMP/missing.json" "$TMP/err"
check "missing scene file: no image" test ! -e "$TMP/missing.png"
printf '{"render": {"width": 10, "height": 10}, "objects": [' >"$TMP/broken.json"
run -o "$TMP/broken.png" "$TMP/broken.json"
check "malformed scene exits 2" test "$rc" -eq 2
check "malformed scene is named with line and column" grep -Eq "^glint: $TMP/broken.json:[0-9]+:[0-9]+: " "$TMP/err"
check "malformed scene: no image" test ! -e "$TMP/broken.png"
"$GLINT" -o "$TMP/stdin-broken.png" - <<<'{"render": 5}' 2>"$TMP/err"
rc=$?
check "malformed scene on stdin exits 2" test "$rc" -eq 2
check "malformed scene on stdin: no image" test ! -e "$TMP/stdin-broken.png"

# Loader warnings (problems worked around in mesh files) are printed by the program, not the library.
run -o "$TMP/warn.ppm" "$DATA/warn.json"
check "mesh warnings: exit 0" test "$rc" -eq 0
check "mesh warnings: printed with file and line" grep -qx "glint: $DATA/warn.obj:6: warning: face has zero area; skipped" "$TMP/err"
run --quiet -o "$TMP/warn.ppm" "$DATA/warn.json"
check "mesh warnings: silenced by --quiet" test ! -s "$TMP/err"

# Brute force on meshes tests every triangle for every ray: said before the (possibly endless) render.
BRUTE="warning: brute force tests every one of the 1 triangle of the scene's meshes for every ray; the render may take far longer than with the default, bvh"
run --accel none -o "$TMP/warn.ppm" "$DATA/warn.json"
check "--accel none on meshes: exit 0" test "$rc" -eq 0
check "--accel none on meshes: a warning" grep -qxF "glint: ${BRUTE/warning:/warning: --accel none:}" "$TMP/err"
sed 's/"render": {/"render": {"accel": "none", /' "$DATA/warn.json" >"$TMP/brute.json"
cp "$DATA/warn.obj" "$TMP/warn.obj"
run -o "$TMP/warn.ppm" "$TMP/brute.json"
check "\"accel\": \"none\" on meshes: a warning" grep -qxF "glint: ${BRUTE/warning:/warning: \"accel\": \"none\":}" "$TMP/err"
run --quiet --accel none -o "$TMP/warn.ppm" "$DATA/warn.json"
check "--accel none on meshes: silenced by --quiet" test ! -s "$TMP/err"
run --accel none -o "$TMP/brute.ppm" "$DATA/tiny.json"
check "--accel none without meshes: no warning" test "$(grep -c warning "$TMP/err")" -eq 0

# A mesh or model given as the scene: what a scene is and how to place the mesh, not a JSON syntax error.
printf 'ply\nformat ascii 1.0\nelement vertex 0\nend_header\n' >"$TMP/model.ply"
printf '{"asset": {"version": "2.0"}}' >"$TMP/model.gltf"
for model in model.ply model.gltf; do
    expect 2 "glint: $TMP/$model: a mesh or model file, not a scene: glint renders JSON scene files (docs/scene-format.md); place the mesh in one with {\"objects\": [{\"type\": \"mesh\", \"file\": \"$TMP/$model\"}]} (Wavefront OBJ; glTF and PLY are not read yet)" "$TMP/$model" -o "$TMP/model.png"
done
summary
