#!/usr/bin/env python3
"""Writes the project's own environment map, scenes/dusk_sky.hdr (docs/local-environment.md,
docs/scenes.md): a 128 x 64 lat-long map (docs/environment.md convention: u = frac(atan2(x, -z) /
2 pi), v = acos(y) / pi, row 0 at the top) of a dusk sky, generated here so the shipped scenes need
no downloaded asset. Radiance HDR (RGBE), uncompressed scanlines. Usage: scripts/make_sky.py [OUT]."""
import math
import struct
import sys

W, H = 128, 64


def sky(x, y, z):
    """Linear RGB radiance towards direction (x, y, z), +y up."""
    if y < 0.0:  # ground: dark, slightly warm, brighter towards the horizon
        g = 0.03 + 0.05 * math.exp(8.0 * y)
        return (g * 1.1, g, g * 0.85)
    horizon = math.exp(-6.0 * y)  # warm glow near the horizon, deep blue above
    r = 0.08 + 0.55 * horizon
    g = 0.12 + 0.35 * horizon
    b = 0.30 + 0.15 * horizon
    # a low sun towards -x, +z (radius ~3 degrees) with a soft halo
    sx, sy, sz = -0.8, 0.12, 0.58
    n = math.sqrt(sx * sx + sy * sy + sz * sz)
    c = (x * sx + y * sy + z * sz) / n
    if c > math.cos(math.radians(3.0)):
        return (60.0, 42.0, 25.0)
    halo = 1.5 * math.exp(40.0 * (c - 1.0))
    return (r + halo, g + 0.7 * halo, b + 0.4 * halo)


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes((0, 0, 0, 0))
    mant, e = math.frexp(m)
    f = mant * 256.0 / m
    return bytes((int(r * f), int(g * f), int(b * f), e + 128))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/dusk_sky.hdr"
    data = bytearray(b"#?RADIANCE\n# nearfield scripts/make_sky.py: generated dusk sky\nFORMAT=32-bit_rle_rgbe\n\n")
    data += f"-Y {H} +X {W}\n".encode()
    for row in range(H):
        v = (row + 0.5) / H
        for a in range(W):
            u = (a + 0.5) / W
            phi, theta = 2.0 * math.pi * u, math.pi * v
            # inverse of u = atan2(x, -z) / 2 pi, v = acos(y) / pi
            x, y, z = math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi)
            data += rgbe(*sky(x, y, z))
    with open(out, "wb") as f:
        f.write(data)


if __name__ == "__main__":
    main()
