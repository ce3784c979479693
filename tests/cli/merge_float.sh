# merge_float.sh — glint merge of float parts from the command line: OpenEXR and PFM regions (with every AOV)
# merge silently into the full render's EXR, PFM and HDR, byte for byte; and every refusal, with its exact message
# and exit status 2 (1 for memory), writes nothing: 8-bit and float parts together, a float output from PNG parts
# (once exit 0 with the bytes decoded as light), an 8-bit output from float parts, PPM and HDR parts, a PFM
# without its region file or beside another PFM's, truncated parts, foreign channels, mismatched parts, overlaps
# and gaps, an output that is a part. (The exact values, over random partitions: tests/test_merge.c.)
source "$2/tests/cli/common.bash"

cd "$TMP" || exit 1
SCENE=$DATA/tiny-path.json
R=(-q --width 40 --height 30 --aov albedo,normal,depth)

run "${R[@]}" "$SCENE" -o full.exr
run "${R[@]}" "$SCENE" -o full.pfm
run "${R[@]}" --half "$SCENE" -o full-half.exr
run -q --width 40 --height 30 "$SCENE" -o full.hdr
# Three parts cut across the 16-pixel tiles: a left column and two bands.
regions=(0,0,13,30 13,0,40,11 13,11,40,30)
for i in 0 1 2; do
    run "${R[@]}" --region "${regions[i]}" "$SCENE" -o "p$i.exr"
    run "${R[@]}" --region "${regions[i]}" "$SCENE" -o "p$i.pfm"
    run "${R[@]}" --half --region "${regions[i]}" "$SCENE" -o "h$i.exr"
    run -q --width 40 --height 30 --region "${regions[i]}" "$SCENE" -o "p$i.png"
    run -q --width 40 --height 30 --region "${regions[i]}" "$SCENE" -o "plain$i.exr"
