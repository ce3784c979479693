# models.sh — glTF 2.0 and PLY files read through assimp (src/io/model_read.c, src/scene/scene_file_import.c):
# every glTF and PLY file of Debian's assimp-testmodels loads or is refused naming the file (exit 2, never a crash or
# a hang), as a "mesh" and as an "import"; the malformed files of tests/data/models (made by its make.py) are
# refused; a reused mesh becomes instances (the same bytes as the JSON scene that places a PLY twin three times); a
# glTF camera and a glTF spot light reproduce their JSON equivalents; BoxTextured's texture is the right way up.
source "$2/tests/cli/common.bash"
MODELS=$DATA/models
cp "$MODELS"/*.gltf "$MODELS"/*.ply "$MODELS"/*.png "$TMP"/ && chmod u+w "$TMP"/*
cd "$TMP" || exit 1

# run_bounded ARGS...: run, but a hang is a failure (rc 137) rather than a test that never ends.
run_bounded() {
    timeout -s KILL 60 "$GLINT" "$@" >"$TMP/out" 2>"$TMP/err" </dev/null
    rc=$?
}

# scene_with KIND FILE: a small scene placing FILE as an object of type KIND ("mesh" or "import"), as s.json.
scene_with() {
    printf '{"render": {"width": 8, "height": 8, "spp": 1, "integrator": "path"},
 "camera": {"type": "lookat", "lookfrom": [0, 2, 6], "lookat": [0, 0, 0]},
 "objects": [{"type": "%s", "file": "%s"}]}\n' "$1" "$2" >s.json
}

# Without assimp, glTF and PLY are refused with a message that says why, and nothing else here can run.
scene_with mesh quad.ply
run_bounded s.json -q -o s.ppm
if [[ $rc -eq 2 ]] && grep -q "built without it" err; then
    echo "glint was built without assimp: glTF and PLY files are refused, as they should be"
    pass
    summary
    exit
fi
check "a PLY mesh renders (exit $rc: $(cat err))" test "$rc" -eq 0

# same_within A.ppm B.ppm TOLERANCE: the mean absolute difference of two 8-bit PPMs is at most TOLERANCE (0..255).
same_within() {
    python3 - "$@" <<'PY'
import sys
def read(p):
    d = open(p, 'rb').read()
    parts = d.split(maxsplit=4)
    return parts[4]
a, b = read(sys.argv[1]), read(sys.argv[2])
diff = sum(abs(x - y) for x, y in zip(a, b)) / max(1, len(a))
ok = len(a) == len(b) and diff <= float(sys.argv[3])
print('mean |difference| %.4f' % diff)
sys.exit(0 if ok else 1)
PY
}

# differ_beyond A.ppm B.ppm TOLERANCE: the mean absolute difference exceeds TOLERANCE.
differ_beyond() { ! same_within "$@" >/dev/null; }

# ---- malformed files: exit 2 within the time limit, a message naming the file ----
for f in index-out-of-range.gltf infinite-vertex.gltf missing-bin.gltf recursive-nodes.gltf cyclic-nodes.gltf \
         huge-count.gltf deep-nodes.gltf huge-count.ply nan-vertex.ply index-out-of-range.ply truncated.ply; do
    for kind in mesh import; do
        scene_with $kind $f
        run_bounded s.json -q -o bad.ppm
        if [[ $rc -eq 2 ]] && grep -qF "\"$f\"" err; then pass; else fail "$kind $f: exit $rc, stderr: $(cat err)"; fi
    done
done
check "no image from a refused model" test ! -e bad.ppm
scene_with mesh missing-bin.gltf
run_bounded s.json -q -o bad.ppm
check "a missing .bin is named: $(cat err)" grep -qF 'cannot open "missing.bin"' err
mkfifo fifo.bin
sed 's/missing.bin/fifo.bin/' missing-bin.gltf >fifo.gltf
scene_with import fifo.gltf
run_bounded s.json -q -o bad.ppm
check "a FIFO .bin is refused, not waited on: exit $rc, $(cat err)" grep -qF '"fifo.bin": not a regular file' err

# ---- a mesh used by three nodes: three instances, the bytes of the JSON scene that places quad.ply so ----
light='"lights": [{"type": "point", "position": [0, 4, 3], "intensity": 30}]'
render='"render": {"width": 48, "height": 32, "spp": 4, "integrator": "path", "background": [0.1, 0.1, 0.1]}'
camera='"camera": {"type": "lookat", "lookfrom": [0, 3, 4], "lookat": [0, 0, 0], "vfov": 50}'
clay='{"type": "pbr", "base_color": [0.8, 0.3, 0.2], "metallic": 0, "roughness": 1}'
cat >import.json <<JSON
{$render, $camera, $light, "objects": [{"type": "import", "file": "reused.gltf"}]}
JSON
cat >byhand.json <<JSON
{$render, $camera, $light, "objects": [
  {"type": "mesh", "file": "quad.ply", "material": $clay, "transform": [{"translate": [-1.5, 0, 0]}]},
  {"type": "mesh", "file": "quad.ply", "material": $clay, "transform": [{"scale": 0.5}, {"translate": [1.5, 0, 0]}]},
  {"type": "mesh", "file": "quad.ply", "material": $clay, "transform": [{"translate": [0, 0, -1.5]}]}]}
JSON
run_bounded import.json -q -o import.ppm
check "reused.gltf imports: $(cat err)" test "$rc" -eq 0
run_bounded byhand.json -q -o byhand.ppm
check "its JSON twin renders: $(cat err)" test "$rc" -eq 0
check "a reused mesh renders as the JSON scene's instances, byte for byte" cmp -s import.ppm byhand.ppm
sed 's/"type": "import", "file": "reused.gltf"/"type": "mesh", "file": "reused.gltf"/' import.json >flat.json
run_bounded flat.json -q -o flat.ppm
check "as a \"mesh\", its nodes flattened with their transforms: the same picture ($(same_within flat.ppm import.ppm 0.25))" \
    same_within flat.ppm import.ppm 0.25
dark='"render": {"width": 48, "height": 32, "spp": 4, "integrator": "path", "background": [0, 0, 0]}'
floor='{"type": "quad", "q": [-3, 0, -3], "u": [0, 0, 6], "v": [6, 0, 0], "material": {"type": "lambertian", "albedo": 0.5}}'

# ---- glTF point and directional lights: the JSON scene's, byte for byte ----
printf '{%s, %s, "objects": [%s, {"type": "import", "file": "lights.gltf"}]}\n' "$dark" "$camera" "$floor" >lights.json
printf '{%s, %s, "objects": [%s, {"type": "mesh", "file": "quad.ply", "material": %s}],
 "lights": [{"type": "point", "position": [1, 2, 3], "intensity": [2, 1, 0.5]},
            {"type": "directional", "direction": [0, 1, 0], "intensity": 3}]}\n' "$dark" "$camera" "$floor" "$clay" >lights-json.json
run_bounded lights.json -q -o lights.ppm
check "lights.gltf imports: $(cat err)" test "$rc" -eq 0
run_bounded lights-json.json -q -o lights-json.ppm
check "glTF point and directional lights light the scene as the JSON ones do, byte for byte" cmp -s lights.ppm lights-json.ppm

# ---- an emissive glTF material (emissiveFactor x KHR_materials_emissive_strength) is an area light: the bytes of
# the JSON scene with the same pbr emitter (so next-event estimation samples it alike) ----
lamp='{"type": "pbr", "base_color": [0.1, 0.2, 0.3], "metallic": 0.25, "roughness": 0.75, "emission": [4, 2, 1]}'
flip='[{"rotate": {"axis": [1, 0, 0], "degrees": 180}}, {"translate": [0, 1.5, 0]}]'
printf '{%s, %s, "objects": [%s, {"type": "import", "file": "emissive.gltf", "transform": %s}]}\n' \
    "$dark" "$camera" "$floor" "$flip" >lamp.json
printf '{%s, %s, "objects": [%s, {"type": "mesh", "file": "quad.ply", "material": %s, "transform": %s}]}\n' \
    "$dark" "$camera" "$floor" "$lamp" "$flip" >lamp-json.json
run_bounded lamp.json -q -o lamp.ppm
check "emissive.gltf imports: $(cat err)" test "$rc" -eq 0
run_bounded lamp-json.json -q -o lamp-json.ppm
check "an emissive glTF material lights the scene as the JSON pbr emitter does, byte for byte" cmp -s lamp.ppm lamp-json.ppm
check "and it does light it" python3 -c "import sys; d = open('lamp.ppm', 'rb').read().split(maxsplit=4)[4]; sys.exit(0 if sum(d) > 4 * len(d) else 1)"

# ---- alphaMode MASK with an alpha below the cutoff: nothing is placed (the scene without it, byte for byte) ----
sphere='{"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": {"type": "lambertian", "albedo": 0.5}}'
printf '{%s, %s, %s, "objects": [%s, {"type": "import", "file": "masked.gltf", "transform": [{"scale": 4}]}]}\n' \
    "$render" "$camera" "$light" "$sphere" >masked.json
printf '{%s, %s, %s, "objects": [%s]}\n' "$render" "$camera" "$light" "$sphere" >unmasked.json
run_bounded masked.json -q -o masked.ppm
run_bounded unmasked.json -q -o unmasked.ppm
check "a fully masked glTF mesh is cut away" cmp -s masked.ppm unmasked.ppm
scene_with mesh masked.gltf
run_bounded s.json -q -o masked.ppm
check "and as a mesh too (exit $rc)" test "$rc" -eq 0

# ---- alphaMode MASK with the base colour texture's alpha (an embedded RGBA PNG checker): the bytes of the JSON pbr
# material with "alpha" and "alpha_cutoff" on the same quad (quad-uv.ply, checker-rgba.png); cells cut away show the
# floor and let the light through to it, so the picture differs from the opaque material's ----
floor_low='{"type": "quad", "q": [-3, -1, -3], "u": [0, 0, 6], "v": [6, 0, 0], "material": {"type": "lambertian", "albedo": [0.2, 0.6, 0.3]}}'
checker='{"type": "image", "file": "checker-rgba.png"}'
leaf="{\"type\": \"pbr\", \"base_color\": $checker, \"metallic\": 0, \"roughness\": 1, \"alpha\": $checker, \"alpha_cutoff\": 0.5}"
opaque="{\"type\": \"pbr\", \"base_color\": $checker, \"metallic\": 0, \"roughness\": 1}"
printf '{%s, %s, %s, "objects": [%s, {"type": "import", "file": "masked-texture.gltf", "transform": [{"scale": 4}]}]}\n' \
    "$render" "$camera" "$light" "$floor_low" >leaf.json
for m in leaf opaque; do
    printf '{%s, %s, %s, "objects": [%s, {"type": "mesh", "file": "quad-uv.ply", "material": %s, "transform": [{"scale": 4}]}]}\n' \
        "$render" "$camera" "$light" "$floor_low" "${!m}" >"$m-json.json"
done
run_bounded leaf.json -o leaf.ppm
check "masked-texture.gltf imports without a warning: $(cat err)" test "$rc" -eq 0 -a "$(grep -c warning err)" -eq 0
run_bounded leaf-json.json -q -o leaf-json.ppm
check "a glTF alpha mask cuts as the JSON pbr alpha mask does, byte for byte" cmp -s leaf.ppm leaf-json.ppm
run_bounded opaque-json.json -q -o opaque-json.ppm
check "and it does cut (exit $rc)" bash -c '! cmp -s leaf.ppm opaque-json.ppm'

# ---- a base colour texture times baseColorFactor: the albedo AOV is what the BSDF shades with (white x the factor),
# not the texture alone ----
printf '{%s, %s, %s, "objects": [{"type": "import", "file": "tinted-texture.gltf", "transform": [{"scale": 4}]}]}\n' \
    "$render" "$camera" "$light" >tinted.json
run_bounded tinted.json -q --aov albedo -o tinted.pfm
check "tinted-texture.gltf renders with an albedo AOV: $(cat err)" test "$rc" -eq 0
check "the albedo AOV of a textured glTF material carries its baseColorFactor" python3 -c "
import struct, sys
d = open('tinted.albedo.pfm', 'rb').read()
h = d.split(b'\n', 3)
v = struct.unpack('<%df' % ((len(h[3])) // 4), h[3])
px = {tuple(round(c, 5) for c in v[i:i + 3]) for i in range(0, len(v), 3)}
sys.exit(0 if (0.5, 0.25, 0.75) in px and (1.0, 1.0, 1.0) not in px else 1)"

# ---- cameras: the file's view, as the equivalent look-at camera ----
for cam in 'front|[0.25, 1, 4]|[0.25, 1, 3]|34.37746771' 'side|[4, 1, 0]|[3, 1, 0]|28.64788976'; do
    IFS='|' read -r name from at vfov <<<"$cam"
    objects='"objects": [{"type": "import", "file": "cameras.gltf"}, {"type": "sphere", "center": [0, 0.6, 0], "radius": 0.6, "material": {"type": "lambertian", "albedo": [0.2, 0.6, 0.3]}}]'
    printf '{%s, "camera": {"type": "import", "file": "cameras.gltf", "name": "%s"}, %s, %s}\n' \
        "$render" "$name" "$light" "$objects" >cam.json
    printf '{%s, "camera": {"type": "lookat", "lookfrom": %s, "lookat": %s, "vfov": %s}, %s, %s}\n' \
        "$render" "$from" "$at" "$vfov" "$light" "$objects" >lookat.json
    # A camera 10%% further away: what the comparison must tell apart.
    printf '{%s, "camera": {"type": "lookat", "lookfrom": %s, "lookat": %s, "vfov": %s}, %s, %s}\n' \
        "$render" "$from" "$at" "$(python3 -c "print($vfov * 0.9)")" "$light" "$objects" >other.json
    run_bounded other.json -q -o other.ppm
    run_bounded cam.json -q -o cam.ppm
    check "camera $name imports: $(cat err)" test "$rc" -eq 0
    run_bounded lookat.json -q -o lookat.ppm
    check "camera $name: the file's view is the look-at camera's ($(same_within cam.ppm lookat.ppm 0.25))" same_within cam.ppm lookat.ppm 0.25
    check "camera $name: and not a narrower one ($(same_within cam.ppm other.ppm 0.25))" differ_beyond cam.ppm other.ppm 0.75
done
printf '{"camera": {"type": "import", "file": "cameras.gltf", "name": "top"}}\n' >cam.json
run_bounded cam.json -q -o cam.ppm
check "an unknown camera name is refused, listing the file's: $(cat err)" grep -qF 'no camera named "top" (it has: "front", "side")' err

# ---- a glTF spot light: the JSON spot light at the same place, cone and intensity ----
spot_cam='"camera": {"type": "lookat", "lookfrom": [0, 5, 5], "lookat": [0, 0, 0], "vfov": 40}'
printf '{%s, %s, "objects": [{"type": "import", "file": "spot.gltf"}]}\n' "$render" "$spot_cam" >spot.json
printf '{%s, %s, "objects": [{"type": "mesh", "file": "quad.ply", "material": %s, "transform": [{"scale": [4, 1, 4]}]}],
 "lights": [{"type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "intensity": [8, 7.2, 6.4],
             "inner_angle": 17.18873385, "outer_angle": 34.3774677}]}\n' "$render" "$spot_cam" "$clay" >spot-json.json
run_bounded spot.json -q -o spot.ppm
check "spot.gltf imports: $(cat err)" test "$rc" -eq 0
run_bounded spot-json.json -q -o spot-json.ppm
check "the glTF spot light is the JSON one ($(same_within spot.ppm spot-json.ppm 0.5))" same_within spot.ppm spot-json.ppm 0.5

# ---- Debian's assimp-testmodels: each glTF and PLY file loads or is refused by name, never a crash ----
if models=$(dpkg -L assimp-testmodels 2>/dev/null | grep -iE '\.(gltf|glb|ply)$'); then
    count=0
    for f in $models; do
        [[ -f $f ]] || continue
        count=$((count + 1))
        for kind in mesh import; do
            scene_with $kind "$f"
            run_bounded s.json -q -o model.ppm
            name=$(basename "$f")
            if [[ $rc -eq 0 ]] || { [[ $rc -eq 2 ]] && grep -qF "$name" err; }; then pass; else
                fail "$kind $f: exit $rc, stderr: $(cat err)"
            fi
        done
    done
    echo "assimp-testmodels: $count glTF and PLY files, each as a mesh and as an import"
    # BoxTextured: its side facing +z shows the Cesium logo's sky (blue) above its hills (green).
    box=/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf
    if [[ -f $box ]]; then
        printf '{"render": {"width": 64, "height": 64, "spp": 4, "integrator": "path", "background": [1, 1, 1]},
 "camera": {"type": "lookat", "lookfrom": [0, 0, 2.2], "lookat": [0, 0, 0], "vfov": 30},
 "objects": [{"type": "import", "file": "%s"}]}\n' "$box" >box.json
        run_bounded box.json -q -o box.ppm
        check "BoxTextured imports: $(cat err)" test "$rc" -eq 0
        check "BoxTextured's texture is the right way up (sky above, hills below)" python3 - box.ppm <<'PY'
import sys
d = open(sys.argv[1], 'rb').read().split(maxsplit=4)
w, h, px = int(d[1]), int(d[2]), d[4]
def mean(y0, y1):
    s = [0, 0, 0]; n = 0
    for y in range(y0, y1):
        for x in range(26, 38):
            for c in range(3): s[c] += px[3 * (y * w + x) + c]
            n += 1
    return [v / n for v in s]
top, bottom = mean(16, 22), mean(42, 48)
print('top', top, 'bottom', bottom)
sys.exit(0 if top[2] > top[0] + 20 and top[2] > top[1] and bottom[1] > bottom[0] + 20 and bottom[1] > bottom[2] + 20 else 1)
PY
    fi
else
    echo "skipped assimp-testmodels: the package is not installed (Debian: assimp-testmodels)"
fi
summary
