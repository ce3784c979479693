# presplit.sh — "presplit" in the scene's render settings: a mesh of slivers (thin triangles across their boxes)
# is cut into more BVH leaves when it is on (the default), and the image is the same bytes either way, on one
# thread and on three.
source "$2/tests/cli/common.bash"

# A sphere of 4 bands from pole to pole in 600 segments: 4,800 slivers.
python3 - "$TMP/slivers.obj" <<'PY'
import math, sys
bands, segments = 4, 600
with open(sys.argv[1], "w") as f:
    for i in range(bands + 1):
        th = math.pi * i / bands
        for j in range(segments):
            ph = 2 * math.pi * j / segments
            f.write("v %.7f %.7f %.7f\n" % (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph)))
    for i in range(bands):
        for j in range(segments):
            a, b = i * segments + j + 1, i * segments + (j + 1) % segments + 1
            f.write("f %d %d %d\nf %d %d %d\n" % (a, a + segments, b, b, a + segments, b + segments))
PY
scene() { # scene PRESPLIT: the slivers on a ground, path traced
    cat <<JSON
{"render": {"width": 40, "height": 30, "spp": 2, "integrator": "path", "background": "sky", "presplit": $1},
 "camera": {"type": "lookat", "lookfrom": [0, 1, 4], "lookat": [0, 0, 0], "vfov": 40},
 "materials": {"clay": {"type": "lambertian", "albedo": [0.7, 0.6, 0.5]}, "ground": {"type": "lambertian", "albedo": 0.5}},
 "objects": [{"type": "quad", "q": [-5, -1, 5], "u": [10, 0, 0], "v": [0, 0, -10], "material": "ground"},
             {"type": "mesh", "file": "slivers.obj", "material": "clay"}]}
JSON
}
scene true >"$TMP/on.json"
scene false >"$TMP/off.json"
leaves() { sed -n 's/.* BVH [0-9]* nodes \([0-9]*\) leaves.*/\1/p' "$TMP/err"; }

run -o "$TMP/on.pfm" --threads 1 "$TMP/on.json"
check "presplit true renders" test "$rc" -eq 0
on_leaves=$(leaves)
run -o "$TMP/off.pfm" --threads 1 "$TMP/off.json"
check "presplit false renders" test "$rc" -eq 0
off_leaves=$(leaves)
check "pre-splitting makes more leaves ($on_leaves against $off_leaves)" test "${on_leaves:-0}" -gt "$((2 * ${off_leaves:-0}))"
check "the same image with and without pre-splitting" cmp -s "$TMP/on.pfm" "$TMP/off.pfm"
run -o "$TMP/on3.pfm" --threads 3 "$TMP/on.json"
check "the same image on three threads" cmp -s "$TMP/on.pfm" "$TMP/on3.pfm"
summary