done
cp p1.exr p1-copy.exr
check "a region's PFM gets its region file" test "$(head -1 p1.pfm.region)" = "glint:region=13,0,40,11,40,30"
check "each AOV PFM gets its own" test -s p1.albedo.pfm.region -a -s p1.normal.pfm.region -a -s p1.depth.pfm.region
check "a whole image's PFM gets none" test ! -e full.pfm.region
hash=$(python3 -c '
import sys
h = 14695981039346656037
for b in open(sys.argv[1], "rb").read():
    h = ((h ^ b) * 1099511628211) % 2**64
print("fnv1a64=%016x" % h)' p1.pfm)
check "the region file holds the FNV-1a hash of the PFM's bytes" test "$(tail -1 p1.pfm.region)" = "$hash"

expect 0 "" merge m.exr p2.exr p0.exr p1.exr
check "EXR parts merge to the full render's EXR, every channel, byte for byte" cmp -s m.exr full.exr
expect 0 "" merge mh.exr h1.exr h2.exr h0.exr
check "half parts merge to the full half render's EXR" cmp -s mh.exr full-half.exr
expect 0 "" merge m.pfm p0.pfm p1.pfm p2.pfm
check "PFM parts merge to the full render's PFM" cmp -s m.pfm full.pfm
check "a merged PFM gets no region file" test ! -e m.pfm.region
for aov in albedo normal depth; do
    run merge "m.$aov.pfm" "p0.$aov.pfm" "p1.$aov.pfm" "p2.$aov.pfm"
    check "the $aov PFM parts merge to the full render's $aov PFM" cmp -s "m.$aov.pfm" "full.$aov.pfm"
done
expect 0 "" merge m.hdr plain0.exr p1.pfm plain2.exr
check "EXR and PFM parts of the same channels merge to the full render's HDR" cmp -s m.hdr full.hdr
expect 0 "" merge m2.pfm p0.exr p1.exr p2.exr
check "EXR parts merge to the full render's PFM" cmp -s m2.pfm full.pfm

# ---- refusals: exit 2, the part named, nothing written ----
out="$TMP/bad"
expect 2 "glint: p2.png: an 8-bit PNG part, but p0.exr is a float OpenEXR part: a merge takes 8-bit parts (to .png or .ppm) or float parts (to .exr, .pfm or .hdr), not both" \
    merge bad.exr p0.exr p1.exr p2.png
expect 2 "glint: p2.pfm: a float PFM part, but p0.png is an 8-bit PNG part: a merge takes 8-bit parts (to .png or .ppm) or float parts (to .exr, .pfm or .hdr), not both" \
    merge bad.png p0.png p1.png p2.pfm
for ext in exr pfm hdr; do
    expect 2 "glint: bad.$ext: p0.png is an 8-bit PNG part: its bytes are display-encoded, not linear light, so 8-bit parts merge to .png or .ppm alone (render .exr or .pfm parts for a float merge)" \
        merge "bad.$ext" p0.png p1.png p2.png
done
for o in bad.png bad.ppm -; do
    expect 2 "glint: $o: p0.exr is a float OpenEXR part: float parts merge to .exr, .pfm or .hdr, not to 8-bit values (render PNG parts for an 8-bit merge)" \
        merge "$o" p0.exr p1.exr p2.exr
done
run -q --width 40 --height 30 --region 0,0,13,30 "$SCENE" -o p0.ppm
run -q --width 40 --height 30 --region 0,0,13,30 "$SCENE" -o p0.hdr
expect 2 "glint: p0.ppm: a PPM, which has no room for where a region lies, expected a PNG, OpenEXR or PFM file written by glint with --region" \
    merge bad.exr p0.ppm p1.exr p2.exr
expect 2 "glint: p0.hdr: a Radiance .hdr, which has no room for where a region lies, expected a PNG, OpenEXR or PFM file written by glint with --region" \
    merge bad.exr p1.exr p2.exr p0.hdr
echo "not an image" >junk.exr
expect 2 "glint: junk.exr: not a region part, expected a PNG, OpenEXR or PFM file written by glint with --region" \
    merge bad.exr p1.exr p2.exr junk.exr

# PFM parts and their region files.
cp p0.pfm lone.pfm
expect 2 "glint: lone.pfm: no region file lone.pfm.region beside it: a PFM has no room for where a region lies, so glint writes it beside the PFM of a region (--region)" \
    merge bad.pfm lone.pfm p1.pfm p2.pfm
cp p1.pfm.region lone.pfm.region
expect 2 "glint: lone.pfm: its region file lone.pfm.region was written for another file (its fnv1a64 ${hash#fnv1a64=} is not the hash of these bytes, $(tail -1 p0.pfm.region | cut -d= -f2)): a part renamed, re-rendered or changed without it" \
    merge bad.pfm lone.pfm p1.pfm p2.pfm
printf 'glint:region=0,0,13,30,40,30\n' >lone.pfm.region
expect 2 "glint: lone.pfm.region: not a region file, expected the two lines glint writes beside a region's PFM: glint:region=X0,Y0,X1,Y1,W,H and fnv1a64= with 16 hexadecimal digits" \
    merge bad.pfm lone.pfm p1.pfm p2.pfm
sed 's/=0,0,13,30,40,30/=0,0,13,30,40,99999/' p0.pfm.region >lone.pfm.region
expect 2 "glint: lone.pfm.region: glint:region '0,0,13,30,40,99999' is not X0,Y0,X1,Y1,W,H of a region inside a W x H image of at most 16384 pixels a side" \
    merge bad.pfm lone.pfm p1.pfm p2.pfm
head -c 1000 p0.pfm >cut.pfm
cp p0.pfm.region cut.pfm.region
expect 2 "glint: cut.pfm: truncated PFM: its 13x30 pixels take 4680 bytes after the header, the file holds 986" \
    merge bad.pfm cut.pfm p1.pfm p2.pfm
expect 2 "glint: bad.exr: p0.depth.pfm is a grey PFM (Pf, an AOV such as depth): grey parts merge to .pfm alone" \
    merge bad.exr p0.depth.pfm p1.depth.pfm p2.depth.pfm
expect 2 "glint: p1.pfm: holds channel R, which p0.depth.pfm lacks: the parts of a merge hold the same channels (rendered with the same --aov, written in the same format)" \
    merge bad.pfm p0.depth.pfm p1.pfm p2.pfm

# OpenEXR parts.
expect 2 "glint: plain1.exr: lacks channel albedo.R, which p0.exr holds: the parts of a merge hold the same channels (rendered with the same --aov, written in the same format)" \
    merge bad.exr p0.exr plain1.exr p2.exr
expect 2 "glint: p1.exr: holds channel albedo.R, which p0.pfm lacks: the parts of a merge hold the same channels (rendered with the same --aov, written in the same format)" \
    merge bad.exr p0.pfm p1.exr p2.exr
cp "$SRC/tests/fuzz/corpus_exr/exr_rgb_plus_y_red.exr" foreign.exr
expect 2 "glint: foreign.exr: channel 'Y' is not one glint writes (R, G, B, albedo.R/G/B, normal.X/Y/Z, Z, samples), expected an OpenEXR file written by glint with --region" \
    merge bad.exr foreign.exr
head -c 2000 p2.exr >cut.exr
run merge bad.exr p0.exr p1.exr cut.exr
check "a truncated EXR part: exit 2, named as corrupt (got $rc: $(cat "$TMP/err"))" \
    grep -q "^glint: cut.exr: corrupt OpenEXR data: " "$TMP/err"
check "... exit 2" test "$rc" -eq 2
head -c 100 p2.exr >cut.exr
expect 2 "glint: cut.exr: unreadable OpenEXR header: End of file attempting to read header" merge bad.exr p0.exr p1.exr cut.exr

# Tiling, as for PNG parts.
expect 2 "glint: p0.exr: overlaps p0.exr at pixel (0, 0)" merge bad.exr p0.exr p1.exr p2.exr p0.exr
expect 2 "glint: no part covers pixel (13, 11) of the 40x30 image (513 pixels missing)" merge bad.exr p0.exr p1.exr
run "${R[@]}" --width 41 --region 13,11,40,30 "$SCENE" -o other.exr
expect 2 "glint: other.exr: a region of a 41x30 image, but p0.exr is of a 40x30 image" merge bad.exr p0.exr p1.exr other.exr
expect 2 "glint: p1.exr: cannot write: it is the part p1.exr, which would be lost" merge p1.exr p0.exr p1.exr p2.exr
expect 2 "glint: ./p1.pfm: cannot write: it is the part p1.pfm, which would be lost" merge ./p1.pfm p0.pfm p1.pfm p2.pfm
check "no output after a refusal" test ! -e bad.exr -a ! -e bad.pfm -a ! -e bad.hdr -a ! -e bad.png -a ! -e bad.ppm
check "the part named as output is unchanged" cmp -s p1.exr p1-copy.exr

# A region file is an output of the render: --checkpoint and --trace may not be one.
expect 2 "glint: --checkpoint: r.depth.pfm.region: cannot write: it is a region file, which would be lost" \
    "${R[@]}" --region 0,0,8,8 "$SCENE" -o r.pfm --checkpoint r.depth.pfm.region
expect 2 "glint: --trace: ./r.pfm.region: cannot write: it is a region file, which would be lost" \
    "${R[@]}" --region 0,0,8,8 "$SCENE" -o r.pfm --trace ./r.pfm.region

# A float merge holds the full image as floats, allocated once from the first part's checked header: short of
# memory it ends with exit 1 and a message, writing nothing. (A 1-pixel region of a 16384 x 16384 image claims
# 3.5 GB.)
if grep -qa __asan_init "$GLINT"; then
    echo "skipped the ulimit -v merge: glint is built with AddressSanitizer"
else
    run -q --width 16384 --height 16384 --region 0,0,1,1 "$SCENE" -o huge.exr
    (ulimit -v 400000 && exec "$GLINT" merge hm.exr huge.exr) >"$TMP/out" 2>"$TMP/err"
    rc=$?
    check "a 16384x16384 float merge within 400 MB: exit 1 (got $rc)" test $rc -eq 1
    check "... out of memory, said" grep -q "^glint: merge: out of memory for a 16384x16384 image of 3 float channels (3489660928 bytes)$" "$TMP/err"
    check "... and nothing written" test ! -e hm.exr
fi

summary
