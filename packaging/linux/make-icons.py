#!/usr/bin/env python3
"""Makes ringlab's icons (packaging/linux/icons/<size>x<size>/ringlab.png) from ringlab itself.

    target/release/ringlab render --preset paper-ring --time 60 --view 3d \
        --width 800 --height 800 --out /tmp/ringlab-icon-src.png
    python3 -m venv /tmp/iconvenv && /tmp/iconvenv/bin/pip install pillow
    /tmp/iconvenv/bin/python packaging/linux/make-icons.py /tmp/ringlab-icon-src.png

The ring and its trace are cropped out of the 800x800 render, the corners rounded, and the
square written at 48, 64, 128 and 256 pixels.
"""

import os
import sys

try:
    from PIL import Image, ImageDraw
except ImportError:
    sys.exit("make-icons.py: error: Pillow is missing (pip install pillow, in a venv)")

SIZES = (48, 64, 128, 256)
# The square around the ring and its trace in an 800x800 render of paper-ring at t = 60.
CROP = (235, 120, 745, 630)
WORK = 1024


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit("usage: make-icons.py RENDER.png (an 800x800 `ringlab render`, see the top of this file)")
    src = Image.open(sys.argv[1]).convert("RGBA")
    if src.size != (800, 800):
        sys.exit(f"make-icons.py: error: {sys.argv[1]} is {src.size[0]}x{src.size[1]}, not 800x800")
    square = src.crop(CROP).resize((WORK, WORK), Image.LANCZOS)
    mask = Image.new("L", (WORK, WORK), 0)
    ImageDraw.Draw(mask).rounded_rectangle((0, 0, WORK - 1, WORK - 1), radius=WORK // 6, fill=255)
    icon = Image.new("RGBA", (WORK, WORK), (0, 0, 0, 0))
    icon.paste(square, (0, 0), mask)
    out_root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "icons")
    for s in SIZES:
        folder = os.path.join(out_root, f"{s}x{s}")
        os.makedirs(folder, exist_ok=True)
        path = os.path.join(folder, "ringlab.png")
        icon.resize((s, s), Image.LANCZOS).save(path, optimize=True)
        print(f"wrote {path} ({os.path.getsize(path)} bytes)")


if __name__ == "__main__":
    main()
