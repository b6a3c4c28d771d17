#!/usr/bin/env python3
"""Generate hills.png: a 129x129 8-bit grayscale PNG heightmap of smooth rolling hills.

The terrain is a deterministic sum of sinusoids and gaussian bumps/dips, scaled
to use most of the 0..255 range. A disc in the middle of the map (about 15 % of
the image area) is perfectly flat at a mid value (about 118; printed when run), blended
smoothly into the hills, to give the robot a flat start area.

Image orientation: row 0 of the image is the NORTH edge of the terrain (rows
increase southwards); column 0 is the WEST edge.

Uses only the Python standard library (zlib + struct). Usage:
    python3 make_hills.py [output.png]     (default: hills.png next to this script)
"""
import math
import os
import struct
import sys
import zlib

SIZE = 129
LO, HI = 3, 252                 # output pixel range used
FLAT_FRACTION = 0.15            # fraction of image area that is flat
BLEND_PX = 14.0                 # width of smooth transition ring, pixels


def raw_height(u, v):
    """Unscaled hill field at normalised coordinates u, v in [0, 1]."""
    h = 0.0
    h += 0.55 * math.sin(2 * math.pi * (1.3 * u + 0.2)) * math.cos(2 * math.pi * (0.9 * v - 0.1))
    h += 0.30 * math.sin(2 * math.pi * (2.1 * v + 0.7 * u + 0.35))
    h += 0.15 * math.cos(2 * math.pi * (3.2 * u - 2.4 * v))
    bumps = [  # (u0, v0, sigma, amplitude)
        (0.18, 0.22, 0.10, 0.9),
        (0.80, 0.75, 0.12, 1.0),
        (0.78, 0.20, 0.08, -0.7),
        (0.25, 0.82, 0.09, -0.6),
    ]
    for u0, v0, s, a in bumps:
        h += a * math.exp(-((u - u0) ** 2 + (v - v0) ** 2) / (2 * s * s))
    return h


def smoothstep(e0, e1, x):
    t = min(1.0, max(0.0, (x - e0) / (e1 - e0)))
    return t * t * (3 - 2 * t)


def make_heights():
    c = (SIZE - 1) / 2.0
    r_flat = SIZE * math.sqrt(FLAT_FRACTION / math.pi)
    field = []
    for row in range(SIZE):
        line = []
        for col in range(SIZE):
            u, v = col / (SIZE - 1), row / (SIZE - 1)
            r = math.hypot(col - c, row - c)
            w = smoothstep(r_flat, r_flat + BLEND_PX, r)
            line.append(w * raw_height(u, v))
        field.append(line)
    lo = min(min(l) for l in field)
    hi = max(max(l) for l in field)
    # Linear map of the field extremes to LO / HI; the flat area (field == 0)
    # lands on a mid value.
    scale = (HI - LO) / (hi - lo)
    return [[max(0, min(255, int(round(LO + scale * (x - lo))))) for x in line] for line in field]


def write_png_gray8(path, rows):
    h, w = len(rows), len(rows[0])
    raw = b"".join(b"\x00" + bytes(r) for r in rows)  # filter type 0 per scanline

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data
                + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))  # 8-bit grayscale
    png += chunk(b"IDAT", zlib.compress(raw, 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "hills.png")
    rows = make_heights()
    write_png_gray8(out, rows)
    mid = rows[SIZE // 2][SIZE // 2]
    flat = sum(1 for r in rows for x in r if x == mid)
    print("wrote %s: %dx%d, min %d, max %d, flat value %d (%.1f%% of pixels)"
          % (out, SIZE, SIZE, min(min(r) for r in rows), max(max(r) for r in rows),
             mid, 100.0 * flat / (SIZE * SIZE)))


if __name__ == "__main__":
    main()
