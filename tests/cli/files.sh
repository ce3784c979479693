# files.sh — what glint does to files: no temporary or stray file survives SIGKILL at any moment of a write;
# symbolic links are written through; the scene file and read-only files are never replaced.
source "$2/tests/cli/common.bash"

# The random delays below come from a seed this prints, so that a failure's delays can be run again
# (GLINT_TEST_SEED=N; the moments glint is killed at still depend on the machine's load).
seed=${GLINT_TEST_SEED:-$(( $(date +%s%N) % 32768 ))}
RANDOM=$seed
echo "files.sh: seed $seed (GLINT_TEST_SEED=$seed repeats its delays)"

TINY=$DATA/tiny.json
BIG=(--quiet --width 1000 --height 1000 --spp 1) # a 12 MB PFM, written in about a tenth of a second

# writing PID DIR: glint holds a file of DIR open (the image being written, named or not).
writing() { find "/proc/$1/fd" -lname "$2/*" 2>/dev/null | grep -q .; }

# kill_while_writing OUT [DELAY]: starts glint on OUT and SIGKILLs it DELAY seconds after its write began,
# or, with DELAY "random", at a random moment of its whole run (loading, render or write).
kill_while_writing() {
    local out=$1 delay=$2
    "$GLINT" "${BIG[@]}" -o "$out" "$TINY" 2>/dev/null &
    local pid=$!
    if [[ $delay == random ]]; then
        sleep "0.$((RANDOM % 30))"
    else
        for _ in $(seq 2000); do
            writing $pid "$(dirname "$out")" && break
            kill -0 $pid 2>/dev/null || break
        done
        sleep "$delay"
    fi
    kill -KILL $pid 2>/dev/null
    wait $pid 2>/dev/null
}

# Only the images themselves may be in the directory: complete, or (for the old one) as they were.
mkdir "$TMP/kill"
"$GLINT" "${BIG[@]}" -o "$TMP/full.pfm" "$TINY"
full_size=$(size "$TMP/full.pfm")
printf 'old' >"$TMP/kill/old.pfm"
for round in $(seq 4); do
    for delay in 0 0.0$((RANDOM % 10)) 0.$((RANDOM % 3))$((RANDOM % 10)) random; do
        rm -f "$TMP/kill/new.pfm"
        kill_while_writing "$TMP/kill/new.pfm" $delay
        kill_while_writing "$TMP/kill/old.pfm" $delay
        left=$(ls -A "$TMP/kill" | grep -v -x -e new.pfm -e old.pfm)
        check "SIGKILL $delay s into a write (round $round): nothing else in the directory: $left" test -z "$left"
        if [[ -e $TMP/kill/new.pfm ]]; then
            check "SIGKILL $delay s into a write: a new image is complete" test "$(size "$TMP/kill/new.pfm")" -eq "$full_size"
        fi
        s=$(size "$TMP/kill/old.pfm")
        check "SIGKILL $delay s into a write: the old image is whole, old or new (size $s)" \
            test "$s" -eq 3 -o "$s" -eq "$full_size"
    done
done

# The scene file is never replaced by the image, whatever the name or link that leads to it (exit 2).
mkdir "$TMP/in"
cp "$TINY" "$TMP/in/same.png"
cp "$TINY" "$TMP/scene.json"
ln -s same.png "$TMP/in/link-to-scene.png"
expect 2 "glint: $TMP/in/same.png: cannot write: it is the scene file, which would be lost" \
    -o "$TMP/in/same.png" "$TMP/in/same.png"
(cd "$TMP/in" && "$GLINT" -o ./same.png same.png 2>"$TMP/err")
check "./same.png for same.png: exit 2" test $? -eq 2
check "./same.png for same.png: the message" grep -qx "glint: ./same.png: cannot write: it is the scene file, which would be lost" "$TMP/err"
expect 2 "glint: $TMP/in/link-to-scene.png: cannot write: it is the scene file, which would be lost" \
    -o "$TMP/in/link-to-scene.png" "$TMP/in/same.png"
"$GLINT" -o "$TMP/in/same.png" - <"$TMP/in/same.png" 2>"$TMP/err"
check "a scene on stdin from the output: exit 2" test $? -eq 2
check "the scene file is unchanged" cmp -s "$TMP/in/same.png" "$TINY"
check "the link is unchanged" test "$(readlink "$TMP/in/link-to-scene.png")" == same.png

# Nor any other file the scene reads: an image texture (exit 2, the texture intact).
cp "$SRC/scenes/meshes/spot/spot_texture.png" "$TMP/in/wood.png"
printf '%s' '{"render":{"width":4,"height":3},"objects":[{"type":"sphere","center":[0,0,-1],"radius":0.5,
"material":{"type":"lambertian","albedo":{"type":"image","file":"wood.png"}}}],"lights":[{"type":"ambient","intensity":1}]}' \
    >"$TMP/in/textured.json"
expect 2 "glint: $TMP/in/wood.png: cannot write: the scene reads it (a mesh, texture or environment map), which would be lost" \
    -o "$TMP/in/wood.png" "$TMP/in/textured.json"
check "the texture is unchanged" cmp -s "$TMP/in/wood.png" "$SRC/scenes/meshes/spot/spot_texture.png"

# A symbolic link as the output: the image is written to the file it names (through a chain of links,
# relative to each link's directory, even dangling), and the links stay links.
run --quiet -o "$TMP/plain.ppm" "$TINY"
mkdir "$TMP/links" "$TMP/links/sub"
printf 'old' >"$TMP/links/sub/target.ppm"
ln -s sub/target.ppm "$TMP/links/first.ppm"
ln -s "$TMP/links/first.ppm" "$TMP/links/second.ppm"
run --quiet -o "$TMP/links/second.ppm" "$TINY"
check "through two links: exit 0" test "$rc" -eq 0
check "through two links: the target holds the image" cmp -s "$TMP/links/sub/target.ppm" "$TMP/plain.ppm"
check "through two links: the first link stays" test -L "$TMP/links/first.ppm"
check "through two links: the second link stays" test -L "$TMP/links/second.ppm"
ln -s sub/created.ppm "$TMP/links/dangling.ppm"
run --quiet -o "$TMP/links/dangling.ppm" "$TINY"
check "a dangling link: its target is created" cmp -s "$TMP/links/sub/created.ppm" "$TMP/plain.ppm"
check "a dangling link stays a link" test -L "$TMP/links/dangling.ppm"
ln -s loop.ppm "$TMP/links/loop.ppm"
expect 1 "glint: $TMP/links/loop.ppm: cannot write: Too many levels of symbolic links" -o "$TMP/links/loop.ppm" "$TINY"
check "links: no temporary files left" no_temp_files "$TMP/links/sub"

# A read-only existing image is refused before the render, as cp refuses it, even for root (exit 1).
printf 'old' >"$TMP/ro.ppm"
chmod 444 "$TMP/ro.ppm"
expect 1 "glint: $TMP/ro.ppm: cannot write: the file is read-only" -o "$TMP/ro.ppm" "$TINY"
check "read-only: the file is unchanged" test "$(cat "$TMP/ro.ppm")" == old
ln -s ro.ppm "$TMP/ro-link.ppm"
expect 1 "glint: $TMP/ro-link.ppm: cannot write: the file is read-only" -o "$TMP/ro-link.ppm" "$TINY"
chmod 644 "$TMP/ro.ppm"
run --quiet -o "$TMP/ro.ppm" "$TINY"
check "writable again: replaced" cmp -s "$TMP/ro.ppm" "$TMP/plain.ppm"

check "no temporary files left" no_temp_files "$TMP"
summary
