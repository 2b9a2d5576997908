"""An X window dump (`xwd -root`) as a PNG, with a line saying what is in it. Std only.

    python3 xwd2png.py screen.xwd screen.png

Reads the usual TrueColor dump of a 24-bit screen (ZPixmap, 24 or 32 bits a pixel).
"""

import struct
import sys
import zlib
from collections import Counter


def read_xwd(path):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 100:
        sys.exit(f"xwd2png.py: {path} is too short for an XWD file")
    h = struct.unpack(">25I", data[:100])
    header_size, version, fmt, _depth, width, height = h[:6]
    byte_order, bpp, bpl = h[7], h[11], h[12]
    masks = h[14:17]
    ncolors = h[19]
    if version != 7 or fmt != 2 or bpp not in (24, 32):
        sys.exit(f"xwd2png.py: unsupported XWD (version {version}, format {fmt}, {bpp} bits a pixel)")
    start = header_size + 12 * ncolors
    pixels = data[start : start + bpl * height]
    if len(pixels) < bpl * height:
        sys.exit(f"xwd2png.py: {path} is truncated")
    order = "little" if byte_order == 0 else "big"
    step = bpp // 8
    shifts = [(m & -m).bit_length() - 1 for m in masks]
    rows = []
    for y in range(height):
        line = pixels[y * bpl : y * bpl + width * step]
        row = bytearray()
        for x in range(0, width * step, step):
            w = int.from_bytes(line[x : x + step], order)
            for m, s in zip(masks, shifts):
                row.append((w & m) >> s)
        rows.append(bytes(row))
    return width, height, rows


def write_png(path, width, height, rows):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    raw = b"".join(b"\x00" + r for r in rows)
    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 6))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def describe(width, height, rows):
    colours = Counter()
    for r in rows[::4]:
        for x in range(0, width * 3, 12):
            colours[r[x : x + 3]] += 1
    total = sum(colours.values())
    top, n = colours.most_common(1)[0]
    return (
        f"{width}x{height}, {len(colours)} distinct colours in a 1/16 sample, "
        f"most common #{top.hex()} on {100 * n / total:.1f}% of it"
    )


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: xwd2png.py SCREEN.xwd OUT.png")
    w, h, rows = read_xwd(sys.argv[1])
    write_png(sys.argv[2], w, h, rows)
    print(describe(w, h, rows))


if __name__ == "__main__":
    main()
