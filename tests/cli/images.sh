# images.sh — images by extension (.png .ppm .pfm, -o - for PPM on stdout), their headers and sizes,
# overrides, the default output name, the statistics line, and identical files for any thread count.
source "$2/tests/cli/common.bash"

TINY=$DATA/tiny.json # 20x12
PATHS=$DATA/tiny-path.json # 24x16, 4 spp: several sample passes

run --quiet -o "$TMP/a.ppm" "$TINY"
check "render to .ppm exits 0" test "$rc" -eq 0
check "--quiet prints nothing" test ! -s "$TMP/err"
check "P6 header" test "$(header "$TMP/a.ppm" 13)" == " P 6 \n 2 0 1 2 \n 2 5 5 \n "
check "P6 size" test "$(size "$TMP/a.ppm")" -eq $((13 + 20 * 12 * 3))

run --quiet -o "$TMP/a.png" "$TINY"
check "render to .png exits 0" test "$rc" -eq 0
check "PNG signature" test "$(od -An -tx1 -N 8 "$TMP/a.png" | tr -d ' \n')" == 89504e470d0a1a0a
check "PNG starts with IHDR" test "$(head -c 16 "$TMP/a.png" | tail -c 4)" == IHDR
check "PNG width" test "$(be32 "$TMP/a.png" 16)" -eq 20
check "PNG height" test "$(be32 "$TMP/a.png" 20)" -eq 12
check "PNG 8-bit RGB" test "$(od -An -tu1 -j 24 -N 2 "$TMP/a.png" | tr -s ' ')" == " 8 2"

run --quiet -o "$TMP/a.pfm" "$TINY"
check "render to .pfm exits 0" test "$rc" -eq 0
check "PFM header" test "$(header "$TMP/a.pfm" 14)" == " P F \n 2 0 1 2 \n - 1 . 0 \n "
check "PFM size" test "$(size "$TMP/a.pfm")" -eq $((14 + 20 * 12 * 12))

run --quiet --ascii-ppm -o "$TMP/ascii.ppm" "$TINY"
check "render to ASCII .ppm exits 0" test "$rc" -eq 0
check "P3 header" test "$(head -n 3 "$TMP/ascii.ppm" | tr '\n' ' ')" == "P3 20 12 255 "
check "P3 holds one line per pixel" test "$(tail -n +4 "$TMP/ascii.ppm" | wc -l)" -eq $((20 * 12))
# The same bytes as P6, written as numbers.
p6_values=$(tail -c $((20 * 12 * 3)) "$TMP/a.ppm" | od -An -v -tu1 | tr -s ' \n' ' ' | sed 's/^ //; s/ $//')
p3_values=$(tail -n +4 "$TMP/ascii.ppm" | tr -s ' \n' ' ' | sed 's/^ //; s/ $//')
check "P3 values equal P6 bytes" test "$p6_values" == "$p3_values"

# -o - writes binary PPM to standard output, and nothing else there.
run --quiet -o - "$TINY"
check "-o - exits 0" test "$rc" -eq 0
check "-o - writes the same PPM to stdout" cmp -s "$TMP/out" "$TMP/a.ppm"
run --quiet --ascii-ppm -o - "$TINY"
check "--ascii-ppm -o - writes P3 to stdout" cmp -s "$TMP/out" "$TMP/ascii.ppm"

# Flags override the scene file.
run --quiet --width 7 --height 5 -o "$TMP/small.ppm" "$TINY"
check "--width/--height override" test "$(header "$TMP/small.ppm" 11)" == " P 6 \n 7 5 \n 2 5 5 \n "
check "--width/--height size" test "$(size "$TMP/small.ppm")" -eq $((11 + 7 * 5 * 3))
run --quiet --spp 2 -o "$TMP/spp2.ppm" "$TINY"
check "--spp overrides (jittered samples change the image)" test "$rc" -eq 0 -a -s "$TMP/spp2.ppm"
check "--spp changes the image" differ "$TMP/spp2.ppm" "$TMP/a.ppm"
run --quiet --seed 1 -o "$TMP/seed1.ppm" "$PATHS"
run --quiet --seed 2 -o "$TMP/seed2.ppm" "$PATHS"
check "--seed changes the image" differ "$TMP/seed1.ppm" "$TMP/seed2.ppm"

# The same bytes for any thread count and any acceleration structure.
for scene in "$TINY" "$PATHS"; do
    name=$(basename "$scene" .json)
    run --quiet --threads 1 -o "$TMP/$name-t1.ppm" "$scene"
    check "$name --threads 1 exits 0" test "$rc" -eq 0
    for n in 2 3; do
        run --quiet --threads $n -o "$TMP/$name-t$n.ppm" "$scene"
        check "$name: --threads 1 and --threads $n give identical files" cmp -s "$TMP/$name-t1.ppm" "$TMP/$name-t$n.ppm"
    done
    for accel in none bvh2 bvh; do
        run --quiet --accel $accel -o "$TMP/$name-$accel.pfm" "$scene"
        check "$name --accel $accel exits 0" test "$rc" -eq 0
    done
    check "$name: --accel none and bvh give identical files" cmp -s "$TMP/$name-none.pfm" "$TMP/$name-bvh.pfm"
    check "$name: --accel none and bvh2 give identical files" cmp -s "$TMP/$name-none.pfm" "$TMP/$name-bvh2.pfm"
