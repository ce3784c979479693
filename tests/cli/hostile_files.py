#!/usr/bin/env python3
"""hostile_files.py — damaged copies of files glint wrote, for tests/cli/hostile.sh (standard library only).

  png SRC DIR   region PNGs: the region chunk after the image data, two region chunks that disagree, a region
                of numbers beyond int, a region chunk with a bad CRC, the file cut in its image data
  big W H OUT   a black region PNG of W x H pixels that is the whole of a W x H image (small on disk)
  claim W H OUT the same header, but image data for one row only
  hdr SRC DIR   run-length Radiance files: a zero run, a run past the end of a scanline, a scanline that is
                not run-length encoded after ones that are, cut in the middle, flat pixels cut short
"""
import os
import struct
import sys
import zlib


def png_chunks(data):
    chunks, i = [], 8
    while i < len(data):
        n = struct.unpack(">I", data[i:i + 4])[0]
        chunks.append([data[i + 4:i + 8], data[i + 8:i + 8 + n]])
        i += 12 + n
    return chunks


def png_bytes(chunks, bad_crc=b""):
    out = b"\x89PNG\r\n\x1a\n"
    for kind, body in chunks:
        crc = zlib.crc32(kind + body) & 0xFFFFFFFF
        if kind == bad_crc:
            crc ^= 0xFF
        out += struct.pack(">I", len(body)) + kind + body + struct.pack(">I", crc)
    return out


def png_variants(src, out):
    data = open(src, "rb").read()
    chunks = png_chunks(data)
    text = next(i for i, c in enumerate(chunks) if c[0] == b"tEXt")
    key, value = chunks[text][1].split(b"\0", 1)
    rest = chunks[:text] + chunks[text + 1:]
    variants = {
        "after_idat.png": png_bytes(rest[:-1] + [chunks[text]] + rest[-1:]),
        "two_regions.png": png_bytes(chunks[:text + 1] + [[b"tEXt", key + b"\0" + value + b"9"]] + chunks[text + 1:]),
        "same_twice.png": png_bytes(chunks[:text + 1] + [chunks[text]] + chunks[text + 1:]),
        "overflow.png": png_bytes(chunks[:text] + [[b"tEXt", key + b"\0" + b"4294967296" + value[1:]]]
                                  + chunks[text + 1:]),
        "bad_crc.png": png_bytes(chunks, bad_crc=b"tEXt"),
    }
    idat = data.index(b"IDAT")
    variants["cut_in_data.png"] = data[:idat + 12]
    for name, body in variants.items():
        open(os.path.join(out, name), "wb").write(body)


def rle_lines(pixels, width, height):
    """Where each run-length scanline starts in the pixel stream (and where the last one ends)."""
    starts, i = [], 0
    for _ in range(height):
        starts.append(i)
        i += 4
        for _ in range(4):
            x = 0
            while x < width:
                count = pixels[i]
                run = count > 128
                count -= 128 if run else 0
                i += 2 if run else 1 + count
                x += count
    return starts + [i]


def hdr_variants(src, out):
    data = open(src, "rb").read()
    end = data.index(b"\n\n") + 2
    size_line = data[end:data.index(b"\n", end)]
    end += len(size_line) + 1
    header, pixels = data[:end], data[end:]
    height, width = int(size_line.split()[1]), int(size_line.split()[3])
    assert pixels[:2] == b"\x02\x02" and height >= 2, "expected a run-length encoded file of two scanlines or more"
    lines = rle_lines(pixels, width, height)
    zero = bytearray(pixels)
    zero[lines[1] + 4] = 0  # the first count of the second scanline
    past = bytearray(pixels)
    past[4] = 128 + min(width + 1, 127)  # a run longer than the scanline (width < 127)
    flat = b"\x80\x80\x80\x80" * width  # a scanline of flat pixels: 4 bytes each, not starting 2 2
    variants = {
        "zero_run.hdr": header + bytes(zero),
        "run_past_end.hdr": header + bytes(past),
        "cut_mid.hdr": header + pixels[:(lines[1] + lines[2]) // 2],
        "not_rle_second.hdr": header + pixels[:lines[1]] + flat * (height - 1),
        "flat_cut.hdr": header.replace(size_line, b"-Y 3 +X 4") + b"\x80\x80\x80\x80" * 11,
        "flat_whole.hdr": header.replace(size_line, b"-Y 3 +X 4") + b"\x80\x80\x80\x80" * 12,
    }
    for name, body in variants.items():
        open(os.path.join(out, name), "wb").write(body)


def big_part(width, height, out, rows=None):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    rows = rows if rows is not None else (b"\0" * (1 + width * 3)) * height  # filter byte 0, black pixels
    region = b"glint:region\0" + b"0,0,%d,%d,%d,%d" % (width, height, width, height)
    body = (chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) + chunk(b"tEXt", region)
            + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))
    open(out, "wb").write(b"\x89PNG\r\n\x1a\n" + body)


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "big":
        big_part(int(sys.argv[2]), int(sys.argv[3]), sys.argv[4])
    elif len(sys.argv) == 5 and sys.argv[1] == "claim":  # whole chunks, but one row of data for the size declared
        big_part(int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], rows=b"\0" * (1 + int(sys.argv[2]) * 3))
    elif len(sys.argv) == 4 and sys.argv[1] in ("png", "hdr"):
        (png_variants if sys.argv[1] == "png" else hdr_variants)(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
