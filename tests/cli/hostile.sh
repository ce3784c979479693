# hostile.sh — files and paths an attacker or an accident hands glint (issue 36 and tests/data/hostile/README.md):
# forged checkpoints, Radiance maps that once hung or were read short, an OpenEXR map with Y beside R, G, B, output
# paths that are FIFOs, devices, symbolic links to them or other spellings of another output, merge parts with
# their region chunk after the image data, twice, out of range, damaged or cut short. Each is refused with its
# exit status and a message naming the file, or read right; nothing special is ever replaced.
source "$2/tests/cli/common.bash"

HOSTILE=$DATA/hostile
cp "$HOSTILE"/* "$TMP"/ && chmod u+w "$TMP"/*
cd "$TMP" || exit 1
SCENE=ck.json

# run_bounded ARGS...: run, but a hang is a failure (rc 137) rather than a test that never ends.
run_bounded() {
    timeout -s KILL 20 "$GLINT" "$@" >"$TMP/out" 2>"$TMP/err" </dev/null
    rc=$?
}

# envmap FILE: a copy of the scene lit by the map FILE, as env.json.
envmap() { sed "s|\"background\": \"sky\"|\"background\": {\"type\": \"envmap\", \"file\": \"$1\"}|" $SCENE >env.json; }

# refused STATUS TEXT ARGS...: glint ARGS exits with STATUS (within 20 s) and its message contains TEXT (if any).
refused() {
    local status=$1 text=$2
    shift 2
    run_bounded "$@"
    if [[ $rc -eq $status ]] && { [[ -z $text ]] || grep -qF -- "$text" "$TMP/err"; }; then pass; else
        fail "glint $*: exit $rc (expected $status), stderr: $(cat "$TMP/err") (expected to contain: $text)"
    fi
}

# ---- forged checkpoints (valid checksums) ----
refused 2 "corrupt checkpoint (a plane listed twice)" $SCENE -o out.pfm --spp 8 --resume ckp_forged_dup_count_big.ckp
refused 2 "a sum that is negative, infinite or not a number" $SCENE -o out.pfm --spp 8 --resume ckp_forged_nan_sums.ckp
check "no image from a forged checkpoint" test ! -e out.pfm

# ---- Radiance maps ----
for map in hdr_rle_zero_count.hdr hdr_rle_trunc_mid_line.hdr; do
    envmap $map
    refused 2 "environment map \"$map\": " env.json -q -o out.pfm
done
envmap hdr_rle_zero_count.hdr
refused 2 "corrupt .hdr image: scanline 1: a run of length zero" env.json -q -o out.pfm
envmap hdr_rle_trunc_mid_line.hdr
refused 2 "truncated .hdr image: the file ends in scanline 2 of 4" env.json -q -o out.pfm
envmap hdr_flat_47_bytes_9999999x6.hdr
refused 2 "truncated .hdr image: 0 bytes of pixels, expected 239999976" env.json -q -o out.pfm
# Maps glint wrote, damaged: each refused by name, none decoded short, none hanging.
run -q $SCENE --width 16 --height 4 -o sky.hdr
check "a 16x4 .hdr written (run-length encoded)" test "$rc" -eq 0
python3 "$SRC/tests/cli/hostile_files.py" hdr sky.hdr . || fail "hostile_files.py hdr failed"
envmap sky.hdr
refused 0 "" env.json -q -o out.pfm
for case in "zero_run.hdr:scanline 2: a run of length zero" "run_past_end.hdr:scanline 1: a run past the end" \
    "cut_mid.hdr:truncated .hdr image: the file ends in scanline 2 of 4" \
    "not_rle_second.hdr:scanline 2: not run-length encoded, unlike the scanlines before it" \
    "flat_cut.hdr:truncated .hdr image: 44 bytes of pixels, expected 48 (4x3 flat RGBE pixels)"; do
    envmap "${case%%:*}"
    refused 2 "${case#*:}" env.json -q -o out.pfm
done
envmap flat_whole.hdr
refused 0 "" env.json -q -o out.pfm
for size in "-Y 99999999999 +X 4:declares more pixels than that" "-Y 0 +X 4:declares no pixels" \
    "-Y -3 +X 4:is not \"-Y HEIGHT +X WIDTH\"" "+Y 4 -X 4:is not \"-Y HEIGHT +X WIDTH\""; do
    printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n%s\n' "${size%%:*}" >size.hdr
    head -c 64 /dev/zero >>size.hdr
    envmap size.hdr
    refused 2 "${size#*:}" env.json -q -o out.pfm
done
printf '#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\x80\x80\x80\x80' >xyze.hdr
envmap xyze.hdr
refused 2 "a format other than 32-bit_rle_rgbe" env.json -q -o out.pfm

# ---- OpenEXR: R, G, B and Y (Y is for grey images alone): a red sky ----
envmap exr_rgb_plus_y_red.exr
run -q env.json -o red.pfm
# The first pixel (the last row of the file, PFM rows go bottom up) looks at the sky: R > 0, G = B = 0.
first=$(tail -c $((12 * 12 * 8)) red.pfm | od -An -tf4 -N 12 | xargs)
read -r r g b <<<"$first"
check "R, G, B with Y: exit 0 (got $rc)" test "$rc" -eq 0
check "R, G, B with Y: the sky is red, not black (got $first)" awk -v r="$r" -v g="$g" -v b="$b" \
    'BEGIN { exit !(r > 0.1 && g == 0 && b == 0) }'

# Found by fuzz_exr: 586 bytes declaring 50331651x2 uncompressed pixels, whose chunks hold 161 bytes; OpenEXRCore
# decoded them without a word into 1.5 GB of black. Every chunk must now lie in the file and hold its pixels.
envmap exr_short_uncompressed_chunks.exr
refused 2 "corrupt OpenEXR data" env.json -q -o out.pfm

# ---- output paths: never a FIFO, a device or a socket, nor through a link to one ----
mkfifo c.fifo
refused 1 "c.fifo: cannot write: it is a FIFO, not a regular file" $SCENE -q -o out.pfm --checkpoint c.fifo
refused 1 "c.fifo: cannot write: it is a FIFO" $SCENE -q -o out.pfm --trace c.fifo
mkfifo f.png
refused 1 "f.png: cannot write: it is a FIFO" $SCENE -q -o f.png
ln -s c.fifo link.png
refused 1 "link.png: cannot write: it is a FIFO" $SCENE -q -o link.png
check "the FIFOs are still FIFOs" test -p c.fifo -a -p f.png
refused 2 "c.fifo: cannot open the checkpoint: not a regular file" $SCENE -q -o out.pfm --resume c.fifo
check "--resume FIFO: still a FIFO" test -p c.fifo
mkdir adir
refused 2 "adir: cannot open the checkpoint: Is a directory" $SCENE -q -o out.pfm --resume adir
if [[ $(id -u) -eq 0 ]] && mknod null.dev c 1 3 2>/dev/null; then
    refused 1 "null.dev: cannot write: it is a device" $SCENE -q -o out.pfm --checkpoint null.dev
    refused 1 "null.dev: cannot write: it is a device" $SCENE -q -o out.pfm --trace null.dev
    check "the device node is still a character device" test -c null.dev
else
    echo "note: not root, no device node made; the FIFO cases stand for it"
fi

# ---- one file under two spellings ----
refused 2 "--trace: ./same.pfm: cannot write: it is the output image" $SCENE -q -o same.pfm --trace ./same.pfm
refused 2 "--checkpoint: same.pfm: cannot write: it is the output image" $SCENE -q -o ./same.pfm --checkpoint same.pfm
refused 2 "--checkpoint: adir/../x.pfm: cannot write: it is the output image" $SCENE -q -o x.pfm --checkpoint adir/../x.pfm
check "nothing written under the second spelling" test ! -e same.pfm

# ---- merge parts ----
run -q $SCENE -o full.png
run -q $SCENE --region 0,0,6,8 -o a.png
run -q $SCENE --region 6,0,12,8 -o b.png
refused 2 "a.png: cannot write: it is the part a.png" merge a.png a.png b.png
ln -s a.png alias.png
refused 2 "alias.png: cannot write: it is the part a.png" merge alias.png a.png b.png
refused 2 "./a.png: cannot write: it is the part a.png" merge ./a.png a.png b.png
run -q $SCENE --region 0,0,6,8 -o again.png
check "the part is unchanged" cmp -s a.png again.png
python3 "$SRC/tests/cli/hostile_files.py" png a.png . || fail "hostile_files.py png failed"
refused 0 "" merge m.png after_idat.png b.png
check "a region chunk after the image data is read: the merge equals the full render" cmp -s m.png full.png
refused 0 "" merge m2.png same_twice.png b.png
refused 2 "two glint:region chunks that disagree" merge m3.png two_regions.png b.png
refused 2 "glint:region '4294967296,0,6,8,12,8' is not X0,Y0,X1,Y1,W,H" merge m3.png overflow.png b.png
refused 2 "bad_crc.png: corrupt PNG (tEXt: CRC error)" merge m3.png bad_crc.png b.png
# The length its IDAT chunk declares: the compressed image's, which changes with the image's bytes.
idat_len=$(python3 -c "import sys; d = open(sys.argv[1], 'rb').read(); i = d.index(b'IDAT'); print(int.from_bytes(d[i - 4:i], 'big'))" cut_in_data.png)
refused 2 "cut_in_data.png: truncated PNG: its IDAT chunk declares $idat_len bytes, the file holds 8 more" merge m3.png cut_in_data.png b.png
refused 1 "f.png: cannot write: it is a FIFO" merge f.png a.png b.png
check "the merge left the FIFO a FIFO" test -p f.png
check "no merge output from refused parts" test ! -e m3.png

# A part too small to hold what it declares is refused before anything is allocated: a chunk longer than the rest
# of the file (fuzz_merge found a 2 GB tEXt in 300 bytes), or rows that deflate (at most 1032 bytes from one)
# cannot have made from the file's size.
python3 "$SRC/tests/cli/hostile_files.py" big 16384 16384 huge.png || fail "hostile_files.py big failed"
head -c 200000 huge.png >huge_cut.png
refused 2 "huge_cut.png: truncated PNG: its IDAT chunk declares 782748 bytes, the file holds 199907 more" merge hm.png huge_cut.png
refused 2 "png_oom_text_length.png: truncated PNG: its tEXt chunk declares 2130706457 bytes" merge hm.png png_oom_text_length.png
python3 "$SRC/tests/cli/hostile_files.py" claim 16384 16384 claim.png || fail "hostile_files.py claim failed"
refused 2 "claim.png: truncated PNG: 180 bytes cannot hold 16384x16384 pixels" merge hm.png claim.png
rm -f huge.png huge_cut.png claim.png

# 8-bit parts merge in 8 bits: an 8192x4096 part (98 kB on disk) takes about 240 MB, not 530 MB (floats).
if grep -qa __asan_init "$GLINT"; then
    echo "skipped the ulimit -v merge: glint is built with AddressSanitizer"
else
    python3 "$SRC/tests/cli/hostile_files.py" big 8192 4096 big.png || fail "hostile_files.py big failed"
    (ulimit -v 400000 && exec "$GLINT" merge bigm.png big.png) >"$TMP/out" 2>"$TMP/err"
    rc=$?
    check "an 8192x4096 8-bit merge within 400 MB of address space: exit 0 (got $rc: $(cat "$TMP/err"))" test $rc -eq 0
    rm -f big.png bigm.png
fi

# ---- documented maxima are accepted, not refused with their own bound ----
sed 's|"objects": \[.*\]|"objects": [{"type": "constant_medium", "boundary": {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5}, "density": 1e30, "g": 0.99999999, "albedo": [1, 1, 1]}]|' \
    $SCENE >maxima.json
refused 0 "" maxima.json -q -o out.pfm
sed 's|"density": 1e30|"density": 1.0000001e30|' maxima.json >over.json
refused 2 '"density" must be a number in (0, 1e30], got 1.0000001e30' over.json -q -o out.pfm

check "no temporary file left" no_temp_files "$TMP"
summary
