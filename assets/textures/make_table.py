#!/usr/bin/env python3
"""Writes table.png: a 256x256 tileable grey wood grain for the table (multiplied by the wood
colour in the shader). Deterministic; standard library only. Run from this folder."""
import math, random, struct, zlib

N = 256
rng = random.Random(7)
# Periodic waves (integer frequencies) so that the texture tiles without seams.
waves = [(rng.randint(1, 4), rng.randint(0, 3), rng.uniform(0, 2 * math.pi), rng.uniform(0.02, 0.06)) for _ in range(6)]
fine = [(rng.randint(20, 60), rng.randint(0, 2), rng.uniform(0, 2 * math.pi), rng.uniform(0.01, 0.03)) for _ in range(10)]

def value(x, y):
    u, v = x / N, y / N
    warp = sum(a * math.sin(2 * math.pi * (fx * u + fy * v) + p) for fx, fy, p, a in waves)
    rings = math.sin(2 * math.pi * (7 * v + 2 * warp))
    streak = sum(a * math.sin(2 * math.pi * (fy * u + fx * v) + p) for fx, fy, p, a in fine)
    g = 0.5 + 0.25 * rings + 2.5 * streak
    return max(0, min(255, int(round(255 * g))))

rows = b"".join(b"\x00" + bytes(value(x, y) for x in range(N)) for y in range(N))
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", N, N, 8, 0, 0, 0, 0)) + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")
open("table.png", "wb").write(png)
