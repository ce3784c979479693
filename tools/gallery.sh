#!/usr/bin/env bash
# gallery.sh — renders the README's gallery from this repository's scenes at reduced sizes and sample counts so
# that the files stay small, on every CPU (the bytes are the same for any thread count; GLINT_GALLERY_THREADS
# sets it). The committed PNGs are exactly what it makes (tests/cli/gallery.sh).
# usage: bash tools/gallery.sh [GLINT_BINARY [OUTPUT_DIR]]   (defaults: build/glint, docs/gallery)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
glint=${1:-$root/build/glint}
out=${2:-$root/docs/gallery}
mkdir -p "$out"
# name width height spp
while read -r name width height spp; do
    # GLINT_GALLERY_SKIP_GLTF=1: a glint built without assimp cannot read the glTF scenes.
    [[ ${GLINT_GALLERY_SKIP_GLTF:-0} != 0 && $name == gltf-* ]] && continue
    "$glint" "$root/scenes/$name.json" --width "$width" --height "$height" --spp "$spp" --threads "${GLINT_GALLERY_THREADS:-0}" -q \
        -o "$out/$name.png"
done <<'LIST'
paper 384 384 1
whitted 320 240 4
howard-final 360 203 64
rtiow-final 400 225 64
cornell-box 300 300 128
bunny 320 240 64
spot 320 240 64
spider 320 240 64
textures 400 200 64
blog-three-spheres 200 200 40
envmap-spheres 320 180 128
rtiow2-bouncing-spheres 400 225 64
cornell-smoke 300 300 128
rtiow2-final 300 300 64
envmap-bunny 320 240 64
material-spheres 240 240 32
bunny-rough 320 180 32
gltf-boxes 320 240 64
LIST
