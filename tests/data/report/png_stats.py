#!/usr/bin/env python3
"""Decode a PNG with the standard library only and print what the tests check.

Usage: png_stats.py FILE.png
Prints one line: "width height colours nonbackground" where colours is the number of distinct pixel values and
nonbackground the fraction of pixels that differ from the most common value. Exits 1 (with a message) when the
file is not a PNG that decodes: bad signature, bad chunk CRC, missing IHDR/IDAT/IEND, wrong data length, an
unsupported filter type.
"""
import struct
import sys
import zlib
from collections import Counter

CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}  # colour type -> samples per pixel


def fail(message):
    print(f"png_stats: {message}", file=sys.stderr)
    sys.exit(1)


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def main(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail(f"{path}: not a PNG signature")
    pos, header, idat, ended = 8, None, b"", False
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        crc = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])[0]
        if zlib.crc32(kind + body) & 0xFFFFFFFF != crc:
            fail(f"{path}: CRC mismatch in chunk {kind!r}")
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            ended = True
            break
        pos += 12 + length
    if header is None or not idat or not ended:
        fail(f"{path}: missing IHDR, IDAT or IEND")
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in CHANNELS or interlace != 0:
        fail(f"{path}: unsupported PNG (bit depth {depth}, colour type {colour}, interlace {interlace})")
    bpp = CHANNELS[colour]
    stride = width * bpp
    raw = zlib.decompress(idat)
    if len(raw) != height * (stride + 1):
        fail(f"{path}: {len(raw)} bytes of image data, expected {height * (stride + 1)}")
    previous = bytearray(stride)
    counts = Counter()
    for row in range(height):
        start = row * (stride + 1)
        kind = raw[start]
        line = bytearray(raw[start + 1:start + 1 + stride])
        for i in range(stride):
            left = line[i - bpp] if i >= bpp else 0
            up = previous[i]
            upleft = previous[i - bpp] if i >= bpp else 0
            if kind == 0:
                pass
            elif kind == 1:
                line[i] = (line[i] + left) & 0xFF
            elif kind == 2:
                line[i] = (line[i] + up) & 0xFF
            elif kind == 3:
                line[i] = (line[i] + ((left + up) >> 1)) & 0xFF
            elif kind == 4:
                line[i] = (line[i] + paeth(left, up, upleft)) & 0xFF
            else:
                fail(f"{path}: row {row} has filter type {kind}")
        counts.update(bytes(line[i:i + bpp]) for i in range(0, stride, bpp))
        previous = line
    background = counts.most_common(1)[0][1]
    total = width * height
    print(f"{width} {height} {len(counts)} {(total - background) / total:.6f}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        fail("usage: png_stats.py FILE.png")
    main(sys.argv[1])
