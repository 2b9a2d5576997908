"""ringlab.ico: a ring tilted on its rim, above its shadow, drawn with Pillow.

    python3 -m venv /tmp/icon-venv && /tmp/icon-venv/bin/pip install pillow
    /tmp/icon-venv/bin/python packaging/windows/make-icon.py

writes packaging/windows/ringlab.png (256 px) and ringlab.ico (16 to 256 px) beside this file.
"""

import math
from pathlib import Path

from PIL import Image, ImageDraw

HERE = Path(__file__).resolve().parent
SIZE = 256
SS = 4  # drawn at 4x, then scaled down: smooth edges without an antialiasing rasterizer


def ellipse_points(cx, cy, a, b, tilt, n=180):
    c, s = math.cos(tilt), math.sin(tilt)
    pts = []
    for k in range(n):
        t = 2 * math.pi * k / n
        x, y = a * math.cos(t), b * math.sin(t)
        pts.append((cx + c * x - s * y, cy + s * x + c * y))
    return pts


def draw() -> Image.Image:
    big = SIZE * SS
    img = Image.new("RGBA", (big, big), (0, 0, 0, 0))
    d = ImageDraw.Draw(img)
    cx, cy = big * 0.5, big * 0.47
    tilt = math.radians(-28)
    # The table's shadow under the ring.
    d.ellipse([big * 0.16, big * 0.80, big * 0.84, big * 0.93], fill=(20, 30, 50, 90))
    # The ring: a dark outer rim, a bright band, the hole punched out.
    d.polygon(ellipse_points(cx, cy, big * 0.44, big * 0.30, tilt), fill=(150, 84, 18, 255))
    d.polygon(ellipse_points(cx, cy - big * 0.015, big * 0.42, big * 0.28, tilt), fill=(236, 160, 46, 255))
    d.polygon(ellipse_points(cx, cy - big * 0.02, big * 0.36, big * 0.225, tilt), fill=(252, 208, 112, 255))
    d.polygon(ellipse_points(cx, cy, big * 0.30, big * 0.17, tilt), fill=(0, 0, 0, 0))
    return img.resize((SIZE, SIZE), Image.LANCZOS)


def main() -> None:
    img = draw()
    img.save(HERE / "ringlab.png")
    sizes = [(s, s) for s in (16, 24, 32, 48, 64, 128, 256)]
    img.save(HERE / "ringlab.ico", sizes=sizes)
    print(HERE / "ringlab.ico", (HERE / "ringlab.ico").stat().st_size, "bytes")


if __name__ == "__main__":
    main()