done

# The scene from standard input; the default output: the scene's name with .png, in the current directory.
"$GLINT" --quiet -o "$TMP/stdin.ppm" - <"$TINY" 2>"$TMP/err"
check "scene from stdin" cmp -s "$TMP/stdin.ppm" "$TMP/a.ppm"
mkdir "$TMP/cwd"
(cd "$TMP/cwd" && "$GLINT" --quiet "$TINY" 2>/dev/null)
check "default output is tiny.png in the current directory" cmp -s "$TMP/cwd/tiny.png" "$TMP/a.png"
(cd "$TMP/cwd" && "$GLINT" --quiet - <"$TINY" 2>/dev/null)
check "default output from stdin is out.png" cmp -s "$TMP/cwd/out.png" "$TMP/a.png"

# An existing image is replaced whole.
printf 'old' >"$TMP/replace.ppm"
run --quiet -o "$TMP/replace.ppm" "$TINY"
check "an existing file is replaced" cmp -s "$TMP/replace.ppm" "$TMP/a.ppm"

# Without --quiet and without a terminal: no progress bar, one statistics line.
run --threads 2 -o "$TMP/stats.ppm" "$TINY"
check "statistics: one line" test "$(wc -l <"$TMP/err")" -eq 1
check "statistics: no progress bar without a terminal" test "$(tr -cd '\r' <"$TMP/err" | wc -c)" -eq 0
check "statistics line format" grep -Eq \
    '^glint: [0-9]+\.[0-9]{3} s wall, [0-9.]+ Msamples/s, [0-9.]+ Mrays/s \(2 threads\), (BVH [0-9]+ nodes [0-9]+ leaves depth [0-9]+|no BVH \(brute force\)), build [0-9.]+ m?s' \
    "$TMP/err"
# Rates to four significant figures (0.7314, 11.24, 734.2, 1234): the benchmarks' ratios come from them.
four='([0-9]\.[0-9]{3}|[1-9][0-9]\.[0-9]{2}|[1-9][0-9]{2}\.[0-9]|[1-9][0-9]{3,})'
check "statistics: rates to four significant figures" grep -Eq " $four Msamples/s, $four Mrays/s " "$TMP/err"
check "statistics: names the image and how long writing it took" grep -Eq "; image $TMP/stats.ppm, written in [0-9]+\.[0-9]{3} s\$" "$TMP/err"
run --threads 2 -o - "$TINY"
check "statistics: names standard output" grep -Eq '; image on standard output, written in [0-9]+\.[0-9]{3} s$' "$TMP/err"
run --threads 1 --accel none -o "$TMP/stats.ppm" "$TINY"
check "statistics: 1 thread, brute force" grep -q 'Mrays/s (1 thread), no BVH (brute force), build' "$TMP/err"

# On a terminal: the progress bar, erased at the end, then the statistics line.
if command -v script >/dev/null; then
    script -qec "'$GLINT' --threads 1 -o '$TMP/tty.ppm' '$PATHS'" /dev/null >"$TMP/tty" 2>&1
    check "progress bar on a terminal" grep -Eq '\[#+\] 100%  [0-9.]+ s elapsed, ETA' "$TMP/tty"
    check "statistics after the bar" grep -q 'Mrays/s (1 thread)' "$TMP/tty"
    # The bar fits the terminal: in 40 and 20 columns no line reaches the last column (it would wrap).
    for cols in 40 20; do
        script -qec "stty cols $cols; '$GLINT' --threads 1 --spp 2000 -o '$TMP/tty.ppm' '$PATHS'" /dev/null >"$TMP/tty" 2>&1
        longest=$(tr '\r' '\n' <"$TMP/tty" | grep -v 'Mrays/s' | sed 's/\x1b\[K//g' | awk '{ if (length($0) > n) n = length($0) } END { print n + 0 }')
        check "progress bar in $cols columns: at most $((cols - 1)) wide (got $longest)" test "$longest" -le $((cols - 1))
        check "progress bar in $cols columns: drawn" grep -q '100%' "$TMP/tty"
    done
    script -qec "'$GLINT' --quiet -o '$TMP/tty.ppm' '$PATHS'" /dev/null >"$TMP/tty" 2>&1
    check "--quiet: no progress bar on a terminal" test ! -s "$TMP/tty"
fi

check "no temporary files left" no_temp_files "$TMP"
summary
